// The element kernels in 3-D (PatchDataT<3>, D = 3 of the one code path), on trivariate NURBS
// blocks built directly: a box (B-splines, the identity map up to scaling) and a quarter of a
// thick cylinder shell extruded along z (rational, non-unit weights), degrees 1..4.
//   Basis3D        partition of unity, the geometry map reproduced (x, and sum_a x_a (x) Grad R_a = I),
//                  the volume; the basis kernel EvaluateBasisT<3> on the execution space
//   Material3D     the 3-D laws against formulas written out here
//   PatchTest3D    a linear displacement field gives the exact constant stress at every point, and
//                  the interior rows of the residual vanish (linear, SVK, neo-Hookean)
//   Tangent3D      the tangent against central differences of the residual (O(h^2)), symmetry,
//                  the 6 rigid-body modes in the null space and no other zero eigenvalue
//   Assembly3D     AssembleInternalT<3> (execution space, batched element matrices) against the
//                  sum of the element matrices and forces
// Tolerances: round-off (a few 1e-16 times the number of terms) where the quantity is exact
// in floating point arithmetic up to rounding; the FD error model for the tangent; the
// quadrature error where a rational integrand is integrated (stated at the test).
#include <gtest/gtest.h>

#include <KokkosSparse_CrsMatrix.hpp>

#include <algorithm>
#include <cstdio>
#include <array>
#include <cmath>
#include <set>
#include <vector>

#include "kernels/basis.hpp"
#include "kernels/elasticity.hpp"
#include "kernels/elasticity_sf3.hpp"
#include "model/nurbs.hpp"
#include "patches3d.hpp"

using namespace iga;
using namespace iga::test3d;

