// VTK rational Bezier output (io/vtk): the point order, the cells' geometry against the
// NURBS patch, the displacement coefficients, the per-element stress fit, the .vtu/.pvd text.
// 3-D (issue 35): BodyField on trivariate patches (Field3D), the face and hexahedron cells
// (VtkBezier3D), a 3-D state's control net and probe entry (Output3D).
// With IGACONTACT_VTU_OUT set, WritesQuarterAnnulusFiles leaves its .vtu files there for the
// ParaView check (tests/paraview/check_bezier.py, run by tests/paraview_bezier.sh).
#include <gtest/gtest.h>

#include <cstring>
#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <set>

#include "io/fields.hpp"
#include "io/output.hpp"
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
  const std::string zip = bezier_vtu(s.P, s.disp, 0.5, "test-run & <1>", VtkEncoding::AppendedZlib);
  EXPECT_NE(bin.find("<AppendedData encoding=\"raw\">"), std::string::npos);
  EXPECT_EQ(bin.find("compressor="), std::string::npos);
  EXPECT_EQ(asc.find("AppendedData"), std::string::npos);
  EXPECT_NE(asc.find("Name=\"RationalWeights\""), std::string::npos);
  EXPECT_NE(zip.find("compressor=\"vtkZLibDataCompressor\""), std::string::npos);
  EXPECT_LT(zip.size(), bin.size());
  for (const auto& [name, text] : {std::pair<std::string, const std::string&>{"annulus.vtu", bin},
                                   std::pair<std::string, const std::string&>{"annulus_ascii.vtu", asc},
                                   std::pair<std::string, const std::string&>{"annulus_zlib.vtu", zip}}) {
    std::ofstream out(dir / name, std::ios::binary);
    out << text;
    ASSERT_TRUE(out.good());
  }
  const std::string pvd = pvd_collection({{0.5, "annulus.vtu"}, {1.0, "annulus_ascii.vtu"}});
  EXPECT_NE(pvd.find("timestep=\"0.5\""), std::string::npos);
  EXPECT_NE(pvd.find("file=\"annulus_ascii.vtu\""), std::string::npos);
  std::ofstream(dir / "annulus.pvd") << pvd;
}

// The cells' fits on several threads (elements in chunks, merged in element order): the same
// mesh, every array bit for bit, on 1 and 3 threads.
TEST(VtkBezier, CellsDoNotDependOnTheThreads) {
  const BezierMesh a = bezier_mesh(annulus().P, annulus().disp, 1), b = bezier_mesh(annulus().P, annulus().disp, 3);
  EXPECT_GT(a.num_cells(), 3u);
  EXPECT_TRUE(a.points == b.points);
  EXPECT_TRUE(a.weights == b.weights);
  EXPECT_TRUE(a.displacement == b.displacement);
  EXPECT_TRUE(a.stress == b.stress);
  EXPECT_TRUE(a.von_mises == b.von_mises);
  EXPECT_TRUE(a.connectivity == b.connectivity);
  EXPECT_TRUE(a.range == b.range);
  EXPECT_EQ(a.max_displacement, b.max_displacement);
}

// The zlib encoding on several threads (the .vtu's arrays split in blocks of 1 MiB, each
// compressed on its own): the same bytes on 1 and 4 threads, and each array's blocks inflate
// back to the raw encoding's bytes. The annulus' cells padded with unreferenced points to
// arrays of several blocks (the displacement: 3.1 MB, 3 blocks).
TEST(VtkBezier, CompressedBlocksDoNotDependOnTheThreads) {
  BezierMesh m = bezier_mesh(annulus().P, annulus().disp);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> U(-1, 1);
  const size_t extra = 130000;
  for (size_t k = 0; k < extra; ++k) {
    for (int c = 0; c < 3; ++c) {
      m.points.push_back(U(rng));
      m.displacement.push_back(1e-3 * U(rng));
    }
    for (int c = 0; c < 6; ++c) m.stress.push_back(U(rng));
    m.weights.push_back(1 + 0.1 * U(rng));
    m.von_mises.push_back(1 + U(rng));
  }
  const std::string one = vtu_text(m, 1.0, "threads", VtkEncoding::AppendedZlib, 1);
  const std::string four = vtu_text(m, 1.0, "threads", VtkEncoding::AppendedZlib, 4);
  EXPECT_EQ(one, four);
  // the displacement array: the header (blocks, block size, last block's size, sizes), then
  // the blocks, against the raw encoding's bytes
  const std::string raw = vtu_text(m, 1.0, "threads", VtkEncoding::AppendedRaw);
  auto appended_offset = [](const std::string& t, const std::string& name) {
    const size_t at = t.find("Name=\"" + name + "\"");
    const size_t o = t.find("offset=\"", at) + 8;
    return std::stoull(t.substr(o, t.find('"', o) - o));
  };
  const size_t zbase = four.find("<AppendedData encoding=\"raw\">\n  _") + 33;
  const size_t rbase = raw.find("<AppendedData encoding=\"raw\">\n  _") + 33;
  ASSERT_EQ(four.substr(zbase - 1, 1), "_");
  const char* z = four.data() + zbase + appended_offset(four, "displacement");
  std::uint64_t hdr[3];
  std::memcpy(hdr, z, sizeof hdr);
  ASSERT_EQ(hdr[1], 1u << 20);
  ASSERT_GE(hdr[0], 3u);
  std::vector<std::uint64_t> sizes(hdr[0]);
  std::memcpy(sizes.data(), z + sizeof hdr, hdr[0] * sizeof(std::uint64_t));
  const char* blocks = z + sizeof hdr + hdr[0] * sizeof(std::uint64_t);
  std::string inflated;
  for (std::uint64_t b = 0; b < hdr[0]; ++b) {
    std::vector<Bytef> buf(hdr[1]);
    uLongf len = static_cast<uLongf>(buf.size());
    ASSERT_EQ(uncompress(buf.data(), &len, reinterpret_cast<const Bytef*>(blocks), static_cast<uLong>(sizes[b])), Z_OK);
    inflated.append(reinterpret_cast<const char*>(buf.data()), len);
    blocks += sizes[b];
  }
  const char* r = raw.data() + rbase + appended_offset(raw, "displacement");
  std::uint64_t rbytes;
  std::memcpy(&rbytes, r, sizeof rbytes);
  EXPECT_EQ(rbytes, 8 * m.displacement.size());
  EXPECT_EQ(inflated.size(), rbytes);
  EXPECT_EQ(hdr[2], rbytes % hdr[1]);
  EXPECT_TRUE(inflated == std::string(r + sizeof rbytes, rbytes));
}

