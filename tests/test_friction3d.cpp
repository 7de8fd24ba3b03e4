// 3-D Coulomb friction, knot-to-surface (kernels/contact_friction3.hpp) and mortar
// (kernels/contact_mortar_friction3.hpp), solver/contact3d.cpp:
//   GrossSliding3  a box pressed onto a rigid flat base and dragged along x or along y (nu = 0,
//                  so the problem is plane strain in the plane of the drag and every point
//                  slides along it): every point slips with |t| = mu p against the drag,
//                  |T| = mu F_n and nothing across the slip; on a base whose top face is
//                  parametrised along skewed directions (e_1 . e_2 = cos 45) as well
//   TurningLoad3   the box dragged along x, then along y: the traction turns towards -y over
//                  the slide and never exceeds mu F_n; the same answer on the skewed base as on
//                  the orthogonal one (the committed traction's components live on the master's
//                  convective basis, which differs between the two)
//   FrictionSlab   the 2-D ring and block with friction (pressed, then dragged into partial
//                  slip), extruded into a slab held at u_z = 0: the 3-D run equals the 2-D
//                  plane-strain run (whose law test_friction verifies) to round-off
//   MortarAlmFriction3  a box pressed onto an elastic block with mortar_alm: converges (the
//                  stick check counts the weighted slip along the contact plane) to
//                  mortar_penalty's answer extrapolated to an infinite penalty
// Run on 1 and 2 ranks (ctest test_friction3d, test_friction3d_2ranks).
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "support.hpp"

using namespace iga;
using namespace iga::test;

namespace {

constexpr double kMu = 0.3;

// A base 0.5 thick whose top face (back) is held (a rigid flat master) and a box 1 x 1 x 0.5 on
// it, nu = 0. skew: the base as a parallelepiped whose second parameter runs along (1, 1, 0)
// (its top face's e_1 . e_2 = cos 45), else a box. drag: the box top's displacement per stage
// after the first (which presses it down by 0.01), as the problem file's x and y lists.
std::string box_on_base(bool skew, const std::string& method, const std::string& stages, const std::string& x,
                        const std::string& y) {
  std::ostringstream os;
  os << "analysis: {type: solid, stages: " << stages << "}\n"
     << "bodies:\n"
     << "  - name: base\n    material: {youngs_modulus: 1000.0, poisson_ratio: 0.0}\n";
  if (skew) {
    os << "    geometry:\n      nurbs:\n        degree: [1, 1, 1]\n"
       << "        knots: [[0, 0, 1, 1], [0, 0, 1, 1], [0, 0, 1, 1]]\n        control_points: [\n";
    for (int k = 0; k < 2; ++k)
      for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 2; ++i)
          os << "          [" << -2.0 + 5.0 * i + 3.0 * j << ", " << -0.5 + 3.0 * j << ", " << 0.5 * k << ", 1],\n";
    os << "        ]\n";
  } else {
    os << "    geometry: {box: {origin: [-1, -0.5, 0], size: [5, 3, 0.5]}}\n";
  }
  os << "    refine: {degree_elevate: [1, 1, 1], subdivide: [6, 4, 1]}\n"
     << "    boundary: {front: {displacement: {x: 0, y: 0, z: 0}}, back: {displacement: {x: 0, y: 0, z: 0}}}\n"
     << "  - name: box\n    material: {youngs_modulus: 1000.0, poisson_ratio: 0.0}\n"
     << "    geometry: {box: {origin: [1, 0.5, 0.5], size: [1, 1, 0.5]}}\n"
     << "    refine: {degree_elevate: [1, 1, 1], subdivide: [4, 4, 2]}\n"
     << "    boundary: {back: {displacement: {x: " << x << ", y: " << y << ", z: -0.01}}}\n"
     << "contact:\n  - {master: {body: base, side: back}, slave: {body: box, side: front}, method: " << method
     << ", penalty: 1.0e5, friction: " << kMu << "}\n";
  return os.str();
}

}  // namespace

