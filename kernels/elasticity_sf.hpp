#pragma once
// Tangent of plane elasticity on a NURBS patch by sum factorisation over the whole patch, row
// by row (solver.formation: sum_factorized, the default). 2-D only (PatchData = PatchDataT<2>):
// in 3-D the tangent is formed element by element (kernels/elasticity.hpp, AssembleInternalT<3>),
// by the element loop or by the element-wise sum factorisation (kernels/elasticity_sf3.hpp); the
// patch-wide row-wise form of this algorithm in 3-D (q3, q2, q1 contractions, planes (a2, a3))
// is not written. The same matrix as the element loop
// (kernels/elasticity.hpp, solver.formation: elements, the reference) up to round-off, for
// every material and either element rule; the internal force stays with the element loop.
//
// Weak form: K_ab,ik = \sum_q R_a,J A_iJkL(F_q) R_b,L |det J| w_q  (kernels/elasticity.hpp).
// With R_a = w_a N_a / W (N_a = N_a1(xi) M_a2(eta) the B-spline product, W = sum_b w_b N_b)
// the physical gradient is a combination of three B-spline "derivative slots":
//   R_a,J = w_a \sum_{d=0..2} E_Jd D_d N_a,   D_0 N = N, D_1 N = N_,xi, D_2 N = N_,eta,
//   E_J1 = Jinv_0J / W, E_J2 = Jinv_1J / W, E_J0 = -(Jinv_0J W_,xi + Jinv_1J W_,eta) / W^2
// (Jinv = (dx/dxi)^-1; E_J0 = 0 where the weights are all equal), so
//   K_ab,ik = w_a w_b \sum_{d,e} \sum_q D_d N_a D_e N_b c^ik_de(q),
//   c^ik_de = \sum_{J,L} E_Jd A_iJkL E_Le |det J| w_q,   c^ki_ed = c^ik_de (A symmetric).
// The rule is a tensor product over the patch (q = (q1, q2); Gauss or the spline rule), so the
// sum over q factorises: for each control-point row a2 (eta) and each b2 >= a2
//   step 1   U^ik_g(b2; q1) = \sum_q2 M^(ya)_a2(q2) M^(yb)_b2(q2) \sum_{(d,e) in g} c^ik_de(q1, q2)
// where g = (xa, xb) groups the slots by their xi-derivative order (slot 0, 2: xi order 0;
// slot 1: 1) and (ya, yb) are their eta orders; then for each a1 and b1
//   step 2   K_ab,ik = w_a w_b \sum_q1 \sum_g N^(xa)_a1(q1) N^(xb)_b1(q1) U^ik_g(b2; q1).
// Only b "after" a is formed (b2 > a2, or b2 = a2 and b1 >= a1): K_ba = K_ab^T is written from
// the same numbers. Points in elements outside this rank's range [e_begin, e_end) weigh zero.
//
// Data layout. 1-D tables per direction d (SumFactorTables, built once per patch block):
//   x_d: nq_d points of the element rule over the patch, point q in element qel_d[q], element k's
//   points qoff_d[k] .. qoff_d[k + 1]; w_d[q] the weights (span length included);
//   B_d(q, o (p_d + 1) + l), o = 0, 1: value and first derivative of the l-th active B-spline
//   (function span - p_d + l) at q; function i's elements [flo_d[i], fhi_d[i]) (span in [i, i + p]).
// Work arrays: C(q2 - q2base, f, q1), f = 9 m + 3 d + e, m = 0, 1, 2 for ik = 00, 01, 11 (27
// fields per point, a chunk of element rows at a time: Rc control-point rows); U(slot, t, 4 ik + g,
// q1), t = b2 - a2 in 0..p1, one slot per row in flight; Ac(slot, a1, (t (2 p0 + 1) + b1 - a1 +
// p0) 4 + 2 i + k) the row's K_ab,ik / (w_a w_b), kept until its rows and mirrored rows are written.
//
// Cost per control point (P = p0 = p1, Q points per element and direction, spline rule Q ~
// (P + 2) / 2; Gauss P + 1): step 1 ~ (P + 1)(P + 2) / 2 Q^2 x 16 (B-spline patch) or x 36
// (rational) multiply-adds, vectorised over q1; step 2 ~ (P + 1)^2 Q (P + 1) x 16 over about
// half the (b1, t) pairs; fields ~ 150 + material flops per point. P = 4, spline rule,
// rational: ~ 4.9k + 6k multiply-adds, against ~ 23k for the element loop's blocks a <= b.
// Writes: 2 rows of up to 2 ((P + 1)(2 P + 1) - P) entries and 2 (P + 1) mirrored rows of up to
// 2 (2 P + 1) entries per control point (one sumIntoValues each, columns ascending), instead of
// (2 (P + 1)^2)^2 sums per element. Reads: the element's control points (and displacements)
// once per point; the tables; the fields once per row of their chunk.
// Measured (BM_Formation<4>, 13,920 dofs, Serial, 31.9 ms a tangent): fields, zeroing and
// fill 8.7 ms, step 1 4.8, step 2 9.6, writes 8.8 (docs/performance.md).
#include <algorithm>
#include <string>
#include <vector>