// ------------------------------------------------------------------ 3-D (issue 35)

namespace {

// A one-body solid (Analysis::Solid) of the given patches, built in C++ (no reader needed):
// control points not merged (cp_index the identity per patch), the given interfaces.
Problem solid_problem(const std::vector<Patch>& patches, Kinematics kin = Kinematics::Small,
                      MaterialModel model = MaterialModel::Linear, std::vector<Interface> interfaces = {}) {
  Problem P;
  P.analysis = Analysis::Solid;
  P.kinematics = kin;
  Body b;
  b.name = "solid";
  b.E = 1000.0;
  b.nu = 0.3;
  b.model = model;
  b.patches = patches;
  b.sides.resize(patches.size());
  b.corners.resize(patches.size());
  b.interfaces = std::move(interfaces);
  b.tolerance = 1e-8 * patches_diameter(patches);   // as the loader sets it
  for (const Patch& pt : patches) {
    std::vector<int> idx(pt.cp.size());
    for (size_t a = 0; a < idx.size(); ++a) idx[a] = b.num_cps + static_cast<int>(a);
    b.cp_index.push_back(idx);
    b.num_cps += static_cast<int>(pt.cp.size());
  }
  P.bodies.push_back(b);
  return P;
}

// A quarter of a thick cylinder shell (radii 1, 2, height 0.8; xi around from the x axis, eta
// radial, zeta along z: a left-handed map, orientation -1), rational quadratic in xi, degrees
// (2, 2, 2), 3 x 2 x 2 elements; `distort`: control points moved and weights changed inside
// (a rational patch of no special form, det J still positive).
Patch shell_patch(bool distort) {
  const double w = std::sqrt(0.5), H = 0.8;
  Patch a;
  a.pdim = 3;
  a.degree = {2, 1, 1};
  a.knots[0] = {0, 0, 0, 1, 1, 1};
  a.knots[1] = {0, 0, 1, 1};
  a.knots[2] = {0, 0, 1, 1};
  for (double z : {0.0, H})
    for (double r : {1.0, 2.0}) {
      a.cp.push_back(ControlPoint({r, 0, z}, 1));
      a.cp.push_back(ControlPoint({r, r, z}, w));
      a.cp.push_back(ControlPoint({0, r, z}, 1));
    }
  a.elevate(1, 1);
  a.elevate(2, 1);
  a.subdivide(0, 3);
  a.subdivide(1, 2);
  a.subdivide(2, 2);
  if (distort)
    for (size_t q = 0; q < a.cp.size(); ++q) {
      ControlPoint& c = a.cp[q];
      const double s = std::sin(1.7 * q);
      c.x[0] += 0.04 * s;
      c.x[1] += 0.03 * std::cos(2.3 * q);
      c.x[2] += 0.02 * s;
      c.w *= 1.0 + 0.15 * std::cos(0.9 * q);
    }
  return a;
}

// The box [x0, x0 + L0] x [0, L1] x [0, L2] as a patch of degrees p, ne elements per direction.
Patch box_patch(std::array<int, 3> p, std::array<int, 3> ne, std::array<double, 3> L, double x0 = 0) {
  Patch a;
  a.pdim = 3;
  a.degree = {1, 1, 1};
  for (int d = 0; d < 3; ++d) a.knots[d] = {0, 0, 1, 1};
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 2; ++i) a.cp.push_back(ControlPoint({x0 + i * L[0], j * L[1], k * L[2]}, 1));
  for (int d = 0; d < 3; ++d) {
    if (p[d] > 1) a.elevate(d, p[d] - 1);
    a.subdivide(d, ne[d]);
  }
  return a;
}

// Control displacements of the affine field u = A x + c (reproduced exactly by the NURBS space).
std::vector<double> affine_u(const Patch& pt, const double A[3][3], const double c[3]) {
  std::vector<double> u;
  for (const ControlPoint& q : pt.cp)
    for (int i = 0; i < 3; ++i) u.push_back(c[i] + A[i][0] * q.x[0] + A[i][1] * q.x[1] + A[i][2] * q.x[2]);
  return u;
}

