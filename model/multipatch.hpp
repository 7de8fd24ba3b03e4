#pragma once
// Multi-patch topology, kept apart from the patches (as G+Smo's gsBoxTopology): which patch
// sides meet (interfaces) and which lie on the body's boundary, named boundaries, and the
// control point merging that makes the displacement continuous across conforming interfaces.
#include <array>
#include <string>
#include <utility>
#include <vector>

#include "model/input_error.hpp"
#include "model/nurbs.hpp"

namespace iga {

/// One side of one patch: `patch<k>.<side>` in a problem file (k from 0, the file's order).
struct PatchSide {
  int patch = 0;
  Side side = Side::West;
  bool operator==(const PatchSide& o) const { return patch == o.patch && side == o.side; }
};
std::string patch_side_name(const PatchSide& s);   // "patch1.north"

/// A conforming interface: side a of one patch meets side b of another (or of the same patch).
/// 2-D: reversed: the two sides' parameters run in opposite directions.
/// 3-D (faces): one of the 8 relative orientations of two faces. A face's own directions are
/// its patch's free directions in increasing order (k = 0, 1; as Patch::face and
/// side_indices number them); face a's direction k runs along face b's direction face_map[k],
/// against it where face_flip[k]. (G+Smo's boundaryInterface holds the same as a map and flags
/// over all 3 patch directions; model/gismo_xml.cpp converts.) The geometry decides where it
/// can: find_interfaces sets these from the coinciding control points, merge_control_points
/// uses the orientation in which they coincide best.
struct Interface {
  PatchSide a, b;
  bool reversed = false;
  std::array<int, 2> face_map{0, 1};
  std::array<bool, 2> face_flip{false, false};
};

/// The free (in-face) patch directions of face s of a trivariate patch, in increasing order.
std::array<int, 2> face_directions(Side s);
/// The position in face b's control point list (Patch::side_indices, first direction fastest)
/// of face a's control point (i0, i1) under f's orientation; nb: face b's counts per direction.
int face_mapped_index(const Interface& f, const std::array<int, 2>& nb, int i0, int i1);
/// 3-D: the face has no area (collapsed onto a curve or a point: along one of its directions
/// every line of control points lies within tol of its first), as the pole face of a sphere
/// octant; no boundary and no interface.
bool face_degenerate(const Patch& P, Side s, double tol);

/// Patches with their topology, as a geometry file holds them.
struct MultiPatch {
  std::vector<Patch> patches;
  std::vector<Interface> interfaces;                                  // declared (may be empty)
  std::vector<PatchSide> boundary;                                    // outer sides, if listed
  std::vector<std::pair<std::string, std::vector<PatchSide>>> named;  // named boundaries
};

/// The body's corner points of a patch (control points at the parametric corners, which
/// interpolate the geometry): south_west (xi min, eta min), south_east, north_west, north_east.
enum class Corner { SouthWest = 0, SouthEast = 1, NorthWest = 2, NorthEast = 3 };
const char* corner_name(Corner c);
bool parse_corner(const std::string& name, Corner& c);
int corner_index(const Patch& P, Corner c);   // the patch control point at the corner

/// Size of a set of patches: the diagonal of their control points' bounding box.
double patches_diameter(const std::vector<Patch>& patches);

/// The side's control points all lie within tol of its first: a side collapsed to a point
/// (a degenerate patch), which is no boundary and no interface. 3-D: face_degenerate (a face
/// collapsed onto a curve, too).
bool side_collapsed(const Patch& P, Side s, double tol);

/// Interfaces of patches found by coincident control points (within tol, forward or reversed)
/// along whole sides, any pair of distinct sides (the same patch's two sides close a ring).
/// Sides collapsed to a point are left out. 3-D: whole faces, in the first of the 8
/// orientations (face_map {0, 1} before {1, 0}, flips (no, no), (yes, no), (no, yes), (yes,
/// yes)) in which all control points coincide; degenerate faces left out.
std::vector<Interface> find_interfaces(const std::vector<Patch>& patches, double tol);
/// Sides whose end points meet another side's end points but whose control points do not
/// coincide (a non-conforming interface): "patch0.east and patch1.west ..." or "".
std::string find_nonconforming(const std::vector<Patch>& patches, const std::vector<Interface>& found, double tol);
/// Checks that an interface is conforming (same number of control points, coincident within
/// tol in its orientation); returns "" or what is wrong, naming both sides.
std::string check_interface(const std::vector<Patch>& patches, const Interface& f, double tol);
/// 2-D: whether the sides of interface f run opposite ways (their first control points apart);
/// the geometry decides the merge whatever f.reversed says.
bool geometric_reversal(const std::vector<Patch>& patches, const Interface& f);
/// The orientation f declares is the geometry's: 2-D, the sides run as f.reversed says; 3-D,
/// the faces' control points coincide within tol under f's face_map and face_flip.
bool declared_orientation_holds(const std::vector<Patch>& patches, const Interface& f, double tol);
/// Merges the control points of conforming interfaces: per patch, control point -> merged
/// index (numbered in patch order, first appearance); n: how many there are. 3-D: faces, in
/// the orientation (of those with matching counts) in which the control points lie closest,
/// f's own first. With tol >= 0 also the coinciding control points (within tol) of every
/// collapsed side or face (side_collapsed: a degenerate patch) are merged: one material point.
std::vector<std::vector<int>> merge_control_points(const std::vector<Patch>& patches,
                                                   const std::vector<Interface>& interfaces, int& n, double tol = -1);

/// A contact surface or loaded boundary made of several patch sides joined end to end (a
/// chain): one NURBS curve with a C0 joint (a p-fold knot) where two sides meet. A single
/// side keeps its own parameter; in a chain of several, piece k covers [k, k + 1].
struct SurfaceChain {
  struct Piece {
    PatchSide side;
    bool reversed = false;   // runs against its side's parameter
    double t0 = 0, t1 = 1;   // chain parameter range
    double a = 0, b = 1;     // the side's own parameter range
  };
  std::vector<Piece> pieces;
  Curve curve;                  // curve.patch_index: the control point in its patch
  std::vector<int> cp_patch;    // the patch of each curve control point
  int normal_sign = 1;          // outward normal n = normal_sign (t_y, -t_x) / |t|
  bool closed = false;
  /// Patch and parametric point (u, v) of chain parameter t.
  int locate(const std::vector<Patch>& patches, double t, double& u, double& v) const;
};
/// Orders and orients the sides head to tail (a joint: coincident end control points, within
/// tol). Throws InputError-free std::invalid_argument with what is wrong: sides that do not
/// form one chain, different degrees, or outward normals on opposite sides of the chain.
SurfaceChain make_chain(const std::vector<Patch>& patches, const std::vector<PatchSide>& sides, double tol);

}  // namespace iga
