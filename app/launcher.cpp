// igacontact: the command users run (usage: app/startup.hpp, docs in README.md).
//
// It answers --help and --version itself, without Trilinos, Kokkos or MPI (the solver binary
// loads some 110 shared libraries before main; this one loads libc and libstdc++), and
// otherwise replaces itself by the solver beside it, igacontact-solver, with the same
// arguments: execv keeps the process (its pid, its place as an MPI rank under mpiexec, its
// standard streams), so `mpiexec -n 2 igacontact run ...` is the solver on 2 ranks. On the way
// it sets the huge-page tunable that glibc reads at process start (one exec instead of the
// solver re-executing itself) and the start time, which the solver reports as "0) Start-up".
#include <unistd.h>

#include <cerrno>
#include <climits>
#include <cstdio>
#include <string>

#include "app/startup.hpp"

int main(int argc, char** argv) {
  if (iga::app::answer_help_or_version(argc, argv, IGACONTACT_VERSION)) return 0;
  const std::string start = std::to_string(iga::app::now_ns());
  setenv(iga::app::kStartVariable, start.c_str(), 1);
  iga::app::set_huge_pages_tunable();
  // the solver lies beside this program (build/bin, or the install's bin)
  char self[PATH_MAX];
  const ssize_t n = readlink("/proc/self/exe", self, sizeof self - 1);
  std::string dir = ".";
  if (n > 0) {
    self[n] = '\0';
    dir = self;
    dir = dir.substr(0, dir.find_last_of('/'));
  }
  const std::string solver = dir + "/igacontact-solver";
  argv[0] = const_cast<char*>(solver.c_str());
  execv(solver.c_str(), argv);
  std::fprintf(stderr, "igacontact: internal error: cannot start %s (%s)\n", solver.c_str(), std::strerror(errno));
  return 1;
}
