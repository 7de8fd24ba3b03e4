#pragma once
// Data the kernels read: one NURBS patch on the device, Gauss rules, material; and the
// D-variate NURBS basis (D = 2: surfaces in the plane, D = 3: solids), one code path for both.
// Kokkos only; the solver layer fills these from the model and from Tpetra.
//
// Spatial dimension: the host keeps a run-time dim; kernels take a compile-time D (and the
// degree P), chosen once by dispatch(dim, p, f) below (dispatch_degree: the 2-D form).
// Numbering (kernels/numbering.hpp): element e = e0 + ne0 (e1 + ne1 e2), control point
// g = i0 + n0 (i1 + n1 i2), local function a = l0 + (p0 + 1)(l1 + (p1 + 1) l2), the first
// direction fastest; dof (g, c) = D g + c.
#include <Kokkos_Core.hpp>

#include <stdexcept>
#include <string>
#include <type_traits>

#include "kernels/numbering.hpp"
#include "kernels/nurbs_basis.hpp"

namespace iga {

using ExecSpace = Kokkos::DefaultExecutionSpace;
using MemSpace = ExecSpace::memory_space;

/// tensor_ij (kernels/numbering.hpp) for a compile-time dimension D: the last direction's index
/// needs no division (e < n0 n1 .. holds), which matters in per-point index arithmetic.
template <int D>
KOKKOS_INLINE_FUNCTION void tensor_ij_d(int e, const int* n, int* ij) {
  for (int d = 0; d < D - 1; ++d) {
    ij[d] = e % n[d];
    e /= n[d];
  }
  ij[D - 1] = e;
}

/// (P + 1)^D: the basis functions of an element of degree P in every direction (the size of
/// the kernels' per-element arrays).
template <int D, int P>
constexpr int kNen = D == 2 ? (P + 1) * (P + 1) : (P + 1) * (P + 1) * (P + 1);

/// One patch of dimension D in memory space Mem (the device for kernels, the host for sampling).
/// Element e = e0 + ne0 (e1 + ne1 e2) covers spans (span[0](e0), span[1](e1), span[2](e2)).
template <int D, class Mem>
struct PatchDataT {
  static_assert(D == 2 || D == 3, "PatchDataT: dimension 2 or 3");
  static constexpr int dim = D;
  using memory_space = Mem;
  int p[D] = {};        // degree per direction
  int n[D] = {};        // basis functions per direction
  int ne[D] = {};       // elements per direction
  Kokkos::View<const double*, Mem> U[D];          // knot vectors, n[d] + p[d] + 1 each
  Kokkos::View<const double* [D + 1], Mem> cp;    // reference coordinates x_0..x_{D-1}, weight at index D
  Kokkos::View<const int*, Mem> span[D];          // the non-empty knot spans of each direction
  Kokkos::View<const int*, Mem> lid;              // cp index -> overlap cp LID (-1: not here)
  // The element rule of each direction (solver.quadrature: spline, model/quadrature.hpp):
  // element row k of direction d has the nodes qx[d][qoff[d][k] .. qoff[d][k + 1]) in the
  // parameter and weights qw[d] (the span's length included). Empty: the Gauss rule the
  // kernel is given, p + 1 points per element.
  Kokkos::View<const double*, Mem> qx[D], qw[D];
  Kokkos::View<const int*, Mem> qoff[D];
  KOKKOS_INLINE_FUNCTION int nen() const {
    int m = 1;
    for (int d = 0; d < D; ++d) m *= p[d] + 1;
    return m;
  }
  KOKKOS_INLINE_FUNCTION int num_elements() const {
    int m = 1;
    for (int d = 0; d < D; ++d) m *= ne[d];
    return m;
  }
  /// The element's index per direction ei[d] and its spans s[d].
  KOKKOS_INLINE_FUNCTION void element_spans(int e, int ei[D], int s[D]) const {
    tensor_ij_d<D>(e, ne, ei);
    for (int d = 0; d < D; ++d) s[d] = span[d](ei[d]);
  }
  /// The control points g[a] of all local functions a = l0 + (p0 + 1)(l1 + (p1 + 1) l2) of the
  /// element with spans s (nested loops: no division per function).
  KOKKOS_INLINE_FUNCTION void local_cps(const int s[D], int* g) const {
    const int m2 = D == 3 ? p[D - 1] + 1 : 1;
    int a = 0;
    for (int l2 = 0; l2 < m2; ++l2) {
      const int k = D == 3 ? s[D - 1] - p[D - 1] + l2 : 0;
      for (int l1 = 0; l1 <= p[1]; ++l1) {
        int gg = s[0] - p[0] + n[0] * (s[1] - p[1] + l1 + n[1] * k);
        for (int l0 = 0; l0 <= p[0]; ++l0) g[a++] = gg++;
      }
    }
  }
  /// Control point of local function a (a = l0 + (p0 + 1)(l1 + ...)) of the element with spans s.
  KOKKOS_INLINE_FUNCTION int local_cp(const int s[D], int a) const {
    int l[D], m[D], g[D];
    for (int d = 0; d < D; ++d) m[d] = p[d] + 1;
    tensor_ij_d<D>(a, m, l);
    for (int d = 0; d < D; ++d) g[d] = s[d] - p[d] + l[d];
    return tensor_index(g, n, D);
  }
};
using PatchData = PatchDataT<2, MemSpace>;
using HostPatchData = PatchDataT<2, Kokkos::HostSpace>;
using PatchData3 = PatchDataT<3, MemSpace>;
using HostPatchData3 = PatchDataT<3, Kokkos::HostSpace>;

/// Gauss-Legendre points and weights on [-1, 1], for n = 1..kMaxGauss.
constexpr int kMaxGauss = 12;
struct GaussRule {
  int n = 0;
  double x[kMaxGauss] = {}, w[kMaxGauss] = {};
};
GaussRule gauss_rule(int n);

/// The 1-D rule of element row k (span s) in direction d: the patch's own rule where it has
/// one (PatchData qx/qw/qoff), else Gauss rule g mapped onto the span. Nodes x in the
/// parameter, weights w including the span's length; returns their number.
template <class PD>
KOKKOS_INLINE_FUNCTION int element_rule_1d(const PD& pd, int d, int k, int s, const GaussRule& g,
                                           double x[kMaxGauss], double w[kMaxGauss]) {
  const auto& off = pd.qoff[d];
  if (off.extent(0) > 0) {
    const auto& qx = pd.qx[d];
    const auto& qw = pd.qw[d];
    const int o = off(k), n = off(k + 1) - o;
    for (int q = 0; q < n; ++q) {
      x[q] = qx(o + q);
      w[q] = qw(o + q);
    }
    return n;
  }
  const double* U = pd.U[d].data();
  const double a = U[s], h = 0.5 * (U[s + 1] - U[s]);
  for (int q = 0; q < g.n; ++q) {
    x[q] = a + h * (g.x[q] + 1.0);
    w[q] = h * g.w[q];
  }
  return g.n;
}

/// The material of a body as the kernels see it (kernels/material.hpp evaluates it), for
/// either dimension.
/// model kLinear: small strain, sigma = D eps with D the elasticity matrix in Voigt notation
/// (engineering shear strain): in 2-D the 3 x 3 plane strain or plane stress matrix
/// (xx, yy, xy) in D[0..2][0..2]; in 3-D the 6 x 6 matrix (xx, yy, zz, yz, xz, xy).
/// kSaintVenantKirchhoff, kNeoHookean: finite strain with the Lame constants lambda, mu
/// (2-D: plane strain). In 2-D, D, lambda and mu include the thickness.
struct Material {
  enum Model : int { kLinear = 0, kSaintVenantKirchhoff = 1, kNeoHookean = 2 };
  int model = kLinear;
  double D[6][6] = {};
  double lambda = 0, mu = 0;
  /// Small-strain linear elasticity in 2-D (plane strain or plane stress).
  static Material plane(double E, double nu, bool plane_strain, double thickness);
  /// A finite-strain model in 2-D (plane strain): model kSaintVenantKirchhoff or kNeoHookean.
  static Material finite(int model, double E, double nu, double thickness);
  /// A 3-D solid: small-strain isotropic (model kLinear, the 6 x 6 D) or a finite-strain model.
  static Material solid(int model, double E, double nu);
  /// Its tangent does not depend on the displacement (small-strain linear).
  KOKKOS_INLINE_FUNCTION bool constant_tangent() const { return model == kLinear; }
};

/// Calls f(std::integral_constant<int, P>{}) for the degree P = 1..kMaxDegree, the one place
/// where run-time degrees become compile-time ones. Unknown degrees are rejected.
template <class F>
void dispatch_degree(int p, F&& f) {
  switch (p) {
    case 1: f(std::integral_constant<int, 1>{}); break;
    case 2: f(std::integral_constant<int, 2>{}); break;
    case 3: f(std::integral_constant<int, 3>{}); break;
    case 4: f(std::integral_constant<int, 4>{}); break;
    case 5: f(std::integral_constant<int, 5>{}); break;
    default: throw std::invalid_argument("unsupported NURBS degree " + std::to_string(p) + " (1..5)");
  }
}

/// Calls f(std::integral_constant<int, D>{}, std::integral_constant<int, P>{}) for the
/// dimension dim = 2, 3 and the degree p = 1..kMaxDegree (the largest of a patch's degrees;
/// the kernels loop over each direction's own degree at run time).
template <class F>
void dispatch(int dim, int p, F&& f) {
  if (dim == 2)
    dispatch_degree(p, [&](auto P) { f(std::integral_constant<int, 2>{}, P); });
  else if (dim == 3)
    dispatch_degree(p, [&](auto P) { f(std::integral_constant<int, 3>{}, P); });
  else
    throw std::invalid_argument("unsupported dimension " + std::to_string(dim) + " (2, 3)");
}

/// Control points of the element with spans s[0..D) in homogeneous form,
/// cw[a] = (w x_0, .., w x_{D-1}, w), a = l0 + (p0 + 1)(l1 + (p1 + 1) l2).
template <int P, class PD>
KOKKOS_INLINE_FUNCTION void element_homogeneous_cp(const PD& pd, const int s[PD::dim],
                                                   double cw[][PD::dim + 1]) {
  constexpr int D = PD::dim;
  const int nen = pd.nen();
  int gs[kNen<D, P>];
  pd.local_cps(s, gs);
  for (int a = 0; a < nen; ++a) {
    const int g = gs[a];
    const double w = pd.cp(g, D);
    double* c = cw[a];
    for (int k = 0; k < D; ++k) c[k] = w * pd.cp(g, k);
    c[D] = w;
  }
}
/// The 2-D form: spans (s0, s1).
template <int P, class PD>
KOKKOS_INLINE_FUNCTION void element_homogeneous_cp(const PD& pd, int s0, int s1, double cw[(P + 1) * (P + 1)][3]) {
  const int s[2] = {s0, s1};
  element_homogeneous_cp<P>(pd, s, cw);
}

/// det A and A^-1 of a D x D matrix (adjugate over the determinant).
template <int D>
KOKKOS_FORCEINLINE_FUNCTION double det_inverse(const double A[D][D], double Ai[D][D]) {
  if constexpr (D == 2) {
    const double det = A[0][0] * A[1][1] - A[0][1] * A[1][0], idet = 1.0 / det;
    Ai[0][0] = A[1][1] * idet;
    Ai[0][1] = -A[0][1] * idet;
    Ai[1][0] = -A[1][0] * idet;
    Ai[1][1] = A[0][0] * idet;
    return det;
  } else {
    const double c00 = A[1][1] * A[2][2] - A[1][2] * A[2][1];
    const double c01 = A[1][2] * A[2][0] - A[1][0] * A[2][2];
    const double c02 = A[1][0] * A[2][1] - A[1][1] * A[2][0];
    const double det = A[0][0] * c00 + A[0][1] * c01 + A[0][2] * c02, idet = 1.0 / det;
    Ai[0][0] = c00 * idet;
    Ai[1][0] = c01 * idet;
    Ai[2][0] = c02 * idet;
    Ai[0][1] = (A[0][2] * A[2][1] - A[0][1] * A[2][2]) * idet;
    Ai[1][1] = (A[0][0] * A[2][2] - A[0][2] * A[2][0]) * idet;
    Ai[2][1] = (A[0][1] * A[2][0] - A[0][0] * A[2][1]) * idet;
    Ai[0][2] = (A[0][1] * A[1][2] - A[0][2] * A[1][1]) * idet;
    Ai[1][2] = (A[0][2] * A[1][0] - A[0][0] * A[1][2]) * idet;
    Ai[2][2] = (A[0][0] * A[1][1] - A[0][1] * A[1][0]) * idet;
    return det;
  }
}

/// The rational map at a point from the homogeneous sums in D + 1 "slots": S[0] = sum_a N_a cw_a
/// and S[1 + alpha] = d/dxi_alpha of it (components w x_0 .. w x_{D-1}, w; each S[s] has at
/// least D + 1 entries): the point x and the inverse Jacobian Ji[alpha][J] = d xi_alpha / d x_J;
/// returns det(dx/dxi). Shared by nurbs_grad and the row-wise formation's point fields
/// (kernels/elasticity_sf.hpp). Cost: D (D + 1) 3 + det/inverse (2-D: 10, 3-D: ~ 45) flops.
template <int D>
KOKKOS_FORCEINLINE_FUNCTION double rational_map(const double* const S[D + 1], double x[D], double Ji[D][D]) {
  const double iW = 1.0 / S[0][D];
  for (int J = 0; J < D; ++J) x[J] = S[0][J] * iW;
  double Jac[D][D];   // Jac[J][alpha] = d x_J / d xi_alpha
  for (int J = 0; J < D; ++J)
    for (int al = 0; al < D; ++al) Jac[J][al] = (S[1 + al][J] - x[J] * S[1 + al][D]) * iW;
  double Jinv[D][D];  // Jinv[alpha][J]
  const double det = det_inverse<D>(Jac, Jinv);
  for (int al = 0; al < D; ++al)
    for (int J = 0; J < D; ++J) Ji[al][J] = Jinv[al][J];
  return det;
}
/// The 2-D form: S, S_xi, S_eta.
KOKKOS_INLINE_FUNCTION double rational_map(const double S[3], const double Su[3], const double Sv[3], double x[2],
                                           double Ji[2][2]) {
  const double* const s[3] = {S, Su, Sv};
  return rational_map<2>(s, x, Ji);
}

/// The homogeneous sums of the D + 1 derivative slots at a point, sum-factorised direction by
/// direction: S[0][k] = sum_a N_a cw_a[k], S[1 + alpha][k] = sum_a (d N_a / d xi_alpha) cw_a[k],
/// N_a = prod_d B_d[0][l_d], d/dxi_alpha replaces B_alpha[0] by B_alpha[1]. B[d][o][l]: the 1-D
/// values (o = 0) and derivatives (o = 1) of direction d; cw: the element's nen values of K
/// components (homogeneous control points, K = D + 1, or more). Contraction over l0 first, then
/// l1 (then l2): cost 2 K nen + 3 K nen / (p0 + 1) + 4 K (p2 + 1) multiply-adds.
template <int D, int K>
KOKKOS_FORCEINLINE_FUNCTION void homogeneous_sums(const int p[D], const double (*const B[D])[kMaxBasis1D],
                                             const double (*cw)[K], double S[D + 1][K]) {
  const int m0 = p[0] + 1, m1 = p[1] + 1, m2 = D == 3 ? p[D - 1] + 1 : 1;
  for (int s = 0; s <= D; ++s)
    for (int k = 0; k < K; ++k) S[s][k] = 0.0;
  for (int l2 = 0; l2 < m2; ++l2) {
    // T: the sums over l0 and l1 of this l2 plane, slots value, xi, eta (3-D; in 2-D the result)
    double T[3][K];
    for (int s = 0; s < 3; ++s)
      for (int k = 0; k < K; ++k) T[s][k] = 0.0;
    for (int l1 = 0; l1 < m1; ++l1) {
      double A[K], Bd[K];
      for (int k = 0; k < K; ++k) A[k] = Bd[k] = 0.0;
      const double(*c)[K] = cw + m0 * (l1 + m1 * l2);
      for (int l0 = 0; l0 < m0; ++l0)
        for (int k = 0; k < K; ++k) {
          A[k] += B[0][0][l0] * c[l0][k];
          Bd[k] += B[0][1][l0] * c[l0][k];
        }
      for (int k = 0; k < K; ++k) {
        T[0][k] += B[1][0][l1] * A[k];
        T[1][k] += B[1][0][l1] * Bd[k];
        T[2][k] += B[1][1][l1] * A[k];
      }
    }
    if constexpr (D == 2) {
      for (int s = 0; s < 3; ++s)
        for (int k = 0; k < K; ++k) S[s][k] = T[s][k];
    } else {
      for (int k = 0; k < K; ++k) {
        for (int s = 0; s < 3; ++s) S[s][k] += B[2][0][l2] * T[s][k];
        S[3][k] += B[2][1][l2] * T[0][k];
      }
    }
  }
}

/// NURBS basis R_a, physical gradients dR[a][J] and the point x from the 1-D B-spline values and
/// first derivatives B[d][0..1][l] of each direction and the homogeneous control points cw.
/// Returns det(dx/dxi). The weighted sums are sum-factorised (homogeneous_sums):
///   W = S_0[D], x = S_0[0..D) / W, dx/dxi_alpha = (S_alpha - x W_alpha) / W,
///   R_a = w_a N_a / W,  R_a,alpha = (w_a N_a,alpha - R_a W_alpha) / W,  grad R_a = J^{-T} (R_a,alpha)
/// Cost: 2-D 12 nen + 9 (p1 + 1) + 13 nen + ~ 20 flops; 3-D ~ 16 nen + 25 nen (basis and
/// gradients) + ~ 80 flops.
template <int D, int P>
KOKKOS_INLINE_FUNCTION double nurbs_grad_tensor(const int p[D], const double (*const B[D])[kMaxBasis1D],
                                                const double (*cw)[D + 1], double R[], double dR[][D], double x[D]) {
  double S[D + 1][D + 1];
  homogeneous_sums<D, D + 1>(p, B, cw, S);
  const double* Sp[D + 1];
  for (int k = 0; k <= D; ++k) Sp[k] = S[k];
  double Ji[D][D];
  const double det = rational_map<D>(Sp, x, Ji);
  const double iW = 1.0 / S[0][D];
  double Wd[D];
  for (int al = 0; al < D; ++al) Wd[al] = S[1 + al][D];
  const int m0 = p[0] + 1, m1 = p[1] + 1, m2 = D == 3 ? p[D - 1] + 1 : 1;
  int a = 0;
  for (int l2 = 0; l2 < m2; ++l2)
    for (int l1 = 0; l1 < m1; ++l1)
      for (int l0 = 0; l0 < m0; ++l0, ++a) {
        const double w = cw[a][D] * iW;
        // products of the 1-D factors, direction 0 first: value and the D derivatives
        double Rd[D];
        if constexpr (D == 2) {
          R[a] = w * B[0][0][l0] * B[1][0][l1];
          Rd[0] = w * B[0][1][l0] * B[1][0][l1] - R[a] * Wd[0] * iW;
          Rd[1] = w * B[0][0][l0] * B[1][1][l1] - R[a] * Wd[1] * iW;
        } else {
          const double z0 = B[2][0][l2];
          R[a] = w * B[0][0][l0] * B[1][0][l1] * z0;
          Rd[0] = w * B[0][1][l0] * B[1][0][l1] * z0 - R[a] * Wd[0] * iW;
          Rd[1] = w * B[0][0][l0] * B[1][1][l1] * z0 - R[a] * Wd[1] * iW;
          Rd[2] = w * B[0][0][l0] * B[1][0][l1] * B[2][1][l2] - R[a] * Wd[2] * iW;
        }
        for (int J = 0; J < D; ++J) {
          double g = Ji[0][J] * Rd[0];
          for (int al = 1; al < D; ++al) g += Ji[al][J] * Rd[al];
          dR[a][J] = g;
        }
      }
  return det;
}

/// The 2-D form: 1-D tables N (along u) and M (along v).
template <int P>
KOKKOS_INLINE_FUNCTION double nurbs_grad_1d(int p0, int p1, const double N[][kMaxBasis1D], const double M[][kMaxBasis1D],
                                            const double cw[(P + 1) * (P + 1)][3], double R[(P + 1) * (P + 1)],
                                            double dR[(P + 1) * (P + 1)][2], double x[2]) {
  const int p[2] = {p0, p1};
  const double(*const B[2])[kMaxBasis1D] = {N, M};
  return nurbs_grad_tensor<2, P>(p, B, cw, R, dR, x);
}

/// NURBS basis R_a and physical gradients at the parametric point xi[0..D) of the element with
/// spans s[0..D), on the reference geometry. Returns det(dx/dxi). a = l0 + (p0 + 1)(l1 + ..)
/// numbers the nen active functions.
template <int P, class PD>
KOKKOS_INLINE_FUNCTION double nurbs_grad(const PD& pd, const int s[PD::dim], const double xi[PD::dim], double R[],
                                         double dR[][PD::dim], double x[PD::dim]) {
  constexpr int D = PD::dim;
  double N[D][3][kMaxBasis1D], cw[kNen<D, P>][D + 1];
  const double(*B[D])[kMaxBasis1D];
  for (int d = 0; d < D; ++d) {
    bspline_ders(s[d], xi[d], pd.p[d], pd.U[d].data(), 1, N[d]);
    B[d] = N[d];
  }
  element_homogeneous_cp<P>(pd, s, cw);
  return nurbs_grad_tensor<D, P>(pd.p, B, cw, R, dR, x);
}
/// The 2-D form: spans (s0, s1), point (u, v).
template <int P, class PD>
KOKKOS_INLINE_FUNCTION double nurbs_grad(const PD& pd, int s0, int s1, double u, double v,
                                         double R[(P + 1) * (P + 1)],
                                         double dR[(P + 1) * (P + 1)][2], double x[2]) {
  const int s[2] = {s0, s1};
  const double xi[2] = {u, v};
  return nurbs_grad<P>(pd, s, xi, R, dR, x);
}

}  // namespace iga
