// Verification of plane elasticity against closed-form solutions
// (../shared/reference-solutions.md): patch test, Lame cylinder rates, Kirsch plate, balance.
#include <gtest/gtest.h>

#include <cmath>

#include "support.hpp"

using namespace iga;
using namespace iga::test;

namespace {

// --- Lame: thick-walled cylinder, a = 1, b = 2, p = 10, E = 2e5, nu = 0.3, plane strain ---
constexpr double kA = 1.0, kB = 2.0, kP = 10.0, kE = 2.0e5, kNu = 0.3;

Exact lame_exact() { return lame_cylinder(kA, kB, kP, kE, kNu); }

std::string lame_yaml(int elevate_xi, int elevate_eta, int n) {
  std::ostringstream os;
  os << "bodies:\n  - name: cyl\n    material: {youngs_modulus: " << kE << ", poisson_ratio: " << kNu << "}\n"
     << "    geometry: {quarter_annulus: {center: [0, 0], inner_radius: " << kA << ", outer_radius: " << kB << "}}\n"
     << "    refine: {degree_elevate: [" << elevate_xi << ", " << elevate_eta << "], subdivide: [" << n << ", " << n << "]}\n"
     << "    boundary:\n      west: {displacement: {y: 0}}\n      east: {displacement: {x: 0}}\n      south: {pressure: " << kP << "}\n"
     << "solver: {linear: {method: cg, preconditioner: muelu, tolerance: 1.0e-13}}\n";
  return os.str();
}

double rate(double e_coarse, double e_fine) { return std::log2(e_coarse / e_fine); }

}  // namespace

TEST(ReferenceSolutions, LameAndKirschSatisfyHookeAndEquilibrium) {
  // the closed forms used below are themselves checked: stresses from the displacement
  // gradient by Hooke's law, and div sigma = 0, by central differences
  const Exact lame = lame_exact();
  const double h = 1e-5, lam = kE * kNu / ((1 + kNu) * (1 - 2 * kNu)), mu = kE / (2 * (1 + kNu));
  for (double r : {1.2, 1.5, 1.9})
    for (double t : {0.2, 0.7, 1.3}) {
      const double x = r * std::cos(t), y = r * std::sin(t);
      const auto ux1 = lame.u(x + h, y), ux0 = lame.u(x - h, y), uy1 = lame.u(x, y + h), uy0 = lame.u(x, y - h);
      const double exx = (ux1[0] - ux0[0]) / (2 * h), eyy = (uy1[1] - uy0[1]) / (2 * h);
      const double gxy = (uy1[0] - uy0[0]) / (2 * h) + (ux1[1] - ux0[1]) / (2 * h);
      const auto s = lame.sigma(x, y);
      EXPECT_NEAR(s[0], (lam + 2 * mu) * exx + lam * eyy, 1e-5 * kP);
      EXPECT_NEAR(s[1], lam * exx + (lam + 2 * mu) * eyy, 1e-5 * kP);
      EXPECT_NEAR(s[2], mu * gxy, 1e-5 * kP);
      const double div_x = (lame.sigma(x + h, y)[0] - lame.sigma(x - h, y)[0] + lame.sigma(x, y + h)[2] - lame.sigma(x, y - h)[2]) / (2 * h);
      const double div_y = (lame.sigma(x + h, y)[2] - lame.sigma(x - h, y)[2] + lame.sigma(x, y + h)[1] - lame.sigma(x, y - h)[1]) / (2 * h);
      EXPECT_NEAR(div_x, 0.0, 1e-4 * kP);
      EXPECT_NEAR(div_y, 0.0, 1e-4 * kP);
    }
}

// Constant stress through a distorted control net with non-uniform knots. The geometry map
// is polynomial (unit weights): then adj(J) grad N is a polynomial of degree <= 2p per
// direction and the (p+1)-point Gauss rule integrates the stiffness exactly, so the linear
// field must come out to round-off. (With non-constant weights the rational gradients are not
// integrated exactly and the patch test only holds to quadrature accuracy, ~1e-4 here.)
TEST(PatchTest, LinearDisplacementIsExactOnDistortedNurbsPatch) {
  for (int p = 1; p <= 4; ++p) {
    const Patch P = distorted_patch(p, 3 + p, false);
    const Solved s = solve_text(patch_yaml(P));
    ASSERT_TRUE(s.res.converged);
    if (Tpetra::getDefaultComm()->getRank() != 0) continue;
    const double E = 1000, nu = 0.3, sxx = 10, syy = 5;
    const double exx = ((1 - nu * nu) * sxx - nu * (1 + nu) * syy) / E;
    const double eyy = ((1 - nu * nu) * syy - nu * (1 + nu) * sxx) / E;
    BodyField f(s.P, 0, s.disp[0]);
    for (int i = 0; i <= 10; ++i)
      for (int j = 0; j <= 10; ++j) {
        const FieldPoint q = f.eval(i / 10.0, j / 10.0);
        EXPECT_NEAR(q.ux, exx * q.x, 1e-10 * exx * 2) << "p = " << p;
        EXPECT_NEAR(q.uy, eyy * q.y, 1e-10 * std::abs(eyy) * 2) << "p = " << p;
        EXPECT_NEAR(q.sxx, sxx, 1e-9 * sxx) << "p = " << p;
        EXPECT_NEAR(q.syy, syy, 1e-9 * sxx) << "p = " << p;
        EXPECT_NEAR(q.sxy, 0.0, 1e-9 * sxx) << "p = " << p;
      }
  }
}

