// 3-D mortar segmentation (kernels/contact_clip.hpp): polygon clipping in the slave parameter
// plane, exact orientation, and the fan rule on the clipped polygon.
//   Orient2d        the sign of orient2d against exact integer arithmetic (__int128) on nearly
//                   collinear triples, and on the Kettner et al. grid near (0.5, 0.5) where the
//                   plain floating-point determinant is wrong
//   ClipArea        rectangles and rotated squares against closed forms; the roles of slave and
//                   master swapped give the same area
//   Partition       a slave rectangle against random non-matching tilings (quads, triangles,
//                   sampled edges, lines through the slave's corners): the clipped areas and
//                   the rule's integrals of a cubic sum to the slave's
//   NearlyCollinear perturbations 1e-15..1e-9: corners kept, no reflex vertex, exact area
//   Degenerate      touching edges, a shared vertex, sub-round-off slivers, bad input: area 0,
//                   no NaN
//   PolygonRule     monomials x^i y^j up to the rule's degree over clipped polygons
//   ClipKernel      many pairs in a Kokkos::parallel_for, against the host
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <initializer_list>
#include <random>
#include <vector>

#include "kernels/contact_clip.hpp"

using namespace iga;

namespace {

ClipPolygon poly(std::initializer_list<std::array<double, 2>> pts) {
  ClipPolygon p;
  for (const auto& x : pts) {
    p.v[p.n][0] = x[0];
    p.v[p.n][1] = x[1];
    ++p.n;
  }
  return p;
}

ClipPolygon poly(const std::vector<std::array<double, 2>>& pts) {
  ClipPolygon p;
  for (const auto& x : pts) {
    p.v[p.n][0] = x[0];
    p.v[p.n][1] = x[1];
    ++p.n;
  }
  return p;
}

ClipPolygon clip(const ClipPolygon& s, const ClipPolygon& m, int* flags = nullptr) {
  ClipPolygon out;
  const int f = clip_polygons(s, m, out);
  if (flags) *flags = f;
  return out;
}

long double binom(int n, int k) {
  long double r = 1;
  for (int i = 1; i <= k; ++i) r = r * (n - k + i) / i;
  return r;
}

// \int_P x^p y^q over a counter-clockwise polygon (Steger's edge formula, long double)
long double moment(const ClipPolygon& P, int p, int q) {
  long double s = 0;
  for (int k = 0; k < P.n; ++k) {
    const long double x0 = P.v[k][0], y0 = P.v[k][1];
    const long double x1 = P.v[(k + 1) % P.n][0], y1 = P.v[(k + 1) % P.n][1];
    long double inner = 0;
    for (int a = 0; a <= p; ++a)
      for (int b = 0; b <= q; ++b)
        inner += binom(a + b, a) * binom(p + q - a - b, q - b) * std::pow(x0, a) * std::pow(x1, p - a) * std::pow(y0, b) *
                 std::pow(y1, q - b);
    s += (x0 * y1 - x1 * y0) * inner;
  }
  return s / ((p + q + 2) * (p + q + 1) * binom(p + q, p));
}

long double area_ld(const ClipPolygon& P) { return moment(P, 0, 0); }

// strictly convex and counter-clockwise, by the exact predicate: every vertex strictly left of
// every edge it is not on
bool strictly_convex_ccw(const ClipPolygon& P) {
  if (P.n < 3) return false;
  for (int k = 0; k < P.n; ++k) {
    const double* a = P.v[k];
    const double* b = P.v[(k + 1) % P.n];
    for (int j = 0; j < P.n; ++j)
      if (j != k && j != (k + 1) % P.n && !(orient2d(a, b, P.v[j]) > 0)) return false;
  }
  return true;
}

bool all_finite(const ClipPolygon& P) {
  for (int k = 0; k < kClipMaxVertices; ++k)
    if (!std::isfinite(P.v[k][0]) || !std::isfinite(P.v[k][1])) return false;
  return true;
}

double shortest_edge(const ClipPolygon& P) {
  double e = 1e300;
  for (int k = 0; k < P.n; ++k)
    e = std::min(e, std::hypot(P.v[(k + 1) % P.n][0] - P.v[k][0], P.v[(k + 1) % P.n][1] - P.v[k][1]));
  return e;
}

ClipPolygon rotated_square(double cx, double cy, double half, double theta) {
  const double c = std::cos(theta), s = std::sin(theta);
  ClipPolygon p;
  p.n = 4;
  const double corner[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
  for (int k = 0; k < 4; ++k) {
    p.v[k][0] = cx + half * (c * corner[k][0] - s * corner[k][1]);
    p.v[k][1] = cy + half * (s * corner[k][0] + c * corner[k][1]);
  }
  return p;
}

double rule_integral(const ClipPolygon& P, const TriangleRule& g, int i, int j) {
  double s = 0;
  for_each_polygon_point(P, g, [&](const double* x, double w) { s += w * std::pow(x[0], i) * std::pow(x[1], j); });
  return s;
}

__extension__ typedef __int128 int128;   // the exact reference of orient2d

int sgn(double x) { return (x > 0) - (x < 0); }

}  // namespace

// ---------------------------------------------------------------------------------------------

TEST(Orient2d, MatchesExactIntegerArithmeticOnNearlyCollinearTriples) {
  // integer coordinates below 2^50 scaled by 2^-50: the doubles are exact and the determinant
  // fits in 128-bit integers
  std::mt19937_64 gen(3);
  std::uniform_int_distribution<long long> I(0, (1LL << 50) - 1);
  std::uniform_int_distribution<int> pert(-3, 3);
  std::uniform_real_distribution<double> T(-0.5, 1.5);
  const double scale = std::ldexp(1.0, -50);
  int wrong = 0, naive_wrong = 0, zero = 0, tested = 0, naive_tested = 0;
  auto check = [&](double o, int expect) {
    ++tested;
    wrong += sgn(o) != expect;
  };
  auto check_naive = [&](double o, int expect) {
    ++naive_tested;
    naive_wrong += sgn(o) != expect;
  };
  for (int k = 0; k < 200000; ++k) {
    const long long ax = I(gen), ay = I(gen), bx = I(gen), by = I(gen);
    const double t = T(gen);
    long long cx = ax + std::llround(t * static_cast<double>(bx - ax)) + pert(gen);
    long long cy = ay + std::llround(t * static_cast<double>(by - ay)) + pert(gen);
    cx = std::clamp(cx, 0LL, (1LL << 50) - 1);
    cy = std::clamp(cy, 0LL, (1LL << 50) - 1);
    const int128 det = static_cast<int128>(ax - cx) * (by - cy) - static_cast<int128>(ay - cy) * (bx - cx);
    const int exact = (det > 0) - (det < 0);
    zero += exact == 0;
    const double a[2] = {ax * scale, ay * scale}, b[2] = {bx * scale, by * scale}, c[2] = {cx * scale, cy * scale};
    check(orient2d(a, b, c), exact);
    check_naive((a[0] - c[0]) * (b[1] - c[1]) - (a[1] - c[1]) * (b[0] - c[0]), exact);
    // the orientation of the same triple in the other orders
    check(orient2d(b, c, a), exact);
    check(orient2d(b, a, c), -exact);
  }
  // exactly collinear triples a, a + i d, a + j d, and the third moved by one unit
  std::uniform_int_distribution<long long> D(-(1LL << 30), 1LL << 30), J(-2000, 2000), A(1LL << 48, 1LL << 49);
  int collinear = 0;
  for (int k = 0; k < 100000; ++k) {
    const long long dx = D(gen), dy = D(gen), i = J(gen), j = J(gen), ax = A(gen), ay = A(gen);
    const long long bx = ax + i * dx, by = ay + i * dy;
    long long cx = ax + j * dx, cy = ay + j * dy;
    if (k % 2) cx += pert(gen) % 2;
    const int128 det = static_cast<int128>(ax - cx) * (by - cy) - static_cast<int128>(ay - cy) * (bx - cx);
    const int exact = (det > 0) - (det < 0);
    collinear += exact == 0;
    const double a[2] = {ax * scale, ay * scale}, b[2] = {bx * scale, by * scale}, c[2] = {cx * scale, cy * scale};
    check(orient2d(a, b, c), exact);
    check_naive((a[0] - c[0]) * (b[1] - c[1]) - (a[1] - c[1]) * (b[0] - c[0]), exact);
    check(orient2d(c, a, b), exact);
  }
  zero += collinear;
  // full 53-bit coordinates in [0.5, 2) (integers in units of 2^-53 below 2^54): their
  // differences are often inexact, which takes the six-product path of the exact stage
  std::uniform_real_distribution<double> C(0.5, 2.0);
  int inexact_differences = 0;
  for (int k = 0; k < 200000; ++k) {
    const double a[2] = {C(gen), C(gen)}, b[2] = {C(gen), C(gen)};
    const double t = T(gen);
    double c[2] = {a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])};
    if (c[0] < 0.5 || c[0] >= 2 || c[1] < 0.5 || c[1] >= 2) continue;
    if (k % 3 == 1) c[0] = std::nextafter(c[0], 3.0);
    auto units = [](double x) { return static_cast<long long>(std::ldexp(x, 53)); };   // exact: x in [0.5, 2)
    const int128 det = static_cast<int128>(units(a[0]) - units(c[0])) * (units(b[1]) - units(c[1])) -
                       static_cast<int128>(units(a[1]) - units(c[1])) * (units(b[0]) - units(c[0]));
    const int exact = (det > 0) - (det < 0);
    zero += exact == 0;
    bool inexact_difference = false;
    for (const double* p : {a, b})
      for (int d = 0; d < 2; ++d) {
        double diff, tail;
        clip_detail::two_sum(p[d], -c[d], diff, tail);
        inexact_difference = inexact_difference || tail != 0;
      }
    inexact_differences += inexact_difference;
    check(orient2d(a, b, c), exact);
    check_naive((a[0] - c[0]) * (b[1] - c[1]) - (a[1] - c[1]) * (b[0] - c[0]), exact);
    check(orient2d(c, a, b), exact);
    check(orient2d(b, a, c), -exact);
  }
  EXPECT_GT(inexact_differences, 5000);
  std::printf("orient2d: %d wrong signs of %d; the plain determinant: %d wrong of %d (%d exactly collinear, %d "
              "triples with an inexact difference)\n",
              wrong, tested, naive_wrong, naive_tested, zero, inexact_differences);
  EXPECT_EQ(wrong, 0);
  EXPECT_GT(naive_wrong, 0);   // the triples are near enough to collinear to need the fallback
}

