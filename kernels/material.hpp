#pragma once
// Material response at one quadrature point, in D = 2 or 3 dimensions: the first
// Piola-Kirchhoff stress P and its derivative A = dP/dF (the consistent tangent: material and
// geometric parts together), from the displacement gradient H = Grad u on the reference
// configuration, F = I + H; in 2-D plane strain (F_33 = 1). Every material goes through this one
// function; the element kernel (kernels/elasticity.hpp) then forms
//   f_int,a = \int_Omega0 P . Grad R_a dOmega0,    K_ab = \int_Omega0 Grad R_a . A . Grad R_b dOmega0.
//
// Models (Material::model; in 2-D lambda, mu, D include the thickness):
//   kLinear (small strain)   P = sigma(eps), eps = sym H, sigma = D eps (Voigt);  A_iJkL = D[v(iJ)][v(kL)],
//                            2-D: v(00) = 0, v(11) = 1, v(01) = v(10) = 2;
//                            3-D: v(00) = 0, v(11) = 1, v(22) = 2, v(12) = 3, v(02) = 4, v(01) = 5
//                            (engineering shear strain), so Grad R_a . A . Grad R_b = B_a^T D B_b,
//                            the small-strain stiffness.
//   kSaintVenantKirchhoff    E = (F^T F - I) / 2, S = lambda tr(E) I + 2 mu E (2-D: E_33 = 0), P = F S,
//                            A_iJkL = delta_ik S_JL + lambda F_iJ F_kL + mu (F F^T)_ik delta_JL + mu F_iL F_kJ
//   kNeoHookean              W = mu/2 (I_1 - 3) - mu ln J + lambda/2 (ln J)^2, I_1 = tr C (+ 1 in 2-D),
//                            P = mu (F - F^-T) + lambda ln J F^-T,
//                            A_iJkL = mu delta_ik delta_JL + (mu - lambda ln J) F^-1_Jk F^-1_Li
//                                     + lambda F^-1_Ji F^-1_Lk
// 2-D: the out-of-plane stress P_33 (= S_33 with F_33 = 1) is returned for the Cauchy stress
// sigma_33 = P_33 / J: lambda tr E (SVK), lambda ln J (neo-Hookean); 0 for kLinear (the
// caller knows sigma_zz = nu (sxx + syy) in plane strain there). 3-D: P33 = 0 (P[2][2] is the
// stress).
// A neo-Hookean point with J <= 0 (a folded deformation) returns NaN: the residual is then
// not finite and Newton's line search or step cutting takes over.
//
// Layout: H[i][J], P[i][J] (row: spatial component i, column: reference direction J),
// A[D i + J][D k + L] (D^2 x D^2).
// Cost per point (D^2 = 4 or 9 stress components, D^4 = 16 or 81 tangent entries):
//   kLinear ~ D^2 (D^2 + 3) / 2 .. 2-D 10, 3-D 54 flops (+ D^4 copies for A);
//   SVK ~ 2-D 30, 3-D 90 + D^4 x 10 flops; neo-Hookean ~ 2-D 35, 3-D 80 flops + a log, + D^4 x 8 for A.
#include <Kokkos_Core.hpp>

#include "kernels/types.hpp"

