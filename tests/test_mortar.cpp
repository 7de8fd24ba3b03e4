// Mortar contact: the segment-based weighted gaps against an independent high-order
// quadrature of the same integral, and the contact patch test at degrees 1..4 on
// non-matching meshes (uniform and non-uniform knot vectors).
#include <gtest/gtest.h>

#include <array>
#include <fstream>

#include "support.hpp"
#include "model/configuration_check.hpp"

using namespace iga;
using namespace iga::test;

namespace {

// A curve on the host from the pair's data (reference positions, no displacement).
struct HostCurve {
  int p = 1, nb = 0, side = 0, orientation = 1;
  std::vector<double> U, w;
  std::vector<std::array<double, 2>> X;
  explicit HostCurve(const CurveData& c) : p(c.p), nb(c.nb), side(c.side), orientation(c.orientation) {
    auto hU = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), c.U);
    auto hw = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), c.w);
    auto hX = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), c.X);
    U.assign(hU.data(), hU.data() + hU.extent(0));
    w.assign(hw.data(), hw.data() + hw.extent(0));
    for (int k = 0; k < nb; ++k) X.push_back({hX(k, 0), hX(k, 1)});
  }
  int eval(double u, double x[2], double dx[2], double ddx[2], double R[3][kMaxBasis1D]) const {
    auto cp = [&](int i, int c) { return X[i][c]; };
    auto wt = [&](int i) { return w[i]; };
    return curve_eval(nb, p, U.data(), cp, wt, u, x, dx, ddx, R);
  }
  double lo() const { return U[p]; }
  double hi() const { return U[nb]; }
};

// Closest point on the whole master curve by dense sampling and Newton; false when the
// nearest point is an end of the curve with the foot beyond it.
bool project(const HostCurve& m, const double x[2], double& eta, double& gap) {
  double R[3][kMaxBasis1D], r[2], t[2], dd[2], best = 1e300;
  const int ns = 4000;
  for (int k = 0; k <= ns; ++k) {
    const double e = m.lo() + (m.hi() - m.lo()) * k / ns;
    m.eval(e, r, t, dd, R);
    const double d = std::hypot(x[0] - r[0], x[1] - r[1]);
    if (d < best) { best = d; eta = e; }
  }
  for (int it = 0; it < 100; ++it) {
    m.eval(eta, r, t, dd, R);
    const double f = (x[0] - r[0]) * t[0] + (x[1] - r[1]) * t[1];
    const double fp = -(t[0] * t[0] + t[1] * t[1]) + (x[0] - r[0]) * dd[0] + (x[1] - r[1]) * dd[1];
    const double ne = std::min(m.hi(), std::max(m.lo(), eta - f / fp));
    const bool done = std::abs(ne - eta) < 1e-16;
    eta = ne;
    if (done) break;
  }
  m.eval(eta, r, t, dd, R);
  const double f = (x[0] - r[0]) * t[0] + (x[1] - r[1]) * t[1];
  if ((eta <= m.lo() && f < 0) || (eta >= m.hi() && f > 0)) return false;
  double n[2];
  side_normal(m.side, m.orientation, t, n);
  gap = (x[0] - r[0]) * n[0] + (x[1] - r[1]) * n[1];
  return true;
}

