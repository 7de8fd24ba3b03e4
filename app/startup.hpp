#pragma once
// What the command `igacontact` (app/launcher.cpp) and the solver it runs
// (igacontact-solver, app/main.cpp) share: the usage text, the version line, the request for
// transparent huge pages, and the start time of the process (which execv keeps).
#include <glob.h>
#include <malloc.h>

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
    "writes into the output directory (default out/<file stem>): result.pvd (open it in ParaView:\n"
    "the exact geometry as rational Bezier cells, every load step), result.xdmf (2-D: the bodies'\n"
    "sampled fields; not written in 3-D), result_control_nets.xdmf and result_contact.xdmf (control\n"
    "nets, contact points), result_<n>.h5, summary.json and contact_<n>.csv.\n"
    "--set overrides a problem-file key by its dotted path,\n"
    "e.g. --set contact.0.penalty=1e7 --set bodies.1.refine.subdivide=[16,8].\n"
    "export writes each body's refined geometry, as the run would use it, without solving:\n"
    "<body>.xml (G+Smo XML) and <body>.txt (GeoPDEs v2.1) in DIR (default out/<file stem>/geometry).\n"
    "Kokkos' own options (threads, devices): --kokkos-help.\n"
    "Exit codes: 0 converged, 2 bad input, 3 not converged (last converged load step kept),\n"
    "4 output could not be written, 5 a converged step failed a physical check\n"
    "(interpenetration, self-penetration, inverted elements; the steps so far\n"
    "are written).\n";

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

// Transparent huge pages for the large arrays (matrix values and indices, Krylov vectors),
// on request only: IGACONTACT_HUGEPAGES=1. Where the kernel grants them only on request
// (transparent_hugepage/enabled is "madvise", Debian's default), glibc's malloc asks for them
// when started with the tunable glibc.malloc.hugetlb=1 (glibc >= 2.35; older ones ignore it);
// a tunable is read at process start, so it must be in the environment of the exec that
// starts the solver. It was the default from the third session (first-touch page faults of
// 4 KiB pages were half of the assembly at 6.6e5 dofs then); measured again on 2026-11-27
// (docs/performance.md, "Huge pages off by default") it cost 10-13 % of whole runs from 3.9e3
// to 5.3e5 dofs (system time: the kernel compacting memory for them) and saved nothing on
// the 77k-dof wheel, 1 or 2 ranks.
/// Adds the tunable to the environment where asked for and useful; true if the environment changed.
inline bool set_huge_pages_tunable() {
  const char* on = std::getenv("IGACONTACT_HUGEPAGES");
  if (!(on && std::strcmp(on, "1") == 0)) return false;
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

// Freed memory kept for the next allocation instead of being returned to the kernel and
// faulted in again, zeroed (a page fault costs several microseconds on this VM). glibc's
// malloc serves blocks from 128 kB up by mmap, raising that threshold only as such blocks are
// freed, and returns the heap's top to the kernel beyond 128 kB: the direct solver's factors,
// the contact's and the output's buffers, allocated afresh each Newton iteration, were
// faulted in each time. Blocks up to 32 MiB (glibc's largest threshold) now come from the heap
// and up to 512 MiB of freed heap top is kept: the 1,806-dof Hertz ball's run made 24,400 page
// faults, now 17,700, and its CPU time fell 0.69 -> 0.59 s (docs/performance.md, "Start-up:
// the multigrid libraries on demand"). The peak resident memory does not grow (freed memory is
// reused, not added to). Not where the user set these tunables.
inline void keep_freed_memory() {
  const char* tun = std::getenv("GLIBC_TUNABLES");
  if (tun && (std::strstr(tun, "mmap_threshold") || std::strstr(tun, "trim_threshold"))) return;
  mallopt(M_MMAP_THRESHOLD, 32 << 20);
  mallopt(M_TRIM_THRESHOLD, 512 << 20);
}

/// Started by mpiexec / mpirun (Open MPI, MPICH's Hydra, PMIx): several processes may run.
inline bool under_mpi_launcher() {
  for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"})
    if (std::getenv(v) != nullptr) return true;
  return false;
}

// Open MPI's start-up, cut to what a run uses (issue 34; docs/performance.md, "Start-up:
// what MPI_Init did"). Of a 1-rank run's 0.4-0.7 s start-up on our 2-core VM, MPI_Init spent
// most on work the run never uses:
//  - one process started without a launcher (a singleton) forked the daemon orted (there for
//    a later MPI_Comm_spawn; igacontact never spawns), which discovered the machine again;
//    it needs no transport but `self`, and no I/O devices in hwloc's topology (its PCI,
//    OpenCL, GL and libxml plugins, loaded and run at start, and the built-in linuxio);
//  - on every rank the cm PML tried its matching transports, PSM and PSM2 (Intel True Scale
//    and Omni-Path) probing about 0.1 s each (leaving only those two out was slower still):
//    where /dev has no such fabric (no hfi1, ipath or infiniband device) the ob1 PML over
//    shared memory and TCP is what runs anyway.
// Only variables the user has not set are set (setenv without overwrite), before MPI_Init
// reads them.
inline bool any_device(const char* pattern) {
  glob_t g;
  const bool found = glob(pattern, 0, nullptr, &g) == 0 && g.gl_pathc > 0;
  globfree(&g);
  return found;
}
inline void set_mpi_startup_variables() {
  if (!under_mpi_launcher()) {
    setenv("OMPI_MCA_ess_singleton_isolated", "1", 0);
    setenv("OMPI_MCA_btl", "self", 0);
    setenv("HWLOC_PLUGINS_BLACKLIST", "hwloc_pci,hwloc_opencl,hwloc_gl,hwloc_xml_libxml", 0);
    // hwloc's linuxio component reads every PCI device's config space from sysfs (3 ms each
    // on this VM: 15-30 ms of a singleton's start-up) for I/O devices a singleton never uses
    setenv("HWLOC_COMPONENTS", "-linuxio", 0);
  }
  if (!any_device("/dev/hfi1*") && !any_device("/dev/ipath*") && !any_device("/dev/infiniband"))
    setenv("OMPI_MCA_pml", "ob1", 0);
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
