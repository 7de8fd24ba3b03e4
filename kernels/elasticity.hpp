#pragma once
// Internal force and tangent of elasticity on a NURBS patch in D = 2 (plane) or 3 dimensions,
// for every material (small strain linear, Saint Venant-Kirchhoff, neo-Hookean:
// kernels/material.hpp), summed into a local (KokkosSparse) matrix and vector: one
// Kokkos::parallel_for over the elements of this rank. One code path for both dimensions:
// the kernels take the compile-time dimension D and degree P (types.hpp, dispatch).
//
// Weak form (total Lagrangian; small strain is the special case P = sigma(eps), A = D)
//   f_int(u) . v = \int_Omega0 P(F) : Grad v dOmega0,   F = I + Grad u     (2-D: P includes thickness)
//   K_T(u) = d f_int / du:  K_ab,ik = \sum_q R_a,J(x_q) A_iJkL(F_q) R_b,L(x_q) |det J(x_q)| w_q
//   f_a,i  = \sum_q P_iJ(F_q) R_a,J(x_q) |det J(x_q)| w_q,   Grad u = \sum_a u_a (x) Grad R_a
// With the small-strain linear material A_iJkL = D[v(iJ)][v(kL)] and R_a,J A R_b,L = B_a^T D B_b
// (B_a the 3 x 2 (2-D) or 6 x 3 (3-D) strain-displacement block): the linear stiffness, and
// f_int = K u. Degrees of freedom: dof (a, c) of control point a, component c, is overlap LID
// D lid(a) + c (kernels/numbering.hpp, dof_of).
//
// Data layout (PatchDataT<D>): knots U[d][n_d + p_d + 1]; cp[n0 n1 (n2)][D + 1] = (x, y, (z,) w);
// elements numbered e = e0 + ne0 (e1 + ne1 e2) with spans span[d](e_d); local functions
// a = l0 + (p0 + 1)(l1 + (p1 + 1) l2). Displacements u[D L + c] in the overlap numbering
// L = lid(a); the force is summed atomically into f[D L + c]. Element arrays: ue[nen][D],
// fe[D nen], Ke[D nen][D nen] row-major with leading dimension ldk (rows D a + i, columns D b + k).
// Per element: nen = prod_d (p_d + 1) functions, nq = prod_d n_d points of a tensor rule: Gauss,
// p_d + 1 per direction, or the patch's spline rule (solver.quadrature: spline,
// model/quadrature.hpp), about (p + 2) / 2 per direction on smooth patches; PatchData qx/qw/qoff
// hold it, element_rule_1d reads it.
//
// Cost per quadrature point, stated for the benchmarks (P = p_d, nen = (P+1)^D):
//   basis     : 1-D B-spline derivatives once per element and direction (amortised), the
//               sum-factorised rational map, Jacobian, inverse and gradients (nurbs_grad_tensor)
//               2-D ~ 25 nen + 9 P + 30, 3-D ~ 41 nen + 80 flops
//   gradient  : Grad u (force, or finite-strain tangent)                      2 D^2 nen flops
//   material  : P and A (material_response)                                   2-D 10 .. 200, 3-D 54 .. 900 flops
//   force     : 2 D^2 nen flops
//   tangent   : rows a: 2 D^4 nen; blocks a <= b: 2 D^3 nen (nen + 1) / 2  ~ D^3 nen^2 flops
//               (2-D 8 nen^2, 3-D 27 nen^2: 421k flops a point at P = 4)
//   reads     : the element's nen control points (D + 1 doubles), knots, D nen displacements
//   writes    : (D nen)^2 matrix entries and D nen force entries summed atomically
// Where the element matrix lives: 2-D, a thread-private array of (2 (P+1)^2)^2 doubles (41 kB
// at P = 5), as before. 3-D: (3 (P+1)^3)^2 doubles is 3.4 MB at P = 5 (1.1 MB at P = 4), too
// big for a stack or GPU local memory, so AssembleInternalT<3> gives each element of a batch
// one row of a work View Kw(slot, (D nen_max)^2) (batches of up to ~64 MB, at least the
// concurrency); the other per-element arrays are nen-sized (R, dR[nen][3], cw[nen][4],
// ue[nen][3], fe[3 nen]: ~ 25 kB at P = 5). 3-D tangents: this element loop, or (sum_factorized)
// the element-wise sum factorisation of kernels/elasticity_sf3.hpp, O(p^7) per element, whose
// point fields sit in the same work view row after Ke. The row-wise sum-factorised formation
// over a whole patch (kernels/elasticity_sf.hpp) is 2-D only.
#include <KokkosSparse_CrsMatrix.hpp>