// g_A = int R_A g dGamma_0 by brute force: each slave element is cut where the projected
// master parameter crosses a master knot or where the projection starts or stops existing
// (found by bisection), and each piece gets 4 x 12 Gauss points.
std::vector<double> reference_weighted_gaps(const HostCurve& s, const HostCurve& m, double thickness) {
  std::vector<double> gA(s.nb, 0.0);
  std::vector<double> mknots;
  for (int k = m.p; k <= m.nb; ++k)
    if (mknots.empty() || m.U[k] > mknots.back()) mknots.push_back(m.U[k]);
  auto state = [&](double xi, double& eta) {
    double R[3][kMaxBasis1D], x[2], dx[2], ddx[2], g;
    s.eval(xi, x, dx, ddx, R);
    if (!project(m, x, eta, g)) return -1;
    return static_cast<int>(std::upper_bound(mknots.begin(), mknots.end(), eta) - mknots.begin());
  };
  const GaussRule G = gauss_rule(12);
  for (int sp = s.p; sp < s.nb; ++sp) {
    const double a = s.U[sp], b = s.U[sp + 1];
    if (b <= a) continue;
    std::vector<double> cuts{a};
    const int nsamp = 64;
    double eta;
    int prev = state(a, eta);
    for (int k = 1; k <= nsamp; ++k) {
      const double xi = a + (b - a) * k / nsamp;
      const int cur = state(xi, eta);
      if (cur != prev) {
        double lo = a + (b - a) * (k - 1) / nsamp, hi = xi;
        for (int it = 0; it < 60; ++it) {
          const double mid = 0.5 * (lo + hi);
          (state(mid, eta) == prev ? lo : hi) = mid;
        }
        cuts.push_back(0.5 * (lo + hi));
      }
      prev = cur;
    }
    cuts.push_back(b);
    for (size_t c = 0; c + 1 < cuts.size(); ++c)
      for (int sub = 0; sub < 4; ++sub) {
        const double u0 = cuts[c] + (cuts[c + 1] - cuts[c]) * sub / 4, u1 = cuts[c] + (cuts[c + 1] - cuts[c]) * (sub + 1) / 4;
        for (int q = 0; q < G.n; ++q) {
          const double xi = u0 + 0.5 * (u1 - u0) * (G.x[q] + 1);
          double R[3][kMaxBasis1D], x[2], dx[2], ddx[2], g;
          const int span = s.eval(xi, x, dx, ddx, R);
          if (!project(m, x, eta, g)) continue;
          const double w = G.w[q] * 0.5 * (u1 - u0) * std::hypot(dx[0], dx[1]) * thickness;
          for (int k = 0; k <= s.p; ++k) gA[span - s.p + k] += R[0][k] * g * w;
        }
      }
  }
  return gA;
}

// The ring and block of tests/support.hpp with non-uniform slave knots, mortar penalty.
std::string ring_and_block(int p, bool ring_is_master, int qp) {
  test::RingAndBlock rb;
  rb.p = p;
  rb.method = "mortar_penalty";
  rb.ring_is_master = ring_is_master;
  rb.quadrature_points = qp;
  rb.block_refine = "insert_knots: [[0.13, 0.37, 0.52, 0.81], [0.5]]";
  return rb.yaml();
}

}  // namespace

class MortarIntegrals : public ::testing::TestWithParam<std::tuple<int, bool>> {};

// Curved master under a flat slave and curved slave over a flat master, p = 2..4: the kernel's
// segment-based g_A equals the brute-force integral. With 12 Gauss points per segment the
// integrand (smooth on each segment) is integrated to round-off; the default rule
// (p_s + p_m + 1 points) is exact for polynomial integrands and within 1e-9 here.
TEST_P(MortarIntegrals, WeightedGapsMatchIndependentQuadrature) {
  const int p = std::get<0>(GetParam());
  const bool ring_is_master = std::get<1>(GetParam());
  for (int qp : {12, 0}) {
    const Problem P = parse_problem(ring_and_block(p, ring_is_master, qp), "mortar.yaml");
    System sys(P, Tpetra::getDefaultComm());
    ContactPairData c(sys, 0);
    Vector u(sys.owned_map());
    c.update(u);
    const auto g = c.weighted_gaps();
    const auto ref = reference_weighted_gaps(HostCurve(c.slave), HostCurve(c.master), P.thickness);
    double diff = 0, scale = 0;
    int touched = 0;
    for (size_t A = 0; A < g.size(); ++A) {
      diff = std::max(diff, std::abs(g[A] - ref[A]));
      scale = std::max(scale, std::abs(ref[A]));
      touched += ref[A] != 0.0;
    }
    std::printf("  p = %d, %s master, %2d points per segment: max |g_A - ref| = %.2e of max |g_A| = %.2e (%d of %zu cps)\n",
                p, ring_is_master ? "curved" : "flat", qp > 0 ? qp : 2 * p + 1, diff, scale, touched, g.size());
    ASSERT_GT(touched, 2);
    EXPECT_LT(diff, (qp > 0 ? 1e-12 : 1e-9) * scale);
  }
}

INSTANTIATE_TEST_SUITE_P(Degrees, MortarIntegrals, ::testing::Combine(::testing::Values(2, 3, 4), ::testing::Bool()));