TEST(Orient2d, KettnerGridNearOneHalf) {
  // p = (0.5 + i u, 0.5 + j u), u = 2^-53, against q = (12, 12), r = (24, 24): the exact
  // determinant is 12 (p_y - p_x), of the sign of j - i
  const double u = std::ldexp(1.0, -53);
  const double q[2] = {12, 12}, r[2] = {24, 24};
  int wrong = 0, naive_wrong = 0;
  for (int i = 0; i < 256; ++i)
    for (int j = 0; j < 256; ++j) {
      const double p[2] = {0.5 + i * u, 0.5 + j * u};
      const int exact = (j > i) - (j < i);
      const double o = orient2d(p, q, r);
      wrong += ((o > 0) - (o < 0)) != exact;
      const double naive = (p[0] - r[0]) * (q[1] - r[1]) - (p[1] - r[1]) * (q[0] - r[0]);
      naive_wrong += ((naive > 0) - (naive < 0)) != exact;
    }
  std::printf("Kettner grid: orient2d %d wrong of 65536, the plain determinant %d\n", wrong, naive_wrong);
  EXPECT_EQ(wrong, 0);
  EXPECT_GT(naive_wrong, 0);
}

// ---------------------------------------------------------------------------------------------

TEST(ClipArea, AxisAlignedRectanglesAgainstTheProductOfOverlaps) {
  std::mt19937 gen(7);
  std::uniform_real_distribution<double> U(0, 1);
  double worst = 0;
  int nonempty = 0;
  for (int k = 0; k < 20000; ++k) {
    double a0 = U(gen), a1 = U(gen), b0 = U(gen), b1 = U(gen), c0 = U(gen), c1 = U(gen), d0 = U(gen), d1 = U(gen);
    if (a0 > a1) std::swap(a0, a1);
    if (b0 > b1) std::swap(b0, b1);
    if (c0 > c1) std::swap(c0, c1);
    if (d0 > d1) std::swap(d0, d1);
    if (k % 4 == 1) c0 = a0;   // a shared edge line
    if (k % 4 == 2) { c0 = a0; d1 = b1; }   // a shared corner
    if (k % 4 == 3) { c0 = a0; c1 = a1; }   // the same u interval
    const ClipPolygon S = parameter_rectangle(a0, a1, b0, b1);
    const ClipPolygon M = parameter_rectangle(c0, c1, d0, d1);
    int flags = -1;
    const ClipPolygon P = clip(S, M, &flags);
    ASSERT_EQ(flags, 0);
    const double exact = std::max(0.0, std::min(a1, c1) - std::max(a0, c0)) * std::max(0.0, std::min(b1, d1) - std::max(b0, d0));
    const double area = polygon_area(P);
    const double slave = (a1 - a0) * (b1 - b0);
    if (exact > kClipAreaTol * slave) {
      ++nonempty;
      EXPECT_TRUE(strictly_convex_ccw(P));
      EXPECT_EQ(P.n, 4);
    }
    worst = std::max(worst, std::abs(area - exact));
  }
  std::printf("rectangles: %d overlaps, worst |area - closed form| %.3g\n", nonempty, worst);
  EXPECT_GT(nonempty, 5000);
  EXPECT_LT(worst, 1e-14);
}

