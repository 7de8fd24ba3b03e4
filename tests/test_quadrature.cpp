// Quadrature rules for spline spaces (model/quadrature.hpp, solver.quadrature: spline):
//  - the generalised Gaussian rule integrates its whole target space (degree 2p, continuity
//    p - m - 1 at a knot of multiplicity m) on uniform, graded and repeated-knot vectors,
//    with about (p + 2) / 2 nodes per element (p >= 2);
//  - with it the assembled stiffness of B-spline patches with an affine map equals the Gauss
//    one to round-off, the patch test holds, and on curved NURBS (Lame cylinder, rational,
//    where neither rule is exact) the convergence rates stay optimal at p = 2..5.
#include <gtest/gtest.h>
#include <Tpetra_Core.hpp>

#include <cmath>
#include <sstream>

#include "model/quadrature.hpp"
#include "solver/newton.hpp"
#include "solver/system.hpp"
#include "support.hpp"

using namespace iga;

namespace {

std::vector<double> knots(int p, const std::vector<double>& interior) {
  std::vector<double> U(p + 1, 0.0);
  U.insert(U.end(), interior.begin(), interior.end());
  U.insert(U.end(), p + 1, 1.0);
  return U;
}

std::vector<double> uniform(int ne) {
  std::vector<double> v;
  for (int k = 1; k < ne; ++k) v.push_back(static_cast<double>(k) / ne);
  return v;
}

// The target space of the rule for U (degree p), built as the rule's documentation says, and
// the largest relative error of the rule over its B-splines.
double moment_error(const SplineRule& r, const std::vector<double>& U, int p) {
  const int d = 2 * p;
  std::vector<double> T(d + 1, U.front());
  for (size_t k = p + 1; k < U.size() - p - 1;) {
    size_t m = 1;
    while (k + m < U.size() - p - 1 && U[k + m] == U[k]) ++m;
    T.insert(T.end(), std::min<size_t>(d + 1, p + m + 1), U[k]);
    k += m;
  }
  T.insert(T.end(), d + 1, U.back());
  const int N = static_cast<int>(T.size()) - d - 1;
  std::vector<double> sum(N, 0.0);
  for (size_t j = 0; j < r.x.size(); ++j) {
    int s = static_cast<int>(std::upper_bound(T.begin(), T.end(), r.x[j]) - T.begin()) - 1;
    s = std::min(std::max(s, d), N - 1);
    double Nv[16];
    host_bspline(T, d, s, r.x[j], Nv, nullptr);
    for (int q = 0; q <= d; ++q) sum[s - d + q] += r.w[j] * Nv[q];
  }
  double e = 0;
  for (int i = 0; i < N; ++i) e = std::max(e, std::abs(sum[i] - (T[i + d + 1] - T[i]) / (d + 1)) / ((T[i + d + 1] - T[i]) / (d + 1)));
  return e;
}

Problem parse(const std::string& yaml) { return parse_problem(yaml, "test.yaml"); }

// The assembled stiffness of a problem (first body) with solver.quadrature set.
RCP<Matrix> stiffness(const std::string& yaml, const std::string& rule) {
  const Problem P = parse(yaml + "solver: {quadrature: " + rule + "}\n");
  System sys(P, Tpetra::getDefaultComm());
  return sys.assemble_stiffness();
}

}  // namespace