// The contact patch test (reference-solutions.md): two blocks of one material, non-matching
// meshes, uniform pressure q = 10 on top. mortar_alm transmits q at every slave point and in
// every multiplier to 1e-6, for p = 1..4, with 5 uniform or 5 non-uniform slave elements
// against 8 master elements.
class MortarPatch : public ::testing::TestWithParam<std::tuple<int, bool>> {};

namespace {

// upper_refine: the slave block's refinement; lower_x: the master's elements along x
void mortar_patch_test(int p, const std::string& upper_refine, int lower_x, const char* label) {
  std::ostringstream os;
  os << "analysis: {type: plane_strain}\nbodies:\n"
     << "  - name: lower\n    material: {youngs_modulus: 1000.0, poisson_ratio: 0.3}\n"
     << "    geometry: {rectangle: {origin: [0.0, 0.0], size: [1.0, 0.5]}}\n"
     << "    refine: {degree_elevate: " << p - 1 << ", subdivide: [" << lower_x << ", 4]}\n"
     << "    boundary: {south: {displacement: {y: 0.0}}, west: {displacement: {x: 0.0}}}\n"
     << "  - name: upper\n    material: {youngs_modulus: 1000.0, poisson_ratio: 0.3}\n"
     << "    geometry: {rectangle: {origin: [0.0, 0.5], size: [1.0, 0.5]}}\n"
     << "    refine: {degree_elevate: " << p - 1 << ", " << upper_refine << "}\n"
     << "    boundary: {west: {displacement: {x: 0.0}}, north: {pressure: 10.0}}\n"
     << "contact:\n  - {master: {body: lower, side: north}, slave: {body: upper, side: south}, method: mortar_alm,"
     << " penalty: 1.0e6}\n"
     << "solver: {linear: "
     << (Tpetra::getDefaultComm()->getSize() == 1 ? "{method: direct}"
                                                  : "{method: gmres, preconditioner: muelu, tolerance: 1.0e-13}")
     << ", newton: {tolerance: 1.0e-12}}\n";
  const Solved s = solve_text(os.str());
  ASSERT_TRUE(s.res.converged) << s.res.message;
  const auto& c = s.res.contact[0];
  const auto st = c.state();
  double dev = 0;
  for (size_t i = 0; i < st.pressure.size(); ++i) {
    ASSERT_TRUE(st.active[i]) << "slave point " << i << " at x = " << st.x[i] << " is not in contact";
    dev = std::max(dev, std::abs(st.pressure[i] - 10.0) / 10.0);
  }
  double dev_l = 0;
  for (double l : c.mortar_multipliers()) dev_l = std::max(dev_l, std::abs(l - 10.0) / 10.0);
  const ContactSummary sum = c.summary();
  std::printf("  p = %d, %s: %zu slave points, max |p - q|/q = %.2e, max |lambda_A - q|/q = %.2e, force %.12g\n", p,
              label, st.pressure.size(), dev, dev_l, sum.normal_force);
  EXPECT_LT(dev, 1e-6) << label;
  EXPECT_LT(dev_l, 1e-6) << label;
  EXPECT_NEAR(sum.normal_force, 10.0, 1e-8 * 10.0) << label;
}

}  // namespace

TEST_P(MortarPatch, UniformPressureIsTransmittedExactly) {
  const int p = std::get<0>(GetParam());
  const bool nonuniform = std::get<1>(GetParam());
  mortar_patch_test(p, nonuniform ? "insert_knots: [[0.13, 0.37, 0.52, 0.81], [0.5]], subdivide: [1, 2]" : "subdivide: [5, 4]", 8,
                    nonuniform ? "non-uniform" : "uniform");
}

// Any ratio of slave to master element sizes (issue 19): one slave element over 120 master
// elements (121 segments, where the slots start with room for 16; delta g_A couples some 250
// dofs, where the scratch starts with 160): both grow, and the patch test still holds.
TEST(MortarPatch, OneSlaveElementOverManyMasterElements) {
  for (int p : {1, 3}) mortar_patch_test(p, "subdivide: [1, 2]", 120, "1 slave over 120 master elements");
}