TEST(ClipArea, RotatedSquaresAgainstTheClosedForm) {
  // the square [-1, 1]^2 and itself rotated by theta: 4 - 2 (s + c - 1)^2 / (s c), an octagon
  const ClipPolygon S = parameter_rectangle(-1, 1, -1, 1);
  double worst = 0;
  const double thetas[] = {1e-15, 1e-12, 1e-9, 1e-6, 1e-3, 0.1, 0.3, M_PI / 6, M_PI / 4, 1.0, 1.3, M_PI / 2 - 1e-9, 2.0, 3.0, -0.7};
  for (const double th : thetas) {
    const ClipPolygon M = rotated_square(0, 0, 1, th);
    int flags = -1;
    const ClipPolygon P = clip(S, M, &flags);
    ASSERT_EQ(flags, 0);
    // reduce to (0, pi/2): the square is symmetric under quarter turns
    double r = std::fmod(th, M_PI / 2);
    if (r < 0) r += M_PI / 2;
    const double s = std::sin(r), c = std::cos(r);
    const double smc = s - 2 * std::sin(r / 2) * std::sin(r / 2);   // s + c - 1 without cancellation
    const double exact = 4 - 2 * smc * smc / (s * c);
    const double area = polygon_area(P);
    EXPECT_TRUE(strictly_convex_ccw(P)) << th;
    EXPECT_LE(P.n, 8);
    worst = std::max(worst, std::abs(area - exact));
    // swapped roles: the same region from different clip lines
    const ClipPolygon Q = clip(M, S);
    EXPECT_NEAR(polygon_area(Q), area, 1e-14) << th;
  }
  // inside and around: a small rotated square inside the slave, the slave inside a big one
  for (const double th : {0.2, 0.9, 2.5}) {
    const ClipPolygon small = rotated_square(0.1, -0.2, 0.3, th);
    const ClipPolygon P = clip(S, small);
    worst = std::max(worst, std::abs(polygon_area(P) - 0.36));
    const ClipPolygon big = rotated_square(0.05, 0, 3.0, th);
    worst = std::max(worst, std::abs(polygon_area(clip(S, big)) - 4.0));
  }
  // a diamond |u - 1| + |v| <= 1 against [-1, 1]^2: half of it, area 1
  worst = std::max(worst, std::abs(polygon_area(clip(S, poly({{0, 0}, {1, -1}, {2, 0}, {1, 1}}))) - 1.0));
  std::printf("rotated squares: worst |area - closed form| %.3g\n", worst);
  EXPECT_LT(worst, 1e-14);
}

// ---------------------------------------------------------------------------------------------

