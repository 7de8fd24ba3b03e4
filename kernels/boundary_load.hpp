#pragma once
// Neumann loads on one side of a patch: one Kokkos::parallel_for over the side's elements.
//
// Weak form   l(v) = \int_{Gamma_side} v . t ds       (times the thickness)
//   t = -p(xi) n for a normal pressure (positive pushes into the body; n outward unit normal),
//   p(xi) = p0 + (p1 - p0) (xi - xi_min) / (xi_max - xi_min) for a linear pressure,
//   t given for a traction.
// f_a += \sum_q R_a(xi_q) t(xi_q) |dx/dxi| w_q, summed atomically into f (overlap dofs, 2 lid + c).
// Cost per quadrature point: ~ 10 (p + 1) flops; reads the p + 1 side control points.
//
// Finite kinematics: a pressure follows the deformed side (AssembleFollowerPressure below).
#include "kernels/numbering.hpp"
#include "kernels/scatter.hpp"
#include "kernels/sides.hpp"
#include "kernels/types.hpp"

namespace iga {

/// Space dimension of the boundary kernels (side loads here, contact in kernels/contact_*.hpp):
/// 2-D, sides are curves. Their dofs are dof_of(l, c, kBoundaryDim) (kernels/numbering.hpp).
constexpr int kBoundaryDim = 2;

struct SideLoad {
  int side = 0;          // 0 west, 1 east, 2 south, 3 north: 2 direction + end (kernels/sides.hpp)
  int kind = 0;          // 1 pressure (and linear pressure), 3 traction
  double p0 = 0, p1 = 0; // pressure at the side's start and end
  double t[2] = {0, 0};
  double scale = 1.0;    // load factor times thickness
  int orientation = 1;   // +1 right-handed patch, -1 left-handed
};

/// Control point index of the k-th control point along a side.
KOKKOS_INLINE_FUNCTION int side_cp(const PatchData& pd, int side, int k) { return side_tensor_index(side, &k, pd.n, 2); }

/// Patch element that element k along a side belongs to.
KOKKOS_INLINE_FUNCTION int side_patch_element(const PatchData& pd, int side, int k) { return side_tensor_index(side, &k, pd.ne, 2); }

/// Outward unit normal of a side from the tangent dx/dxi along it (the sign rule of kernels/sides.hpp).
KOKKOS_INLINE_FUNCTION void side_normal(int side, int orientation, const double t[2], double n[2]) {
  const double len = kmath::sqrt(t[0] * t[0] + t[1] * t[1]);
  const double s = static_cast<double>(side_normal_sign(side)) * orientation;
  n[0] = s * t[1] / len;
  n[1] = -s * t[0] / len;
}

template <class FView>
struct AssembleSideLoad {
  PatchData pd;
  SideLoad load;
  GaussRule g;
  FView f;
  int e_begin = 0, e_end = 0;  // patch elements of this rank: a side element is done by its owner

  /// Patch element that side element k belongs to.
  KOKKOS_INLINE_FUNCTION int patch_element(int k) const { return side_patch_element(pd, load.side, k); }

  KOKKOS_INLINE_FUNCTION void operator()(const int k) const {
    const int pe = patch_element(k);
    if (pe < e_begin || pe >= e_end) return;
    const int d = side_tangent_direction(load.side);  // parameter direction along the side
    const int p = pd.p[d], nb = pd.n[d];
    const double* U = pd.U[d].data();
    const int s = pd.span[d](k);
    const double a = U[s], b = U[s + 1], h = 0.5 * (b - a);
    const double umin = U[0], umax = U[nb + p];
    for (int q = 0; q < g.n; ++q) {
      const double u = a + h * (g.x[q] + 1.0);
      double ders[3][kMaxBasis1D], w[kMaxBasis1D], R[3][kMaxBasis1D];
      bspline_ders(s, u, p, U, 1, ders);
      for (int j = 0; j <= p; ++j) { w[j] = pd.cp(side_cp(pd, load.side, s - p + j), kBoundaryDim); ders[2][j] = 0; }   // the weight column
      rationalize_1d(p, ders, w, R);
      double tan[2] = {0, 0};
      for (int j = 0; j <= p; ++j)
        for (int c = 0; c < 2; ++c) tan[c] += R[1][j] * pd.cp(side_cp(pd, load.side, s - p + j), c);
      const double jac = kmath::sqrt(tan[0] * tan[0] + tan[1] * tan[1]);
      double tr[2] = {load.t[0], load.t[1]};
      if (load.kind == 1) {
        double n[2];
        side_normal(load.side, load.orientation, tan, n);
        const double pr = load.p0 + (load.p1 - load.p0) * (u - umin) / (umax - umin);
        tr[0] = -pr * n[0];
        tr[1] = -pr * n[1];
      }
      const double wq = g.w[q] * h * jac * load.scale;
      for (int j = 0; j <= p; ++j) {
        const int l = pd.lid(side_cp(pd, load.side, s - p + j));
        if (l < 0) continue;
        for (int c = 0; c < 2; ++c) Kokkos::atomic_add(&f(dof_of(l, c, kBoundaryDim)), R[0][j] * tr[c] * wq);
      }
    }
  }
};

/// A pressure on the deformed side (finite kinematics): a follower load, part of the
/// displacement-dependent force (System::assemble_internal), with its own tangent.
///   -f_ext,a = \int p R_a n ds = \int p R_a s N(x_,xi) dxi,   N(t) = (t_y, -t_x),
///   x_,xi = \sum_b R_b' (X_b + u_b),  s = +-1 (side and orientation: n outward),
/// linear in u, so its derivative is constant in u (not in p):
///   d(-f_ext,a0)/du_b1 = \int p s R_a R_b' dxi,   d(-f_ext,a1)/du_b0 = -\int p s R_a R_b' dxi.
/// The pressure p (and the linear p0 -> p1) is at the current point of the load path.
/// Non-symmetric (the pressure stiffness); the per-side element matrix is 2 (p + 1) square.
/// Cost per quadrature point: ~ 10 (p + 1) + 4 (p + 1)^2 flops; (2 (p + 1))^2 atomic additions.
template <class LocalMatrix>
struct AssembleFollowerPressure {
  PatchData pd;
  SideLoad load;   // kind 1; p0, p1 at the current load point; scale = thickness
  GaussRule g;
  int e_begin = 0, e_end = 0;
  Kokkos::View<const double*, MemSpace> u = {};   // overlap displacements (2 lid + c)
  Kokkos::View<double*, MemSpace> f = {};         // overlap: -f_ext summed in (when force)
  ElementScatter<LocalMatrix> scatter = {};
  bool force = false, tangent = false;