// The same constant stress on a triangle made as a patch with a collapsed edge (the two
// north control points coincide, and stay so under refinement): the elements at that edge
// are slivers and the control points there coincide. Uniaxial stress sxx = s, plane stress:
// symmetry on the legs (west u_x = 0, south u_y = 0), traction (s / sqrt 2, 0) = sigma n on the
// hypotenuse. The affine solution u = (s x / E, -nu s y / E) is in the NURBS space, so it comes
// out to the solver's tolerance; it also checks that MueLu's aggregation (distance Laplacian
// of the control points) copes with coincident points, on enough dofs for several levels.
TEST(PatchTest, UniaxialStressIsExactOnPatchWithCollapsedEdge) {
  const double E = 1000, nu = 0.3, sxx = 10;
  std::ostringstream os;
  os.precision(17);
  os << "analysis: {type: plane_stress}\n"
     << "bodies:\n  - name: wedge\n    material: {youngs_modulus: " << E << ", poisson_ratio: " << nu << "}\n"
     << "    geometry: {nurbs: {degree: [1, 1], knots: [[0, 0, 1, 1], [0, 0, 1, 1]],\n"
     << "               control_points: [[0, 0, 1], [1, 0, 1], [0, 1, 1], [0, 1, 1]]}}\n"
     << "    refine: {degree_elevate: 1, subdivide: [40, 40]}\n"
     << "    boundary:\n      west: {displacement: {x: 0}}\n      south: {displacement: {y: 0}}\n"
     << "      east: {traction: [" << sxx / std::sqrt(2.0) << ", 0]}\n"
     << "solver: {linear: {method: cg, preconditioner: muelu, tolerance: 1.0e-12}}\n";
  const Solved s = solve_text(os.str());
  ASSERT_TRUE(s.res.converged) << s.res.message;
  std::printf("  collapsed edge: %lld dofs, %d CG iterations\n", static_cast<long long>(s.sys->num_dofs()),
              s.res.linear_iterations);
  if (Tpetra::getDefaultComm()->getRank() != 0) return;
  BodyField f(s.P, 0, s.disp[0]);
  const double umax = sxx / E;
  for (int i = 0; i <= 10; ++i)
    for (int j = 0; j <= 9; ++j) {   // eta = 1 is the collapsed edge (singular Jacobian)
      const FieldPoint q = f.eval(i / 10.0, j / 10.0);
      EXPECT_NEAR(q.ux, sxx / E * q.x, 1e-9 * umax) << q.x << ", " << q.y;
      EXPECT_NEAR(q.uy, -nu * sxx / E * q.y, 1e-9 * umax) << q.x << ", " << q.y;
    }
}

class LameDegree : public ::testing::TestWithParam<int> {};

// Displacement L2 error ~ h^(p+1), stress ~ h^p, on the exact quarter annulus.
TEST_P(LameDegree, ConvergesAtOptimalRates) {
  const int p = GetParam();
  std::vector<Errors> errs;
  for (int n : {2, 4, 8, 16}) {
    const Solved s = solve_text(lame_yaml(p - 2, p - 1, n));
    ASSERT_TRUE(s.res.converged);
    if (Tpetra::getDefaultComm()->getRank() == 0) errs.push_back(l2_errors(s, 0, lame_exact()));
  }
  if (errs.empty()) return;
  for (size_t k = 0; k < errs.size(); ++k)
    std::printf("  p = %d  n = %2d  |u - uh|/|u| = %.3e  |s - sh|/|s| = %.3e\n", p, 2 << k, errs[k].u_rel, errs[k].s_rel);
  const double ru = rate(errs[2].u_rel, errs[3].u_rel), rs = rate(errs[2].s_rel, errs[3].s_rel);
  std::printf("  rates (8 -> 16): displacement %.2f (expect %d), stress %.2f (expect %d)\n", ru, p + 1, rs, p);
  EXPECT_GT(ru, p + 1 - 0.3);
  EXPECT_GT(rs, p - 0.3);
}

