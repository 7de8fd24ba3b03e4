// The geometry check (model/geometry_check): valid patches pass, folded, flat and degenerate
// ones are found in the right element, also where det J is wrong only between Gauss points.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <ctime>
#include <cstdio>

#include "kernels/types.hpp"
#include "model/geometry_check.hpp"
#include "model/nurbs.hpp"
#include "tests/patches.hpp"
#include "tests/patches3d.hpp"
#include "model/problem.hpp"
#include "model/rigid_modes.hpp"

#include <random>
#include <vector>
#include "support.hpp"

using namespace iga;

namespace {

Patch bilinear(std::array<double, 2> a, std::array<double, 2> b, std::array<double, 2> c, std::array<double, 2> d) {
  Patch P;
  P.degree = {1, 1};
  P.knots = {uniform_open_knots(1, 1), uniform_open_knots(1, 1)};
  P.cp = {{{a[0], a[1]}, 1}, {{b[0], b[1]}, 1}, {{c[0], c[1]}, 1}, {{d[0], d[1]}, 1}};
  return P;
}

using iga::test::annulus;

// Biquadratic unit square, control points on a 3 x 3 grid.
Patch biquadratic_square() {
  Patch P;
  P.degree = {2, 2};
  P.knots = {uniform_open_knots(2, 1), uniform_open_knots(2, 1)};
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) P.cp.push_back({{0.5 * i, 0.5 * j}, 1});
  return P;
}

// det J by central differences of Patch::eval
double det_fd(const Patch& P, double u, double v) {
  const double h = 1e-6;
  const auto a = P.eval(u + h, v), b = P.eval(u - h, v), c = P.eval(u, v + h), d = P.eval(u, v - h);
  return ((a[0] - b[0]) * (c[1] - d[1]) - (a[1] - b[1]) * (c[0] - d[0])) / (4 * h * h);
}

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

}  // namespace

TEST(GeometryCheck, AcceptsRectanglesAnnuliAndLeftHandedPatches) {
  EXPECT_EQ(check_jacobian(bilinear({0, 0}, {2, 0}, {0, 1}, {2, 1})), "");
  // left-handed: det J < 0 everywhere (xi runs to -x)
  const Patch left = bilinear({2, 0}, {0, 0}, {2, 1}, {0, 1});
  EXPECT_EQ(left.orientation(), -1);
  EXPECT_EQ(check_jacobian(left), "");
  // quarter annulus at degrees 1..5 (eta) and 2..5 (xi), elevated and subdivided
  for (int p = 1; p <= 5; ++p) {
    Patch P = annulus(1.0, 2.0);
    P.elevate(0, std::max(p, 2) - 2);
    P.elevate(1, p - 1);
    P.subdivide(0, 5);
    P.subdivide(1, 3);
    P.insert_knot(0, 0.123);
    EXPECT_EQ(P.orientation(), -1);   // xi counter-clockwise, eta outwards: left-handed
    EXPECT_EQ(check_jacobian(P), "") << "p = " << p;
    for (auto& c : P.cp) c.x[0] = -c.x[0];   // mirrored: right-handed
    EXPECT_EQ(P.orientation(), 1);
    EXPECT_EQ(check_jacobian(P), "") << "mirrored, p = " << p;
  }
  // a thin ring at high degree: large coordinates against small elements
  Patch ring = annulus(1000.0, 1000.001);
  ring.elevate(0, 3);
  ring.elevate(1, 4);
  ring.subdivide(0, 50);
  EXPECT_EQ(check_jacobian(ring), "");
}