namespace {

// The exact map at the parameter xi.
std::array<double, 3> exact_map(const Block3& b, const double xi[3]) {
  if (!b.curved) return {b.L[0] * xi[0], b.L[1] * xi[1], b.L[2] * xi[2]};
  return {0, 0, b.H * xi[2]};   // the shell: z only (the angle is not uniform in xi_0; see the test)
}

double volume(const Block3& b) {
  return b.curved ? 0.25 * M_PI * (b.ro * b.ro - b.ri * b.ri) * b.H : b.L[0] * b.L[1] * b.L[2];
}

// Control points on the boundary of the block (some index at either end).
bool on_boundary(const Block3& b, int g) {
  const int i = g % b.n(0), j = (g / b.n(0)) % b.n(1), k = g / (b.n(0) * b.n(1));
  return i == 0 || j == 0 || k == 0 || i == b.n(0) - 1 || j == b.n(1) - 1 || k == b.n(2) - 1;
}

template <class F>
void for_degree(int p, F&& f) {
  dispatch_degree(p, std::forward<F>(f));
}

int pmax(const Block3& b) { return std::max({b.p[0], b.p[1], b.p[2]}); }

std::vector<Block3> geometries(bool with_p4 = true) {
  std::vector<Block3> g;
  for (int p = 1; p <= (with_p4 ? 4 : 3); ++p) g.push_back(box({p, p, p}, {2, 3, 2}));
  g.push_back(box({1, 3, 2}, {3, 2, 2}));
  for (int p = 2; p <= (with_p4 ? 4 : 3); ++p) g.push_back(shell(p, {2, 2, 2}, p));
  g.push_back(shell(2, {3, 1, 2}, 1));
  return g;
}

std::string name(const Block3& b) {
  return std::string(b.curved ? "shell" : "box") + " p = (" + std::to_string(b.p[0]) + ", " + std::to_string(b.p[1]) +
         ", " + std::to_string(b.p[2]) + ")";
}

// ---------------------------------------------------------------------------------------------

TEST(Basis3D, PartitionOfUnityGeometryAndVolume) {
  for (const Block3& b : geometries()) {
    const HostPatchData3 pd = patch_data<Kokkos::HostSpace>(b);
    double worst_sum = 0, worst_grad = 0, worst_x = 0, worst_map = 0, worst_id = 0, vol = 0;
    // 12-point Gauss: exact for the box; for the shell the Jacobian is rational and the rule's
    // error at this element size is below round-off
    const GaussRule g = gauss_rule(12);
    for_degree(pmax(b), [&](auto PP) {
      constexpr int P = decltype(PP)::value;
      double R[kNen<3, P>], dR[kNen<3, P>][3], x[3];
      for (int e = 0; e < pd.num_elements(); ++e) {
        int ei[3], s[3];
        pd.element_spans(e, ei, s);
        for (int q = 0; q < g.n * g.n * g.n; ++q) {
          const int qi[3] = {q % g.n, (q / g.n) % g.n, q / (g.n * g.n)};
          double xi[3], jw = 1;
          for (int d = 0; d < 3; ++d) {
            const double a = b.U[d][s[d]], h = 0.5 * (b.U[d][s[d] + 1] - a);
            xi[d] = a + h * (g.x[qi[d]] + 1);
            jw *= h * g.w[qi[d]];
          }
          const double det = nurbs_grad<P>(pd, s, xi, R, dR, x);
          vol += std::abs(det) * jw;
          double sum = 0, gs[3] = {0, 0, 0}, xs[3] = {0, 0, 0}, I[3][3] = {};
          for (int a = 0; a < pd.nen(); ++a) {
            const int cp = pd.local_cp(s, a);
            sum += R[a];
            for (int J = 0; J < 3; ++J) {
              gs[J] += dR[a][J];
              xs[J] += R[a] * b.cp[cp][J];
              for (int I2 = 0; I2 < 3; ++I2) I[I2][J] += b.cp[cp][I2] * dR[a][J];
            }
          }
          worst_sum = std::max(worst_sum, std::abs(sum - 1));
          for (int J = 0; J < 3; ++J) {
            worst_grad = std::max(worst_grad, std::abs(gs[J]));
            worst_x = std::max(worst_x, std::abs(xs[J] - x[J]));
            for (int I2 = 0; I2 < 3; ++I2) worst_id = std::max(worst_id, std::abs(I[I2][J] - (I2 == J ? 1.0 : 0.0)));
          }
          const auto xe = exact_map(b, xi);
          if (!b.curved) {
            for (int J = 0; J < 3; ++J) worst_map = std::max(worst_map, std::abs(x[J] - xe[J]));
          } else {
            // radius linear in xi_1 (the annulus' radial direction), z linear in xi_2
            const double r = std::hypot(x[0], x[1]);
            worst_map = std::max({worst_map, std::abs(r - (b.ri + (b.ro - b.ri) * xi[1])), std::abs(x[2] - xe[2])});
          }
        }
      }
    });
    EXPECT_LT(worst_sum, 1e-14) << name(b);
    EXPECT_LT(worst_grad, 1e-12) << name(b);   // gradients ~ 1 / h ~ 10: a few ulps of the terms
    EXPECT_LT(worst_x, 1e-14) << name(b);
    EXPECT_LT(worst_map, 1e-14) << name(b);
    EXPECT_LT(worst_id, 1e-13) << name(b);
    EXPECT_NEAR(vol, volume(b), 1e-13 * volume(b)) << name(b);
  }
}

// The basis kernel on the execution space: the same partition of unity, and the volume with
// the (p + 1)-point rule (exact on the box).
TEST(Basis3D, EvaluateBasisKernel) {
  for (const Block3& b : {box({2, 2, 2}, {3, 2, 2}), box({1, 3, 2}, {2, 2, 3}), shell(3, {2, 2, 1}, 2)}) {
    dispatch(3, pmax(b), [&](auto DD, auto PP) {   // the run-time (dim, p) to compile-time (D, P)
      constexpr int D = decltype(DD)::value, P = decltype(PP)::value;
      if constexpr (D == 3) {
        EvaluateBasisT<D, P> k;
        k.pd = patch_data<MemSpace>(b);
        for (int d = 0; d < 3; ++d) k.g[d] = gauss_rule(b.p[d] + 1);
        k.run(k.pd.num_elements());
        auto R = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), k.R);
        auto dR = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), k.dR);
        auto J = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), k.JxW);
        double worst_sum = 0, worst_grad = 0, vol = 0;
        for (size_t e = 0; e < R.extent(0); ++e)
          for (size_t q = 0; q < R.extent(1); ++q) {
            double s = 0, gsum[3] = {0, 0, 0};
            for (size_t a = 0; a < R.extent(2); ++a) {
              s += R(e, q, a);
              for (int c = 0; c < 3; ++c) gsum[c] += dR(e, q, a, c);
            }
            worst_sum = std::max(worst_sum, std::abs(s - 1));
            worst_grad = std::max({worst_grad, std::abs(gsum[0]), std::abs(gsum[1]), std::abs(gsum[2])});
            vol += J(e, q);
          }
        EXPECT_LT(worst_sum, 1e-14) << name(b);
        EXPECT_LT(worst_grad, 1e-12) << name(b);
        // the box: exact (round-off); the shell with the (p + 1)-point rule: the quadrature error of
        // the rational Jacobian, which 12 points remove (PartitionOfUnityGeometryAndVolume); the
        // 2-D annulus shows 3e-9 at p = 2 on 5 x 3 elements (test_kernels), so 1e-7 bounds it here
        EXPECT_NEAR(vol, volume(b), (b.curved ? 1e-7 : 1e-14) * volume(b)) << name(b);
        std::printf("  basis kernel: %s: |sum R - 1| %.1e, |sum grad R| %.1e, volume error %.1e\n", name(b).c_str(),
                    worst_sum, worst_grad, std::abs(vol - volume(b)) / volume(b));
      } else {
        ADD_FAILURE() << "dispatch(3, ..) called the D = " << D << " branch";
      }
    });
  }
}