namespace {

// tiles of a perturbed, rotated grid around the slave: quads (kind 0), triangles (1), quads with
// every edge sampled at 3 interior points (2, collinear up to round-off); kind 3: an axis-aligned
// grid whose lines pass through the slave's corners and edges, some moved by 1e-15..1e-9
std::vector<ClipPolygon> tiling(int kind, const double lo[2], const double hi[2], std::mt19937& gen) {
  std::uniform_real_distribution<double> U(-1, 1);
  const int m = kind == 3 ? 8 : 7;
  const double cx = 0.5 * (lo[0] + hi[0]), cy = 0.5 * (lo[1] + hi[1]);
  const double L = 1.5 * std::max(hi[0] - lo[0], hi[1] - lo[1]);   // half-width of the grid
  const double theta = kind == 3 ? 0.0 : 3.0 * U(gen);
  std::vector<std::array<double, 2>> node((m + 1) * (m + 1));
  for (int j = 0; j <= m; ++j)
    for (int i = 0; i <= m; ++i) {
      double x, y;
      if (kind == 3) {   // lines at the slave's sides and between, a few moved a hair
        const double tx = std::clamp(-0.5 + 2.0 * i / m, -0.5, 1.5), ty = std::clamp(-0.5 + 2.0 * j / m, -0.5, 1.5);
        x = lo[0] + tx * (hi[0] - lo[0]);
        y = lo[1] + ty * (hi[1] - lo[1]);
        if (i > 0 && i < m && j > 0 && j < m && (i + j) % 3 == 0) {
          const double d = std::pow(10.0, -15 + 6 * (0.5 + 0.5 * U(gen)));
          x += d * U(gen);
          y += d * U(gen);
        }
      } else {
        double a = -L + 2 * L * i / m, b = -L + 2 * L * j / m;
        if (i > 0 && i < m && j > 0 && j < m) {   // interior nodes moved: convex quads still
          a += 0.2 * (2 * L / m) * U(gen);
          b += 0.2 * (2 * L / m) * U(gen);
        }
        x = cx + std::cos(theta) * a - std::sin(theta) * b;
        y = cy + std::sin(theta) * a + std::cos(theta) * b;
      }
      node[i + (m + 1) * j] = {x, y};
    }
  std::vector<ClipPolygon> tiles;
  for (int j = 0; j < m; ++j)
    for (int i = 0; i < m; ++i) {
      const std::array<double, 2> q[4] = {node[i + (m + 1) * j], node[i + 1 + (m + 1) * j], node[i + 1 + (m + 1) * (j + 1)],
                                          node[i + (m + 1) * (j + 1)]};
      if (kind == 1) {
        tiles.push_back(poly({q[0], q[1], q[2]}));
        tiles.push_back(poly({q[0], q[2], q[3]}));
      } else if (kind == 2) {
        std::vector<std::array<double, 2>> pts;
        for (int e = 0; e < 4; ++e)
          for (int s = 0; s < 3; ++s) {   // the corner and 2 interior points per edge: 12 points
            const double t = s / 3.0;
            const auto& a = q[e];
            const auto& b = q[(e + 1) % 4];
            pts.push_back({a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])});
          }
        tiles.push_back(poly(pts));
      } else {
        tiles.push_back(poly({q[0], q[1], q[2], q[3]}));
      }
    }
  return tiles;
}

}  // namespace

TEST(Partition, ClippedAreasOfATilingSumToTheSlave) {
  std::mt19937 gen(17);
  std::uniform_real_distribution<double> U(0, 1);
  const TriangleRule g = triangle_rule_collapsed(gauss_rule(3));   // degree 4
  double worst_area = 0, worst_int = 0;
  int segments = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const int kind = trial % 4;
    const double lo[2] = {U(gen), U(gen)}, hi[2] = {lo[0] + 0.05 + U(gen), lo[1] + 0.05 + U(gen)};
    const ClipPolygon S = parameter_rectangle(lo[0], hi[0], lo[1], hi[1]);
    const double slave_area = (hi[0] - lo[0]) * (hi[1] - lo[1]);
    // \int_S u^3 + u v^2 - 2 v exactly
    auto F = [](double a0, double a1, double b0, double b1) {
      return (std::pow(a1, 4) - std::pow(a0, 4)) / 4 * (b1 - b0) + (a1 * a1 - a0 * a0) / 2 * (std::pow(b1, 3) - std::pow(b0, 3)) / 3 -
             2 * (a1 - a0) * (b1 * b1 - b0 * b0) / 2;
    };
    const double exact_int = F(lo[0], hi[0], lo[1], hi[1]);
    long double sum = 0, sum_int = 0;
    for (const ClipPolygon& M : tiling(kind, lo, hi, gen)) {
      int flags = -1;
      const ClipPolygon P = clip(S, M, &flags);
      ASSERT_EQ(flags, 0);
      if (P.n == 0) continue;
      ++segments;
      ASSERT_TRUE(strictly_convex_ccw(P));
      sum += polygon_area(P);
      for_each_polygon_point(P, g, [&](const double* x, double w) {
        ASSERT_GT(w, 0);
        sum_int += w * (x[0] * x[0] * x[0] + x[0] * x[1] * x[1] - 2 * x[1]);
      });
    }
    worst_area = std::max(worst_area, static_cast<double>(std::abs(sum - slave_area) / slave_area));
    worst_int = std::max(worst_int, static_cast<double>(std::abs(sum_int - exact_int) / slave_area));
  }
  std::printf("tilings: %d segments in 200 slaves; worst |sum of areas - slave| / slave %.3g, "
              "worst |sum of rule integrals - exact| / slave %.3g\n",
              segments, worst_area, worst_int);
  EXPECT_LT(worst_area, 1e-14);
  EXPECT_LT(worst_int, 1e-14);
}

// ---------------------------------------------------------------------------------------------

