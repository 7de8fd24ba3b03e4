// 3-D solids (analysis.type: solid) through the whole solver: problem file, System, Newton,
// against closed-form answers (../shared/reference-solutions.md, "3-D").
//   PatchTest3D     uniaxial stress on a box and on a distorted rational block: the affine
//                   displacement is in every NURBS space, so it comes out to the solver's
//                   tolerance, and the reactions balance the applied traction
//   ThickSphere     the thick-walled sphere under internal pressure on an octant with a
//                   degenerate pole face, L2 error of u_r against the closed form, converging
//   FiniteStretch3D homogeneous uniaxial stretch of a neo-Hookean and an SVK block against the
//                   exact lateral stretch and first Piola stress
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "tests/solid_errors.hpp"
#include "tests/support.hpp"

using namespace iga;
using namespace iga::test;
using iga::test3d::l2_error3;

namespace {

constexpr double kE = 1000.0, kNu = 0.3;

std::string box_yaml(const std::string& refine, const std::string& boundary, const std::string& extra = "",
                     const std::string& material = "") {
  std::ostringstream os;
  os.precision(17);
  os << "analysis: {type: solid" << extra << "}\n"
     << "bodies:\n  - name: block\n    material: {" << material << "youngs_modulus: " << kE << ", poisson_ratio: " << kNu << "}\n"
     << "    geometry: {box: {origin: [0, 0, 0], size: [2.0, 1.0, 0.5]}}\n"
     << "    refine: {" << refine << "}\n"
     << "    boundary:\n" << boundary;
  return os.str();
}

// The control point values of body 0 against u(x) = A x (affine fields are reproduced by any
// NURBS space through their control point values): the largest difference.
double affine_error(const Solved& s, const double A[3][3]) {
  const Body& b = s.P.bodies[0];
  double worst = 0;
  for (size_t k = 0; k < b.patches.size(); ++k) {
    const auto uk = b.patch_values(static_cast<int>(k), s.disp[0]);
    for (size_t a = 0; a < b.patches[k].cp.size(); ++a)
      for (int i = 0; i < 3; ++i) {
        double e = 0;
        for (int j = 0; j < 3; ++j) e += A[i][j] * b.patches[k].cp[a].x[j];
        worst = std::max(worst, std::abs(uk[3 * a + i] - e));
      }
  }
  return worst;
}

}  // namespace

// Uniaxial stress sxx = s on a box: west u_x = 0, south u_y = 0, front u_z = 0 (rollers), east
// traction (s, 0, 0): u = (s x / E, -nu s y / E, -nu s z / E), at p = 1..3 with knots inside.
TEST(PatchTest3D, UniaxialStressOnABoxIsExactAtEveryDegree) {
  const double s = 10.0;
  const std::string bc = "      west: {displacement: {x: 0}}\n      south: {displacement: {y: 0}}\n"
                         "      front: {displacement: {z: 0}}\n      east: {traction: [10.0, 0, 0]}\n";
  for (int p = 1; p <= 3; ++p) {
    const Solved r = solve_text(box_yaml("degree_elevate: " + std::to_string(p - 1) + ", subdivide: [3, 2, 2]", bc));
    ASSERT_TRUE(r.res.converged) << r.res.message;
    EXPECT_EQ(r.sys->num_dofs(), 3LL * (p + 3) * (p + 2) * (p + 2));
    if (Tpetra::getDefaultComm()->getRank() != 0) continue;
    const double A[3][3] = {{s / kE, 0, 0}, {0, -kNu * s / kE, 0}, {0, 0, -kNu * s / kE}};
    EXPECT_LT(affine_error(r, A), 1e-10 * s / kE * 2.0) << "p = " << p;
  }
}