#include "kernels/material.hpp"
#include "kernels/scatter.hpp"
#include "kernels/types.hpp"

namespace iga {

/// 2-D only (the 3-D tangent is formed by the element loop, AssembleInternalT<3, ..>): the
/// weight's index in PatchData::cp.
constexpr int kW = 2;

/// The 1-D tables of one patch and element range (see the header): built on the host once.
struct SumFactorTables {
  int nq[2] = {0, 0};
  Kokkos::View<double*, MemSpace> w0, w1;
  Kokkos::View<int*, MemSpace> qel0, qel1, qoff0, qoff1, flo0, fhi0, flo1, fhi1;
  Kokkos::View<double**, Kokkos::LayoutRight, MemSpace> B0, B1;
  bool rational = false;     // the weights differ: slot 0 (E_J0) is not zero
};

/// Host copies of the eta direction's offsets, spans and function ranges (the chunking).
struct SumFactorRows {
  std::vector<int> qoff1, span1, flo1, fhi1;
};

/// Both, for one patch block.
struct SumFactorPatch {
  SumFactorTables dev;
  SumFactorRows host;
};

namespace sf_detail {

template <class PD>
inline void build_direction(const PD& pd, int d, const GaussRule& g, Kokkos::View<double*, MemSpace>& w,
                            Kokkos::View<int*, MemSpace>& qel, Kokkos::View<int*, MemSpace>& qoff,
                            Kokkos::View<int*, MemSpace>& flo, Kokkos::View<int*, MemSpace>& fhi,
                            Kokkos::View<double**, Kokkos::LayoutRight, MemSpace>& B, int& nq,
                            SumFactorRows* host) {
  const int ne = pd.ne[d], p = pd.p[d], n = pd.n[d];
  const auto& off_dev = pd.qoff[d];
  std::vector<int> h_off(ne + 1);
  if (off_dev.extent(0) > 0) {
    auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), off_dev);
    for (int k = 0; k <= ne; ++k) h_off[k] = h(k) - h(0);
  } else {
    for (int k = 0; k <= ne; ++k) h_off[k] = k * g.n;
  }
  nq = h_off[ne];
  auto h_span = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), pd.span[d]);
  std::vector<int> h_qel(nq), h_flo(n), h_fhi(n);
  for (int k = 0; k < ne; ++k)
    for (int q = h_off[k]; q < h_off[k + 1]; ++q) h_qel[q] = k;
  for (int i = 0; i < n; ++i) {
    int lo = 0;
    while (lo < ne && h_span(lo) < i) ++lo;
    int hi = lo;
    while (hi < ne && h_span(hi) <= i + p) ++hi;
    h_flo[i] = lo;
    h_fhi[i] = hi;
  }
  const auto up = [](const std::string& name, const std::vector<int>& v) {
    Kokkos::View<int*, MemSpace> dv(name, v.size());
    auto h = Kokkos::create_mirror_view(dv);
    for (size_t k = 0; k < v.size(); ++k) h(k) = v[k];
    Kokkos::deep_copy(dv, h);
    return dv;
  };
  qel = up("sf::qel", h_qel);
  qoff = up("sf::qoff", h_off);
  flo = up("sf::flo", h_flo);
  fhi = up("sf::fhi", h_fhi);
  w = Kokkos::View<double*, MemSpace>("sf::w", nq);
  B = Kokkos::View<double**, Kokkos::LayoutRight, MemSpace>("sf::B", nq, 2 * (p + 1));
  const auto wv = w;
  const auto Bv = B;
  const auto span = pd.span[d];
  const auto U = pd.U[d];
  const auto off = qoff;
  const PD pdc = pd;
  Kokkos::parallel_for(
      "iga::SumFactorTables", Kokkos::RangePolicy<ExecSpace>(0, ne), KOKKOS_LAMBDA(const int k) {
        double x[kMaxGauss], ww[kMaxGauss];
        const int s = span(k);
        const int m = element_rule_1d(pdc, d, k, s, g, x, ww);
        for (int q = 0; q < m; ++q) {
          double N[2][kMaxBasis1D];
          bspline_ders(s, x[q], p, U.data(), 1, N);
          const int qq = off(k) + q;
          wv(qq) = ww[q];
          for (int l = 0; l <= p; ++l) {
            Bv(qq, l) = N[0][l];
            Bv(qq, p + 1 + l) = N[1][l];
          }
        }
      });
  if (host) {   // the eta direction's host copies, for the chunking
    host->qoff1 = h_off;
    host->span1.assign(h_span.data(), h_span.data() + ne);
    host->flo1 = h_flo;
    host->fhi1 = h_fhi;
  }
}

