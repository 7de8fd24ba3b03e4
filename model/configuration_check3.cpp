// find_penetration for solids (3-D): points of every body's outer faces inside another body,
// or inside their own body far (in the reference configuration) from where they belong,
// deeper than the contact pairs between those bodies allow. The 2-D check
// (configuration_check.cpp) works on boundary polylines; this one on the faces' Bezier
// elements, in the same three steps:
//  1) Candidates: every outer face element's deformed bounding box (the box of its rational
//     Bezier points: the element lies in their convex hull) binned; two face
//     elements of two bodies whose boxes overlap, or of one body whose boxes overlap and that
//     lie more than 4 steps apart along its boundary (face elements sharing a corner are one
//     step), are tested further. A locally
//     injective map whose boundary does not meet itself does not overlap itself, and two
//     bodies whose boundaries do not meet do not overlap unless one lies wholly inside the
//     other: for that, one face element of each body is tested against every body it does
//     not meet.
//  2) A point x of such a face element (4 x 4 per element, its edges included) is inside
//     body b when Newton on x_Q(xi) = x, from the centre of an element of b whose deformed
//     box holds x, converges inside that element to |x_Q(xi) - x| <= 1e-10 L (L the largest
//     body's size); in its own body the preimage must not be x's own reference point.
//  3) Its depth: the distance from x to b's deformed outer faces (the closest point on the
//     face elements of the nearest samples, by Gauss-Newton in the face's parameters; in its
//     own body leaving out the faces within 4 element sizes of x's reference point).
// Allowed depth: 3 x the largest penetration the pairs between the two bodies report, and at
// least 1 % of x's face element, as in 2-D, or 5 % of the larger of x's face element and the
// one it is nearest to where a contact pair joins the two bodies (the pairs hold the slave's
// points out of the master, not the master's edges out of the slave: in the 3-D ironing the
// slab's top edge cut 3 x the penalty penetration into the die, which overhangs it, between
// the die's quadrature points). The deepest finding is
// reported.
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <sstream>

#include "kernels/nurbs_basis.hpp"
#include "model/bezier.hpp"
#include "model/configuration_check.hpp"
#include "model/multipatch.hpp"

namespace iga {

namespace {

using V3 = std::array<double, 3>;

double dist3(const V3& a, const V3& b) { return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2])); }

std::string point3(const V3& x) { return "(" + check_number(x[0]) + ", " + check_number(x[1]) + ", " + check_number(x[2]) + ")"; }

struct Box {
  V3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
  void add(const V3& x) {
    for (int d = 0; d < 3; ++d) { lo[d] = std::min(lo[d], x[d]); hi[d] = std::max(hi[d], x[d]); }
  }
  bool holds(const V3& x, double tol) const {
    for (int d = 0; d < 3; ++d)
      if (x[d] < lo[d] - tol || x[d] > hi[d] + tol) return false;
    return true;
  }
  bool meets(const Box& o, double tol) const {
    for (int d = 0; d < 3; ++d)
      if (hi[d] + tol < o.lo[d] || o.hi[d] + tol < lo[d]) return false;
    return true;
  }
  double gap(const Box& o) const {   // distance between two boxes (0 when they meet)
    double s = 0;
    for (int d = 0; d < 3; ++d) {
      const double g = std::max({0.0, lo[d] - o.hi[d], o.lo[d] - hi[d]});
      s += g * g;
    }
    return std::sqrt(s);
  }
  double size() const { return std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2], 0.0}); }
};