// The same state on a block whose map is a non-uniform reparametrisation of the box in each
// direction (x_d = f_d(xi_d): the middle control points moved along their own direction by an
// amount of that direction only, so the faces stay planar), loaded by pressure on the east
// face: pressure q on x = 2 gives sxx = -q. Why separable: in 3-D the cofactors of J are
// products of two derivatives, and for a general distorted map B det J has degree ~3p per
// direction, beyond the p + 1 Gauss points (the 2-D patch test has no such limit: there adj J
// is linear in the derivatives); with x_d = f_d(xi_d) it stays within them.
TEST(PatchTest3D, PressureOnADistortedBlockGivesUniaxialStress) {
  const double q = 4.0;
  // degree 2 in every direction, 3 x 3 x 3 control points; the middle ones moved
  std::ostringstream cps;
  cps.precision(17);
  const double L[3] = {2.0, 1.0, 0.5};
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i) {
        double x[3] = {L[0] * i / 2.0, L[1] * j / 2.0, L[2] * k / 2.0};
        double w = 1.0;
        const int idx[3] = {i, j, k};
        for (int d = 0; d < 3; ++d)   // move middle points along their own direction only: faces stay planar
          if (idx[d] == 1) x[d] += 0.13 * L[d] * std::sin(1.0 + 2 * d);
        cps << (cps.tellp() > 0 ? ", " : "") << "[" << x[0] << ", " << x[1] << ", " << x[2] << ", " << w << "]";
      }
  std::ostringstream os;
  os << "analysis: {type: solid}\n"
     << "bodies:\n  - name: block\n    material: {youngs_modulus: " << kE << ", poisson_ratio: " << kNu << "}\n"
     << "    geometry:\n      nurbs:\n        degree: [2, 2, 2]\n"
     << "        knots: [[0, 0, 0, 1, 1, 1], [0, 0, 0, 1, 1, 1], [0, 0, 0, 1, 1, 1]]\n"
     << "        control_points: [" << cps.str() << "]\n"
     << "    refine: {subdivide: [2, 3, 2]}\n"
     << "    boundary:\n      west: {displacement: {x: 0}}\n      south: {displacement: {y: 0}}\n"
     << "      front: {displacement: {z: 0}}\n      east: {pressure: " << q << "}\n";
  const Solved r = solve_text(os.str());
  ASSERT_TRUE(r.res.converged) << r.res.message;
  if (Tpetra::getDefaultComm()->getRank() != 0) return;
  const double s = -q;
  const double A[3][3] = {{s / kE, 0, 0}, {0, -kNu * s / kE, 0}, {0, 0, -kNu * s / kE}};
  EXPECT_LT(affine_error(r, A), 1e-10 * q / kE * 2.0);
}

namespace {

// The octant of a thick sphere, radii a < b: degree (2, 2, 1), xi the angle about z from x to y,
// eta the latitude from the equator (z = 0) to the pole, zeta the radius; the pole face
// (north, eta = 1) collapses onto the z axis. Control points: the quarter circle's
// {(1, 0), (1, 1), (0, 1)} with weights {1, sqrt(1/2), 1} in both angles.
std::string sphere_octant_yaml(double a, double b, double p, int n, int elevate_r) {
  const double w = std::sqrt(0.5);
  const double c[3][2] = {{1, 0}, {1, 1}, {0, 1}}, cw[3] = {1, w, 1};
  std::ostringstream os;
  os.precision(17);
  os << "analysis: {type: solid}\n"
     << "bodies:\n  - name: sphere\n    material: {youngs_modulus: " << kE << ", poisson_ratio: " << kNu << "}\n"
     << "    geometry:\n      nurbs:\n        degree: [2, 2, 1]\n"
     << "        knots: [[0, 0, 0, 1, 1, 1], [0, 0, 0, 1, 1, 1], [0, 0, 1, 1]]\n        control_points: [";
  bool first = true;
  for (double r : {a, b})
    for (int j = 0; j < 3; ++j)        // latitude: rho = r c[j][0], z = r c[j][1]
      for (int i = 0; i < 3; ++i) {    // longitude
        const double rho = r * c[j][0], z = r * c[j][1];
        os << (first ? "" : ", ") << "[" << rho * c[i][0] << ", " << rho * c[i][1] << ", " << z << ", " << cw[i] * cw[j] << "]";
        first = false;
      }
  os << "]\n    refine: {degree_elevate: [0, 0, " << elevate_r << "], subdivide: [" << n << ", " << n << ", " << n << "]}\n"
     << "    boundary:\n      west: {displacement: {y: 0}}\n      east: {displacement: {x: 0}}\n"
     << "      south: {displacement: {z: 0}}\n      front: {pressure: " << p << "}\n"
     << "solver: {linear: {method: direct}}\n";
  return os.str();
}

}  // namespace

// u of the thick-walled sphere, radii a < b, internal pressure p (reference-solutions.md, 3-D).
static std::array<double, 3> sphere_u(double a, double b, double p, const double* x) {
  const double r = std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
  const double ur = p * a * a * a / (kE * (b * b * b - a * a * a)) * ((1 - 2 * kNu) * r + (1 + kNu) * b * b * b / (2 * r * r));
  return {ur * x[0] / r, ur * x[1] / r, ur * x[2] / r};
}

