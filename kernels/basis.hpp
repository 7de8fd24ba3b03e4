#pragma once
// NURBS basis values and physical gradients at every quadrature point of a patch's elements,
// in D = 2 or 3 dimensions, stored for reuse: one Kokkos::parallel_for over (element,
// quadrature point).
//
// Output layout (e: element of the range, q = q0 + n0 (q1 + n1 q2): tensor Gauss point,
// a = l0 + (p0 + 1)(l1 + (p1 + 1) l2): function)
//   R   (ne, nq, nen)      basis values
//   dR  (ne, nq, nen, D)   dR/dx_J
//   JxW (ne, nq)           |det J| times the Gauss weight (parametric map included)
// Cost per point (P = p_d, nen = (P+1)^D): 2-D ~ 12 P^2 (1-D derivatives) + 30 nen flops,
// 3-D ~ 18 P^2 + 45 nen; reads nen control points (8 (D + 1) nen bytes), writes
// 8 ((D + 1) nen + 1) bytes.
#include "kernels/types.hpp"

namespace iga {

template <int D, int P>
struct EvaluateBasisT {
  PatchDataT<D, MemSpace> pd;
  GaussRule g[D];
  int e_begin = 0;
  Kokkos::View<double***, MemSpace> R;
  Kokkos::View<double****, MemSpace> dR;
  Kokkos::View<double**, MemSpace> JxW;

  static constexpr int nen_max = kNen<D, P>;
  static constexpr double flops_per_point() {
    return D == 2 ? 12.0 * P * P + 30.0 * nen_max : 18.0 * P * P + 45.0 * nen_max;
  }
  static constexpr double bytes_per_point() { return 8.0 * (D + 1) * nen_max + 8.0 * ((D + 1) * nen_max + 1); }

  KOKKOS_INLINE_FUNCTION void operator()(const int k, const int q) const {
    const int e = e_begin + k;
    int ei[D], s[D], qi[D], nq[D];
    pd.element_spans(e, ei, s);
    for (int d = 0; d < D; ++d) nq[d] = g[d].n;
    tensor_ij_d<D>(q, nq, qi);
    double xi[D], h[D];
    for (int d = 0; d < D; ++d) {
      const double a = pd.U[d](s[d]), b = pd.U[d](s[d] + 1);
      h[d] = 0.5 * (b - a);
      xi[d] = a + h[d] * (g[d].x[qi[d]] + 1);
    }
    double r[nen_max], dr[nen_max][D], x[D];
    const double det = nurbs_grad<P>(pd, s, xi, r, dr, x);
    const int nen = pd.nen();
    for (int a = 0; a < nen; ++a) {
      R(k, q, a) = r[a];
      for (int J = 0; J < D; ++J) dR(k, q, a, J) = dr[a][J];
    }
    double jw = kmath::fabs(det);
    for (int d = 0; d < D; ++d) jw *= g[d].w[qi[d]];
    for (int d = 0; d < D; ++d) jw *= h[d];
    JxW(k, q) = jw;
  }

  void run(int e_end) {
    int nq = 1;
    for (int d = 0; d < D; ++d) nq *= g[d].n;
    const int ne = e_end - e_begin;
    if (R.extent(0) != static_cast<size_t>(ne)) {
      R = Kokkos::View<double***, MemSpace>("R", ne, nq, pd.nen());
      dR = Kokkos::View<double****, MemSpace>("dR", ne, nq, pd.nen(), D);
      JxW = Kokkos::View<double**, MemSpace>("JxW", ne, nq);
    }
    Kokkos::parallel_for("iga::EvaluateBasis",
                         Kokkos::MDRangePolicy<ExecSpace, Kokkos::Rank<2>>({0, 0}, {ne, nq}), *this);
  }
};

template <int P>
using EvaluateBasis = EvaluateBasisT<2, P>;

}  // namespace iga
