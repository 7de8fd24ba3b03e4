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

using namespace iga;

namespace {

constexpr double kA = 1.0, kB = 2.0, kE = 1000.0, kNu = 0.3, kP = 1.0;

std::array<double, 3> exact(const double* x) {
  const double r = std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
  const double ur = kP * kA * kA * kA / (kE * (kB * kB * kB - kA * kA * kA)) * ((1 - 2 * kNu) * r + (1 + kNu) * kB * kB * kB / (2 * r * r));
  return {ur * x[0] / r, ur * x[1] / r, ur * x[2] / r};
}

// x and u_h of a trivariate patch at the parameters t (tests/test_solid.cpp's eval3)
void eval3(const Patch& P, const std::vector<double>& u, const double t[3], double x[3], double uh[3]) {
  int s[3];
  double N[3][3][kMaxBasis1D];
  for (int d = 0; d < 3; ++d) {
    s[d] = find_span(P.ncp(d), P.degree[d], t[d], P.knots[d].data());
    bspline_ders(s[d], t[d], P.degree[d], P.knots[d].data(), 0, N[d]);
  }
  double W = 0;
  for (int c = 0; c < 3; ++c) x[c] = uh[c] = 0;
  for (int k = 0; k <= P.degree[2]; ++k)
    for (int j = 0; j <= P.degree[1]; ++j)
      for (int i = 0; i <= P.degree[0]; ++i) {
        const int a = P.index(s[0] - P.degree[0] + i, s[1] - P.degree[1] + j, s[2] - P.degree[2] + k);
        const double b = N[0][0][i] * N[1][0][j] * N[2][0][k] * P.cp[a].w;
        W += b;
        for (int c = 0; c < 3; ++c) {
          x[c] += b * P.cp[a].x[c];
          uh[c] += b * u[3 * a + c];
        }
      }
  for (int c = 0; c < 3; ++c) {
    x[c] /= W;
    uh[c] /= W;
  }
}

// the L2 norms of u_h - u and of u over body 0's single patch (tests/test_solid.cpp's l2_error3)
std::pair<double, double> l2_error3(const Problem& Pr, const std::vector<double>& disp) {
  const Patch& P = Pr.bodies[0].patches[0];
  const auto u = Pr.bodies[0].patch_values(0, disp);
  std::vector<int> sp[3];
  for (int d = 0; d < 3; ++d) sp[d] = P.element_spans(d);
  GaussRule g[3];
  for (int d = 0; d < 3; ++d) g[d] = gauss_rule(P.degree[d] + 2);
  double err = 0, norm = 0;
  for (int e2 : sp[2])
    for (int e1 : sp[1])
      for (int e0 : sp[0]) {
        const int es[3] = {e0, e1, e2};
        for (int q2 = 0; q2 < g[2].n; ++q2)
          for (int q1 = 0; q1 < g[1].n; ++q1)
            for (int q0 = 0; q0 < g[0].n; ++q0) {
              const int q[3] = {q0, q1, q2};
              double t[3], w = 1, h[3];
              for (int d = 0; d < 3; ++d) {
                const double a = P.knots[d][es[d]], b = P.knots[d][es[d] + 1];
                h[d] = 0.5 * (b - a);
                t[d] = a + h[d] * (g[d].x[q[d]] + 1);
                w *= g[d].w[q[d]] * h[d];
              }
              double J[3][3];
              for (int d = 0; d < 3; ++d) {
                double tp[3] = {t[0], t[1], t[2]}, tm[3] = {t[0], t[1], t[2]};
                const double dt = 1e-6 * h[d];
                tp[d] += dt;
                tm[d] -= dt;
                const auto xp = P.point(tp), xm = P.point(tm);
                for (int c = 0; c < 3; ++c) J[c][d] = (xp[c] - xm[c]) / (2 * dt);
              }
              const double det = J[0][0] * (J[1][1] * J[2][2] - J[1][2] * J[2][1]) - J[0][1] * (J[1][0] * J[2][2] - J[1][2] * J[2][0]) +
                                 J[0][2] * (J[1][0] * J[2][1] - J[1][1] * J[2][0]);
              double x[3], uh[3];
              eval3(P, u, t, x, uh);
              const std::array<double, 3> ue = exact(x);
              for (int c = 0; c < 3; ++c) {
                err += (uh[c] - ue[c]) * (uh[c] - ue[c]) * std::abs(det) * w;
                norm += ue[c] * ue[c] * std::abs(det) * w;
              }
            }
      }
  return {std::sqrt(err), std::sqrt(norm)};
}

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
  const auto [err, norm] = l2_error3(P, disp[0]);
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
