#pragma once
// Quadrature rules made for splines: a generalised Gaussian rule per patch direction that
// integrates exactly every function of the spline space the element integrals live in,
// with about half the points of the element-wise Gauss rule.
//
// What must be integrated. On a knot vector U of degree p, a knot of multiplicity m makes the
// basis C^(p-m). The stiffness and internal force integrands, for an affine map and
// polynomial B-splines, are per direction products of two basis functions or of their first
// derivatives: piecewise polynomials of degree 2p, C^(p-m-1) at that knot. Their space is the
// spline space S of degree d = 2p with the knot repeated p + m + 1 times (2p + 1 when
// m = p: no continuity), of dimension N. A Gaussian rule for S (Micchelli and Pinkus 1977;
// Hughes, Reali and Sangalli 2010, "Efficient quadrature for NURBS-based isogeometric
// analysis"; Barton and Calo 2016, "Optimal quadrature rules for odd-degree spline spaces")
// has N / 2 nodes: for maximal smoothness (m = 1) about (p + 2) / 2 per element against
// p + 1 Gauss points, so (p + 2)^2 / 4 instead of (p + 1)^2 points per element in 2-D
// (p = 2: 4 for 9, p = 4: 9 for 25).
//
// How it is computed: Newton's method on the N moment equations sum_j w_j B_i(x_j) = int B_i
// for the nodes and weights (banded Jacobian, LAPACK dgbsv through Teuchos), from nodes
// between pairs of consecutive Greville abscissae of S and weights summing the paired
// functions' integrals. Where N is odd, S is enlarged by one function: one more copy of the
// knot at the middle of [a, b] (or a new knot there), so that a symmetric knot vector keeps a
// symmetric rule (a patch and its mirror image then get mirrored rules). Where Newton from
// that start fails (strongly graded knots), the rule is continued from the knot vector with
// the same multiplicities and evenly spaced values to the given one. The result
// is checked: every moment to 1e-12 relative, weights > 0, nodes strictly increasing inside
// [a, b], at most kMaxNodesPerElement in an element. A rule that fails the check is not
// used (the caller keeps Gauss and says why).
//
// Where it is exact: B-spline patches (weights 1) with an affine map, where the stiffness
// integrand is in S x S. Rational weights and curved maps make the integrand rational: the
// rule is then as inexact as Gauss is, in a different way (tests/test_quadrature.cpp).
#include <string>
#include <vector>

namespace iga {

/// A 1-D rule over a whole knot vector, grouped by element (non-empty span, in order):
/// element k holds nodes x[off[k] .. off[k + 1]) with weights w (in the parameter, the
/// length of the span included).
struct SplineRule {
  std::vector<double> x, w;
  std::vector<int> off;
  int newton_iterations = 0;
  double moment_error = 0;   // max over the target space of |rule - integral| / integral
  std::string failure;       // empty when the rule is valid
};

constexpr int kMaxNodesPerElement = 12;   // kernels' fixed arrays (kMaxGauss)

/// The generalised Gaussian rule for the integrands of degree p splines on knot vector U.
SplineRule spline_gauss_rule(const std::vector<double>& U, int p);

/// Host B-spline values (and first derivatives when d1 is not null) of degree d <= 12 at u in
/// span s of knot vector T: N[0..d] are the functions s - d .. s.
void host_bspline(const std::vector<double>& T, int d, int s, double u, double* N, double* d1);

}  // namespace iga
