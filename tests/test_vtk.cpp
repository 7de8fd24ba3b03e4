// VTK rational Bezier output (io/vtk): the point order, the cells' geometry against the
// NURBS patch, the displacement coefficients, the per-element stress fit, the .vtu/.pvd text.
// With IGACONTACT_VTU_OUT set, WritesQuarterAnnulusFiles leaves its .vtu files there for the
// ParaView check (tests/paraview/check_bezier.py, run by tests/paraview_bezier.sh).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <set>

#include "io/vtk.hpp"
#include "kernels/nurbs_basis.hpp"
#include "model/bezier.hpp"
#include "support.hpp"

using namespace iga;

namespace {

// A quarter annulus (centre 0, radii 1 and 2; xi around, eta radial, inner = south) at degrees
// (3, 2) with non-uniform spans under internal pressure, and a block of degrees (1, 2).
std::string annulus_yaml() {
  return "analysis: {type: plane_strain}\n"
         "bodies:\n"
         "  - name: annulus\n"
         "    material: {youngs_modulus: 2.0e5, poisson_ratio: 0.3}\n"
         "    geometry: {quarter_annulus: {center: [0, 0], inner_radius: 1.0, outer_radius: 2.0, start_angle: 0}}\n"
         "    refine: {degree_elevate: [1, 1], insert_knots: [[0.3], [0.7]], subdivide: [3, 2]}\n"
         "    boundary:\n"
         "      west: {displacement: {y: 0.0}}\n"
         "      east: {displacement: {x: 0.0}}\n"
         "      south: {pressure: 10.0}\n"
         "  - name: block\n"
         "    material: {youngs_modulus: 1.0e3, poisson_ratio: 0.25}\n"
         "    geometry: {rectangle: {origin: [3.0, 0.0], size: [1.0, 0.5]}}\n"
         "    refine: {degree_elevate: [0, 1], subdivide: [3, 2]}\n"
         "    boundary:\n"
         "      west: {displacement: {x: 0.0, y: 0.0}}\n"
         "      east: {traction: [1.0, 0.5]}\n"
         "solver:\n  linear: {method: gmres, preconditioner: muelu, tolerance: 1.0e-12}\n";
}

// Solved once; only the problem and the displacements are kept (no Tpetra objects may
// outlive Tpetra's scope guard in main).
struct Annulus {
  Problem P;
  std::vector<std::vector<double>> disp;
};
const Annulus& annulus() {
  static const Annulus a = [] {
    const test::Solved s = test::solve_text(annulus_yaml());
    return Annulus{s.P, s.disp};
  }();
  return a;
}

// Rational Bezier evaluation of a cell's point array (ncomp per point, VTK order) at (t0, t1).
void eval_cell(const BezierMesh& m, size_t cell, const std::vector<double>& a, int ncomp, double t0, double t1,
               double* out) {
  const int p0 = m.degrees[3 * cell], p1 = m.degrees[3 * cell + 1];
  const size_t first = cell == 0 ? 0 : static_cast<size_t>(m.offsets[cell - 1]);
  double b0[kMaxBasis1D], b1[kMaxBasis1D], W = 0;
  bernstein(p0, t0, b0);
  bernstein(p1, t1, b1);
  for (int c = 0; c < ncomp; ++c) out[c] = 0;
  for (int j = 0; j <= p1; ++j)
    for (int i = 0; i <= p0; ++i) {
      const size_t q = static_cast<size_t>(m.connectivity[first + vtk_quad_point_index(i, j, p0, p1)]);
      const double r = b0[i] * b1[j] * m.weights[q];
      W += r;
      for (int c = 0; c < ncomp; ++c) out[c] += r * a[q * ncomp + c];
    }
  for (int c = 0; c < ncomp; ++c) out[c] /= W;
}

}  // namespace