// A patch's point and its derivatives dx/dt_d (d < pdim) at t, t inside the knot vectors.
V3 point_jacobian(const Patch& P, const double* t, double J[3][3]) {
  double N[3][3][kMaxBasis1D];
  int s[3] = {0, 0, 0}, m[3] = {1, 1, 1};
  const int pd = P.dim();
  for (int d = 0; d < pd; ++d) {
    s[d] = find_span(P.ncp(d), P.degree[d], t[d], P.knots[d].data());
    bspline_ders(s[d], t[d], P.degree[d], P.knots[d].data(), 1, N[d]);
    m[d] = P.degree[d] + 1;
  }
  for (int d = pd; d < 3; ++d) { N[d][0][0] = 1.0; N[d][1][0] = 0.0; }
  double A[4] = {0, 0, 0, 0}, dA[3][4] = {};
  for (int k = 0; k < m[2]; ++k)
    for (int j = 0; j < m[1]; ++j)
      for (int i = 0; i < m[0]; ++i) {
        const ControlPoint& q = P.cp[P.index(s[0] - (m[0] - 1) + i, s[1] - (m[1] - 1) + j, s[2] - (m[2] - 1) + k)];
        const double b = N[0][0][i] * N[1][0][j] * N[2][0][k] * q.w;
        const double db[3] = {N[0][1][i] * N[1][0][j] * N[2][0][k] * q.w, N[0][0][i] * N[1][1][j] * N[2][0][k] * q.w,
                              N[0][0][i] * N[1][0][j] * N[2][1][k] * q.w};
        for (int c = 0; c < 3; ++c) A[c] += b * q.x[c];
        A[3] += b;
        for (int d = 0; d < 3; ++d) {
          for (int c = 0; c < 3; ++c) dA[d][c] += db[d] * q.x[c];
          dA[d][3] += db[d];
        }
      }
  V3 x{A[0] / A[3], A[1] / A[3], A[2] / A[3]};
  for (int d = 0; d < 3; ++d)
    for (int c = 0; c < 3; ++c) J[c][d] = (dA[d][c] - x[c] * dA[d][3]) / A[3];
  return x;
}

// The parametric box of one element and the box of its deformed control points.
struct Element {
  int patch = 0;
  double t0[3] = {0, 0, 0}, t1[3] = {0, 0, 0};
  Box box;
};

// The elements (pdim = 3: volume elements; pdim = 2: face elements) of a patch with the boxes
// of their rational Bezier points in `cur` (tight: a rational Bezier element with positive
// weights lies in their convex hull; the B-spline control points around an element would
// span its neighbours too).
void patch_elements(const Patch& cur, int patch, std::vector<Element>& out) {
  const BezierPatch bz(cur);
  std::vector<ControlPoint> q(static_cast<size_t>(bz.points_per_element()));
  for (int e = 0; e < bz.num_elements(); ++e) {
    Element el;
    el.patch = patch;
    for (int d = 0; d < cur.dim(); ++d) {
      const auto r = bz.range(e, d);
      el.t0[d] = r[0];
      el.t1[d] = r[1];
    }
    bz.element_points(e, q.data());
    for (const ControlPoint& c : q) el.box.add({c.x[0], c.x[1], c.x[2]});
    out.push_back(el);
  }
}

// Uniform bins over boxes: each box in every cell it overlaps.
struct Bins {
  Box all;
  double cell = 1;
  int n[3] = {1, 1, 1};
  std::vector<std::vector<int>> bins;
  void build(const std::vector<Box>& boxes, double min_cell = 0) {
    all = Box();
    double mean = 0;
    for (const Box& b : boxes) {
      all.add(b.lo);
      all.add(b.hi);
      mean += b.size();
    }
    if (boxes.empty()) return;
    mean /= static_cast<double>(boxes.size());
    const double ext = std::max(all.size(), 1e-300);
    cell = std::max({mean, min_cell, ext / 256, 1e-300});
    // at most about 8 bins a box (boxes on a surface fill few of a volume's cells)
    for (;;) {
      for (int d = 0; d < 3; ++d) n[d] = std::max(1, static_cast<int>(std::ceil((all.hi[d] - all.lo[d]) / cell)));
      if (static_cast<double>(n[0]) * n[1] * n[2] <= 8.0 * static_cast<double>(boxes.size()) + 512) break;
      cell *= 1.25;
    }
    bins.assign(static_cast<size_t>(n[0]) * n[1] * n[2], {});
    for (size_t k = 0; k < boxes.size(); ++k) {
      int a[3], z[3];
      range(boxes[k], 0.0, a, z);
      for (int i2 = a[2]; i2 <= z[2]; ++i2)
        for (int i1 = a[1]; i1 <= z[1]; ++i1)
          for (int i0 = a[0]; i0 <= z[0]; ++i0) bins[index(i0, i1, i2)].push_back(static_cast<int>(k));
    }
  }
  int c(double x, int d) const { return std::clamp(static_cast<int>(std::floor((x - all.lo[d]) / cell)), 0, n[d] - 1); }
  size_t index(int i0, int i1, int i2) const { return static_cast<size_t>(i0) + static_cast<size_t>(n[0]) * (i1 + static_cast<size_t>(n[1]) * i2); }
  void range(const Box& b, double tol, int* a, int* z) const {
    for (int d = 0; d < 3; ++d) { a[d] = c(b.lo[d] - tol, d); z[d] = c(b.hi[d] + tol, d); }
  }
  const std::vector<int>& at(const V3& x) const { return bins[index(c(x[0], 0), c(x[1], 1), c(x[2], 2))]; }
};

