// Multi-patch bodies (conforming interfaces, merged control points, patch<k>.<side> names,
// chains of patch sides), against single-patch answers and closed-form solutions
// (../shared/reference-solutions.md): the Lame cylinder, split and as a whole ring.
#include <cmath>
#include <sstream>

#include "support.hpp"

using namespace iga;
using namespace iga::test;

namespace {

// --- Lame: thick-walled cylinder, a = 1, b = 2, p = 10, E = 2e5, nu = 0.3, plane strain ---
constexpr double kA = 1.0, kB = 2.0, kP = 10.0, kE = 2.0e5, kNu = 0.3;

Exact lame_exact() { return lame_cylinder(kA, kB, kP, kE, kNu); }

// Control points of an exact circular arc of degree 2 from angle t0 to t1 (< 180 degrees) at
// radius r, as "[x, y, w]" rows (the middle one at the tangents' intersection).
std::vector<std::array<double, 3>> arc(double r, double t0, double t1) {
  const double h = 0.5 * (t1 - t0), m = 0.5 * (t0 + t1), c = std::cos(h);
  return {{r * std::cos(t0), r * std::sin(t0), 1.0}, {r / c * std::cos(m), r / c * std::sin(m), c}, {r * std::cos(t1), r * std::sin(t1), 1.0}};
}

// An annular sector patch of degree [2, 1] from angle t0 to t1: xi along the arc, eta from the
// inner radius a to the outer b.
std::string sector(double t0, double t1) {
  std::ostringstream os;
  os.precision(17);
  os << "{degree: [2, 1], knots: [[0, 0, 0, 1, 1, 1], [0, 0, 1, 1]], control_points: [";
  bool first = true;
  for (double r : {kA, kB})
    for (const auto& p : arc(r, t0, t1)) {
      os << (first ? "" : ", ") << "[" << p[0] << ", " << p[1] << ", " << p[2] << "]";
      first = false;
    }
  os << "]}";
  return os.str();
}

std::string head() {
  std::ostringstream os;
  os << "bodies:\n  - name: cyl\n    material: {youngs_modulus: " << kE << ", poisson_ratio: " << kNu << "}\n";
  return os.str();
}
const char* kDirect = "solver: {linear: {method: direct}}\n";

// The quarter annulus as one patch with a C0 line at 45 degrees (knot 0.5 twice), or as two
// patches meeting there: the same discrete space.
std::string quarter_one_patch(int e, int n) {
  std::ostringstream os;
  os.precision(17);
  const double q = M_PI / 4;
  os << head() << "    geometry:\n      nurbs:\n        degree: [2, 1]\n"
     << "        knots: [[0, 0, 0, 0.5, 0.5, 1, 1, 1], [0, 0, 1, 1]]\n        control_points: [";
  bool first = true;
  for (double r : {kA, kB}) {
    auto a0 = arc(r, 0, q), a1 = arc(r, q, 2 * q);
    a0.insert(a0.end(), a1.begin() + 1, a1.end());
    for (const auto& p : a0) {
      os << (first ? "" : ", ") << "[" << p[0] << ", " << p[1] << ", " << p[2] << "]";
      first = false;
    }
  }
  os << "]\n    refine: {degree_elevate: [" << e << ", " << e + 1 << "], subdivide: [" << n << ", " << 2 * n << "]}\n"
     << "    boundary:\n      west: {displacement: {y: 0}}\n      east: {displacement: {x: 0}}\n      south: {pressure: " << kP
     << "}\n"
     << kDirect;
  return os.str();
}

std::string quarter_two_patches(int e, int n, bool second_reversed = false) {
  std::ostringstream os;
  const double q = M_PI / 4;
  os << head() << "    geometry:\n      patches:\n        - " << sector(0, q) << "\n        - " << sector(q, 2 * q) << "\n"
     << "    refine: {degree_elevate: [" << e << ", " << e + 1 << "], subdivide: [" << n << ", " << 2 * n << "]}\n"
     << "    boundary:\n      patch0.west: {displacement: {y: 0}}\n      patch1.east: {displacement: {x: 0}}\n"
     << "      patch0.south: {pressure: " << kP << "}\n      patch1.south: {pressure: " << kP << "}\n"
     << kDirect;
  (void)second_reversed;
  return os.str();
}

// The whole ring as four quarter patches, no symmetry conditions: rigid motion is removed
// by three point constraints at inner corners, which the radial solution satisfies
// ((1, 0) and (-1, 0) move along x, (0, 1) along y).
std::string ring_four_patches(int e, int n, const std::string& solver = kDirect) {
  std::ostringstream os;
  os << head() << "    geometry:\n      patches:\n";
  for (int k = 0; k < 4; ++k) os << "        - " << sector(k * M_PI / 2, (k + 1) * M_PI / 2) << "\n";
  os << "    refine: {degree_elevate: [" << e << ", " << e + 1 << "], subdivide: [" << n << ", " << n << "]}\n"
     << "    boundary:\n";
  for (int k = 0; k < 4; ++k) os << "      patch" << k << ".south: {pressure: " << kP << "}\n";
  os << "      patch0.south_west: {displacement: {y: 0}}\n      patch1.south_west: {displacement: {x: 0}}\n"
     << "      patch2.south_west: {displacement: {y: 0}}\n"
     << solver;
  return os.str();
}

std::string quarter_single(int e, int n) {
  std::ostringstream os;
  os << head() << "    geometry: {quarter_annulus: {center: [0, 0], inner_radius: " << kA << ", outer_radius: " << kB << "}}\n"
     << "    refine: {degree_elevate: [" << e << ", " << e + 1 << "], subdivide: [" << n << ", " << n << "]}\n"
     << "    boundary:\n      west: {displacement: {y: 0}}\n      east: {displacement: {x: 0}}\n      south: {pressure: " << kP << "}\n"
     << kDirect;
  return os.str();
}

bool root() { return Tpetra::getDefaultComm()->getRank() == 0; }

}  // namespace

