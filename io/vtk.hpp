#pragma once
// The exact geometry of every body as VTK rational Bezier cells (one .vtu for all bodies),
// and the .pvd collection over load steps.
//
// What it computes. Each element (non-empty knot span pair) of a body's NURBS patch is a
// rational Bezier patch (model/bezier.hpp); it becomes one VTK_BEZIER_QUADRILATERAL (type 77)
// cell of degrees (p0, p1) whose (p0 + 1)(p1 + 1) points are the element's Bezier points
// (reference configuration, z = 0) with their weights as the point array RationalWeights.
// VTK evaluates such a cell as x(t) = sum_k B_k(t) w_k x_k / sum_k B_k(t) w_k, and any point
// array the same way, so:
//   - displacement: the Bezier coefficients of the displacement (exact: it is in the NURBS
//     space), 3 components (ux, uy, 0); Warp By Vector moves the cells onto the exact
//     deformed geometry;
//   - stress is not in the spline space: per element, coefficients c_k are fitted so that
//     the element's rational Bezier interpolant equals BodyField's stress at the
//     (p0 + 1)(p1 + 1) collocation points t = (j0 / p0, j1 / p1) (a small dense solve per
//     element); von_mises is fitted the same way (it is not recomputed from the tensor).
//     A coefficient shared by neighbouring cells (below) is the mean of their fits, then
//     clamped into the union of the ranges of those cells' samples (the collocation points
//     and the output grid of result.xdmf), per component: the field, a convex combination of
//     its coefficients (positive weights), stays within what was sampled (von Mises >= 0).
//     Corners still interpolate; interior points where a coefficient was clamped no longer
//     do (docs/paraview.md).
//   Points are shared within a patch where the fields are continuous: neighbouring elements
//   share their boundary Bezier points where the knot between them has a multiplicity below
//   p (the displacement is C^1 there, the stress continuous, and the two fits agree on the
//   edge to round-off); at a C^0 knot (and everywhere at p = 1) each element keeps its own
//   points, so a stress jump is drawn as one. A patch with ne0 x ne1 elements of degree p
//   has about (p ne0 + 1)(p ne1 + 1) points instead of (p + 1)^2 ne0 ne1.
//
// Layout. Cells are numbered body after body, element e = e0 + e1 * ne0 (xi fastest) within
// a body; each cell lists (p0 + 1)(p1 + 1) points (connectivity) in VTK's higher-order
// quadrilateral order (vtk_quad_point_index): corners (0,0), (p0,0), (p0,p1), (0,p1), then the
// interior points of the edges j = 0 (i increasing), i = p0 (j increasing), j = p1 (i
// increasing), i = 0 (j increasing), then the face-interior points, i fastest.
// Arrays (N points, C cells):
//   Points             N x 3  Float64  Bezier points x, y, 0
//   RationalWeights    N      Float64  (point attribute RationalWeights)
//   displacement       N x 3  Float64  (point vectors)
//   stress             N x 6  Float32  XX, YY, ZZ, XY, YZ, XZ (VTK's symmetric tensor order)
//   von_mises          N      Float32  (point scalars)
//   connectivity, offsets     Int32    (Int64 beyond 2^31 entries)
//   HigherOrderDegrees C x 3  Int32    p0, p1, 0 (cell attribute HigherOrderDegrees)
//   body               C      Int32    index into Problem::bodies
//   patch              C      Int32    the body's patch (0 for single-patch bodies)
//   element            C      Int32    e0 + e1 * ne0
//   element_ij         C x 2  Int32    e0, e1
//   knot_span          C x 2  Int32    knot span indices s0, s1 into the patch's knot vectors
//   parametric_range   C x 4  Float64  u_a, u_b, v_a, v_b of the element
//   field data: TimeValue (Float64, 1: the load factor), run_id (String, 1),
//               body_names (String, one per body)
// 3-D (Analysis::Solid, trivariate patches): the same construction on
//   - faces (default, output.cells: faces): each boundary face of a patch that is not an
//     interface and not collapsed onto a curve or a point (a sphere octant's pole) is the bivariate patch Patch::face(s) (3-D Bezier points, its directions the
//     free ones in increasing order); its elements become VTK_BEZIER_QUADRILATERAL cells
//     carrying the volume's field on the face (stress evaluated in the volume at the face's
//     parameter); a cell is transposed (i <-> j, degrees (p1, p0)) where that order's normal
//     points into the body, so every face cell's VTK normal points outwards. Points are shared
//     within a face, not between faces. Bounds of the stress fit: fit points and the grid of
//     output_samples of the face.
//   - volume (output.cells: volume): each element a VTK_BEZIER_HEXAHEDRON (type 79) of
//     (p0 + 1)(p1 + 1)(p2 + 1) points in vtk_hex_point_index order, shared within the patch
//     as above in three directions; bounds: the fit points (j0 / p0, j1 / p1, j2 / p2) and,
//     where output.samples_per_element is given, that grid.
//   Arrays as in 2-D with Points x, y, z, displacement ux, uy, uz, stress all six components,
//   HigherOrderDegrees p0, p1, p2 (hexahedra) or the face's two degrees and 0; the cell arrays
//   name the volume element the cell is or lies on: element e0 + ne0 (e1 + ne1 e2),
//   element_ij C x 3, knot_span C x 3, parametric_range C x 6 (u_a, u_b, v_a, v_b, w_a, w_b;
//   on a face the fixed direction's a = b), and face C Int32 (the side 0..5 of a face cell,
//   -1 for a hexahedron).
// Cost: O(C (p0 + p1 + 2)(p0 + 1)(p1 + 1)) for the fits (tensor-product solves of the
// Bernstein collocation matrices), plus one BodyField evaluation per fit point and per
// sample of the bounds.
#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "model/problem.hpp"