// Gross sliding: the drag (0.05, ten times the elastic slip mu p / eps_T) makes every contact
// point slip (KTS: every slave point; mortar: every slave control point, so that the traction
// field sum_A tau_A R_A is -mu p e_drag at every slot); with nu = 0 the box deforms in the plane of the drag only, so every point's
// traction is mu p along -drag exactly (the return mapping's result, whatever the trial's
// history), and their sum is mu F_n along -drag: both to round-off.
TEST(GrossSliding3, EveryPointSlipsWithTheCoulombTraction) {
  for (bool skew : {false, true})
    for (int dir : {0, 1})
      for (const char* method : {"kts_penalty", "kts_alm", "mortar_penalty", "mortar_alm"}) {
        if (std::string(method).find("alm") != std::string::npos && skew) continue;
        const std::string x = dir == 0 ? "[0.0, 0.05]" : "0", y = dir == 1 ? "[0.0, 0.05]" : "0";
        const Solved s = solve_text(box_on_base(skew, method, "[1, 2]", x, y));
        ASSERT_TRUE(s.res.converged) << s.res.message;
        const ContactSummary sm = s.res.contact[0].summary();
        const auto st = s.res.contact[0].state(true);
        const double* T = sm.tangential;
        double worst_point = 0, pmax = 0;
        int slipping = 0, active = 0;
        for (size_t i = 0; i < st.x.size(); ++i) {
          if (!st.active[i]) continue;
          ++active;
          slipping += st.state[i] == 2;
          const double t[3] = {st.tx[i], st.ty[i], st.tz[i]};
          pmax = std::max(pmax, st.pressure[i]);
          // t = -mu p along the drag, nothing across it or along the normal
          for (int c = 0; c < 3; ++c) worst_point = std::max(worst_point, std::abs(t[c] - (c == dir ? -kMu * st.pressure[i] : 0.0)));
        }
        std::printf("  %s base, drag along %c, %s: %d of %d points slip; T = (%.12g, %.3g, %.3g), mu F_n = %.12g; "
                    "max |t - (-mu p) e_drag| = %.2e of max p %.3g; Newton %d\n",
                    skew ? "skewed" : "orthogonal", "xy"[dir], method, slipping, active, T[dir], T[1 - dir], T[2],
                    kMu * sm.normal_force, worst_point, pmax, newton_total(s));
        EXPECT_EQ(slipping, active);
        EXPECT_GT(active, 100);
        EXPECT_NEAR(sm.stick_length, 0.0, 1e-14);
        EXPECT_NEAR(sm.slip_length, 1.0, 1e-12);   // the box's footprint
        // per point the law holds exactly; each point's slip direction is that of the converged
        // displacements (Newton's tolerance: 1e-10 of the residual); measured 3e-12 of max p
        EXPECT_LT(worst_point, 1e-10 * pmax);
        EXPECT_NEAR(T[dir], -kMu * sm.normal_force, 1e-10 * sm.normal_force);
        EXPECT_NEAR(T[1 - dir], 0.0, 1e-10 * sm.normal_force);
        EXPECT_NEAR(T[2], 0.0, 1e-10 * sm.normal_force);
        // on a flat master the tangential force is the whole in-plane force on the box
        EXPECT_NEAR(sm.fx, T[0], 1e-10 * sm.normal_force);
        EXPECT_NEAR(sm.fy, T[1], 1e-10 * sm.normal_force);
      }
}