#include <algorithm>

#include "kernels/elasticity_sf3.hpp"
#include "kernels/material.hpp"
#include "kernels/scatter.hpp"
#include "kernels/types.hpp"

namespace iga {

/// Forms element e's internal force fe[D a + i] (when Force) and tangent Ke (row-major,
/// D nen x D nen with leading dimension ldk, when Tangent) at the element displacements ue[a][i]
/// (ue may be null: u = 0), with the Gauss rules *g[d] where the patch has no rule of its own.
/// Returns false where the material response is inadmissible (J <= 0: NaN entries).
/// Shared by the kernel below, the host references in the tests and the benchmarks; PD is a
/// PatchDataT<D, Mem> of either memory space the caller can read.
template <int P, bool Force, bool Tangent, class PD>
KOKKOS_INLINE_FUNCTION bool element_internal(const PD& pd, const Material& mat, const GaussRule* const g[],
                                             int e, const double (*ue)[PD::dim], double* fe, double* Ke, int ldk) {
  constexpr int D = PD::dim;
  constexpr int MaxNen = kNen<D, P>;
  const int nen = pd.nen();
  int ei[D], s[D];
  pd.element_spans(e, ei, s);
  // the element's rule: a tensor product of 1-D rules (Gauss, or the patch's spline rule), and
  // per direction the 1-D B-spline values and derivatives at its abscissae (tensor product:
  // sum_d n_d 1-D evaluations instead of D per quadrature point)
  double xq[D][kMaxGauss], wq1[D][kMaxGauss], Nq[D][kMaxGauss][2][kMaxBasis1D];
  int nq[D];
  for (int d = 0; d < D; ++d) {
    nq[d] = element_rule_1d(pd, d, ei[d], s[d], *g[d], xq[d], wq1[d]);
    for (int q = 0; q < nq[d]; ++q) bspline_ders(s[d], xq[d][q], pd.p[d], pd.U[d].data(), 1, Nq[d][q]);
  }
  double cw[MaxNen][D + 1];
  element_homogeneous_cp<P>(pd, s, cw);
  if (Force)
    for (int i = 0; i < D * nen; ++i) fe[i] = 0.0;
  if (Tangent)
    for (int i = 0; i < D * nen; ++i)
      for (int j = 0; j < D * nen; ++j) Ke[i * ldk + j] = 0.0;
  // the gradient is needed for the force, and for the tangent of a finite-strain material
  const bool grad = ue != nullptr && (Force || !mat.constant_tangent());
  bool ok = true;
  double R[MaxNen], dR[MaxNen][D], x[D];
  const int nq2 = D == 3 ? nq[D - 1] : 1;
  for (int q2 = 0; q2 < nq2; ++q2)
    for (int q1 = 0; q1 < nq[1]; ++q1)
      for (int q0 = 0; q0 < nq[0]; ++q0) {
        const int qd[3] = {q0, q1, q2};
        const double(*B[D])[kMaxBasis1D];
        for (int d = 0; d < D; ++d) B[d] = Nq[d][qd[d]];
        const double det = nurbs_grad_tensor<D, P>(pd.p, B, cw, R, dR, x);
        double wq = kmath::fabs(det);
        for (int d = 0; d < D; ++d) wq *= wq1[d][qd[d]];
        double H[D][D] = {};
        if (grad)
          for (int a = 0; a < nen; ++a)
            for (int i = 0; i < D; ++i)
              for (int J = 0; J < D; ++J) H[i][J] += ue[a][i] * dR[a][J];
        double Pk[D][D], P33, A[D * D][D * D];
        ok = material_response<Tangent>(mat, H, Pk, P33, A) && ok;
        if (Force)
          for (int a = 0; a < nen; ++a)
            for (int i = 0; i < D; ++i) {
              double t = Pk[i][0] * dR[a][0];
              for (int J = 1; J < D; ++J) t += Pk[i][J] * dR[a][J];
              fe[D * a + i] += t * wq;
            }
        if (Tangent)
          for (int a = 0; a < nen; ++a) {
            // G[i][k][L] = sum_J R_a,J A_iJkL w_q
            double G[D][D][D];
            for (int i = 0; i < D; ++i)
              for (int k = 0; k < D; ++k)
                for (int L = 0; L < D; ++L) {
                  double t = dR[a][0] * A[D * i][D * k + L];
                  for (int J = 1; J < D; ++J) t += dR[a][J] * A[D * i + J][D * k + L];
                  G[i][k][L] = t * wq;
                }
            for (int b = a; b < nen; ++b)
              for (int i = 0; i < D; ++i) {
                double* row = Ke + (D * a + i) * ldk + D * b;
                for (int k = 0; k < D; ++k) {
                  double t = G[i][k][0] * dR[b][0];
                  for (int L = 1; L < D; ++L) t += G[i][k][L] * dR[b][L];
                  row[k] += t;
                }
              }
          }
      }
  // A is symmetric (hyperelastic materials): K_ba = K_ab^T
  if (Tangent)
    for (int a = 0; a < nen; ++a)
      for (int b = a + 1; b < nen; ++b)
        for (int c = 0; c < D; ++c)
          for (int d = 0; d < D; ++d) Ke[(D * b + d) * ldk + D * a + c] = Ke[(D * a + c) * ldk + D * b + d];
  return ok;
}

/// The 2-D form: rules g0, g1, Ke as a 2 (P+1)^2 square array.
template <int P, bool Force, bool Tangent>
KOKKOS_INLINE_FUNCTION bool element_internal(const PatchData& pd, const Material& mat, const GaussRule& g0,
                                             const GaussRule& g1, int e, const double (*ue)[2], double* fe,
                                             double Ke[2 * (P + 1) * (P + 1)][2 * (P + 1) * (P + 1)]) {
  const GaussRule* const g[2] = {&g0, &g1};
  return element_internal<P, Force, Tangent>(pd, mat, g, e, ue, fe, Tangent ? &Ke[0][0] : nullptr,
                                             2 * (P + 1) * (P + 1));
}

/// The element stiffness at u = 0 (the small-strain stiffness for every material).
template <int P>
KOKKOS_INLINE_FUNCTION void element_stiffness(const PatchData& pd, const Material& mat, const GaussRule& g0,
                                              const GaussRule& g1, int e,
                                              double Ke[2 * (P + 1) * (P + 1)][2 * (P + 1) * (P + 1)]) {
  element_internal<P, false, true>(pd, mat, g0, g1, e, nullptr, nullptr, Ke);
}

/// Global control point index of local function a of element e.
template <class PD>
KOKKOS_INLINE_FUNCTION int element_cp(const PD& pd, int e, int a) {
  int ei[PD::dim], s[PD::dim];
  pd.element_spans(e, ei, s);
  return pd.local_cp(s, a);
}

/// Assembles the internal force and/or the tangent of the elements [e_begin, e_end) of one
/// patch of dimension D (atomic sums: correct on threaded and GPU backends where elements share
/// control points). u: overlap displacements (empty: u = 0); f: overlap force; K through
/// `scatter` (kernels/scatter.hpp: one matrix, or owned + ghost rows on several ranks).
/// 2-D: AssembleInternal<P, LocalMatrix>{pd, mat, g0, g1, e_begin}.
template <int D, int P, class LocalMatrix>
struct AssembleInternalT {
  PatchDataT<D, MemSpace> pd;
  Material mat;
  GaussRule g[D];
  int e_begin = 0;
  ElementScatter<LocalMatrix> scatter = {};
  Kokkos::View<const double*, MemSpace> u = {};
  Kokkos::View<double*, MemSpace> f = {};
  bool force = false, tangent = false;   // what run() assembles: f (into f), K (through scatter)
  /// 3-D: the element matrices of one batch of elements, Kw(slot, r ldk + c) (see the header).
  Kokkos::View<double**, Kokkos::LayoutRight, MemSpace> Kw = {};
  int batch_elements = 0;   // 3-D: elements per batch (0: as many as ~ 64 MB hold, at least the concurrency)
  /// 3-D: the tangent by element-wise sum factorisation (kernels/elasticity_sf3.hpp, O(p^7)), the
  /// force by the element loop.
  bool sum_factorized = false;