TEST(MultiPatchTopology, InterfacesAreFoundAndControlPointsMerged) {
  const Problem P = parse_problem(ring_four_patches(0, 2), "ring.yaml");
  const Body& b = P.bodies[0];
  ASSERT_EQ(b.patches.size(), 4u);
  EXPECT_EQ(b.interfaces.size(), 4u);   // a closed ring: 4 radial joints
  // 4 patches of 5 x 3 control points, sharing 4 radial rows of 3
  EXPECT_EQ(b.num_cps, 4 * 15 - 4 * 3);
  for (const Interface& f : b.interfaces) EXPECT_FALSE(f.reversed);   // east of k meets west of k + 1 in the same direction
  // a merged control point has one position
  for (size_t p = 0; p < 4; ++p)
    for (size_t q = 0; q < 4; ++q)
      for (size_t a = 0; a < b.patches[p].cp.size(); ++a)
        for (size_t c = 0; c < b.patches[q].cp.size(); ++c)
          if (b.cp_index[p][a] == b.cp_index[q][c]) {
            EXPECT_NEAR(b.patches[p].cp[a].x[0], b.patches[q].cp[c].x[0], 1e-14);
            EXPECT_NEAR(b.patches[p].cp[a].x[1], b.patches[q].cp[c].x[1], 1e-14);
          }
}

TEST(MultiPatchTopology, ChainOfSidesIsOneC0Curve) {
  const Problem P = parse_problem(ring_four_patches(0, 2, "") +
                                      "  - name: pad\n    material: {youngs_modulus: 1, poisson_ratio: 0.3}\n"
                                      "    geometry: {rectangle: {origin: [-1, -4], size: [2, 1]}}\n"
                                      "    boundary: {south: {displacement: {x: 0, y: 0}}}\n"
                                      "contact:\n  - {master: {body: pad, side: north}, slave: {body: cyl, side: [patch3.north, patch2.north, patch0.north]}, "
                                      "method: kts_penalty, penalty: 1.0}\n",
                                  "ring.yaml");
  const SurfaceChain ch = surface_chain(P, P.contact[0].slave);
  // ordered head to tail from the open end: patch2 (180..270), patch3 (270..360), patch0 (0..90)
  ASSERT_EQ(ch.pieces.size(), 3u);
  EXPECT_EQ(ch.pieces[0].side.patch, 2);
  EXPECT_EQ(ch.pieces[1].side.patch, 3);
  EXPECT_EQ(ch.pieces[2].side.patch, 0);
  EXPECT_FALSE(ch.closed);
  // the curve is the outer circle: |x| = 2 everywhere, on [0, 3]
  EXPECT_EQ(ch.curve.knots.front(), 0.0);
  EXPECT_EQ(ch.curve.knots.back(), 3.0);
  for (double t = 0; t <= 3.0; t += 0.0625) {
    const auto x = ch.curve.eval(t);
    EXPECT_NEAR(std::hypot(x[0], x[1]), kB, 1e-13) << t;
  }
  // outward normal: the ring's outer side
  const auto x0 = ch.curve.eval(1.5), x1 = ch.curve.eval(1.5 + 1e-6);
  const double n[2] = {ch.normal_sign * (x1[1] - x0[1]), -ch.normal_sign * (x1[0] - x0[0])};
  EXPECT_GT(n[0] * x0[0] + n[1] * x0[1], 0.0);
  // locate: chain parameter -> patch point
  double u, v;
  EXPECT_EQ(ch.locate(P.bodies[0].patches, 2.5, u, v), 0);
  EXPECT_NEAR(u, 0.5, 1e-15);
  EXPECT_EQ(v, 1.0);
}