TEST(VtkOrder, HigherOrderQuadrilateralPointIndex) {
  // degrees (2, 2): the 9-point quad of VTK's documentation
  EXPECT_EQ(vtk_quad_point_index(0, 0, 2, 2), 0);
  EXPECT_EQ(vtk_quad_point_index(2, 0, 2, 2), 1);
  EXPECT_EQ(vtk_quad_point_index(2, 2, 2, 2), 2);
  EXPECT_EQ(vtk_quad_point_index(0, 2, 2, 2), 3);
  EXPECT_EQ(vtk_quad_point_index(1, 0, 2, 2), 4);
  EXPECT_EQ(vtk_quad_point_index(2, 1, 2, 2), 5);
  EXPECT_EQ(vtk_quad_point_index(1, 2, 2, 2), 6);
  EXPECT_EQ(vtk_quad_point_index(0, 1, 2, 2), 7);
  EXPECT_EQ(vtk_quad_point_index(1, 1, 2, 2), 8);
  // degrees (3, 2): edges in VTK's directions (the top edge runs with i, the left one with j)
  const int expect[3][4] = {{0, 4, 5, 1}, {9, 10, 11, 6}, {3, 7, 8, 2}};   // [j][i]
  for (int j = 0; j <= 2; ++j)
    for (int i = 0; i <= 3; ++i) EXPECT_EQ(vtk_quad_point_index(i, j, 3, 2), expect[j][i]) << i << " " << j;
  // a permutation for every pair of degrees
  for (int p0 = 1; p0 <= 5; ++p0)
    for (int p1 = 1; p1 <= 5; ++p1) {
      std::set<int> seen;
      for (int j = 0; j <= p1; ++j)
        for (int i = 0; i <= p0; ++i) seen.insert(vtk_quad_point_index(i, j, p0, p1));
      EXPECT_EQ(static_cast<int>(seen.size()), (p0 + 1) * (p1 + 1));
      EXPECT_EQ(*seen.begin(), 0);
      EXPECT_EQ(*seen.rbegin(), (p0 + 1) * (p1 + 1) - 1);
    }
}

// The hexahedron's order against VTK's own: the tables below are
// vtkBezierHexahedron::PointIndexFromIJK(i, j, k, order) printed by ParaView 5.11's pvpython,
// (i, j, k) with i fastest, then j, then k.
TEST(VtkOrder, HigherOrderHexahedronPointIndexIsVtks) {
  const std::vector<std::pair<std::array<int, 3>, std::vector<int>>> vtk = {
      {{2, 2, 2}, {0, 8, 1, 11, 24, 9, 3, 10, 2, 16, 22, 17, 20, 26, 21, 19, 23, 18, 4, 12, 5, 15, 25, 13, 7, 14, 6}},
      {{3, 2, 1}, {0, 8, 9, 1, 13, 20, 21, 10, 3, 11, 12, 2, 4, 14, 15, 5, 19, 22, 23, 16, 7, 17, 18, 6}},
      {{1, 3, 2}, {0, 1, 10, 8, 11, 9, 3, 2, 16, 17, 20, 22, 21, 23, 19, 18, 4, 5, 14, 12, 15, 13, 7, 6}}};
  for (const auto& [p, want] : vtk) {
    size_t q = 0;
    for (int k = 0; k <= p[2]; ++k)
      for (int j = 0; j <= p[1]; ++j)
        for (int i = 0; i <= p[0]; ++i, ++q)
          EXPECT_EQ(vtk_hex_point_index(i, j, k, p[0], p[1], p[2]), want[q]) << p[0] << p[1] << p[2] << ": " << i << j << k;
  }
  // a permutation for every triple of degrees 1..4
  for (int p0 = 1; p0 <= 4; ++p0)
    for (int p1 = 1; p1 <= 4; ++p1)
      for (int p2 = 1; p2 <= 4; ++p2) {
        std::set<int> seen;
        for (int k = 0; k <= p2; ++k)
          for (int j = 0; j <= p1; ++j)
            for (int i = 0; i <= p0; ++i) seen.insert(vtk_hex_point_index(i, j, k, p0, p1, p2));
        const int n = (p0 + 1) * (p1 + 1) * (p2 + 1);
        ASSERT_EQ(static_cast<int>(seen.size()), n) << p0 << p1 << p2;
        EXPECT_EQ(*seen.begin(), 0);
        EXPECT_EQ(*seen.rbegin(), n - 1);
      }
}