// Newton on x_P(t) = x inside the parametric box [t0, t1] from its centre; true with t when it
// converges to within tol.
bool invert(const Patch& P, const double* t0, const double* t1, const V3& x, double* t, double tol) {
  const int pd = P.dim();
  for (int d = 0; d < pd; ++d) t[d] = 0.5 * (t0[d] + t1[d]);
  double rn_prev = 1e300;
  bool clamped = false;
  for (int it = 0; it < 30; ++it) {
    double J[3][3];
    const V3 p = point_jacobian(P, t, J);
    const double r[3] = {p[0] - x[0], p[1] - x[1], p[2] - x[2]};
    const double rn = std::sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
    if (rn <= tol) return true;
    // a volume: held on the element's boundary without converging: x lies outside it
    if (pd == 3 && it >= 3 && clamped && rn > 0.5 * rn_prev) return false;
    rn_prev = rn;
    double dt[3] = {0, 0, 0};
    if (pd == 3) {   // J dt = -r
      const double det = J[0][0] * (J[1][1] * J[2][2] - J[1][2] * J[2][1]) - J[0][1] * (J[1][0] * J[2][2] - J[1][2] * J[2][0]) +
                         J[0][2] * (J[1][0] * J[2][1] - J[1][1] * J[2][0]);
      if (!(std::abs(det) > 0)) return false;
      for (int d = 0; d < 3; ++d) {
        double M[3][3];
        for (int a = 0; a < 3; ++a)
          for (int b = 0; b < 3; ++b) M[a][b] = b == d ? -r[a] : J[a][b];
        dt[d] = (M[0][0] * (M[1][1] * M[2][2] - M[1][2] * M[2][1]) - M[0][1] * (M[1][0] * M[2][2] - M[1][2] * M[2][0]) +
                 M[0][2] * (M[1][0] * M[2][1] - M[1][1] * M[2][0])) / det;
      }
    } else {   // a face: Gauss-Newton, the closest point (callers compare the distance)
      double G[2][2] = {{0, 0}, {0, 0}}, g[2] = {0, 0};
      for (int a = 0; a < 2; ++a) {
        for (int c = 0; c < 3; ++c) g[a] -= J[c][a] * r[c];
        for (int b = 0; b < 2; ++b)
          for (int c = 0; c < 3; ++c) G[a][b] += J[c][a] * J[c][b];
      }
      const double det = G[0][0] * G[1][1] - G[0][1] * G[1][0];
      if (!(std::abs(det) > 0)) return false;
      dt[0] = (G[1][1] * g[0] - G[0][1] * g[1]) / det;
      dt[1] = (G[0][0] * g[1] - G[1][0] * g[0]) / det;
    }
    bool moved = false;
    clamped = false;
    for (int d = 0; d < pd; ++d) {
      const double w = t1[d] - t0[d];
      const double tu = t[d] + std::clamp(dt[d], -0.5 * w, 0.5 * w);
      const double tn = std::clamp(tu, t0[d], t1[d]);
      clamped = clamped || tn != tu;
      moved = moved || std::abs(tn - t[d]) > 1e-14 * std::max(1.0, std::abs(t[d]));
      t[d] = tn;
    }
    if (!moved) return pd == 2;   // a face: the clamped closest point; a volume: x is outside this element
  }
  return pd == 2;
}

// A face element of a body's outer faces: its face (patch and side), its face patch in the
// reference and deformed configurations, its boxes and samples.
struct FaceElement {
  int body = 0, face = 0;   // face: index into Faces::sides / cur / ref of its body
  double t0[2] = {0, 0}, t1[2] = {0, 0};
  Box box;            // its deformed rational Bezier points' box
  double h = 0;       // the longest reference distance between two of its corners
  int first = 0, count = 0;   // its samples
  std::array<V3, 4> corner;   // reference corners
  V3 centre{}, n{};           // deformed: the centre and the outward unit normal there
};