TEST(SplineQuadrature, IntegratesItsTargetSpaceWithAboutHalfTheGaussPoints) {
  for (int p = 1; p <= 5; ++p) {
    struct Case {
      const char* name;
      std::vector<double> interior;
    };
    std::vector<double> graded;
    for (int k = 1; k < 24; ++k) graded.push_back(std::pow(static_cast<double>(k) / 24, 2.0));
    std::vector<double> doubled = {0.25, 0.5, 0.5, 0.75};   // a C^(p-2) line
    std::vector<double> c0(p, 0.5);                          // a C0 line: two independent halves
    c0.insert(c0.begin(), 0.25);
    c0.push_back(0.75);
    const std::vector<Case> cases = {{"one element", {}},      {"2 elements", uniform(2)}, {"3 elements", uniform(3)},
                                     {"40 elements", uniform(40)}, {"graded 24", graded},   {"double knot", doubled},
                                     {"C0 line", c0}};
    for (const Case& c : cases) {
      const std::vector<double> U = knots(p, c.interior);
      const SplineRule r = spline_gauss_rule(U, p);
      ASSERT_TRUE(r.failure.empty()) << "p = " << p << ", " << c.name << ": " << r.failure;
      EXPECT_LT(moment_error(r, U, p), 1e-12) << "p = " << p << ", " << c.name;
      double sum = 0;
      for (double w : r.w) sum += w;
      EXPECT_NEAR(sum, 1.0, 1e-14) << "p = " << p << ", " << c.name;
      // monomials up to degree 2p on [0, 1] (they lie in the target space)
      for (int k = 0; k <= 2 * p; ++k) {
        double q = 0;
        for (size_t j = 0; j < r.x.size(); ++j) q += r.w[j] * std::pow(r.x[j], k);
        EXPECT_NEAR(q, 1.0 / (k + 1), 1e-13) << "p = " << p << ", " << c.name << ", x^" << k;
      }
    }
    // many elements: about (p + 2) / 2 nodes per element, against p + 1 Gauss points
    const SplineRule r = spline_gauss_rule(knots(p, uniform(40)), p);
    const double per_element = r.x.size() / 40.0;
    std::printf("p = %d: %.3f nodes per element on 40 uniform elements (Gauss %d), %d Newton iterations\n", p,
                per_element, p + 1, r.newton_iterations);
    // (p = 1: the derivative products are discontinuous at every knot, so each element
    // needs its own rule: 2 points, as Gauss)
    EXPECT_LE(per_element, p == 1 ? 2.0 : (p + 2) / 2.0 + 0.1) << p;
  }
}

TEST(SplineQuadrature, SymmetricKnotsGiveSymmetricRules) {
  // a patch and its mirror image must get mirrored rules (else a symmetric problem solved
  // whole and by its symmetric half differ by the quadrature error): uniform knot vectors
  // with even and odd target dimensions, and a symmetric graded one (at p = 5 found by the
  // continuation from evenly spaced knots)
  for (int p = 2; p <= 5; ++p)
    for (int ne = 1; ne <= 9; ++ne) {
      std::vector<double> interior = uniform(ne);
      if (ne == 9) interior = {0.05, 0.15, 0.3, 0.5, 0.7, 0.85, 0.95};
      const SplineRule r = spline_gauss_rule(knots(p, interior), p);
      ASSERT_TRUE(r.failure.empty()) << p << " " << ne << ": " << r.failure;
      const size_t n = r.x.size();
      for (size_t j = 0; j < n; ++j) {
        EXPECT_NEAR(r.x[j] + r.x[n - 1 - j], 1.0, 1e-13) << "p = " << p << ", " << ne << " elements, node " << j;
        EXPECT_NEAR(r.w[j], r.w[n - 1 - j], 1e-13) << "p = " << p << ", " << ne << " elements, node " << j;
      }
    }
}

TEST(SplineQuadrature, AffineBSplineStiffnessEqualsGaussToRoundOff) {
  // B-spline patches (weights 1) on a parallelogram: the map is affine, the integrand a
  // polynomial spline in the target space; graded knots and a double knot included
  for (int p = 2; p <= 5; ++p) {
    std::ostringstream y;
    y << "bodies:\n  - name: b\n    material: {youngs_modulus: 100.0, poisson_ratio: 0.3}\n"
      << "    geometry: {nurbs: {degree: [1, 1], knots: [[0, 0, 1, 1], [0, 0, 1, 1]], "
      << "control_points: [[0, 0], [2, 0.5], [0.7, 1.3], [2.7, 1.8]]}}\n"
      << "    refine: {degree_elevate: " << p - 1
      << ", insert_knots: [[0.1, 0.15, 0.3, 0.3, 0.6], [0.2, 0.5, 0.55]], subdivide: [3, 2]}\n"
      << "    boundary: {south: {displacement: {x: 0, y: 0}}}\n";
    const RCP<Matrix> A = stiffness(y.str(), "gauss"), B = stiffness(y.str(), "spline");
    double scale = 0;
    const double diff = iga::test::max_abs_difference(*A, *B, scale);
    EXPECT_LT(diff, 1e-12 * scale) << "p = " << p << ": max |K_spline - K_gauss| = " << diff << " of " << scale;
  }
}

