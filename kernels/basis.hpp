#pragma once
// NURBS basis values and physical gradients at every quadrature point of a patch's elements,
// stored for reuse: one Kokkos::parallel_for over (element, quadrature point).
//
// Output layout (e: element of the range, q = qi + qj n0: tensor Gauss point, a: function)
//   R   (ne, nq, nen)      basis values
//   dR  (ne, nq, nen, 2)   dR/dx, dR/dy
//   JxW (ne, nq)           |det J| times the Gauss weight (parametric map included)
// Cost per point (P = p0 = p1, nen = (P+1)^2): ~ 12 P^2 (1-D derivatives) + 30 nen flops;
// reads nen control points (24 nen bytes), writes 8 (3 nen + 1) bytes.
#include "kernels/types.hpp"

namespace iga {

template <int P>
struct EvaluateBasis {
  PatchData pd;
  GaussRule g0, g1;
  int e_begin = 0;
  Kokkos::View<double***, MemSpace> R;
  Kokkos::View<double****, MemSpace> dR;
  Kokkos::View<double**, MemSpace> JxW;

  static constexpr double flops_per_point() { return 12.0 * P * P + 30.0 * (P + 1) * (P + 1); }
  static constexpr double bytes_per_point() { return 24.0 * (P + 1) * (P + 1) + 8.0 * (3 * (P + 1) * (P + 1) + 1); }

  KOKKOS_INLINE_FUNCTION void operator()(const int k, const int q) const {
    const int e = e_begin + k;
    const int s0 = pd.span0(e % pd.ne[0]), s1 = pd.span1(e / pd.ne[0]);
    const double ua = pd.U0(s0), ub = pd.U0(s0 + 1), va = pd.U1(s1), vb = pd.U1(s1 + 1);
    const int qi = q % g0.n, qj = q / g0.n;
    const double hu = 0.5 * (ub - ua), hv = 0.5 * (vb - va);
    double r[(P + 1) * (P + 1)], dr[(P + 1) * (P + 1)][2], x[2];
    const double det = nurbs_grad<P>(pd, s0, s1, ua + hu * (g0.x[qi] + 1), va + hv * (g1.x[qj] + 1), r, dr, x);
    const int nen = pd.nen();
    for (int a = 0; a < nen; ++a) {
      R(k, q, a) = r[a];
      dR(k, q, a, 0) = dr[a][0];
      dR(k, q, a, 1) = dr[a][1];
    }
    JxW(k, q) = kmath::fabs(det) * g0.w[qi] * g1.w[qj] * hu * hv;
  }

  void run(int e_end) {
    const int ne = e_end - e_begin, nq = g0.n * g1.n;
    if (R.extent(0) != static_cast<size_t>(ne)) {
      R = Kokkos::View<double***, MemSpace>("R", ne, nq, pd.nen());
      dR = Kokkos::View<double****, MemSpace>("dR", ne, nq, pd.nen(), 2);
      JxW = Kokkos::View<double**, MemSpace>("JxW", ne, nq);
    }
    Kokkos::parallel_for("iga::EvaluateBasis",
                         Kokkos::MDRangePolicy<ExecSpace, Kokkos::Rank<2>>({0, 0}, {ne, nq}), *this);
  }
};

}  // namespace iga