// The thick-walled sphere under internal pressure (reference-solutions.md, 3-D):
// u_r = p a^3 / (E (b^3 - a^3)) ((1 - 2 nu) r + (1 + nu) b^3 / (2 r^2)). The octant's geometry is
// exact, so the L2 error of u falls as h^(p+1) (p = 2: 3); checked from n = 2 to 4 to 8 elements
// per direction, and the error at n = 8 below 1e-4 of |u|.
TEST(ThickSphere, OctantWithDegeneratePoleConvergesAtOptimalRate) {
  const double a = 1.0, b = 2.0, p = 1.0;
  auto exact = [&](const double* x) { return sphere_u(a, b, p, x); };
  std::vector<double> rel;
  for (int n : {2, 4, 8}) {
    const Solved s = solve_text(sphere_octant_yaml(a, b, p, n, 1));
    ASSERT_TRUE(s.res.converged) << s.res.message;
    // the pole's coinciding control points are one point (merged): the deformed pole stays
    // collapsed and no element inverts (they moved apart by 2e-8 and folded it before)
    EXPECT_EQ(find_inverted_elements(*s.sys, *s.res.u), "");
    EXPECT_EQ(s.sys->num_dofs(), 3LL * (n + 2) * (n + 2) * (n + 2) - 3LL * (n + 1) * (n + 2));
    if (Tpetra::getDefaultComm()->getRank() != 0) continue;
    const auto [err, norm] = l2_error3(s.P, s.disp[0], exact);
    rel.push_back(err / norm);
    std::printf("  thick sphere, p = 2, n = %d: %lld dofs, L2 error of u %.3e (relative)\n", n,
                static_cast<long long>(s.sys->num_dofs()), err / norm);
  }
  if (Tpetra::getDefaultComm()->getRank() != 0) return;
  for (size_t k = 1; k < rel.size(); ++k) {
    const double rate = std::log2(rel[k - 1] / rel[k]);
    EXPECT_GT(rate, 2.6) << "n = " << (2 << k);   // p + 1 = 3, pre-asymptotic at n = 2
  }
}

// The same sphere octant as two trivariate patches from a G+Smo file
// (examples/geometry/sphere_octant2.xml: split at 45 degrees about z, the second patch's
// directions permuted, each with a degenerate pole face), loaded through the file's named
// boundaries: the interface is found and its control points merged, and u converges at the
// rate of the single patch (degree elevated to (3, 3, 2) / (2, 3, 3): at least 3).
TEST(ThickSphere, TwoPatchOctantFromAGismoFileConverges) {
  const double a = 1.0, b = 2.0, p = 1.0;
  auto exact = [&](const double* x) { return sphere_u(a, b, p, x); };
  std::vector<double> rel;
  for (int n : {2, 4}) {
    std::ostringstream os;
    os << "analysis: {type: solid}\n"
       << "bodies:\n  - name: sphere\n    material: {youngs_modulus: " << kE << ", poisson_ratio: " << kNu << "}\n"
       << "    geometry: {file: " << IGACONTACT_SOURCE_DIR << "/examples/geometry/sphere_octant2.xml}\n"
       << "    refine: {degree_elevate: 1, subdivide: " << n << "}\n"
       << "    boundary:\n      inner: {pressure: " << p << "}\n      x0: {displacement: {x: 0}}\n"
       << "      y0: {displacement: {y: 0}}\n      z0: {displacement: {z: 0}}\n"
       << "solver: {linear: {method: direct}}\n";
    const Solved s = solve_text(os.str());
    ASSERT_TRUE(s.res.converged) << s.res.message;
    ASSERT_EQ(s.P.bodies[0].interfaces.size(), 1u);
    EXPECT_EQ(find_inverted_elements(*s.sys, *s.res.u), "");
    if (Tpetra::getDefaultComm()->getRank() != 0) continue;
    const auto [err, norm] = l2_error3(s.P, s.disp[0], exact);
    rel.push_back(err / norm);
    std::printf("  thick sphere, 2 patches, n = %d: %lld dofs, L2 error of u %.3e (relative)\n", n,
                static_cast<long long>(s.sys->num_dofs()), err / norm);
  }
  if (Tpetra::getDefaultComm()->getRank() != 0) return;
  EXPECT_GT(std::log2(rel[0] / rel[1]), 2.7);
}

