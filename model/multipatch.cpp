#include "model/multipatch.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <stdexcept>

namespace iga {

std::string patch_side_name(const PatchSide& s) { return "patch" + std::to_string(s.patch) + "." + side_name(s.side); }

const char* corner_name(Corner c) {
  switch (c) {
    case Corner::SouthWest: return "south_west";
    case Corner::SouthEast: return "south_east";
    case Corner::NorthWest: return "north_west";
    case Corner::NorthEast: return "north_east";
  }
  return "?";
}

bool parse_corner(const std::string& name, Corner& c) {
  for (int k = 0; k < 4; ++k)
    if (name == corner_name(static_cast<Corner>(k))) {
      c = static_cast<Corner>(k);
      return true;
    }
  return false;
}

int corner_index(const Patch& P, Corner c) {
  const int k = static_cast<int>(c);
  return P.index(k % 2 == 0 ? 0 : P.ncp(0) - 1, k < 2 ? 0 : P.ncp(1) - 1);
}

double patches_diameter(const std::vector<Patch>& patches) {
  double lo[3] = {1e300, 1e300, 1e300}, hi[3] = {-1e300, -1e300, -1e300};
  for (const Patch& P : patches)
    for (const auto& c : P.cp)
      for (int d = 0; d < 3; ++d) lo[d] = std::min(lo[d], c.x[d]), hi[d] = std::max(hi[d], c.x[d]);
  // hypot(h, 0) = h exactly: 2-D (z = 0) gives the 2-D diagonal bit for bit
  return patches.empty() ? 0.0 : std::hypot(std::hypot(hi[0] - lo[0], hi[1] - lo[1]), hi[2] - lo[2]);
}

namespace {

// hypot(h, 0) = h exactly: in 2-D (z = 0) the plane distance bit for bit
double dist(const ControlPoint& a, const ControlPoint& b) {
  return std::hypot(std::hypot(a.x[0] - b.x[0], a.x[1] - b.x[1]), a.x[2] - b.x[2]);
}

std::vector<ControlPoint> side_points(const Patch& P, Side s) {
  std::vector<ControlPoint> v;
  for (int a : P.side_indices(s)) v.push_back(P.cp[a]);
  return v;
}

bool collapsed(const std::vector<ControlPoint>& v, double tol) {
  for (const auto& p : v)
    if (dist(p, v.front()) > tol) return false;
  return true;
}

// 0: no match, 1: coincident in the same direction, 2: reversed.
int coincide(const std::vector<ControlPoint>& a, const std::vector<ControlPoint>& b, double tol) {
  if (a.size() != b.size()) return 0;
  bool fwd = true, rev = true;
  for (size_t k = 0; k < a.size(); ++k) {
    fwd = fwd && dist(a[k], b[k]) <= tol;
    rev = rev && dist(a[k], b[b.size() - 1 - k]) <= tol;
  }
  return fwd ? 1 : rev ? 2 : 0;
}

// A side's knots mapped onto [0, 1], reversed if asked.
std::vector<double> unit_knots(const Patch& P, Side s, bool reversed) {
  const auto& U = P.knots[side_tangent_direction(s)];
  std::vector<double> v;
  const double a = U.front(), b = U.back();
  for (double u : U) v.push_back((u - a) / (b - a));
  if (reversed) {
    std::reverse(v.begin(), v.end());
    for (double& u : v) u = 1.0 - u;
  }
  return v;
}

std::string knots_text(const std::vector<double>& v) {
  std::string t = "[";
  for (size_t k = 0; k < v.size(); ++k) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.6g", v[k]);
    t += (k ? ", " : "") + std::string(buf);
  }
  return t + "]";
}

// "" when the two sides (coincident control points) carry the same basis: degree and knots.
std::string same_basis(const Patch& P, Side s, const Patch& Q, Side t, bool reversed, const std::string& names) {
  const int dp = P.degree[side_tangent_direction(s)], dq = Q.degree[side_tangent_direction(t)];
  const auto a = unit_knots(P, s, false), b = unit_knots(Q, t, reversed);
  bool same = dp == dq && a.size() == b.size();
  for (size_t k = 0; same && k < a.size(); ++k) same = std::abs(a[k] - b[k]) <= 1e-12;
  if (same) return "";
  return names + " meet along a curve with different " + (dp != dq ? "degrees (" + std::to_string(dp) + " and " + std::to_string(dq) + ")"
                                                                     : "knots (" + knots_text(a) + " and " + knots_text(b) + ")") +
         ": a non-conforming interface; give both sides the same knots and degree";
}

int base_normal_sign(const Patch& P, Side s) {
  return side_normal_sign(s) * P.orientation();
}

// ---- 3-D faces ----

// control point counts of face s along its two directions
std::array<int, 2> face_counts(const Patch& P, Side s) {
  const auto f = face_directions(s);
  return {P.ncp(f[0]), P.ncp(f[1])};
}

// The 8 relative orientations, in the order find_interfaces tries them.
std::array<Interface, 8> orientations(const PatchSide& a, const PatchSide& b) {
  std::array<Interface, 8> o;
  for (int k = 0; k < 8; ++k) {
    o[k].a = a;
    o[k].b = b;
    o[k].face_map = k < 4 ? std::array<int, 2>{0, 1} : std::array<int, 2>{1, 0};
    o[k].face_flip = {(k & 1) != 0, (k & 2) != 0};
  }
  return o;
}

bool counts_fit(const Interface& f, const std::array<int, 2>& na, const std::array<int, 2>& nb) {
  return nb[f.face_map[0]] == na[0] && nb[f.face_map[1]] == na[1] && f.face_map[0] != f.face_map[1];
}

// largest distance between face a's control points and their images on face b (counts fit);
// returns early once it exceeds stop
double face_gap(const std::vector<Patch>& patches, const Interface& f, double stop = 1e300) {
  const Patch &P = patches[f.a.patch], &Q = patches[f.b.patch];
  const auto ia = P.side_indices(f.a.side), ib = Q.side_indices(f.b.side);
  const auto na = face_counts(P, f.a.side), nb = face_counts(Q, f.b.side);
  double g = 0;
  for (int i1 = 0; i1 < na[1]; ++i1)
    for (int i0 = 0; i0 < na[0]; ++i0)
      if ((g = std::max(g, dist(P.cp[ia[i0 + na[0] * i1]], Q.cp[ib[face_mapped_index(f, nb, i0, i1)]]))) > stop) return g;
  return g;
}

// The orientation of faces a and b in which all control points coincide within tol (the
// first of the 8), or false.
bool match_faces(const std::vector<Patch>& patches, const PatchSide& a, const PatchSide& b, double tol, Interface& out) {
  const auto na = face_counts(patches[a.patch], a.side), nb = face_counts(patches[b.patch], b.side);
  for (const Interface& f : orientations(a, b))
    if (counts_fit(f, na, nb) && face_gap(patches, f, tol) <= tol) {
      out = f;
      return true;
    }
  return false;
}

// the 4 corners of face a coincide with those of face b in some orientation (counts aside)
bool corners_meet(const std::vector<Patch>& patches, const PatchSide& a, const PatchSide& b, double tol) {
  const Patch &P = patches[a.patch], &Q = patches[b.patch];
  const auto ia = P.side_indices(a.side), ib = Q.side_indices(b.side);
  const auto na = face_counts(P, a.side), nb = face_counts(Q, b.side);
  for (const Interface& f : orientations(a, b)) {
    bool all = true;
    for (int c = 0; c < 4 && all; ++c) {
      const int i0 = c % 2 ? na[0] - 1 : 0, i1 = c / 2 ? na[1] - 1 : 0;
      // the corner's image: the end of b's direction face_map[k] (counts may differ)
      int pb[2];
      const int ic[2] = {c % 2, c / 2};
      for (int k = 0; k < 2; ++k) pb[f.face_map[k]] = (ic[k] != 0) != f.face_flip[k] ? nb[f.face_map[k]] - 1 : 0;
      all = dist(P.cp[ia[i0 + na[0] * i1]], Q.cp[ib[pb[0] + nb[0] * pb[1]]]) <= tol;
    }
    if (all) return true;
  }
  return false;
}

std::array<double, kMaxDim> face_centre(const Patch& P, Side s) {
  const Patch F = P.face(s);
  const double t[2] = {0.5 * (F.knots[0].front() + F.knots[0].back()), 0.5 * (F.knots[1].front() + F.knots[1].back())};
  return F.point(t);
}

std::string counts_text(const std::array<int, 2>& n) { return std::to_string(n[0]) + " x " + std::to_string(n[1]); }

// "" when faces a and b (coincident control points, orientation f) carry the same basis
std::string same_face_basis(const std::vector<Patch>& patches, const Interface& f, const std::string& names) {
  const Patch &P = patches[f.a.patch], &Q = patches[f.b.patch];
  const auto da = face_directions(f.a.side), db = face_directions(f.b.side);
  for (int k = 0; k < 2; ++k) {
    const int d = da[k], e = db[f.face_map[k]];
    const int dp = P.degree[d], dq = Q.degree[e];
    auto unit = [](const std::vector<double>& U, bool rev) {
      std::vector<double> v;
      for (double u : U) v.push_back((u - U.front()) / (U.back() - U.front()));
      if (rev) {
        std::reverse(v.begin(), v.end());
        for (double& u : v) u = 1.0 - u;
      }
      return v;
    };
    const auto a = unit(P.knots[d], false), b = unit(Q.knots[e], f.face_flip[k]);
    bool same = dp == dq && a.size() == b.size();
    for (size_t m = 0; same && m < a.size(); ++m) same = std::abs(a[m] - b[m]) <= 1e-12;
    if (!same)
      return names + " meet along a face with different " +
             (dp != dq ? "degrees (" + std::to_string(dp) + " and " + std::to_string(dq) + ")"
                       : "knots (" + knots_text(a) + " and " + knots_text(b) + ")") +
             " in one direction: a non-conforming interface; give both faces the same knots and degrees";
  }
  return "";
}

bool is_3d_pair(const std::vector<Patch>& patches, const PatchSide& x, const PatchSide& y) {
  return patches[x.patch].dim() == 3 || patches[y.patch].dim() == 3;
}

}  // namespace