// Rational Bezier evaluation of a cell's point array at the cell parameters tc (2 for a
// quadrilateral, 3 for a hexahedron), through the connectivity in VTK's point order.
void eval_cell3(const BezierMesh& m, size_t cell, const std::vector<double>& a, int ncomp, const double* tc,
                double* out) {
  const bool hex = m.types[cell] == 79;
  const int p0 = m.degrees[3 * cell], p1 = m.degrees[3 * cell + 1], p2 = hex ? m.degrees[3 * cell + 2] : 0;
  const size_t first = cell == 0 ? 0 : static_cast<size_t>(m.offsets[cell - 1]);
  double b0[kMaxBasis1D], b1[kMaxBasis1D], b2[kMaxBasis1D] = {1.0}, W = 0;
  bernstein(p0, tc[0], b0);
  bernstein(p1, tc[1], b1);
  if (hex) bernstein(p2, tc[2], b2);
  for (int c = 0; c < ncomp; ++c) out[c] = 0;
  for (int k = 0; k <= p2; ++k)
    for (int j = 0; j <= p1; ++j)
      for (int i = 0; i <= p0; ++i) {
        const int at = hex ? vtk_hex_point_index(i, j, k, p0, p1, p2) : vtk_quad_point_index(i, j, p0, p1);
        const size_t q = static_cast<size_t>(m.connectivity[first + at]);
        const double r = b0[i] * b1[j] * b2[k] * m.weights[q];
        W += r;
        for (int c = 0; c < ncomp; ++c) out[c] += r * a[q * ncomp + c];
      }
  for (int c = 0; c < ncomp; ++c) out[c] /= W;
}

// The volume parameters of cell point tc. A face cell's parameters are those of the face's
// free directions in increasing order, transposed where the writer transposed the cell for
// an outward normal (the rule is checked geometrically by OutwardFaceNormals).
void cell_params(const BezierMesh& m, size_t c, const Patch& pt, const double* tc, double* t) {
  const double* r = &m.range[6 * c];
  if (m.types[c] == 79) {
    for (int d = 0; d < 3; ++d) t[d] = r[2 * d] + tc[d] * (r[2 * d + 1] - r[2 * d]);
    return;
  }
  const int f = m.face[c], fd = f / 2;
  const bool flip = side_normal_sign(static_cast<Side>(f)) * pt.orientation() < 0;
  const double tf[2] = {flip ? tc[1] : tc[0], flip ? tc[0] : tc[1]};
  for (int d = 0, a = 0; d < 3; ++d) t[d] = d == fd ? r[2 * d] : r[2 * d] + tf[a++] * (r[2 * d + 1] - r[2 * d]);
}

// The 3 x 3 Cauchy stress of BodyField's point, symmetric.
void stress_tensor(const FieldPoint& f, double s[3][3]) {
  s[0][0] = f.sxx; s[1][1] = f.syy; s[2][2] = f.szz;
  s[1][2] = s[2][1] = f.syz; s[0][2] = s[2][0] = f.sxz; s[0][1] = s[1][0] = f.sxy;
}

double det3(const double F[3][3]) {
  return F[0][0] * (F[1][1] * F[2][2] - F[1][2] * F[2][1]) - F[0][1] * (F[1][0] * F[2][2] - F[1][2] * F[2][0]) +
         F[0][2] * (F[1][0] * F[2][1] - F[1][1] * F[2][0]);
}

}  // namespace

// A hand-computed value: the unit box, small strain, E = 1000, nu = 0.3 (lambda = 576.923..,
// mu = 384.615..), u = (0.01 x + 0.02 z, 0, 0): eps_xx = 0.01, gamma_xz = 0.02, so
// sxx = (lambda + 2 mu) 0.01, syy = szz = lambda 0.01, sxz = mu 0.02, the rest 0.
TEST(Field3D, HandComputedUniaxialStretchAndShear) {
  const Patch box = box_patch({2, 2, 1}, {2, 1, 1}, {1, 1, 1});
  const Problem P = solid_problem({box});
  const double A[3][3] = {{0.01, 0, 0.02}, {0, 0, 0}, {0, 0, 0}}, c[3] = {0.1, -0.2, 0.3};
  const BodyField f(P, 0, affine_u(box, A, c));
  const double lam = 1000.0 * 0.3 / (1.3 * 0.4), mu = 1000.0 / 2.6;
  const double t[3] = {0.3, 0.6, 0.9};
  const FieldPoint q = f.eval(t);
  EXPECT_NEAR(q.x, 0.3, 1e-15);
  EXPECT_NEAR(q.y, 0.6, 1e-15);
  EXPECT_NEAR(q.z, 0.9, 1e-15);
  EXPECT_NEAR(q.detJ, 1.0, 1e-14);
  EXPECT_NEAR(q.ux, 0.1 + 0.003 + 0.018, 1e-15);
  EXPECT_NEAR(q.uy, -0.2, 1e-15);
  EXPECT_NEAR(q.uz, 0.3, 1e-15);
  EXPECT_NEAR(q.sxx, (lam + 2 * mu) * 0.01, 1e-12);
  EXPECT_NEAR(q.syy, lam * 0.01, 1e-12);
  EXPECT_NEAR(q.szz, lam * 0.01, 1e-12);
  EXPECT_NEAR(q.sxz, mu * 0.02, 1e-12);
  EXPECT_NEAR(q.syz, 0.0, 1e-12);
  EXPECT_NEAR(q.sxy, 0.0, 1e-12);
  // von Mises of (2 mu e, 0, 0 deviatoric part ...): sqrt(((2 mu e)^2 + (2 mu e)^2) / 2 + 3 (mu g)^2)
  EXPECT_NEAR(q.von_mises(), std::sqrt(4 * mu * mu * 1e-4 + 3 * mu * mu * 4e-4), 1e-11);
}