// Uniaxial stretch l1 of a box with free lateral faces at finite strain: the lateral stretch s
// and the first Piola stress P11 against the closed forms (reference-solutions.md, 3-D):
// neo-Hookean  mu (s - 1/s) + lambda ln(l1 s^2) / s = 0,  P11 = mu (l1 - 1/l1) + lambda ln(l1 s^2) / l1;
// Saint Venant-Kirchhoff  S22 = 0 gives s^2 = 1 - nu (l1^2 - 1), P11 = l1 E (l1^2 - 1) / 2.
// The deformation is homogeneous, so it is in every NURBS space: exact to Newton's tolerance.
TEST(FiniteStretch3D, UniaxialStretchMatchesTheClosedForms) {
  const double lam = kE * kNu / ((1 + kNu) * (1 - 2 * kNu)), mu = kE / (2 * (1 + kNu));
  const double Lx = 2.0, A = 1.0 * 0.5;
  for (const char* model : {"neo_hookean", "saint_venant_kirchhoff"})
    for (double l1 : {1.3, 0.8}) {
      double s = 1, P11 = 0;
      if (std::string(model) == "neo_hookean") {
        for (int it = 0; it < 100; ++it) {   // Newton on g(s) = mu (s - 1/s) + lam ln(l1 s^2) / s
          const double g = mu * (s - 1 / s) + lam * std::log(l1 * s * s) / s;
          const double dg = mu * (1 + 1 / (s * s)) + lam * (2 - std::log(l1 * s * s)) / (s * s);
          s -= g / dg;
        }
        P11 = mu * (l1 - 1 / l1) + lam * std::log(l1 * s * s) / l1;
      } else {
        s = std::sqrt(1 - kNu * (l1 * l1 - 1));
        P11 = l1 * kE * (l1 * l1 - 1) / 2;
      }
      std::ostringstream bc;
      bc.precision(17);
      bc << "      west: {displacement: {x: 0}}\n      south: {displacement: {y: 0}}\n"
         << "      front: {displacement: {z: 0}}\n      east: {displacement: {x: " << (l1 - 1) * Lx << "}}\n";
      const Solved r = solve_text(box_yaml("degree_elevate: 1, subdivide: [2, 2, 1]", bc.str(), ", kinematics: finite, load_steps: 4",
                                           std::string("model: ") + model + ", "));
      ASSERT_TRUE(r.res.converged) << model << " " << l1 << ": " << r.res.message;
      const auto reac = reactions_json(*r.sys, *r.res.residual);
      if (Tpetra::getDefaultComm()->getRank() != 0) continue;
      const double G[3][3] = {{l1 - 1, 0, 0}, {0, s - 1, 0}, {0, 0, s - 1}};
      EXPECT_LT(affine_error(r, G), 1e-8) << model << " l1 = " << l1;
      const double Rx = reac["block"]["east"][0].get<double>();
      EXPECT_NEAR(Rx, P11 * A, 1e-8 * std::abs(P11 * A)) << model << " l1 = " << l1;
      EXPECT_NEAR(reac["block"]["west"][0].get<double>(), -P11 * A, 1e-8 * std::abs(P11 * A)) << model;
    }
}

// The assembled 3-D tangent is the derivative of the assembled internal force (central
// differences along a random direction) for every material, on the rational thick-sphere
// octant, with finite kinematics the follower pressure on the curved inner face included; on
// any number of ranks.
TEST(Tangent3DSystem, IsTheDerivativeOfTheForceWithFollowerPressure) {
  auto comm = Tpetra::getDefaultComm();
  for (const std::string model : {"linear", "saint_venant_kirchhoff", "neo_hookean"}) {
    std::string yaml = sphere_octant_yaml(1.0, 2.0, 30.0, 2, 1);
    if (model != "linear") {
      yaml.replace(yaml.find("{type: solid}"), 13, "{type: solid, kinematics: finite}");
      yaml.replace(yaml.find("material: {"), 11, "material: {model: " + model + ", ");
    }
    const Problem P = parse_problem(yaml, "t.yaml");
    System sys(P, comm);
    const auto [diff, scale] = tangent_fd_check(sys, LoadPoint::at(0.7, 1));
    EXPECT_LT(diff, 1e-7 * scale) << model;
  }
}