std::array<int, 2> face_directions(Side s) {
  const int d = side_direction(s);
  return d == 0 ? std::array<int, 2>{1, 2} : d == 1 ? std::array<int, 2>{0, 2} : std::array<int, 2>{0, 1};
}

int face_mapped_index(const Interface& f, const std::array<int, 2>& nb, int i0, int i1) {
  int pb[2];
  const int ia[2] = {i0, i1};
  for (int k = 0; k < 2; ++k) pb[f.face_map[k]] = f.face_flip[k] ? nb[f.face_map[k]] - 1 - ia[k] : ia[k];
  return pb[0] + nb[0] * pb[1];
}

bool face_degenerate(const Patch& P, Side s, double tol) {
  const auto idx = P.side_indices(s);
  const auto n = face_counts(P, s);
  for (int k = 0; k < 2; ++k) {
    bool all = true;   // every line along direction k collapsed to a point
    for (int l = 0; l < n[1 - k] && all; ++l)
      for (int m = 1; m < n[k] && all; ++m) {
        const int first = k == 0 ? n[0] * l : l, here = k == 0 ? m + n[0] * l : l + n[0] * m;
        all = dist(P.cp[idx[first]], P.cp[idx[here]]) <= tol;
      }
    if (all) return true;
  }
  return false;
}

