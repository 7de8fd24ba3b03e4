#pragma once
// Element stiffness of plane linear elasticity on a NURBS patch, summed into a local
// (KokkosSparse) matrix: one Kokkos::parallel_for over the elements of this rank.
//
// Weak form       a(u, v) = \int_Omega eps(v) : D eps(u) dOmega      (D includes thickness)
// Element matrix  K_ab = \sum_q B_a(x_q)^T D B_b(x_q) |det J(x_q)| w_q,
//                 B_a = [[R_a,x, 0], [0, R_a,y], [R_a,y, R_a,x]]
// Degrees of freedom: dof (a, c) of control point a, component c, is overlap LID 2 lid(a) + c.
//
// Data layout (PatchData): knots U0[n0 + p0 + 1], U1[n1 + p1 + 1]; cp[n0 n1][3] = (x, y, w);
// elements numbered e = e0 + ne0 e1 with spans span0[e0], span1[e1].
// Per element: nen = (p0+1)(p1+1) functions, nq = (p0+1)(p1+1) Gauss points (tensor rule).
//
// Cost per quadrature point, stated for the benchmarks (P = p0 = p1, nen = (P+1)^2):
//   basis     : 1-D B-spline derivatives once per element and direction at the P + 1 Gauss
//               abscissae (amortised ~ 2 (6 P^2 + 10 P) / (P + 1) per point), sum-factorised
//               rational map, Jacobian, inverse and gradients (nurbs_grad_1d)  ~ 25 nen + 9 P + 30 flops
//   stiffness : nen (nen + 1) / 2 blocks of 2 x 2, ~ 13 flops each      ~ 6.5 nen^2 flops
//   reads     : the element's nen control points (3 doubles) and knots   24 nen bytes / element
//   writes    : (2 nen)^2 matrix entries summed atomically               8 (2 nen)^2 bytes / element
// The element matrix lives in a thread-private array of (2 (P+1)^2)^2 doubles.
#include <KokkosSparse_CrsMatrix.hpp>

#include "kernels/types.hpp"