TEST(VtkBezier, CellsReproduceThePatchAndTheDisplacement) {
  const auto& s = annulus();
  const BezierMesh m = bezier_mesh(s.P, s.disp);
  ASSERT_EQ(m.num_cells(), static_cast<size_t>(s.P.bodies[0].patches[0].num_elements() + s.P.bodies[1].patches[0].num_elements()));
  EXPECT_EQ(m.body_names, (std::vector<std::string>{"annulus", "block"}));
  std::vector<BodyField> fields;
  for (int b = 0; b < 2; ++b) fields.emplace_back(s.P, b, s.disp[b]);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> U(0, 1);
  std::vector<double> umax(2, 0.0);
  for (int b = 0; b < 2; ++b)
    for (double v : s.disp[b]) umax[b] = std::max(umax[b], std::abs(v));
  ASSERT_GT(umax[0], 0);
  ASSERT_GT(umax[1], 0);
  int on_circle = 0;
  for (size_t c = 0; c < m.num_cells(); ++c) {
    const Patch& pt = s.P.bodies[m.body[c]].patches[m.patch[c]];
    EXPECT_EQ(m.degrees[3 * c], pt.degree[0]);
    EXPECT_EQ(m.degrees[3 * c + 1], pt.degree[1]);
    EXPECT_EQ(m.degrees[3 * c + 2], 0);
    EXPECT_EQ(m.element[c], m.element_ij[2 * c] + m.element_ij[2 * c + 1] * static_cast<int>(pt.element_spans(0).size()));
    const double* r = &m.range[4 * c];
    for (int q = 0; q < 12; ++q) {
      const double t0 = q < 4 ? q / 3.0 : U(rng), t1 = q < 4 ? (q % 2) : U(rng);
      const double u = r[0] + t0 * (r[1] - r[0]), v = r[2] + t1 * (r[3] - r[2]);
      double X[3], D[3];
      eval_cell(m, c, m.points, 3, t0, t1, X);
      eval_cell(m, c, m.displacement, 3, t0, t1, D);
      const auto x = pt.eval(u, v);
      EXPECT_NEAR(X[0], x[0], 1e-14);
      EXPECT_NEAR(X[1], x[1], 1e-14);
      EXPECT_EQ(X[2], 0.0);
      const FieldPoint f = fields[m.body[c]].eval(u, v, m.knot_span[2 * c], m.knot_span[2 * c + 1]);
      EXPECT_NEAR(D[0], f.ux, 1e-14 * umax[m.body[c]]);
      EXPECT_NEAR(D[1], f.uy, 1e-14 * umax[m.body[c]]);
      if (m.body[c] == 0 && ((t1 == 0.0 && r[2] == 0.0) || (t1 == 1.0 && r[3] == 1.0))) {
        EXPECT_NEAR(std::hypot(X[0], X[1]), t1 == 0.0 ? 1.0 : 2.0, 1e-14);
        ++on_circle;
      }
    }
  }
  EXPECT_GT(on_circle, 0);
}