bool side_collapsed(const Patch& P, Side s, double tol) {
  return P.dim() == 3 ? face_degenerate(P, s, tol) : collapsed(side_points(P, s), tol);
}

namespace {
// Calls f(x, y, a, b) for every pair of distinct sides x < y (the same patch's too) that are
// not collapsed to a point, with their control points a, b; stops when f returns true.
template <class F>
void for_each_side_pair(const std::vector<Patch>& patches, double tol, F f) {
  const int np = static_cast<int>(patches.size());
  for (int p = 0; p < np; ++p)
    for (int s = 0; s < num_sides(patches[p].dim()); ++s) {
      const auto a = side_points(patches[p], static_cast<Side>(s));
      if (collapsed(a, tol)) continue;
      for (int q = p; q < np; ++q)
        for (int t = (q == p ? s + 1 : 0); t < num_sides(patches[q].dim()); ++t)
          if (f(PatchSide{p, static_cast<Side>(s)}, PatchSide{q, static_cast<Side>(t)}, a, side_points(patches[q], static_cast<Side>(t))))
            return;
    }
}
}  // namespace

std::vector<Interface> find_interfaces(const std::vector<Patch>& patches, double tol) {
  std::vector<Interface> out;
  for_each_side_pair(patches, tol, [&](PatchSide x, PatchSide y, const std::vector<ControlPoint>& a, const std::vector<ControlPoint>& b) {
    if (is_3d_pair(patches, x, y)) {
      Interface f;
      if (patches[x.patch].dim() == 3 && patches[y.patch].dim() == 3 && !face_degenerate(patches[x.patch], x.side, tol) &&
          !face_degenerate(patches[y.patch], y.side, tol) && match_faces(patches, x, y, tol, f))
        out.push_back(f);
      return false;
    }
    const int m = coincide(a, b, tol);
    if (m) out.push_back({x, y, m == 2});
    return false;
  });
  return out;
}