TEST(NearlyCollinear, ATiltedEdgeKeepsItsCorner) {
  // master edge from (-0.5, d) to (1.5, -d) across the slave [0, 1]^2 crosses v = 0 at u = 0.5:
  // the segment is the pentagon (0, d/2) (0.5, 0) (1, 0) (1, 1) (0, 1), area 1 - d/8
  const ClipPolygon S = parameter_rectangle(0, 1, 0, 1);
  double worst = 0;
  for (int e = -15; e <= -9; ++e)
    for (const double sign : {1.0, -1.0}) {
      const double d = sign * std::pow(10.0, e);
      const ClipPolygon M = poly({{-0.5, d}, {1.5, -d}, {1.5, 2}, {-0.5, 2}});
      const ClipPolygon P = clip(S, M);
      EXPECT_EQ(P.n, 5) << d;
      EXPECT_TRUE(strictly_convex_ccw(P)) << d;
      bool corner = false;
      for (int k = 0; k < P.n; ++k) corner = corner || (std::abs(P.v[k][0] - 0.5) < 1e-15 && std::abs(P.v[k][1]) < 1e-15);
      EXPECT_TRUE(corner) << d;
      worst = std::max(worst, std::abs(polygon_area(P) - (1 - std::abs(d) / 8)));
    }
  std::printf("tilted edge: worst |area - (1 - d/8)| %.3g\n", worst);
  EXPECT_LT(worst, 1e-15);
}

TEST(NearlyCollinear, SampledEdgesBulgingOutKeepEveryCornerAndBulgingInGiveNoReflexVertex) {
  // the square [0.25, 0.75]^2 with 3 points inside each edge (at 1/4, 1/2, 3/4) moved outward
  // (d > 0: a strictly convex 16-gon, every point a corner) or inward (d < 0: its hull is the
  // square); inside the slave [0, 1]^2 the segment is that polygon bit for bit, and a slave
  // [0, 0.5] x [0, 1] cuts it through the middle sample points
  const ClipPolygon S = parameter_rectangle(0, 1, 0, 1), half = parameter_rectangle(0, 0.5, 0, 1);
  double worst = 0;
  for (int e = -15; e <= -9; ++e)
    for (const double sign : {1.0, -1.0}) {
      const double d = sign * std::pow(10.0, e);
      const double bulge[3] = {0.75 * d, d, 0.75 * d};
      std::vector<std::array<double, 2>> pts;
      for (int s = 0; s < 4; ++s) pts.push_back({0.25 + 0.125 * s, s == 0 ? 0.25 : 0.25 - bulge[s - 1]});   // bottom
      for (int s = 0; s < 4; ++s) pts.push_back({s == 0 ? 0.75 : 0.75 + bulge[s - 1], 0.25 + 0.125 * s});   // right
      for (int s = 0; s < 4; ++s) pts.push_back({0.75 - 0.125 * s, s == 0 ? 0.75 : 0.75 + bulge[s - 1]});   // top
      for (int s = 0; s < 4; ++s) pts.push_back({s == 0 ? 0.25 : 0.25 - bulge[s - 1], 0.75 - 0.125 * s});   // left
      const ClipPolygon M = poly(pts);
      const ClipPolygon P = clip(S, M);
      EXPECT_TRUE(strictly_convex_ccw(P)) << d;
      if (d > 0) {
        EXPECT_EQ(P.n, 16) << d;
        worst = std::max(worst, static_cast<double>(std::abs(area_ld(P) - area_ld(M))));
        worst = std::max(worst, std::abs(polygon_area(P) - (0.25 + 4 * 0.3125 * d)));
      } else {
        EXPECT_EQ(P.n, 4) << d;
        worst = std::max(worst, std::abs(polygon_area(P) - 0.25));
      }
      // cut at u = 0.5 through the top and bottom middle points
      const ClipPolygon H = clip(half, M);
      EXPECT_TRUE(strictly_convex_ccw(H)) << d;
      // the left corners, 2 samples of the bottom and top edges, the middle ones on u = 0.5
      // (on the clip line: kept, no crossing), 3 of the left edge
      EXPECT_EQ(H.n, d > 0 ? 9 : 4) << d;
      // M is symmetric about u = 0.5: half its area
      const double expect_half = d > 0 ? 0.5 * (0.25 + 4 * 0.3125 * d) : 0.125;
      worst = std::max(worst, std::abs(polygon_area(H) - expect_half));
    }
  std::printf("bulged edges: worst |area - exact| %.3g\n", worst);
  EXPECT_LT(worst, 1e-15);
}