// A turning load: pressed, dragged 0.05 along x, then 0.1 along y in 8 steps. The traction turns
// from -x towards -y as the box slides (its x shear relaxes as it slides, so the turn takes a
// few steps), |T| <= mu F_n throughout and -> mu F_n; the skewed base gives the same answer as
// the orthogonal one at every step (the committed traction and the slip live on the master's
// convective basis: orthogonal on one, at 45 degrees on the other).
TEST(TurningLoad3, TheTractionFollowsTheSlipOnAnyParametrisation) {
  for (const char* method : {"kts_penalty", "mortar_penalty"}) {
  std::printf("  %s\n", method);
  std::vector<std::array<double, 4>> hist[2];   // per base: Tx, Ty, Tz, F_n per step
  for (bool skew : {false, true}) {
    const Problem P = parse_problem(box_on_base(skew, method, "[1, 2, 8]", "[0.0, 0.05, 0.05]", "[0.0, 0.0, 0.1]"),
                                    "turn.yaml");
    System sys(P, Tpetra::getDefaultComm());
    const SolveResult res = solve(sys, {}, [&](const StepState& st) {
      const ContactSummary c = (*st.contact)[0].summary();
      hist[skew].push_back({c.tangential[0], c.tangential[1], c.tangential[2], c.normal_force});
    });
    ASSERT_TRUE(res.converged) << res.message;
  }
  ASSERT_EQ(hist[0].size(), hist[1].size());
  ASSERT_EQ(hist[0].size(), 11u);
  double diff = 0, prev_ratio = 1;
  for (size_t k = 0; k < hist[0].size(); ++k) {
    const auto& h = hist[0][k];
    for (int c = 0; c < 4; ++c) diff = std::max(diff, std::abs(hist[1][k][c] - h[c]));
    const double T = std::hypot(h[0], h[1]);
    std::printf("  step %2zu: T = (%9.6f, %9.6f), |T| / F_n = %.12f; skewed - orthogonal: %.1e\n", k + 1, h[0], h[1], T / h[3],
                std::abs(hist[1][k][0] - h[0]) + std::abs(hist[1][k][1] - h[1]));
    EXPECT_LE(T, kMu * h[3] * (1 + 1e-12));
    if (k >= 3) {   // the y drag: T turns towards -y
      const double ratio = std::abs(h[0]) / T;
      EXPECT_LT(h[1], 0.0);
      EXPECT_LT(ratio, prev_ratio);
      prev_ratio = ratio;
    }
  }
  const auto& end = hist[0].back();
  // after 0.1 of sliding along y (17 times the box's elastic shear deflection mu F_n / (G A / H)
  // = 5.9e-3), the x part has decayed: measured 7e-4 of |T|
  EXPECT_LT(std::abs(end[0]) / std::hypot(end[0], end[1]), 2e-3);
  EXPECT_NEAR(std::hypot(end[0], end[1]), kMu * end[3], 1e-5 * end[3]);
  EXPECT_LT(diff, 1e-9 * kMu * end[3]);
  }
}

// The 2-D ring-and-block contact with friction (mu = 0.3, the block pressed by 0.01 and then
// dragged 0.004 along x: stick in the middle, slip at the edges) against the same bodies
// extruded into a slab held at u_z = 0 (plane strain): the 3-D law on the unit covariant basis
// reduces to the 2-D law (tau^1 = tau, |a_1| dxi^1 = |t| d eta), so the runs agree to round-off,
// the stick and slip measures per unit thickness included.
TEST(FrictionSlab, EqualsThe2DPlaneStrainRun) {
  test::RingAndBlock rb;
  rb.p = 2;
  std::string y2 = "analysis: {type: plane_strain, stages: [1, 2]}\n" + rb.yaml();
  const std::string held = "{displacement: {x: 0, y: -0.01}}", dragged = "{displacement: {x: [0.0, 0.004], y: -0.01}}";
  y2.replace(y2.find(held), held.size(), dragged);
  y2.insert(y2.rfind('}'), ", friction: 0.3");
  const Solved s2 = solve_text(y2);
  ASSERT_TRUE(s2.res.converged) << s2.res.message;
  const Solved s3 = solve_text(extruded_ring_and_block(s2.P, ", stages: [1, 2]", "x: [0.0, 0.004], y: -0.01", ", friction: 0.3"));
  ASSERT_TRUE(s3.res.converged) << s3.res.message;
  const ContactSummary c2 = s2.res.contact[0].summary(), c3 = s3.res.contact[0].summary();   // collective
  if (s3.sys->comm()->getRank() != 0) return;
  double diff = 0, scale = 0;
  for (int b = 0; b < 2; ++b) {
    const size_t n2 = s2.disp[b].size() / 2;
    ASSERT_EQ(s3.disp[b].size(), 6 * n2);
    for (size_t a = 0; a < n2; ++a)
      for (int k = 0; k < 2; ++k)
        for (int c = 0; c < 2; ++c) {
          diff = std::max(diff, std::abs(s3.disp[b][3 * (a + n2 * k) + c] - s2.disp[b][2 * a + c]));
          scale = std::max(scale, std::abs(s2.disp[b][2 * a + c]));
        }
  }
  std::printf("  max |u_3D - u_2D| = %.2e of %.2e; force (%.12g, %.12g) vs 2-D (%.12g, %.12g); stick %.12g vs %.12g, slip %.12g "
              "vs %.12g; T_x %.12g; Newton %d vs %d\n",
              diff, scale, c3.fx, c3.fy, c2.fx, c2.fy, c3.stick_length, c2.stick_length, c3.slip_length, c2.slip_length,
              c3.tangential[0], newton_total(s3), newton_total(s2));
  EXPECT_GT(c2.stick_length, 0.0);   // partial slip: both states present
  EXPECT_GT(c2.slip_length, 0.0);
  EXPECT_LT(diff, 1e-12 * scale);   // the same discrete problem: round-off (measured 1.2e-13)
  EXPECT_NEAR(c3.fx, c2.fx, 1e-9 * std::abs(c2.fy));
  EXPECT_NEAR(c3.fy, c2.fy, 1e-9 * std::abs(c2.fy));
  EXPECT_NEAR(c3.fz, 0.0, 1e-12 * std::abs(c2.fy));
  EXPECT_NEAR(c3.stick_length, c2.stick_length, 1e-12);
  EXPECT_NEAR(c3.slip_length, c2.slip_length, 1e-12);
  EXPECT_NEAR(c3.stick_length + c3.slip_length, 0.4, 1e-12);
}

