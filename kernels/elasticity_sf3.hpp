#pragma once
// Tangent of a 3-D element by sum factorisation (D = 3): the same matrix as the element loop
// (kernels/elasticity.hpp, element_internal<P, false, true>) up to round-off, at O(p^7) instead
// of O(p^9) operations per element. Used by AssembleInternalT<3, P> (kernels/elasticity.hpp) when sum_factorized is set;
// the 2-D row-wise formation over the whole patch is kernels/elasticity_sf.hpp.
//
// Weak form: K_ab,ik = \sum_q R_a,J A_iJkL(F_q) R_b,L |det J| w_q. With R_a = w_a N_a / W
// (N_a = X_a0(xi) Y_a1(eta) Z_a2(zeta)) the physical gradient combines four B-spline
// "derivative slots" d: D_0 N = N, D_1 N = N_,xi, D_2 N = N_,eta, D_3 N = N_,zeta:
//   R_a,J = w_a \sum_d E_Jd D_d N_a,  E_J(1+alpha) = Jinv_alpha,J / W,
//   E_J0 = -\sum_alpha Jinv_alpha,J W_,alpha / W^2   (Jinv = (dx/dxi)^-1),
// so K_ab,ik = w_a w_b \sum_{d,e} \sum_q D_d N_a D_e N_b c^ik_de(q),
//   c^ik_de(q) = \sum_{J,L} E_Jd A_iJkL E_Le |det J| w_q      (9 ik x 16 de = 144 fields a point).
// Grad u at the point comes from the same sums: H_iJ = \sum_d E_Jd \sum_a w_a u_ai D_d N_a.
// The element rule is a tensor product (q = (q0, q1, q2)), so the sum over q factorises. Slot d
// has derivative orders (x, y, z): 0 (0,0,0), 1 (1,0,0), 2 (0,1,0), 3 (0,0,1); in (x, y) the
// slots fall in three classes: A = {0, 3} (0,0), B = {1} (1,0), C = {2} (0,1). For each pair
// (a2, b2) of zeta functions:
//   step 1  T1^ik_g(q0, q1) = \sum_q2 \sum_{(d,e) in g} Z^(d)_a2(q2) Z^(e)_b2(q2) c^ik_de(q0, q1, q2)
//           g: the 9 class pairs (A, B, C)^2 (16 (d,e) pairs in all);
// for each pair (a1, b1):
//   step 2  T2^ik_h(q0) = \sum_q1 \sum_{g in h} Y^(g_a)_a1(q1) Y^(g_b)_b1(q1) T1^ik_g(q0, q1)
//           h: the 4 x-order pairs (0 or 1 for a and b);
// for each pair (a0, b0):
//   step 3  K_ab,ik = w_a w_b \sum_q0 \sum_h X^(h_a)_a0(q0) X^(h_b)_b0(q0) T2^ik_h(q0).
// Only b after a (a = a0 + m0 (a1 + m1 a2), b >= a) is formed; K_ba = K_ab^T is mirrored, as in
// the element loop.
//
// Layout: Ke row-major, rows 3 a + i, leading dimension ldk; the work array (sf3_work_size
// doubles, in AssembleInternalT's batched work view beside Ke, not on the stack) holds the fields
// c(q, 16 ik' + 4 d + e) (ik' = 3 i + k, nq points) and T1(9 ik + g, q0 + nq0 q1).
// Cost per element (P = p_d, m = P + 1 functions and Q points per direction, nen = m^3):
//   fields   Q^3 (basis sums 7 x 2 nen + ~ 1,200 for E, H, A and c)
//   step 1   9 x 16 Q^3 m (m + 1) / 2 multiply-adds   (pairs a2 <= b2; P = 4, Gauss: 0.27 M)
//   step 2   9 x 9 Q^2 m^4 / 2                       (0.63 M)
//   step 3   9 x 4 Q nen^2 / 2                       (1.4 M)
// about 5 M flops at P = 4 against ~ 27 nen^2 Q^3 / 2 ~ 27 M for the element loop's blocks;
// at P = 2 the two are about equal (0.3 M flops). Measured (BM_Formation3D, Serial, one core,
// CPU time per tangent + force): P = 4 3.5 x faster than the element loop, P = 3 2.0 x, P = 2
// equal, P = 1 1.8 x slower (the element loop is the default; AssembleInternalT::sum_factorized). Reads: the element's control points and
// displacements once per point; writes (3 nen)^2 matrix entries.
#include "kernels/material.hpp"
#include "kernels/types.hpp"