// ---------------------------------------------------------------------------------------------
// The 3-D laws against the formulas written out (P = F S, S from E; neo-Hookean with F^-T).

void inverse3(const double A[3][3], double Ai[3][3], double& det) {
  det = A[0][0] * (A[1][1] * A[2][2] - A[1][2] * A[2][1]) - A[0][1] * (A[1][0] * A[2][2] - A[1][2] * A[2][0]) +
        A[0][2] * (A[1][0] * A[2][1] - A[1][1] * A[2][0]);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      // cofactor C_ji / det
      const int r0 = (j + 1) % 3, r1 = (j + 2) % 3, c0 = (i + 1) % 3, c1 = (i + 2) % 3;
      Ai[i][j] = (A[r0][c0] * A[r1][c1] - A[r0][c1] * A[r1][c0]) / det;
    }
}

void reference_P(const Material& m, const double H[3][3], double P[3][3]) {
  const double lam = m.lambda, mu = m.mu;
  double F[3][3];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) F[i][j] = H[i][j] + (i == j);
  if (m.model == Material::kLinear) {
    const double tr = H[0][0] + H[1][1] + H[2][2];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) P[i][j] = mu * (H[i][j] + H[j][i]) + (i == j ? lam * tr : 0.0);
  } else if (m.model == Material::kSaintVenantKirchhoff) {
    double E[3][3], S[3][3];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        E[i][j] = -0.5 * (i == j);
        for (int k = 0; k < 3; ++k) E[i][j] += 0.5 * F[k][i] * F[k][j];
      }
    const double tr = E[0][0] + E[1][1] + E[2][2];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) S[i][j] = 2 * mu * E[i][j] + (i == j ? lam * tr : 0.0);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        P[i][j] = 0;
        for (int k = 0; k < 3; ++k) P[i][j] += F[i][k] * S[k][j];
      }
  } else {
    double Fi[3][3], J;
    inverse3(F, Fi, J);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) P[i][j] = mu * (F[i][j] - Fi[j][i]) + lam * std::log(J) * Fi[j][i];
  }
}

const double kE = 1.0, kNu = 0.3;

TEST(Material3D, StressAndTangentAgainstFormulas) {
  const double H[3][3] = {{0.02, -0.013, 0.007}, {0.011, -0.017, 0.004}, {-0.006, 0.009, 0.025}};
  for (int model : {Material::kLinear, Material::kSaintVenantKirchhoff, Material::kNeoHookean}) {
    const Material m = Material::solid(model, kE, kNu);
    double P[3][3], Pr[3][3], P33, A[9][9];
    ASSERT_TRUE(material_response<true>(m, H, P, P33, A));
    reference_P(m, H, Pr);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) EXPECT_NEAR(P[i][j], Pr[i][j], 1e-15) << model;
    // A = dP/dF by central differences, h = 1e-6: error h^2 |P'''| + eps |P| / h ~ 1e-10
    const double h = 1e-6;
    double worst = 0;
    for (int k = 0; k < 3; ++k)
      for (int L = 0; L < 3; ++L) {
        double Hp[3][3], Hm[3][3], Pp[3][3], Pm[3][3];
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j) Hp[i][j] = Hm[i][j] = H[i][j];
        Hp[k][L] += h;
        Hm[k][L] -= h;
        reference_P(m, Hp, Pp);
        reference_P(m, Hm, Pm);
        for (int i = 0; i < 3; ++i)
          for (int J = 0; J < 3; ++J)
            worst = std::max(worst, std::abs(A[3 * i + J][3 * k + L] - (Pp[i][J] - Pm[i][J]) / (2 * h)));
      }
    EXPECT_LT(worst, 1e-8) << model;
    // major symmetry A_iJkL = A_kLiJ (hyperelastic)
    for (int r = 0; r < 9; ++r)
      for (int c = 0; c < 9; ++c) EXPECT_NEAR(A[r][c], A[c][r], 1e-15) << model;
  }
  // neo-Hookean: a folded point gives NaN and false
  const double fold[3][3] = {{-2, 0, 0}, {0, 0, 0}, {0, 0, 0}};
  double P[3][3], P33, A[9][9];
  EXPECT_FALSE(material_response<true>(Material::solid(Material::kNeoHookean, kE, kNu), fold, P, P33, A));
  EXPECT_TRUE(std::isnan(P[0][0]));
}