namespace iga {

/// Forms the element matrix of element e (in the patch's numbering) into Ke (row-major,
/// 2 nen x 2 nen). Shared by the kernel below and the benchmarks.
template <int P>
KOKKOS_INLINE_FUNCTION void element_stiffness(const PatchData& pd, const Material& mat, const GaussRule& g0,
                                              const GaussRule& g1, int e,
                                              double Ke[2 * (P + 1) * (P + 1)][2 * (P + 1) * (P + 1)]) {
  constexpr int MaxNen = (P + 1) * (P + 1);
  const int nen = pd.nen();
  const int s0 = pd.span0(e % pd.ne[0]), s1 = pd.span1(e / pd.ne[0]);
  const double ua = pd.U0(s0), ub = pd.U0(s0 + 1), va = pd.U1(s1), vb = pd.U1(s1 + 1);
  const double hu = 0.5 * (ub - ua), hv = 0.5 * (vb - va);
  const double D00 = mat.D[0][0], D01 = mat.D[0][1], D11 = mat.D[1][1], D22 = mat.D[2][2];
  // per element: 1-D B-spline values and derivatives at the Gauss abscissae of each direction
  // (tensor product: (p0 + 1) + (p1 + 1) 1-D evaluations instead of 2 per quadrature point)
  // and the homogeneous control points
  double Nq[kMaxGauss][3][kMaxBasis1D], Mq[kMaxGauss][3][kMaxBasis1D], cw[MaxNen][3];
  for (int q = 0; q < g0.n; ++q) bspline_ders(s0, ua + hu * (g0.x[q] + 1.0), pd.p[0], pd.U0.data(), 1, Nq[q]);
  for (int q = 0; q < g1.n; ++q) bspline_ders(s1, va + hv * (g1.x[q] + 1.0), pd.p[1], pd.U1.data(), 1, Mq[q]);
  element_homogeneous_cp<P>(pd, s0, s1, cw);
  for (int i = 0; i < 2 * nen; ++i)
    for (int j = 0; j < 2 * nen; ++j) Ke[i][j] = 0.0;
  double R[MaxNen], dR[MaxNen][2], x[2];
  for (int qj = 0; qj < g1.n; ++qj)
    for (int qi = 0; qi < g0.n; ++qi) {
      const double det = nurbs_grad_1d<P>(pd.p[0], pd.p[1], Nq[qi], Mq[qj], cw, R, dR, x);
      const double wq = kmath::fabs(det) * g0.w[qi] * g1.w[qj] * hu * hv;
      for (int a = 0; a < nen; ++a) {
        const double ax = dR[a][0] * wq, ay = dR[a][1] * wq;
        for (int b = a; b < nen; ++b) {
          const double bx = dR[b][0], by = dR[b][1];
          Ke[2 * a][2 * b] += D00 * ax * bx + D22 * ay * by;
          Ke[2 * a][2 * b + 1] += D01 * ax * by + D22 * ay * bx;
          Ke[2 * a + 1][2 * b] += D01 * ay * bx + D22 * ax * by;
          Ke[2 * a + 1][2 * b + 1] += D11 * ay * by + D22 * ax * bx;
        }
      }
    }
  for (int a = 0; a < nen; ++a)
    for (int b = a + 1; b < nen; ++b)
      for (int c = 0; c < 2; ++c)
        for (int d = 0; d < 2; ++d) Ke[2 * b + d][2 * a + c] = Ke[2 * a + c][2 * b + d];
}

/// Global control point index of local function a of element e.
KOKKOS_INLINE_FUNCTION int element_cp(const PatchData& pd, int e, int a) {
  const int s0 = pd.span0(e % pd.ne[0]), s1 = pd.span1(e / pd.ne[0]);
  const int i = a % (pd.p[0] + 1), j = a / (pd.p[0] + 1);
  return s0 - pd.p[0] + i + (s1 - pd.p[1] + j) * pd.n[0];
}

/// Assembles the elements [e_begin, e_end) of one patch into A (atomic sums: correct on
/// threaded and GPU backends where elements share control points).
/// One matrix (orow empty): rows and columns are the overlap numbering pd.lid.
/// Owned + ghost (several ranks): the row of control point a goes to A, the owned rows'
/// matrix, at local row orow(a) with columns ocol(.), when a is owned here; otherwise to G,
/// the few shared rows, at row grow(a) with columns pd.lid(.). (An owned control point couples
/// with every control point of its elements, so ocol is defined wherever it is used.)
template <int P, class LocalMatrix>
struct AssembleElasticity {
  PatchData pd;
  Material mat;
  GaussRule g0, g1;
  int e_begin = 0;
  LocalMatrix A;
  LocalMatrix G = {};
  Kokkos::View<const int*, MemSpace> orow = {}, ocol = {}, grow = {};

  KOKKOS_INLINE_FUNCTION void operator()(const int k) const {
    constexpr int MaxDof = 2 * (P + 1) * (P + 1);
    const int e = e_begin + k;
    double Ke[MaxDof][MaxDof];
    element_stiffness<P>(pd, mat, g0, g1, e, Ke);
    const int nen = pd.nen();
    int cols[MaxDof], gcols[MaxDof], cps[MaxDof / 2];
    const bool split = orow.extent(0) > 0;
    for (int a = 0; a < nen; ++a) {
      const int cp = cps[a] = element_cp(pd, e, a);
      const int l = pd.lid(cp), o = split ? ocol(cp) : l;
      cols[2 * a] = 2 * o;
      cols[2 * a + 1] = 2 * o + 1;
      gcols[2 * a] = 2 * l;
      gcols[2 * a + 1] = 2 * l + 1;
    }
    for (int r = 0; r < 2 * nen; ++r) {
      const int cp = cps[r / 2];
      if (!split) A.sumIntoValues(cols[r], cols, 2 * nen, Ke[r], false, true);
      else if (orow(cp) >= 0) A.sumIntoValues(2 * orow(cp) + r % 2, cols, 2 * nen, Ke[r], false, true);
      else G.sumIntoValues(2 * grow(cp) + r % 2, gcols, 2 * nen, Ke[r], false, true);
    }
  }

  void run(int e_end) {
    Kokkos::parallel_for("iga::AssembleElasticity", Kokkos::RangePolicy<ExecSpace>(0, e_end - e_begin), *this);
  }
};

}  // namespace iga