/// Step 1's update for one component pair ik: the field block c (fields f at c[f ldc + q],
/// transposed: c^ki read for ik = 10) into U's four groups (u[g ldu + q]), for q in [0, n).
/// m[2 ya + yb] = M^(ya)_a2 M^(yb)_b2. Groups g: 0 (xa, xb) = (0, 0), 1 (1, 0), 2 (0, 1), 3 (1, 1).
template <bool Rational, bool Transpose>
KOKKOS_INLINE_FUNCTION void step1_update(int n, const double m[4], const double* KOKKOS_RESTRICT c, int ldc,
                                         double* KOKKOS_RESTRICT u, int ldu) {
  const auto F = [=](int d, int e) { return Transpose ? c + (3 * e + d) * ldc : c + (3 * d + e) * ldc; };
  const double m00 = m[0], m01 = m[1], m10 = m[2], m11 = m[3];
  const double *c11 = F(1, 1), *c12 = F(1, 2), *c21 = F(2, 1), *c22 = F(2, 2);
  double *u0 = u, *u1 = u + ldu, *u2 = u + 2 * ldu, *u3 = u + 3 * ldu;
  if (!Rational) {
    for (int q = 0; q < n; ++q) {
      u0[q] += m11 * c22[q];
      u1[q] += m01 * c12[q];
      u2[q] += m10 * c21[q];
      u3[q] += m00 * c11[q];
    }
  } else {
    const double *c00 = F(0, 0), *c02 = F(0, 2), *c20 = F(2, 0), *c10 = F(1, 0), *c01 = F(0, 1);
    for (int q = 0; q < n; ++q) {
      u0[q] += m00 * c00[q] + m01 * c02[q] + m10 * c20[q] + m11 * c22[q];
      u1[q] += m00 * c10[q] + m01 * c12[q];
      u2[q] += m00 * c01[q] + m10 * c21[q];
      u3[q] += m00 * c11[q];
    }
  }
}

}  // namespace sf_detail

/// Builds the tables of patch pd (element rules: the patch's, else Gauss g0, g1).
inline SumFactorPatch sum_factor_tables(const PatchData& pd, const GaussRule& g0, const GaussRule& g1) {
  SumFactorPatch sp;
  SumFactorTables& t = sp.dev;
  SumFactorRows& h = sp.host;
  sf_detail::build_direction(pd, 0, g0, t.w0, t.qel0, t.qoff0, t.flo0, t.fhi0, t.B0, t.nq[0], nullptr);
  sf_detail::build_direction(pd, 1, g1, t.w1, t.qel1, t.qoff1, t.flo1, t.fhi1, t.B1, t.nq[1], &h);
  auto cp = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), pd.cp);
  for (size_t a = 1; a < cp.extent(0); ++a)
    if (cp(a, kW) != cp(0, kW)) t.rational = true;
  Kokkos::fence();
  return sp;
}

/// Assembles the tangent K_T(u) of the elements [e_begin, e_end) of one patch through
/// `scatter` (kernels/scatter.hpp) by the row-wise sum factorisation above. u: overlap
/// displacements (empty: u = 0).
template <int P, class LocalMatrix>
struct SumFactorizedTangent {
  PatchData pd;
  Material mat;
  SumFactorTables t;
  int e_begin = 0, e_end = 0;
  ElementScatter<LocalMatrix> scatter = {};
  Kokkos::View<const double*, MemSpace> u = {};

