// The tangent formed row by row by sum factorisation (solver.formation: sum_factorized, the
// default; kernels/elasticity_sf.hpp) against the element loop (solver.formation: elements,
// the reference): the same matrix to round-off, entry by entry, for
//  - rational curved patches (the Lame quarter annulus) at p = 1..5, mixed degrees, both rules;
//  - B-spline patches (weights 1: the kernel's non-rational path) with graded and double knots;
//  - finite strain (Saint Venant-Kirchhoff, neo-Hookean) at a non-zero displacement;
//  - a multi-patch body (the whole wheel of four patches read from a G+Smo file) and two bodies;
//  - 1 and 2 ranks (ctest test_formation_2ranks: owned and ghost rows).
// Round-off: both sum the same products in a different order; entries are compared to 1e-12
// times the largest entry.
#include <gtest/gtest.h>
#include <Tpetra_Core.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

#include "solver/system.hpp"
#include "support.hpp"

using namespace iga;

namespace {

// A smooth displacement on every control point: u = a (sin(x + 2 y), cos(3 x - y)).
RCP<Vector> smooth_u(const System& sys, double a) {
  RCP<Vector> u = rcp(new Vector(sys.owned_map()));
  auto v = u->getLocalViewHost(Tpetra::Access::OverwriteAll);
  const auto& m = *sys.owned_map();
  for (size_t l = 0; l < m.getNodeNumElements(); ++l) {
    const GO dof = m.getGlobalElement(static_cast<LO>(l));
    const auto& X = sys.control_point(dof / 2).x;
    v(l, 0) = a * (dof % 2 == 0 ? std::sin(X[0] + 2 * X[1]) : std::cos(3 * X[0] - X[1]));
  }
  return u;
}

// K_T(u) of a problem with each formation (u = a smooth_u; a = 0: the stiffness), and the
// largest difference relative to the largest entry.
double relative_difference(const std::string& text, const std::vector<std::string>& sets, double a = 0.0,
                           const std::string& file = "test.yaml") {
  RCP<Matrix> K[2];
  const char* formation[2] = {"elements", "sum_factorized"};
  for (int k = 0; k < 2; ++k) {
    std::vector<std::string> s = sets;
    s.push_back(std::string("solver.formation=") + formation[k]);
    const Problem P = parse_problem(text, file, s);
    System sys(P, Tpetra::getDefaultComm());
    if (a == 0.0) {
      K[k] = sys.assemble_stiffness();
    } else {
      const RCP<Vector> u = smooth_u(sys, a);
      sys.assemble_internal(u.get(), nullptr, &K[k]);
    }
  }
  double scale = 0;
  const double d = iga::test::max_abs_difference(*K[0], *K[1], scale);
  EXPECT_GT(scale, 0.0);
  if (std::getenv("IGA_VERBOSE")) std::printf("  relative difference %.3e\n", d / scale);
  return d / scale;
}

std::string lame(int p0, int p1, int n0, int n1) {
  std::ostringstream y;
  y << "bodies:\n  - name: c\n    material: {youngs_modulus: 2.0e5, poisson_ratio: 0.3}\n"
    << "    geometry: {quarter_annulus: {center: [0, 0], inner_radius: 1.0, outer_radius: 2.0, start_angle: 0}}\n"
    << "    refine: {degree_elevate: [" << p0 - 2 << ", " << p1 - 1 << "], subdivide: [" << n0 << ", " << n1 << "]}\n"
    << "    boundary: {west: {displacement: {y: 0}}, east: {displacement: {x: 0}}, south: {pressure: 10.0}}\n";
  return y.str();
}

}  // namespace

TEST(SumFactorized, RationalCurvedPatchEqualsElementLoop) {
  for (const char* rule : {"spline", "gauss"})
    for (int p = 2; p <= 5; ++p) {
      const double d = relative_difference(lame(p, p, 7, 5), {std::string("solver.quadrature=") + rule});
      EXPECT_LT(d, 1e-12) << "p = " << p << ", " << rule;
    }
}

TEST(SumFactorized, MixedDegrees) {
  for (const auto& pq : {std::pair<int, int>{2, 4}, {5, 1}, {3, 2}}) {
    const double d = relative_difference(lame(pq.first, pq.second, 6, 4), {});
    EXPECT_LT(d, 1e-12) << "p = (" << pq.first << ", " << pq.second << ")";
  }
}

TEST(SumFactorized, BSplinePatchGradedAndRepeatedKnots) {
  // weights 1: the non-rational path; a double knot (C0 line) and graded knots
  for (int p = 2; p <= 5; ++p)
    for (const char* rule : {"spline", "gauss"}) {
      std::ostringstream y;
      y << "bodies:\n  - name: b\n    material: {youngs_modulus: 100.0, poisson_ratio: 0.3}\n"
        << "    geometry: {nurbs: {degree: [1, 1], knots: [[0, 0, 1, 1], [0, 0, 1, 1]], "
        << "control_points: [[0, 0], [2, 0.5], [0.7, 1.3], [2.9, 1.8]]}}\n"
        << "    refine: {degree_elevate: " << p - 1
        << ", insert_knots: [[0.1, 0.15, 0.3, 0.3, 0.6], [0.2, 0.5, 0.55]], subdivide: [3, 2]}\n"
        << "    boundary: {south: {displacement: {x: 0, y: 0}}}\n";
      const double d = relative_difference(y.str(), {std::string("solver.quadrature=") + rule});
      EXPECT_LT(d, 1e-12) << "p = " << p << ", " << rule;
    }
}

TEST(SumFactorized, FiniteStrainTangentAtADisplacement) {
  for (const char* model : {"saint_venant_kirchhoff", "neo_hookean"})
    for (int p = 2; p <= 4; ++p) {
      const std::string y = "analysis: {kinematics: finite}\n" + lame(p, p, 6, 5);
      const double d = relative_difference(y, {std::string("bodies.0.material.model=") + model}, 0.05);
      EXPECT_LT(d, 1e-12) << model << ", p = " << p;
    }
}

TEST(SumFactorized, MultiPatchBodyAndTwoBodies) {
  const std::string dir = std::string(IGACONTACT_SOURCE_DIR) + "/examples/";
  const std::string text = iga::test::read(dir + "whole_wheel.yaml");
  const double d = relative_difference(text, {"bodies.1.refine.subdivide=[8, 2]"}, 0.0, dir + "whole_wheel.yaml");
  EXPECT_LT(d, 1e-12);
  const std::string t2 = iga::test::read(dir + "two_blocks_left.yaml");
  EXPECT_LT(relative_difference(t2, {}, 0.0, dir + "two_blocks_left.yaml"), 1e-12);
}