INSTANTIATE_TEST_SUITE_P(Degrees, MortarPatch, ::testing::Combine(::testing::Values(1, 2, 3, 4), ::testing::Bool()));

// The method of multipliers (solver/newton.cpp, NewtonCore::augment): where a multiplier
// update closes the gaps by less than 4x, the penalty of the next solves is raised (x 10, up
// to 100 E/h). The wheel example with mortar_alm stalled before at its own penalty (1e6:
// 0.86 per update) and at 1e4; it converges from either, to the same answer (the ALM answer
// does not depend on the penalty: both within alm_tolerance x h of closed gaps), with the
// penalty in use raised no higher than 100 E/h.
TEST(MortarAlm, SlowUpdatesRaiseThePenaltyAndConverge) {
  std::vector<Solved> runs;
  for (const char* eps : {"1e4", "1e6"}) {
    runs.push_back(solve_text(read(IGACONTACT_SOURCE_DIR "/examples/wheel.yaml"), Tpetra::getDefaultComm(), {},
                              {"contact.0.method=mortar_alm", std::string("contact.0.penalty=") + eps}));
    const Solved& s = runs.back();
    ASSERT_TRUE(s.res.converged) << "penalty " << eps << ": " << s.res.message;
    const auto& c = s.res.contact[0];
    double E = 0, h = 0;
    const double ratio = penalty_ratio(s.P, c.pair(), &E, &h);
    std::printf("  penalty %s: raised x %.4g to %.4g (%.4g E/h), Newton iterations [%d, %d], largest gap %.2e h, "
                "max pressure %.12g\n",
                eps, c.penalty_raised(), c.pair().penalty, ratio, s.res.newton_iterations[0], s.res.newton_iterations[1],
                c.max_active_gap_ratio(), c.summary().max_pressure);
    EXPECT_GT(c.penalty_raised(), 1.0) << eps;
    EXPECT_LE(ratio, 100 * (1 + 1e-9)) << eps;
    EXPECT_LE(c.max_active_gap_ratio(), s.P.contact[0].alm_tolerance) << eps;
  }
  const double d = relative_displacement_difference(runs[0], runs[1]);
  std::printf("  displacements from penalty 1e4 against 1e6: %.2e relative\n", d);
  EXPECT_LT(d, 1e-6);
  EXPECT_NEAR(runs[0].res.contact[0].summary().max_pressure, runs[1].res.contact[0].summary().max_pressure,
              1e-6 * runs[1].res.contact[0].summary().max_pressure);
}

