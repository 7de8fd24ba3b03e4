#pragma once
// Internal force and tangent of plane elasticity on a NURBS patch, for every material (small
// strain linear, Saint Venant-Kirchhoff, neo-Hookean: kernels/material.hpp), summed into a local
// (KokkosSparse) matrix and vector: one Kokkos::parallel_for over the elements of this rank.
//
// Weak form (total Lagrangian; small strain is the special case P = sigma(eps), A = D)
//   f_int(u) . v = \int_Omega0 P(F) : Grad v dOmega0,   F = I + Grad u     (P includes thickness)
//   K_T(u) = d f_int / du:  K_ab,ik = \sum_q R_a,J(x_q) A_iJkL(F_q) R_b,L(x_q) |det J(x_q)| w_q
//   f_a,i  = \sum_q P_iJ(F_q) R_a,J(x_q) |det J(x_q)| w_q,   Grad u = \sum_a u_a (x) Grad R_a
// With the small-strain linear material A_iJkL = D[v(iJ)][v(kL)] and R_a,J A R_b,L = B_a^T D B_b,
// B_a = [[R_a,x, 0], [0, R_a,y], [R_a,y, R_a,x]]: the linear stiffness, and f_int = K u.
// Degrees of freedom: dof (a, c) of control point a, component c, is overlap LID 2 lid(a) + c.
//
// Data layout (PatchData): knots U0[n0 + p0 + 1], U1[n1 + p1 + 1]; cp[n0 n1][3] = (x, y, w);
// elements numbered e = e0 + ne0 e1 with spans span0[e0], span1[e1]. Displacements u[2 L + c]
// in the overlap numbering L = lid(a); the force is summed atomically into f[2 L + c].
// Per element: nen = (p0+1)(p1+1) functions, nq = n0 n1 points of a tensor rule: Gauss,
// (p0+1)(p1+1), or the patch's spline rule (solver.quadrature: spline, model/quadrature.hpp),
// about (p0+2)(p1+2)/4 on smooth patches; PatchData qx/qw/qoff hold it, element_rule_1d reads it.
//
// Cost per quadrature point, stated for the benchmarks (P = p0 = p1, nen = (P+1)^2):
//   basis     : 1-D B-spline derivatives once per element and direction at the P + 1 Gauss
//               abscissae (amortised ~ 2 (6 P^2 + 10 P) / (P + 1) per point), sum-factorised
//               rational map, Jacobian, inverse and gradients (nurbs_grad_1d)  ~ 25 nen + 9 P + 30 flops
//   gradient  : Grad u (force, or finite-strain tangent)                      4 nen flops
//   material  : P and A (material_response)                                   10 .. 200 flops
//   force     : 4 nen flops;  tangent: 32 nen (rows a) + 16 nen (nen + 1) / 2 (blocks a <= b) ~ 8 nen^2 flops
//   reads     : the element's nen control points (3 doubles), knots, 2 nen displacements
//   writes    : (2 nen)^2 matrix entries and 2 nen force entries summed atomically
// The element matrix lives in a thread-private array of (2 (P+1)^2)^2 doubles.
#include <KokkosSparse_CrsMatrix.hpp>

#include "kernels/material.hpp"
#include "kernels/scatter.hpp"
#include "kernels/types.hpp"