std::string find_nonconforming(const std::vector<Patch>& patches, const std::vector<Interface>& found, double tol) {
  const int np = static_cast<int>(patches.size());
  for (const Interface& f : found) {
    if (f.a.patch < 0 || f.a.patch >= np || f.b.patch < 0 || f.b.patch >= np) continue;
    if (is_3d_pair(patches, f.a, f.b)) {
      Interface g;
      if (patches[f.a.patch].dim() != 3 || patches[f.b.patch].dim() != 3 || !match_faces(patches, f.a, f.b, tol, g)) continue;
      const std::string err = same_face_basis(patches, g, patch_side_name(f.a) + " and " + patch_side_name(f.b));
      if (!err.empty()) return err;
      continue;
    }
    const std::string err = same_basis(patches[f.a.patch], f.a.side, patches[f.b.patch], f.b.side,
                                       coincide(side_points(patches[f.a.patch], f.a.side), side_points(patches[f.b.patch], f.b.side), tol) == 2,
                                       patch_side_name(f.a) + " and " + patch_side_name(f.b));
    if (!err.empty()) return err;
  }
  auto is_interface = [&](PatchSide x, PatchSide y) {
    for (const Interface& f : found)
      if ((f.a == x && f.b == y) || (f.a == y && f.b == x)) return true;
    return false;
  };
  std::string msg;
  for_each_side_pair(patches, tol, [&](PatchSide x, PatchSide y, const std::vector<ControlPoint>& a, const std::vector<ControlPoint>& b) {
    if (is_interface(x, y)) return false;
    if (is_3d_pair(patches, x, y)) {
      const Patch &P = patches[x.patch], &Q = patches[y.patch];
      if (P.dim() != 3 || Q.dim() != 3 || face_degenerate(P, x.side, tol) || face_degenerate(Q, y.side, tol)) return false;
      if (!corners_meet(patches, x, y, tol)) return false;
      // the same corners: the same face with other control points, or another surface between
      // the same corners; compare the faces' centres
      const auto ma = face_centre(P, x.side), mb = face_centre(Q, y.side);
      if (std::hypot(std::hypot(ma[0] - mb[0], ma[1] - mb[1]), ma[2] - mb[2]) > 1e3 * tol) return false;
      msg = patch_side_name(x) + " and " + patch_side_name(y) + " meet along a face with different control points (" +
            counts_text(face_counts(P, x.side)) + " and " + counts_text(face_counts(Q, y.side)) +
            "): a non-conforming interface; give both faces the same knots and degrees";
      return true;
    }
    const bool ends = (dist(a.front(), b.front()) <= tol && dist(a.back(), b.back()) <= tol) ||
                      (dist(a.front(), b.back()) <= tol && dist(a.back(), b.front()) <= tol);
    if (!ends) return false;
    // the same end points: the same curve with other control points, or a different curve
    // between the same two corners (a lens); compare mid-parameter points
    const Curve ca = patches[x.patch].side_curve(x.side), cb = patches[y.patch].side_curve(y.side);
    const auto ma = ca.eval(0.5 * (ca.knots.front() + ca.knots.back()));
    const auto mb = cb.eval(0.5 * (cb.knots.front() + cb.knots.back()));
    if (std::hypot(ma[0] - mb[0], ma[1] - mb[1]) > 1e3 * tol) return false;
    msg = patch_side_name(x) + " and " + patch_side_name(y) + " meet along a curve with different control points (" +
          std::to_string(a.size()) + " and " + std::to_string(b.size()) +
          "): a non-conforming interface; give both sides the same knots and degree";
    return true;
  });
  return msg;
}