  static constexpr int kFields = 27;
  Kokkos::View<double***, Kokkos::LayoutRight, MemSpace> C;    // (q2 in chunk, field, q1)
  Kokkos::View<double****, Kokkos::LayoutRight, MemSpace> Uw;  // (slot, t, 4 ik + g, q1)
  Kokkos::View<double***, Kokkos::LayoutRight, MemSpace> Ac;   // (slot, a1, (t (2 p0 + 1) + b1 - a1 + p0) 4 + 2 i + k)
  int q2base = 0, row_base = 0, ec0 = 0, ec1 = 0;

  // ---- the point fields c^ik_de at (q1, q2) ----
  KOKKOS_INLINE_FUNCTION void fields(const int q2l, const int q1) const {
    const int q2 = q2base + q2l;
    const int e0 = t.qel0(q1), e1 = t.qel1(q2), e = e0 + pd.ne[0] * e1;
    if (e < e_begin || e >= e_end) {
      for (int f = 0; f < kFields; ++f) C(q2l, f, q1) = 0.0;
      return;
    }
    const int p0 = pd.p[0], p1 = pd.p[1];
    const int s0 = pd.span[0](e0), s1 = pd.span[1](e1);
    double N[2][P + 1], M[2][P + 1];
    for (int l = 0; l <= p0; ++l) {
      N[0][l] = t.B0(q1, l);
      N[1][l] = t.B0(q1, p0 + 1 + l);
    }
    for (int l = 0; l <= p1; ++l) {
      M[0][l] = t.B1(q2, l);
      M[1][l] = t.B1(q2, p1 + 1 + l);
    }
    // sum-factorised sums of the homogeneous control points (and of w u where u is given):
    // S[o][k] = sum_ij D_o(N_i M_j) c_ij[k], o = value, xi, eta; k = w x, w y, w, w u_x, w u_y
    const bool have_u = u.extent(0) > 0;
    const int nk = have_u ? 5 : 3;
    double S[3][5] = {};
    for (int j = 0; j <= p1; ++j) {
      double A[5] = {0, 0, 0, 0, 0}, Bd[5] = {0, 0, 0, 0, 0};
      for (int i = 0; i <= p0; ++i) {
        const int g = s0 - p0 + i + (s1 - p1 + j) * pd.n[0];
        const double w = pd.cp(g, kW);
        double c[5] = {w * pd.cp(g, 0), w * pd.cp(g, 1), w, 0.0, 0.0};
        if (have_u) {
          const int l = pd.lid(g);
          c[3] = w * u(dof_of(l, 0, 2));
          c[4] = w * u(dof_of(l, 1, 2));
        }
        for (int k = 0; k < nk; ++k) {
          A[k] += N[0][i] * c[k];
          Bd[k] += N[1][i] * c[k];
        }
      }
      for (int k = 0; k < nk; ++k) {
        S[0][k] += M[0][j] * A[k];
        S[1][k] += M[0][j] * Bd[k];
        S[2][k] += M[1][j] * A[k];
      }
    }
    double x[2], Ji[2][2];   // Ji[alpha][J]
    const double det = rational_map(S[0], S[1], S[2], x, Ji);
    const double iW = 1.0 / S[0][2], Wu = S[1][2], Wv = S[2][2];
    double E[2][3];
    for (int J = 0; J < 2; ++J) {
      E[J][1] = Ji[0][J] * iW;
      E[J][2] = Ji[1][J] * iW;
      E[J][0] = -(Ji[0][J] * Wu + Ji[1][J] * Wv) * iW * iW;
    }
    // Grad u: H_iJ = sum_d E_Jd V_id, V_id = sum_a w_a u_ai D_d N_a = S[d][3 + i]
    double H[2][2] = {{0, 0}, {0, 0}};
    if (have_u)
      for (int i = 0; i < 2; ++i)
        for (int J = 0; J < 2; ++J) H[i][J] = E[J][0] * S[0][3 + i] + E[J][1] * S[1][3 + i] + E[J][2] * S[2][3 + i];
    double Pk[2][2], P33, A[4][4];
    material_response<true>(mat, H, Pk, P33, A);
    const double wq = kmath::fabs(det) * t.w0(q1) * t.w1(q2);
    constexpr int ik[3][2] = {{0, 0}, {0, 1}, {1, 1}};
    for (int m = 0; m < 3; ++m) {
      const int i = ik[m][0], k = ik[m][1];
      for (int d = 0; d < 3; ++d) {
        double Y[2];
        for (int L = 0; L < 2; ++L) Y[L] = (E[0][d] * A[2 * i][2 * k + L] + E[1][d] * A[2 * i + 1][2 * k + L]) * wq;
        for (int e2 = 0; e2 < 3; ++e2) C(q2l, 9 * m + 3 * d + e2, q1) = Y[0] * E[0][e2] + Y[1] * E[1][e2];
      }
    }
  }