TEST(SplineQuadrature, LameRatesStayOptimal) {
  // the quarter annulus is rational and curved: neither rule is exact; both must converge at
  // the optimal rates (displacement p + 1, stress p in L2)
  for (int p = 2; p <= 5; ++p) {
    double eu[2][2], es[2][2];
    for (int r = 0; r < 2; ++r)
      for (int level = 0; level < 2; ++level) {
        const int n = 8 << level;
        std::ostringstream y;
        y << "bodies:\n  - name: c\n    material: {youngs_modulus: 1000.0, poisson_ratio: 0.3}\n"
          << "    geometry: {quarter_annulus: {center: [0, 0], inner_radius: 1.0, outer_radius: 2.0, start_angle: 0}}\n"
          << "    refine: {degree_elevate: [" << p - 2 << ", " << p - 1 << "], subdivide: [" << n << ", " << n << "]}\n"
          << "    boundary:\n      west: {displacement: {y: 0.0}}\n      east: {displacement: {x: 0.0}}\n"
          << "      south: {pressure: 1.0}\n"
          << "solver: {quadrature: " << (r ? "spline" : "gauss") << ", linear: {method: direct}}\n";
        const test::Solved sv = test::solve_text(y.str());
        ASSERT_TRUE(sv.res.converged);
        const test::Errors e = test::l2_errors(sv, 0, test::lame_cylinder(1.0, 2.0, 1.0, 1000.0, 0.3));
        eu[r][level] = e.u_rel;
        es[r][level] = e.s_rel;
      }
    for (int r = 0; r < 2; ++r) {
      const double ru = std::log2(eu[r][0] / eu[r][1]), rs = std::log2(es[r][0] / es[r][1]);
      std::printf("p = %d, %s: errors u %.3e -> %.3e (rate %.2f), stress %.3e -> %.3e (rate %.2f)\n", p,
                  r ? "spline" : "gauss ", eu[r][0], eu[r][1], ru, es[r][0], es[r][1], rs);
      // 8 -> 16 elements: the rates approach p + 1 and p from below (pre-asymptotic at p = 5)
      EXPECT_GT(ru, p + 1 - 0.4) << p << (r ? " spline" : " gauss");
      EXPECT_GT(rs, p - 0.4) << p << (r ? " spline" : " gauss");
    }
    // the spline rule's error is the discretisation's, not the quadrature's: within 10 % of
    // Gauss's (measured: 1.5 % at p = 2 on 8 elements, equal to 4 digits otherwise)
    for (int level = 0; level < 2; ++level) {
      EXPECT_LT(eu[1][level], 1.1 * eu[0][level]) << p;
      EXPECT_LT(es[1][level], 1.1 * es[0][level]) << p;
    }
  }
}

TEST(SplineQuadrature, FallsBackToGaussWhereNoRuleIsFound) {
  // p = 3 on knots graded geometrically by a factor 10 towards xi = 0 (spans from 1e-6 to
  // 0.9): neither Newton from the Greville start nor the continuation from evenly spaced knots
  // finds the rule; that direction keeps Gauss, says why, and the stiffness is Gauss's
  std::ostringstream y;
  y << "bodies:\n  - name: b\n    material: {youngs_modulus: 100.0, poisson_ratio: 0.3}\n"
    << "    geometry: {rectangle: {origin: [0, 0], size: [2, 1]}}\n"
    << "    refine: {degree_elevate: 2, insert_knots: [[1.0e-6, 1.0e-5, 1.0e-4, 1.0e-3, 1.0e-2, 0.1], []], subdivide: [1, 3]}\n"
    << "    boundary: {south: {displacement: {x: 0, y: 0}}}\n";
  const Problem P = parse(y.str() + "solver: {quadrature: spline}\n");
  System sys(P, Tpetra::getDefaultComm());
  const std::string q = sys.blocks()[0].quadrature;
  std::printf("%s\n", q.c_str());
  EXPECT_EQ(q.rfind("gauss (the spline rule: ", 0), 0u) << q;
  EXPECT_NE(q.find(" x spline"), std::string::npos) << q;   // the other direction has its rule
  const RCP<Matrix> A = stiffness(y.str(), "gauss"), B = sys.assemble_stiffness();
  double scale = 0;
  const double diff = iga::test::max_abs_difference(*A, *B, scale);
  EXPECT_LT(diff, 1e-12 * scale);
}