std::string check_interface(const std::vector<Patch>& patches, const Interface& f, double tol) {
  const int np = static_cast<int>(patches.size());
  const std::string names = patch_side_name(f.a) + " and " + patch_side_name(f.b);
  if (f.a.patch < 0 || f.a.patch >= np || f.b.patch < 0 || f.b.patch >= np)
    return "interface " + names + " names a patch that does not exist (" + std::to_string(np) + " patches)";
  if (is_3d_pair(patches, f.a, f.b)) {
    const Patch &P = patches[f.a.patch], &Q = patches[f.b.patch];
    if (P.dim() != Q.dim()) return "interface " + names + " joins a 2-D and a 3-D patch";
    for (const PatchSide& s : {f.a, f.b})
      if (static_cast<int>(s.side) >= num_sides(3)) return "interface " + names + " names a side that does not exist";
    const auto na = face_counts(P, f.a.side), nb = face_counts(Q, f.b.side);
    bool fits = false;
    for (const Interface& g : orientations(f.a, f.b)) fits = fits || counts_fit(g, na, nb);
    if (!fits)
      return "interface " + names + " is not conforming: " + counts_text(na) + " and " + counts_text(nb) +
             " control points on its faces (refine both patches alike along the interface)";
    // coincident in some orientation (a wrong orientation in a file is harmless: the geometry decides)
    Interface g;
    if (!match_faces(patches, f.a, f.b, tol, g)) return "interface " + names + " is not conforming: the control points on it do not coincide";
    return "";
  }
  const auto a = side_points(patches[f.a.patch], f.a.side), b = side_points(patches[f.b.patch], f.b.side);
  if (a.size() != b.size())
    return "interface " + names + " is not conforming: " + std::to_string(a.size()) + " and " + std::to_string(b.size()) +
           " control points along it (refine both patches alike along the interface)";
  // coincident in either direction (a wrong orientation flag is harmless: the geometry decides)
  if (coincide(a, b, tol) == 0) return "interface " + names + " is not conforming: the control points along it do not coincide";
  return "";
}

bool declared_orientation_holds(const std::vector<Patch>& patches, const Interface& f, double tol) {
  if (!is_3d_pair(patches, f.a, f.b)) return geometric_reversal(patches, f) == f.reversed;
  const auto na = face_counts(patches[f.a.patch], f.a.side), nb = face_counts(patches[f.b.patch], f.b.side);
  return counts_fit(f, na, nb) && face_gap(patches, f, tol) <= tol;
}

bool geometric_reversal(const std::vector<Patch>& patches, const Interface& f) {
  const auto ia = patches[f.a.patch].side_indices(f.a.side), ib = patches[f.b.patch].side_indices(f.b.side);
  return dist(patches[f.a.patch].cp[ia.front()], patches[f.b.patch].cp[ib.front()]) >
         dist(patches[f.a.patch].cp[ia.front()], patches[f.b.patch].cp[ib.back()]);
}