TEST(GeometryCheck, AcceptsACollapsedEdge) {
  // the triangle of PatchTest.UniaxialStressIsExactOnPatchWithCollapsedEdge: north edge at (0, 1)
  Patch P = bilinear({0, 0}, {1, 0}, {0, 1}, {0, 1});
  EXPECT_EQ(check_jacobian(P), "");
  P.elevate(0, 1);
  P.elevate(1, 1);
  EXPECT_EQ(check_jacobian(P), "");
  P.subdivide(0, 40);
  P.subdivide(1, 40);
  EXPECT_EQ(check_jacobian(P), "");
  // a circular sector: quarter annulus with inner radius 0 (the south side collapses)
  Patch sector = annulus(0.0, 1.0);
  EXPECT_EQ(check_jacobian(sector), "");
  sector.elevate(0, 2);
  sector.elevate(1, 3);
  sector.subdivide(0, 4);
  sector.subdivide(1, 4);
  EXPECT_EQ(check_jacobian(sector), "");
  // a corner with a straight angle (det J = 0 at that patch corner only)
  EXPECT_EQ(check_jacobian(bilinear({0, 0}, {1, 0}, {0, 1}, {0.5, 0.5})), "");
  // but a collapsed interior knot line is not a boundary: there det J = 0 inside the patch
  Patch two;   // the middle row of control points collapsed to (0, 0.5): two triangles
  two.degree = {1, 1};
  two.knots = {uniform_open_knots(1, 1), {0, 0, 0.5, 1, 1}};
  two.cp = {{{0, 0}, 1}, {{1, 0}, 1}, {{0, 0.5}, 1}, {{0, 0.5}, 1}, {{0, 1}, 1}, {{1, 1}, 1}};
  const std::string err = check_jacobian(two);
  EXPECT_TRUE(contains(err, "det J vanishes inside the patch")) << err;
}

TEST(GeometryCheck, AcceptsAStronglyDistortedValidPatch) {
  // biquadratic square with the middle point pushed past the far corner, to (1.3, 1.3): some
  // Bernstein coefficients of D are negative, yet det J >= 0.2 everywhere (subdivision
  // proves it; the quick test of step 1 does not)
  Patch P = biquadratic_square();
  P.cp[4] = {{1.3, 1.3}, 1};
  double lo = 1e300;
  for (int i = 0; i <= 200; ++i)
    for (int j = 0; j <= 200; ++j) lo = std::min(lo, det_fd(P, 0.0025 + i * 0.995 / 200, 0.0025 + j * 0.995 / 200));
  EXPECT_GT(lo, 0.15);
  EXPECT_EQ(check_jacobian(P), "");
  Patch Q = P;   // rational, refined
  Q.cp[4].w = 0.5;
  Q.elevate(0, 1);
  Q.subdivide(0, 3);
  Q.subdivide(1, 2);
  lo = 1e300;
  for (int i = 0; i <= 200; ++i)
    for (int j = 0; j <= 200; ++j) lo = std::min(lo, det_fd(Q, 0.0025 + i * 0.995 / 200, 0.0025 + j * 0.995 / 200));
  EXPECT_GT(lo, 0.0);
  EXPECT_EQ(check_jacobian(Q), "");
}

TEST(GeometryCheck, FindsAFoldMadeByAWeight) {
  // the same net, but weight 3 on the middle point pulls the patch over itself near the east side
  Patch P = biquadratic_square();
  P.cp[4] = {{1.3, 1.3}, 3.0};
  P.elevate(0, 1);
  P.subdivide(0, 3);
  P.subdivide(1, 2);
  const std::string err = check_jacobian(P);
  EXPECT_TRUE(contains(err, "det J changes sign in element [0.666667, 1] x [0, 0.5]")) << err;
  const double xi = std::stod(err.substr(err.find("xi = ") + 5)), eta = std::stod(err.substr(err.find("eta = ") + 6));
  EXPECT_LT(det_fd(P, xi, eta), 0.0) << err;
}