namespace iga {

/// Offset of Bezier point (i, j), 0 <= i <= p0, 0 <= j <= p1, in a VTK higher-order
/// quadrilateral of degrees (p0, p1) (vtkHigherOrderQuadrilateral::PointIndexFromIJK).
int vtk_quad_point_index(int i, int j, int p0, int p1);

/// Offset of Bezier point (i, j, k) in a VTK higher-order hexahedron of degrees (p0, p1, p2)
/// (VTK_BEZIER_HEXAHEDRON = 79, vtkHigherOrderHexahedron::PointIndexFromIJK): the 8 corners
/// (bottom k = 0 counter-clockwise, then top), the interior points of the 12 edges (bottom:
/// along i at j = 0, along j at i = p0, along i at j = p1, along j at i = 0; the same on top;
/// then along k at the corners 0, 1, 2, 3), of the 6 faces (i = 0, i = p0, j = 0, j = p1,
/// k = 0, k = p2; the lower remaining index fastest), then the interior, i fastest. For the
/// 3-D output (issue 35).
int vtk_hex_point_index(int i, int j, int k, int p0, int p1, int p2);

/// Collocation points of the per-element fit in [0, 1]^2, numbered j0 + j1 (p0 + 1):
/// (j0 / p0, j1 / p1).
std::vector<std::array<double, 2>> fit_points(int p0, int p1);

/// Coefficients c of ncomp fields in the rational Bezier basis of degrees (p0, p1) with
/// weights w (per Bezier point, k = k0 + k1 (p0 + 1)) that interpolate `values`
/// (values[j * ncomp + c] at fit_points(p0, p1)[j]): coef[k * ncomp + c].
void fit_rational_bezier(int p0, int p1, const double* w, int ncomp, const double* values, double* coef);
/// The same in dim = 1, 2 or 3 directions of degrees p[d]: points, weights and values numbered
/// k0 + (p0 + 1)(k1 + (p1 + 1) k2), fit points (j0 / p0, j1 / p1, j2 / p2). Tensor-product
/// solves, O(p^(dim+1)) per call.
void fit_rational_bezier(int dim, const int* p, const double* w, int ncomp, const double* values, double* coef);

/// Clamps coefficient k, component q into [lo[q], hi[q]] (coef[k * ncomp + q], k < n). A
/// rational Bezier field with positive weights is a convex combination of its coefficients,
/// so afterwards it lies within [lo, hi] everywhere in the cell.
void clamp_coefficients(int n, int ncomp, const double* lo, const double* hi, double* coef);

/// All bodies as rational Bezier cells, arrays as described above (points in VTK order).
struct BezierMesh {
  int dim = 2;                        // of the problem: 3-D cells carry 3-component indices
  std::vector<double> points;         // 3 per point
  std::vector<double> weights;        // 1 per point
  std::vector<double> displacement;   // 3 per point
  std::vector<double> stress;         // 6 per point: XX, YY, ZZ, XY, YZ, XZ
  std::vector<double> von_mises;      // 1 per point
  std::vector<std::int64_t> connectivity;   // the cell's points, VTK order
  std::vector<std::int64_t> offsets;  // end of each cell's connectivity (VTK "offsets")
  std::vector<std::uint8_t> types;    // VTK cell type: 77 quadrilateral, 79 hexahedron
  std::vector<int> degrees;           // 3 per cell
  std::vector<int> body, patch, element;   // 1 per cell (patch: of its body)
  std::vector<int> element_ij;        // dim per cell
  std::vector<int> knot_span;         // dim per cell
  std::vector<double> range;          // 2 dim per cell
  std::vector<int> face;              // 3-D: 1 per cell, the side (0..5) of a face cell, -1 for a hexahedron
  std::vector<std::string> body_names;
  /// Largest |u| at the points where the field was evaluated (fit points and bounds samples)
  double max_displacement = 0;
  std::size_t num_points() const { return weights.size(); }
  std::size_t num_cells() const { return body.size(); }
};

/// Samples per element and direction of the output grid of a patch (OutputOptions::samples).
int output_samples(const OutputOptions& o, const Patch& pt);

/// Builds the cells. cp_displacement: per body, dim values per control point (as
/// gather_displacements returns them on rank 0). 3-D (Problem::dim() = 3): by default the
/// boundary faces of every patch that are not interfaces (output.cells: faces), or with
/// OutputOptions::volume_cells (output.cells: volume) every element as a hexahedron; see
/// "3-D" above. The elements' field evaluations and fits run on up to `threads` threads, in
/// chunks merged in element order (the same mesh for any number).
BezierMesh bezier_mesh(const Problem& P, const std::vector<std::vector<double>>& cp_displacement, int threads = 1);

/// AppendedZlib: as AppendedRaw, each array compressed in blocks of 1 MiB in zlib's format (level 1;
/// libdeflate where the build found it, else zlib)
/// as VTK's vtkZLibDataCompressor reads them (ParaView, any VTK reader).
enum class VtkEncoding { Ascii, AppendedRaw, AppendedZlib };

/// Bytes of the arrays of mesh's .vtu uncompressed (AppendedRaw), headers apart.
std::size_t vtu_raw_bytes(const BezierMesh& mesh);

/// The VTK XML UnstructuredGrid text (.vtu) of a mesh; load_factor goes into the field data
/// TimeValue, run_id into the string field data run_id. AppendedRaw: binary arrays after the
/// XML (header_type UInt64, the machine's byte order), the field data stays ascii.
/// AppendedZlib compresses each array's blocks on up to `threads` threads (the same bytes for
/// any number).
std::string vtu_text(const BezierMesh& mesh, double load_factor, const std::string& run_id,
                     VtkEncoding encoding = VtkEncoding::AppendedRaw, int threads = 1);

/// A .vtu as the pieces of its bytes in order (vtu_text joins them; ResultWriter writes them in
/// turn, without a copy into one string). The pieces point into `keep` and into the mesh's
/// arrays: the mesh must outlive them.
struct VtuFile {
  std::vector<std::string_view> parts;
  std::vector<std::shared_ptr<const void>> keep;
  std::size_t size() const;
  std::string str() const;
};
VtuFile vtu_file(const BezierMesh& mesh, double load_factor, const std::string& run_id,
                 VtkEncoding encoding = VtkEncoding::AppendedRaw, int threads = 1);

/// bezier_mesh + vtu_text.
std::string bezier_vtu(const Problem& P, const std::vector<std::vector<double>>& cp_displacement,
                       double load_factor, const std::string& run_id,
                       VtkEncoding encoding = VtkEncoding::AppendedRaw);

/// A ParaView .pvd collection of (time, file) pairs; file names relative to the .pvd.
std::string pvd_collection(const std::vector<std::pair<double, std::string>>& steps);

}  // namespace iga
