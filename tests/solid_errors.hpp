#pragma once
// The L2 error of a solid's displacement against a closed form, on the host: shared by
// tests/test_solid.cpp and benchmarks/peers/iga_sphere.cpp (the deal.II comparison).
#include <array>
#include <cmath>
#include <utility>
#include <vector>

#include "kernels/nurbs_basis.hpp"
#include "kernels/types.hpp"
#include "model/problem.hpp"

namespace iga::test3d {

// Host evaluation of a trivariate patch and a field given per control point (3 values each):
// x and u at the parameters t.
inline void eval3(const Patch& P, const std::vector<double>& u, const double t[3], double x[3], double uh[3]) {
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

// The L2 norms of u_h - u and of u over body 0 (all its patches), u(x) given: Gauss rule of p + 2
// points per element and direction, det J by central differences of the map (relative error
// ~ 1e-10, far below the discretisation errors measured).
template <class Exact>
std::pair<double, double> l2_error3(const Problem& Pr, const std::vector<double>& disp, Exact exact) {
  double err = 0, norm = 0;
  for (size_t pk = 0; pk < Pr.bodies[0].patches.size(); ++pk) {
  const Patch& P = Pr.bodies[0].patches[pk];
  const auto u = Pr.bodies[0].patch_values(static_cast<int>(pk), disp);
  std::vector<int> sp[3];
  for (int d = 0; d < 3; ++d) sp[d] = P.element_spans(d);
  for (int e2 : sp[2])
    for (int e1 : sp[1])
      for (int e0 : sp[0]) {
        const int es[3] = {e0, e1, e2};
        GaussRule g[3];
        for (int d = 0; d < 3; ++d) g[d] = gauss_rule(P.degree[d] + 2);
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
  }
  return {std::sqrt(err), std::sqrt(norm)};
}

}  // namespace iga::test3d
