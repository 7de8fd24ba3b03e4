// NURBS basis, refinement and boundary curves.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "kernels/nurbs_basis.hpp"
#include "model/bezier.hpp"
#include "model/nurbs.hpp"
#include "tests/patches.hpp"

using namespace iga;

namespace {
// Non-uniform open knot vector of degree p with one repeated interior knot (C^{p-2}).
std::vector<double> test_knots(int p) {
  std::vector<double> U(p + 1, 0.0);
  for (double k : {0.13, 0.4, 0.4, 0.71, 0.9}) U.push_back(k);
  U.insert(U.end(), p + 1, 1.0);
  return U;
}

using iga::test::annulus;
}  // namespace

class BasisDegree : public ::testing::TestWithParam<int> {};

TEST_P(BasisDegree, PartitionOfUnityAndDerivativesMatchFiniteDifferences) {
  const int p = GetParam();
  const auto U = test_knots(p);
  const int nb = static_cast<int>(U.size()) - p - 1;
  for (int k = 1; k < 200; ++k) {
    const double u = k / 200.0;
    const int s = find_span(nb, p, u, U.data());
    ASSERT_LE(U[s], u);
    ASSERT_LT(u, U[s + 1]);
    double d[3][kMaxBasis1D];
    bspline_ders(s, u, p, U.data(), 2, d);
    double sum = 0, dsum = 0, ddsum = 0;
    for (int j = 0; j <= p; ++j) { sum += d[0][j]; dsum += d[1][j]; ddsum += d[2][j]; EXPECT_GE(d[0][j], -1e-15); }
    EXPECT_NEAR(sum, 1.0, 1e-14);
    EXPECT_NEAR(dsum, 0.0, 1e-11);
    EXPECT_NEAR(ddsum, 0.0, 1e-9);
    // central differences inside the span (h small against the span)
    const double h = 1e-6 * (U[s + 1] - U[s]);
    if (u - h <= U[s] || u + h >= U[s + 1]) continue;
    double dp[3][kMaxBasis1D], dm[3][kMaxBasis1D];
    bspline_ders(s, u + h, p, U.data(), 2, dp);
    bspline_ders(s, u - h, p, U.data(), 2, dm);
    for (int j = 0; j <= p; ++j) {
      const double scale = 1.0 + std::abs(d[1][j]);
      EXPECT_NEAR((dp[0][j] - dm[0][j]) / (2 * h), d[1][j], 1e-6 * scale);
      if (p >= 2) EXPECT_NEAR((dp[1][j] - dm[1][j]) / (2 * h), d[2][j], 1e-5 * (1.0 + std::abs(d[2][j])));
    }
  }
}

