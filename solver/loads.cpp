// Loads: the load path's points (LoadPoint) and the Neumann loads of a stage end.
#include "solver/system.hpp"
#include "solver/system_internal.hpp"

#include <algorithm>
#include <cmath>

#include "kernels/boundary_load.hpp"
#include "kernels/face_load.hpp"
#include "kernels/numbering.hpp"

namespace iga {

using namespace system_detail;

LoadPoint LoadPoint::at(double t, int num_stages) {
  LoadPoint lp;
  lp.stage = std::clamp(static_cast<int>(std::ceil(t)) - 1, 0, num_stages - 1);
  lp.s = t - lp.stage;
  return lp;
}

RCP<Vector> System::assemble_loads(double lambda, int stage) const {
  if (stage < 0) stage = P_.num_stages() - 1;
  Vector f_ov(overlap_);
  {
    auto f = Kokkos::subview(f_ov.getLocalViewDevice(Tpetra::Access::ReadWrite), Kokkos::ALL(), 0);
    for (const PatchBlock& bd : blocks_) {
      for (int s = 0; s < num_sides(dim()); ++s) {
        const SideCondition& sc = P_.bodies[bd.body].sides[bd.patch][s];
        if (sc.load == LoadKind::None) continue;
        // finite kinematics: pressures are follower loads, in assemble_internal
        if (sc.load != LoadKind::Traction && P_.kinematics == Kinematics::Finite) continue;
        if (dim() == 3) {
          AssembleFaceLoad<decltype(f)> k;
          k.pd = bd.pd3;
          k.load.face = s;
          k.load.kind = sc.load == LoadKind::Traction ? 3 : 1;
          k.load.p = sc.p0[stage];
          for (int c = 0; c < 3; ++c) k.load.t[c] = sc.traction[stage][c];
          k.load.scale = lambda;
          k.load.orientation = bd.orientation;
          int fd[2];
          face_directions(s, fd);
          for (int i = 0; i < 2; ++i) k.g[i] = gauss_rule(bd.pd3.p[fd[i]] + 1);
          k.f = f;
          k.e_begin = bd.e_begin; k.e_end = bd.e_end;
          Kokkos::parallel_for("iga::AssembleFaceLoad", Kokkos::RangePolicy<ExecSpace>(0, k.num_face_elements()), k);
          continue;
        }
        AssembleSideLoad<decltype(f)> k;
        k.pd = bd.pd;
        k.load.side = s;
        k.load.kind = sc.load == LoadKind::Traction ? 3 : 1;
        k.load.p0 = sc.p0[stage]; k.load.p1 = sc.p1[stage];
        k.load.t[0] = sc.traction[stage][0]; k.load.t[1] = sc.traction[stage][1];
        k.load.scale = lambda * P_.thickness;
        k.load.orientation = bd.orientation;
        const int d = side_tangent_direction(s);
        k.g = gauss_rule(bd.pd.p[d] + 1);
        k.f = f;
        k.e_begin = bd.e_begin; k.e_end = bd.e_end;
        Kokkos::parallel_for("iga::AssembleSideLoad", Kokkos::RangePolicy<ExecSpace>(0, bd.pd.ne[d]), k);
      }
    }
    Kokkos::fence();
  }
  if (!user_tractions_.empty()) {
    auto h = f_ov.getLocalViewHost(Tpetra::Access::ReadWrite);
    for (const auto& ut : user_tractions_) {
      const PatchBlock& bd = blocks_[block_of(ut.body, ut.patch)];
      const Curve c = P_.bodies[ut.body].patches[ut.patch].side_curve(ut.side);
      const GaussRule g = gauss_rule(c.degree + 2);
      const auto spans = c.element_spans();
      for (size_t k = 0; k < spans.size(); ++k) {
        const int s = spans[k];
        // the side element belongs to the rank owning its patch element
        const int pe = side_patch_element(bd.pd, static_cast<int>(ut.side), static_cast<int>(k));
        if (pe < bd.e_begin || pe >= bd.e_end) continue;
        const double a = c.knots[s], b = c.knots[s + 1], hh = 0.5 * (b - a);
        for (int q = 0; q < g.n; ++q) {
          const double u = a + hh * (g.x[q] + 1.0);
          double ders[3][kMaxBasis1D], w[kMaxBasis1D], R[3][kMaxBasis1D];
          bspline_ders(s, u, c.degree, c.knots.data(), 1, ders);
          for (int j = 0; j <= c.degree; ++j) { w[j] = c.cp[s - c.degree + j].w; ders[2][j] = 0; }
          rationalize_1d(c.degree, ders, w, R);
          double x[2] = {0, 0}, t[2] = {0, 0};
          for (int j = 0; j <= c.degree; ++j)
            for (int d = 0; d < 2; ++d) {
              x[d] += R[0][j] * c.cp[s - c.degree + j].x[d];
              t[d] += R[1][j] * c.cp[s - c.degree + j].x[d];
            }
          const auto tr = ut.t(x[0], x[1]);
          const double wq = lambda * g.w[q] * hh * std::hypot(t[0], t[1]) * P_.thickness;
          for (int j = 0; j <= c.degree; ++j) {
            const int l = bd.lid[c.patch_index[s - c.degree + j]];
            for (int d = 0; d < 2; ++d) h(dof_of(l, d, dim()), 0) += R[0][j] * tr[d] * wq;
          }
        }
      }
    }
  }
  if (!user_body_forces_.empty()) {
    auto h = f_ov.getLocalViewHost(Tpetra::Access::ReadWrite);
    for (const auto& ub : user_body_forces_)
      for (const PatchBlock& bd : blocks_) {
        if (bd.body != ub.body) continue;
        const Patch& pt = P_.bodies[bd.body].patches[bd.patch];
        const HostPatchData pd = host_patch_data(pt);
        const auto sp0 = pt.element_spans(0), sp1 = pt.element_spans(1);
        const GaussRule g0 = gauss_rule(pd.p[0] + 2), g1 = gauss_rule(pd.p[1] + 2);
        dispatch_degree(std::max(pd.p[0], pd.p[1]), [&](auto PP) {
          constexpr int P = decltype(PP)::value;
          double R[(P + 1) * (P + 1)], dR[(P + 1) * (P + 1)][2], x[2];
          for (int e = bd.e_begin; e < bd.e_end; ++e) {
            int ij[2];
            tensor_ij(e, pd.ne, 2, ij);
            const int s0 = sp0[ij[0]], s1 = sp1[ij[1]];
            const double ua = pt.knots[0][s0], ub0 = pt.knots[0][s0 + 1], va = pt.knots[1][s1], vb = pt.knots[1][s1 + 1];
            for (int qj = 0; qj < g1.n; ++qj)
              for (int qi = 0; qi < g0.n; ++qi) {
                const double u = ua + 0.5 * (ub0 - ua) * (g0.x[qi] + 1), v = va + 0.5 * (vb - va) * (g1.x[qj] + 1);
                const double det = nurbs_grad<P>(pd, s0, s1, u, v, R, dR, x);
                const auto b = ub.b(x[0], x[1]);
                const double w = lambda * std::abs(det) * g0.w[qi] * g1.w[qj] * 0.25 * (ub0 - ua) * (vb - va) * P_.thickness;
                for (int j = 0; j <= pd.p[1]; ++j)
                  for (int i = 0; i <= pd.p[0]; ++i) {
                    const int l = bd.lid[s0 - pd.p[0] + i + (s1 - pd.p[1] + j) * pd.n[0]];
                    const double Rw = R[i + j * (pd.p[0] + 1)] * w;
                    h(dof_of(l, 0, dim()), 0) += Rw * b[0];
                    h(dof_of(l, 1, dim()), 0) += Rw * b[1];
                  }
              }
          }
        });
      }
  }
  if (!user_body_forces3_.empty()) {
    auto h = f_ov.getLocalViewHost(Tpetra::Access::ReadWrite);
    for (const auto& ub : user_body_forces3_)
      for (const PatchBlock& bd : blocks_) {
        if (bd.body != ub.body) continue;
        const Patch& pt = P_.bodies[bd.body].patches[bd.patch];
        const HostPatchData3 pd = host_patch_data3(pt);
        GaussRule g[3];
        for (int d = 0; d < 3; ++d) g[d] = gauss_rule(pd.p[d] + 2);
        dispatch_degree(std::max({pd.p[0], pd.p[1], pd.p[2]}), [&](auto PP) {
          constexpr int P = decltype(PP)::value;
          std::vector<double> R(kNen<3, P>);
          std::vector<std::array<double, 3>> dR(kNen<3, P>);
          std::vector<int> cps(kNen<3, P>);
          double x[3];
          for (int e = bd.e_begin; e < bd.e_end; ++e) {
            int ei[3], s[3];
            pd.element_spans(e, ei, s);
            pd.local_cps(s, cps.data());
            double lo[3], hh[3];
            for (int d = 0; d < 3; ++d) {
              lo[d] = pt.knots[d][s[d]];
              hh[d] = 0.5 * (pt.knots[d][s[d] + 1] - lo[d]);
            }
            for (int q2 = 0; q2 < g[2].n; ++q2)
              for (int q1 = 0; q1 < g[1].n; ++q1)
                for (int q0 = 0; q0 < g[0].n; ++q0) {
                  const double xi[3] = {lo[0] + hh[0] * (g[0].x[q0] + 1), lo[1] + hh[1] * (g[1].x[q1] + 1), lo[2] + hh[2] * (g[2].x[q2] + 1)};
                  const double det = nurbs_grad<P>(pd, s, xi, R.data(), reinterpret_cast<double(*)[3]>(dR.data()), x);
                  const auto b = ub.b(x[0], x[1], x[2]);
                  const double w = lambda * std::abs(det) * g[0].w[q0] * g[1].w[q1] * g[2].w[q2] * hh[0] * hh[1] * hh[2];
                  for (int a = 0; a < pd.nen(); ++a) {
                    const int l = bd.lid[cps[a]];
                    for (int c = 0; c < 3; ++c) h(dof_of(l, c, 3), 0) += R[a] * w * b[c];
                  }
                }
          }
        });
      }
  }
  return export_vector(f_ov);
}


}  // namespace iga