  // ---- one control-point row a2: step 1, step 2, writes ----
  template <bool Rational>
  KOKKOS_INLINE_FUNCTION void row(const int a2, const int slot) const {
    const int p0 = pd.p[0], p1 = pd.p[1], n0 = pd.n[0], n1 = pd.n[1], nq0 = t.nq[0];
    const int ld = static_cast<int>(Uw.extent(3));
    double* Us = &Uw(slot, 0, 0, 0);
    for (size_t k = 0; k < static_cast<size_t>(p1 + 1) * 16 * ld; ++k) Us[k] = 0.0;
    constexpr int W1 = 2 * P + 1;
    // step 1: contract q2 (the element rows of a2's support in this chunk)
    const int elo = t.flo1(a2) > ec0 ? t.flo1(a2) : ec0, ehi = t.fhi1(a2) < ec1 ? t.fhi1(a2) : ec1;
    const int ldc = static_cast<int>(C.extent(2));
    for (int e1 = elo; e1 < ehi; ++e1) {
      const int la = a2 - (pd.span[1](e1) - p1);
      for (int q2 = t.qoff1(e1); q2 < t.qoff1(e1 + 1); ++q2) {
        const double ma0 = t.B1(q2, la), ma1 = t.B1(q2, p1 + 1 + la);
        const double* Cq = &C(q2 - q2base, 0, 0);
        for (int lb = la; lb <= p1; ++lb) {
          const double mb0 = t.B1(q2, lb), mb1 = t.B1(q2, p1 + 1 + lb);
          const double m[4] = {ma0 * mb0, ma0 * mb1, ma1 * mb0, ma1 * mb1};
          double* Ut = Us + static_cast<size_t>(lb - la) * 16 * ld;
          // ik = 00, 01, 10 (c^01 transposed), 11
          sf_detail::step1_update<Rational, false>(nq0, m, Cq, ldc, Ut, ld);
          sf_detail::step1_update<Rational, false>(nq0, m, Cq + 9 * ldc, ldc, Ut + 4 * ld, ld);
          sf_detail::step1_update<Rational, true>(nq0, m, Cq + 9 * ldc, ldc, Ut + 8 * ld, ld);
          sf_detail::step1_update<Rational, false>(nq0, m, Cq + 18 * ldc, ldc, Ut + 12 * ld, ld);
        }
      }
    }
    // step 2: contract q1 for each a1: Ac(a1, (t (2 p0 + 1) + b1 - a1 + p0) 4 + 2 i + k) = K_ab,ik / (w_a w_b)
    const int W = 2 * p0 + 1;
    for (int a1 = 0; a1 < n0; ++a1) {
      double* acc = &Ac(slot, a1, 0);
      for (int r = 0; r < (p1 + 1) * W * 4; ++r) acc[r] = 0.0;
      if (pd.lid(a1 + n0 * a2) < 0) continue;
      for (int e0 = t.flo0(a1); e0 < t.fhi0(a1); ++e0) {
        // the element's points: products N^(xa)_a1 N^(xb)_b1 per point and b1, then per (t, b1)
        // the sum over the points in registers
        const int s0 = pd.span[0](e0), la = a1 - (s0 - p0);
        const int qb = t.qoff0(e0), nqe = t.qoff0(e0 + 1) - qb;
        double nn[kMaxGauss][P + 1][4];
        for (int q = 0; q < nqe; ++q) {
          const double na0 = t.B0(qb + q, la), na1 = t.B0(qb + q, p0 + 1 + la);
          for (int lb = 0; lb <= p0; ++lb) {
            const double nb0 = t.B0(qb + q, lb), nb1 = t.B0(qb + q, p0 + 1 + lb);
            nn[q][lb][0] = na0 * nb0;
            nn[q][lb][1] = na1 * nb0;
            nn[q][lb][2] = na0 * nb1;
            nn[q][lb][3] = na1 * nb1;
          }
        }
        for (int tt = 0; tt <= p1; ++tt) {
          double ue[kMaxGauss][16];
          for (int r = 0; r < 16; ++r) {
            const double* src = Us + (static_cast<size_t>(tt) * 16 + r) * ld + qb;
            for (int q = 0; q < nqe; ++q) ue[q][r] = src[q];
          }
          for (int lb = (tt == 0 ? la : 0); lb <= p0; ++lb) {
            double o4[4] = {0, 0, 0, 0};
            for (int q = 0; q < nqe; ++q) {
              const double* n4 = nn[q][lb];
              for (int r = 0; r < 4; ++r)
                o4[r] += n4[0] * ue[q][4 * r] + n4[1] * ue[q][4 * r + 1] + n4[2] * ue[q][4 * r + 2] + n4[3] * ue[q][4 * r + 3];
            }
            double* o = acc + (tt * W + lb - la + p0) * 4;
            for (int r = 0; r < 4; ++r) o[r] += o4[r];
          }
        }
      }
    }
    // writes, each row in one call with ascending columns: the rows (a, i) over b after a ...
    for (int a1 = 0; a1 < n0; ++a1) {
      const int ca = a1 + n0 * a2;
      if (pd.lid(ca) < 0) continue;
      const double wa = pd.cp(ca, kW);
      const double* acc = &Ac(slot, a1, 0);
      int cps[(P + 1) * W1];
      double vals[2][2 * (P + 1) * W1];
      int nb = 0;
      for (int tt = 0; tt <= p1 && a2 + tt < n1; ++tt)
        for (int b1 = (tt == 0 ? a1 : (a1 > p0 ? a1 - p0 : 0)); b1 <= a1 + p0 && b1 < n0; ++b1) {
          const int cb = b1 + n0 * (a2 + tt);
          if (pd.lid(cb) < 0) continue;
          const double sc = wa * pd.cp(cb, kW);
          const double* o = acc + (tt * W + b1 - a1 + p0) * 4;
          cps[nb] = cb;
          for (int i = 0; i < 2; ++i)
            for (int k = 0; k < 2; ++k) vals[i][2 * nb + k] = sc * o[2 * i + k];
          ++nb;
        }
      scatter.template add_row<(P + 1) * W1>(pd.lid, ca, 0, cps, nb, vals[0]);
      scatter.template add_row<(P + 1) * W1>(pd.lid, ca, 1, cps, nb, vals[1]);
    }
    // ... and the mirrored rows (b, k) over this row's a before b: K_ba,ki = K_ab,ik
    for (int tt = 0; tt <= p1 && a2 + tt < n1; ++tt)
      for (int b1 = 0; b1 < n0; ++b1) {
        const int cb = b1 + n0 * (a2 + tt);
        if (pd.lid(cb) < 0) continue;
        const double wb = pd.cp(cb, kW);
        int cps[W1];
        double vals[2][2 * W1];
        int na = 0;
        const int hi = tt == 0 ? b1 - 1 : b1 + p0;   // same row: a1 < b1 (the diagonal block is in the row above)
        for (int a1 = (b1 > p0 ? b1 - p0 : 0); a1 <= hi && a1 < n0; ++a1) {
          const int ca = a1 + n0 * a2;
          if (pd.lid(ca) < 0) continue;
          const double sc = wb * pd.cp(ca, kW);
          const double* o = &Ac(slot, a1, (tt * W + b1 - a1 + p0) * 4);
          cps[na] = ca;
          for (int k = 0; k < 2; ++k)
            for (int i = 0; i < 2; ++i) vals[k][2 * na + i] = sc * o[2 * i + k];
          ++na;
        }
        if (na == 0) continue;
        scatter.template add_row<W1>(pd.lid, cb, 0, cps, na, vals[0]);
        scatter.template add_row<W1>(pd.lid, cb, 1, cps, na, vals[1]);
      }
  }

