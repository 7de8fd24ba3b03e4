#pragma once
// Host-side NURBS geometry: 2-D tensor-product patches, their boundary curves, and the
// refinements that leave the geometry unchanged (knot insertion, degree elevation).
//
// Storage: control points in Euclidean coordinates with a named weight, cp[a] = {{x, y}, w}
// (ControlPoint), a = i + j * ncp(0) (xi runs fastest). Refinement works in homogeneous
// coordinates (w x, w y, w), where a NURBS patch is a plain B-spline patch.
#include <array>
#include <string>
#include <vector>

#include "kernels/sides.hpp"

namespace iga {

/// A patch side, numbered 2 direction + end (kernels/sides.hpp: one rule for 2-D and 3-D).
enum class Side { West = 0, East = 1, South = 2, North = 3 };
constexpr int side_direction(Side s) { return side_direction(static_cast<int>(s)); }
constexpr int side_end(Side s) { return side_end(static_cast<int>(s)); }
constexpr Side side_of(int direction, int end) { return static_cast<Side>(side_number(direction, end)); }
constexpr int side_normal_sign(Side s) { return side_normal_sign(static_cast<int>(s)); }
constexpr int side_tangent_direction(Side s) { return side_tangent_direction(static_cast<int>(s)); }
const char* side_name(Side s);
bool parse_side(const std::string& name, Side& s);

/// Largest spatial dimension of the geometry: 2 today. 3-D changes this constant to 3 (a 2-D
/// problem then carries z = 0 in every control point).
constexpr int kMaxDim = 2;

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
};

struct Patch {
  std::array<int, 2> degree{1, 1};
  std::array<std::vector<double>, 2> knots;
  std::vector<ControlPoint> cp;

  /// Parametric dimension: 2 (bivariate; its sides are the num_sides(dim()) of kernels/sides.hpp).
  int dim() const { return 2; }
  int ncp(int d) const { return static_cast<int>(knots[d].size()) - degree[d] - 1; }
  int index(int i, int j) const { return i + j * ncp(0); }
  /// Indices s of the non-empty knot spans [U[s], U[s+1]] in direction d.
  std::vector<int> element_spans(int d) const;
  int num_elements() const {
    return static_cast<int>(element_spans(0).size() * element_spans(1).size());
  }

  /// Checks the knot vectors, degrees, counts and weights; returns "" or what is wrong.
  std::string validate() const;

  /// Physical point at (u, v).
  std::array<double, 2> eval(double u, double v) const;
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

  /// Boundary side as a NURBS curve of its own; its parameter increases with xi (south,
  /// north) or eta (west, east).
  Curve side_curve(Side s) const;
  /// Patch control point indices on a side, in increasing parameter order.
  std::vector<int> side_indices(Side s) const;
};

/// Open knot vector [0..0, 1/n, ..., 1..1] with p + 1 repeated end knots and n spans.
std::vector<double> uniform_open_knots(int p, int n);
/// The non-empty knot spans s (U[s] < U[s + 1]) of knot vector U of degree p: the elements.
std::vector<int> nonempty_spans(const std::vector<double>& U, int p);

}  // namespace iga