TEST(NearlyCollinear, RandomPerturbationsGiveTheExactHull) {
  // a master quad's edges sampled at 3 points each (12 points), each moved by +-1e-15..1e-9
  // across its edge, partly outside the slave: the segment must be the exact convex hull of the
  // points inside (every vertex an input point or a crossing, strictly convex, containing every
  // input point that is inside the slave) and its area within 1e-14 of the unperturbed one
  std::mt19937 gen(23);
  std::uniform_real_distribution<double> U(-1, 1);
  const ClipPolygon S = parameter_rectangle(0, 1, 0, 1);
  int checked = 0;
  double worst = 0, worst_outside = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    const double amp = std::pow(10.0, -15 + 6 * (0.5 + 0.5 * U(gen)));
    const double th = U(gen), cx = 0.5 + 0.6 * U(gen), cy = 0.5 + 0.6 * U(gen), half = 0.3 + 0.2 * U(gen);
    const ClipPolygon Q = rotated_square(cx, cy, half, th);
    std::vector<std::array<double, 2>> pts, straight;
    for (int e = 0; e < 4; ++e) {
      const double* a = Q.v[e];
      const double* b = Q.v[(e + 1) % 4];
      const double nx = b[1] - a[1], ny = a[0] - b[0];   // outward normal (times the edge length)
      for (int s = 0; s < 3; ++s) {
        const double t = s / 3.0, dd = s == 0 ? 0 : amp * U(gen);
        pts.push_back({a[0] + t * (b[0] - a[0]) + dd * nx, a[1] + t * (b[1] - a[1]) + dd * ny});
      }
    }
    const ClipPolygon M = poly(pts);
    const ClipPolygon P = clip(S, M);
    const double ref = polygon_area(clip(S, Q));
    worst = std::max(worst, std::abs(polygon_area(P) - ref));
    if (P.n == 0) continue;
    ++checked;
    ASSERT_TRUE(strictly_convex_ccw(P)) << trial;
    // every master point inside the slave is inside or on the segment
    for (const auto& x : pts) {
      if (x[0] < 0 || x[0] > 1 || x[1] < 0 || x[1] > 1) continue;
      // (a master point that the master hull dropped, within round-off of a hull edge, may be
      // outside by the round-off of a crossing on that edge: allowed 4 eps)
      for (int k = 0; k < P.n; ++k) {
        const double* a = P.v[k];
        const double* b = P.v[(k + 1) % P.n];
        const double dist = orient2d(a, b, x.data()) / std::hypot(b[0] - a[0], b[1] - a[1]);
        worst_outside = std::max(worst_outside, -dist);
        ASSERT_GE(dist, -4.5e-16) << trial;
      }
    }
    // a vertex strictly inside the slave is one of the master points, bit for bit
    for (int k = 0; k < P.n; ++k) {
      const double* v = P.v[k];
      if (v[0] <= 0 || v[0] >= 1 || v[1] <= 0 || v[1] >= 1) continue;
      // (crossings lie exactly on the slave's edges: they are put on axis-parallel lines)
      bool input = false;
      for (const auto& x : pts) input = input || (x[0] == v[0] && x[1] == v[1]);
      ASSERT_TRUE(input) << trial;
    }
    EXPECT_GE(shortest_edge(P), kClipMergeTol);
  }
  std::printf("random perturbations: %d segments checked, worst |area - unperturbed| %.3g, a master point inside the "
              "slave at most %.3g outside the segment\n",
              checked, worst, worst_outside);
  EXPECT_GT(checked, 2000);
  EXPECT_LT(worst, 1e-8);   // the perturbations themselves move the area by up to ~1e-9
}

TEST(NearlyCollinear, AVertexJustAcrossAnEdgeLeavesNoSliver) {
  // a diamond whose bottom vertex is d below the slave's edge v = 0: the two crossings are 2 d
  // apart; below kClipMergeTol they merge, above they stay a short edge; either way every
  // weight of the rule is positive and finite
  const ClipPolygon S = parameter_rectangle(0, 1, 0, 1);
  const TriangleRule g = triangle_rule_collapsed(gauss_rule(4));
  for (int e = -17; e <= -9; ++e)
    for (const double sign : {1.0, -1.0}) {
      const double d = sign * std::pow(10.0, e);
      const ClipPolygon M = poly({{0.5, -d}, {0.9, 0.4 - d}, {0.5, 0.8 - d}, {0.1, 0.4 - d}});
      const ClipPolygon P = clip(S, M);
      EXPECT_TRUE(strictly_convex_ccw(P)) << d;
      EXPECT_GE(shortest_edge(P), kClipMergeTol) << d;
      const double exact = 0.32 - (d > 0 ? d * d : 0);
      EXPECT_NEAR(polygon_area(P), exact, 1e-15) << d;
      double wsum = 0;
      for_each_polygon_point(P, g, [&](const double*, double w) {
        EXPECT_GT(w, 0);
        wsum += w;
      });
      EXPECT_NEAR(wsum, exact, 1e-15) << d;
    }
}

// ---------------------------------------------------------------------------------------------

TEST(Degenerate, TouchingAndSubRoundOffOverlapsAreEmptyWithoutNaN) {
  const ClipPolygon S = parameter_rectangle(0, 1, 0, 1);
  const TriangleRule g = triangle_rule_collapsed(gauss_rule(3));
  const ClipPolygon cases[] = {
      parameter_rectangle(1, 2, 0, 1),                  // a shared edge
      parameter_rectangle(1, 2, 0.2, 0.7),              // part of an edge
      parameter_rectangle(1, 2, 1, 2),                  // a shared corner
      poly({{1, 0.5}, {2, 0}, {2, 1}}),                 // a vertex on an edge
      poly({{1, 1}, {2, 1.5}, {1.5, 2}}),               // a vertex on a corner
      parameter_rectangle(0.2, 0.8, -1, 1e-17),         // a band below round-off
      poly({{-1, -1}, {2, 2}, {0.5, 0.5}}),             // a collinear master (the diagonal)
      poly({{0.3, 0.3}, {0.3, 0.3}, {0.3, 0.3}}),       // a master collapsed to a point
      poly({{0.2, 0.2}, {0.7, 0.4}}),                   // two points
      parameter_rectangle(3, 4, 3, 4),                  // far away
      poly({{std::nextafter(1.0, 2.0), 0}, {2, 0}, {2, 1}, {std::nextafter(1.0, 2.0), 1}}),   // one ulp beside
  };
  for (const ClipPolygon& M : cases) {
    for (int swap = 0; swap < 2; ++swap) {
      int flags = -1;
      const ClipPolygon P = swap ? clip(M, S, &flags) : clip(S, M, &flags);
      EXPECT_EQ(flags, 0);
      EXPECT_EQ(P.n, 0);
      EXPECT_EQ(polygon_area(P), 0.0);
      EXPECT_TRUE(all_finite(P));
      EXPECT_EQ(polygon_rule_size(P, g), 0);
      int calls = 0;
      for_each_polygon_point(P, g, [&](const double*, double) { ++calls; });
      EXPECT_EQ(calls, 0);
    }
  }
  // identical, and the slave given clockwise: the same square
  const ClipPolygon cw = poly({{0, 0}, {0, 1}, {1, 1}, {1, 0}});
  EXPECT_EQ(polygon_area(clip(S, S)), 1.0);
  EXPECT_EQ(polygon_area(clip(cw, S)), 1.0);
  EXPECT_EQ(polygon_area(clip(S, cw)), 1.0);
  // bad input: NaN, infinity, a count out of range
  ClipPolygon bad = parameter_rectangle(0.2, 0.5, 0.2, 0.5);
  bad.v[2][0] = std::nan("");
  int flags = 0;
  ClipPolygon P = clip(S, bad, &flags);
  EXPECT_EQ(flags, kClipBadInput);
  EXPECT_EQ(P.n, 0);
  bad.v[2][0] = HUGE_VAL;
  P = clip(bad, S, &flags);
  EXPECT_EQ(flags, kClipBadInput);
  bad = S;
  bad.n = kClipMaxVertices + 1;
  P = clip(S, bad, &flags);
  EXPECT_EQ(flags, kClipBadInput);
}