TEST(GeometryCheck, FindsABowTieInTheRightElement) {
  // bilinear square with the two north control points swapped (x = 0.3 instead of 0 at the
  // north-east end so that the fold is not symmetric): det J = 1 - 1.7 eta, < 0 for eta > 0.588
  Patch P = bilinear({0, 0}, {1, 0}, {1, 1}, {0.3, 1});
  std::string err = check_jacobian(P);
  EXPECT_TRUE(contains(err, "det J changes sign in element [0, 1] x [0, 1]")) << err;
  EXPECT_TRUE(contains(err, "the control net folds over")) << err;
  P.subdivide(0, 2);
  P.subdivide(1, 2);
  err = check_jacobian(P);
  EXPECT_TRUE(contains(err, "det J changes sign in element [0, 0.5] x [0.5, 1]")) << err;
  // the plain swap (the bow tie): det J = 1 - 2 eta, zero signed area
  err = check_jacobian(bilinear({0, 0}, {1, 0}, {1, 1}, {0, 1}));
  EXPECT_TRUE(contains(err, "det J changes sign")) << err;
}

TEST(GeometryCheck, FindsAFoldInTheRightElement) {
  // the middle control point pushed through the south side: det J < 0 near the south edge
  Patch P = biquadratic_square();
  P.cp[4] = {{0.5, -0.6}, 1};
  std::string err = check_jacobian(P);
  EXPECT_TRUE(contains(err, "det J changes sign in element [0, 1] x [0, 1]")) << err;
  P.subdivide(0, 2);
  P.subdivide(1, 4);
  err = check_jacobian(P);
  EXPECT_TRUE(contains(err, "det J changes sign in element [0, 0.5] x [0, 0.25]")) << err;
  // the message's point has the wrong sign
  const double xi = std::stod(err.substr(err.find("xi = ") + 5)), eta = std::stod(err.substr(err.find("eta = ") + 6));
  EXPECT_LT(det_fd(P, xi, eta), 0.0) << err;
}

TEST(GeometryCheck, FindsASignChangeBetweenTheGaussPoints) {
  // a bilinear dart: corner (1, 1) at (0.49, 0.49) is reflex, det J = 2 * 0.49 - 1 < 0 there
  // and in a region of ~0.02 around it, but > 0 at the 2 x 2 Gauss points (and on a 10 x 10
  // grid of interior points): only the Bernstein coefficients see it.
  const Patch P = bilinear({0, 0}, {1, 0}, {0, 1}, {0.49, 0.49});
  const GaussRule g = gauss_rule(2);
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j) EXPECT_GT(det_fd(P, 0.5 * (g.x[i] + 1), 0.5 * (g.x[j] + 1)), 0.1);
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 10; ++j) EXPECT_GT(det_fd(P, (i + 0.5) / 10, (j + 0.5) / 10), 0.0);
  EXPECT_LT(det_fd(P, 0.995, 0.995), 0.0);
  const std::string err = check_jacobian(P);
  EXPECT_TRUE(contains(err, "det J changes sign in element [0, 1] x [0, 1]")) << err;
  const double xi = std::stod(err.substr(err.find("xi = ") + 5)), eta = std::stod(err.substr(err.find("eta = ") + 6));
  EXPECT_LT(det_fd(P, xi, eta), 0.0) << err;
  // refined: the same fold, in the north-east element
  Patch Q = P;
  Q.elevate(0, 1);
  Q.subdivide(0, 3);
  Q.subdivide(1, 3);
  const std::string err2 = check_jacobian(Q);
  EXPECT_TRUE(contains(err2, "det J changes sign in element [0.666667, 1] x [0.666667, 1]")) << err2;
}

TEST(GeometryCheck, FindsTheThinFoldOfARandomNet) {
  // test::distorted_patch(5, 11), once used by test_kernels: the random interior control
  // points overtake the west side's neighbours, and the patch folds in a layer of ~1e-5 in xi
  // (x < 0 there, west of its own west side x = 0)
  const Patch P = test::distorted_patch(5, 11);
  const std::string err = check_jacobian(P);
  EXPECT_TRUE(contains(err, "det J changes sign in element [0, 0.1] x [0, 0.5]")) << err;
  const double eta = std::stod(err.substr(err.find("eta = ") + 6));
  EXPECT_LT(P.eval(1e-5, eta)[0], 0.0);
  EXPECT_EQ(check_jacobian(test::distorted_patch(5, 12)), "");
}