TEST(SplitQuarterAnnulus, TwoPatchesGiveTheSinglePatchAnswer) {
  // the same space (a C0 line inside one patch, or two patches meeting there): the same
  // discrete solution, to the direct solver's round-off
  for (int e : {0, 1}) {
    const Solved one = solve_text(quarter_one_patch(e, 4));
    const Solved two = solve_text(quarter_two_patches(e, 4));
    ASSERT_TRUE(one.res.converged);
    ASSERT_TRUE(two.res.converged);
    EXPECT_EQ(one.sys->num_dofs(), two.sys->num_dofs());
    if (!root()) continue;
    const double ref = std::hypot(lame_exact().u(1, 0)[0], 0.0);
    double worst = 0;
    for (double t : {0.0, 0.1, 0.37, 0.5, 0.5001, 0.83, 1.0})
      for (double r : {0.0, 0.3, 1.0}) {
        const BodyField f1(one.P, 0, one.disp[0]);
        // t in [0, 1] along the quarter: patch 0 holds [0, 0.5], patch 1 [0.5, 1]
        const int k = t < 0.5 ? 0 : 1;
        const BodyField f2(two.P, 0, two.disp[0], k);
        const FieldPoint a = f1.eval(t, r), b = f2.eval(k == 0 ? 2 * t : 2 * t - 1, r);
        ASSERT_NEAR(a.x, b.x, 1e-13);
        ASSERT_NEAR(a.y, b.y, 1e-13);
        worst = std::max({worst, std::abs(a.ux - b.ux), std::abs(a.uy - b.uy)});
        EXPECT_NEAR(a.sxx, b.sxx, 1e-8 * kP);
        EXPECT_NEAR(a.syy, b.syy, 1e-8 * kP);
      }
    std::printf("  split quarter annulus, p = %d: max |u_one - u_two| / |u| = %.2e\n", 2 + e, worst / ref);
    EXPECT_LT(worst, 1e-10 * ref);
    const Errors e1 = l2_errors(one, 0, lame_exact()), e2 = l2_errors(two, 0, lame_exact());
    EXPECT_NEAR(e1.u_rel, e2.u_rel, 1e-8 * e1.u_rel);
  }
}

TEST(RingOfFourPatches, LameWithoutSymmetryConditionsConvergesLikeTheQuarter) {
  // The discrete ring solution is unique (three point constraints) and, by symmetry, the
  // quarter's rotated: its errors equal the quarter's, and fall at the optimal rates.
  for (int e : {0, 1}) {
    std::vector<Errors> ring, quarter;
    for (int n : {2, 4, 8}) {
      const Solved s = solve_text(ring_four_patches(e, n));
      const Solved q = solve_text(quarter_single(e, n));
      ASSERT_TRUE(s.res.converged);
      ASSERT_TRUE(q.res.converged);
      // the point constraints carry no load (the solution is radial)
      const auto R = total_reaction(*s.sys, *s.res.residual);
      const auto reac = reactions_json(*s.sys, *s.res.residual);
      if (root()) {
        for (const auto& side : reac["cyl"])
          for (int c = 0; c < 2; ++c) EXPECT_LT(std::abs(side[c].get<double>()), 1e-8 * kP * kA);
        ring.push_back(l2_errors(s, 0, lame_exact()));
        quarter.push_back(l2_errors(q, 0, lame_exact()));
      }
      (void)R;
    }
    if (!root()) continue;
    for (size_t k = 0; k < ring.size(); ++k) {
      std::printf("  ring of 4 patches, p = %d, n = %d: |u - uh|/|u| = %.4e (quarter %.4e), |s - sh|/|s| = %.4e (quarter %.4e)\n",
                  2 + e, 2 << k, ring[k].u_rel, quarter[k].u_rel, ring[k].s_rel, quarter[k].s_rel);
      EXPECT_NEAR(ring[k].u_rel, quarter[k].u_rel, 1e-6 * quarter[k].u_rel);
      EXPECT_NEAR(ring[k].s_rel, quarter[k].s_rel, 1e-6 * quarter[k].s_rel);
    }
    const double ru = std::log2(ring[1].u_rel / ring[2].u_rel), rs = std::log2(ring[1].s_rel / ring[2].s_rel);
    std::printf("  rates p = %d: u %.2f, stress %.2f\n", 2 + e, ru, rs);
    EXPECT_GT(ru, 2 + e + 1 - 0.3);   // p + 1
    EXPECT_GT(rs, 2 + e - 0.3);       // p
  }
}

