#pragma once
// Bezier extraction of NURBS patches (Borden, Scott, Evans, Hughes 2011, "Isogeometric finite
// element data structures based on Bezier extraction of NURBS", Algorithm 1).
//
// On element e of a 1-D knot vector (the e-th non-empty span s), the p + 1 B-splines that do
// not vanish there are polynomials of degree p, and so combinations of the Bernstein
// polynomials B_k(t), t = (u - U[s]) / (U[s+1] - U[s]) in [0, 1]:
//
//     N_{s-p+i}(u) = sum_k C^e[i][k] B_k(t),      i, k = 0..p        (C^e: the extraction operator)
//
// In 2-D the operator is the tensor product C^{e0} x C^{e1} (3-D: x C^{e2}). A NURBS patch with
// homogeneous control points P^w_a = (w x, w y, w z, w) is, on each element, a rational Bezier
// patch with the homogeneous Bezier points Q^w = (C^{e0} x C^{e1} [x C^{e2}])^T P^w. A field f = sum_a R_a f_a in the
// same space has Bezier coefficients f^B = (C^T (w f))_k / w^B_k with the same rational
// basis, so geometry and displacement extract alike.
//
// Cost: O(p^2) per element in 1-D to build the operators, O((p+1)^(dim+1)) per element and
// component to apply them (dim 1-D contractions). Used for the rational Bezier cells of the
// VTK output and for the sign of det J (model/geometry_check).
#include <array>
#include <vector>

#include "model/nurbs.hpp"

namespace iga {

/// Extraction operators of a 1-D open knot vector of degree p, one per non-empty span in
/// increasing order: C[e][i * (p + 1) + k] = C^e[i][k].
std::vector<std::vector<double>> bezier_extraction_1d(const std::vector<double>& U, int p);

/// Bernstein polynomials B_0..B_p of degree p at t in [0, 1].
void bernstein(int p, double t, double* B);

/// The elements of a patch (2-D or 3-D) in Bezier form. Elements are numbered
/// e = e0 + ne0 (e1 + ne1 e2) (xi fastest); the (p0 + 1)(p1 + 1)[(p2 + 1)] Bezier points of an
/// element are numbered k0 + (p0 + 1)(k1 + (p1 + 1) k2).
class BezierPatch {
 public:
  explicit BezierPatch(const Patch& patch);

  int dim() const { return dim_; }
  int num_elements() const { return ne_[0] * ne_[1] * ne_[2]; }
  int num_elements(int d) const { return ne_[d]; }
  int points_per_element() const { return (p_[0] + 1) * (p_[1] + 1) * (p_[2] + 1); }
  /// Degrees per direction (0 for a direction d >= dim()).
  const std::array<int, 3>& degree() const { return p_; }
  /// Knot span index (into the patch's knot vector) of element e's direction d.
  int span(int e, int d) const { return spans_[d][element_index(e, d)]; }
  /// The index along direction d of element e (kernels/numbering.hpp: first direction fastest).
  int element_index(int e, int d) const {
    int ij[3];
    tensor_ij(e, ne_.data(), 3, ij);
    return ij[d];
  }
  /// Parameter range of element e in direction d.
  std::array<double, 2> range(int e, int d) const;

  /// Rational Bezier points of element e: {x, y, z} in Euclidean coordinates with weight.
  void element_points(int e, ControlPoint* out) const;
  /// Bezier coefficients of a field given per control point of the patch (ncomp values each,
  /// f[a * ncomp + c]), interpolated with the patch's rational basis: out[k * ncomp + c].
  void element_field(int e, const double* f, int ncomp, double* out) const;

 private:
  const Patch* patch_;
  int dim_ = 2;
  std::array<int, 3> p_{0, 0, 0}, ne_{1, 1, 1};
  std::array<std::vector<int>, 3> spans_;
  std::array<std::vector<std::vector<double>>, 3> C_;
  // the patch control point of local function (i, j, k) of element e
  int local_cp(int e, int i, int j, int k) const;
  // homogeneous values (ncomp + 1 per control point, the weight last) of element e -> Bezier
  void extract(int e, int ncomp, const std::vector<double>& hom, double* out) const;
};

}  // namespace iga