// An affine displacement u = A x + c on a distorted rational patch: the field is affine
// everywhere (x and u agree with Patch::point and A x + c), the stress constant and equal to
// the law's value at H = A, to round-off: small strain, Saint Venant-Kirchhoff and
// neo-Hookean (Cauchy stress on the deformed configuration, computed here by hand).
TEST(Field3D, AffineFieldOnADistortedRationalPatch) {
  const Patch pt = shell_patch(true);
  const double A[3][3] = {{0.02, -0.01, 0.03}, {0.015, -0.025, 0.01}, {-0.02, 0.005, 0.04}}, c[3] = {0.01, 0.02, -0.03};
  const double E = 1000.0, nu = 0.3, lam = E * nu / ((1 + nu) * (1 - 2 * nu)), mu = E / (2 * (1 + nu));
  double F[3][3], eps[3][3];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      F[i][j] = (i == j) + A[i][j];
      eps[i][j] = 0.5 * (A[i][j] + A[j][i]);
    }
  const double J = det3(F), tre = eps[0][0] + eps[1][1] + eps[2][2];
  double C[3][3], B[3][3];   // C = F^T F, B = F F^T
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      C[i][j] = B[i][j] = 0;
      for (int k = 0; k < 3; ++k) {
        C[i][j] += F[k][i] * F[k][j];
        B[i][j] += F[i][k] * F[j][k];
      }
    }
  const double trEg = 0.5 * (C[0][0] + C[1][1] + C[2][2] - 3);
  for (auto [kin, model] : {std::pair{Kinematics::Small, MaterialModel::Linear},
                            std::pair{Kinematics::Finite, MaterialModel::SaintVenantKirchhoff},
                            std::pair{Kinematics::Finite, MaterialModel::NeoHookean}}) {
    double expect[3][3];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        if (kin == Kinematics::Small) {
          expect[i][j] = 2 * mu * eps[i][j] + (i == j ? lam * tre : 0.0);
        } else if (model == MaterialModel::NeoHookean) {
          expect[i][j] = (mu * (B[i][j] - (i == j)) + (i == j ? lam * std::log(J) : 0.0)) / J;
        } else {   // sigma = F S F^T / J, S = lambda tr E I + 2 mu E
          double s = 0;
          for (int k = 0; k < 3; ++k)
            for (int l = 0; l < 3; ++l) {
              const double S = 2 * mu * 0.5 * (C[k][l] - (k == l)) + (k == l ? lam * trEg : 0.0);
              s += F[i][k] * S * F[j][l];
            }
          expect[i][j] = s / J;
        }
      }
    const Problem P = solid_problem({pt}, kin, model);
    const BodyField f(P, 0, affine_u(pt, A, c));
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> U(0, 1);
    double worst = 0, smax = 0;
    for (int q = 0; q < 40; ++q) {
      const double t[3] = {q == 0 ? 0.0 : q == 1 ? 1.0 : U(rng), q == 0 ? 0.0 : q == 1 ? 1.0 : U(rng), U(rng)};
      const FieldPoint p = f.eval(t);
      const auto x = pt.point(t);
      EXPECT_LT(p.detJ, 0.0);   // the shell's map is left-handed (orientation -1): the distortion kept the sign
      EXPECT_NEAR(p.x, x[0], 1e-13);
      EXPECT_NEAR(p.y, x[1], 1e-13);
      EXPECT_NEAR(p.z, x[2], 1e-13);
      const double u[3] = {p.ux, p.uy, p.uz};
      for (int i = 0; i < 3; ++i) EXPECT_NEAR(u[i], c[i] + A[i][0] * x[0] + A[i][1] * x[1] + A[i][2] * x[2], 1e-14);
      double s[3][3];
      stress_tensor(p, s);
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
          worst = std::max(worst, std::abs(s[i][j] - expect[i][j]));
          smax = std::max(smax, std::abs(expect[i][j]));
        }
    }
    ASSERT_GT(smax, 1.0);
    EXPECT_LT(worst, 1e-11 * smax) << "model " << static_cast<int>(model);
  }
}