// A flat punch (E 1e5, half-width 0.5, degree 2) as the master of a soft block (E 100): the
// punch's corner ends inside the support of one slave control point, which the master covers
// on a sliver only (3e-5 of its w_A). Its weighted gap (2.2e-9 h) stayed the same over every
// multiplier update, whose force acts on the sliver alone, and mortar_alm stopped as stalled
// (found by a problem written from the docs). The ALM test now leaves out control points
// covered on less than 1e-3 of w_A: it converges, in equilibrium, to the force of the same
// punch as the slave (another discretisation of the same contact) within 0.5 %.
TEST(MortarAlm, FlatPunchAsTheMasterConverges) {
  auto punch = [](bool punch_is_master) {
    const std::string p = "{body: punch, side: south}", b = "{body: block, side: north}";
    return std::string(
               "analysis: {type: plane_strain}\n"
               "bodies:\n"
               "  - name: block\n"
               "    material: {youngs_modulus: 100.0, poisson_ratio: 0.3}\n"
               "    geometry: {rectangle: {origin: [0.0, -4.0], size: [5.0, 4.0]}}\n"
               "    refine:\n"
               "      degree_elevate: 1\n"
               "      insert_knots: [[0.02, 0.04, 0.06, 0.08, 0.09, 0.095, 0.1, 0.105, 0.11, 0.12, 0.14, 0.2, 0.3, 0.5],"
               " [0.5, 0.7, 0.8, 0.9, 0.95, 0.98]]\n"
               "      subdivide: [2, 2]\n"
               "    boundary:\n"
               "      south: {displacement: {x: 0.0, y: 0.0}}\n"
               "      west:  {displacement: {x: 0.0}}\n"
               "  - name: punch\n"
               "    material: {youngs_modulus: 1.0e5, poisson_ratio: 0.3}\n"
               "    geometry: {rectangle: {origin: [0.0, 0.0], size: [0.5, 0.5]}}\n"
               "    refine: {degree_elevate: 1, subdivide: [8, 4]}\n"
               "    boundary:\n"
               "      west:  {displacement: {x: 0.0}}\n"
               "      north: {displacement: {y: -0.01}}\n"
               "contact:\n"
               "  - {master: ") +
           (punch_is_master ? p : b) + ", slave: " + (punch_is_master ? b : p) + ", method: mortar_alm, penalty: 1.0e5}\n";
  };
  const Solved m = solve_text(punch(true)), s = solve_text(punch(false));
  ASSERT_TRUE(m.res.converged) << m.res.message;
  ASSERT_TRUE(s.res.converged) << s.res.message;
  const auto& c = m.res.contact[0];
  EXPECT_LE(c.max_active_gap_ratio(), m.P.contact[0].alm_tolerance);
  const double Fm = c.summary().normal_force, Fs = s.res.contact[0].summary().normal_force;
  std::printf("  normal force: punch master %.9g, punch slave %.9g (%.2e apart); Newton %d\n", Fm, Fs,
              std::abs(Fm - Fs) / Fs, m.res.newton_iterations[0]);
  EXPECT_NEAR(Fm, Fs, 5e-3 * Fs);
  // the contact force on the slave (the block) balances the block's support, and the punch's
  // support carries the same force
  const ContactSummary cs = c.summary();
  const auto R = reactions_json(*m.sys, *m.res.residual);
  const double Rblock = R["block"]["south"][1].get<double>(), Rpunch = R["punch"]["north"][1].get<double>();
  EXPECT_NEAR(cs.fy, -Rblock, 1e-8 * std::abs(Rblock));
  EXPECT_NEAR(cs.fy, Rpunch, 1e-8 * std::abs(Rblock));
}

// A slave wider than its master (a block pressed by a narrower cap): the cap's ends lie inside
// the supports of slave control points, which it covers in part. Their multipliers act on the
// covered part cw_A only, so they close g_A as a penalty of eps cw_A / w_A would: both ALM
// methods stalled at 0.89 per update (exit 3; found by a problem written from the docs).
// The penalty of such a point is now scaled by w_A / cw_A at each update (MortarState::scale):
// they converge, and as the converged answer of an ALM must, to the same force at penalties
// 1e5 and 1e6 (to what alm_tolerance leaves).
TEST(MortarAlm, SlaveWiderThanItsMasterConverges) {
  const std::string yaml = R"(
analysis: {type: plane_strain, load_steps: 1}
bodies:
  - name: base
    material: {youngs_modulus: 1000.0, poisson_ratio: 0.3}
    geometry: {rectangle: {origin: [0.0, 0.0], size: [2.0, 0.5]}}
    refine: {degree_elevate: 1, subdivide: [9, 3]}
    boundary: {south: {displacement: {x: 0.0, y: 0.0}}}
  - name: cap
    material: {youngs_modulus: 1000.0, poisson_ratio: 0.3}
    geometry: {rectangle: {origin: [0.55, 0.5], size: [1.0, 0.5]}}
    refine: {degree_elevate: 1, subdivide: [6, 3]}
    boundary: {north: {displacement: {x: 0.0, y: -0.01}}}
contact:
  - {master: {body: cap, side: south}, slave: {body: base, side: north}, method: mortar_alm, penalty: 1.0e5}
)";
  for (const char* method : {"mortar_alm", "kts_alm"}) {
    double F[2];
    for (int k = 0; k < 2; ++k) {
      const Solved s = solve_text(yaml, Tpetra::getDefaultComm(), {},
                                  {std::string("contact.0.method=") + method, k == 0 ? "contact.0.penalty=1e5" : "contact.0.penalty=1e6"});
      ASSERT_TRUE(s.res.converged) << method << ": " << s.res.message;
      F[k] = s.res.contact[0].summary().normal_force;
      std::printf("  %s, penalty %s: normal force %.10g, Newton %d\n", method, k == 0 ? "1e5" : "1e6", F[k],
                  s.res.newton_iterations[0]);
    }
    EXPECT_NEAR(F[1], F[0], 1e-6 * F[0]) << method;
  }
}