// --- A whole wheel of four patches pressed onto a block, against Hertz ---------------------
namespace {

// Rim radius R = 1, hub radius 0.2, centre (0, 1) (touching y = 0); patch k spans the angles
// [offset + 90 k, offset + 90 (k + 1)] (degrees). offset 45: the contact point (270) lies in the
// middle of patch 2; offset 0: on the joint of patches 2 and 3. The hub (each patch's south
// side) is pushed down by d; the block [-1, 1] x [-1, 0] is held at its base.
std::string whole_wheel(double offset_deg, const std::string& method, int n) {
  std::ostringstream os;
  os.precision(17);
  os << "analysis: {type: plane_strain, load_steps: 2}\nbodies:\n"
     << "  - name: block\n    material: {youngs_modulus: 1000.0, poisson_ratio: 0.3}\n"
     << "    geometry: {rectangle: {origin: [-1.0, -1.0], size: [2.0, 1.0]}}\n"
     << "    refine: {degree_elevate: 1, insert_knots: [[0.3, 0.4, 0.45, 0.475, 0.5, 0.525, 0.55, 0.6, 0.7], [0.5, 0.75, 0.875, 0.9375]],"
     << " subdivide: [" << n / 16 << ", " << n / 16 << "]}\n"
     << "    boundary: {south: {displacement: {x: 0.0, y: 0.0}}}\n"
     << "  - name: wheel\n    material: {youngs_modulus: 1000.0, poisson_ratio: 0.3}\n    geometry:\n      patches:\n";
  for (int k = 0; k < 4; ++k) {
    const double t0 = (offset_deg + 90.0 * k) * M_PI / 180, t1 = t0 + M_PI / 2;
    os << "        - {degree: [2, 1], knots: [[0, 0, 0, 1, 1, 1], [0, 0, 1, 1]], control_points: [";
    bool first = true;
    for (double r : {0.2, 1.0})
      for (auto p : arc(r, t0, t1)) {
        os << (first ? "" : ", ") << "[" << p[0] << ", " << p[1] + 1.0 << ", " << p[2] << "]";
        first = false;
      }
    os << "]}\n";
  }
  os << "    refine: {degree_elevate: [0, 1], insert_knots: [[], [0.5, 0.75, 0.875, 0.9375, 0.96875]], subdivide: [" << n << ", 2]}\n"
     << "    boundary:\n";
  for (int k = 0; k < 4; ++k) os << "      patch" << k << ".south: {displacement: {x: 0.0, y: -0.004}}\n";
  os << "contact:\n  - master: {body: block, side: north}\n"
     << "    slave: {body: wheel, side: [patch0.north, patch1.north, patch2.north, patch3.north]}\n"
     << "    method: " << method << "\n    penalty: 1.0e6\n"
     << "solver: {linear: {method: direct}}\n";
  return os.str();
}

}  // namespace

class WholeWheel : public ::testing::TestWithParam<std::tuple<const char*, double>> {};

TEST_P(WholeWheel, HertzAcrossAndInsideAPatch) {
  const auto [method, offset] = GetParam();
  const int n = std::getenv("WHEEL_N") ? std::atoi(std::getenv("WHEEL_N")) : 192;
  const Solved s = solve_text(whole_wheel(offset, method, n));
  ASSERT_TRUE(s.res.converged) << s.res.message;
  const ContactSummary c = s.res.contact[0].summary();
  const double R = 1.0, E = 1000.0, nu = 0.3, Estar = 1.0 / (2 * (1 - nu * nu) / E);
  const double Pn = c.normal_force;   // the whole wheel
  const double a = std::sqrt(4 * Pn * R / (M_PI * Estar)), p0 = 2 * Pn / (M_PI * a);
  // contact half-width: half the distance between the gap's zero crossings at the two ends
  // of the active zone (points run along the rim)
  const auto st = s.res.contact[0].state();
  std::vector<double> edges;
  for (size_t i = 0; i + 1 < st.x.size(); ++i)
    if (st.active[i] != st.active[i + 1]) {
      const double t = st.gap[i] / (st.gap[i] - st.gap[i + 1]);
      edges.push_back(st.x[i] + t * (st.x[i + 1] - st.x[i]));
    }
  ASSERT_EQ(edges.size(), 2u) << "one contact zone";
  const double half = 0.5 * std::abs(edges[1] - edges[0]);
  std::printf("  %s, patches from %g deg: P = %.5g: p0 = %.5g (Hertz %.5g, %+.2f %%), a = %.5g (Hertz %.5g, %+.2f %%), Fx = %.2e\n",
              method, offset, Pn, c.max_pressure, p0, 100 * (c.max_pressure / p0 - 1), half, a, 100 * (half / a - 1), c.fx);
  EXPECT_LT(a / R, 0.1);
  EXPECT_NEAR(c.max_pressure, p0, 0.05 * p0);
  EXPECT_NEAR(half, a, 0.05 * a);
  EXPECT_LT(std::abs(c.fx), 1e-6 * Pn);   // symmetric about x = 0
  EXPECT_NEAR(0.5 * (edges[0] + edges[1]), 0.0, 0.02 * a);
}