namespace iga {

/// Forms element e's internal force fe[2 a + i] (when Force) and tangent Ke (row-major,
/// 2 nen x 2 nen, when Tangent) at the element displacements ue[a][i] (ue may be null: u = 0).
/// Returns false where the material response is inadmissible (J <= 0: NaN entries).
/// Shared by the kernel below, the host reference in the tests and the benchmarks.
template <int P, bool Force, bool Tangent>
KOKKOS_INLINE_FUNCTION bool element_internal(const PatchData& pd, const Material& mat, const GaussRule& g0,
                                             const GaussRule& g1, int e, const double (*ue)[2], double* fe,
                                             double Ke[2 * (P + 1) * (P + 1)][2 * (P + 1) * (P + 1)]) {
  constexpr int MaxNen = (P + 1) * (P + 1);
  const int nen = pd.nen();
  const int e0 = e % pd.ne[0], e1 = e / pd.ne[0];
  const int s0 = pd.span0(e0), s1 = pd.span1(e1);
  // the element's rule: a tensor product of 1-D rules (Gauss, or the patch's spline rule)
  double x0[kMaxGauss], w0[kMaxGauss], x1[kMaxGauss], w1[kMaxGauss];
  const int n0 = element_rule_1d(pd, 0, e0, s0, g0, x0, w0), n1 = element_rule_1d(pd, 1, e1, s1, g1, x1, w1);
  // per element: 1-D B-spline values and derivatives at the abscissae of each direction
  // (tensor product: n0 + n1 1-D evaluations instead of 2 per quadrature point) and the
  // homogeneous control points
  double Nq[kMaxGauss][3][kMaxBasis1D], Mq[kMaxGauss][3][kMaxBasis1D], cw[MaxNen][3];
  for (int q = 0; q < n0; ++q) bspline_ders(s0, x0[q], pd.p[0], pd.U0.data(), 1, Nq[q]);
  for (int q = 0; q < n1; ++q) bspline_ders(s1, x1[q], pd.p[1], pd.U1.data(), 1, Mq[q]);
  element_homogeneous_cp<P>(pd, s0, s1, cw);
  if (Force)
    for (int i = 0; i < 2 * nen; ++i) fe[i] = 0.0;
  if (Tangent)
    for (int i = 0; i < 2 * nen; ++i)
      for (int j = 0; j < 2 * nen; ++j) Ke[i][j] = 0.0;
  // the gradient is needed for the force, and for the tangent of a finite-strain material
  const bool grad = ue != nullptr && (Force || !mat.constant_tangent());
  bool ok = true;
  double R[MaxNen], dR[MaxNen][2], x[2];
  for (int qj = 0; qj < n1; ++qj)
    for (int qi = 0; qi < n0; ++qi) {
      const double det = nurbs_grad_1d<P>(pd.p[0], pd.p[1], Nq[qi], Mq[qj], cw, R, dR, x);
      const double wq = kmath::fabs(det) * w0[qi] * w1[qj];
      double H[2][2] = {{0, 0}, {0, 0}};
      if (grad)
        for (int a = 0; a < nen; ++a)
          for (int i = 0; i < 2; ++i) {
            H[i][0] += ue[a][i] * dR[a][0];
            H[i][1] += ue[a][i] * dR[a][1];
          }
      double Pk[2][2], P33, A[4][4];
      ok = material_response<Tangent>(mat, H, Pk, P33, A) && ok;
      if (Force)
        for (int a = 0; a < nen; ++a)
          for (int i = 0; i < 2; ++i) fe[2 * a + i] += (Pk[i][0] * dR[a][0] + Pk[i][1] * dR[a][1]) * wq;
      if (Tangent)
        for (int a = 0; a < nen; ++a) {
          // G[i][k][L] = sum_J R_a,J A_iJkL w_q
          double G[2][2][2];
          for (int i = 0; i < 2; ++i)
            for (int k = 0; k < 2; ++k)
              for (int L = 0; L < 2; ++L)
                G[i][k][L] = (dR[a][0] * A[2 * i][2 * k + L] + dR[a][1] * A[2 * i + 1][2 * k + L]) * wq;
          for (int b = a; b < nen; ++b) {
            const double bx = dR[b][0], by = dR[b][1];
            for (int i = 0; i < 2; ++i)
              for (int k = 0; k < 2; ++k) Ke[2 * a + i][2 * b + k] += G[i][k][0] * bx + G[i][k][1] * by;
          }
        }
    }
  // A is symmetric (hyperelastic materials): K_ba = K_ab^T
  if (Tangent)
    for (int a = 0; a < nen; ++a)
      for (int b = a + 1; b < nen; ++b)
        for (int c = 0; c < 2; ++c)
          for (int d = 0; d < 2; ++d) Ke[2 * b + d][2 * a + c] = Ke[2 * a + c][2 * b + d];
  return ok;
}

/// The element stiffness at u = 0 (the small-strain stiffness for every material).
template <int P>
KOKKOS_INLINE_FUNCTION void element_stiffness(const PatchData& pd, const Material& mat, const GaussRule& g0,
                                              const GaussRule& g1, int e,
                                              double Ke[2 * (P + 1) * (P + 1)][2 * (P + 1) * (P + 1)]) {
  element_internal<P, false, true>(pd, mat, g0, g1, e, nullptr, nullptr, Ke);
}

/// Global control point index of local function a of element e.
KOKKOS_INLINE_FUNCTION int element_cp(const PatchData& pd, int e, int a) {
  const int s0 = pd.span0(e % pd.ne[0]), s1 = pd.span1(e / pd.ne[0]);
  const int i = a % (pd.p[0] + 1), j = a / (pd.p[0] + 1);
  return s0 - pd.p[0] + i + (s1 - pd.p[1] + j) * pd.n[0];
}

/// Assembles the internal force and/or the tangent of the elements [e_begin, e_end) of one
/// patch (atomic sums: correct on threaded and GPU backends where elements share control points).
/// u: overlap displacements (empty: u = 0); f: overlap force; K through `scatter`
/// (kernels/scatter.hpp: one matrix, or owned + ghost rows on several ranks).
template <int P, class LocalMatrix>
struct AssembleInternal {
  PatchData pd;
  Material mat;
  GaussRule g0, g1;
  int e_begin = 0;
  ElementScatter<LocalMatrix> scatter = {};
  Kokkos::View<const double*, MemSpace> u = {};
  Kokkos::View<double*, MemSpace> f = {};
  bool force = false, tangent = false;   // what run() assembles: f (into f), K (through scatter)

