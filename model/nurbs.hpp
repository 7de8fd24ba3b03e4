#pragma once
// Host-side NURBS geometry: bivariate (2-D) and trivariate (3-D) tensor-product patches, their
// boundary curves and faces, and the refinements that leave the geometry unchanged (knot
// insertion, degree elevation).
//
// Storage: control points in Euclidean coordinates with a named weight, cp[a] = {{x, y, z}, w}
// (ControlPoint; z = 0 in 2-D), a = i + ncp(0) (j + ncp(1) k) (xi runs fastest). Refinement works
// in homogeneous coordinates (w x, w y, w z, w), where a NURBS patch is a plain B-spline patch.
#include <array>
#include <string>
#include <vector>

#include "kernels/sides.hpp"

namespace iga {

/// A patch side, numbered 2 direction + end (kernels/sides.hpp: one rule for 2-D and 3-D).
enum class Side { West = 0, East = 1, South = 2, North = 3, Front = 4, Back = 5 };
constexpr int side_direction(Side s) { return side_direction(static_cast<int>(s)); }
constexpr int side_end(Side s) { return side_end(static_cast<int>(s)); }
constexpr Side side_of(int direction, int end) { return static_cast<Side>(side_number(direction, end)); }
constexpr int side_normal_sign(Side s) { return side_normal_sign(static_cast<int>(s)); }
constexpr int side_tangent_direction(Side s) { return side_tangent_direction(static_cast<int>(s)); }
const char* side_name(Side s);
/// The side named `name` among the num_sides(dim) sides (front and back only in 3-D).
bool parse_side(const std::string& name, Side& s, int dim = 2);

/// Largest spatial dimension of the geometry. A 2-D problem carries z = 0 in every control point.
constexpr int kMaxDim = 3;

/// A control point: Euclidean coordinates x[0 .. kMaxDim) and its weight w, by name, so that no
/// code reads the weight as a coordinate. Built as ControlPoint{{x, y}, w}; a bare {x, y, w}
/// does not compile. Laid out as kMaxDim + 1 doubles {x..., w}, the row layout of the
/// kernels' control point views (solver/patch_data.cpp's host_patch_data aliases it).
struct ControlPoint {
  std::array<double, kMaxDim> x{};
  double w = 1.0;

  ControlPoint() = default;
  ControlPoint(const std::array<double, kMaxDim>& coords, double weight) : x(coords), w(weight) {}
  bool operator==(const ControlPoint& o) const { return x == o.x && w == o.w; }
  bool operator!=(const ControlPoint& o) const { return !(*this == o); }
};

/// A NURBS curve; `patch_index[k]` is the patch control point that control point k came from.
struct Curve {
  int degree = 1;
  std::vector<double> knots;
  std::vector<ControlPoint> cp;
  std::vector<int> patch_index;
  int ncp() const { return static_cast<int>(cp.size()); }
  /// Parameter intervals [knots[s], knots[s+1]] of non-zero length: the curve's elements.
  std::vector<int> element_spans() const;
  std::array<double, 2> eval(double u) const;
  /// dC/du at u, exact (the rational quotient rule on the basis derivatives).
  std::array<double, 2> derivative(double u) const;
};

struct Patch {
  std::array<int, kMaxDim> degree{1, 1, 0};
  std::array<std::vector<double>, kMaxDim> knots;
  std::vector<ControlPoint> cp;
  /// Parametric dimension: 2 (bivariate) or 3 (trivariate); directions d >= pdim are unused
  /// (one control point, no knots). Its sides are the num_sides(dim()) of kernels/sides.hpp.
  int pdim = 2;

  int dim() const { return pdim; }
  int ncp(int d) const { return d < pdim ? static_cast<int>(knots[d].size()) - degree[d] - 1 : 1; }
  int index(int i, int j, int k = 0) const { return i + ncp(0) * (j + ncp(1) * k); }
  /// Indices s of the non-empty knot spans [U[s], U[s+1]] in direction d.
  std::vector<int> element_spans(int d) const;
  /// Elements per direction (1 for a direction d >= dim()).
  int num_elements(int d) const { return d < pdim ? static_cast<int>(element_spans(d).size()) : 1; }
  int num_elements() const {
    int m = 1;
    for (int d = 0; d < pdim; ++d) m *= num_elements(d);
    return m;
  }

  /// Checks the knot vectors, degrees, counts and weights; returns "" or what is wrong.
  std::string validate() const;

  /// Physical point at (u, v) (2-D).
  std::array<double, 2> eval(double u, double v) const;
  /// Physical point {x, y, z} at the parameters t[0 .. dim()) (2-D: z = 0).
  std::array<double, kMaxDim> point(const double* t) const;
  /// Sign of det(dx/dxi) at the parametric centre: +1 right-handed, -1 left-handed.
  int orientation() const;

  /// Knot insertion (Boehm), once, of u in direction d. Geometry unchanged.
  void insert_knot(int d, double u);
  /// Split every non-empty knot span of direction d into n equal pieces.
  void subdivide(int d, int n);
  /// Raise the degree of direction d by t, increasing every knot's multiplicity by t.
  /// The new control points interpolate the old patch at the Greville abscissae of the
  /// new space; since the old space is contained in the new one this reproduces the
  /// geometry exactly (to round-off).
  void elevate(int d, int t);

  /// 2-D: boundary side as a NURBS curve of its own; its parameter increases with xi (south,
  /// north) or eta (west, east).
  Curve side_curve(Side s) const;
  /// 3-D: face s as a bivariate patch of its own (3-D control points): its directions are the
  /// face's free parametric directions in increasing order (west/east: eta, zeta;
  /// south/north: xi, zeta; front/back: xi, eta), as side_tensor_index numbers them.
  Patch face(Side s) const;
  /// Patch control point indices on a side (2-D, in increasing parameter order) or a face
  /// (3-D, the first free direction fastest).
  std::vector<int> side_indices(Side s) const;
};

/// Open knot vector [0..0, 1/n, ..., 1..1] with p + 1 repeated end knots and n spans.
std::vector<double> uniform_open_knots(int p, int n);
/// The non-empty knot spans s (U[s] < U[s + 1]) of knot vector U of degree p: the elements.
std::vector<int> nonempty_spans(const std::vector<double>& U, int p);

}  // namespace iga