INSTANTIATE_TEST_SUITE_P(MethodsAndJoints, WholeWheel,
                         ::testing::Combine(::testing::Values("kts_penalty", "mortar_penalty"), ::testing::Values(45.0, 0.0)));

// --- Kirsch: the plate with a hole read from a G+Smo file (two patches) --------------------
namespace {
constexpr double kT = 10.0, kRh = 1.0;
Exact kirsch_exact(double E, double nu) { return kirsch_plate(kRh, kT, E, nu); }

// examples/geometry/plate_with_hole.{xml,txt}: [0, 4]^2 minus the disc r < 1; named boundaries
// hole, bottom (y = 0), right (x = 4, patch 0 east), top (y = 4, patch 1 east), left (x = 0).
Solved kirsch_from_file(const std::string& file, int e, int n) {
  std::ostringstream os;
  os << "bodies:\n  - name: plate\n    material: {youngs_modulus: 1.0e5, poisson_ratio: 0.3}\n"
     << "    geometry: {file: " << IGACONTACT_SOURCE_DIR << "/examples/geometry/" << file << "}\n"
     << "    refine: {degree_elevate: " << e << ", subdivide: [" << n << ", " << n << "]}\n"
     << "    boundary:\n      bottom: {displacement: {y: 0}}\n      left: {displacement: {x: 0}}\n"
     << "solver: {linear: {method: direct}}\n";
  const Exact ex = kirsch_exact(1.0e5, 0.3);
  return solve_text(os.str(), Tpetra::getDefaultComm(), [ex](System& sys) {
    sys.add_traction(0, Side::East, [ex](double x, double y) { const auto s = ex.sigma(x, y); return std::array<double, 2>{s[0], s[2]}; }, 0);
    sys.add_traction(0, Side::East, [ex](double x, double y) { const auto s = ex.sigma(x, y); return std::array<double, 2>{s[2], s[1]}; }, 1);
  });
}
}  // namespace

TEST(KirschFromGeometryFile, TwoPatchPlateConvergesAtOptimalRates) {
  const Exact ex = kirsch_exact(1.0e5, 0.3);
  for (int e : {0, 1}) {
    std::vector<Errors> errs;
    for (int n : {4, 8, 16, 32}) {
      const Solved s = kirsch_from_file("plate_with_hole.xml", e, n);
      ASSERT_TRUE(s.res.converged);
      ASSERT_EQ(s.P.bodies[0].patches.size(), 2u);
      if (root()) errs.push_back(l2_errors(s, 0, ex, 3));
      if (n == 8 && e == 0) {
        // the GeoPDEs file of the same geometry: the same answer
        const Solved t = kirsch_from_file("plate_with_hole.txt", e, n);
        if (root()) {
          const Errors et = l2_errors(t, 0, ex, 3);
          EXPECT_NEAR(et.u_rel, errs.back().u_rel, 1e-9 * errs.back().u_rel);
        }
      }
    }
    if (!root()) continue;
    for (size_t k = 0; k < errs.size(); ++k)
      std::printf("  Kirsch from G+Smo file, p = %d, n = %2d: |u - uh|/|u| = %.3e  |s - sh|/|s| = %.3e\n", 2 + e, 4 << k,
                  errs[k].u_rel, errs[k].s_rel);
    // the stress error is pre-asymptotic on the coarse meshes (rates rising towards p): the
    // finest pair decides
    const double ru = std::log2(errs[2].u_rel / errs[3].u_rel), rs = std::log2(errs[2].s_rel / errs[3].s_rel);
    std::printf("  rates p = %d: u %.2f, stress %.2f\n", 2 + e, ru, rs);
    EXPECT_GT(ru, 2 + e + 1 - 0.3);
    EXPECT_GT(rs, 2 + e - 0.3);
  }
}

