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

/// Plane elasticity matrix D (Voigt, engineering shear strain) times the thickness.
struct Material {
  double D[3][3] = {};
  static Material plane(double E, double nu, bool plane_strain, double thickness);
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

/// NURBS basis R_a and physical gradients at parametric point (u, v) of the element with
/// spans (s0, s1). `xy` are the reference positions used for the geometry map. Returns
/// det(dx/dxi). a = i + j (p0 + 1) numbers the (p0 + 1)(p1 + 1) active functions.
template <int P, class PD>
KOKKOS_INLINE_FUNCTION double nurbs_grad(const PD& pd, int s0, int s1, double u, double v,
                                         double R[(P + 1) * (P + 1)],
                                         double dR[(P + 1) * (P + 1)][2], double x[2]) {
  const int p0 = pd.p[0], p1 = pd.p[1];
  double N[3][kMaxBasis1D], M[3][kMaxBasis1D];
  bspline_ders(s0, u, p0, pd.U0.data(), 1, N);
  bspline_ders(s1, v, p1, pd.U1.data(), 1, M);
  double W = 0, Wu = 0, Wv = 0;
  for (int j = 0; j <= p1; ++j)
    for (int i = 0; i <= p0; ++i) {
      const double w = pd.cp(s0 - p0 + i + (s1 - p1 + j) * pd.n[0], 2);
      W += N[0][i] * M[0][j] * w;
      Wu += N[1][i] * M[0][j] * w;
      Wv += N[0][i] * M[1][j] * w;
    }
  double J[2][2] = {{0, 0}, {0, 0}};
  x[0] = x[1] = 0;
  for (int j = 0; j <= p1; ++j)
    for (int i = 0; i <= p0; ++i) {
      const int a = i + j * (p0 + 1);
      const int g = s0 - p0 + i + (s1 - p1 + j) * pd.n[0];
      const double w = pd.cp(g, 2);
      R[a] = N[0][i] * M[0][j] * w / W;
      const double Ru = (N[1][i] * M[0][j] * w - R[a] * Wu) / W;
      const double Rv = (N[0][i] * M[1][j] * w - R[a] * Wv) / W;
      dR[a][0] = Ru; dR[a][1] = Rv;
      for (int c = 0; c < 2; ++c) {
        x[c] += R[a] * pd.cp(g, c);
        J[c][0] += Ru * pd.cp(g, c);
        J[c][1] += Rv * pd.cp(g, c);
      }
    }
  const double det = J[0][0] * J[1][1] - J[0][1] * J[1][0];
  // dR/dx = J^{-T} dR/dxi
  const double inv[2][2] = {{J[1][1] / det, -J[0][1] / det}, {-J[1][0] / det, J[0][0] / det}};
  const int nen = (p0 + 1) * (p1 + 1);
  for (int a = 0; a < nen; ++a) {
    const double gu = dR[a][0], gv = dR[a][1];
    dR[a][0] = inv[0][0] * gu + inv[1][0] * gv;
    dR[a][1] = inv[0][1] * gu + inv[1][1] * gv;
  }
  return det;
}

}  // namespace iga