TEST_P(BasisDegree, RationalCurveDerivativesMatchFiniteDifferences) {
  const int p = GetParam();
  const auto U = test_knots(p);
  const int nb = static_cast<int>(U.size()) - p - 1;
  std::mt19937 rng(p);
  std::uniform_real_distribution<double> wd(0.5, 1.5), xd(-1, 1);
  Kokkos::View<double* [2], Kokkos::HostSpace> cp("cp", nb);
  Kokkos::View<double*, Kokkos::HostSpace> w("w", nb);
  for (int i = 0; i < nb; ++i) { cp(i, 0) = i + 0.3 * xd(rng); cp(i, 1) = xd(rng); w(i) = wd(rng); }
  for (double u : {0.05, 0.2, 0.55, 0.8, 0.95}) {
    double x[2], dx[2], ddx[2], xp[2], dxp[2], ddxp[2], xm[2], dxm[2], ddxm[2], R[3][kMaxBasis1D];
    const double h = 1e-6;
    curve_eval(nb, p, U.data(), cp, w, u, x, dx, ddx, R);
    curve_eval(nb, p, U.data(), cp, w, u + h, xp, dxp, ddxp, R);
    curve_eval(nb, p, U.data(), cp, w, u - h, xm, dxm, ddxm, R);
    for (int c = 0; c < 2; ++c) {
      EXPECT_NEAR((xp[c] - xm[c]) / (2 * h), dx[c], 1e-6 * (1 + std::abs(dx[c])));
      EXPECT_NEAR((dxp[c] - dxm[c]) / (2 * h), ddx[c], 1e-5 * (1 + std::abs(ddx[c])));
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Degrees, BasisDegree, ::testing::Range(1, 6));

TEST(Refinement, QuarterAnnulusIsExactAtEveryDegreeAfterElevationAndInsertion) {
  Patch P = annulus(1.0, 2.0);
  for (int p = 2; p <= 5; ++p) {
    if (p > 2) P.elevate(0, 1);
    if (P.degree[1] < p) P.elevate(1, 1);
    Patch Q = P;
    Q.subdivide(0, 3);
    Q.subdivide(1, 2);
    Q.insert_knot(0, 0.123);
    EXPECT_EQ(Q.degree[0], p);
    EXPECT_TRUE(Q.validate().empty()) << Q.validate();
    for (int i = 0; i <= 20; ++i)
      for (int j = 0; j <= 4; ++j) {
        const double u = i / 20.0, v = j / 4.0;
        const auto a = P.eval(u, v), b = Q.eval(u, v);
        // the geometry is unchanged, and points lie exactly on circles of radius 1 + v
        EXPECT_NEAR(a[0], b[0], 1e-13);
        EXPECT_NEAR(a[1], b[1], 1e-13);
        EXPECT_NEAR(std::hypot(b[0], b[1]), 1.0 + v, 1e-13);
      }
  }
}

TEST(Refinement, SubdivideMakesUniformSpans) {
  Patch P = annulus(1.0, 2.0);
  P.subdivide(0, 4);
  P.subdivide(1, 3);
  EXPECT_EQ(P.element_spans(0).size(), 4u);
  EXPECT_EQ(P.element_spans(1).size(), 3u);
  EXPECT_EQ(P.ncp(0), 6);
  EXPECT_EQ(P.ncp(1), 4);
  EXPECT_EQ(P.num_elements(), 12);
}

TEST(Refinement, SideCurvesMatchThePatchBoundary) {
  Patch P = annulus(1.0, 3.0);
  P.elevate(1, 2);
  P.subdivide(0, 3);
  P.subdivide(1, 2);
  for (Side s : {Side::West, Side::East, Side::South, Side::North}) {
    const Curve c = P.side_curve(s);
    for (int k = 0; k <= 10; ++k) {
      const double t = k / 10.0;
      double u = t, v = t;
      if (s == Side::West) u = 0;
      if (s == Side::East) u = 1;
      if (s == Side::South) v = 0;
      if (s == Side::North) v = 1;
      const auto a = P.eval(u, v), b = c.eval(t);
      EXPECT_NEAR(a[0], b[0], 1e-14) << side_name(s);
      EXPECT_NEAR(a[1], b[1], 1e-14) << side_name(s);
    }
  }
  EXPECT_EQ(P.orientation(), -1);  // xi angular, eta radial: left-handed
}

TEST(Validation, RejectsBadKnotsCountsAndWeights) {
  Patch P = annulus(1.0, 2.0);
  EXPECT_TRUE(P.validate().empty());
  Patch a = P; a.knots[0] = {0, 0, 0, 0.7, 0.5, 1, 1, 1};
  EXPECT_NE(a.validate().find("not non-decreasing"), std::string::npos);
  Patch b = P; b.cp.pop_back();
  EXPECT_NE(b.validate().find("control_points has 5 points"), std::string::npos);
  Patch c = P; c.cp[1].w = 0.0;
  EXPECT_NE(c.validate().find("weights must be > 0"), std::string::npos);
  Patch d = P; d.knots[0] = {0, 0, 0.5, 1, 1, 1};
  EXPECT_NE(d.validate().find("not open"), std::string::npos);
}

// Bezier extraction: every B-spline equals its extracted Bernstein combination (test knots
// with a repeated interior knot, every degree), and the rational Bezier form of a refined
// quarter annulus lies on the circles (the geometry the VTK cells draw).
TEST_P(BasisDegree, BezierExtractionReproducesTheBSplines) {
  const int p = GetParam();
  const auto U = test_knots(p);
  const int nb = static_cast<int>(U.size()) - p - 1;
  const auto C = bezier_extraction_1d(U, p);
  std::vector<int> spans;
  for (int s = p; s < nb; ++s)
    if (U[s + 1] > U[s]) spans.push_back(s);
  ASSERT_EQ(C.size(), spans.size());
  for (size_t e = 0; e < spans.size(); ++e) {
    const int s = spans[e];
    for (int q = 0; q <= 10; ++q) {
      const double t = q / 10.0, u = U[s] + t * (U[s + 1] - U[s]);
      double ders[3][kMaxBasis1D], B[kMaxBasis1D];
      bspline_ders(s, u, p, U.data(), 0, ders);
      bernstein(p, t, B);
      for (int i = 0; i <= p; ++i) {
        double v = 0;
        for (int k = 0; k <= p; ++k) v += C[e][i * (p + 1) + k] * B[k];
        EXPECT_NEAR(v, ders[0][i], 1e-14) << "p " << p << " element " << e << " t " << t << " i " << i;
      }
    }
  }
}

TEST(Bezier, RefinedQuarterAnnulusCellsLieOnTheCirclesAndCarryTheField) {
  Patch P = annulus(1.0, 2.0);
  P.elevate(0, 1);
  P.elevate(1, 2);
  P.insert_knot(0, 0.3);
  P.subdivide(0, 3);
  P.subdivide(1, 2);
  const BezierPatch B(P);
  ASSERT_EQ(B.num_elements(), 6 * 2);
  // a field in the NURBS space: the control point coordinates themselves reproduce x, y
  std::vector<double> f;
  for (const auto& c : P.cp) f.insert(f.end(), {c.x[0], c.x[1]});
  const int n0 = B.degree()[0] + 1, n1 = B.degree()[1] + 1;
  std::vector<ControlPoint> pts(B.points_per_element());
  std::vector<double> fb(2 * B.points_per_element());
  for (int e = 0; e < B.num_elements(); ++e) {
    B.element_points(e, pts.data());
    B.element_field(e, f.data(), 2, fb.data());
    for (double t0 : {0.0, 0.27, 0.5, 1.0})
      for (double t1 : {0.0, 0.61, 1.0}) {
        double b0[kMaxBasis1D], b1[kMaxBasis1D], X = 0, Y = 0, W = 0, FX = 0, FY = 0;
        bernstein(n0 - 1, t0, b0);
        bernstein(n1 - 1, t1, b1);
        for (int k1 = 0; k1 < n1; ++k1)
          for (int k0 = 0; k0 < n0; ++k0) {
            const int k = k0 + k1 * n0;
            const double r = b0[k0] * b1[k1] * pts[k].w;
            X += r * pts[k].x[0]; Y += r * pts[k].x[1]; W += r;
            FX += r * fb[2 * k]; FY += r * fb[2 * k + 1];
          }
        X /= W; Y /= W; FX /= W; FY /= W;
        const auto r0 = B.range(e, 0), r1 = B.range(e, 1);
        const auto x = P.eval(r0[0] + t0 * (r0[1] - r0[0]), r1[0] + t1 * (r1[1] - r1[0]));
        EXPECT_NEAR(X, x[0], 1e-14);
        EXPECT_NEAR(Y, x[1], 1e-14);
        EXPECT_NEAR(FX, x[0], 1e-14);
        EXPECT_NEAR(FY, x[1], 1e-14);
        if (t1 == 0.0 && r1[0] == 0.0) EXPECT_NEAR(std::hypot(X, Y), 1.0, 1e-14);
        if (t1 == 1.0 && r1[1] == 1.0) EXPECT_NEAR(std::hypot(X, Y), 2.0, 1e-14);
      }
  }
}

// ---- trivariate patches ----------------------------------------------------------------

namespace {
// A quarter of a thick cylinder shell (radii 1..2, angle rational quadratic) extruded along z
// to height 0.8, degree (2, 1, 1): exact circles in every z-plane.
Patch shell3() {
  Patch a;
  a.pdim = 3;
  a.degree = {2, 1, 1};
  a.knots[0] = {0, 0, 0, 1, 1, 1};
  a.knots[1] = {0, 0, 1, 1};
  a.knots[2] = {0, 0, 1, 1};
  const double w = std::sqrt(0.5);
  for (double z : {0.0, 0.8})
    for (double r : {1.0, 2.0}) {
      a.cp.push_back(ControlPoint({r, 0, z}, 1));
      a.cp.push_back(ControlPoint({r, r, z}, w));
      a.cp.push_back(ControlPoint({0, r, z}, 1));
    }
  return a;
}
}  // namespace

TEST(Refinement3D, ShellIsExactAfterElevationInsertionAndSubdivisionInEveryDirection) {
  Patch a = shell3();
  ASSERT_EQ(a.validate(), "");
  EXPECT_EQ(a.orientation(), -1);   // xi turns counter-clockwise, eta runs outward: left-handed with z
  a.elevate(0, 1);
  a.elevate(2, 2);
  a.insert_knot(1, 0.3);
  a.subdivide(0, 3);
  a.subdivide(2, 2);
  ASSERT_EQ(a.validate(), "");
  EXPECT_EQ(a.degree, (std::array<int, 3>{3, 1, 3}));
  EXPECT_EQ(a.num_elements(), 3 * 2 * 2);
  EXPECT_EQ(static_cast<int>(a.cp.size()), a.ncp(0) * a.ncp(1) * a.ncp(2));
  std::mt19937 gen(7);
  std::uniform_real_distribution<double> U(0, 1);
  for (int k = 0; k < 50; ++k) {
    const double t[3] = {U(gen), U(gen), U(gen)};
    const auto x = a.point(t);
    const double r = std::hypot(x[0], x[1]);
    EXPECT_NEAR(r, 1.0 + t[1], 1e-13);   // linear in eta
    EXPECT_NEAR(x[2], 0.8 * t[2], 1e-13);
    EXPECT_GE(x[0], -1e-14);
    EXPECT_GE(x[1], -1e-14);
  }
}

TEST(Refinement3D, FacesAreThePatchBoundaryWithOutwardNormalsBySideNormalSign) {
  Patch a = shell3();
  a.elevate(1, 1);
  a.subdivide(2, 2);
  std::mt19937 gen(3);
  std::uniform_real_distribution<double> U(0, 1);
  for (int s = 0; s < 6; ++s) {
    const Patch F = a.face(static_cast<Side>(s));
    ASSERT_EQ(F.validate(), "") << s;
    EXPECT_EQ(F.cp.size(), a.side_indices(static_cast<Side>(s)).size());
    const int d = side_direction(s);
    for (int k = 0; k < 5; ++k) {
      const double f[2] = {U(gen), U(gen)};
      double t[3];
      for (int e = 0, fi = 0; e < 3; ++e) t[e] = e == d ? (side_end(s) ? 1.0 : 0.0) : f[fi++];
      const auto x = a.point(t), y = F.point(f);
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(x[c], y[c], 1e-13) << "face " << s;
      // outward: the face's tangent cross product times side_normal_sign points away from the
      // interior point one step inward
      const double h = 1e-6;
      double fa[2] = {f[0] + h, f[1]}, fb[2] = {f[0], f[1] + h};
      const auto xa = F.point(fa), xb = F.point(fb);
      double ta[3], tb[3];
      for (int c = 0; c < 3; ++c) { ta[c] = xa[c] - y[c]; tb[c] = xb[c] - y[c]; }
      const double n[3] = {ta[1] * tb[2] - ta[2] * tb[1], ta[2] * tb[0] - ta[0] * tb[2], ta[0] * tb[1] - ta[1] * tb[0]};
      double ti[3] = {t[0], t[1], t[2]};
      ti[d] = side_end(s) ? 0.9 : 0.1;
      const auto xi = a.point(ti);
      double dot = 0;
      for (int c = 0; c < 3; ++c) dot += n[c] * (y[c] - xi[c]);
      EXPECT_GT(side_normal_sign(s) * a.orientation() * dot, 0) << "face " << s;
    }
  }
}

TEST(Bezier3D, CellsOfARefinedShellInterpolateThePatch) {
  Patch a = shell3();
  a.elevate(2, 1);
  a.subdivide(0, 2);
  a.subdivide(1, 2);
  a.insert_knot(2, 0.4);
  const BezierPatch bz(a);
  ASSERT_EQ(bz.num_elements(), a.num_elements());
  const auto p = bz.degree();
  std::vector<ControlPoint> pts(bz.points_per_element());
  std::vector<double> f(a.cp.size());
  for (size_t q = 0; q < a.cp.size(); ++q) f[q] = std::sin(1.0 + q);   // any field of the space
  std::vector<double> fb(bz.points_per_element());
  for (int e = 0; e < bz.num_elements(); ++e) {
    bz.element_points(e, pts.data());
    bz.element_field(e, f.data(), 1, fb.data());
    for (const double t0 : {0.0, 0.3, 1.0})
      for (const double t1 : {0.0, 0.6})
        for (const double t2 : {0.2, 1.0}) {
          double B0[8], B1[8], B2[8];
          bernstein(p[0], t0, B0);
          bernstein(p[1], t1, B1);
          bernstein(p[2], t2, B2);
          double x[3] = {0, 0, 0}, w = 0, fv = 0;
          for (int k = 0; k <= p[2]; ++k)
            for (int j = 0; j <= p[1]; ++j)
              for (int i = 0; i <= p[0]; ++i) {
                const int m = i + (p[0] + 1) * (j + (p[1] + 1) * k);
                const double b = B0[i] * B1[j] * B2[k] * pts[m].w;
                for (int c = 0; c < 3; ++c) x[c] += b * pts[m].x[c];
                fv += b * fb[m];
                w += b;
              }
          double t[3];
          const double tt[3] = {t0, t1, t2};
          for (int d = 0; d < 3; ++d) {
            const auto r = bz.range(e, d);
            t[d] = r[0] + tt[d] * (r[1] - r[0]);
          }
          const auto y = a.point(t);
          for (int c = 0; c < 3; ++c) EXPECT_NEAR(x[c] / w, y[c], 1e-13);
          // the field through the patch's own basis at t
          double fr = 0, wr = 0;
          const int nb[3] = {a.ncp(0), a.ncp(1), a.ncp(2)};
          for (int k = 0; k < nb[2]; ++k)
            for (int j = 0; j < nb[1]; ++j)
              for (int i = 0; i < nb[0]; ++i) {
                const int idx[3] = {i, j, k};
                double b = a.cp[a.index(i, j, k)].w;
                for (int d = 0; d < 3; ++d) {
                  const int sp = find_span(nb[d], a.degree[d], t[d], a.knots[d].data());
                  if (idx[d] < sp - a.degree[d] || idx[d] > sp) { b = 0; break; }
                  double N[3][kMaxBasis1D];
                  bspline_ders(sp, t[d], a.degree[d], a.knots[d].data(), 0, N);
                  b *= N[0][idx[d] - (sp - a.degree[d])];
                }
                fr += b * f[a.index(i, j, k)];
                wr += b;
              }
          EXPECT_NEAR(fv / w, fr / wr, 1e-12);
        }
  }
}
