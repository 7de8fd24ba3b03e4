// iga_sphere: igacontact's side of compare_sphere.sh (issue 35, item 7): the thick sphere octant
// of examples/thick_sphere.yaml solved the way `igacontact run` solves it, and its relative L2
// displacement error against the closed form
//   u = u_r(r) x / r,  u_r = p a^3 / (E (b^3 - a^3)) ((1 - 2 nu) r + (1 + nu) b^3 / (2 r^2))
// (a = 1, b = 2, E = 1000, nu = 0.3, p = 1: examples/thick_sphere.yaml's values).
//
// Why a program of its own: `igacontact run` of a 3-D problem stops after solving, at the
// output ("host_patch_data: patch of dimension 3"), so there is neither a summary.json nor a
// result file to read the control net from. This program runs the app's code path up to
// there: Tpetra::ScopeGuard with the app's MPI start-up variables, load_problem(FILE, --set
// overrides), System, solve (Newton with the linear solver the problem file and `auto` pick),
// then gathers the displacement and integrates the error as tests/test_solid.cpp (l2_error3)
// does: the Gauss rule of p + 2 points per element and direction, det J by central differences
// of the geometric map. It prints one JSON line: dofs, error, stage seconds.
//
// Build: benchmarks/peers/build_peers.sh iga_sphere (build-peers/, linking the main build's
// libigacontact_core.a: configure build-peers with -DIGACONTACT_BUILD_DIR=... when the main
// build is not ROOT/build)
// Run:   build-peers/iga_sphere examples/thick_sphere.yaml [--set KEY=VALUE ...]
#include <Tpetra_Core.hpp>

#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "app/startup.hpp"
#include "kernels/nurbs_basis.hpp"
#include "kernels/types.hpp"
#include "model/input_error.hpp"
#include "model/problem.hpp"
#include "solver/checks.hpp"
#include "solver/newton.hpp"
#include "tests/solid_errors.hpp"

using namespace iga;

namespace {

constexpr double kA = 1.0, kB = 2.0, kE = 1000.0, kNu = 0.3, kP = 1.0;

std::array<double, 3> exact(const double* x) {
  const double r = std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
  const double ur = kP * kA * kA * kA / (kE * (kB * kB * kB - kA * kA * kA)) * ((1 - 2 * kNu) * r + (1 + kNu) * kB * kB * kB / (2 * r * r));
  return {ur * x[0] / r, ur * x[1] / r, ur * x[2] / r};
}

// x and u_h of a trivariate patch at the parameters t (tests/test_solid.cpp's eval3)

double since(std::chrono::steady_clock::time_point& t0) {
  const auto t = std::chrono::steady_clock::now();
  const double s = std::chrono::duration<double>(t - t0).count();
  t0 = t;
  return s;
}

int run(int argc, char** argv) {
  auto comm = Tpetra::getDefaultComm();
  if (comm->getSize() != 1) {
    std::fprintf(stderr, "iga_sphere: one rank only\n");
    return 2;
  }
  std::string file;
  std::vector<std::string> sets;
  for (int i = 1; i < argc; ++i) {
    const std::string s = argv[i];
    if (s == "--set" && i + 1 < argc) sets.push_back(argv[++i]);
    else if (s.rfind("--set=", 0) == 0) sets.push_back(s.substr(6));
    else if (file.empty() && !s.empty() && s[0] != '-') file = s;
    else {
      std::fprintf(stderr, "usage: iga_sphere FILE [--set KEY=VALUE ...]\n");
      return 2;
    }
  }
  if (file.empty()) {
    std::fprintf(stderr, "usage: iga_sphere FILE [--set KEY=VALUE ...]\n");
    return 2;
  }
  auto t0 = std::chrono::steady_clock::now();
  Problem P;
  try {
    P = load_problem(file, sets);
  } catch (const InputError& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 2;
  }
  if (P.dim() != 3 || P.bodies.size() != 1 || P.bodies[0].patches.size() != 1) {
    std::fprintf(stderr, "iga_sphere: a 3-D problem of one single-patch body (the sphere octant) expected\n");
    return 2;
  }
  const double t_read = since(t0);
  System sys(P, comm);
  const double t_setup = since(t0);
  const SolveResult res = solve(sys);
  const double t_solve = since(t0);
  if (!res.converged) {
    std::fprintf(stderr, "iga_sphere: not converged: %s\n", res.message.c_str());
    return 3;
  }
  const auto disp = gather_displacements(sys, *res.u);
  const auto [err, norm] = iga::test3d::l2_error3(P, disp[0], exact);
  const double t_error = since(t0);
  const Patch& pt = P.bodies[0].patches[0];
  std::printf("{\"code\": \"igacontact\", \"degree\": [%d, %d, %d], \"elements\": [%d, %d, %d], \"dofs\": %lld, "
              "\"l2_error\": %.6g, \"read_s\": %.6g, \"setup_s\": %.6g, \"solve_s\": %.6g, \"error_s\": %.6g}\n",
              pt.degree[0], pt.degree[1], pt.degree[2], pt.num_elements(0), pt.num_elements(1), pt.num_elements(2),
              static_cast<long long>(sys.num_dofs()), err / norm, t_read, t_setup, t_solve, t_error);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  iga::app::set_mpi_startup_variables();   // as app/main.cpp, before MPI_Init reads them
  int code = 0;
  {
    Tpetra::ScopeGuard guard(&argc, &argv);
    code = run(argc, argv);
  }
  return code;
}
