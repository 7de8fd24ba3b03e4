#pragma once
// Data the kernels read: one NURBS patch on the device, Gauss rules, material.
// Kokkos only; the solver layer fills these from the model and from Tpetra.
#include <Kokkos_Core.hpp>

#include <stdexcept>
#include <string>

#include "kernels/nurbs_basis.hpp"

namespace iga {

using ExecSpace = Kokkos::DefaultExecutionSpace;
using MemSpace = ExecSpace::memory_space;

/// One patch in memory space Mem (the device for kernels, the host for sampling).
/// Element e covers spans (span0[e % ne0], span1[e / ne0]).
template <class Mem>
struct PatchDataT {
  int p[2] = {1, 1};
  int n[2] = {0, 0};    // basis functions per direction
  int ne[2] = {0, 0};   // elements per direction
  Kokkos::View<const double*, Mem> U0, U1;       // knot vectors
  Kokkos::View<const double* [3], Mem> cp;       // reference x, y and weight
  Kokkos::View<const int*, Mem> span0, span1;    // non-empty knot spans
  Kokkos::View<const int*, Mem> lid;             // cp index -> overlap cp LID (-1: not here)
  // The element rule of each direction (solver.quadrature: spline, model/quadrature.hpp):
  // element row k of direction d has the nodes qx_d[qoff_d[k] .. qoff_d[k + 1]) in the
  // parameter and weights qw_d (the span's length included). Empty: the Gauss rule the
  // kernel is given, p + 1 points per element.
  Kokkos::View<const double*, Mem> qx0, qw0, qx1, qw1;
  Kokkos::View<const int*, Mem> qoff0, qoff1;
  KOKKOS_INLINE_FUNCTION int nen() const { return (p[0] + 1) * (p[1] + 1); }
};
using PatchData = PatchDataT<MemSpace>;
using HostPatchData = PatchDataT<Kokkos::HostSpace>;

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
  const auto& off = d == 0 ? pd.qoff0 : pd.qoff1;
  if (off.extent(0) > 0) {
    const auto& qx = d == 0 ? pd.qx0 : pd.qx1;
    const auto& qw = d == 0 ? pd.qw0 : pd.qw1;
    const int o = off(k), n = off(k + 1) - o;
    for (int q = 0; q < n; ++q) {
      x[q] = qx(o + q);
      w[q] = qw(o + q);
    }
    return n;
  }
  const double* U = d == 0 ? pd.U0.data() : pd.U1.data();
  const double a = U[s], h = 0.5 * (U[s + 1] - U[s]);
  for (int q = 0; q < g.n; ++q) {
    x[q] = a + h * (g.x[q] + 1.0);
    w[q] = h * g.w[q];
  }
  return g.n;
}