// ---- 3-D: trivariate patches sharing faces ----
namespace {

std::vector<double> greville_of(const std::vector<double>& U, int p) {
  std::vector<double> g;
  for (size_t i = 0; i + p + 1 < U.size(); ++i) {
    double s = 0;
    for (int k = 1; k <= p; ++k) s += U[i + k];
    g.push_back(s / p);
  }
  return g;
}

// Box [o, o + L] with knot vectors U (x, y, z directions), control points at the Greville
// abscissae (the map is affine).
Patch box3(std::array<double, 3> o, std::array<double, 3> L, std::array<int, 3> p, std::array<std::vector<double>, 3> U) {
  Patch P;
  P.pdim = 3;
  for (int d = 0; d < 3; ++d) P.degree[d] = p[d], P.knots[d] = U[d];
  const auto g0 = greville_of(U[0], p[0]), g1 = greville_of(U[1], p[1]), g2 = greville_of(U[2], p[2]);
  for (double z : g2)
    for (double y : g1)
      for (double x : g0) P.cp.push_back(ControlPoint({o[0] + L[0] * x, o[1] + L[1] * y, o[2] + L[2] * z}, 1.0));
  return P;
}

// P with its parametric directions relabelled: direction d of the result is direction perm[d]
// of P, reversed where rev[d]. Same geometry, another parametrisation.
Patch relabel(const Patch& P, std::array<int, 3> perm, std::array<bool, 3> rev) {
  Patch Q;
  Q.pdim = 3;
  for (int d = 0; d < 3; ++d) {
    Q.degree[d] = P.degree[perm[d]];
    Q.knots[d] = P.knots[perm[d]];
    if (rev[d]) {
      const auto& U = P.knots[perm[d]];
      for (size_t m = 0; m < U.size(); ++m) Q.knots[d][m] = U.front() + U.back() - U[U.size() - 1 - m];
    }
  }
  Q.cp.resize(P.cp.size());
  for (int k = 0; k < Q.ncp(2); ++k)
    for (int j = 0; j < Q.ncp(1); ++j)
      for (int i = 0; i < Q.ncp(0); ++i) {
        const int q[3] = {i, j, k};
        int src[3];
        for (int d = 0; d < 3; ++d) src[perm[d]] = rev[d] ? Q.ncp(d) - 1 - q[d] : q[d];
        Q.cp[Q.index(i, j, k)] = P.cp[P.index(src[0], src[1], src[2])];
      }
  return Q;
}

// Every merged id has one position, and distinct ids distinct positions (the boxes' control
// points lie on a grid with spacing >= 0.1).
void expect_merged_by_position(const std::vector<Patch>& patches, const std::vector<std::vector<int>>& id, int n) {
  std::vector<std::array<double, 3>> at(n, {1e300, 1e300, 1e300});
  for (size_t p = 0; p < patches.size(); ++p)
    for (size_t a = 0; a < patches[p].cp.size(); ++a) {
      auto& x = at[id[p][a]];
      const auto& y = patches[p].cp[a].x;
      if (x[0] == 1e300) x = y;
      else
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(x[c], y[c], 1e-14) << "id " << id[p][a];
    }
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j)
      EXPECT_GT(std::hypot(std::hypot(at[i][0] - at[j][0], at[i][1] - at[j][1]), at[i][2] - at[j][2]), 1e-3);
}

}  // namespace

