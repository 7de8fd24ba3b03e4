// igacontact-solver: isogeometric analysis of elastostatic contact between NURBS bodies. Users
// run it as `igacontact` (app/launcher.cpp), which answers --help and --version itself and
// replaces itself by this program for everything else; run directly it does the same.
//   igacontact run FILE [--output DIR] [--set KEY=VALUE ...] [--quiet]   (short: igacontact FILE ...)
//   igacontact check FILE [--set KEY=VALUE ...]
//   igacontact export FILE [--output DIR] [--set KEY=VALUE ...]
//   igacontact --help | --version
// Exit codes: 0 converged, 1 internal error, 2 bad input, 3 the nonlinear solve did not converge,
// 4 the output could not be written (summary.json is then absent), 5 a converged load step failed
// a physical check (interpenetration, self-penetration, an inverted element): the run stops
// there, its steps are written, summary.json says why.
#include <Teuchos_StackedTimer.hpp>
#include <Teuchos_TimeMonitor.hpp>
#include <Tpetra_Core.hpp>

#include <Teuchos_CommHelpers.hpp>
#include <Teuchos_DefaultSerialComm.hpp>
#include <sys/resource.h>

#include <mpi.h>
#include <csignal>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <filesystem>
#include <iostream>
#include <sstream>

#include "app/startup.hpp"
#include "io/files.hpp"
#include "io/output.hpp"
#include "model/geometry_file.hpp"
#include "model/problem.hpp"
#include "solver/newton.hpp"