  KOKKOS_INLINE_FUNCTION int patch_element(int k) const { return side_patch_element(pd, load.side, k); }

  KOKKOS_INLINE_FUNCTION void operator()(const int k) const {
    const int pe = patch_element(k);
    if (pe < e_begin || pe >= e_end) return;
    const int d = side_tangent_direction(load.side);
    const int p = pd.p[d], nb = pd.n[d];
    const double* U = pd.U[d].data();
    const int s = pd.span[d](k);
    const double a = U[s], b = U[s + 1], h = 0.5 * (b - a);
    const double umin = U[0], umax = U[nb + p];
    const double sgn = static_cast<double>(side_normal_sign(load.side)) * load.orientation;
    int cps[kMaxBasis1D];
    double x[kMaxBasis1D][2];   // current positions of the side's control points
    for (int j = 0; j <= p; ++j) {
      cps[j] = side_cp(pd, load.side, s - p + j);
      const int l = pd.lid(cps[j]);
      for (int c = 0; c < 2; ++c) x[j][c] = pd.cp(cps[j], c) + (u.extent(0) > 0 ? u(dof_of(l, c, kBoundaryDim)) : 0.0);
    }
    double fe[kBoundaryDim * kMaxBasis1D] = {}, Ke[kBoundaryDim * kMaxBasis1D][kBoundaryDim * kMaxBasis1D] = {};
    for (int q = 0; q < g.n; ++q) {
      const double uq = a + h * (g.x[q] + 1.0);
      double ders[3][kMaxBasis1D], w[kMaxBasis1D], R[3][kMaxBasis1D];
      bspline_ders(s, uq, p, U, 1, ders);
      // the weight column follows the coordinates (solver/patch_data.cpp)
      for (int j = 0; j <= p; ++j) { w[j] = pd.cp(cps[j], kBoundaryDim); ders[2][j] = 0; }
      rationalize_1d(p, ders, w, R);
      double tan[2] = {0, 0};
      for (int j = 0; j <= p; ++j)
        for (int c = 0; c < 2; ++c) tan[c] += R[1][j] * x[j][c];
      const double pr = load.p0 + (load.p1 - load.p0) * (uq - umin) / (umax - umin);
      const double wq = g.w[q] * h * load.scale * pr * sgn;
      for (int i = 0; i <= p; ++i) {
        fe[dof_of(i, 0, kBoundaryDim)] += R[0][i] * tan[1] * wq;
        fe[dof_of(i, 1, kBoundaryDim)] -= R[0][i] * tan[0] * wq;
        for (int j = 0; j <= p; ++j) {
          Ke[dof_of(i, 0, kBoundaryDim)][dof_of(j, 1, kBoundaryDim)] += R[0][i] * R[1][j] * wq;
          Ke[dof_of(i, 1, kBoundaryDim)][dof_of(j, 0, kBoundaryDim)] -= R[0][i] * R[1][j] * wq;
        }
      }
    }
    if (force)
      for (int j = 0; j <= p; ++j) {
        const int l = pd.lid(cps[j]);
        for (int c = 0; c < kBoundaryDim; ++c) Kokkos::atomic_add(&f(dof_of(l, c, kBoundaryDim)), fe[dof_of(j, c, kBoundaryDim)]);
      }
    if (tangent) scatter.template add<kMaxBasis1D>(pd.lid, cps, p + 1, &Ke[0][0], kBoundaryDim * kMaxBasis1D);
  }
};

}  // namespace iga