  static constexpr int MaxNen = kNen<D, P>;
  static constexpr int MaxDof = D * MaxNen;
  // 2-D: Ke on the stack (41 kB at P = 5) where the memory is the host's; on a GPU (and in 3-D)
  // in the work view Kw, since a per-thread frame that large is local memory there (ptxas:
  // 47 kB per thread at P = 5; docs/verification.md, "Kernels on a GPU")
  static constexpr bool kStackKe = D == 2 && Kokkos::SpaceAccessibility<Kokkos::HostSpace, MemSpace>::accessible;

  template <bool Force, bool Tangent>
  KOKKOS_INLINE_FUNCTION void element(const int e, const int slot) const {
    const int nen = pd.nen();
    int cps[MaxNen];
    double ue[MaxNen][D], fe[MaxDof];
    double Ks[Tangent && kStackKe ? MaxDof : 1][Tangent && kStackKe ? MaxDof : 1];
    double* Ke = !Tangent ? nullptr : kStackKe ? &Ks[0][0] : &Kw(slot, 0);
    const bool have_u = u.extent(0) > 0;
    {
      int ei[D], s[D];
      pd.element_spans(e, ei, s);
      pd.local_cps(s, cps);
    }
    for (int a = 0; a < nen; ++a) {
      const int l = pd.lid(cps[a]);
      for (int c = 0; c < D; ++c) ue[a][c] = have_u ? u(dof_of(l, c, D)) : 0.0;
    }
    const GaussRule* gp[D];
    for (int d = 0; d < D; ++d) gp[d] = &g[d];
    if constexpr (D == 3) {
      if (Tangent && sum_factorized) {
        if (Force) element_internal<P, true, false>(pd, mat, gp, e, have_u ? ue : nullptr, fe, nullptr, MaxDof);
        element_tangent_sf3<P>(pd, mat, gp, e, have_u ? ue : nullptr, Ke, MaxDof, Ke + static_cast<size_t>(MaxDof) * MaxDof);
      } else {
        element_internal<P, Force, Tangent>(pd, mat, gp, e, have_u ? ue : nullptr, fe, Ke, MaxDof);
      }
    } else {
      element_internal<P, Force, Tangent>(pd, mat, gp, e, have_u ? ue : nullptr, fe, Ke, MaxDof);
    }
    if (Force)
      for (int a = 0; a < nen; ++a) {
        const int l = pd.lid(cps[a]);
        for (int c = 0; c < D; ++c) Kokkos::atomic_add(&f(dof_of(l, c, D)), fe[D * a + c]);
      }
    if (Tangent) scatter.template add<MaxNen, D>(pd.lid, cps, nen, Ke, MaxDof);
  }