// ---------------------------------------------------------------------------------------------

// Residual f (3 n) and, when K is given, the dense tangent (3 n x 3 n) summed from the element
// functions on the host, at control-point displacements u (3 n).
template <int P, bool Tangent>
void assemble_host(const HostPatchData3& pd, const Material& m, const GaussRule* const g[3], const std::vector<double>& u,
                   std::vector<double>& f, std::vector<double>* K) {
  const int n = static_cast<int>(pd.cp.extent(0));
  constexpr int MaxDof = 3 * kNen<3, P>;
  f.assign(3 * n, 0.0);
  if (K) K->assign(static_cast<size_t>(3 * n) * 3 * n, 0.0);
  std::vector<double> Ke(Tangent ? MaxDof * MaxDof : 1), fe(MaxDof);
  std::vector<std::array<double, 3>> ue(kNen<3, P>);
  std::vector<int> cps(kNen<3, P>);
  const int nen = pd.nen();
  for (int e = 0; e < pd.num_elements(); ++e) {
    for (int a = 0; a < nen; ++a) {
      cps[a] = element_cp(pd, e, a);
      for (int c = 0; c < 3; ++c) ue[a][c] = u[3 * cps[a] + c];
    }
    const auto* uep = reinterpret_cast<const double(*)[3]>(ue.data());
    ASSERT_TRUE((element_internal<P, true, Tangent>(pd, m, g, e, uep, fe.data(), Ke.data(), MaxDof)));
    for (int r = 0; r < 3 * nen; ++r) {
      const int R = 3 * cps[r / 3] + r % 3;
      f[R] += fe[r];
      if (Tangent && K)
        for (int c = 0; c < 3 * nen; ++c) (*K)[static_cast<size_t>(R) * 3 * n + 3 * cps[c / 3] + c % 3] += Ke[r * MaxDof + c];
    }
  }
}