namespace {

// A non-affine displacement of a patch's control points (smooth in the index).
std::vector<double> wavy_u(const Patch& pt, double amp) {
  std::vector<double> u;
  for (size_t a = 0; a < pt.cp.size(); ++a) {
    const ControlPoint& q = pt.cp[a];
    u.push_back(amp * (0.3 * q.x[0] * q.x[1] + 0.1 * std::sin(q.x[2] + a)));
    u.push_back(amp * (-0.2 * q.x[0] * q.x[2] + 0.05 * q.x[1] * q.x[1]));
    u.push_back(amp * (0.1 * q.x[0] + 0.2 * q.x[1] * q.x[2] + 0.03 * std::cos(2.0 * a)));
  }
  return u;
}

// The cells of a 3-D mesh reproduce the patch: points of each cell (Bezier evaluation from its
// points, weights and connectivity) equal Patch::point at the cell's volume parameters, the
// displacement BodyField's, and the stress at the cell corners (which the fit interpolates and
// the clamp keeps) BodyField's stress. Returns the number of cells checked.
int check_cells_reproduce(const Problem& P, const std::vector<double>& u, const BezierMesh& m) {
  const Patch& pt = P.bodies[0].patches[0];
  const BodyField field(P, 0, u);
  double umax = 0, smax = 0;
  for (double v : u) umax = std::max(umax, std::abs(v));
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> U(0, 1);
  int checked = 0;
  for (size_t c = 0; c < m.num_cells(); ++c) {
    const bool hex = m.types[c] == 79;
    for (int q = 0; q < 10; ++q) {
      double tc[3] = {q < 4 ? static_cast<double>(q & 1) : U(rng), q < 4 ? static_cast<double>(q >> 1) : U(rng), U(rng)};
      if (hex && q < 4) tc[2] = q & 1;
      double t[3], X[3], D[3], S[6];
      cell_params(m, c, pt, tc, t);
      eval_cell3(m, c, m.points, 3, tc, X);
      eval_cell3(m, c, m.displacement, 3, tc, D);
      const auto x = pt.point(t);
      const FieldPoint f = field.eval(t);
      for (int d = 0; d < 3; ++d) EXPECT_NEAR(X[d], x[d], 1e-13) << "cell " << c;
      EXPECT_NEAR(D[0], f.ux, 1e-13 * umax);
      EXPECT_NEAR(D[1], f.uy, 1e-13 * umax);
      EXPECT_NEAR(D[2], f.uz, 1e-13 * umax);
      if (q < 4) {   // a corner of a face cell, or of the bottom/top of a hexahedron
        eval_cell3(m, c, m.stress, 6, tc, S);
        const double s[6] = {f.sxx, f.syy, f.szz, f.sxy, f.syz, f.sxz};   // VTK order
        for (int k = 0; k < 6; ++k) {
          smax = std::max(smax, std::abs(s[k]));
          EXPECT_NEAR(S[k], s[k], 1e-9 * (1 + std::abs(s[k]))) << "cell " << c << " component " << k;
        }
      }
    }
    ++checked;
  }
  EXPECT_GT(smax, 0.0);
  return checked;
}

}  // namespace

// Faces (the default in 3-D): every boundary face of the patch, one Bezier quadrilateral per
// face element, 3-D points; they interpolate the patch, the displacement and the stress.
TEST(VtkBezier3D, FaceCellsReproduceThePatchAndTheField) {
  const Patch pt = shell_patch(true);
  const Problem P = solid_problem({pt});
  const std::vector<double> u = wavy_u(pt, 0.01);
  const BezierMesh m = bezier_mesh(P, {u});
  EXPECT_EQ(m.dim, 3);
  const int ne[3] = {pt.num_elements(0), pt.num_elements(1), pt.num_elements(2)};
  ASSERT_EQ(static_cast<int>(m.num_cells()), 2 * (ne[0] * ne[1] + ne[0] * ne[2] + ne[1] * ne[2]));
  std::vector<int> per_face(6, 0);
  for (size_t c = 0; c < m.num_cells(); ++c) {
    EXPECT_EQ(m.types[c], 77);
    EXPECT_EQ(m.degrees[3 * c + 2], 0);
    ASSERT_GE(m.face[c], 0);
    ++per_face[m.face[c]];
    EXPECT_EQ(m.element[c], m.element_ij[3 * c] + ne[0] * (m.element_ij[3 * c + 1] + ne[1] * m.element_ij[3 * c + 2]));
    const int fd = m.face[c] / 2;   // the fixed direction: its end value, a = b
    EXPECT_EQ(m.range[6 * c + 2 * fd], m.range[6 * c + 2 * fd + 1]);
    EXPECT_EQ(m.range[6 * c + 2 * fd], (m.face[c] % 2) ? 1.0 : 0.0);
  }
  for (int s = 0; s < 6; ++s) EXPECT_EQ(per_face[s], ne[(s / 2 + 1) % 3] * ne[(s / 2 + 2) % 3]) << "face " << s;
  EXPECT_EQ(check_cells_reproduce(P, u, m), static_cast<int>(m.num_cells()));
  // the largest |u| reported is a field value no larger than the control net's bound
  double ucp = 0;
  for (size_t a = 0; a < u.size(); a += 3) ucp = std::max(ucp, std::sqrt(u[a] * u[a] + u[a + 1] * u[a + 1] + u[a + 2] * u[a + 2]));
  EXPECT_GT(m.max_displacement, 0.5 * ucp);
  EXPECT_LE(m.max_displacement, ucp * (1 + 1e-12));
}

// Volume (output.cells: volume): every element a Bezier hexahedron, shared points.
TEST(VtkBezier3D, HexahedraReproduceThePatchAndTheField) {
  const Patch pt = shell_patch(true);
  Problem P = solid_problem({pt});
  P.output.volume_cells = true;
  const std::vector<double> u = wavy_u(pt, 0.01);
  const BezierMesh m = bezier_mesh(P, {u});
  ASSERT_EQ(static_cast<int>(m.num_cells()), pt.num_elements());
  for (size_t c = 0; c < m.num_cells(); ++c) {
    EXPECT_EQ(m.types[c], 79);
    EXPECT_EQ(m.face[c], -1);
    for (int d = 0; d < 3; ++d) EXPECT_EQ(m.degrees[3 * c + d], pt.degree[d]);
  }
  // degree 2 with simple knots: neighbours share points, (2 ne + 1) per direction
  size_t expect = 1;
  for (int d = 0; d < 3; ++d) expect *= static_cast<size_t>(2 * pt.num_elements(d) + 1);
  EXPECT_EQ(m.num_points(), expect);
  EXPECT_EQ(check_cells_reproduce(P, u, m), pt.num_elements());
}