// Face elements next to each other on a body's boundary: those that share a corner (the
// reference corners, to within q), and the elements within `rings` such steps of one.
struct Adjacency {
  std::vector<std::vector<int>> next;
  std::vector<int> mark;
  int stamp = 0;
  void build(const std::vector<FaceElement>& fe, double q) {
    std::map<std::array<long long, 3>, std::vector<int>> at;
    auto key = [q](const V3& x) {
      return std::array<long long, 3>{std::llround(x[0] / q), std::llround(x[1] / q), std::llround(x[2] / q)};
    };
    for (size_t e = 0; e < fe.size(); ++e)
      for (const V3& c : fe[e].corner) at[key(c)].push_back(static_cast<int>(e));
    next.assign(fe.size(), {});
    for (size_t e = 0; e < fe.size(); ++e) {
      for (const V3& c : fe[e].corner) {
        const auto k = key(c);
        for (long long i = -1; i <= 1; ++i)
          for (long long j = -1; j <= 1; ++j)
            for (long long l = -1; l <= 1; ++l) {
              const auto it = at.find({k[0] + i, k[1] + j, k[2] + l});
              if (it == at.end()) continue;
              for (const int f : it->second)
                if (f != static_cast<int>(e) && fe[static_cast<size_t>(f)].body == fe[e].body) next[e].push_back(f);
            }
      }
      std::sort(next[e].begin(), next[e].end());
      next[e].erase(std::unique(next[e].begin(), next[e].end()), next[e].end());
    }
    mark.assign(fe.size(), 0);
  }
  // marks (mark[f] == stamp) the elements within `rings` steps of e, e included
  void around(int e, int rings) {
    ++stamp;
    std::vector<int> front{e}, grown;
    mark[static_cast<size_t>(e)] = stamp;
    for (int r = 0; r < rings && !front.empty(); ++r) {
      grown.clear();
      for (const int f : front)
        for (const int g : next[static_cast<size_t>(f)])
          if (mark[static_cast<size_t>(g)] != stamp) {
            mark[static_cast<size_t>(g)] = stamp;
            grown.push_back(g);
          }
      std::swap(front, grown);
    }
  }
  bool marked(int f) const { return mark[static_cast<size_t>(f)] == stamp; }
};

struct Faces {
  std::vector<PatchSide> sides;
  std::vector<Patch> ref, cur;
};

}  // namespace