namespace {

using iga::app::kUsage;

struct Args {
  std::string command = "run", file, output;
  std::vector<std::string> sets;
  bool quiet = false;
};

struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

Args parse_args(int argc, char** argv) {
  Args a;
  int i = 1;
  if (i < argc && (std::string(argv[i]) == "run" || std::string(argv[i]) == "check" || std::string(argv[i]) == "export"))
    a.command = argv[i++];
  for (; i < argc; ++i) {
    const std::string s = argv[i];
    auto value = [&](const char* opt) {
      if (i + 1 >= argc) throw UsageError(std::string("option ") + opt + " needs a value");
      return std::string(argv[++i]);
    };
    if (s == "--output" || s == "-o") {
      a.output = value("--output");
      // an empty path wrote into the default folder without a word (found by a user's test)
      if (a.output.empty()) throw UsageError("--output needs a folder, not an empty path");
    }
    else if (s == "--set") a.sets.push_back(value("--set"));
    else if (s.rfind("--set=", 0) == 0) a.sets.push_back(s.substr(6));
    else if (s.rfind("--output=", 0) == 0) {
      a.output = s.substr(9);
      if (a.output.empty()) throw UsageError("--output needs a folder, not an empty path");
    }
    else if (s == "--quiet" || s == "-q") a.quiet = true;
    else if (!s.empty() && s[0] == '-') throw UsageError("unknown option '" + s + "'");
    else if (a.file.empty()) a.file = s;
    else if (i == 2 && a.command == "run" && std::string(argv[1]) == a.file && a.file.find('.') == std::string::npos &&
             a.file.find('/') == std::string::npos)   // 'igacontact frob x.yaml': a mistyped command
      throw UsageError("unknown command '" + a.file + "' (the commands are run, check and export)");
    else throw UsageError("more than one problem file given ('" + a.file + "' and '" + s + "')");
  }
  if (a.file.empty()) throw UsageError("no problem file given");
  if (a.command == "check" && !a.output.empty()) throw UsageError("check writes nothing; --output is not for it");
  return a;
}

size_t num_elements(const iga::Body& b) {
  size_t ne = 0;
  for (const auto& pt : b.patches) ne += pt.num_elements();
  return ne;
}

// The output directory must be usable before anything is written or solved (created if
// needed, writable, checked on rank 0): else one line naming the key that chose it, false.
bool usable_output_directory(const iga::Comm& comm, const std::string& file, const std::string& dir,
                             const std::string& key) {
  try {
    iga::on_root(comm, [&] {
      const std::string why = iga::check_output_directory(dir);
      if (!why.empty()) throw iga::OutputError(why);
    });
  } catch (const iga::OutputError& e) {
    if (comm.getRank() == 0) std::cerr << file << ": " << key << " = " << dir << ": " << e.what() << "\n";
    return false;
  }
  return true;
}

// "[p0, p1]" or "[p0, p1, p2]" and "ne0 x ne1 (x ne2)" of a patch.
std::string degrees(const iga::Patch& pt) {
  std::string s = "[";
  for (int d = 0; d < pt.dim(); ++d) s += (d ? ", " : "") + std::to_string(pt.degree[d]);
  return s + "]";
}
std::string element_counts(const iga::Patch& pt) {
  std::string s;
  for (int d = 0; d < pt.dim(); ++d) s += (d ? " x " : "") + std::to_string(pt.num_elements(d));
  return s;
}

// "E = .., nu = .." and, where it is not the linear law of small strain, the material model
std::string material(const iga::Problem& P, const iga::Body& b) {
  std::ostringstream os;
  os << "E = " << b.E << ", nu = " << b.nu;
  if (P.kinematics == iga::Kinematics::Finite)
    os << ", " << (b.model == iga::MaterialModel::Linear ? "saint_venant_kirchhoff" : iga::material_model_name(b.model));
  return os.str();
}

void describe(const iga::Problem& P, int ranks, std::ostream& os) {
  long long dofs = 0;
  const int dim = P.dim();
  os << "problem " << P.file << ": "
     << (P.analysis == iga::Analysis::Solid ? "solid (3-D)" : P.analysis == iga::Analysis::PlaneStrain ? "plane strain" : "plane stress")
     << (P.kinematics == iga::Kinematics::Finite ? ", finite strain" : "") << ", " << P.load_steps << " load step(s)";
  if (P.num_stages() > 1) {
    os << " in " << P.num_stages() << " stages [";
    for (int k = 0; k < P.num_stages(); ++k) os << (k ? ", " : "") << P.stages[k];
    os << "]";
  }
  os << "\n";
  for (const auto& b : P.bodies) {
    dofs += static_cast<long long>(dim) * b.num_cps;
    if (!b.multipatch()) {
      const auto& pt = b.patches[0];
      os << "  body " << b.name << ": degree " << degrees(pt) << ", " << element_counts(pt) << " elements, "
         << dim * pt.cp.size() << " dofs, " << material(P, b) << "\n";
      continue;
    }
    os << "  body " << b.name << ": " << b.patches.size() << " patches, " << b.interfaces.size() << " interfaces, " << num_elements(b)
       << " elements, " << dim * b.num_cps << " dofs, " << material(P, b) << "\n";
    for (size_t k = 0; k < b.patches.size(); ++k) {
      const auto& pt = b.patches[k];
      os << "    patch " << k << ": degree " << degrees(pt) << ", " << element_counts(pt) << " elements\n";
    }
  }
  for (size_t k = 0; k < P.contact.size(); ++k) {
    const auto& c = P.contact[k];
    os << "  contact " << k << ": master " << P.bodies[c.master.body].name << "." << c.master.label << ", slave "
       << P.bodies[c.slave.body].name << "." << c.slave.label << ", "
       << iga::contact_method_name(c.method) << ", penalty " << c.penalty << "\n";
  }
  os << "  total " << dofs << " dofs on " << ranks << " rank(s)";
  // check and export run without Kokkos: the threads are decided when a run starts it
  if (Kokkos::is_initialized()) os << " x " << iga::ExecSpace::concurrency() << " " << iga::ExecSpace::name() << " thread(s)";
  else os << " (" << iga::ExecSpace::name() << ")";
  os << "; linear solver " << iga::linear_method_name(P.linear.method);
  if (P.linear.method == iga::LinearMethod::Direct) {
    os << " (MUMPS " << (P.linear.symmetric ? "LDLT" : "LU");
    const std::string why = P.not_condensed_reason();
    if (why.empty()) os << ", condensed onto the contact sides: at most " << P.contact_side_dofs() << " dofs";
    else if (!P.contact.empty() && P.kinematics == iga::Kinematics::Small) os << ", not condensed: " << why;
    os << ")";
  }
  else os << " + " << iga::preconditioner_name(P.linear.preconditioner)
          << (iga::eisenstat_walker_forcing(P) ? ", Eisenstat-Walker forcing" : "");
  if (P.linear.automatic)
    os << " [auto: " << (P.linear.method == iga::LinearMethod::Direct ? "at most " : "more than ")
       << P.auto_direct_max_dofs() << " dofs" << (P.has_friction() ? ", with friction" : "") << "]";
  os << "\n";
}

// igacontact export: the refined geometry of every body (what a run would solve on), in the
// two formats IGA tools read, without setting up or solving anything. Rank 0 writes; each file
// is written whole or not at all (io/files.hpp).
int export_geometry(const iga::Problem& P, const Args& args, const iga::Comm& comm) {
  std::string dir = args.output, dir_key = "--output";
  if (dir.empty()) {
    dir = "out/" + std::filesystem::path(args.file).stem().string() + "/geometry";
    dir_key = "output directory (default)";
  }
  if (!usable_output_directory(comm, args.file, dir, dir_key)) return 2;
  std::vector<std::string> written;
  iga::on_root(comm, [&] {
    for (const iga::Body& b : P.bodies) {
      const iga::MultiPatch mp = iga::body_geometry(b);
      const std::filesystem::path base = std::filesystem::path(dir) / b.name;
      iga::write_file_atomic(base.string() + ".xml", iga::gismo_xml_text({&mp}));
      iga::write_file_atomic(base.string() + ".txt", iga::geopdes_text(mp));
      std::ostringstream line;
      line << "  " << b.name << ": " << b.patches.size() << " patch(es), " << b.interfaces.size() << " interface(s), " << num_elements(b)
           << " elements, " << b.num_cps << " control points -> " << base.string() << ".{xml,txt}";
      written.push_back(line.str());
    }
  });
  if (comm.getRank() == 0 && !args.quiet) {
    std::cout << "export " << args.file << ": refined geometry (G+Smo XML, GeoPDEs v2.1)\n";
    for (const auto& l : written) std::cout << l << "\n";
  }
  return 0;
}

// `check` and `export`: no solve, so no MPI and no Kokkos where one process runs them.
bool light_command(int argc, char** argv) {
  return argc > 1 && (std::strcmp(argv[1], "check") == 0 || std::strcmp(argv[1], "export") == 0);
}

// When the process started: the launcher's time (IGACONTACT_START_NS, app/launcher.cpp), or
// main's entry when the solver is run directly.
std::int64_t g_start_ns = 0;

int run(int argc, char** argv, Teuchos::RCP<const iga::Comm> comm) {
  const bool root = comm->getRank() == 0;
  // start-up: exec, loading the shared libraries, MPI and Kokkos (the slowest rank's)
  double startup = 1e-9 * static_cast<double>(iga::app::now_ns() - g_start_ns), startup_max = 0;
  Teuchos::reduceAll(*comm, Teuchos::REDUCE_MAX, 1, &startup, &startup_max);
  Args args;
  try {
    args = parse_args(argc, argv);
  } catch (const UsageError& e) {
    if (root) std::cerr << "igacontact: " << e.what() << "\n" << kUsage;
    return 2;
  }
  iga::Problem P;
  try {
    Teuchos::TimeMonitor t(*Teuchos::TimeMonitor::getNewTimer("0) Read problem"));
    P = iga::load_problem(args.file, args.sets);
  } catch (const iga::InputError& e) {
    if (root) std::cerr << e.what() << "\n";
    return 2;
  }
  if (root)
    for (const std::string& w : P.warnings) std::cerr << "warning: " << w << "\n";
  if (args.command == "check") {
    if (root) {
      describe(P, comm->getSize(), std::cout);
      std::cout << "check: OK\n";
    }
    return 0;
  }
  if (args.command == "export") return export_geometry(P, args, *comm);
  std::string dir = args.output;
  std::string dir_key = "--output";
  if (dir.empty()) { dir = P.output.directory; dir_key = "output.directory"; }
  if (dir.empty()) { dir = "out/" + std::filesystem::path(args.file).stem().string(); dir_key = "output directory (default)"; }
  // The output directory must be usable before anything is solved: bad input, exit 2.
  if (!usable_output_directory(*comm, args.file, dir, dir_key)) return 2;
  // One run's files only: what a previous run left is removed as this one starts writing.
  const std::string run_id = iga::broadcast_string(*comm, root ? iga::new_run_id() : std::string());
  iga::on_root(*comm, [&] { iga::remove_previous_outputs(dir); });
  if (root && !args.quiet) describe(P, comm->getSize(), std::cout);

  Teuchos::RCP<iga::System> sys;
  {
    Teuchos::TimeMonitor t(*Teuchos::TimeMonitor::getNewTimer("1) Set-up: maps and patches"));
    sys = Teuchos::rcp(new iga::System(P, comm));
  }
  // the element rule (solver.quadrature): what each patch got, against Gauss
  long long qp = 0, qp_gauss = 0;
  const bool spline = P.quadrature == iga::Quadrature::Spline;
  for (const iga::PatchBlock& bd : sys->blocks()) {
    long long g = 1;
    const iga::Patch& pt = P.bodies[bd.body].patches[bd.patch];
    for (int d = 0; d < pt.dim(); ++d) g *= 1LL * pt.num_elements(d) * (pt.degree[d] + 1);
    qp += bd.quadrature_points;
    qp_gauss += g;
    if (root && !args.quiet && spline && bd.quadrature != "spline")   // a direction kept Gauss: say why
      std::cout << "  quadrature " << P.bodies[bd.body].name << (P.bodies[bd.body].multipatch() ? ".patch" + std::to_string(bd.patch) : "")
                << ": " << bd.quadrature << "\n";
  }
  if (root && !args.quiet)
    std::cout << "  quadrature: " << (spline ? "spline" : "gauss") << ", " << qp << " points" << (spline ? " (Gauss: " + std::to_string(qp_gauss) + ")" : "")
              << "; tangent formed "
              << (P.formation != iga::Formation::SumFactorized ? "element by element"
                  : P.dim() == 2                               ? "row by row (sum_factorized)"
                                                               : "element by element, sum-factorised from p = 3 (sum_factorized)")
              << "\n";
  // Fault injection for the test of what one failing rank does to the others
  // (tests/cli_reliability.sh): IGACONTACT_TEST_FAULT=<rank> throws there after set-up.
  if (const char* f = std::getenv("IGACONTACT_TEST_FAULT"))
    if (*f && std::atoi(f) == comm->getRank()) throw std::runtime_error("injected fault (IGACONTACT_TEST_FAULT)");
  const bool show = root && !args.quiet;
  // friction: the stick and slip counts and the points that changed state beside the active set
  const bool friction = P.has_friction();
  if (show) {
    std::printf("%5s %8s %4s %4s %4s %12s %8s", "step", "t", "cut", "aug", "it", "residual", "active");
    if (friction) std::printf(" %6s %6s %6s", "stick", "slip", "switch");
    std::printf(" %8s %6s %9s\n", "lin.its", "ls", "seconds");
  }
  auto progress = [&](const iga::IterationLog& l) {
    if (show) {
      std::printf("%5d %8.4g %4d %4d %4d %12.3e %8d", l.step, l.lambda, l.cuts, l.augmentation, l.iteration, l.residual,
                  l.active);
      if (friction) std::printf(" %6d %6d %6d", l.stick, l.slip, l.switches);
      std::printf(" %8d %6.3g %9.2f\n", l.linear_iterations, l.line_search, l.seconds);
      std::fflush(stdout);
    }
  };
  iga::ResultWriter writer(*sys, dir, args.file, run_id);
  // a cut increment: why, before the table goes on with the halved increment
  auto on_cut = [&](int, const std::string& why) {
    if (show) {
      std::printf("      cut: %s\n", why.c_str());
      std::fflush(stdout);
    }
  };
  // after every converged step (and after its files are written, so that the picture of a
  // failed check can be looked at): interpenetration, self-penetration, inverted elements
  auto on_step = [&](const iga::StepState& st) {
    writer.step(st);
    *st.stop = iga::check_configuration(*sys, *st.u, *st.contact);
  };
  const iga::SolveResult res = iga::solve(*sys, progress, on_step, on_cut);
  nlohmann::json summary = writer.finish(res);
  summary["check"] = {{"passed", res.stopped.empty()}, {"message", res.stopped}};
  // a converged run whose contact zone is too narrow for its slave elements: the peak pressure
  // is not resolved (the forces are): one warning line per pair, on stderr and in summary.json
  std::vector<std::string> warnings = P.warnings;
  // A pair that carried no force in any converged load step gets one line too: a mistyped
  // origin or a load that never brings the bodies together converged with every contact
  // quantity 0 and no word (found by a problem written from the docs)
  const auto never_touched = [&](size_t k) -> std::string {
    if (!summary.contains("history") || summary["history"].empty()) return "";
    for (const auto& h : summary["history"]) {
      if (!h.contains("contact") || h["contact"].size() <= k) return "";
      const auto& f = h["contact"][k]["force"];
      for (const auto& v : f)
        if (v.get<double>() != 0.0) return "";
    }
    const iga::ContactPointState st = res.contact[k].state(true);   // (collective in 3-D)
    double g = std::numeric_limits<double>::infinity();
    for (double x : st.gap) g = std::min(g, x);
    std::ostringstream os;
    os.precision(3);
    os << res.contact[k].pair_text(static_cast<int>(k), P) << " carried no force in any load step";
    if (std::isfinite(g)) os << " (its nearest slave point ended " << g << " from the master)";
    os << ": check the bodies' positions and the loads or prescribed displacements that should bring them together";
    return os.str();
  };
  if (res.converged && res.stopped.empty())
    for (size_t k = 0; k < res.contact.size(); ++k) {
      std::string w = never_touched(k);
      if (w.empty()) w = res.contact[k].unresolved_zone(static_cast<int>(k), P);
      if (w.empty()) continue;
      warnings.push_back(args.file + ": " + w);
      if (root) std::cerr << "warning: " << args.file << ": " << w << "\n";
    }
  summary["warnings"] = warnings;

  // timings: the slowest rank's time per stage
  std::vector<std::string> names;
  Teuchos::stat_map_type stats;
  Teuchos::TimeMonitor::computeGlobalTimerStatistics(stats, names, comm.ptr(), Teuchos::Union);
  size_t imax = 0;
  for (size_t k = 0; k < names.size(); ++k)
    if (names[k] == "MaxOverProcs") imax = k;
  nlohmann::json timings = nlohmann::json::object();
  for (const auto& kv : stats)
    if (!kv.first.empty() && std::isdigit(static_cast<unsigned char>(kv.first[0])))  // our numbered stages
      timings[kv.first] = kv.second[imax].first;
  timings["0) Start-up: exec, libraries, MPI"] = startup_max;
  summary["quadrature"] = {{"rule", spline ? "spline" : "gauss"},
                           {"points", qp}, {"gauss_points", qp_gauss}};
  summary["formation"] = P.formation == iga::Formation::SumFactorized ? "sum_factorized" : "elements";
  summary["timings"] = timings;
  // peak resident memory, the largest rank's and the sum over ranks (bytes per dof below)
  struct rusage ru;
  getrusage(RUSAGE_SELF, &ru);
  double mem = ru.ru_maxrss / 1024.0, mem_max = 0, mem_sum = 0;  // MiB (ru_maxrss is KiB on Linux)
  Teuchos::reduceAll(*comm, Teuchos::REDUCE_MAX, 1, &mem, &mem_max);
  Teuchos::reduceAll(*comm, Teuchos::REDUCE_SUM, 1, &mem, &mem_sum);
  summary["peak_memory_mib"] = {{"max_rank", mem_max}, {"all_ranks", mem_sum}};
  summary["bytes_per_dof"] = mem_sum * 1048576.0 / static_cast<double>(sys->num_dofs());
  // summary.json last: its presence says the run's files are complete
  iga::on_root(*comm, [&] {
    iga::write_file_atomic((std::filesystem::path(dir) / "summary.json").string(), summary.dump(2) + "\n");
  });
  if (root) {
    if (!args.quiet) {
      std::cout << "\nstage timings (seconds, slowest rank):\n";
      for (const auto& kv : timings.items()) std::printf("  %-36s %10.4f\n", kv.key().c_str(), kv.value().get<double>());
      std::cout << "\n";
      for (const auto& c : summary["contact"])
        std::cout << "contact " << c["slave"]["body"].get<std::string>() << " on " << c["master"]["body"].get<std::string>()
                  << ": normal force " << c["normal_force"].get<double>() << ", max pressure "
                  << c["max_pressure"].get<double>()
                  << (c.contains("contact_area") ? ", contact area " : ", contact length ")
                  << (c.contains("contact_area") ? c["contact_area"] : c["contact_length"]).get<double>()
                  << ", max penetration " << c["max_penetration"].get<double>() << "\n";
      std::cout << (!res.converged ? "NOT converged" : res.stopped.empty() ? "converged" : "converged, physical check FAILED") << ": " << sys->num_dofs() << " dofs, "
                << comm->getSize() << " rank(s), Newton iterations per step [";
      for (size_t k = 0; k < res.newton_iterations.size(); ++k) std::cout << (k ? ", " : "") << res.newton_iterations[k];
      std::cout << "], " << res.linear_iterations << " linear iterations; results in " << dir << "\n";
    }
    if (!res.converged) std::cerr << args.file << ": " << res.message << "\n";
    else if (!res.stopped.empty())
      std::cerr << args.file << ": load step " << res.steps_converged << " converged but failed a physical check: " << res.stopped << "\n";
  }
  return !res.converged ? 3 : !res.stopped.empty() ? 5 : 0;
}

}  // namespace