namespace iga {

namespace sf3_detail {
// The (x, y) class of slot d: 0 = A (orders (0, 0)), 1 = B (1, 0), 2 = C (0, 1).
KOKKOS_INLINE_FUNCTION constexpr int xy_class(int d) { return d == 1 ? 1 : d == 2 ? 2 : 0; }
KOKKOS_INLINE_FUNCTION constexpr int z_order(int d) { return d == 3 ? 1 : 0; }
KOKKOS_INLINE_FUNCTION constexpr int y_order(int c) { return c == 2 ? 1 : 0; }   // of a class
KOKKOS_INLINE_FUNCTION constexpr int x_order(int c) { return c == 1 ? 1 : 0; }
}  // namespace sf3_detail

/// Doubles of work for element_tangent_sf3 with nq[d] points per direction (at most).
KOKKOS_INLINE_FUNCTION size_t sf3_work_size(const int nq[3]) {
  return static_cast<size_t>(nq[0]) * nq[1] * nq[2] * 144 + static_cast<size_t>(81) * nq[0] * nq[1];
}

/// The tangent Ke (3 nen x 3 nen, leading dimension ldk) of element e at displacements ue (null:
/// u = 0) by sum factorisation; work: sf3_work_size doubles. Returns false where the material
/// response is inadmissible (NaN entries).
template <int P, class PD>
KOKKOS_INLINE_FUNCTION bool element_tangent_sf3(const PD& pd, const Material& mat, const GaussRule* const g[], int e,
                                                const double (*ue)[3], double* Ke, int ldk, double* work) {
  static_assert(PD::dim == 3, "element_tangent_sf3: 3-D patches");
  using namespace sf3_detail;
  constexpr int MaxNen = kNen<3, P>;
  const int nen = pd.nen();
  const int m0 = pd.p[0] + 1, m1 = pd.p[1] + 1, m2 = pd.p[2] + 1;
  int ei[3], s[3];
  pd.element_spans(e, ei, s);
  double xq[3][kMaxGauss], wq1[3][kMaxGauss], Nq[3][kMaxGauss][2][kMaxBasis1D];
  int nq[3];
  for (int d = 0; d < 3; ++d) {
    nq[d] = element_rule_1d(pd, d, ei[d], s[d], *g[d], xq[d], wq1[d]);
    for (int q = 0; q < nq[d]; ++q) bspline_ders(s[d], xq[d][q], pd.p[d], pd.U[d].data(), 1, Nq[d][q]);
  }
  const int nqt = nq[0] * nq[1] * nq[2], nq01 = nq[0] * nq[1];
  double* C = work;                                   // C[q * 144 + 16 ik + 4 d + e]
  double* T1 = work + static_cast<size_t>(nqt) * 144;   // T1[(9 ik + g) nq01 + q0 + nq0 q1]
  // homogeneous control points and weighted displacements: (w x, w y, w z, w, w u_x, w u_y, w u_z)
  double cwu[MaxNen][7];
  double wa[MaxNen];
  int gs[MaxNen];
  pd.local_cps(s, gs);
  for (int a = 0; a < nen; ++a) {
    const int gcp = gs[a];
    const double w = pd.cp(gcp, 3);
    wa[a] = w;
    for (int k = 0; k < 3; ++k) {
      cwu[a][k] = w * pd.cp(gcp, k);
      cwu[a][4 + k] = ue ? w * ue[a][k] : 0.0;
    }
    cwu[a][3] = w;
  }
  // ---- the point fields ----
  bool ok = true;
  for (int q2 = 0; q2 < nq[2]; ++q2)
    for (int q1 = 0; q1 < nq[1]; ++q1)
      for (int q0 = 0; q0 < nq[0]; ++q0) {
        const double(*B[3])[kMaxBasis1D] = {Nq[0][q0], Nq[1][q1], Nq[2][q2]};
        double S[4][7];
        homogeneous_sums<3, 7>(pd.p, B, cwu, S);
        const double* Sp[4] = {S[0], S[1], S[2], S[3]};
        double x[3], Ji[3][3];
        const double det = rational_map<3>(Sp, x, Ji);
        const double iW = 1.0 / S[0][3];
        double E[3][4];
        for (int J = 0; J < 3; ++J) {
          double c0 = 0;
          for (int al = 0; al < 3; ++al) {
            E[J][1 + al] = Ji[al][J] * iW;
            c0 += Ji[al][J] * S[1 + al][3];
          }
          E[J][0] = -c0 * iW * iW;
        }
        double H[3][3] = {};
        if (ue)
          for (int i = 0; i < 3; ++i)
            for (int J = 0; J < 3; ++J)
              for (int d = 0; d < 4; ++d) H[i][J] += E[J][d] * S[d][4 + i];
        double Pk[3][3], P33, A[9][9];
        ok = material_response<true>(mat, H, Pk, P33, A) && ok;
        const double wq = kmath::fabs(det) * wq1[0][q0] * wq1[1][q1] * wq1[2][q2];
        double* c = C + static_cast<size_t>(q0 + nq[0] * (q1 + nq[1] * q2)) * 144;
        for (int i = 0; i < 3; ++i)
          for (int k = 0; k < 3; ++k)
            for (int d = 0; d < 4; ++d) {
              double Y[3];
              for (int L = 0; L < 3; ++L) {
                double t = 0;
                for (int J = 0; J < 3; ++J) t += E[J][d] * A[3 * i + J][3 * k + L];
                Y[L] = t * wq;
              }
              for (int ee = 0; ee < 4; ++ee) c[16 * (3 * i + k) + 4 * d + ee] = Y[0] * E[0][ee] + Y[1] * E[1][ee] + Y[2] * E[2][ee];
            }
      }
  for (int r = 0; r < 3 * nen; ++r)
    for (int c = 0; c < 3 * nen; ++c) Ke[r * ldk + c] = 0.0;
  // ---- steps 1-3 over the pairs (a2 <= b2), (a1, b1), (a0, b0) with b after a ----
  for (int a2 = 0; a2 < m2; ++a2)
    for (int b2 = a2; b2 < m2; ++b2) {
      // step 1: contract q2
      for (int r = 0; r < 81 * nq01; ++r) T1[r] = 0.0;
      for (int q2 = 0; q2 < nq[2]; ++q2) {
        const double za[2] = {Nq[2][q2][0][a2], Nq[2][q2][1][a2]}, zb[2] = {Nq[2][q2][0][b2], Nq[2][q2][1][b2]};
        for (int q01 = 0; q01 < nq01; ++q01) {
          const double* c = C + static_cast<size_t>(q01 + nq01 * q2) * 144;
          for (int ik = 0; ik < 9; ++ik)
            for (int d = 0; d < 4; ++d)
              for (int ee = 0; ee < 4; ++ee) {
                const int gg = 3 * xy_class(d) + xy_class(ee);
                T1[(9 * ik + gg) * nq01 + q01] += za[z_order(d)] * zb[z_order(ee)] * c[16 * ik + 4 * d + ee];
              }
        }
      }
      for (int a1 = 0; a1 < m1; ++a1)
        for (int b1 = (b2 == a2 ? a1 : 0); b1 < m1; ++b1) {
          // step 2: contract q1 into the 4 x-order pairs h = 2 x_a + x_b
          double T2[9][4][kMaxGauss] = {};
          for (int q1 = 0; q1 < nq[1]; ++q1) {
            const double ya[2] = {Nq[1][q1][0][a1], Nq[1][q1][1][a1]}, yb[2] = {Nq[1][q1][0][b1], Nq[1][q1][1][b1]};
            for (int ik = 0; ik < 9; ++ik)
              for (int ga = 0; ga < 3; ++ga)
                for (int gb = 0; gb < 3; ++gb) {
                  const double f = ya[y_order(ga)] * yb[y_order(gb)];
                  const double* t = T1 + (9 * ik + 3 * ga + gb) * nq01 + nq[0] * q1;
                  double* o = T2[ik][2 * x_order(ga) + x_order(gb)];
                  for (int q0 = 0; q0 < nq[0]; ++q0) o[q0] += f * t[q0];
                }
          }
          // step 3: contract q0 for each (a0, b0)
          const bool same = a2 == b2 && a1 == b1;
          for (int a0 = 0; a0 < m0; ++a0)
            for (int b0 = (same ? a0 : 0); b0 < m0; ++b0) {
              double k9[9] = {};
              for (int q0 = 0; q0 < nq[0]; ++q0) {
                const double xa0 = Nq[0][q0][0][a0], xa1 = Nq[0][q0][1][a0];
                const double xb0 = Nq[0][q0][0][b0], xb1 = Nq[0][q0][1][b0];
                const double h[4] = {xa0 * xb0, xa0 * xb1, xa1 * xb0, xa1 * xb1};
                for (int ik = 0; ik < 9; ++ik)
                  k9[ik] += h[0] * T2[ik][0][q0] + h[1] * T2[ik][1][q0] + h[2] * T2[ik][2][q0] + h[3] * T2[ik][3][q0];
              }
              const int a = a0 + m0 * (a1 + m1 * a2), b = b0 + m0 * (b1 + m1 * b2);
              const double sc = wa[a] * wa[b];
              for (int i = 0; i < 3; ++i)
                for (int k = 0; k < 3; ++k) Ke[(3 * a + i) * ldk + 3 * b + k] = sc * k9[3 * i + k];
            }
        }
    }
  // K_ba = K_ab^T
  for (int a = 0; a < nen; ++a)
    for (int b = a + 1; b < nen; ++b)
      for (int c = 0; c < 3; ++c)
        for (int d = 0; d < 3; ++d) Ke[(3 * b + d) * ldk + 3 * a + c] = Ke[(3 * a + c) * ldk + 3 * b + d];
  return ok;
}

}  // namespace iga