std::string find_penetration3(const Problem& P, const std::vector<std::vector<double>>& u,
                              const std::vector<double>& pair_penetration) {
  const int nb = static_cast<int>(P.bodies.size());
  constexpr int kPer = 3;            // samples a direction per face element: kPer + 1, its edges included
  constexpr int kNear = 4;           // self: the face elements within 4 steps along the boundary are the point's own
  constexpr double kFloor = 0.01;    // allowed depth at least 1 % of the face element,
  constexpr double kPairFloor = 0.05;   // 5 % between bodies with a contact pair (a master edge between slave points)
  constexpr int kNearest = 4;        // depth: the face elements of the nearest samples refined
  double L = 0;
  std::vector<MultiPatch> deformed;
  std::vector<Faces> faces(static_cast<size_t>(nb));
  std::vector<FaceElement> fe;
  std::vector<V3> sx, sX;   // samples: deformed and reference points
  std::vector<int> s_elem;  // the face element of each sample
  for (int b = 0; b < nb; ++b) {
    const Body& B = P.bodies[b];
    L = std::max(L, patches_diameter(B.patches));
    deformed.push_back(body_geometry(B, &u[b]));
    for (const PatchSide& ps : outer_sides(B)) {
      const size_t k = static_cast<size_t>(ps.patch);
      Faces& F = faces[static_cast<size_t>(b)];
      const int f = static_cast<int>(F.sides.size());
      F.sides.push_back(ps);
      F.ref.push_back(B.patches[k].face(ps.side));
      F.cur.push_back(deformed.back().patches[k].face(ps.side));
      const double sign = side_normal_sign(ps.side) * B.patches[k].orientation();   // outward normals
      std::vector<Element> cur_el;
      patch_elements(F.cur.back(), f, cur_el);
      for (size_t e = 0; e < cur_el.size(); ++e) {
        FaceElement x;
        x.body = b;
        x.face = f;
        for (int d = 0; d < 2; ++d) { x.t0[d] = cur_el[e].t0[d]; x.t1[d] = cur_el[e].t1[d]; }
        x.box = cur_el[e].box;
        x.first = static_cast<int>(sx.size());
        for (int j = 0; j <= kPer; ++j)
          for (int i = 0; i <= kPer; ++i) {
            const double t[2] = {x.t0[0] + (x.t1[0] - x.t0[0]) * i / kPer, x.t0[1] + (x.t1[1] - x.t0[1]) * j / kPer};
            sx.push_back(F.cur.back().point(t));
            sX.push_back(F.ref.back().point(t));
            s_elem.push_back(static_cast<int>(fe.size()));
            if ((i == 0 || i == kPer) && (j == 0 || j == kPer)) x.corner[(i ? 1 : 0) + (j ? 2 : 0)] = sX.back();
          }
        x.count = static_cast<int>(sx.size()) - x.first;
        {
          const double t[3] = {0.5 * (x.t0[0] + x.t1[0]), 0.5 * (x.t0[1] + x.t1[1]), 0.0};
          double J[3][3];
          x.centre = point_jacobian(F.cur.back(), t, J);
          V3 n{J[1][0] * J[2][1] - J[2][0] * J[1][1], J[2][0] * J[0][1] - J[0][0] * J[2][1], J[0][0] * J[1][1] - J[1][0] * J[0][1]};
          const double l = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
          if (l > 0)
            for (int c = 0; c < 3; ++c) x.n[c] = sign * n[c] / l;
        }
        for (int a = 0; a < 4; ++a)
          for (int c = a + 1; c < 4; ++c) x.h = std::max(x.h, dist3(x.corner[a], x.corner[c]));
        fe.push_back(x);
      }
    }
  }
  if (fe.empty()) return "";
  std::vector<double> allowed;   // 3 x the penetration of the pairs between two bodies
  std::vector<bool> declared;
  pair_allowances(P, pair_penetration, allowed, declared);
  const double tol_x = 1e-10 * L;
  // 1) candidates: per face element, the bodies its points are tested against
  std::vector<Box> boxes;
  for (const FaceElement& x : fe) boxes.push_back(x.box);
  Bins fbins;
  fbins.build(boxes);
  Adjacency adj;
  adj.build(fe, 1e-9 * L);
  std::vector<std::vector<char>> test(fe.size(), std::vector<char>(static_cast<size_t>(nb), 0));
  bool any = false;
  for (const auto& bin : fbins.bins)
    for (size_t p = 0; p < bin.size(); ++p) {
      bool around = false;   // adj marks bin[p]'s neighbours
      for (size_t q = p + 1; q < bin.size(); ++q) {
        const FaceElement& A = fe[static_cast<size_t>(bin[p])];
        const FaceElement& B = fe[static_cast<size_t>(bin[q])];
        if (!A.box.meets(B.box, tol_x)) continue;
        if (A.body == B.body) {   // one body: not neighbours along its boundary
          if (!around) adj.around(bin[p], kNear);
          around = true;
          if (adj.marked(bin[q])) continue;
        }
        test[static_cast<size_t>(bin[p])][static_cast<size_t>(B.body)] = 1;
        test[static_cast<size_t>(bin[q])][static_cast<size_t>(A.body)] = 1;
        any = true;
      }
    }
  // a body wholly inside another (no faces meet): one face element of each body tested
  // against every other body it does not meet
  for (int a = 0; a < nb; ++a) {
    const auto first = std::find_if(fe.begin(), fe.end(), [a](const FaceElement& x) { return x.body == a; });
    if (first == fe.end()) continue;
    for (int b = 0; b < nb; ++b) {
      if (b == a) continue;
      bool meets = false;
      for (size_t e = 0; e < fe.size() && !meets; ++e) meets = fe[e].body == a && test[e][static_cast<size_t>(b)];
      if (!meets) {
        test[static_cast<size_t>(first - fe.begin())][static_cast<size_t>(b)] = 1;
        any = true;
      }
    }
  }
  if (!any) return "";
  // the volume elements of each body tested against (built on demand) and its samples' bins
  std::vector<std::vector<Element>> vol(static_cast<size_t>(nb));
  std::vector<Bins> vbins(static_cast<size_t>(nb)), sbins(static_cast<size_t>(nb));
  std::vector<std::vector<int>> body_samples(static_cast<size_t>(nb));
  std::vector<char> built(static_cast<size_t>(nb), 0);
  auto build = [&](int b) {
    if (built[static_cast<size_t>(b)]) return;
    built[static_cast<size_t>(b)] = 1;
    const MultiPatch& D = deformed[static_cast<size_t>(b)];
    for (size_t k = 0; k < D.patches.size(); ++k) patch_elements(D.patches[k], static_cast<int>(k), vol[static_cast<size_t>(b)]);
    std::vector<Box> vb;
    for (const Element& e : vol[static_cast<size_t>(b)]) vb.push_back(e.box);
    vbins[static_cast<size_t>(b)].build(vb);
    std::vector<Box> sb;
    for (size_t i = 0; i < sx.size(); ++i)
      if (fe[static_cast<size_t>(s_elem[i])].body == b) {
        body_samples[static_cast<size_t>(b)].push_back(static_cast<int>(i));
        Box one;
        one.add(sx[i]);
        sb.push_back(one);
      }
    double hb = 0;   // the body's mean face element: about 16 samples a cell
    int nf = 0;
    for (const FaceElement& x : fe)
      if (x.body == b) { hb += x.box.size(); ++nf; }
    sbins[static_cast<size_t>(b)].build(sb, nf > 0 ? hb / nf : 0.0);
  };
  // the k samples of body b's faces nearest to x, nearest first, leaving out those skip(sample)
  // names: (distance, sample)
  auto nearest = [&](int b, const V3& x, int k, const auto& skip) {
    std::vector<std::pair<double, int>> near;
    const Bins& sb = sbins[static_cast<size_t>(b)];
    const std::vector<int>& ids = body_samples[static_cast<size_t>(b)];
    const int c0 = sb.c(x[0], 0), c1 = sb.c(x[1], 1), c2 = sb.c(x[2], 2);
    const int rings = std::max({sb.n[0], sb.n[1], sb.n[2]});
    for (int ring = 0; ring <= rings; ++ring) {
      if (static_cast<int>(near.size()) >= k && (ring - 1) * sb.cell > near.back().first) break;
      for (int i2 = c2 - ring; i2 <= c2 + ring; ++i2)
        for (int i1 = c1 - ring; i1 <= c1 + ring; ++i1)
          for (int i0 = c0 - ring; i0 <= c0 + ring; ++i0) {
            if (i0 < 0 || i1 < 0 || i2 < 0 || i0 >= sb.n[0] || i1 >= sb.n[1] || i2 >= sb.n[2]) continue;
            if (std::max({std::abs(i0 - c0), std::abs(i1 - c1), std::abs(i2 - c2)}) != ring) continue;
            for (const int q : sb.bins[sb.index(i0, i1, i2)]) {
              const int smp = ids[static_cast<size_t>(q)];
              if (skip(smp)) continue;
              const double d = dist3(sx[static_cast<size_t>(smp)], x);
              if (static_cast<int>(near.size()) >= k && d >= near.back().first) continue;
              near.insert(std::upper_bound(near.begin(), near.end(), std::make_pair(d, smp)), {d, smp});
              if (static_cast<int>(near.size()) > k) near.pop_back();
            }
          }
    }
    return near;
  };
  double worst = 0;
  bool worst_facing = false;
  std::string message;
  for (size_t e = 0; e < fe.size(); ++e) {
    const FaceElement& S = fe[e];
    for (int b = 0; b < nb; ++b) {
      if (!test[e][static_cast<size_t>(b)]) continue;
      build(b);
      const bool self = b == S.body;
      const Body& B = P.bodies[static_cast<size_t>(b)];
      const size_t ab = static_cast<size_t>(S.body) * nb + b;
      const double limit = std::max((declared[ab] ? kPairFloor : kFloor) * S.h, allowed[ab]);
      if (self) adj.around(static_cast<int>(e), kNear);
      for (int i = S.first; i < S.first + S.count; ++i) {
        const V3& x = sx[static_cast<size_t>(i)];
        const V3& X = sX[static_cast<size_t>(i)];
        // 2) inside an element of body b (self: a preimage other than x's own reference point)
        bool inside = false;
        for (const int k : vbins[static_cast<size_t>(b)].at(x)) {
          const Element& el = vol[static_cast<size_t>(b)][static_cast<size_t>(k)];
          if (!el.box.holds(x, tol_x)) continue;
          double t[3];
          if (!invert(deformed[static_cast<size_t>(b)].patches[static_cast<size_t>(el.patch)], el.t0, el.t1, x, t, tol_x)) continue;
          if (self && dist3(B.patches[static_cast<size_t>(el.patch)].point(t), X) <= 1e-6 * L) continue;   // its own place
          inside = true;
          break;
        }
        if (!inside) continue;
        // 3) depth: the distance to b's deformed outer faces (self: away from x's own place)
        const double enough = std::max(limit, worst);
        auto own = [&](int smp) { return self && adj.marked(s_elem[static_cast<size_t>(smp)]); };
        const auto near = nearest(b, x, kNearest, own);
        if (near.empty()) continue;
        double depth = near.front().first;
        int through = s_elem[static_cast<size_t>(near.front().second)];
        std::vector<int> refined;
        for (const auto& [d0, smp] : near) {
          if (depth <= enough) break;
          const int g = s_elem[static_cast<size_t>(smp)];
          if (std::find(refined.begin(), refined.end(), g) != refined.end()) continue;
          refined.push_back(g);
          const FaceElement& G = fe[static_cast<size_t>(g)];
          double t[3];
          const Patch& face = faces[static_cast<size_t>(b)].cur[static_cast<size_t>(G.face)];
          if (!invert(face, G.t0, G.t1, x, t, 0.0)) continue;
          const double d = dist3(face.point(t), x);
          if (d < depth) { depth = d; through = g; }
        }
        // with a pair between the bodies, 5 % of the larger of x's face element and the one it
        // is nearest to: a fine master's points between a coarse slave's points
        const double lim = declared[ab] ? std::max(limit, kPairFloor * fe[static_cast<size_t>(through)].h) : limit;
        if (!(depth > lim)) continue;
        // the face it passes through: the nearest boundary's where that faces it (opposed
        // normals: the face a contact pair would pair it with), else the nearest face of body
        // b that faces it, if that is near, else the nearest boundary's
        auto opposed = [&](int g) {
          const FaceElement& G = fe[static_cast<size_t>(g)];
          return G.n[0] * S.n[0] + G.n[1] * S.n[1] + G.n[2] * S.n[2] < 0;
        };
        int facing = opposed(through) ? through : -1;
        if (facing < 0) {
          // (within an element of the nearest boundary: a body wholly inside faces nothing)
          const auto f = nearest(b, x, 1, [&](int smp) { return own(smp) || !opposed(s_elem[static_cast<size_t>(smp)]); });
          if (!f.empty() && f.front().first <= depth + S.h) facing = s_elem[static_cast<size_t>(f.front().second)];
        }
        // the deepest finding; of equal depths (a rigid overlap), one through a facing face
        const bool deeper = depth > enough * (1 + 1e-9) || (facing >= 0 && !worst_facing && depth > enough * (1 - 1e-9));
        if (!deeper) continue;
        if (facing >= 0) through = facing;
        worst_facing = facing >= 0;
        worst = depth;
        const Body& A = P.bodies[static_cast<size_t>(S.body)];
        const PatchSide sa = faces[static_cast<size_t>(S.body)].sides[static_cast<size_t>(S.face)];
        const PatchSide sbs = faces[static_cast<size_t>(b)].sides[static_cast<size_t>(fe[static_cast<size_t>(through)].face)];
        std::ostringstream os;
        if (self) {
          os << "self-penetration: " << A.name << "." << A.side_label(sa.patch, sa.side) << " passes " << check_number(depth)
             << " into its own body through " << A.name << "." << B.side_label(sbs.patch, sbs.side) << " at " << point3(x);
          os << (declared[static_cast<size_t>(b) * nb + b] ? "; its self-contact pairs allow " + check_number(lim)
                                                           : "; declare a contact pair between those two faces of " + A.name + " (self-contact)");
        } else {
          os << "interpenetration: " << A.name << "." << A.side_label(sa.patch, sa.side) << " is " << check_number(depth) << " inside "
             << B.name << " (below " << B.name << "." << B.side_label(sbs.patch, sbs.side) << ") at " << point3(x);
          os << (declared[static_cast<size_t>(S.body) * nb + b]
                     ? "; the contact pairs between them allow " + check_number(lim) +
                           (allowed[ab] >= lim ? std::string(" (3 x their penalty penetration)")
                                               : std::string(" (5 % of the face element, above 3 x their penalty penetration)"))
                     : "; no contact pair is declared between " + A.name + " and " + B.name);
        }
        message = os.str();
      }
    }
  }
  return message;
}

}  // namespace iga