int main(int argc, char** argv) {
  // started by the launcher (app/launcher.cpp): its start time; run directly: now
  const char* start = std::getenv(iga::app::kStartVariable);
  g_start_ns = start && *start ? std::atoll(start) : iga::app::now_ns();
  if (!(start && *start)) setenv(iga::app::kStartVariable, std::to_string(g_start_ns).c_str(), 1);
  // --help and --version answer before anything starts (no MPI, no Kokkos, whose own
  // option banner would come first; Kokkos' options stay reachable with --kokkos-help).
  // The launcher answers them without even loading this binary.
  if (iga::app::answer_help_or_version(argc, argv, IGACONTACT_VERSION)) return 0;
  // run directly (not through the launcher, which sets it): the huge-page tunable is read at
  // process start, so set it and re-execute (returns only on failure: run on without)
  if (iga::app::set_huge_pages_tunable()) execv("/proc/self/exe", argv);
  // A file-size limit (ulimit -f) makes write(2) fail with EFBIG, reported like a full disk,
  // instead of killing the process with SIGXFSZ.
  std::signal(SIGXFSZ, SIG_IGN);
  // an interrupt (Ctrl-C, a batch system's SIGTERM) leaves no half-written <name>.part file
  iga::remove_part_files_on_interrupt();
  iga::app::keep_freed_memory();
  // run, with its errors turned into exit codes: an OutputError is thrown on every rank
  // together (io/files.hpp); any other failure on one rank only would leave the others waiting
  // in a collective forever, so on several ranks it ends them all
  auto guarded = [&](const Teuchos::RCP<const iga::Comm>& comm) {
    try {
      return run(argc, argv, comm);
    } catch (const iga::OutputError& e) {
      if (comm->getRank() == 0) std::cerr << "igacontact: " << e.what() << "\n";
      return 4;
    } catch (const std::exception& e) {
      std::cerr << "igacontact: internal error: " << e.what() << "\n";
      if (comm->getSize() > 1) {
        std::cerr.flush();
        MPI_Abort(MPI_COMM_WORLD, 1);
      }
      return 1;
    }
  };
  // check and export read the problem (and export writes the geometry) on one process: they
  // start neither MPI nor Kokkos (about 0.5 s of a run's start-up), unless an MPI launcher
  // started several processes, which then take the parallel path (rank 0 prints and writes)
  if (light_command(argc, argv) && !iga::app::under_mpi_launcher()) return guarded(Teuchos::rcp(new Teuchos::SerialComm<int>()));
  bool kokkos_help = false;   // Kokkos prints its options (and removes the argument)
  for (int i = 1; i < argc; ++i) kokkos_help = kokkos_help || std::string(argv[i]) == "--kokkos-help";
  int code = 0;
  iga::app::set_mpi_startup_variables();   // before MPI_Init reads them (app/startup.hpp)
  {
    Tpetra::ScopeGuard guard(&argc, &argv);
    if (kokkos_help) return 0;
    code = guarded(Tpetra::getDefaultComm());
  }
  return code;
}