// The follower pressure alone: on the inner face of the octant, at u = 0, the force it adds to
// f_int is minus the dead-load vector of the same pressure (both integrate -p n over the same
// reference face, to round-off), and the resultant tends to p times the projected area of the
// inner face (pi a^2 / 4 in each of x, y, z) as the p + 1 Gauss points per face element
// integrate the rational integrand better: by h^(2p+2) in principle, checked as at least a
// factor 16 from 2 to 4 elements per direction.
TEST(Tangent3DSystem, FollowerPressureAtRestEqualsTheDeadLoad) {
  auto comm = Tpetra::getDefaultComm();
  double previous = 0;
  for (int n : {2, 4}) {
    std::string yaml = sphere_octant_yaml(1.0, 2.0, 30.0, n, 1);
    const Problem Ps = parse_problem(yaml, "t.yaml");
    yaml.replace(yaml.find("{type: solid}"), 13, "{type: solid, kinematics: finite}");
    const Problem Pf = parse_problem(yaml, "t.yaml");
    System ss(Ps, comm), sf(Pf, comm);
    Vector u(sf.owned_map()), f(sf.owned_map());
    u.putScalar(0.0);
    const LoadPoint lp = LoadPoint::at(1.0, 1);
    sf.assemble_internal(&u, &f, nullptr, &lp);   // f_int(0) = 0 plus the follower -f_ext
    RCP<Vector> fd = ss.assemble_loads(1.0);
    f.update(1.0, *fd, 1.0);
    EXPECT_LT(f.normInf(), 1e-13 * fd->normInf());
    double loc[3] = {0, 0, 0}, glob[3];
    auto h = fd->getLocalViewHost(Tpetra::Access::ReadOnly);
    for (size_t l = 0; l < fd->getLocalLength(); ++l) loc[ss.owned_map()->getGlobalElement(l) % 3] += h(l, 0);
    Teuchos::reduceAll(*comm, Teuchos::REDUCE_SUM, 3, loc, glob);
    double worst = 0;
    for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(glob[c] - 30.0 * M_PI / 4));
    std::printf("  inner-face resultant, %d elements per direction: max error %.2e of %.2f\n", n, worst, 30.0 * M_PI / 4);
    if (previous > 0) EXPECT_LT(worst, previous / 16);
    previous = worst;
  }
}

// Cook's membrane (examples/cooks_membrane.yaml: neo-Hookean, finite strain, dead shear load)
// as a 3-D slab of thickness t with u_z = 0 on its front and back faces: the slab's discrete
// problem, degree 1 in z with one element, has the plane-strain solution in each layer (the
// problem is symmetric about the mid-plane, so both layers move alike and e_xz = e_yz = 0),
// so every control point moves as in the 2-D plane-strain run with thickness t: one code path,
// the same answer to Newton's tolerance, on 1 and 2 ranks.
TEST(Cook3D, SlabWithFixedFacesEqualsPlaneStrain) {
  const double t = 2.5;
  const std::string base = read(std::string(IGACONTACT_SOURCE_DIR) + "/examples/cooks_membrane.yaml");
  const std::string refine = "{degree_elevate: 1, subdivide: [8, 8]}";
  std::string two = base;
  two.replace(two.find("{kinematics: finite, load_steps: 4}"), 35, "{kinematics: finite, load_steps: 4, thickness: 2.5}");
  two.replace(two.find("{degree_elevate: 1, subdivide: [16, 16]}"), 40, refine);
  two.replace(two.find("output:"), std::string::npos, "solver: {linear: {method: direct}, newton: {tolerance: 1.0e-12}}\n");
  const Solved s2 = solve_text(two);
  ASSERT_TRUE(s2.res.converged) << s2.res.message;
  const double X[4][2] = {{0, 0}, {48, 44}, {0, 44}, {48, 60}};
  std::ostringstream os;
  os.precision(17);
  os << "analysis: {type: solid, kinematics: finite, load_steps: 4}\n"
     << "bodies:\n  - name: panel\n    material: {model: neo_hookean, youngs_modulus: 200.0, poisson_ratio: 0.3}\n"
     << "    geometry:\n      nurbs:\n        degree: [1, 1, 1]\n        knots: [[0, 0, 1, 1], [0, 0, 1, 1], [0, 0, 1, 1]]\n"
     << "        control_points: [";
  for (int k = 0; k < 2; ++k)
    for (int a = 0; a < 4; ++a) os << (k + a ? ", " : "") << "[" << X[a][0] << ", " << X[a][1] << ", " << k * t << ", 1]";
  os << "]\n    refine: {degree_elevate: [1, 1, 0], subdivide: [8, 8, 1]}\n"
     << "    boundary:\n      west: {displacement: {x: 0.0, y: 0.0, z: 0.0}}\n      east: {traction: [0.0, 6.0, 0.0]}\n"
     << "      front: {displacement: {z: 0.0}}\n      back: {displacement: {z: 0.0}}\n"
     << "solver: {linear: {method: direct}, newton: {tolerance: 1.0e-12}}\n";
  const Solved s3 = solve_text(os.str());
  ASSERT_TRUE(s3.res.converged) << s3.res.message;
  if (Tpetra::getDefaultComm()->getRank() != 0) return;
  const auto& u2 = s2.disp[0];
  const auto& u3 = s3.disp[0];
  const size_t n2 = u2.size() / 2;
  ASSERT_EQ(u3.size(), 3 * 2 * n2);
  double worst = 0, umax = 0;
  for (int k = 0; k < 2; ++k)
    for (size_t a = 0; a < n2; ++a) {
      for (int c = 0; c < 2; ++c) {
        worst = std::max(worst, std::abs(u3[3 * (a + k * n2) + c] - u2[2 * a + c]));
        umax = std::max(umax, std::abs(u2[2 * a + c]));
      }
      EXPECT_EQ(u3[3 * (a + k * n2) + 2], 0.0);
    }
  std::printf("  Cook: tip (2-D) %.6f %.6f; max |u_3D - u_2D| = %.1e of %.2f\n", u2[2 * (n2 - 1)], u2[2 * (n2 - 1) + 1], worst, umax);
  EXPECT_LT(worst, 1e-8 * umax);
}