// mortar_alm's stick check on a dented master (2026-11-28): a box (E = 500, nu = 0.35) pressed
// 0.008 onto an elastic block (E = 2000, nu = 0.25) with mu = 0.4 and one load step: the block's
// top is dented under the box's edges (a flat punch), so the slip vectors of the slots, each
// tangent to the master at its foot, sum to a weighted slip s_A with a part along A's normal.
// The tangential multipliers cannot close that part (it is no slip): the check measured it and
// the press never converged (50 updates, exit 3; the stick slip's tangential part had gone to
// 1e-10 while the normal part sat at 5 x alm_tolerance). Now the check takes s_A's part along
// the contact plane: converged, with a stick zone, and the normal force the limit of
// mortar_penalty's as the penalty grows (Richardson on eps = 1e6, 3e6).
TEST(MortarAlmFriction3, PressOfABoxOnADentedBlockConverges) {
  const std::string yaml = R"(analysis: {type: solid}
bodies:
  - name: base
    material: {youngs_modulus: 2000.0, poisson_ratio: 0.25}
    geometry: {box: {origin: [0.0, 0.0, 0.0], size: [3.0, 2.0, 1.0]}}
    refine: {degree_elevate: 2, subdivide: [4, 3, 1]}
    boundary: {front: {displacement: {x: 0.0, y: 0.0, z: 0.0}}}
  - name: box
    material: {youngs_modulus: 500.0, poisson_ratio: 0.35}
    geometry: {box: {origin: [1.0, 0.5, 1.0], size: [1.0, 1.0, 0.4]}}
    refine: {degree_elevate: 1, subdivide: [2, 2, 1]}
    boundary: {back: {displacement: {x: 0.0, y: 0.0, z: -0.008}}}
contact:
  - {master: {body: base, side: back}, slave: {body: box, side: front}, method: mortar_alm, penalty: 1.0e5, friction: 0.4}
)";
  const Solved alm = solve_text(yaml);
  ASSERT_TRUE(alm.res.converged) << alm.res.message;
  const ContactSummary a = alm.res.contact[0].summary();
  // mortar_penalty at eps and 3 eps (error O(1 / eps)) extrapolated to eps -> infinity
  double fn[2];
  for (int k = 0; k < 2; ++k) {
    const Solved pen = solve_text(yaml, Tpetra::getDefaultComm(), {},
                                  {"contact.0.method=mortar_penalty", k == 0 ? "contact.0.penalty=1e6" : "contact.0.penalty=3e6"});
    ASSERT_TRUE(pen.res.converged) << pen.res.message;
    fn[k] = pen.res.contact[0].summary().normal_force;
  }
  const double limit = (3 * fn[1] - fn[0]) / 2;
  std::printf("  mortar_alm: F_n = %.10g, stick area %.4f; mortar_penalty 1e6, 3e6: %.10g, %.10g, extrapolated %.10g\n",
              a.normal_force, a.stick_length, fn[0], fn[1], limit);
  EXPECT_GT(a.stick_length, 0.1);
  EXPECT_NEAR(a.normal_force, limit, 1e-4 * limit);   // (1e-6 measured; the penalty runs' own errors 1.3e-3, 4.3e-4)
}