TEST(Degenerate, TooManyVerticesIsFlagged) {
  // a regular 16-gon of radius 1.05 over the square [-1, 1]^2: its 4 vertices on the axes and
  // the square's corners are outside, 12 vertices + 8 crossings = 20 > 16
  const ClipPolygon S = parameter_rectangle(-1, 1, -1, 1);
  ClipPolygon M;
  M.n = 16;
  for (int k = 0; k < 16; ++k) {
    M.v[k][0] = 1.05 * std::cos(2 * M_PI * k / 16);
    M.v[k][1] = 1.05 * std::sin(2 * M_PI * k / 16);
  }
  int flags = 0;
  const ClipPolygon P = clip(S, M, &flags);
  EXPECT_EQ(flags, kClipOverflow);
  EXPECT_EQ(P.n, 0);
  // within the bound (4 + 12): a 12-gon the same way, 8 vertices + 8 crossings
  M.n = 12;
  for (int k = 0; k < 12; ++k) {
    M.v[k][0] = 1.05 * std::cos(2 * M_PI * k / 12);
    M.v[k][1] = 1.05 * std::sin(2 * M_PI * k / 12);
  }
  const ClipPolygon Q = clip(S, M, &flags);
  EXPECT_EQ(flags, 0);
  EXPECT_EQ(Q.n, 16);
  EXPECT_TRUE(strictly_convex_ccw(Q));
}

// ---------------------------------------------------------------------------------------------

TEST(PolygonRule, MonomialsUpToTheDegreeOverClippedPolygons) {
  // closed-form check of the moment formula first: \int_[0,1]^2 x^i y^j = 1 / ((i + 1)(j + 1))
  const ClipPolygon unit = parameter_rectangle(0, 1, 0, 1);
  for (int i = 0; i <= 6; ++i)
    for (int j = 0; j <= 6; ++j) EXPECT_NEAR(static_cast<double>(moment(unit, i, j)), 1.0 / ((i + 1) * (j + 1)), 1e-17);
  // segments: an octagon, a rotated quad cut by a rectangle, a bulged 16-gon cut in half
  std::vector<ClipPolygon> segs;
  segs.push_back(clip(parameter_rectangle(-1, 1, -1, 1), rotated_square(0, 0, 1, 0.37)));
  segs.push_back(clip(parameter_rectangle(0.1, 0.9, 0.2, 0.6), poly({{0.3, 0.05}, {1.1, 0.3}, {0.8, 0.9}, {0.2, 0.5}})));
  segs.push_back(clip(parameter_rectangle(0.2, 0.5, 0.1, 0.8), rotated_square(0.45, 0.45, 0.3, 0.2)));
  for (const ClipPolygon& P : segs) ASSERT_GE(P.n, 4);
  double worst = 0;
  for (int n = 1; n <= 7; ++n) {
    const TriangleRule g = triangle_rule_collapsed(gauss_rule(n));
    const int deg = polygon_rule_degree(n);
    double inexact = 0;   // the largest error at degree deg + 1: the degree is not higher
    for (const ClipPolygon& P : segs) {
      EXPECT_EQ(polygon_rule_size(P, g), P.n * n * n);
      // the indexed points are the ones for_each visits
      std::vector<std::array<double, 3>> seen;
      for_each_polygon_point(P, g, [&](const double* x, double w) { seen.push_back({x[0], x[1], w}); });
      ASSERT_EQ(static_cast<int>(seen.size()), polygon_rule_size(P, g));
      for (int k = 0; k < polygon_rule_size(P, g); ++k) {
        double x[2], w;
        polygon_rule_point(P, g, k, x, w);
        ASSERT_EQ(x[0], seen[k][0]);
        ASSERT_EQ(x[1], seen[k][1]);
        ASSERT_EQ(w, seen[k][2]);
      }
      for (int i = 0; i <= deg + 1; ++i)
        for (int j = 0; i + j <= deg + 1; ++j) {
          const double exact = static_cast<double>(moment(P, i, j));
          const double err = std::abs(rule_integral(P, g, i, j) - exact);
          if (i + j <= deg)
            worst = std::max(worst, err);
          else
            inexact = std::max(inexact, err);
        }
    }
    // (the octagon is centrally symmetric: its odd moments come out exact at any degree)
    std::printf("  n = %d: degree %d, largest error at degree %d: %.3g\n", n, deg, deg + 1, inexact);
    if (n <= 5) {   // beyond, the error at degree 2n - 1 is near round-off on these polygons
      EXPECT_GT(inexact, 1e-12) << "n = " << n;
    }
  }
  std::printf("polygon rule: worst |rule - exact| over monomials up to degree 2n - 2, n = 1..7: %.3g\n", worst);
  EXPECT_LT(worst, 1e-14);
}