// An affine displacement: the stress is constant, so every stress and von Mises coefficient of
// every cell (faces and hexahedra) is that constant to round-off.
TEST(VtkBezier3D, ConstantStressOfAnAffineFieldIsDrawnConstant) {
  const Patch pt = shell_patch(true);
  const double A[3][3] = {{0.02, -0.01, 0.03}, {0.015, -0.025, 0.01}, {-0.02, 0.005, 0.04}}, c[3] = {0, 0, 0};
  for (bool volume : {false, true}) {
    Problem P = solid_problem({pt});
    P.output.volume_cells = volume;
    const std::vector<double> u = affine_u(pt, A, c);
    const BezierMesh m = bezier_mesh(P, {u});
    const double t[3] = {0.5, 0.5, 0.5};
    const FieldPoint f = BodyField(P, 0, u).eval(t);
    const double s[6] = {f.sxx, f.syy, f.szz, f.sxy, f.syz, f.sxz};
    const double scale = std::abs(f.von_mises());
    ASSERT_GT(scale, 1.0);
    double worst = 0;
    for (size_t q = 0; q < m.num_points(); ++q) {
      for (int k = 0; k < 6; ++k) worst = std::max(worst, std::abs(m.stress[6 * q + k] - s[k]));
      worst = std::max(worst, std::abs(m.von_mises[q] - f.von_mises()));
    }
    EXPECT_LT(worst, 1e-10 * scale) << (volume ? "hexahedra" : "faces");
  }
}

// The face cells' VTK normal (d/dt0 x d/dt1 of the cell) points out of the body, on a
// right-handed box (orientation +1) and on the left-handed shell (-1).
TEST(VtkBezier3D, OutwardFaceNormals) {
  for (bool shell : {false, true}) {
    const Patch pt = shell ? shell_patch(false) : box_patch({2, 1, 2}, {2, 2, 1}, {2.0, 1.0, 0.5});
    ASSERT_EQ(pt.orientation(), shell ? -1 : 1);
    const Problem P = solid_problem({pt});
    const BezierMesh m = bezier_mesh(P, {std::vector<double>(3 * pt.cp.size(), 0.0)});
    for (size_t c = 0; c < m.num_cells(); ++c) {
      const double h = 1e-6, t0[2] = {0.5, 0.5}, ta[2] = {0.5 + h, 0.5}, tb[2] = {0.5, 0.5 + h};
      double X[3], Xa[3], Xb[3];
      eval_cell3(m, c, m.points, 3, t0, X);
      eval_cell3(m, c, m.points, 3, ta, Xa);
      eval_cell3(m, c, m.points, 3, tb, Xb);
      const double a[3] = {Xa[0] - X[0], Xa[1] - X[1], Xa[2] - X[2]}, b[3] = {Xb[0] - X[0], Xb[1] - X[1], Xb[2] - X[2]};
      const double n[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
      double out[3];   // the outward direction of the face the cell lies on
      if (!shell) {   // west, east, south, north, front, back: -x, +x, -y, +y, -z, +z
        for (int d = 0; d < 3; ++d) out[d] = d == m.face[c] / 2 ? (m.face[c] % 2 ? 1.0 : -1.0) : 0.0;
      } else {
        const double r = std::hypot(X[0], X[1]);
        const double radial[3] = {X[0] / r, X[1] / r, 0};
        const double dirs[6][3] = {{0, -1, 0}, {-1, 0, 0}, {-radial[0], -radial[1], 0}, {radial[0], radial[1], 0},
                                   {0, 0, -1}, {0, 0, 1}};
        std::copy(dirs[m.face[c]], dirs[m.face[c]] + 3, out);
      }
      const double dot = n[0] * out[0] + n[1] * out[1] + n[2] * out[2];
      const double nn = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]),
                   no = std::sqrt(out[0] * out[0] + out[1] * out[1] + out[2] * out[2]);
      EXPECT_GT(dot, 0.5 * nn * no) << (shell ? "shell" : "box") << " face " << m.face[c] << " cell " << c;
    }
  }
}

// A two-patch body: the faces shared by the interface are inside the body and not drawn.
TEST(VtkBezier3D, InterfacesAreNotDrawn) {
  const Patch a = box_patch({2, 2, 2}, {2, 1, 1}, {1, 1, 1}), b = box_patch({2, 2, 2}, {1, 1, 1}, {1, 1, 1}, 1.0);
  const Problem P = solid_problem({a, b}, Kinematics::Small, MaterialModel::Linear,
                                  {Interface{PatchSide{0, Side::East}, PatchSide{1, Side::West}}});
  std::vector<double> u(3 * P.bodies[0].num_cps, 0.0);
  const BezierMesh m = bezier_mesh(P, {u});
  // patch 0: 2 x 1 x 1 elements, 5 faces (no east): 2 + 2 + 2 + 2 + 1 (west); patch 1: 5 x 1
  EXPECT_EQ(m.num_cells(), 9u + 5u);
  for (size_t c = 0; c < m.num_cells(); ++c) {
    EXPECT_FALSE(m.patch[c] == 0 && m.face[c] == static_cast<int>(Side::East));
    EXPECT_FALSE(m.patch[c] == 1 && m.face[c] == static_cast<int>(Side::West));
  }
  // the bounds of the drawn points: the two boxes
  double lo[3] = {1e9, 1e9, 1e9}, hi[3] = {-1e9, -1e9, -1e9};
  for (size_t q = 0; q < m.num_points(); ++q)
    for (int d = 0; d < 3; ++d) {
      lo[d] = std::min(lo[d], m.points[3 * q + d]);
      hi[d] = std::max(hi[d], m.points[3 * q + d]);
    }
  const double expect_hi[3] = {2.0, 1.0, 1.0};
  for (int d = 0; d < 3; ++d) {
    EXPECT_NEAR(lo[d], 0.0, 1e-14);
    EXPECT_NEAR(hi[d], expect_hi[d], 1e-14);
  }
}