TEST(PatchTest3D, LinearFieldGivesConstantStressAndBalancedInteriorRows) {
  const double G[3][3] = {{0.010, 0.004, -0.002}, {-0.003, 0.006, 0.005}, {0.002, -0.001, -0.008}};
  const double c0[3] = {0.1, -0.2, 0.05};
  for (const Block3& b : geometries(false)) {
    const HostPatchData3 pd = patch_data<Kokkos::HostSpace>(b);
    const int n = static_cast<int>(b.cp.size());
    std::vector<double> u(3 * n);
    for (int a = 0; a < n; ++a)
      for (int i = 0; i < 3; ++i)
        u[3 * a + i] = c0[i] + G[i][0] * b.cp[a][0] + G[i][1] * b.cp[a][1] + G[i][2] * b.cp[a][2];
    // the box: (p + 1)-point Gauss integrates the polynomial integrand exactly. The shell:
    // the integrand is rational; 12 points make the quadrature error negligible beside round-off
    GaussRule gr[3];
    for (int d = 0; d < 3; ++d) gr[d] = gauss_rule(b.curved ? 12 : b.p[d] + 1);
    const GaussRule* g[3] = {&gr[0], &gr[1], &gr[2]};
    for (int model : {Material::kLinear, Material::kSaintVenantKirchhoff, Material::kNeoHookean}) {
      const Material m = Material::solid(model, kE, kNu);
      double Pref[3][3];
      reference_P(m, G, Pref);
      std::vector<double> f;
      double worst_H = 0, worst_P = 0, fmax = 0, worst_row = 0;
      for_degree(pmax(b), [&](auto PP) {
        constexpr int P = decltype(PP)::value;
        // Grad u and the stress at sample points of every element
        double R[kNen<3, P>], dR[kNen<3, P>][3], x[3];
        for (int e = 0; e < pd.num_elements(); ++e) {
          int ei[3], s[3];
          pd.element_spans(e, ei, s);
          for (int q = 0; q < 3; ++q) {
            double xi[3];
            for (int d = 0; d < 3; ++d) xi[d] = b.U[d][s[d]] + (0.2 + 0.3 * q + 0.05 * d) * (b.U[d][s[d] + 1] - b.U[d][s[d]]);
            nurbs_grad<P>(pd, s, xi, R, dR, x);
            double Hq[3][3] = {}, Pq[3][3], P33;
            for (int a = 0; a < pd.nen(); ++a) {
              const int cp = pd.local_cp(s, a);
              for (int i = 0; i < 3; ++i)
                for (int J = 0; J < 3; ++J) Hq[i][J] += u[3 * cp + i] * dR[a][J];
            }
            material_response<false>(m, Hq, Pq, P33, nullptr);
            for (int i = 0; i < 3; ++i)
              for (int J = 0; J < 3; ++J) {
                worst_H = std::max(worst_H, std::abs(Hq[i][J] - G[i][J]));
                worst_P = std::max(worst_P, std::abs(Pq[i][J] - Pref[i][J]));
              }
          }
        }
        assemble_host<P, false>(pd, m, g, u, f, nullptr);
      });
      for (int a = 0; a < n; ++a)
        for (int i = 0; i < 3; ++i) {
          fmax = std::max(fmax, std::abs(f[3 * a + i]));
          if (!on_boundary(b, a)) worst_row = std::max(worst_row, std::abs(f[3 * a + i]));
        }
      // u is O(1) with O(1) coordinates: Grad u = G to round-off of sums of ~ nen terms of size ~ 10
      EXPECT_LT(worst_H, 1e-13) << name(b) << " model " << model;
      EXPECT_LT(worst_P, 1e-14) << name(b) << " model " << model;
      // interior rows: sums of nq x nen-element contributions of size ~ fmax
      EXPECT_LT(worst_row, 1e-12 * fmax) << name(b) << " model " << model << " |f|max " << fmax;
      EXPECT_GT(fmax, 1e-4) << name(b);   // the boundary rows carry the tractions
      std::printf("  patch test: %s model %d: |H - G| %.1e, |P - P(G)| %.1e, interior rows / max |f| %.1e\n", name(b).c_str(),
                  model, worst_H, worst_P, worst_row / fmax);
    }
  }
}

// ---------------------------------------------------------------------------------------------

// Element e's force and tangent at ue, with (p + 1)-point Gauss.
template <int P>
void element_fk(const HostPatchData3& pd, const Material& m, int e, const std::vector<double>& ue, std::vector<double>& fe,
                std::vector<double>* Ke) {
  constexpr int MaxDof = 3 * kNen<3, P>;
  GaussRule gr[3];
  for (int d = 0; d < 3; ++d) gr[d] = gauss_rule(pd.p[d] + 1);
  const GaussRule* g[3] = {&gr[0], &gr[1], &gr[2]};
  fe.assign(MaxDof, 0.0);
  std::vector<double> K(MaxDof * MaxDof);
  const auto* up = reinterpret_cast<const double(*)[3]>(ue.data());
  if (Ke) element_internal<P, true, true>(pd, m, g, e, up, fe.data(), K.data(), MaxDof);
  else element_internal<P, true, false>(pd, m, g, e, up, fe.data(), nullptr, MaxDof);
  if (Ke) {
    const int nd = 3 * pd.nen();
    Ke->assign(nd * nd, 0.0);
    for (int r = 0; r < nd; ++r)
      for (int c = 0; c < nd; ++c) (*Ke)[r * nd + c] = K[r * MaxDof + c];
  }
}