  template <bool Force, bool Tangent>
  KOKKOS_INLINE_FUNCTION void element(const int e) const {
    constexpr int MaxDof = 2 * (P + 1) * (P + 1);
    const int nen = pd.nen();
    int cps[MaxDof / 2];
    double ue[MaxDof / 2][2], fe[MaxDof];
    double Ke[Tangent ? MaxDof : 1][Tangent ? MaxDof : 1];
    const bool have_u = u.extent(0) > 0;
    for (int a = 0; a < nen; ++a) {
      cps[a] = element_cp(pd, e, a);
      const int l = pd.lid(cps[a]);
      ue[a][0] = have_u ? u(2 * l) : 0.0;
      ue[a][1] = have_u ? u(2 * l + 1) : 0.0;
    }
    element_internal<P, Force, Tangent>(pd, mat, g0, g1, e, have_u ? ue : nullptr, fe,
                                        reinterpret_cast<double(*)[MaxDof]>(&Ke[0][0]));
    if (Force)
      for (int a = 0; a < nen; ++a) {
        const int l = pd.lid(cps[a]);
        Kokkos::atomic_add(&f(2 * l), fe[2 * a]);
        Kokkos::atomic_add(&f(2 * l + 1), fe[2 * a + 1]);
      }
    if (Tangent) scatter.template add<MaxDof / 2>(pd.lid, cps, nen, &Ke[0][0], MaxDof);
  }

  void run(int e_end) {
    const int eb = e_begin;
    const auto policy = Kokkos::RangePolicy<ExecSpace>(0, e_end - e_begin);
    const AssembleInternal self = *this;
    if (force && tangent)
      Kokkos::parallel_for("iga::AssembleInternal(f, K)", policy, KOKKOS_LAMBDA(const int k) { self.template element<true, true>(eb + k); });
    else if (force)
      Kokkos::parallel_for("iga::AssembleInternal(f)", policy, KOKKOS_LAMBDA(const int k) { self.template element<true, false>(eb + k); });
    else if (tangent)
      Kokkos::parallel_for("iga::AssembleInternal(K)", policy, KOKKOS_LAMBDA(const int k) { self.template element<false, true>(eb + k); });
  }
};

}  // namespace iga