std::vector<std::vector<int>> merge_control_points(const std::vector<Patch>& patches,
                                                   const std::vector<Interface>& interfaces, int& n, double tol) {
  std::vector<size_t> offset(patches.size() + 1, 0);
  for (size_t p = 0; p < patches.size(); ++p) offset[p + 1] = offset[p] + patches[p].cp.size();
  std::vector<size_t> parent(offset.back());
  std::iota(parent.begin(), parent.end(), size_t{0});
  auto find = [&](size_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  for (const Interface& f : interfaces) {
    const auto ia = patches[f.a.patch].side_indices(f.a.side), ib = patches[f.b.patch].side_indices(f.b.side);
    if (is_3d_pair(patches, f.a, f.b)) {
      // faces: the orientation with matching counts in which the control points lie closest
      // (f's own first: ties keep it)
      const auto na = face_counts(patches[f.a.patch], f.a.side), nb = face_counts(patches[f.b.patch], f.b.side);
      Interface best;
      double gap = 1e300;
      std::array<Interface, 9> cand;
      cand[0] = f;
      const auto o = orientations(f.a, f.b);
      std::copy(o.begin(), o.end(), cand.begin() + 1);
      for (const Interface& g : cand)
        if (counts_fit(g, na, nb)) {
          const double d = face_gap(patches, g);
          if (d < gap) gap = d, best = g;
        }
      if (gap == 1e300) continue;   // not conforming (check_interface says so)
      for (int i1 = 0; i1 < na[1]; ++i1)
        for (int i0 = 0; i0 < na[0]; ++i0) {
          const size_t x = find(offset[f.a.patch] + ia[i0 + na[0] * i1]), y = find(offset[f.b.patch] + ib[face_mapped_index(best, nb, i0, i1)]);
          if (x != y) parent[std::max(x, y)] = std::min(x, y);
        }
      continue;
    }
    // the geometry decides the direction (a wrong flag in a file is harmless; the loader warns)
    const bool rev = geometric_reversal(patches, f);
    for (size_t k = 0; k < ia.size() && k < ib.size(); ++k) {
      const size_t x = find(offset[f.a.patch] + ia[k]), y = find(offset[f.b.patch] + ib[rev ? ib.size() - 1 - k : k]);
      if (x != y) parent[std::max(x, y)] = std::min(x, y);   // the root: the first appearance
    }
  }
  // a side collapsed to a point, or a face collapsed onto a curve or a point (a degenerate
  // patch: a sphere's pole): its coinciding control points are one material point, one set of
  // dofs (else they could move apart and open or fold the collapsed side)
  if (tol >= 0)
    for (size_t p = 0; p < patches.size(); ++p)
      for (int sd = 0; sd < num_sides(patches[p].dim()); ++sd) {
        if (!side_collapsed(patches[p], static_cast<Side>(sd), tol)) continue;
        const auto idx = patches[p].side_indices(static_cast<Side>(sd));
        for (size_t i = 0; i < idx.size(); ++i)
          for (size_t j = i + 1; j < idx.size(); ++j)
            if (dist(patches[p].cp[idx[i]], patches[p].cp[idx[j]]) <= tol) {
              const size_t x = find(offset[p] + idx[i]), y = find(offset[p] + idx[j]);
              if (x != y) parent[std::max(x, y)] = std::min(x, y);
            }
      }
  std::vector<int> number(parent.size(), -1);
  std::vector<std::vector<int>> out(patches.size());
  n = 0;
  for (size_t p = 0; p < patches.size(); ++p)
    for (size_t a = 0; a < patches[p].cp.size(); ++a) {
      const size_t r = find(offset[p] + a);
      if (number[r] < 0) number[r] = n++;
      out[p].push_back(number[r]);
    }
  return out;
}

int SurfaceChain::locate(const std::vector<Patch>& patches, double t, double& u, double& v) const {
  size_t k = 0;
  while (k + 1 < pieces.size() && t > pieces[k].t1) ++k;
  const Piece& pc = pieces[k];
  const double f = std::clamp((t - pc.t0) / (pc.t1 - pc.t0), 0.0, 1.0);
  const double s = pc.reversed ? pc.b - f * (pc.b - pc.a) : pc.a + f * (pc.b - pc.a);
  const Patch& P = patches[pc.side.patch];
  // the fixed direction at its first or last knot, the free one at s
  double uv[2];
  const int d = side_direction(pc.side.side);
  uv[d] = side_end(pc.side.side) == 1 ? P.knots[d].back() : P.knots[d].front();
  uv[1 - d] = s;
  u = uv[0];
  v = uv[1];
  return pc.side.patch;
}

SurfaceChain make_chain(const std::vector<Patch>& patches, const std::vector<PatchSide>& sides, double tol) {
  if (sides.empty()) throw std::invalid_argument("no sides given");
  for (const PatchSide& s : sides)
    if (s.patch < 0 || s.patch >= static_cast<int>(patches.size()))
      throw std::invalid_argument(patch_side_name(s) + ": the body has " + std::to_string(patches.size()) + " patches");
  for (size_t i = 0; i < sides.size(); ++i)
    for (size_t j = i + 1; j < sides.size(); ++j)
      if (sides[i] == sides[j]) throw std::invalid_argument(patch_side_name(sides[i]) + " is listed twice");
  SurfaceChain ch;
  std::vector<Curve> cv;
  for (const PatchSide& s : sides) cv.push_back(patches[s.patch].side_curve(s.side));
  const int p = cv[0].degree;
  for (size_t i = 0; i < sides.size(); ++i)
    if (cv[i].degree != p)
      throw std::invalid_argument(patch_side_name(sides[i]) + " has degree " + std::to_string(cv[i].degree) + " and " +
                                  patch_side_name(sides[0]) + " degree " + std::to_string(p) +
                                  ": the sides of a chain need the same degree");
  const size_t n = sides.size();
  // order head to tail: start from a side whose start or end meets no other side (an open
  // chain's end), else (closed) from the first listed
  auto meets = [&](const ControlPoint& x, size_t self) {
    for (size_t j = 0; j < n; ++j)
      if (j != self && (dist(x, cv[j].cp.front()) <= tol || dist(x, cv[j].cp.back()) <= tol)) return true;
    return false;
  };
  size_t first = 0;
  bool first_rev = false;
  for (size_t i = 0; i < n && n > 1; ++i) {
    if (!meets(cv[i].cp.front(), i)) { first = i; first_rev = false; break; }
    if (!meets(cv[i].cp.back(), i)) { first = i; first_rev = true; break; }
  }
  std::vector<bool> used(n, false);
  std::vector<std::pair<size_t, bool>> order{{first, first_rev}};
  used[first] = true;
  for (size_t k = 1; k < n; ++k) {
    const auto& [last, lrev] = order.back();
    const ControlPoint end = lrev ? cv[last].cp.front() : cv[last].cp.back();
    bool found = false;
    for (size_t j = 0; j < n && !found; ++j) {
      if (used[j]) continue;
      if (dist(end, cv[j].cp.front()) <= tol) order.push_back({j, false}), found = true;
      else if (dist(end, cv[j].cp.back()) <= tol) order.push_back({j, true}), found = true;
      if (found) used[j] = true;
    }
    if (!found) {
      std::string rest;
      for (size_t j = 0; j < n; ++j)
        if (!used[j]) rest += (rest.empty() ? "" : ", ") + patch_side_name(sides[j]);
      throw std::invalid_argument("the sides do not join end to end into one chain (" + rest + " left over after " +
                                  patch_side_name(sides[last]) + ")");
    }
  }
  // one piece keeps its own parameter and direction
  const bool single = n == 1;
  if (single) order[0].second = false;
  Curve& c = ch.curve;
  c.degree = p;
  double scale = 1.0;
  for (size_t k = 0; k < n; ++k) {
    const auto [i, rev] = order[k];
    Curve pc = cv[i];
    std::vector<int> pidx = pc.patch_index;
    const double a = pc.knots.front(), b = pc.knots.back();
    if (rev) {
      std::reverse(pc.cp.begin(), pc.cp.end());
      std::reverse(pidx.begin(), pidx.end());
      std::vector<double> U(pc.knots.size());
      for (size_t m = 0; m < U.size(); ++m) U[m] = a + b - pc.knots[pc.knots.size() - 1 - m];
      pc.knots = U;
    }
    SurfaceChain::Piece piece;
    piece.side = sides[i];
    piece.reversed = rev;
    piece.a = a;
    piece.b = b;
    piece.t0 = single ? a : static_cast<double>(k);
    piece.t1 = single ? b : static_cast<double>(k + 1);
    const int sign = base_normal_sign(patches[sides[i].patch], sides[i].side) * (rev ? -1 : 1);
    if (k == 0) ch.normal_sign = sign;
    else if (sign != ch.normal_sign)
      throw std::invalid_argument(patch_side_name(sides[i]) + " faces the other way from " + patch_side_name(sides[order[0].first]) +
                                  " along the chain: its body lies on the other side (not one boundary curve)");
    // knots mapped onto [t0, t1]; a joint: the end knot p times (C0)
    auto map = [&](double u) { return single ? u : piece.t0 + (u - a) / (b - a); };
    const size_t nk = pc.knots.size();
    for (size_t m = (k == 0 ? 0 : static_cast<size_t>(p) + 1); m < nk - (k + 1 == n ? 0 : 1); ++m) c.knots.push_back(map(pc.knots[m]));
    // weights: a piece's rational basis is unchanged by scaling all its weights; scale so
    // the joint's weight matches the previous piece's
    if (k > 0) scale = c.cp.back().w / pc.cp.front().w;
    for (size_t m = (k == 0 ? 0 : 1); m < pc.cp.size(); ++m) {
      ControlPoint q = pc.cp[m];
      q.w *= scale;
      c.cp.push_back(q);
      c.patch_index.push_back(pidx[m]);
      ch.cp_patch.push_back(sides[i].patch);
    }
    ch.pieces.push_back(piece);
  }
  ch.closed = n > 1 && dist(c.cp.front(), c.cp.back()) <= tol;
  return ch;
}

}  // namespace iga