// The stress fit: per cell the interpolant at the (p0+1)(p1+1) fit points; a Bezier point
// shared by neighbouring cells (knot multiplicity below p: the stress is continuous there)
// takes the mean of their fits, clamped into the union of those cells' sampled ranges (fit
// points and the output grid), so the field stays within what was sampled (von Mises >= 0).
// Where the stress is continuous the neighbours' fits agree on their shared points, so the
// mean changes nothing: every fit point still interpolates unless a clamp acted in the cell.
TEST(VtkBezier, StressFitInterpolatesAndStaysWithinTheCellsSamples) {
  const auto& s = annulus();
  const BezierMesh m = bezier_mesh(s.P, s.disp);
  double smax = 0;
  for (double v : m.von_mises) smax = std::max(smax, std::abs(v));
  ASSERT_GT(smax, 1.0);   // internal pressure 10
  const size_t np = m.num_points();
  // points are shared between cells: fewer points than cells x points per cell
  EXPECT_LT(np, m.connectivity.size());
  std::vector<double> plo(2 * np, 1e300), phi(2 * np, -1e300), fit(2 * np, 0.0);
  std::vector<int> users(np, 0);
  double disagree = 0;
  std::vector<std::vector<double>> coefs(m.num_cells());
  for (size_t c = 0; c < m.num_cells(); ++c) {
    const BodyField f(s.P, m.body[c], s.disp[m.body[c]]);
    const Patch& pt = s.P.bodies[m.body[c]].patches[m.patch[c]];
    const double* r = &m.range[4 * c];
    const int p0 = m.degrees[3 * c], p1 = m.degrees[3 * c + 1], sp = output_samples(s.P.output, pt);
    auto at = [&](double t0, double t1) {
      return f.eval(r[0] + t0 * (r[1] - r[0]), r[2] + t1 * (r[3] - r[2]), m.knot_span[2 * c], m.knot_span[2 * c + 1]);
    };
    // the cell's sampled range of von Mises and sxx
    double lo[2] = {1e300, 1e300}, hi[2] = {-1e300, -1e300};
    auto grow = [&](const FieldPoint& p) {
      const double v[2] = {p.von_mises(), p.sxx};
      for (int q = 0; q < 2; ++q) lo[q] = std::min(lo[q], v[q]), hi[q] = std::max(hi[q], v[q]);
    };
    for (const auto& t : fit_points(p0, p1)) grow(at(t[0], t[1]));
    for (int j = 0; j <= sp; ++j)
      for (int i = 0; i <= sp; ++i) grow(at(static_cast<double>(i) / sp, static_cast<double>(j) / sp));
    EXPECT_GE(lo[0], 0.0);
    // the cell's own (unclamped) fit
    const int n0 = p0 + 1, n = n0 * (p1 + 1);
    const int64_t first = c ? m.offsets[c - 1] : 0;
    std::vector<double> w(n), vals(2 * n);
    coefs[c].resize(2 * n);
    const auto tf = fit_points(p0, p1);
    for (int k = 0; k < n; ++k) {
      w[k] = m.weights[m.connectivity[first + vtk_quad_point_index(k % n0, k / n0, p0, p1)]];
      const FieldPoint p = at(tf[k][0], tf[k][1]);
      vals[2 * k] = p.von_mises();
      vals[2 * k + 1] = p.sxx;
    }
    fit_rational_bezier(p0, p1, w.data(), 2, vals.data(), coefs[c].data());
    for (int k = 0; k < n; ++k) {
      const int64_t q = m.connectivity[first + vtk_quad_point_index(k % n0, k / n0, p0, p1)];
      for (int a = 0; a < 2; ++a) {
        plo[2 * q + a] = std::min(plo[2 * q + a], lo[a]);
        phi[2 * q + a] = std::max(phi[2 * q + a], hi[a]);
        if (users[q]) disagree = std::max(disagree, std::abs(fit[2 * q + a] - coefs[c][2 * k + a]));
        fit[2 * q + a] = coefs[c][2 * k + a];
      }
      ++users[q];
    }
  }
  // neighbours' fits agree on their shared points (the stress is continuous there)
  EXPECT_LT(disagree, 1e-12 * smax);
  for (size_t q = 0; q < np; ++q) {
    ASSERT_GT(users[q], 0);
    EXPECT_GE(m.von_mises[q], plo[2 * q] - 1e-12 * smax);
    EXPECT_LE(m.von_mises[q], phi[2 * q] + 1e-12 * smax);
    EXPECT_GE(m.stress[6 * q], plo[2 * q + 1] - 1e-12 * smax);
    EXPECT_LE(m.stress[6 * q], phi[2 * q + 1] + 1e-12 * smax);
  }
  int interpolated = 0, clamped_cells = 0;
  for (size_t c = 0; c < m.num_cells(); ++c) {
    const BodyField f(s.P, m.body[c], s.disp[m.body[c]]);
    const double* r = &m.range[4 * c];
    const int p0 = m.degrees[3 * c], p1 = m.degrees[3 * c + 1], n0 = p0 + 1, n = n0 * (p1 + 1);
    const int64_t first = c ? m.offsets[c - 1] : 0;
    bool clamped = false;
    for (int k = 0; k < n; ++k) {
      const int64_t q = m.connectivity[first + vtk_quad_point_index(k % n0, k / n0, p0, p1)];
      clamped = clamped || std::abs(coefs[c][2 * k] - m.von_mises[q]) > 1e-12 * smax ||
                std::abs(coefs[c][2 * k + 1] - m.stress[6 * q]) > 1e-12 * smax;
    }
    clamped_cells += clamped;
    for (const auto& t : fit_points(p0, p1)) {
      const bool corner = (t[0] == 0.0 || t[0] == 1.0) && (t[1] == 0.0 || t[1] == 1.0);
      if (!corner && clamped) continue;
      double S[6], VM;
      eval_cell(m, c, m.stress, 6, t[0], t[1], S);
      eval_cell(m, c, m.von_mises, 1, t[0], t[1], &VM);
      const FieldPoint p = f.eval(r[0] + t[0] * (r[1] - r[0]), r[2] + t[1] * (r[3] - r[2]), m.knot_span[2 * c],
                                  m.knot_span[2 * c + 1]);
      if (corner) {
        EXPECT_NEAR(S[0], p.sxx, 1e-12 * smax);
        EXPECT_NEAR(S[1], p.syy, 1e-12 * smax);
        EXPECT_NEAR(S[2], p.szz, 1e-12 * smax);
        EXPECT_NEAR(S[3], p.sxy, 1e-12 * smax);
      }
      EXPECT_EQ(S[4], 0.0);
      EXPECT_EQ(S[5], 0.0);
      EXPECT_NEAR(VM, p.von_mises(), 1e-12 * smax);
      ++interpolated;
    }
  }
  std::printf("  %zu cells, %zu points (%zu unshared), %d cells with coefficients clamped, %d fit points "
              "interpolated, neighbours' fits agree to %.2g of max |s|\n",
              m.num_cells(), np, m.connectivity.size(), clamped_cells, interpolated, disagree / smax);
  EXPECT_GT(interpolated, 0);
}

