#pragma once
// Material response at one quadrature point: the first Piola-Kirchhoff stress P and its
// derivative A = dP/dF (the consistent tangent: material and geometric parts together), from
// the displacement gradient H = Grad u on the reference configuration, F = I + H, in plane
// strain (F_33 = 1). Every material goes through this one function; the element kernel
// (kernels/elasticity.hpp) then forms
//   f_int,a = \int_Omega0 P . Grad R_a dOmega0,    K_ab = \int_Omega0 Grad R_a . A . Grad R_b dOmega0.
//
// Models (Material::model; lambda, mu, D include the thickness):
//   kLinear (small strain)   P = sigma(eps), eps = sym H, sigma = D eps (Voigt);  A_iJkL = D[v(iJ)][v(kL)],
//                            v(00) = 0, v(11) = 1, v(01) = v(10) = 2 (engineering shear strain),
//                            so Grad R_a . A . Grad R_b = B_a^T D B_b, the small-strain stiffness.
//   kSaintVenantKirchhoff    E = (F^T F - I) / 2, S = lambda tr(E) I + 2 mu E (E_33 = 0), P = F S,
//                            A_iJkL = delta_ik S_JL + lambda F_iJ F_kL + mu (F F^T)_ik delta_JL + mu F_iL F_kJ
//   kNeoHookean              W = mu/2 (I_1 - 3) - mu ln J + lambda/2 (ln J)^2, I_1 = tr C + 1,
//                            P = mu (F - F^-T) + lambda ln J F^-T,
//                            A_iJkL = mu delta_ik delta_JL + (mu - lambda ln J) F^-1_Jk F^-1_Li
//                                     + lambda F^-1_Ji F^-1_Lk
// The out-of-plane stress P_33 (= S_33 with F_33 = 1) is returned for the Cauchy stress
// sigma_33 = P_33 / J: lambda tr E (SVK), lambda ln J (neo-Hookean); 0 for kLinear (the
// caller knows sigma_zz = nu (sxx + syy) in plane strain there).
// A neo-Hookean point with J <= 0 (a folded deformation) returns NaN: the residual is then
// not finite and Newton's line search or step cutting takes over.
//
// Layout: P[i][J] (row: spatial component i, column: reference direction J), A[2 i + J][2 k + L].
// Cost per point: kLinear ~ 10 flops (+ 16 copies for A); SVK ~ 30 + 16 x 10 flops;
// neo-Hookean ~ 35 flops + a log, + 16 x 8 flops for A.
#include <Kokkos_ArithTraits.hpp>
#include <Kokkos_Core.hpp>

#include "kernels/types.hpp"