TEST(GeometryCheck, FindsZeroAreaAndInteriorZeros) {
  // all control points on a line
  const std::string err = check_jacobian(bilinear({0, 0}, {1, 1}, {2, 2}, {3, 3}));
  EXPECT_TRUE(contains(err, "det J vanishes (zero area) on all of element [0, 1] x [0, 1]")) << err;
  Patch line = bilinear({0, 0}, {1, 1}, {2, 2}, {3, 3});
  line.elevate(0, 2);
  line.subdivide(0, 3);
  EXPECT_TRUE(contains(check_jacobian(line), "zero area")) << check_jacobian(line);
  // x = (2 xi - 1)^3, y = eta: det J = 6 (2 xi - 1)^2 >= 0, zero on the line xi = 1/2, which
  // no Gauss point nor grid point hits
  Patch cusp;
  cusp.degree = {3, 1};
  cusp.knots = {uniform_open_knots(3, 1), uniform_open_knots(1, 1)};
  for (double y : {0.0, 1.0})
    for (double x : {-1.0, 1.0, -1.0, 1.0}) cusp.cp.push_back({{x, y}, 1});
  const std::string err2 = check_jacobian(cusp);
  EXPECT_TRUE(contains(err2, "det J vanishes inside the patch in element [0, 1] x [0, 1]")) << err2;
  EXPECT_TRUE(contains(err2, "xi = 0.5")) << err2;
  // coordinates whose products overflow are refused, not passed for lack of a finite answer
  const std::string err3 = check_jacobian(bilinear({0, 0}, {1e200, 0}, {0, 1e200}, {1e200, 1e200}));
  EXPECT_TRUE(contains(err3, "det J overflows")) << err3;
}

TEST(GeometryCheck, LoaderRefusesTheBody) {
  const std::string yaml =
      "bodies:\n  - name: tie\n    material: {youngs_modulus: 1000.0, poisson_ratio: 0.3}\n"
      "    geometry: {nurbs: {degree: [1, 1], knots: [[0, 0, 1, 1], [0, 0, 1, 1]],\n"
      "               control_points: [[0, 0], [1, 0], [1, 1], [0, 1]]}}\n";
  try {
    parse_problem(yaml, "t.yaml");
    FAIL() << "accepted";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_EQ(m.rfind("t.yaml:5: bodies[0].geometry.nurbs.control_points = [[0, 0], [1, 0], [1, 1], [0, 1]]: body 'tie': ", 0), 0u) << m;
    EXPECT_TRUE(contains(m, ": body 'tie': det J changes sign in element [0, 1] x [0, 1]")) << m;
  }
}

// Cost on a patch with ~1e6 dofs: quarter annulus at degree 2, 700 x 700 elements.
// Run with --gtest_also_run_disabled_tests.
TEST(GeometryCheck, DISABLED_TimeOnAMillionDofs) {
  Patch P = annulus(1.0, 2.0);
  P.elevate(1, 1);
  P.subdivide(0, 700);
  P.subdivide(1, 700);
  std::printf("  %d x %d control points = %d dofs, %d elements\n", P.ncp(0), P.ncp(1), 2 * P.ncp(0) * P.ncp(1),
              P.num_elements());
  for (int rep = 0; rep < 3; ++rep) {
    const auto t0 = std::chrono::steady_clock::now();
    const std::clock_t c0 = std::clock();
    const std::string err = check_jacobian(P);
    const double dt = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    EXPECT_EQ(err, "");
    std::printf("  check_jacobian, rational (degree 2, 2): %.3f s wall, %.3f s cpu\n", dt,
                double(std::clock() - c0) / CLOCKS_PER_SEC);
  }
  Patch R;   // the same size with equal weights
  R.degree = {2, 2};
  R.knots = {uniform_open_knots(2, 1), uniform_open_knots(2, 1)};
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) R.cp.push_back({{0.5 * i + 0.1 * j * j, 0.5 * j}, 1});
  R.subdivide(0, 700);
  R.subdivide(1, 700);
  const auto t0 = std::chrono::steady_clock::now();
  EXPECT_EQ(check_jacobian(R), "");
  std::printf("  check_jacobian, equal weights (degree 2, 2): %.3f s\n",
              std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
}