// A field in the element's rational Bezier space is fitted exactly: the coordinates (whose
// coefficients are the Bezier points) and the displacement (element_field's coefficients).
TEST(VtkBezier, StressFitIsExactForAFieldInTheSpace) {
  const auto& s = annulus();
  for (int b = 0; b < 2; ++b) {
    const Patch& pt = s.P.bodies[b].patches[0];
    const BezierPatch B(pt);
    const BodyField f(s.P, b, s.disp[b]);
    const int p0 = B.degree()[0], p1 = B.degree()[1], n = B.points_per_element();
    const auto t = fit_points(p0, p1);
    double umax = 0;
    for (double v : s.disp[b]) umax = std::max(umax, std::abs(v));
    std::vector<ControlPoint> pts(n);
    std::vector<double> w(n), ub(2 * n), vals(4 * n), coef(4 * n);
    for (int e = 0; e < B.num_elements(); ++e) {
      B.element_points(e, pts.data());
      B.element_field(e, s.disp[b].data(), 2, ub.data());
      const auto r0 = B.range(e, 0), r1 = B.range(e, 1);
      for (int j = 0; j < n; ++j) {
        w[j] = pts[j].w;
        const FieldPoint p = f.eval(r0[0] + t[j][0] * (r0[1] - r0[0]), r1[0] + t[j][1] * (r1[1] - r1[0]), B.span(e, 0),
                                    B.span(e, 1));
        const double v[4] = {p.x, p.y, p.ux, p.uy};
        std::copy(v, v + 4, &vals[4 * j]);
      }
      fit_rational_bezier(p0, p1, w.data(), 4, vals.data(), coef.data());
      for (int k = 0; k < n; ++k) {
        EXPECT_NEAR(coef[4 * k], pts[k].x[0], 1e-13);
        EXPECT_NEAR(coef[4 * k + 1], pts[k].x[1], 1e-13);
        EXPECT_NEAR(coef[4 * k + 2], ub[2 * k], 1e-13 * umax);
        EXPECT_NEAR(coef[4 * k + 3], ub[2 * k + 1], 1e-13 * umax);
      }
    }
  }
}

