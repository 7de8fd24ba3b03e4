#pragma once
// What the command `igacontact` (app/launcher.cpp) and the solver it runs
// (igacontact-solver, app/main.cpp) share: the usage text, the version line, the request for
// transparent huge pages, and the start time of the process (which execv keeps).
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <fstream>
#include <string>

namespace iga::app {

inline const char* kUsage =
    "usage: igacontact run FILE [--output DIR] [--set KEY=VALUE ...] [--quiet]\n"
    "       igacontact FILE [...]            (short for run)\n"
    "       igacontact check FILE [--set KEY=VALUE ...]\n"
    "       igacontact export FILE [--output DIR] [--set KEY=VALUE ...]\n"
    "       igacontact --help | --version | --kokkos-help\n"
    "\n"
    "Solves the elastostatic contact problem of a YAML problem file (docs/problem-file.md) and\n"
    "writes into the output directory (default out/<file stem>): result.xdmf (open it in ParaView:\n"
    "the bodies' sampled fields, every load step; control nets and contact points in\n"
    "result_control_nets.xdmf and result_contact.xdmf), result.pvd (the exact\n"
    "geometry as rational Bezier cells), result.h5, summary.json and contact_<n>.csv. --set overrides a problem-file key by its dotted path,\n"
    "e.g. --set contact.0.penalty=1e7 --set bodies.1.refine.subdivide=[16,8].\n"
    "export writes each body's refined geometry, as the run would use it, without solving:\n"
    "<body>.xml (G+Smo XML) and <body>.txt (GeoPDEs v2.1) in DIR (default out/<file stem>/geometry).\n"
    "Kokkos' own options (threads, devices): --kokkos-help.\n"
    "Exit codes: 0 converged, 2 bad input, 3 not converged (last converged load step kept),\n"
    "4 output could not be written, 5 a converged step failed a physical check\n"
    "(interpenetration, self-penetration, inverted elements; the steps so far are written).\n";

/// --help or --version among the arguments: answered (usage or version on stdout), true.
inline bool answer_help_or_version(int argc, char** argv, const char* version) {
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--help") == 0 || std::strcmp(argv[i], "-h") == 0) {
      std::fputs(kUsage, stdout);
      return true;
    }
    if (std::strcmp(argv[i], "--version") == 0) {
      std::printf("igacontact %s\n", version);
      return true;
    }
  }
  return false;
}

// Transparent huge pages for the large arrays (matrix values and indices, Krylov vectors,
// MueLu's levels). Where the kernel grants them only on request (transparent_hugepage/enabled
// is "madvise", Debian's default), glibc's malloc asks for them when started with the
// tunable glibc.malloc.hugetlb=1 (glibc >= 2.35; older ones ignore it); a tunable is read at
// process start, so it must be in the environment of the exec that starts the solver.
// First-touch page faults of 4 KiB pages were half of the assembly and tangent stages at
// 6.6e5 dofs on our 2-core VM (docs/performance.md). IGACONTACT_HUGEPAGES=0 turns this off.
/// Adds the tunable to the environment where it helps; true if the environment changed.
inline bool set_huge_pages_tunable() {
  const char* off = std::getenv("IGACONTACT_HUGEPAGES");
  if (off && std::strcmp(off, "0") == 0) return false;
  const char* tun = std::getenv("GLIBC_TUNABLES");
  if (tun && std::strstr(tun, "glibc.malloc.hugetlb")) return false;   // set already
  std::ifstream thp("/sys/kernel/mm/transparent_hugepage/enabled");
  std::string mode;
  std::getline(thp, mode);
  if (mode.find("[madvise]") == std::string::npos) return false;   // "always": no need; "never": no use
  std::string value = tun && *tun ? std::string(tun) + ":" : std::string();
  value += "glibc.malloc.hugetlb=1";
  return setenv("GLIBC_TUNABLES", value.c_str(), 1) == 0;
}

/// CLOCK_REALTIME in nanoseconds.
inline std::int64_t now_ns() {
  timespec ts;
  clock_gettime(CLOCK_REALTIME, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * 1000000000LL + ts.tv_nsec;
}

/// Environment variable carrying the launcher's start time (ns, CLOCK_REALTIME) to the solver.
inline const char* kStartVariable = "IGACONTACT_START_NS";

}  // namespace iga::app