// The rigid-body modes the rigid-body check and the AMG null space share (model/rigid_modes.hpp):
// 3 in 2-D ((1, 0), (0, 1), (-y, x)), 6 in 3-D; each has a vanishing symmetric gradient
// (linear fields: the gradient is exact from two points) and they are independent (Gram
// matrix of full rank at random points).
TEST(RigidModes, AreStrainFreeAndIndependentIn2DAnd3D) {
  const double x2[2] = {0.3, -1.7};
  EXPECT_EQ(rigid_mode(0, 0, x2, 2), 1.0);
  EXPECT_EQ(rigid_mode(1, 1, x2, 2), 1.0);
  EXPECT_EQ(rigid_mode(2, 0, x2, 2), 1.7);
  EXPECT_EQ(rigid_mode(2, 1, x2, 2), 0.3);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> U(-2, 2);
  for (int dim = 2; dim <= 3; ++dim) {
    const int nm = num_rigid_modes(dim);
    ASSERT_EQ(nm, dim == 2 ? 3 : 6);
    for (int m = 0; m < nm; ++m) {
      double x[3] = {U(rng), U(rng), U(rng)}, G[3][3];
      for (int c = 0; c < dim; ++c)
        for (int d = 0; d < dim; ++d) {
          double xp[3] = {x[0], x[1], x[2]};
          xp[d] += 1.0;
          G[c][d] = rigid_mode(m, c, xp, dim) - rigid_mode(m, c, x, dim);
        }
      for (int c = 0; c < dim; ++c)
        for (int d = 0; d < dim; ++d) EXPECT_NEAR(G[c][d] + G[d][c], 0.0, 1e-14) << dim << " " << m;
    }
    // Gram matrix over 10 random points, all components: eigen-free rank check by elimination
    std::vector<std::vector<double>> A(nm, std::vector<double>(nm, 0.0));
    for (int q = 0; q < 10; ++q) {
      double x[3] = {U(rng), U(rng), U(rng)};
      for (int c = 0; c < dim; ++c)
        for (int i = 0; i < nm; ++i)
          for (int j = 0; j < nm; ++j) A[i][j] += rigid_mode(i, c, x, dim) * rigid_mode(j, c, x, dim);
    }
    for (int k = 0; k < nm; ++k) {
      ASSERT_GT(std::abs(A[k][k]), 1e-8) << "dim " << dim << ": mode " << k << " depends on the others";
      for (int i = k + 1; i < nm; ++i) {
        const double f = A[i][k] / A[k][k];
        for (int j = k; j < nm; ++j) A[i][j] -= f * A[k][j];
      }
    }
  }
}

// ---- 3-D: trivariate patches ----
namespace {

// A model Patch (pdim = 3) of a kernel-side block of tests/patches3d.hpp.
Patch patch_of_block(const iga::test3d::Block3& b) {
  Patch P;
  P.pdim = 3;
  for (int d = 0; d < 3; ++d) {
    P.degree[d] = b.p[d];
    P.knots[d] = b.U[d];
  }
  for (const auto& c : b.cp) P.cp.push_back(ControlPoint({c[0], c[1], c[2]}, c[3]));
  return P;
}

// Sphere octant, radii a (zeta = 0) and b (zeta = 1), degree (2, 2, 1) rational: a surface of
// revolution of a quarter circle. xi: the revolution about z (from +x to +y), eta: the meridian
// (from the equator to the pole), zeta: the radius. The north face (eta = 1) collapses onto the
// z axis. Right-handed: at (a, 0, 0) x_xi ~ +y, x_eta ~ +z, x_zeta ~ +x.
Patch sphere_octant(double a, double b) {
  Patch P;
  P.pdim = 3;
  P.degree = {2, 2, 1};
  P.knots = {std::vector<double>{0, 0, 0, 1, 1, 1}, std::vector<double>{0, 0, 0, 1, 1, 1}, std::vector<double>{0, 0, 1, 1}};
  const double s = std::sqrt(0.5);
  const double rev[3][3] = {{1, 0, 1}, {1, 1, s}, {0, 1, 1}};   // (cos-like, sin-like, weight) of the revolution arc
  const double mer[3][3] = {{1, 0, 1}, {1, 1, s}, {0, 1, 1}};   // (distance from the axis, z, weight) of the meridian
  for (double R : {a, b})
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i)
        P.cp.push_back(ControlPoint({R * mer[j][0] * rev[i][0], R * mer[j][0] * rev[i][1], R * mer[j][1]}, mer[j][2] * rev[i][2]));
  return P;
}

