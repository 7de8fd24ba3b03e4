#pragma once
// Validity of a patch's geometry map: the sign of det J, checked before anything is solved.
//
// The kernels integrate with |det J| (and Patch::orientation() turns left-handed patches
// around), so a patch whose Jacobian changes sign (a folded or self-overlapping control net,
// e.g. a bow tie) or vanishes inside (zero area) would run to a wrong answer. This check
// finds such a patch and says where.
//
// What is computed, per element (Bezier extraction, model/bezier.hpp): with the rational
// Bezier points in homogeneous form, A = sum w_k (x_k - c) B_k (c: a point of the element, for
// conditioning; D does not depend on it) and W = sum w_k B_k (weights scaled to max 1),
//
//     det J = D / W^3,    D = det [[W, A1, A2], [W_t, A1_t, A2_t], [W_s, A1_s, A2_s]],
//
// (t, s) the element's local coordinates in [0, 1]^2. D is a polynomial of bidegree
// (3 p0 - 1, 3 p1 - 1); where the element's weights are all equal it is W^3 (x_t y_s - x_s y_t),
// of bidegree (2 p0 - 1, 2 p1 - 1), and that cheaper form is used. Its Bernstein coefficients
// are computed exactly (derivatives: scaled differences; products: convolutions of the
// coefficients scaled by binomials), and D lies between the smallest and largest of them.
//
// Data layout: Bernstein coefficients c[i + j (m0 + 1)] (t index fastest, like the patch's
// control points), bidegree (m0, m1) <= (14, 14), on the stack; elements are visited one at a
// time (e0 fastest) and nothing is kept per element but one byte (its sign class from step 1).
//
// Decision. sigma = the patch's orientation, the sign of its signed area (approximately: the
// sum over the elements of mean M1 / (mean W)^2, M1 below), so that a fold is blamed on the
// smaller, inverted part; Patch::orientation() where the area is 0 to round-off (a symmetric
// bow tie). For a valid patch both agree. tol = 1e-12 L^2 + 1e-15 L X (L: the element's
// extent, X: its largest coordinate, for round-off), on det J in local coordinates; on D,
// tol * (smallest Bezier weight / largest)^3. Elements that step 1 finds of the wrong sign
// throughout are examined first (a fold is then named as one, not by the zero on its crease),
// then the others in element order; the first finding is the message.
//  1. sigma * D > tol is proven on the element: quickly, from the exact coefficients of
//     M1 = A1_t A2_s - A1_s A2_t (D itself where the weights are equal) and a bound on the
//     terms with W_t, W_s (small where the weights vary slowly: min W min M1 - R > tol, R from
//     the largest coefficients), else from all coefficients of D. Every element of a valid
//     patch without a collapsed edge and with a convex-enough net ends here.
//  2. Otherwise D is evaluated at the solver's (p0 + 1) x (p1 + 1) Gauss points and a 10 x 10
//     grid of interior points: sigma * det J < -tol anywhere is an error ("changes sign"),
//     |det J| <= tol an error ("vanishes"; "zero area" where every coefficient is ~0).
//  3. Otherwise (a sign change or zero between the samples, or a legitimate zero on the
//     boundary) the Bernstein form decides: for each element edge that lies on the patch
//     boundary and on which D vanishes identically (all its coefficients |D| <= tol: a
//     collapsed patch edge, the control points there coincide), the factor t, 1 - t, s or
//     1 - s is divided out, as often as it goes; the quotient E is then subdivided (de
//     Casteljau, halves in t and s, at most 12 levels). A piece whose coefficients are all
//     sigma * E > tol is proven fine; a corner of a piece (where E is exact) with
//     sigma * E < -tol is an error (changes sign), one with |E| <= tol is an error unless the
//     corner lies on the patch boundary.
//  Rule for zeros: det J = 0 is accepted on the patch boundary only, i.e. along a collapsed
//  patch edge (exactly: the factor is divided out and the rest must be positive) or at
//  isolated points of the patch boundary (e.g. a corner with a straight angle; there down to
//  2^-12 of the element: a piece that still cannot be proven positive is accepted when it
//  touches such a boundary zero). det J = 0 at any interior point of the patch, on interior
//  element edges too, is an error, and so is a wrong sign anywhere, boundary included.
//  Not checked: self-intersection of the boundary with det J > 0 inside (a patch wound twice
//  around a hole); overlaps between bodies.
//
// Cost per element: the extraction (3 (p+1)^3 per direction), M1 (2 p0 p1 (p0+1)(p1+1)
// multiply-adds: 72 at p = 2) and, only where the quick bound fails, the full D
// (18 p0 p1 (p0+1)(p1+1): 648 at p = 2, 16200 at p = 5); steps 2-3 run only on elements that
// step 1 does not prove (those at a collapsed edge: 100 samples, usually one subdivision
// piece). Measured (GeometryCheck.DISABLED_TimeOnAMillionDofs, one core, Release): quarter
// annulus at degree (2, 2), 700 x 700 elements, 985,608 dofs: 0.07 s (0.055 s with equal
// weights), ~140 ns per element; the same problem's whole read stage took 0.28 s, its set-up
// stage 0.32 s, the run 45 s.
//
// 3-D (trivariate patches, Patch::dim() == 3; the same rules, one more direction). With A the
// homogeneous coordinates translated by c as above,
//
//     det J = D / W^4,    D = det [[W, A1, A2, A3], [W_t, ...], [W_s, ...], [W_r, ...]],
//
// (t, s, r) in [0, 1]^3, of degree (4 p0 - 1, 4 p1 - 1, 4 p2 - 1); where the element's weights
// are equal, D = det [A_t; A_s; A_r] = det J, of degree (3 p - 1) per direction. The 2 x 2
// minors of rows (s, r) are formed once and shared by the 3 x 3 cofactors (28 trivariate
// products rational, 9 with equal weights). Coefficients in std::vector (degree 19 per
// direction at p = 5: 8000 of them). tol = 1e-12 L^3 + 1e-15 L^2 X on det J, times
// (smallest weight / largest)^4 on D. Step 1: all coefficients of D of the sign sigma (the
// patch's, from its signed volume: the sum of the elements' mean coefficient of D, or of
// M0 = det [A_t; A_s; A_r] over mean W^3 where rational). Rational elements are first tried
// with a quick bound as in 2-D: D = W M0 - A1 M1 + A2 M2 - A3 M3, M0 exact, the rest bounded
// by the largest coefficients (|M_a| <= the permanent of the largest derivative
// coefficients of its columns); only where min W min M0 - R > tol fails is the full D formed.
// Step 2: the (p + 1)^3 Gauss points and a 6^3 interior grid. Step 3: the factor of each patch
// face on which D vanishes identically (a face collapsed onto an edge or a point, e.g. the pole
// face of a sphere octant) divided out, then octree subdivision (at most 8 levels, 20000 pieces
// per element) with the 8 corners of each piece tested as the 4 corners in 2-D.
// Measured (GeometryCheck3D.DISABLED_Time8000Elements, one core, Release, degree 2, 20^3
// elements): equal weights 2.8 us per element, the rational quarter cylinder shell 5.8 us
// per element (the quick bound holds on all of them; the full D costs ~30 us).
#include <string>

#include "model/nurbs.hpp"

namespace iga {

/// "" if det J has one sign over the whole patch and vanishes at most on its boundary (see
/// above; 2-D or 3-D by patch.dim()); else one line: what is wrong, the element (its parametric box), a parametric point
/// and its physical point, e.g. "det J changes sign in element [0.25, 0.5] x [0, 0.5] (det J
/// = -0.31 at xi = 0.41, eta = 0.12, x = (1.2, 0.3)); the control net folds over" (3-D: "element [..] x [..] x [..]
/// (det J = .. at xi = .., eta = .., zeta = .., x = (x, y, z))", "zero volume").
/// The patch must have passed Patch::validate(). sign: the sign det J must have everywhere
/// (+1 or -1; a deformed configuration keeps its reference patch's), 0: the patch's own
/// orientation, decided by its signed area as above.
std::string check_jacobian(const Patch& patch, int sign = 0);

}  // namespace iga