namespace {

// u_h and grad u_h of body 0's patch at the parameters xi (3-D), through the kernels' basis.
template <int P>
void eval_grad3(const HostPatchData3& pd, const std::vector<double>& u, const double xi[3], double x[3], double uh[3],
                double G[3][3], double& det) {
  int s[3];
  for (int d = 0; d < 3; ++d) s[d] = find_span(pd.n[d], pd.p[d], xi[d], pd.U[d].data());
  double R[kNen<3, P>], dR[kNen<3, P>][3];
  int cps[kNen<3, P>];
  det = nurbs_grad<P>(pd, s, xi, R, dR, x);
  pd.local_cps(s, cps);
  for (int i = 0; i < 3; ++i) {
    uh[i] = 0;
    for (int j = 0; j < 3; ++j) G[i][j] = 0;
  }
  for (int a = 0; a < pd.nen(); ++a)
    for (int i = 0; i < 3; ++i) {
      uh[i] += R[a] * u[3 * cps[a] + i];
      for (int j = 0; j < 3; ++j) G[i][j] += dR[a][j] * u[3 * cps[a] + i];
    }
}

}  // namespace

// A manufactured solution on the unit cube, all faces held: u = v(x) c with
// v = sin(pi x) sin(pi y) sin(pi z), c = (1, 2, -1) / 100, and the body force
// b = -div sigma(u) = -(lambda + mu) H(v) c + 3 mu pi^2 v c (H: the Hessian of v). The L2
// error of u falls as h^(p+1), the H1 seminorm error as h^p, at p = 1..4 (n = 4 -> 8 elements
// per direction; rates within 0.3 of the optimal ones).
TEST(Manufactured3D, ConvergesAtOptimalRatesForDegreesOneToFour) {
  const double lam = kE * kNu / ((1 + kNu) * (1 - 2 * kNu)), mu = kE / (2 * (1 + kNu));
  const double c[3] = {0.01, 0.02, -0.01}, pi = M_PI;
  auto v = [&](double x, double y, double z) { return std::sin(pi * x) * std::sin(pi * y) * std::sin(pi * z); };
  auto gradv = [&](double x, double y, double z) {
    return std::array<double, 3>{pi * std::cos(pi * x) * std::sin(pi * y) * std::sin(pi * z),
                                 pi * std::sin(pi * x) * std::cos(pi * y) * std::sin(pi * z),
                                 pi * std::sin(pi * x) * std::sin(pi * y) * std::cos(pi * z)};
  };
  auto body = [&](double x, double y, double z) {
    const double s[3] = {std::sin(pi * x), std::sin(pi * y), std::sin(pi * z)}, k[3] = {std::cos(pi * x), std::cos(pi * y), std::cos(pi * z)};
    double H[3][3];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        double h = pi * pi;
        for (int m = 0; m < 3; ++m) h *= (m == i || m == j) ? (i == j ? s[m] : k[m]) : s[m];
        H[i][j] = i == j ? -h : h;
      }
    std::array<double, 3> b{};
    for (int i = 0; i < 3; ++i) {
      double Hc = 0;
      for (int j = 0; j < 3; ++j) Hc += H[i][j] * c[j];
      b[i] = -(lam + mu) * Hc + 3 * mu * pi * pi * v(x, y, z) * c[i];
    }
    return b;
  };
  for (int p = 1; p <= 4; ++p) {
    double el2[2], eh1[2];
    int k = 0;
    for (int n : {4, 8}) {
      std::ostringstream os;
      os << "analysis: {type: solid}\n"
         << "bodies:\n  - name: cube\n    material: {youngs_modulus: " << kE << ", poisson_ratio: " << kNu << "}\n"
         << "    geometry: {box: {origin: [0, 0, 0], size: [1, 1, 1]}}\n"
         << "    refine: {degree_elevate: " << p - 1 << ", subdivide: " << n << "}\n"
         << "    boundary:\n";
      for (const char* f : {"west", "east", "south", "north", "front", "back"})
        os << "      " << f << ": {displacement: {x: 0, y: 0, z: 0}}\n";
      os << "solver: {linear: {method: direct}}\n";
      const Solved s = solve_text(os.str(), Tpetra::getDefaultComm(), [&](System& sys) { sys.add_body_force(0, System::BodyForceFunction3(body)); });
      ASSERT_TRUE(s.res.converged) << s.res.message;
      if (Tpetra::getDefaultComm()->getRank() != 0) continue;
      const Patch& pt = s.P.bodies[0].patches[0];
      const HostPatchData3 pd = host_patch_data3(pt);
      const auto u = s.P.bodies[0].patch_values(0, s.disp[0]);
      double e0 = 0, e1 = 0, n0 = 0, n1 = 0;
      GaussRule g = gauss_rule(p + 2);
      dispatch_degree(p, [&](auto PP) {
        constexpr int P = decltype(PP)::value;
        for (int e = 0; e < pd.num_elements(); ++e) {
          int ei[3], sp[3];
          pd.element_spans(e, ei, sp);
          double lo[3], hh[3];
          for (int d = 0; d < 3; ++d) {
            lo[d] = pt.knots[d][sp[d]];
            hh[d] = 0.5 * (pt.knots[d][sp[d] + 1] - lo[d]);
          }
          for (int q2 = 0; q2 < g.n; ++q2)
            for (int q1 = 0; q1 < g.n; ++q1)
              for (int q0 = 0; q0 < g.n; ++q0) {
                const double xi[3] = {lo[0] + hh[0] * (g.x[q0] + 1), lo[1] + hh[1] * (g.x[q1] + 1), lo[2] + hh[2] * (g.x[q2] + 1)};
                double x[3], uh[3], G[3][3], det;
                eval_grad3<P>(pd, u, xi, x, uh, G, det);
                const double w = std::abs(det) * g.w[q0] * g.w[q1] * g.w[q2] * hh[0] * hh[1] * hh[2];
                const double vv = v(x[0], x[1], x[2]);
                const auto gv = gradv(x[0], x[1], x[2]);
                for (int i = 0; i < 3; ++i) {
                  e0 += (uh[i] - vv * c[i]) * (uh[i] - vv * c[i]) * w;
                  n0 += vv * c[i] * vv * c[i] * w;
                  for (int j = 0; j < 3; ++j) {
                    e1 += (G[i][j] - c[i] * gv[j]) * (G[i][j] - c[i] * gv[j]) * w;
                    n1 += c[i] * gv[j] * c[i] * gv[j] * w;
                  }
                }
              }
        }
      });
      el2[k] = std::sqrt(e0 / n0);
      eh1[k] = std::sqrt(e1 / n1);
      std::printf("  manufactured 3-D, p = %d, n = %d: %lld dofs, L2 %.3e, H1 %.3e\n", p, n, static_cast<long long>(s.sys->num_dofs()),
                  el2[k], eh1[k]);
      ++k;
    }
    if (Tpetra::getDefaultComm()->getRank() != 0) continue;
    EXPECT_GT(std::log2(el2[0] / el2[1]), p + 1 - 0.3) << "p = " << p;
    EXPECT_GT(std::log2(eh1[0] / eh1[1]), p - 0.3) << "p = " << p;
  }
}

