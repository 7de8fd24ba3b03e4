#pragma once
// Helpers shared by the tests: solve a problem given as YAML text, integrate errors.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <random>
#include <fstream>
#include <sstream>
#include <string>

#include "io/fields.hpp"
#include "io/output.hpp"
#include "model/problem.hpp"
#include "solver/newton.hpp"

namespace iga::test {

struct Solved {
  Problem P;
  RCP<System> sys;
  SolveResult res;
  std::vector<std::vector<double>> disp;   // per body, on rank 0
};

/// The whole text of a file (an example problem).
inline std::string read(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

inline Solved solve_text(const std::string& yaml, RCP<const Comm> comm = Tpetra::getDefaultComm(),
                         const std::function<void(System&)>& setup = {},
                         const std::vector<std::string>& sets = {}) {
  Solved s;
  s.P = parse_problem(yaml, "test.yaml", sets);
  s.sys = rcp(new System(s.P, comm));
  if (setup) setup(*s.sys);
  s.res = solve(*s.sys);
  s.disp = gather_displacements(*s.sys, *s.res.u);
  return s;
}

/// A curved master (outer arc of a quarter annulus, radius 2, from 45 to 135 degrees, top at
/// (0, 2)) and a block whose flat bottom at block_y cuts into it (or, ring_is_master false,
/// the block bottom as master). Degree p in both bodies; the block's refinement is
/// `block_refine` besides the degree elevation.
struct RingAndBlock {
  int p = 2;
  double block_y = 1.985;
  std::string method = "kts_penalty";
  bool ring_is_master = true;
  int quadrature_points = 4;                          // 0: the method's default
  std::string block_refine = "subdivide: [5, 2]";
  std::string yaml() const {
    std::ostringstream os;
    os << "bodies:\n"
       << "  - name: ring\n    material: {youngs_modulus: 1000.0, poisson_ratio: 0.3}\n"
       << "    geometry: {quarter_annulus: {center: [0, 0], inner_radius: 1.0, outer_radius: 2.0, start_angle: 45}}\n"
       << "    refine: {degree_elevate: [" << p - 2 << ", " << p - 1 << "], subdivide: [7, 2]}\n"
       << "    boundary: {south: {displacement: {x: 0, y: 0}}}\n"
       << "  - name: block\n    material: {youngs_modulus: 500.0, poisson_ratio: 0.25}\n"
       << "    geometry: {rectangle: {origin: [-0.5, " << block_y << "], size: [1.0, 0.5]}}\n"
       << "    refine: {degree_elevate: " << p - 1 << ", " << block_refine << "}\n"
       << "    boundary: {north: {displacement: {x: 0, y: -0.01}}}\n";
    const std::string ring = "{body: ring, side: north}", block = "{body: block, side: south}";
    os << "contact:\n  - {master: " << (ring_is_master ? ring : block) << ", slave: " << (ring_is_master ? block : ring)
       << ", method: " << method << ", penalty: 1.0e4";
    if (quadrature_points > 0) os << ", quadrature_points: " << quadrature_points;
    os << "}\n";
    return os.str();
  }
};

// A 2-D patch extruded into a slab of thickness 1 along z (degree 1, one element): the same
// control net at z = 0 and z = 1, as an inline trivariate NURBS.
inline std::string extruded_nurbs(const Patch& P) {
  std::ostringstream os;
  os.precision(17);
  auto knots = [&](const std::vector<double>& U) {
    os << "[";
    for (size_t k = 0; k < U.size(); ++k) os << (k ? ", " : "") << U[k];
    os << "]";
  };
  os << "      nurbs:\n        degree: [" << P.degree[0] << ", " << P.degree[1] << ", 1]\n        knots: [";
  knots(P.knots[0]);
  os << ", ";
  knots(P.knots[1]);
  os << ", [0, 0, 1, 1]]\n        control_points: [\n";
  for (int k = 0; k < 2; ++k)
    for (const ControlPoint& c : P.cp) os << "          [" << c.x[0] << ", " << c.x[1] << ", " << k << ", " << c.w << "],\n";
  os << "        ]\n";
  return os.str();
}

/// A solved RingAndBlock problem (2-D) extruded into a slab held at u_z = 0 on its front and
/// back faces (plane strain), as a solid problem: `analysis` the keys of its analysis map after
/// the type, `block_top` the block's north displacement as "x: .., y: .." (the ring's south is
/// held), `contact` more keys of the KTS pair (4 quadrature points per direction).
inline std::string extruded_ring_and_block(const Problem& P2, const std::string& analysis, const std::string& block_top,
                                           const std::string& contact = "") {
  std::ostringstream os;
  os << "analysis: {type: solid" << analysis << "}\nbodies:\n";
  const std::string faces = "front: {displacement: {z: 0}}, back: {displacement: {z: 0}}}";
  const std::string bc[2] = {"{south: {displacement: {x: 0, y: 0, z: 0}}, " + faces,
                             "{north: {displacement: {" + block_top + ", z: 0}}, " + faces};
  for (int b = 0; b < 2; ++b) {
    const Body& B = P2.bodies[b];
    os << "  - name: " << B.name << "\n    material: {youngs_modulus: " << B.E << ", poisson_ratio: " << B.nu << "}\n"
       << "    geometry:\n" << extruded_nurbs(B.patches[0]) << "    boundary: " << bc[b] << "\n";
  }
  os << "contact:\n  - {master: {body: ring, side: north}, slave: {body: block, side: south}, method: kts_penalty, "
        "penalty: 1.0e4, quadrature_points: 4" << contact << "}\n";
  return os.str();
}

/// The largest |A_ij - B_ij| over the owned rows of all ranks (the same pattern expected,
/// entry by entry), and in `scale` the largest |A_ij|.
inline double max_abs_difference(const Matrix& A, const Matrix& B, double& scale) {
  double diff = 0;
  scale = 0;
  const auto& rows = *A.getRowMap();
  for (size_t l = 0; l < A.getNodeNumRows(); ++l) {
    const GO g = rows.getGlobalElement(static_cast<LO>(l));
    const size_t n = A.getNumEntriesInGlobalRow(g);
    typename Matrix::nonconst_global_inds_host_view_type ca("c", n), cb("c", n);
    typename Matrix::nonconst_values_host_view_type va("v", n), vb("v", n);
    size_t na = 0, nb = 0;
    A.getGlobalRowCopy(g, ca, va, na);
    B.getGlobalRowCopy(g, cb, vb, nb);
    EXPECT_EQ(na, nb);
    for (size_t k = 0; k < na && k < nb; ++k) {
      EXPECT_EQ(ca(k), cb(k));
      diff = std::max(diff, std::abs(va(k) - vb(k)));
      scale = std::max(scale, std::abs(va(k)));
    }
  }
  const auto comm = A.getRowMap()->getComm();
  double in[2] = {diff, scale}, out[2];
  Teuchos::reduceAll(*comm, Teuchos::REDUCE_MAX, 2, in, out);
  scale = out[1];
  return out[0];
}

struct Exact {
  std::function<std::array<double, 2>(double, double)> u;        // displacement
  std::function<std::array<double, 3>(double, double)> sigma;    // sxx, syy, sxy
};

/// The largest displacement difference of two runs of one problem, over every body, relative
/// to b's largest displacement (the control-point displacements gathered on rank 0; 0 on
/// the other ranks).
inline double relative_displacement_difference(const Solved& a, const Solved& b) {
  double d = 0, scale = 0;
  for (size_t body = 0; body < b.disp.size() && body < a.disp.size(); ++body)
    for (size_t k = 0; k < b.disp[body].size() && k < a.disp[body].size(); ++k) {
      d = std::max(d, std::abs(a.disp[body][k] - b.disp[body][k]));
      scale = std::max(scale, std::abs(b.disp[body][k]));
    }
  return scale > 0 ? d / scale : d;
}

/// Newton iterations over all load steps
inline int newton_total(const Solved& s) {
  int n = 0;
  for (int k : s.res.newton_iterations) n += k;
  return n;
}

/// Lame: thick-walled cylinder under internal pressure p, inner radius a, outer b, plane
/// strain (../shared/reference-solutions.md).
inline Exact lame_cylinder(double a, double b, double p, double E, double nu) {
  Exact ex;
  const double c = p * a * a / (b * b - a * a);
  ex.u = [c, b, E, nu](double x, double y) {
    const double r = std::hypot(x, y);
    const double ur = (1 + nu) / E * c * ((1 - 2 * nu) * r + b * b / r);
    return std::array<double, 2>{ur * x / r, ur * y / r};
  };
  ex.sigma = [c, b](double x, double y) {
    const double r2 = x * x + y * y, srr = c * (1 - b * b / r2), stt = c * (1 + b * b / r2);
    const double cs = x * x / r2, sn = y * y / r2, cssn = x * y / r2;
    return std::array<double, 3>{srr * cs + stt * sn, srr * sn + stt * cs, (srr - stt) * cssn};
  };
  return ex;
}

/// Kirsch: infinite plate with a hole of radius R under remote tension T along x, plane strain
/// (../shared/reference-solutions.md).
inline Exact kirsch_plate(double R, double T, double E, double nu) {
  Exact ex;
  const double mu = E / (2 * (1 + nu)), kappa = 3 - 4 * nu;
  ex.sigma = [R, T](double x, double y) {
    const double r = std::hypot(x, y), t = std::atan2(y, x), a2 = R * R / (r * r), a4 = a2 * a2;
    return std::array<double, 3>{T * (1 - a2 * (1.5 * std::cos(2 * t) + std::cos(4 * t)) + 1.5 * a4 * std::cos(4 * t)),
                                 T * (-a2 * (0.5 * std::cos(2 * t) - std::cos(4 * t)) - 1.5 * a4 * std::cos(4 * t)),
                                 T * (-a2 * (0.5 * std::sin(2 * t) + std::sin(4 * t)) + 1.5 * a4 * std::sin(4 * t))};
  };
  ex.u = [R, T, mu, kappa](double x, double y) {
    const double r = std::hypot(x, y), t = std::atan2(y, x), c = T * R / (8 * mu);
    return std::array<double, 2>{c * (r / R * (kappa + 1) * std::cos(t) + 2 * R / r * ((1 + kappa) * std::cos(t) + std::cos(3 * t)) -
                                      2 * std::pow(R / r, 3) * std::cos(3 * t)),
                                 c * (r / R * (kappa - 3) * std::sin(t) + 2 * R / r * ((1 - kappa) * std::sin(t) + std::sin(3 * t)) -
                                      2 * std::pow(R / r, 3) * std::sin(3 * t))};
  };
  return ex;
}

struct Errors {
  double u_l2 = 0, u_rel = 0, s_l2 = 0, s_rel = 0;
};

/// Relative L2 errors of displacement and stress over one body (rank 0 only).
inline Errors l2_errors(const Solved& s, int body, const Exact& ex, int extra_points = 2) {
  Errors e;
  double eu = 0, nu = 0, es = 0, ns = 0;
  for (size_t k = 0; k < s.P.bodies[body].patches.size(); ++k) {
  BodyField f(s.P, body, s.disp[body], static_cast<int>(k));
  const Patch& pt = s.P.bodies[body].patches[k];
  const GaussRule g0 = gauss_rule(pt.degree[0] + extra_points), g1 = gauss_rule(pt.degree[1] + extra_points);
  for (int s1 : pt.element_spans(1))
    for (int s0 : pt.element_spans(0)) {
      const double ua = pt.knots[0][s0], ub = pt.knots[0][s0 + 1], va = pt.knots[1][s1], vb = pt.knots[1][s1 + 1];
      for (int j = 0; j < g1.n; ++j)
        for (int i = 0; i < g0.n; ++i) {
          const double u = ua + 0.5 * (ub - ua) * (g0.x[i] + 1), v = va + 0.5 * (vb - va) * (g1.x[j] + 1);
          const FieldPoint p = f.eval(u, v, s0, s1);
          const double w = std::abs(p.detJ) * g0.w[i] * g1.w[j] * 0.25 * (ub - ua) * (vb - va);
          const auto ue = ex.u(p.x, p.y);
          const auto se = ex.sigma(p.x, p.y);
          eu += w * (std::pow(p.ux - ue[0], 2) + std::pow(p.uy - ue[1], 2));
          nu += w * (ue[0] * ue[0] + ue[1] * ue[1]);
          es += w * (std::pow(p.sxx - se[0], 2) + std::pow(p.syy - se[1], 2) + 2 * std::pow(p.sxy - se[2], 2));
          ns += w * (se[0] * se[0] + se[1] * se[1] + 2 * se[2] * se[2]);
        }
    }
  }
  e.u_l2 = std::sqrt(eu);
  e.u_rel = std::sqrt(eu / nu);
  e.s_l2 = std::sqrt(es);
  e.s_rel = std::sqrt(es / ns);
  return e;
}

/// The largest |K v - (f(u + h v) - f(u - h v)) / 2h| and |K v| (all ranks) of the System's
/// tangent K at a random u (entries in [-amplitude, amplitude]) along a random v, h = 1e-6,
/// at load point lp: the tangent against central differences of the internal force.
inline std::pair<double, double> tangent_fd_check(const System& sys, const LoadPoint& lp, double amplitude = 0.05) {
  Vector u(sys.owned_map()), v(sys.owned_map());
  u.randomize(-amplitude, amplitude);
  v.randomize(-1.0, 1.0);
  RCP<Matrix> K;
  sys.assemble_internal(&u, nullptr, &K, &lp);
  Vector Kv(sys.owned_map()), fp(sys.owned_map()), fm(sys.owned_map()), up(sys.owned_map()), um(sys.owned_map());
  K->apply(v, Kv);
  const double h = 1e-6;
  up.update(1.0, u, h, v, 0.0);
  um.update(1.0, u, -h, v, 0.0);
  sys.assemble_internal(&up, &fp, nullptr, &lp);
  sys.assemble_internal(&um, &fm, nullptr, &lp);
  fp.update(-1.0 / (2 * h), fm, 1.0 / (2 * h));
  fp.update(-1.0, Kv, 1.0);
  return {fp.normInf(), Kv.normInf()};
}

/// Sum of all external loads (x, y) at load factor 1, over all ranks.
inline std::array<double, 2> total_load(const System& sys) {
  RCP<Vector> f = sys.assemble_loads(1.0);
  auto h = f->getLocalViewHost(Tpetra::Access::ReadOnly);
  double loc[2] = {0, 0}, glob[2];
  for (size_t l = 0; l < f->getLocalLength(); ++l) loc[sys.owned_map()->getGlobalElement(l) % 2] += h(l, 0);
  Teuchos::reduceAll(*sys.comm(), Teuchos::REDUCE_SUM, 2, loc, glob);
  return {glob[0], glob[1]};
}

/// Sum of all reactions (x, y), over all ranks.
inline std::array<double, 2> total_reaction(const System& sys, const Vector& residual) {
  const auto j = reactions_json(sys, residual);
  std::array<double, 2> r{0, 0};
  for (const auto& body : j)
    for (const auto& side : body) { r[0] += side[0].get<double>(); r[1] += side[1].get<double>(); }
  return r;
}

/// A distorted NURBS patch of degrees (p, p): unit square with perturbed interior control
// points and weights, 3 x 2 elements.
inline Patch distorted_patch(int p, unsigned seed = 7, bool rational = true) {
  Patch P;
  P.degree = {1, 1};
  P.knots = {uniform_open_knots(1, 1), uniform_open_knots(1, 1)};
  P.cp = {{{0, 0}, 1}, {{2, 0}, 1}, {{0, 1}, 1}, {{2, 1}, 1}};
  P.elevate(0, p - 1);
  P.elevate(1, p - 1);
  P.subdivide(0, 3);
  P.subdivide(1, 2);
  P.insert_knot(0, 0.1);  // non-uniform spans
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> d(-0.08, 0.08), w(0.75, 1.25);
  for (int j = 1; j + 1 < P.ncp(1); ++j)
    for (int i = 1; i + 1 < P.ncp(0); ++i) {
      auto& c = P.cp[P.index(i, j)];
      c.x[0] += d(rng); c.x[1] += d(rng);
      if (rational) c.w = w(rng);
    }
  return P;
}

/// YAML of a single patch: rollers on west and south, tractions (10, 0) east and (0, 5) north.
inline std::string patch_yaml(const Patch& P) {
  std::ostringstream os;
  os.precision(17);
  os << "bodies:\n  - name: b\n    material: {youngs_modulus: 1000.0, poisson_ratio: 0.3}\n    geometry:\n      nurbs:\n"
     << "        degree: [" << P.degree[0] << ", " << P.degree[1] << "]\n        knots: [[";
  for (size_t k = 0; k < P.knots[0].size(); ++k) os << (k ? ", " : "") << P.knots[0][k];
  os << "], [";
  for (size_t k = 0; k < P.knots[1].size(); ++k) os << (k ? ", " : "") << P.knots[1][k];
  os << "]]\n        control_points:\n";
  for (const auto& c : P.cp) os << "          - [" << c.x[0] << ", " << c.x[1] << ", " << c.w << "]\n";
  os << "    boundary:\n      west: {displacement: {x: 0.0}}\n      south: {displacement: {y: 0.0}}\n"
     << "      east: {traction: [10.0, 0.0]}\n      north: {traction: [0.0, 5.0]}\n";
  return os.str();
}


}  // namespace iga::test