// The tensor-product fit recovers the coefficients of any field of the rational Bezier space
// (random weights in [0.5, 2], random coefficients) in 1, 2 and 3 directions, p = 1..5.
TEST(VtkBezier, FitRecoversCoefficientsInEveryDimension) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> U(-1, 1), Wd(0.5, 2.0);
  for (int dim = 1; dim <= 3; ++dim)
    for (int deg = 1; deg <= 5; ++deg) {
      const int p[3] = {deg, std::max(1, deg - 1), deg == 5 ? 2 : deg};
      int n[3] = {1, 1, 1};
      size_t N = 1;
      for (int d = 0; d < dim; ++d) N *= static_cast<size_t>(n[d] = p[d] + 1);
      std::vector<double> w(N), c(2 * N), v(2 * N), fit(2 * N);
      for (auto& x : w) x = Wd(rng);
      for (auto& x : c) x = U(rng);
      // the field at the fit points (j0 / p0, j1 / p1, j2 / p2)
      for (size_t j = 0; j < N; ++j) {
        int jj[3] = {0, 0, 0};
        size_t r = j;
        for (int d = 0; d < dim; ++d) jj[d] = static_cast<int>(r % n[d]), r /= n[d];
        double b[3][kMaxBasis1D];
        for (int d = 0; d < dim; ++d) bernstein(p[d], static_cast<double>(jj[d]) / p[d], b[d]);
        double W = 0, s[2] = {0, 0};
        for (size_t k = 0; k < N; ++k) {
          size_t rk = k;
          double B = w[k];
          for (int d = 0; d < dim; ++d) B *= b[d][rk % n[d]], rk /= n[d];
          W += B;
          for (int q = 0; q < 2; ++q) s[q] += B * c[2 * k + q];
        }
        for (int q = 0; q < 2; ++q) v[2 * j + q] = s[q] / W;
      }
      fit_rational_bezier(dim, p, w.data(), 2, v.data(), fit.data());
      for (size_t k = 0; k < 2 * N; ++k) EXPECT_NEAR(fit[k], c[k], 1e-11) << "dim " << dim << " p " << deg << " k " << k;
    }
}

TEST(VtkBezier, WritesQuarterAnnulusFiles) {
  const auto& s = annulus();
  const char* env = std::getenv("IGACONTACT_VTU_OUT");
  const std::filesystem::path dir =
      env ? std::filesystem::path(env) : std::filesystem::temp_directory_path() / "igacontact_test_vtk";
  std::filesystem::create_directories(dir);
  const std::string bin = bezier_vtu(s.P, s.disp, 0.5, "test-run & <1>");
  const std::string asc = bezier_vtu(s.P, s.disp, 0.5, "test-run & <1>", VtkEncoding::Ascii);
  EXPECT_NE(bin.find("<AppendedData encoding=\"raw\">"), std::string::npos);
  EXPECT_EQ(asc.find("AppendedData"), std::string::npos);
  EXPECT_NE(asc.find("Name=\"RationalWeights\""), std::string::npos);
  for (const auto& [name, text] : {std::pair<std::string, const std::string&>{"annulus.vtu", bin},
                                   std::pair<std::string, const std::string&>{"annulus_ascii.vtu", asc}}) {
    std::ofstream out(dir / name, std::ios::binary);
    out << text;
    ASSERT_TRUE(out.good());
  }
  const std::string pvd = pvd_collection({{0.5, "annulus.vtu"}, {1.0, "annulus_ascii.vtu"}});
  EXPECT_NE(pvd.find("timestep=\"0.5\""), std::string::npos);
  EXPECT_NE(pvd.find("file=\"annulus_ascii.vtu\""), std::string::npos);
  std::ofstream(dir / "annulus.pvd") << pvd;
}