// The 3-D .vtu text, and the files tests/paraview/check_bezier3d.py opens (IGACONTACT_VTU_OUT):
// the undistorted shell (exact quarter cylinders) with a non-affine displacement, faces and
// hexahedra, binary and ascii.
TEST(VtkBezier3D, WritesShellFiles) {
  const Patch pt = shell_patch(false);
  const char* env = std::getenv("IGACONTACT_VTU_OUT");
  const std::filesystem::path dir =
      env ? std::filesystem::path(env) : std::filesystem::temp_directory_path() / "igacontact_test_vtk";
  std::filesystem::create_directories(dir);
  for (bool volume : {false, true}) {
    Problem P = solid_problem({pt});
    P.output.volume_cells = volume;
    const std::vector<double> u = wavy_u(pt, 0.05);
    const std::string bin = bezier_vtu(P, {u}, 1.0, "test-3d");
    const std::string asc = bezier_vtu(P, {u}, 1.0, "test-3d", VtkEncoding::Ascii);
    EXPECT_NE(asc.find("Name=\"element_ij\" NumberOfComponents=\"3\""), std::string::npos);
    EXPECT_NE(asc.find("Name=\"parametric_range\" NumberOfComponents=\"6\""), std::string::npos);
    EXPECT_NE(asc.find("Name=\"face\""), std::string::npos);
    // VTK >= 9.1 reads hexahedra of files before version 2.2 in the legacy point order
    EXPECT_NE(bin.find("<VTKFile type=\"UnstructuredGrid\" version=\"2.2\""), std::string::npos);
    EXPECT_NE(asc.find(volume ? "\n     79 79" : "\n     77 77"), std::string::npos);
    const std::string stem = volume ? "shell_volume" : "shell_faces";
    std::ofstream(dir / (stem + ".vtu"), std::ios::binary) << bin;
    std::ofstream(dir / (stem + "_ascii.vtu"), std::ios::binary) << asc;
  }
}

// A 3-D state's files without a System (ResultWriter's pieces): the control net in the HDF5
// image (Float64, hexahedra), no sampled grid, and a probe with three coordinates, three
// displacements and six stresses. With IGACONTACT_VTU_OUT set, writes an output directory
// as a 3-D run writes it (result_0001.h5, result_control_nets.xdmf, result_contact.xdmf,
// result_0001.vtu, result.pvd, summary.json) for tests/paraview/check_results.py
// (tests/paraview_output3d.sh).
TEST(Output3D, ControlNetAndProbe) {
  const Patch pt = shell_patch(false);
  const Problem P = solid_problem({pt});
  const double A[3][3] = {{0.02, -0.01, 0.03}, {0.015, -0.025, 0.01}, {-0.02, 0.005, 0.04}}, c[3] = {0.01, 0.02, -0.03};
  const std::vector<double> u = affine_u(pt, A, c);
  H5Memory f("result_0001.h5");
  f.group("/bodies");
  std::ostringstream grids, nets;
  EXPECT_EQ(write_bodies(f, "result_0001.h5", P, {u}, grids, nets), 0.0);
  EXPECT_TRUE(grids.str().empty());   // no sampled grid in 3-D
  const int m0 = pt.ncp(0), m1 = pt.ncp(1), m2 = pt.ncp(2);
  const std::string net = nets.str();
  EXPECT_NE(net.find("TopologyType=\"Hexahedron\" NumberOfElements=\"" + std::to_string((m0 - 1) * (m1 - 1) * (m2 - 1)) +
                     "\" NodesPerElement=\"8\""),
            std::string::npos);
  EXPECT_NE(net.find("result_0001.h5:/bodies/solid/control_xyz"), std::string::npos);
  EXPECT_NE(net.find("result_0001.h5:/bodies/solid/control_displacement"), std::string::npos);
  const std::string h5 = f.image();

  Probe pr;
  pr.body = 0;
  pr.at = {0.25, 0.5, 0.75};
  const nlohmann::json j = probe_json(P, pr, u);
  const double t[3] = {0.25, 0.5, 0.75};
  const FieldPoint fp = BodyField(P, 0, u).eval(t);
  const auto x = pt.point(t);
  EXPECT_EQ(j["body"], "solid");
  EXPECT_EQ(j["at"].size(), 3u);
  EXPECT_EQ(j["at"][2].get<double>(), 0.75);
  EXPECT_NEAR(j["x"].get<double>(), x[0], 1e-14);
  EXPECT_NEAR(j["y"].get<double>(), x[1], 1e-14);
  EXPECT_NEAR(j["z"].get<double>(), x[2], 1e-14);
  ASSERT_EQ(j["displacement"].size(), 3u);
  for (int i = 0; i < 3; ++i)
    EXPECT_NEAR(j["displacement"][i].get<double>(), c[i] + A[i][0] * x[0] + A[i][1] * x[1] + A[i][2] * x[2], 1e-14);
  ASSERT_EQ(j["stress"].size(), 6u);   // sxx, syy, szz, syz, sxz, sxy
  const double s[6] = {fp.sxx, fp.syy, fp.szz, fp.syz, fp.sxz, fp.sxy};
  for (int k = 0; k < 6; ++k) EXPECT_EQ(j["stress"][k].get<double>(), s[k]);
  const double mu = 1000.0 / 2.6;   // sxy of the affine field: mu (A01 + A10)
  EXPECT_NEAR(j["stress"][5].get<double>(), mu * (A[0][1] + A[1][0]), 1e-10);

  if (const char* env = std::getenv("IGACONTACT_VTU_OUT")) {
    const std::filesystem::path dir(env);
    std::filesystem::create_directories(dir);
    std::ofstream(dir / "result_0001.h5", std::ios::binary) << h5;
    const std::string state = "  <Grid Name=\"step_0001\" GridType=\"Collection\" CollectionType=\"Spatial\">\n"
                              "   <Time Value=\"1\"/>\n" + net + "  </Grid>\n";
    std::ofstream(dir / "result_control_nets.xdmf") << xdmf_file("test-3d", {state});
    const BezierMesh mesh = bezier_mesh(P, {u});
    std::ofstream(dir / "result_0001.vtu", std::ios::binary) << vtu_text(mesh, 1.0, "test-3d");
    std::ofstream(dir / "result.pvd") << pvd_collection({{1.0, "result_0001.vtu"}});
    // no contact: an empty spatial collection per state, as ResultWriter writes it
    std::ofstream(dir / "result_contact.xdmf")
        << xdmf_file("test-3d", {"  <Grid Name=\"step_0001\" GridType=\"Collection\" CollectionType=\"Spatial\">\n"
                                 "   <Time Value=\"1\"/>\n  </Grid>\n"});
    // what tests/paraview/check_results.py reads of summary.json
    nlohmann::json s = {{"load_factor", 1.0}, {"max_displacement", mesh.max_displacement}, {"contact", nlohmann::json::array()}};
    for (const char* name : {"result_0001.h5", "result_0001.vtu", "result_control_nets.xdmf", "result_contact.xdmf", "result.pvd"})
      s["files"][name] = nlohmann::json::object();
    std::ofstream(dir / "summary.json") << s.dump(1);
  }
}