// ---------------------------------------------------------------------------------------------

// Clips every pair (slave rectangle k, master quad k) both ways in a parallel_for on the execution
// space and integrates 1 and u v with the rule g: res(k, :) = area, area swapped, rule of 1, rule
// of u v (a free function: nvcc takes no device lambda inside a gtest body, a private member).
static void clip_on_device(const Kokkos::View<double* [4], MemSpace>& slave, const Kokkos::View<double* [4][2], MemSpace>& master,
                    const TriangleRule& g, const Kokkos::View<double* [4], MemSpace>& res, const Kokkos::View<int*, MemSpace>& flags) {
  const int N = static_cast<int>(slave.extent(0));
  Kokkos::parallel_for("test::PolygonClip", Kokkos::RangePolicy<ExecSpace>(0, N), KOKKOS_LAMBDA(const int k) {
    const ClipPolygon S = parameter_rectangle(slave(k, 0), slave(k, 1), slave(k, 2), slave(k, 3));
    ClipPolygon M;
    M.n = 4;
    for (int a = 0; a < 4; ++a) {
      M.v[a][0] = master(k, a, 0);
      M.v[a][1] = master(k, a, 1);
    }
    ClipPolygon P, Q;
    flags(k) = clip_polygons(S, M, P) | clip_polygons(M, S, Q);
    double one = 0, uv = 0;
    for_each_polygon_point(P, g, [&](const double* x, double w) {
      one += w;
      uv += w * x[0] * x[1];
    });
    res(k, 0) = polygon_area(P);
    res(k, 1) = polygon_area(Q);
    res(k, 2) = one;
    res(k, 3) = uv;
  });
}

TEST(ClipKernel, ManyPairsInAParallelFor) {
  // random slave rectangles and master quads (rotated, sheared, some far away) in views; a
  // Kokkos::parallel_for clips every pair both ways and integrates 1 and u v with the rule
  const int N = 20000;
  Kokkos::View<double* [4], MemSpace> slave("slave", N);
  Kokkos::View<double* [4][2], MemSpace> master("master", N);
  auto hs = Kokkos::create_mirror_view(slave);
  auto hm = Kokkos::create_mirror_view(master);
  std::mt19937 gen(31);
  std::uniform_real_distribution<double> U(0, 1);
  for (int k = 0; k < N; ++k) {
    const double u0 = U(gen), v0 = U(gen);
    hs(k, 0) = u0;
    hs(k, 1) = u0 + 0.1 + U(gen);
    hs(k, 2) = v0;
    hs(k, 3) = v0 + 0.1 + U(gen);
    const ClipPolygon Q = rotated_square(0.2 + 1.5 * U(gen), 0.2 + 1.5 * U(gen), 0.1 + 0.5 * U(gen), 6 * U(gen));
    for (int a = 0; a < 4; ++a)
      for (int c = 0; c < 2; ++c) hm(k, a, c) = Q.v[a][c] + 0.05 * (U(gen) - 0.5);   // a general quad
  }
  Kokkos::deep_copy(slave, hs);
  Kokkos::deep_copy(master, hm);
  Kokkos::View<double* [4], MemSpace> res("res", N);   // area, area swapped, rule of 1, rule of u v
  Kokkos::View<int*, MemSpace> flags("flags", N);
  const TriangleRule g = triangle_rule_collapsed(gauss_rule(3));
  clip_on_device(slave, master, g, res, flags);
  Kokkos::fence();
  auto hr = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), res);
  auto hf = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), flags);
  int nonempty = 0;
  double worst_swap = 0, worst_rule = 0, worst_uv = 0;
  for (int k = 0; k < N; ++k) {
    ASSERT_EQ(hf(k), 0);
    const ClipPolygon S = parameter_rectangle(hs(k, 0), hs(k, 1), hs(k, 2), hs(k, 3));
    ClipPolygon M;
    M.n = 4;
    for (int a = 0; a < 4; ++a)
      for (int c = 0; c < 2; ++c) M.v[a][c] = hm(k, a, c);
    const ClipPolygon P = clip(S, M);
    const double scale = (hs(k, 1) - hs(k, 0)) * (hs(k, 3) - hs(k, 2));
    nonempty += P.n > 0;
    EXPECT_NEAR(hr(k, 0), static_cast<double>(area_ld(P)), 1e-15 * scale);
    worst_swap = std::max(worst_swap, std::abs(hr(k, 0) - hr(k, 1)) / scale);
    worst_rule = std::max(worst_rule, std::abs(hr(k, 2) - hr(k, 0)) / scale);
    worst_uv = std::max(worst_uv, std::abs(hr(k, 3) - static_cast<double>(moment(P, 1, 1))) / scale);
  }
  std::printf("kernel: %d pairs, %d overlapping; worst relative |area - swapped roles| %.3g, |rule of 1 - area| %.3g, "
              "|rule of uv - exact| %.3g\n",
              N, nonempty, worst_swap, worst_rule, worst_uv);
  EXPECT_GT(nonempty, N / 4);
  EXPECT_LT(worst_swap, 1e-14);
  EXPECT_LT(worst_rule, 1e-14);
  EXPECT_LT(worst_uv, 1e-14);
}