INSTANTIATE_TEST_SUITE_P(Degrees, LameDegree, ::testing::Values(2, 3));

TEST(Equilibrium, ReactionsBalanceAppliedLoads) {
  const Solved s = solve_text(lame_yaml(1, 2, 8));
  const auto F = total_load(*s.sys);
  const auto R = total_reaction(*s.sys, *s.res.residual);
  const double scale = std::hypot(F[0], F[1]);
  EXPECT_NEAR(F[0] + R[0], 0.0, 1e-10 * scale);
  EXPECT_NEAR(F[1] + R[1], 0.0, 1e-10 * scale);
  // the exact resultant of the pressure on the quarter arc is (p a, p a)
  EXPECT_NEAR(F[0], kP * kA, 1e-12 * kP);
  EXPECT_NEAR(F[1], kP * kA, 1e-12 * kP);
}

// --- Kirsch: infinite plate with a circular hole, a = 1, L = 4, T = 10 (Hughes et al. 2005) ---
namespace {
constexpr double kT = 10.0, kR = 1.0;
Exact kirsch_exact(double E, double nu) { return kirsch_plate(kR, kT, E, nu); }

// The quarter plate of Hughes, Cottrell & Bazilevs (2005), x in [-4, 0], y in [0, 4].
std::string kirsch_yaml(int n, int elevate) {
  const double w = (1 + 1 / std::sqrt(2.0)) / 2;
  std::ostringstream os;
  os.precision(17);
  os << "bodies:\n  - name: plate\n    material: {youngs_modulus: 1.0e5, poisson_ratio: 0.3}\n    geometry:\n      nurbs:\n"
     << "        degree: [2, 2]\n        knots: [[0, 0, 0, 0.5, 1, 1, 1], [0, 0, 0, 1, 1, 1]]\n        control_points:\n"
     << "          - [-1, 0, 1]\n          - [-1, " << std::sqrt(2.0) - 1 << ", " << w << "]\n"
     << "          - [" << 1 - std::sqrt(2.0) << ", 1, " << w << "]\n          - [0, 1, 1]\n"
     << "          - [-2.5, 0, 1]\n          - [-2.5, 0.75, 1]\n          - [-0.75, 2.5, 1]\n          - [0, 2.5, 1]\n"
     << "          - [-4, 0, 1]\n          - [-4, 4, 1]\n          - [-4, 4, 1]\n          - [0, 4, 1]\n"
     << "    refine: {degree_elevate: " << elevate << ", subdivide: [" << n << ", " << n << "]}\n"
     << "    boundary:\n      west: {displacement: {y: 0}}\n      east: {displacement: {x: 0}}\n"
     << "solver: {linear: {method: cg, preconditioner: muelu, tolerance: 1.0e-13}}\n";
  return os.str();
}
}  // namespace

TEST(Kirsch, StressErrorFallsUnderRefinement) {
  const Exact ex = kirsch_exact(1.0e5, 0.3);
  std::vector<Errors> errs;
  for (int n : {2, 4, 8, 16}) {
    const Solved s = solve_text(kirsch_yaml(n, 0), Tpetra::getDefaultComm(), [&](System& sys) {
      // exact tractions on the outer edges x = -4 (normal -x) and y = 4 (normal +y)
      sys.add_traction(0, Side::North, [&](double x, double y) {
        const auto sg = ex.sigma(x, y);
        if (std::abs(x + 4) < 1e-9 && y < 4 - 1e-9) return std::array<double, 2>{-sg[0], -sg[2]};
        return std::array<double, 2>{sg[2], sg[1]};
      });
    });
    ASSERT_TRUE(s.res.converged);
    if (Tpetra::getDefaultComm()->getRank() == 0) errs.push_back(l2_errors(s, 0, ex, 3));
  }
  if (errs.empty()) return;
  for (size_t k = 0; k < errs.size(); ++k)
    std::printf("  Kirsch p = 2  n = %2d  |u - uh|/|u| = %.3e  |s - sh|/|s| = %.3e\n", 2 << k, errs[k].u_rel, errs[k].s_rel);
  // pre-asymptotic on the coarsest mesh (2 x 2 elements across a hole); from n = 4 on the
  // error falls at the rate h^p of the stress for p = 2
  for (size_t k = 2; k < errs.size(); ++k) EXPECT_LT(errs[k].s_rel, 0.5 * errs[k - 1].s_rel);
  EXPECT_GT(rate(errs[2].s_rel, errs[3].s_rel), 1.7);
  EXPECT_GT(rate(errs[2].u_rel, errs[3].u_rel), 2.7);   // displacement ~ h^(p+1)
}