namespace iga {

/// P (and A when Tangent) at H for material m; returns false where the deformation is
/// inadmissible (det F <= 0 for the neo-Hookean model).
template <bool Tangent>
KOKKOS_INLINE_FUNCTION bool material_response(const Material& m, const double H[2][2], double P[2][2], double& P33,
                                              double A[4][4]) {
  if (m.model == Material::kLinear) {
    const double e0 = H[0][0], e1 = H[1][1], e2 = H[0][1] + H[1][0];
    P[0][0] = m.D[0][0] * e0 + m.D[0][1] * e1 + m.D[0][2] * e2;
    P[1][1] = m.D[1][0] * e0 + m.D[1][1] * e1 + m.D[1][2] * e2;
    P[0][1] = P[1][0] = m.D[2][0] * e0 + m.D[2][1] * e1 + m.D[2][2] * e2;
    P33 = 0.0;
    if (Tangent) {
      constexpr int v[4] = {0, 2, 2, 1};
      for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) A[r][c] = m.D[v[r]][v[c]];
    }
    return true;
  }
  const double F[2][2] = {{1.0 + H[0][0], H[0][1]}, {H[1][0], 1.0 + H[1][1]}};
  const double lam = m.lambda, mu = m.mu;
  if (m.model == Material::kSaintVenantKirchhoff) {
    double E[2][2];
    for (int I = 0; I < 2; ++I)
      for (int J = 0; J < 2; ++J) E[I][J] = 0.5 * (F[0][I] * F[0][J] + F[1][I] * F[1][J] - (I == J ? 1.0 : 0.0));
    const double trE = E[0][0] + E[1][1];
    double S[2][2];
    for (int I = 0; I < 2; ++I)
      for (int J = 0; J < 2; ++J) S[I][J] = 2.0 * mu * E[I][J] + (I == J ? lam * trE : 0.0);
    for (int i = 0; i < 2; ++i)
      for (int J = 0; J < 2; ++J) P[i][J] = F[i][0] * S[0][J] + F[i][1] * S[1][J];
    P33 = lam * trE;
    if (Tangent) {
      double FFt[2][2];
      for (int i = 0; i < 2; ++i)
        for (int k = 0; k < 2; ++k) FFt[i][k] = F[i][0] * F[k][0] + F[i][1] * F[k][1];
      for (int i = 0; i < 2; ++i)
        for (int J = 0; J < 2; ++J)
          for (int k = 0; k < 2; ++k)
            for (int L = 0; L < 2; ++L)
              A[2 * i + J][2 * k + L] = (i == k ? S[J][L] : 0.0) + lam * F[i][J] * F[k][L] +
                                        (J == L ? mu * FFt[i][k] : 0.0) + mu * F[i][L] * F[k][J];
    }
    return true;
  }
  // neo-Hookean
  const double J = F[0][0] * F[1][1] - F[0][1] * F[1][0];
  if (!(J > 0.0)) {
    const double nan = Kokkos::Details::ArithTraits<double>::nan();
    P[0][0] = P[0][1] = P[1][0] = P[1][1] = P33 = nan;
    if (Tangent)
      for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) A[r][c] = nan;
    return false;
  }
  const double iJ = 1.0 / J, lnJ = kmath::log(J);
  const double Fi[2][2] = {{F[1][1] * iJ, -F[0][1] * iJ}, {-F[1][0] * iJ, F[0][0] * iJ}};   // F^-1
  for (int i = 0; i < 2; ++i)
    for (int K = 0; K < 2; ++K) P[i][K] = mu * F[i][K] + (lam * lnJ - mu) * Fi[K][i];
  P33 = lam * lnJ;
  if (Tangent) {
    const double c = mu - lam * lnJ;
    for (int i = 0; i < 2; ++i)
      for (int Jd = 0; Jd < 2; ++Jd)
        for (int k = 0; k < 2; ++k)
          for (int L = 0; L < 2; ++L)
            A[2 * i + Jd][2 * k + L] =
                (i == k && Jd == L ? mu : 0.0) + c * Fi[Jd][k] * Fi[L][i] + lam * Fi[Jd][i] * Fi[L][k];
  }
  return true;
}

/// Cauchy stress sigma = P F^T / J on the deformed configuration, in-plane components and
/// sigma_33 = P_33 / J (F_33 = 1). Small strain (kLinear): sigma = P.
KOKKOS_INLINE_FUNCTION void cauchy_stress(const Material& m, const double H[2][2], const double P[2][2], double P33,
                                          double s[2][2], double& s33) {
  if (m.model == Material::kLinear) {
    for (int i = 0; i < 2; ++i)
      for (int j = 0; j < 2; ++j) s[i][j] = P[i][j];
    s33 = P33;
    return;
  }
  const double F[2][2] = {{1.0 + H[0][0], H[0][1]}, {H[1][0], 1.0 + H[1][1]}};
  const double iJ = 1.0 / (F[0][0] * F[1][1] - F[0][1] * F[1][0]);
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j) s[i][j] = (P[i][0] * F[j][0] + P[i][1] * F[j][1]) * iJ;
  s33 = P33 * iJ;
}

}  // namespace iga
