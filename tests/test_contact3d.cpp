// 3-D contact geometry kernels (kernels/contact_surface.hpp): closest-point projection onto a
// NURBS surface and the bin search over its elements.
//   SurfaceProjection  points around the outer face of a sphere octant (an exact rational
//                      surface with a degenerate pole edge) project onto the sphere: distance
//                      |r - R| and foot R x / |x| to 1e-10, through the search (a Kokkos
//                      parallel_for) and against projecting on every element
//   SurfaceDerivatives the first and second derivatives of the rational surface against
//                      central differences
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "kernels/contact_surface.hpp"
#include "model/nurbs.hpp"
#include "tests/surfaces3d.hpp"

using namespace iga;
using iga::test3d::sphere_octant;
using iga::test3d::surface_of;

namespace {

// The kernels' device functions called from the tests, each in a parallel_for on the execution
// space (SurfaceData holds views of MemSpace, which the host cannot read on a GPU build; and
// nvcc takes no device lambda inside a gtest body, a private member).

void derivatives_on_device(const SurfaceData& sd, const int s[2], double u, double v, double d[6][3]) {
  Kokkos::View<double[6][3], MemSpace> out("d");
  const int s0 = s[0], s1 = s[1];
  Kokkos::parallel_for("test::SurfaceDerivatives", Kokkos::RangePolicy<ExecSpace>(0, 1), KOKKOS_LAMBDA(const int) {
    const int ss[2] = {s0, s1};
    double dd[6][3];
    surface_derivatives(sd, ss, u, v, dd);
    for (int i = 0; i < 6; ++i)
      for (int c = 0; c < 3; ++c) out(i, c) = dd[i][c];
  });
  auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), out);
  for (int i = 0; i < 6; ++i)
    for (int c = 0; c < 3; ++c) d[i][c] = h(i, c);
}

// closest_on_surface for every point X(k, :): out(k, :) = element (-1: none found), inside (1 or
// 0), distance, foot
void project_on_device(const SurfaceData& sd, const SurfaceSearch& g, const Kokkos::View<double* [3], MemSpace>& X,
                       const Kokkos::View<double* [6], MemSpace>& out) {
  Kokkos::parallel_for("test::ProjectOnSphere", Kokkos::RangePolicy<ExecSpace>(0, X.extent(0)), KOKKOS_LAMBDA(const int k) {
    const double x[3] = {X(k, 0), X(k, 1), X(k, 2)};
    double uv[2], foot[3], d2;
    bool inside = false;
    const int e = closest_on_surface(sd, g, x, 0.5, uv, foot, d2, inside);
    out(k, 0) = e;
    out(k, 1) = inside ? 1 : 0;
    out(k, 2) = kmath::sqrt(d2);
    for (int c = 0; c < 3; ++c) out(k, 3 + c) = foot[c];
  });
}

// one point through closest_on_surface: the element (-1: none found), inside or not, the foot
int closest_on_device(const SurfaceData& sd, const SurfaceSearch& g, const double x[3], bool& inside, double foot[3]) {
  Kokkos::View<double* [3], MemSpace> X("X", 1);
  Kokkos::View<double* [6], MemSpace> out("out", 1);
  auto hX = Kokkos::create_mirror_view(X);
  for (int c = 0; c < 3; ++c) hX(0, c) = x[c];
  Kokkos::deep_copy(X, hX);
  project_on_device(sd, g, X, out);
  auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), out);
  for (int c = 0; c < 3; ++c) foot[c] = h(0, 3 + c);
  inside = h(0, 1) == 1;
  return static_cast<int>(h(0, 0));
}

// the squared distance of x to the surface: the least over a projection on every element
double nearest_over_all_elements(const SurfaceData& sd, const double x[3]) {
  const double x0 = x[0], x1 = x[1], x2 = x[2];
  double best = 0;
  Kokkos::parallel_reduce("test::ProjectOnEveryElement", Kokkos::RangePolicy<ExecSpace>(0, sd.ne[0] * sd.ne[1]),
                          KOKKOS_LAMBDA(const int e, double& m) {
                            const double y[3] = {x0, x1, x2};
                            double uv[2], foot[3];
                            bool in;
                            const double d2 = project_on_surface_element(sd, e, y, uv, foot, in);
                            if (d2 < m) m = d2;
                          },
                          Kokkos::Min<double>(best));
  return best;
}

}  // namespace