void transform(Patch& P, const double A[3][3]) {
  for (auto& c : P.cp) {
    const auto x = c.x;
    for (int r = 0; r < 3; ++r) c.x[r] = A[r][0] * x[0] + A[r][1] * x[1] + A[r][2] * x[2];
  }
}

}  // namespace

TEST(GeometryCheck3D, AcceptsBoxesShellsAndTransformedBoxes) {
  EXPECT_EQ(check_jacobian(patch_of_block(iga::test3d::box({1, 1, 1}, {1, 1, 1}))), "");
  EXPECT_EQ(check_jacobian(patch_of_block(iga::test3d::box({2, 3, 1}, {3, 2, 4}))), "");
  EXPECT_EQ(check_jacobian(patch_of_block(iga::test3d::box({4, 2, 3}, {2, 2, 2}))), "");
  // rotated (about an oblique axis) and sheared
  Patch P = patch_of_block(iga::test3d::box({2, 2, 2}, {2, 3, 2}));
  const double c = std::cos(0.7), s = std::sin(0.7);
  const double rot[3][3] = {{c, -s, 0}, {s * 0.6, c * 0.6, -0.8}, {s * 0.8, c * 0.8, 0.6}};
  const double shear[3][3] = {{1, 0.9, -0.4}, {0, 1, 0.7}, {0, 0, 1}};
  transform(P, rot);
  transform(P, shear);
  EXPECT_EQ(P.orientation(), 1);
  EXPECT_EQ(check_jacobian(P), "");
  EXPECT_EQ(check_jacobian(P, 1), "");
  // mirrored: left-handed, valid with its own orientation, refused where +1 is required
  const double mirror[3][3] = {{-1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  transform(P, mirror);
  EXPECT_EQ(P.orientation(), -1);
  EXPECT_EQ(check_jacobian(P), "");
  EXPECT_TRUE(contains(check_jacobian(P, 1), "changes sign")) << check_jacobian(P, 1);
  // the quarter thick cylinder shell (rational in the angle), degrees 2 and 3
  EXPECT_EQ(check_jacobian(patch_of_block(iga::test3d::shell(2, {3, 2, 2}, 1))), "");
  EXPECT_EQ(check_jacobian(patch_of_block(iga::test3d::shell(3, {2, 2, 2}, 2))), "");
}

TEST(GeometryCheck3D, SphereOctantWithDegeneratePoleFace) {
  const double a = 1.0, b = 1.6;
  Patch P = sphere_octant(a, b);
  ASSERT_EQ(P.validate(), "");
  EXPECT_EQ(P.orientation(), 1);
  // the geometry: on the spheres r = a and r = b, linear in zeta between them, in the octant
  for (int k = 0; k <= 4; ++k)
    for (int j = 0; j <= 8; ++j)
      for (int i = 0; i <= 8; ++i) {
        const double t[3] = {i / 8.0, j / 8.0, k / 4.0};
        const auto x = P.point(t);
        EXPECT_NEAR(std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]), a + t[2] * (b - a), 1e-12 * b);
        EXPECT_GE(x[0], -1e-14); EXPECT_GE(x[1], -1e-14); EXPECT_GE(x[2], -1e-14);
      }
  // the pole face collapses onto the z axis
  for (int a_ : P.side_indices(Side::North)) {
    EXPECT_EQ(P.cp[a_].x[0], 0.0);
    EXPECT_EQ(P.cp[a_].x[1], 0.0);
  }
  EXPECT_EQ(check_jacobian(P), "");
  EXPECT_EQ(check_jacobian(P, 1), "");
  // refined in all directions and elevated: still exact, still accepted
  Patch Q = P;
  Q.elevate(2, 1);
  Q.subdivide(0, 2);
  Q.subdivide(1, 3);
  Q.subdivide(2, 2);
  EXPECT_EQ(check_jacobian(Q), "");
  // degree 5 in every direction (the largest), 3 x 3 x 2 elements: D of degree 19, the pole
  // elements divided and subdivided
  Patch H = P;
  H.elevate(0, 3);
  H.elevate(1, 3);
  H.elevate(2, 4);
  H.subdivide(0, 3);
  H.subdivide(1, 3);
  H.subdivide(2, 2);
  EXPECT_EQ(check_jacobian(H), "");   // (36 ms here)
  // left-handed (zeta reversed): accepted with its own orientation
  Patch R = P;
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) std::swap(R.cp[R.index(i, j, 0)], R.cp[R.index(i, j, 1)]);
  EXPECT_EQ(R.orientation(), -1);
  EXPECT_EQ(check_jacobian(R), "");
}

