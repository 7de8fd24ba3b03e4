#pragma once
// Checks of a configuration that do not trust the declared contact pairs: a run that exits 0
// must be physically right (docs/problem-file.md, exit code 5; docs/architecture.md).
//
//  * check_pair_facing (read time, `check` and `run`): a contact pair whose slave side faces
//    away from its master can never touch it; the run would "converge" with no contact.
//  * penalty_ratio: the penalty against the stiffness scale E / h of the pair.
//  * find_penetration (after every converged load step): points of every body's boundary
//    (the sides that are not interfaces) inside another body, or inside their own body far
//    (in the reference configuration) from where they belong (self-penetration), deeper than
//    the contact pairs between those bodies allow.
//  * find_inverted: an element of the deformed configuration x = X + u whose Jacobian changes
//    sign or vanishes (det F <= 0), by the exact Bezier-coefficient test of
//    model/geometry_check.hpp applied to the deformed control net.
//
// What find_penetration computes. The boundary: every outer side (not an interface, not
// collapsed) as a polyline of 4 + 1 points per element, deformed (x) and reference (X), with
// its reference arc length. 1) Crossings: segments of two bodies' lines that cross, or of one
// body's lines that cross and are not neighbours along the boundary, found through bins
// (about one segment per bin). A locally injective map (no inverted element)
// whose boundary curves do not cross does not overlap itself, and two bodies whose boundaries
// do not cross do not overlap unless one lies wholly inside the other: only the lines found
// here, and each body's first line against the bodies none of its lines crosses (one wholly
// inside another), are tested further. 2) A point x of such a line is inside patch Q of
// the body it crosses when Newton on x_Q(xi) = x, from the nearest of Q's 2 x 2 points per
// element (in its own body: from one of the 6 nearest), converges to |x_Q(xi) - x| <= 1e-10 L (L the largest body's size); in
// its own body, the preimage must not be x's own reference point. 3) Its depth is the
// distance from x to that body's deformed boundary polylines (its own body: leaving out the
// boundary within 4 element sizes of x along the boundary). Allowed depth: 3 x the largest
// penetration the pairs between the two bodies report (penalty contact penetrates by about
// p / eps by design), and at least 1 % of x's boundary element (below, the discretisation
// decides: a KTS slave's corner between its quadrature points). The deepest finding is
// reported. Cost: host, rank 0, after each converged step: 1-4 % of the runs of the examples
// (timer "7) Checks"), most of it in contact runs, where penalty penetration makes the
// contact sides cross.
#include <string>
#include <vector>

#include "model/problem.hpp"

namespace iga {

/// "" when some slave point has the master in front of it with opposed outward normals
/// (n_s . n_m < 0, (x_m - x_s) . n_s >= -d and (x_s - x_m) . n_m >= -d, d half the slave
/// body's smallest extent), else why not: the slave side lies deeper than d inside the master
/// (the bodies overlap), or the sides face away (naming the slave sides that do face it).
/// Where they face, *overlap_warning (if given) gets one line when the slave side starts inside
/// its master (an initial overlap deeper than 1e-8 of that extent, measured between sample
/// points of the two sides with opposed normals): the run treats it as an interference fit.
/// Where the slave body has no side that faces the master but the master body has sides that
/// face the slave side, the line blames the master side and names those, and *master_at_fault
/// (if given) is set.
std::string check_pair_facing(const Problem& P, const ContactPair& c, std::string* overlap_warning = nullptr,
                              bool* master_at_fault = nullptr);

/// penalty / (E / h): E the smaller Young's modulus of the pair's bodies, h the smallest slave
/// element (reference arc length). Typical penalties are 1..100 E / h; far above, round-off in
/// the gaps (times the penalty) and the conditioning of the tangent spoil the pressure.
double penalty_ratio(const Problem& P, const ContactPair& c, double* E = nullptr, double* h = nullptr);
constexpr double kPenaltyRatioWarning = 1e4;
/// One line about a pair's penalty where its ratio is above kPenaltyRatioWarning, else "".
std::string penalty_warning(const Problem& P, int pair);

/// A face (a bivariate patch with 3-D points): the smallest over its elements of the longest
/// distance between two corners along an element edge (infinity without elements of positive
/// size). The slave element size of the penalty check and of 3-D contact's tolerances.
double smallest_element_size(const Patch& face);

/// u: per body, dim displacements per merged control point (Body::cp_index numbering).
/// allowed_penetration[pair]: the largest penetration each contact pair reports now.
/// Returns "" or one line: bodies, sides, depth and where.
std::string find_penetration(const Problem& P, const std::vector<std::vector<double>>& u,
                             const std::vector<double>& pair_penetration);
/// Per pair of bodies (a * num_bodies + b, both orders): allowed = 3 x the largest penetration
/// their contact pairs report (pair_penetration[pair]), declared = a pair joins them.
void pair_allowances(const Problem& P, const std::vector<double>& pair_penetration, std::vector<double>& allowed,
                     std::vector<bool>& declared);
/// The outer sides (2-D) or faces (3-D) of a body: not interfaces, not collapsed to a point.
std::vector<PatchSide> outer_sides(const Body& b);
/// A number of the checks' one-line messages ("%.3g").
std::string check_number(double v);
/// The same for solids (model/configuration_check3.cpp: the outer faces' Bezier elements
/// instead of polylines); find_penetration calls it in 3-D.
std::string find_penetration3(const Problem& P, const std::vector<std::vector<double>>& u,
                              const std::vector<double>& pair_penetration);
/// "" or one line naming the body, patch, element and a point where det F <= 0.
std::string find_inverted(const Problem& P, const std::vector<std::vector<double>>& u);

}  // namespace iga