// solver.linear.preconditioner: control_net (the default for solids): CG with BoomerAMG of
// the degree-1 stiffness on the same control nets gives the direct solver's answer on the
// two-patch sphere octant (rational, a merged degenerate pole, an interface in permuted
// directions) and GMRES the same on a neo-Hookean block with a follower pressure. With
// contact, BoomerAMG is built of the control nets' stiffness + K_c: on the 3-D contact patch
// test the top block is held in z by contact alone (the control nets' stiffness alone is
// singular there), and GMRES gives the direct answer with KTS and with mortar.
TEST(ControlNetPreconditioner, GivesTheDirectAnswer) {
  std::ostringstream os;
  os << "analysis: {type: solid}\n"
     << "bodies:\n  - name: sphere\n    material: {youngs_modulus: " << kE << ", poisson_ratio: " << kNu << "}\n"
     << "    geometry: {file: " << IGACONTACT_SOURCE_DIR << "/examples/geometry/sphere_octant2.xml}\n"
     << "    refine: {degree_elevate: 1, subdivide: 4}\n"
     << "    boundary:\n      inner: {pressure: 1.0}\n      x0: {displacement: {x: 0}}\n"
     << "      y0: {displacement: {y: 0}}\n      z0: {displacement: {z: 0}}\n";
  const std::string block =
      "analysis: {type: solid, kinematics: finite, load_steps: 2}\n"
      "bodies:\n  - name: block\n    material: {model: neo_hookean, youngs_modulus: 1000.0, poisson_ratio: 0.3}\n"
      "    geometry: {box: {origin: [0, 0, 0], size: [3, 1, 1]}}\n"
      "    refine: {degree_elevate: 1, subdivide: [6, 2, 2]}\n"
      "    boundary:\n      west: {displacement: {x: 0, y: 0, z: 0}}\n      back: {pressure: 20.0}\n"
      "      east: {traction: [0, 15.0, 0]}\n";
  const std::string patch = read(IGACONTACT_SOURCE_DIR "/examples/contact_patch_3d.yaml");
  const std::vector<std::tuple<std::string, std::string, std::string>> cases = {
      {os.str(), "cg", ""}, {block, "gmres", ""}, {patch, "gmres", "kts_penalty"}, {patch, "gmres", "mortar_penalty"}};
  for (const auto& [yaml, method, contact] : cases) {
    std::vector<std::string> sd = {"solver.linear.method=direct"};
    std::vector<std::string> sc = {"solver.linear.method=" + method, "solver.linear.tolerance=1e-13", "solver.linear.forcing=fixed"};
    if (!contact.empty()) {
      sd.push_back("contact.0.method=" + contact);
      sc.push_back("contact.0.method=" + contact);
    }
    const Solved d = solve_text(yaml, Tpetra::getDefaultComm(), {}, sd);
    const Solved c = solve_text(yaml, Tpetra::getDefaultComm(), {}, sc);
    ASSERT_TRUE(d.res.converged && c.res.converged) << c.res.message;
    EXPECT_EQ(c.P.linear.preconditioner, Preconditioner::ControlNet);
    if (Tpetra::getDefaultComm()->getRank() != 0) continue;
    const double rel = relative_displacement_difference(c, d);
    std::printf("  control_net, %s %s: %lld dofs, %d Krylov iterations, max |u - u_direct| / max |u| = %.1e\n", method.c_str(),
                contact.c_str(), static_cast<long long>(c.sys->num_dofs()), c.res.linear_iterations, rel);
    EXPECT_LT(rel, 1e-9) << method << " " << contact;
  }
}