namespace iga {

namespace material_detail {
/// The Voigt index of the tensor pair (i, J), row-major i * D + J.
template <int D>
KOKKOS_INLINE_FUNCTION int voigt(int iJ) {
  if constexpr (D == 2) {
    constexpr int v[4] = {0, 2, 2, 1};
    return v[iJ];
  } else {
    constexpr int v[9] = {0, 5, 4, 5, 1, 3, 4, 3, 2};
    return v[iJ];
  }
}
// A row of the tangent, D^2 wide: A's parameter type below names D only through this (a
// non-deduced context), so that D is deduced from H alone (nvcc's front end does not deduce
// through the bound D * D)
template <int D>
struct TangentRow {
  using type = double[D * D];
};
}  // namespace material_detail

/// P (and A when Tangent) at H for material m in dimension D (deduced from H); returns false
/// where the deformation is inadmissible (det F <= 0 for the neo-Hookean model).
template <bool Tangent, int D>
KOKKOS_INLINE_FUNCTION bool material_response(const Material& m, const double H[D][D], double P[D][D], double& P33,
                                              typename material_detail::TangentRow<D>::type* A) {
  constexpr int NV = D == 2 ? 3 : 6;   // Voigt components
  if (m.model == Material::kLinear) {
    // engineering strain: normal components, then the shear pairs in Voigt order
    double e[NV];
    for (int i = 0; i < D; ++i) e[i] = H[i][i];
    if constexpr (D == 2) {
      e[2] = H[0][1] + H[1][0];
    } else {
      e[3] = H[1][2] + H[2][1];
      e[4] = H[0][2] + H[2][0];
      e[5] = H[0][1] + H[1][0];
    }
    for (int i = 0; i < D; ++i)
      for (int J = 0; J < D; ++J) {
        const double* Dr = m.D[material_detail::voigt<D>(D * i + J)];
        double s = Dr[0] * e[0];
        for (int r = 1; r < NV; ++r) s += Dr[r] * e[r];
        P[i][J] = s;
      }
    P33 = 0.0;
    if (Tangent)
      for (int r = 0; r < D * D; ++r)
        for (int c = 0; c < D * D; ++c) A[r][c] = m.D[material_detail::voigt<D>(r)][material_detail::voigt<D>(c)];
    return true;
  }
  double F[D][D];
  for (int i = 0; i < D; ++i)
    for (int J = 0; J < D; ++J) F[i][J] = (i == J ? 1.0 + H[i][J] : H[i][J]);
  const double lam = m.lambda, mu = m.mu;
  if (m.model == Material::kSaintVenantKirchhoff) {
    double E[D][D];
    for (int I = 0; I < D; ++I)
      for (int J = 0; J < D; ++J) {
        double c = F[0][I] * F[0][J];
        for (int k = 1; k < D; ++k) c += F[k][I] * F[k][J];
        E[I][J] = 0.5 * (c - (I == J ? 1.0 : 0.0));
      }
    double trE = E[0][0];
    for (int I = 1; I < D; ++I) trE += E[I][I];
    double S[D][D];
    for (int I = 0; I < D; ++I)
      for (int J = 0; J < D; ++J) S[I][J] = 2.0 * mu * E[I][J] + (I == J ? lam * trE : 0.0);
    for (int i = 0; i < D; ++i)
      for (int J = 0; J < D; ++J) {
        double s = F[i][0] * S[0][J];
        for (int K = 1; K < D; ++K) s += F[i][K] * S[K][J];
        P[i][J] = s;
      }
    P33 = D == 2 ? lam * trE : 0.0;
    if (Tangent) {
      double FFt[D][D];
      for (int i = 0; i < D; ++i)
        for (int k = 0; k < D; ++k) {
          double s = F[i][0] * F[k][0];
          for (int K = 1; K < D; ++K) s += F[i][K] * F[k][K];
          FFt[i][k] = s;
        }
      for (int i = 0; i < D; ++i)
        for (int J = 0; J < D; ++J)
          for (int k = 0; k < D; ++k)
            for (int L = 0; L < D; ++L)
              A[D * i + J][D * k + L] = (i == k ? S[J][L] : 0.0) + lam * F[i][J] * F[k][L] +
                                        (J == L ? mu * FFt[i][k] : 0.0) + mu * F[i][L] * F[k][J];
    }
    return true;
  }
  // neo-Hookean
  double Fi[D][D];   // F^-1
  const double J = det_inverse<D>(F, Fi);
  if (!(J > 0.0)) {
    const double nan = kmath::nan("");
    for (int i = 0; i < D; ++i)
      for (int K = 0; K < D; ++K) P[i][K] = nan;
    P33 = nan;
    if (Tangent)
      for (int r = 0; r < D * D; ++r)
        for (int c = 0; c < D * D; ++c) A[r][c] = nan;
    return false;
  }
  const double lnJ = kmath::log(J);
  for (int i = 0; i < D; ++i)
    for (int K = 0; K < D; ++K) P[i][K] = mu * F[i][K] + (lam * lnJ - mu) * Fi[K][i];
  P33 = D == 2 ? lam * lnJ : 0.0;
  if (Tangent) {
    const double c = mu - lam * lnJ;
    for (int i = 0; i < D; ++i)
      for (int Jd = 0; Jd < D; ++Jd)
        for (int k = 0; k < D; ++k)
          for (int L = 0; L < D; ++L)
            A[D * i + Jd][D * k + L] =
                (i == k && Jd == L ? mu : 0.0) + c * Fi[Jd][k] * Fi[L][i] + lam * Fi[Jd][i] * Fi[L][k];
  }
  return true;
}

/// Cauchy stress sigma = P F^T / J on the deformed configuration (2-D: in-plane components and
/// sigma_33 = P_33 / J, F_33 = 1; 3-D: s33 = 0, s[2][2] is the stress). Small strain (kLinear):
/// sigma = P.
template <int D>
KOKKOS_INLINE_FUNCTION void cauchy_stress(const Material& m, const double H[D][D], const double P[D][D], double P33,
                                          double s[D][D], double& s33) {
  if (m.model == Material::kLinear) {
    for (int i = 0; i < D; ++i)
      for (int j = 0; j < D; ++j) s[i][j] = P[i][j];
    s33 = P33;
    return;
  }
  double F[D][D], Fi[D][D];
  for (int i = 0; i < D; ++i)
    for (int J = 0; J < D; ++J) F[i][J] = (i == J ? 1.0 + H[i][J] : H[i][J]);
  const double iJ = 1.0 / det_inverse<D>(F, Fi);
  for (int i = 0; i < D; ++i)
    for (int j = 0; j < D; ++j) {
      double t = P[i][0] * F[j][0];
      for (int K = 1; K < D; ++K) t += P[i][K] * F[j][K];
      s[i][j] = t * iJ;
    }
  s33 = P33 * iJ;
}

}  // namespace iga