/// The material of a body as the kernels see it (kernels/material.hpp evaluates it).
/// model kLinear: small strain, sigma = D eps with D the plane elasticity matrix (Voigt,
/// engineering shear strain). kSaintVenantKirchhoff, kNeoHookean: finite strain, plane strain,
/// with the Lame constants lambda, mu. D, lambda and mu include the thickness.
struct Material {
  enum Model : int { kLinear = 0, kSaintVenantKirchhoff = 1, kNeoHookean = 2 };
  int model = kLinear;
  double D[3][3] = {};
  double lambda = 0, mu = 0;
  /// Small-strain linear elasticity (plane strain or plane stress).
  static Material plane(double E, double nu, bool plane_strain, double thickness);
  /// A finite-strain model (plane strain): model kSaintVenantKirchhoff or kNeoHookean.
  static Material finite(int model, double E, double nu, double thickness);
  /// Its tangent does not depend on the displacement (small-strain linear).
  bool constant_tangent() const { return model == kLinear; }
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

/// Control points of the element with spans (s0, s1) in homogeneous form, cw[a] = (w x, w y, w),
/// a = i + j (p0 + 1).
template <int P, class PD>
KOKKOS_INLINE_FUNCTION void element_homogeneous_cp(const PD& pd, int s0, int s1, double cw[(P + 1) * (P + 1)][3]) {
  const int p0 = pd.p[0], p1 = pd.p[1];
  for (int j = 0; j <= p1; ++j)
    for (int i = 0; i <= p0; ++i) {
      const int g = s0 - p0 + i + (s1 - p1 + j) * pd.n[0];
      const double w = pd.cp(g, 2);
      double* c = cw[i + j * (p0 + 1)];
      c[0] = w * pd.cp(g, 0);
      c[1] = w * pd.cp(g, 1);
      c[2] = w;
    }
}

/// The rational map at a point from the homogeneous sums S = sum_ij N_i M_j cw_ij and their
/// xi and eta derivatives Su, Sv (components w x, w y, w): the point x and the inverse Jacobian
/// Ji[alpha][J] = d xi_alpha / d x_J; returns det(dx/dxi). Shared by nurbs_grad_1d and the
/// row-wise formation's point fields (kernels/elasticity_sf.hpp).
KOKKOS_INLINE_FUNCTION double rational_map(const double S[3], const double Su[3], const double Sv[3], double x[2],
                                           double Ji[2][2]) {
  const double iW = 1.0 / S[2], Wu = Su[2], Wv = Sv[2];
  x[0] = S[0] * iW;
  x[1] = S[1] * iW;
  const double xu = (Su[0] - x[0] * Wu) * iW, xv = (Sv[0] - x[0] * Wv) * iW;
  const double yu = (Su[1] - x[1] * Wu) * iW, yv = (Sv[1] - x[1] * Wv) * iW;
  const double det = xu * yv - xv * yu, idet = 1.0 / det;
  Ji[0][0] = yv * idet;
  Ji[0][1] = -xv * idet;
  Ji[1][0] = -yu * idet;
  Ji[1][1] = xu * idet;
  return det;
}

/// NURBS basis R_a, physical gradients and the point x from the 1-D B-spline values and first
/// derivatives N[0..1][i] (along u) and M[0..1][j] (along v) and the homogeneous control
/// points cw. Returns det(dx/dxi). The weighted sums are sum-factorised (over i, then j):
///   S = sum_ij N_i M_j cw_ij,  S_u = sum_ij N_i' M_j cw_ij,  S_v = sum_ij N_i M_j' cw_ij
///   W = S_2, x = S_0..1 / W, x_u = (S_u - x W_u) / W, R_a = w_a N_i M_j / W,
///   R_a,u = (w_a N_i' M_j - R_a W_u) / W,  grad R_a = J^{-T} (R_a,u, R_a,v)
/// Cost: 12 nen + 9 (p1 + 1) (sums) + 13 nen (basis and gradients) + ~ 20 flops.
template <int P>
KOKKOS_INLINE_FUNCTION double nurbs_grad_1d(int p0, int p1, const double N[][kMaxBasis1D], const double M[][kMaxBasis1D],
                                            const double cw[(P + 1) * (P + 1)][3], double R[(P + 1) * (P + 1)],
                                            double dR[(P + 1) * (P + 1)][2], double x[2]) {
  double S[3] = {0, 0, 0}, Su[3] = {0, 0, 0}, Sv[3] = {0, 0, 0};
  for (int j = 0; j <= p1; ++j) {
    double A[3] = {0, 0, 0}, B[3] = {0, 0, 0};
    for (int i = 0; i <= p0; ++i) {
      const double* c = cw[i + j * (p0 + 1)];
      for (int k = 0; k < 3; ++k) {
        A[k] += N[0][i] * c[k];
        B[k] += N[1][i] * c[k];
      }
    }
    for (int k = 0; k < 3; ++k) {
      S[k] += M[0][j] * A[k];
      Su[k] += M[0][j] * B[k];
      Sv[k] += M[1][j] * A[k];
    }
  }
  double Ji[2][2];
  const double det = rational_map(S, Su, Sv, x, Ji);
  const double iW = 1.0 / S[2], Wu = Su[2], Wv = Sv[2];
  // dR/dx = J^{-T} dR/dxi, J = [[xu, xv], [yu, yv]]
  const double i00 = Ji[0][0], i01 = Ji[0][1], i10 = Ji[1][0], i11 = Ji[1][1];
  for (int j = 0; j <= p1; ++j)
    for (int i = 0; i <= p0; ++i) {
      const int a = i + j * (p0 + 1);
      const double w = cw[a][2] * iW;
      R[a] = w * N[0][i] * M[0][j];
      const double Ru = w * N[1][i] * M[0][j] - R[a] * Wu * iW;
      const double Rv = w * N[0][i] * M[1][j] - R[a] * Wv * iW;
      dR[a][0] = i00 * Ru + i10 * Rv;
      dR[a][1] = i01 * Ru + i11 * Rv;
    }
  return det;
}

/// NURBS basis R_a and physical gradients at parametric point (u, v) of the element with
/// spans (s0, s1), on the reference geometry. Returns det(dx/dxi). a = i + j (p0 + 1)
/// numbers the (p0 + 1)(p1 + 1) active functions.
template <int P, class PD>
KOKKOS_INLINE_FUNCTION double nurbs_grad(const PD& pd, int s0, int s1, double u, double v,
                                         double R[(P + 1) * (P + 1)],
                                         double dR[(P + 1) * (P + 1)][2], double x[2]) {
  double N[3][kMaxBasis1D], M[3][kMaxBasis1D], cw[(P + 1) * (P + 1)][3];
  bspline_ders(s0, u, pd.p[0], pd.U0.data(), 1, N);
  bspline_ders(s1, v, pd.p[1], pd.U1.data(), 1, M);
  element_homogeneous_cp<P>(pd, s0, s1, cw);
  return nurbs_grad_1d<P>(pd.p[0], pd.p[1], N, M, cw, R, dR, x);
}

}  // namespace iga