TEST(GeometryCheck3D, WedgeWithAFaceCollapsedOntoAnEdgeIsAccepted) {
  // trilinear box whose east face (x = 1) collapses onto the edge y = 0: det J = 0 there only
  Patch P = patch_of_block(iga::test3d::box({1, 1, 1}, {1, 1, 1}, {1.0, 1.0, 1.0}));
  for (int a : P.side_indices(Side::East)) P.cp[a].x[1] = 0.0;
  EXPECT_EQ(check_jacobian(P), "");
  // the same at degree 2 with 2 x 2 x 2 elements (the collapsed face in the last elements)
  Patch Q = patch_of_block(iga::test3d::box({2, 2, 2}, {2, 2, 2}, {1.0, 1.0, 1.0}));
  for (auto& c : Q.cp) c.x[1] *= 1.0 - c.x[0];   // y -> y (1 - x): the face x = 1 onto y = 0
  EXPECT_EQ(check_jacobian(Q), "");
  // pinched inside (the middle plane x = 1/2 collapsed onto a line): refused
  Patch R = patch_of_block(iga::test3d::box({1, 1, 1}, {2, 1, 1}, {1.0, 1.0, 1.0}));
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 2; ++j) R.cp[R.index(1, j, k)].x[1] = 0.0;
  const std::string m = check_jacobian(R);
  EXPECT_TRUE(contains(m, "vanishes inside the patch")) << m;
}

TEST(GeometryCheck3D, StraightDihedralAngleAlongAnEdgeIsAccepted) {
  // a prism: the trilinear block whose corner (xi, eta) = (1, 1) goes to (2, 0), so that the
  // faces eta = 0 and xi = 1 are coplanar at the edge (xi, eta) = (1, 0): det J = 0 along that
  // patch edge only (not a whole face: no factor to divide out; subdivision ends on it)
  Patch P = patch_of_block(iga::test3d::box({1, 1, 1}, {1, 1, 1}, {1.0, 1.0, 1.0}));
  for (int k = 0; k < 2; ++k) {
    P.cp[P.index(1, 1, k)].x[0] = 2.0;
    P.cp[P.index(1, 1, k)].x[1] = 0.0;
  }
  EXPECT_EQ(check_jacobian(P), "");
  // degree 2 (elevated) and 2 x 2 x 2 elements: the same geometry, the same answer
  Patch Q = P;
  for (int d = 0; d < 3; ++d) Q.elevate(d, 1), Q.subdivide(d, 2);
  EXPECT_EQ(check_jacobian(Q), "");
  // past the straight angle (a reflex corner): det J < 0 near that edge
  Patch R = P;
  for (int k = 0; k < 2; ++k) R.cp[R.index(1, 1, k)].x[1] = -0.3;
  const std::string m = check_jacobian(R);
  EXPECT_TRUE(contains(m, "det J changes sign")) << m;
}