TEST(Tangent3D, AgainstCentralDifferencesOfTheResidual) {
  for (const Block3& b : {box({1, 1, 1}, {1, 1, 1}), box({1, 3, 2}, {2, 1, 1}), shell(2, {2, 1, 1}, 2)}) {
    const HostPatchData3 pd = patch_data<Kokkos::HostSpace>(b);
    for (int model : {Material::kLinear, Material::kSaintVenantKirchhoff, Material::kNeoHookean}) {
      const Material m = Material::solid(model, kE, kNu);
      for_degree(pmax(b), [&](auto PP) {
        constexpr int P = decltype(PP)::value;
        const int e = pd.num_elements() - 1, nd = 3 * pd.nen();
        std::vector<double> ue(nd), f, fp, fm, K;
        for (int r = 0; r < nd; ++r) ue[r] = 0.05 * std::sin(1.3 * r + 0.7 * model);   // strains ~ 5 %
        element_fk<P>(pd, m, e, ue, f, &K);
        double Kmax = 0;
        for (double v : K) Kmax = std::max(Kmax, std::abs(v));
        // central differences at h and h/2: the error is c h^2 (+ round-off eps |f| / h ~ 1e-12 |K|)
        double err[2] = {0, 0};
        for (int t = 0; t < 2; ++t) {
          const double h = t == 0 ? 1e-3 : 5e-4;
          for (int j = 0; j < nd; ++j) {
            auto up = ue, um = ue;
            up[j] += h;
            um[j] -= h;
            element_fk<P>(pd, m, e, up, fp, nullptr);
            element_fk<P>(pd, m, e, um, fm, nullptr);
            for (int r = 0; r < nd; ++r) err[t] = std::max(err[t], std::abs(K[r * nd + j] - (fp[r] - fm[r]) / (2 * h)));
          }
        }
        std::printf("  FD: %s model %d: max |K - FD| / max |K| = %.1e (h = 1e-3), %.1e (h = 5e-4)\n", name(b).c_str(), model,
                    err[0] / Kmax, err[1] / Kmax);
        if (model == Material::kLinear) {
          // f is linear in u: the difference quotient is exact up to round-off
          EXPECT_LT(err[0], 1e-10 * Kmax) << name(b);
        } else {
          EXPECT_LT(err[0], 1e-4 * Kmax) << name(b) << " model " << model;
          // O(h^2): halving h divides the error by ~ 4
          EXPECT_GT(err[0] / err[1], 3.5) << name(b) << " model " << model << " errors " << err[0] << " " << err[1];
          EXPECT_LT(err[0] / err[1], 4.5) << name(b) << " model " << model;
        }
        // the tangent of a hyperelastic law is symmetric (blocks a < b mirrored exactly; the
        // diagonal blocks computed both ways: round-off)
        for (int r = 0; r < nd; ++r)
          for (int c = 0; c < nd; ++c) ASSERT_NEAR(K[r * nd + c], K[c * nd + r], 1e-15 * Kmax);
      });
    }
  }
}

// Eigenvalues of a symmetric matrix (cyclic Jacobi).
std::vector<double> eigenvalues(std::vector<double> A, int n) {
  for (int sweep = 0; sweep < 100; ++sweep) {
    double off = 0, diag = 0;
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) (i == j ? diag : off) += A[i * n + j] * A[i * n + j];
    if (off < 1e-30 * diag) break;
    for (int p = 0; p < n; ++p)
      for (int q = p + 1; q < n; ++q) {
        const double apq = A[p * n + q];
        if (std::abs(apq) < 1e-300) continue;
        const double theta = (A[q * n + q] - A[p * n + p]) / (2 * apq);
        const double t = (theta >= 0 ? 1 : -1) / (std::abs(theta) + std::sqrt(theta * theta + 1));
        const double c = 1 / std::sqrt(t * t + 1), s = t * c;
        for (int k = 0; k < n; ++k) {
          const double akp = A[k * n + p], akq = A[k * n + q];
          A[k * n + p] = c * akp - s * akq;
          A[k * n + q] = s * akp + c * akq;
        }
        for (int k = 0; k < n; ++k) {
          const double apk = A[p * n + k], aqk = A[q * n + k];
          A[p * n + k] = c * apk - s * aqk;
          A[q * n + k] = s * apk + c * aqk;
        }
      }
  }
  std::vector<double> ev(n);
  for (int i = 0; i < n; ++i) ev[i] = A[i * n + i];
  std::sort(ev.begin(), ev.end());
  return ev;
}