TEST(SurfaceDerivatives, AgainstCentralDifferences) {
  const Patch F = sphere_octant(2.0, 3).face(Side::Back);
  const SurfaceData sd = surface_of(F);
  std::mt19937 gen(5);
  std::uniform_real_distribution<double> U(0.02, 0.98);
  double worst1 = 0, worst2 = 0;
  for (int k = 0; k < 20; ++k) {
    const double u = U(gen), v = U(gen), h = 1e-5;
    const int s[2] = {find_span(sd.n[0], sd.p[0], u, F.knots[0].data()), find_span(sd.n[1], sd.p[1], v, F.knots[1].data())};
    double d[6][3], dp[6][3], dm[6][3], ep[6][3], em[6][3];
    derivatives_on_device(sd, s, u, v, d);
    derivatives_on_device(sd, s, u + h, v, dp);
    derivatives_on_device(sd, s, u - h, v, dm);
    derivatives_on_device(sd, s, u, v + h, ep);
    derivatives_on_device(sd, s, u, v - h, em);
    for (int c = 0; c < 3; ++c) {
      worst1 = std::max({worst1, std::abs((dp[0][c] - dm[0][c]) / (2 * h) - d[1][c]), std::abs((ep[0][c] - em[0][c]) / (2 * h) - d[2][c])});
      worst2 = std::max({worst2, std::abs((dp[1][c] - dm[1][c]) / (2 * h) - d[3][c]), std::abs((ep[1][c] - em[1][c]) / (2 * h) - d[4][c]),
                         std::abs((ep[2][c] - em[2][c]) / (2 * h) - d[5][c])});
    }
  }
  // central differences: O(h^2) ~ 1e-10 times the third derivatives (~ R per unit parameter cubed)
  EXPECT_LT(worst1, 1e-7);
  EXPECT_LT(worst2, 1e-6);
}

TEST(SurfaceProjection, PointsAroundASphereFaceFindTheirRadialFoot) {
  const double R = 2.0;
  const Patch F = sphere_octant(R, 6).face(Side::Back);
  const SurfaceData sd = surface_of(F);
  const SurfaceSearch g = SurfaceSearch::build(sd);
  // points at radii R - 0.3 .. R + 0.3 inside the octant's cone (longitude and latitude in
  // [0.05, 0.95] x 90 degrees: their foot is inside the face)
  const int n = 2000;
  Kokkos::View<double* [3], MemSpace> X("X", n);
  auto hX = Kokkos::create_mirror_view(X);
  std::mt19937 gen(11);
  std::uniform_real_distribution<double> A(0.05 * M_PI / 2, 0.95 * M_PI / 2), Rr(R - 0.3, R + 0.3);
  for (int k = 0; k < n; ++k) {
    const double lon = A(gen), lat = A(gen), r = Rr(gen);
    hX(k, 0) = r * std::cos(lat) * std::cos(lon);
    hX(k, 1) = r * std::cos(lat) * std::sin(lon);
    hX(k, 2) = r * std::sin(lat);
  }
  Kokkos::deep_copy(X, hX);
  Kokkos::View<double* [6], MemSpace> out("out", n);   // element, inside, distance, foot
  project_on_device(sd, g, X, out);
  auto ho = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), out);
  double worst_d = 0, worst_f = 0;
  int brute_checked = 0;
  for (int k = 0; k < n; ++k) {
    ASSERT_TRUE(ho(k, 0) >= 0 && ho(k, 1) == 1) << "point " << k << " found no foot inside an element";
    const double x[3] = {hX(k, 0), hX(k, 1), hX(k, 2)};
    const double r = std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
    worst_d = std::max(worst_d, std::abs(ho(k, 2) - std::abs(r - R)));
    for (int c = 0; c < 3; ++c) worst_f = std::max(worst_f, std::abs(ho(k, 3 + c) - R * x[c] / r));
    // every 50th point: the search's answer is the best over all elements
    if (k % 50 == 0) {
      const double best = nearest_over_all_elements(sd, x);
      EXPECT_NEAR(std::sqrt(best), ho(k, 2), 1e-12);
      ++brute_checked;
    }
  }
  std::printf("  sphere face, %d x %d elements: %d points, max |distance - |r - R|| %.1e, max |foot - R x/|x|| %.1e (%d checked against all elements)\n",
              sd.ne[0], sd.ne[1], n, worst_d, worst_f, brute_checked);
  EXPECT_LT(worst_d, 1e-10 * R);
  EXPECT_LT(worst_f, 1e-10 * R);
  // a point beside the face (longitude -5 degrees: beyond its west edge) finds the edge,
  // clamped, and says it lies outside the surface
  {
    const double lon = -5.0 * M_PI / 180, lat = 0.6, r = R + 0.02;
    const double x[3] = {r * std::cos(lat) * std::cos(lon), r * std::cos(lat) * std::sin(lon), r * std::sin(lat)};
    double foot[3];
    bool inside = true;
    EXPECT_GE(closest_on_device(sd, g, x, inside, foot), 0);
    EXPECT_FALSE(inside);
    EXPECT_NEAR(foot[1], 0.0, 1e-12);   // on the edge y = 0
  }
  // a point farther than the radius from the surface finds nothing
  {
    const double x[3] = {0.1, 0.1, 0.1};
    double foot[3];
    bool inside;
    EXPECT_EQ(closest_on_device(sd, g, x, inside, foot), -1);
  }
}