TEST(MultiPatch3D, TwoBoxesShareAFaceInEveryOrientation) {
  // A: [0, 1] x [0, 1] x [0, 1], degrees (2, 1, 3), 3 x 2 x 4 control points; B: [1, 2.5] x
  // [0, 1] x [0, 1] with the same y and z bases, 4 x 2 x 4; shared face x = 1 of 2 x 4 points
  const std::vector<double> Ux = uniform_open_knots(2, 1), Uy = uniform_open_knots(1, 1), Uz = uniform_open_knots(3, 1),
                            Ubx = uniform_open_knots(2, 2);
  const Patch A = box3({0, 0, 0}, {1, 1, 1}, {2, 1, 3}, {Ux, Uy, Uz});
  const Patch B0 = box3({1, 0, 0}, {1.5, 1, 1}, {2, 1, 3}, {Ubx, Uy, Uz});
  const int nA = static_cast<int>(A.cp.size()), nB = static_cast<int>(B0.cp.size());
  ASSERT_EQ(nA, 24);
  ASSERT_EQ(nB, 32);
  const double tol = 1e-10;
  int cases = 0;
  const std::array<std::array<int, 3>, 6> perms{{{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}}};
  for (const auto& perm : perms)
    for (int r = 0; r < 8; ++r) {
      const std::array<bool, 3> rev{(r & 1) != 0, (r & 2) != 0, (r & 4) != 0};
      const std::vector<Patch> patches{A, relabel(B0, perm, rev)};
      ASSERT_EQ(patches[1].validate(), "");
      // which side of B is the face x = 1: B0's west, wherever relabel put that direction
      int d0 = 0;
      while (perm[d0] != 0) ++d0;
      const Side sb = side_of(d0, rev[d0] ? 1 : 0);
      const auto found = find_interfaces(patches, tol);
      ASSERT_EQ(found.size(), 1u) << "perm " << perm[0] << perm[1] << perm[2] << " rev " << r;
      const Interface& f = found[0];
      EXPECT_EQ(f.a, (PatchSide{0, Side::East}));
      EXPECT_EQ(f.b, (PatchSide{1, sb}));
      EXPECT_EQ(check_interface(patches, f, tol), "");
      EXPECT_EQ(find_nonconforming(patches, found, tol), "");
      int n = 0;
      auto id = merge_control_points(patches, found, n);
      EXPECT_EQ(n, nA + nB - 8);
      expect_merged_by_position(patches, id, n);
      // a declared interface with the default (often wrong) orientation: the geometry decides
      Interface g{f.a, f.b};
      EXPECT_EQ(check_interface(patches, g, tol), "");
      int n2 = 0;
      const auto id2 = merge_control_points(patches, {g}, n2);
      EXPECT_EQ(n2, n);
      EXPECT_EQ(id2, id);
      // the same with the patches' order swapped: the interface's roles swap
      const std::vector<Patch> swapped{patches[1], patches[0]};
      const auto found2 = find_interfaces(swapped, tol);
      ASSERT_EQ(found2.size(), 1u);
      int n3 = 0;
      merge_control_points(swapped, found2, n3);
      EXPECT_EQ(n3, n);
      ++cases;
    }
  EXPECT_EQ(cases, 48);
}

TEST(MultiPatch3D, StackedBoxes) {
  // three boxes stacked along z: back of k meets front of k + 1
  const auto U1 = uniform_open_knots(1, 1), U2 = uniform_open_knots(2, 1);
  std::vector<Patch> patches;
  for (int k = 0; k < 3; ++k) patches.push_back(box3({0, 0, double(k)}, {1, 1, 1}, {1, 2, 1}, {U1, U2, U1}));
  const double tol = 1e-10;
  const auto found = find_interfaces(patches, tol);
  ASSERT_EQ(found.size(), 2u);
  EXPECT_EQ(found[0].a, (PatchSide{0, Side::Back}));
  EXPECT_EQ(found[0].b, (PatchSide{1, Side::Front}));
  EXPECT_EQ(found[1].a, (PatchSide{1, Side::Back}));
  EXPECT_EQ(found[1].b, (PatchSide{2, Side::Front}));
  int n = 0;
  const auto id = merge_control_points(patches, found, n);
  EXPECT_EQ(n, 3 * 12 - 2 * 6);
  expect_merged_by_position(patches, id, n);
}

TEST(MultiPatch3D, NonconformingFacesAreNamed) {
  const double tol = 1e-10;
  const auto U1 = uniform_open_knots(1, 1), U2 = uniform_open_knots(2, 1), U2b = uniform_open_knots(2, 2);
  // B has one more element in y on the shared face x = 1: other counts
  std::vector<Patch> patches{box3({0, 0, 0}, {1, 1, 1}, {1, 2, 1}, {U1, U2, U1}), box3({1, 0, 0}, {1, 1, 1}, {1, 2, 1}, {U1, U2b, U1})};
  EXPECT_TRUE(find_interfaces(patches, tol).empty());
  std::string m = find_nonconforming(patches, {}, tol);
  EXPECT_EQ(m, "patch0.east and patch1.west meet along a face with different control points (3 x 2 and 4 x 2): a non-conforming "
               "interface; give both faces the same knots and degrees");
  m = check_interface(patches, Interface{{0, Side::East}, {1, Side::West}}, tol);
  EXPECT_EQ(m, "interface patch0.east and patch1.west is not conforming: 3 x 2 and 4 x 2 control points on its faces (refine both "
               "patches alike along the interface)");
  // the same control points on the face but other knots: the same net, another surface basis
  std::vector<double> Uq{0, 0, 0, 0.3, 1, 1, 1}, Ur{0, 0, 0, 0.5, 1, 1, 1};
  patches = {box3({0, 0, 0}, {1, 1, 1}, {1, 2, 1}, {U1, Ur, U1}), box3({1, 0, 0}, {1, 1, 1}, {1, 2, 1}, {U1, Ur, U1})};
  patches[1].knots[1] = Uq;
  const auto found = find_interfaces(patches, tol);
  ASSERT_EQ(found.size(), 1u);
  m = find_nonconforming(patches, found, tol);
  EXPECT_EQ(m, "patch0.east and patch1.west meet along a face with different knots ([0, 0, 0, 0.5, 1, 1, 1] and [0, 0, 0, 0.3, 1, 1, 1]) "
               "in one direction: a non-conforming interface; give both faces the same knots and degrees");
}