TEST(Tangent3D, SymmetricWithExactlySixRigidBodyModes) {
  // small strain at u = 0 (every model's tangent there is the linear stiffness)
  for (const Block3& b : {box({1, 1, 1}, {1, 1, 1}), box({2, 1, 1}, {1, 2, 1}), shell(2, {1, 1, 1}, 1), shell(2, {2, 1, 1}, 2)}) {
    const HostPatchData3 pd = patch_data<Kokkos::HostSpace>(b);
    const int n = static_cast<int>(b.cp.size()), N = 3 * n;
    for (int model : {Material::kLinear, Material::kNeoHookean}) {
      const Material m = Material::solid(model, kE, kNu);
      std::vector<double> f, K, u(N, 0.0);
      GaussRule gr[3];
      for (int d = 0; d < 3; ++d) gr[d] = gauss_rule(b.p[d] + 1);
      const GaussRule* g[3] = {&gr[0], &gr[1], &gr[2]};
      for_degree(pmax(b), [&](auto PP) { assemble_host<decltype(PP)::value, true>(pd, m, g, u, f, &K); });
      double Kmax = 0;
      for (double v : K) Kmax = std::max(Kmax, std::abs(v));
      for (int r = 0; r < N; ++r)
        for (int c = 0; c < N; ++c) ASSERT_NEAR(K[r * N + c], K[c * N + r], 1e-15 * Kmax) << name(b);
      // the six rigid-body modes: translations e_c and rotations omega x x_a
      double worst = 0;
      for (int mode = 0; mode < 6; ++mode) {
        std::vector<double> r(N, 0.0);
        for (int a = 0; a < n; ++a) {
          if (mode < 3) r[3 * a + mode] = 1.0;
          else {
            const int k = mode - 3, i = (k + 1) % 3, j = (k + 2) % 3;   // rotation about axis k
            r[3 * a + i] = -b.cp[a][j];
            r[3 * a + j] = b.cp[a][i];
          }
        }
        double rmax = 0;
        for (double v : r) rmax = std::max(rmax, std::abs(v));
        for (int row = 0; row < N; ++row) {
          double s = 0;
          for (int c = 0; c < N; ++c) s += K[row * N + c] * r[c];
          worst = std::max(worst, std::abs(s) / (Kmax * rmax));
        }
      }
      EXPECT_LT(worst, 1e-13) << name(b) << " model " << model;
      // no other zero-energy mode: 6 eigenvalues at round-off, the 7th well above
      const auto ev = eigenvalues(K, N);
      const double emax = ev.back();
      for (int i = 0; i < 6; ++i) EXPECT_LT(std::abs(ev[i]), 1e-12 * emax) << name(b) << " eigenvalue " << i;
      EXPECT_GT(ev[6], 1e-4 * emax) << name(b);
      EXPECT_GT(ev[0], -1e-12 * emax) << name(b);   // positive semi-definite
      std::printf("  rigid modes: %s model %d: |K r| %.1e, eigenvalues / max: %.1e .. %.1e, 7th %.1e\n", name(b).c_str(), model,
                  worst, ev[0] / emax, ev[5] / emax, ev[6] / emax);
    }
  }
}

// ---------------------------------------------------------------------------------------------

template <int P>
void check_assembly(const Block3& b, const Material& m, int batch, bool sum_factorized = false) {
  const HostPatchData3 hpd = patch_data<Kokkos::HostSpace>(b);
  const int n = static_cast<int>(b.cp.size()), N = 3 * n;
  std::vector<double> u(N);
  for (int r = 0; r < N; ++r) u[r] = 0.02 * std::cos(0.37 * r);
  GaussRule gr[3];
  for (int d = 0; d < 3; ++d) gr[d] = gauss_rule(b.p[d] + 1);
  const GaussRule* g[3] = {&gr[0], &gr[1], &gr[2]};
  std::vector<double> fref, Kref;
  assemble_host<P, true>(hpd, m, g, u, fref, &Kref);

  Crs K = make_matrix(hpd);
  AssembleInternalT<3, P, Crs> k{patch_data<MemSpace>(b), m, {gr[0], gr[1], gr[2]}, 0};
  k.scatter.A = K;
  k.scatter.sorted_A = true;
  k.u = to_view<double, MemSpace>("u", u);
  k.f = Kokkos::View<double*, MemSpace>("f", N);
  k.force = k.tangent = true;
  k.batch_elements = batch;
  k.sum_factorized = sum_factorized;
  k.run(hpd.num_elements());
  Kokkos::fence();
  auto f = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), k.f);
  auto rm = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), K.graph.row_map);
  auto en = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), K.graph.entries);
  auto val = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), K.values);
  double fmax = 0, Kmax = 0, df = 0, dK = 0;
  for (int r = 0; r < N; ++r) {
    fmax = std::max(fmax, std::abs(fref[r]));
    df = std::max(df, std::abs(f(r) - fref[r]));
  }
  std::vector<double> dense(static_cast<size_t>(N) * N, 0.0);
  for (int r = 0; r < N; ++r)
    for (size_t q = rm(r); q < rm(r + 1); ++q) dense[static_cast<size_t>(r) * N + en(q)] = val(q);
  for (size_t i = 0; i < dense.size(); ++i) {
    Kmax = std::max(Kmax, std::abs(Kref[i]));
    dK = std::max(dK, std::abs(dense[i] - Kref[i]));
  }
  // the same element functions summed in another order: round-off of a few terms
  EXPECT_LT(df, 1e-14 * fmax) << name(b) << " batch " << batch;
  // the sum-factorised tangent sums the same products in another order: ~ nq nen eps
  EXPECT_LT(dK, (sum_factorized ? 1e-13 : 1e-14) * Kmax) << name(b) << " batch " << batch << " sf " << sum_factorized;
}