  /// Runs the assembly (host): chunks of control-point rows, their fields, then the rows.
  /// h: the host part of the tables t.
  void run(const SumFactorRows& h) {
    if (e_end <= e_begin) return;
    const int p1 = pd.p[1], nq0 = t.nq[0];
    const int ne0 = pd.ne[0];
    const int E1lo = e_begin / ne0, E1hi = (e_end - 1) / ne0;   // element rows of this rank
    const int r_lo = std::max(0, h.span1[E1lo] - p1), r_hi = h.span1[E1hi] + 1;   // rows a2
    // chunk: about 8 MB of fields (48 MB measured no faster, and 32 MB more resident at 1e5
    // dofs), at least 2 (p1 + 1) rows
    const size_t per_row = static_cast<size_t>(h.qoff1[E1hi + 1] - h.qoff1[E1lo]) / (E1hi - E1lo + 1) + 1;
    const size_t bytes_row = per_row * kFields * nq0 * sizeof(double);
    const int Rc = std::max<int>(2 * (p1 + 1), static_cast<int>(8e6 / static_cast<double>(bytes_row)) - p1);
    const int slots = std::max(1, std::min<int>(Rc, ExecSpace().concurrency()));
    // the largest chunk's points
    int maxq = 0;
    const auto chunk_rows = [&](int A0, int A1, int& c0, int& c1) {
      c0 = std::max(h.flo1[A0], E1lo);
      c1 = std::min(h.fhi1[A1 - 1], E1hi + 1);
    };
    for (int A0 = r_lo; A0 < r_hi; A0 += Rc) {
      int c0, c1;
      chunk_rows(A0, std::min(A0 + Rc, r_hi), c0, c1);
      if (c1 > c0) maxq = std::max(maxq, h.qoff1[c1] - h.qoff1[c0]);
    }
    if (C.extent(0) < static_cast<size_t>(maxq) || C.extent(2) != static_cast<size_t>(nq0))
      C = decltype(C)(Kokkos::ViewAllocateWithoutInitializing("sf::C"), maxq, kFields, nq0);
    if (Uw.extent(0) < static_cast<size_t>(slots) || Uw.extent(1) != static_cast<size_t>(p1 + 1) ||
        Uw.extent(3) != static_cast<size_t>(nq0))
      Uw = decltype(Uw)(Kokkos::ViewAllocateWithoutInitializing("sf::U"), slots, p1 + 1, 16, nq0);
    const size_t nacc = static_cast<size_t>(p1 + 1) * (2 * pd.p[0] + 1) * 4;
    if (Ac.extent(0) < static_cast<size_t>(slots) || Ac.extent(1) != static_cast<size_t>(pd.n[0]) || Ac.extent(2) != nacc)
      Ac = decltype(Ac)(Kokkos::ViewAllocateWithoutInitializing("sf::Ac"), slots, pd.n[0], nacc);
    for (int A0 = r_lo; A0 < r_hi; A0 += Rc) {
      const int A1 = std::min(A0 + Rc, r_hi);
      chunk_rows(A0, A1, ec0, ec1);
      if (ec1 <= ec0) continue;
      q2base = h.qoff1[ec0];
      const int nq2 = h.qoff1[ec1] - q2base;
      {
        const SumFactorizedTangent self = *this;
        Kokkos::parallel_for(
            "iga::SumFactorizedTangent(fields)",
            Kokkos::MDRangePolicy<ExecSpace, Kokkos::Rank<2>>({0, 0}, {nq2, nq0}),
            KOKKOS_LAMBDA(const int q2l, const int q1) { self.fields(q2l, q1); });
      }
      for (int B0 = A0; B0 < A1; B0 += slots) {
        const int B1 = std::min(B0 + slots, A1);
        const SumFactorizedTangent self = *this;
        if (t.rational)
          Kokkos::parallel_for("iga::SumFactorizedTangent(rows)", Kokkos::RangePolicy<ExecSpace>(B0, B1),
                               KOKKOS_LAMBDA(const int a2) { self.template row<true>(a2, a2 - B0); });
        else
          Kokkos::parallel_for("iga::SumFactorizedTangent(rows)", Kokkos::RangePolicy<ExecSpace>(B0, B1),
                               KOKKOS_LAMBDA(const int a2) { self.template row<false>(a2, a2 - B0); });
      }
    }
    Kokkos::fence();
  }
};

}  // namespace iga