TEST(MultiPatch3D, SphereOctantsShareAMeridianFaceNotTheirPoleFaces) {
  // two sphere octants (degree (2, 2, 1), xi: the revolution, eta: the meridian to the pole,
  // zeta: the radius), the second turned by 90 degrees about z: they share the face xi = 1 /
  // xi = 0; their pole faces (eta = 1) both collapse onto the z axis and are no interface
  const double s2 = std::sqrt(0.5);
  auto octant = [&](double turn) {
    Patch P;
    P.pdim = 3;
    P.degree = {2, 2, 1};
    P.knots = {std::vector<double>{0, 0, 0, 1, 1, 1}, std::vector<double>{0, 0, 0, 1, 1, 1}, std::vector<double>{0, 0, 1, 1}};
    const double rev[3][3] = {{1, 0, 1}, {1, 1, s2}, {0, 1, 1}}, mer[3][3] = {{1, 0, 1}, {1, 1, s2}, {0, 1, 1}};
    const double c = std::cos(turn), s = std::sin(turn);
    for (double R : {1.0, 1.5})
      for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i) {
          const double x = R * mer[j][0] * rev[i][0], y = R * mer[j][0] * rev[i][1];
          P.cp.push_back(ControlPoint({c * x - s * y, s * x + c * y, R * mer[j][1]}, mer[j][2] * rev[i][2]));
        }
    return P;
  };
  const std::vector<Patch> patches{octant(0), octant(M_PI / 2)};
  const double tol = 1e-10;
  EXPECT_TRUE(face_degenerate(patches[0], Side::North, tol));
  EXPECT_TRUE(side_collapsed(patches[0], Side::North, tol));
  EXPECT_FALSE(face_degenerate(patches[0], Side::East, tol));
  const auto found = find_interfaces(patches, tol);
  ASSERT_EQ(found.size(), 1u);
  EXPECT_EQ(found[0].a, (PatchSide{0, Side::East}));
  EXPECT_EQ(found[0].b, (PatchSide{1, Side::West}));
  EXPECT_EQ(find_nonconforming(patches, found, tol), "");
  int n = 0;
  merge_control_points(patches, found, n);
  EXPECT_EQ(n, 2 * 18 - 6);   // the shared face: 3 (meridian) x 2 (radius)
}

TEST(MultiPatch3D, EightBoxesAroundAPointMergeToOneGrid) {
  // 2 x 2 x 2 trilinear unit boxes, each in its own parametrisation (directions permuted and
  // reversed, chosen by a fixed pseudo-random sequence): 12 interfaces; points shared by 2, 4
  // or 8 boxes (on faces, edges, the middle) get one id: the 3 x 3 x 3 vertices
  const std::array<std::array<int, 3>, 6> perms{{{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}}};
  const auto U1 = uniform_open_knots(1, 1);
  std::mt19937 rng(12345);
  for (int trial = 0; trial < 20; ++trial) {
    std::vector<Patch> patches;
    for (int k = 0; k < 2; ++k)
      for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 2; ++i) {
          const Patch B = box3({double(i), double(j), double(k)}, {1, 1, 1}, {1, 1, 1}, {U1, U1, U1});
          const int r = static_cast<int>(rng() % 48);
          patches.push_back(relabel(B, perms[r / 8], {(r & 1) != 0, (r & 2) != 0, (r & 4) != 0}));
        }
    const auto found = find_interfaces(patches, 1e-12);
    EXPECT_EQ(found.size(), 12u);
    EXPECT_EQ(find_nonconforming(patches, found, 1e-12), "");
    int n = 0;
    const auto id = merge_control_points(patches, found, n);
    EXPECT_EQ(n, 27);   // the 3 x 3 x 3 vertices
    expect_merged_by_position(patches, id, n);
  }
}