  /// The sum factorisation's work doubles per element (3-D): the largest element rule of each direction.
  size_t sf3_work() const {
    int nq[3] = {1, 1, 1};
    for (int d = 0; d < D; ++d) {
      nq[d] = g[d].n;
      if (pd.qoff[d].extent(0) > 0) {
        auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), pd.qoff[d]);
        for (size_t k = 0; k + 1 < h.extent(0); ++k) nq[d] = std::max(nq[d], h(k + 1) - h(k));
      }
    }
    return sf3_work_size(nq);
  }

  template <bool Force, bool Tangent>
  void launch(const char* name, int b, int n) const {
    const AssembleInternalT self = *this;
    Kokkos::parallel_for(name, Kokkos::RangePolicy<ExecSpace>(0, n),
                         KOKKOS_LAMBDA(const int k) { self.template element<Force, Tangent>(b + k, k); });
  }

  void run(int e_end) {
    const int n = e_end - e_begin;
    if (n <= 0) return;
    if (!tangent) {
      if (force) launch<true, false>("iga::AssembleInternal(f)", e_begin, n);
      return;
    }
    // batches: all elements at once where Ke is on the stack, else as many as the work view holds
    int batch = n;
    if (!kStackKe) {
      const double bytes = 8.0 * MaxDof * MaxDof + 8.0 * (sum_factorized ? sf3_work() : 0);
      const int conc = std::min(ExecSpace().concurrency(), 4096);
      batch = std::min(n, batch_elements > 0 ? batch_elements : std::max(conc, static_cast<int>(64e6 / bytes)));
      const size_t row = static_cast<size_t>(MaxDof) * MaxDof + (sum_factorized ? sf3_work() : 0);
      if (Kw.extent(0) < static_cast<size_t>(batch) || Kw.extent(1) != row)
        Kw = decltype(Kw)(Kokkos::ViewAllocateWithoutInitializing("iga::AssembleInternal::Kw"), batch, row);
    }
    for (int b = e_begin; b < e_end; b += batch) {
      const int m = std::min(batch, e_end - b);
      if (force) launch<true, true>("iga::AssembleInternal(f, K)", b, m);
      else launch<false, true>("iga::AssembleInternal(K)", b, m);
    }
  }
};

template <int P, class LocalMatrix>
using AssembleInternal = AssembleInternalT<2, P, LocalMatrix>;

}  // namespace iga