// control_net with contact: where a fresh preconditioner of the control nets + K_c does not
// reach the tolerance within LinearOptions::control_net_contact_limit iterations, the solve
// is taken up with BoomerAMG of the tangent (for the rest of the increment). Forced here with
// a limit of 1 on the 3-D contact patch test: the direct answer, and more preconditioners
// built than with the default limit (each increment's first one is the control nets').
TEST(ControlNetPreconditioner, FallsBackToTheTangentsAmgWithContact) {
  const std::string patch = read(IGACONTACT_SOURCE_DIR "/examples/contact_patch_3d.yaml");
  const std::vector<std::string> sets = {"solver.linear.method=gmres", "solver.linear.tolerance=1e-13",
                                         "solver.linear.forcing=fixed"};
  const Solved d = solve_text(patch, Tpetra::getDefaultComm(), {}, {"solver.linear.method=direct"});
  const Solved c = solve_text(patch, Tpetra::getDefaultComm(), {}, sets);
  Solved f;
  f.P = parse_problem(patch, "test.yaml", sets);
  f.P.linear.control_net_contact_limit = 1;
  f.sys = rcp(new System(f.P, Tpetra::getDefaultComm()));
  f.res = solve(*f.sys);
  f.disp = gather_displacements(*f.sys, *f.res.u);
  ASSERT_TRUE(d.res.converged && c.res.converged && f.res.converged) << f.res.message;
  EXPECT_EQ(f.P.linear.preconditioner, Preconditioner::ControlNet);
  std::printf("  limit 200: %d GMRES iterations, %d preconditioners; limit 1: %d, %d; max |u - u_direct| / max |u| = %.1e\n",
              c.res.linear_iterations, c.res.preconditioner_builds, f.res.linear_iterations, f.res.preconditioner_builds,
              relative_displacement_difference(f, d));
  EXPECT_GT(f.res.preconditioner_builds, c.res.preconditioner_builds);
  if (Tpetra::getDefaultComm()->getRank() == 0) EXPECT_LT(relative_displacement_difference(f, d), 1e-9);
}