namespace {

// The octant of a thick sphere, radii 1 and 2 (as tests/test_solid.cpp builds it): degree
// (2, 2, 1), xi the longitude, eta the latitude up to the pole, zeta the radius; the north face
// (eta = 1) collapses onto the z axis, where det J = 0. Refined to degrees (2, 2, 2), n elements
// per direction.
Patch sphere_octant(int n) {
  const double w = std::sqrt(0.5), c[3][2] = {{1, 0}, {1, 1}, {0, 1}}, cw[3] = {1, w, 1};
  Patch a;
  a.pdim = 3;
  a.degree = {2, 2, 1};
  a.knots[0] = {0, 0, 0, 1, 1, 1};
  a.knots[1] = {0, 0, 0, 1, 1, 1};
  a.knots[2] = {0, 0, 1, 1};
  for (double r : {1.0, 2.0})
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i) {
        const double rho = r * c[j][0], z = r * c[j][1];
        a.cp.push_back(ControlPoint({rho * c[i][0], rho * c[i][1], z}, cw[i] * cw[j]));
      }
  a.elevate(2, 1);
  for (int d = 0; d < 3; ++d) a.subdivide(d, n);
  return a;
}

}  // namespace

// A patch with a degenerate face (the sphere octant's pole, det J = 0 on it): the stress there
// is taken 1 % of the way inside the element (BodyField::eval3), so an affine displacement's constant stress is drawn constant on
// every cell, those touching the pole included (faces and hexahedra), and the probe at the
// pole gives it; the collapsed face itself is not drawn.
TEST(VtkBezier3D, DegeneratePoleFace) {
  const Patch pt = sphere_octant(2);
  const double A[3][3] = {{0.02, -0.01, 0.03}, {0.015, -0.025, 0.01}, {-0.02, 0.005, 0.04}}, c[3] = {0, 0, 0};
  const std::vector<double> u = affine_u(pt, A, c);
  Problem P = solid_problem({pt});
  const double tin[3] = {0.3, 0.4, 0.5}, tpole[3] = {0.3, 1.0, 0.5};
  const FieldPoint in = BodyField(P, 0, u).eval(tin), pole = BodyField(P, 0, u).eval(tpole);
  EXPECT_NEAR(std::hypot(pole.x, pole.y), 0.0, 1e-14);   // on the z axis
  const double s_in[6] = {in.sxx, in.syy, in.szz, in.sxy, in.syz, in.sxz}, s_pole[6] = {pole.sxx, pole.syy, pole.szz, pole.sxy, pole.syz, pole.sxz};
  const double scale = in.von_mises();
  for (int k = 0; k < 6; ++k) EXPECT_NEAR(s_pole[k], s_in[k], 1e-6 * scale) << "component " << k;
  for (bool volume : {false, true}) {
    P.output.volume_cells = volume;
    const BezierMesh m = bezier_mesh(P, {u});
    // faces: the pole face (north, collapsed onto the z axis) has no area and is not drawn
    const int ne = 2 * 2;
    EXPECT_EQ(m.num_cells(), volume ? 8u : 5u * ne);
    for (size_t q = 0; q < m.num_cells(); ++q) EXPECT_NE(m.face[q], static_cast<int>(Side::North));
    double worst = 0;
    auto take = [&](double d) { worst = std::isfinite(d) ? std::max(worst, d) : HUGE_VAL; };
    for (size_t q = 0; q < m.num_points(); ++q) {
      for (int k = 0; k < 6; ++k) take(std::abs(m.stress[6 * q + k] - s_in[k]));
      take(std::abs(m.von_mises[q] - scale));
    }
    EXPECT_LT(worst, 1e-6 * scale) << (volume ? "hexahedra" : "faces");
  }
}