TEST(Assembly3D, KernelEqualsSumOfElementMatrices) {
  const Material nh = Material::solid(Material::kNeoHookean, kE, kNu);
  const Material lin = Material::solid(Material::kLinear, kE, kNu);
  check_assembly<1>(box({1, 1, 1}, {3, 2, 2}), lin, 0);
  check_assembly<2>(box({2, 2, 2}, {2, 2, 2}), nh, 0);
  check_assembly<2>(box({2, 2, 2}, {2, 2, 2}), nh, 3);   // batches of 3 elements through the work view
  check_assembly<3>(shell(3, {2, 1, 1}, 2), nh, 1);
  check_assembly<2>(box({2, 2, 2}, {2, 2, 2}), nh, 3, true);
  check_assembly<3>(shell(3, {2, 1, 1}, 2), nh, 0, true);
}

// The element-wise sum-factorised tangent (kernels/elasticity_sf3.hpp) equals the element loop's
// to round-off: both sum the same products over the same points, in another order.
TEST(SumFactorized3D, EqualsElementTangent) {
  std::vector<Block3> gs = geometries();
  gs.push_back(shell(4, {1, 1, 1}, 1));
  gs.push_back(box({1, 4, 2}, {1, 1, 2}));
  for (const Block3& b : gs) {
    const HostPatchData3 pd = patch_data<Kokkos::HostSpace>(b);
    for (int model : {Material::kLinear, Material::kSaintVenantKirchhoff, Material::kNeoHookean}) {
      const Material m = Material::solid(model, kE, kNu);
      for_degree(pmax(b), [&](auto PP) {
        constexpr int P = decltype(PP)::value;
        constexpr int MaxDof = 3 * kNen<3, P>;
        GaussRule gr[3];
        for (int d = 0; d < 3; ++d) gr[d] = gauss_rule(b.p[d] + 1);
        const GaussRule* g[3] = {&gr[0], &gr[1], &gr[2]};
        int nq[3] = {gr[0].n, gr[1].n, gr[2].n};
        std::vector<double> K1(MaxDof * MaxDof), K2(MaxDof * MaxDof), work(sf3_work_size(nq));
        std::vector<std::array<double, 3>> ue(kNen<3, P>);
        double worst = 0, Kmax = 0;
        for (int e = 0; e < pd.num_elements(); ++e) {
          for (int a = 0; a < pd.nen(); ++a)
            for (int c = 0; c < 3; ++c) ue[a][c] = model == Material::kLinear ? 0.0 : 0.05 * std::sin(1.1 * a + 2.3 * c + e);
          const auto* up = reinterpret_cast<const double(*)[3]>(ue.data());
          ASSERT_TRUE((element_internal<P, false, true>(pd, m, g, e, up, nullptr, K1.data(), MaxDof)));
          ASSERT_TRUE((element_tangent_sf3<P>(pd, m, g, e, up, K2.data(), MaxDof, work.data())));
          const int nd = 3 * pd.nen();
          for (int r = 0; r < nd; ++r)
            for (int c = 0; c < nd; ++c) {
              Kmax = std::max(Kmax, std::abs(K1[r * MaxDof + c]));
              worst = std::max(worst, std::abs(K1[r * MaxDof + c] - K2[r * MaxDof + c]));
            }
        }
        EXPECT_LT(worst, 1e-13 * Kmax) << name(b) << " model " << model;
        std::printf("  sum-factorised: %s model %d: max |K_sf - K| / max |K| = %.1e\n", name(b).c_str(), model, worst / Kmax);
      });
    }
  }
}

}  // namespace