TEST(GeometryCheck3D, FoldedBoxesAreRefused) {
  // trilinear 2 x 2 x 2 elements: the middle control point moved through the east face
  Patch P = patch_of_block(iga::test3d::box({1, 1, 1}, {2, 2, 2}, {1.0, 1.0, 1.0}));
  ASSERT_EQ(check_jacobian(P), "");
  P.cp[P.index(1, 1, 1)].x[0] = 1.5;
  std::string m = check_jacobian(P);
  EXPECT_TRUE(contains(m, "det J changes sign in element [0.5, 1] x ")) << m;
  EXPECT_TRUE(contains(m, "the control net folds over")) << m;
  // triquadratic, one element: the interior control point far through the east face; det J
  // < 0 near the middle of that face only
  Patch Q = patch_of_block(iga::test3d::box({2, 2, 2}, {1, 1, 1}, {1.0, 1.0, 1.0}));
  Q.cp[Q.index(1, 1, 1)].x[0] = 4.0;
  m = check_jacobian(Q);
  EXPECT_TRUE(contains(m, "det J changes sign in element [0, 1] x [0, 1] x [0, 1]")) << m;
  // barely through: x_xi < 0 only for xi > 0.988 near the middle of the east face (at s = r =
  // 1/2, x_xi = 2 (1 - xi) a - 2 xi (a - 1), a = 0.375 + X / 4 = 1.0125), where no sample point
  // of step 2 lies (the last: xi = 0.917): found by the Bernstein coefficients and subdivision
  Q.cp[Q.index(1, 1, 1)].x[0] = 2.55;
  m = check_jacobian(Q);
  EXPECT_TRUE(contains(m, "det J changes sign in element [0, 1] x [0, 1] x [0, 1]")) << m;
  // the same at X = 2.45 (a < 1): x_xi > 0 everywhere, accepted
  Q.cp[Q.index(1, 1, 1)].x[0] = 2.45;
  EXPECT_EQ(check_jacobian(Q), "");
  // a flat element: zero volume
  Patch F = patch_of_block(iga::test3d::box({1, 1, 1}, {1, 1, 1}, {1.0, 1.0, 1.0}));
  for (auto& c : F.cp) c.x[2] = 0.0;
  m = check_jacobian(F);
  EXPECT_TRUE(contains(m, "zero volume")) << m;
  // the sphere octant with the inner middle control point pushed out so far that the inner
  // surface crosses the outer one (x3 would not: the inner point at the centre reaches r = 1.59)
  Patch S = sphere_octant(1.0, 1.6);
  for (int c = 0; c < 3; ++c) S.cp[S.index(1, 1, 0)].x[c] *= 5.0;
  m = check_jacobian(S);
  EXPECT_TRUE(contains(m, "det J changes sign")) << m;
}

// Cost of the 3-D check (run by hand: --gtest_also_run_disabled_tests): the quarter cylinder
// shell (rational) and a box (equal weights) of 20^3 elements at degree 2.
TEST(GeometryCheck3D, DISABLED_Time8000Elements) {
  for (const bool curved : {true, false}) {
    const Patch P = patch_of_block(curved ? iga::test3d::shell(2, {20, 20, 20}, 2) : iga::test3d::box({2, 2, 2}, {20, 20, 20}));
    const auto t0 = std::chrono::steady_clock::now();
    EXPECT_EQ(check_jacobian(P), "");
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf("%s: %d elements, %.3f s, %.1f us per element\n", curved ? "shell" : "box", P.num_elements(), s, 1e6 * s / P.num_elements());
  }
}
