#pragma once
// 3-D mortar segmentation (issue 36, item 1): the overlap of a slave element and a master
// element in the slave element's parameter plane, and a quadrature rule on it. Kokkos only,
// header only; not yet wired to the contact pairs.
//
// What it computes. A slave element's parameter rectangle S (or any convex polygon) and the
// master element's boundary, sampled and projected into the slave parameter plane (a point set
// M, in any order), give the segment P = S n hull(M): the region of S where slave points see
// this master element. Integrals over S of the mortar integrands are sums over the segments
// P of the master elements that cover S, each with its own rule, so the integrand is smooth on
// every piece (as the 2-D segments of contact_mortar.hpp). The segments of the master elements
// tile S (to round-off) when neighbouring master elements use the same projected points on
// their common edge (sample each master edge once, at the same parameters for both sides).
//   1. hull(S), hull(M): Andrew's monotone chain with exact orientation tests: the strictly
//      convex hull, counter-clockwise; collinear and repeated points are dropped exactly, a
//      corner with the smallest non-zero turn is kept (a master polygon that is not convex,
//      e.g. a distorted element's projection, is replaced by its hull).
//   2. Sutherland-Hodgman: hull(M) clipped by the closed half-plane left of each edge a -> b of
//      hull(S). Each vertex is classified by the exact sign of orient2d(a, b, x); a crossing is
//      emitted only where the signs are strictly opposite, at x = s + t (e - s), t = o_s /
//      (o_s - o_e) from the end point nearer the line, clamped to [0, 1], and put exactly on
//      the line when it is axis-parallel (a slave rectangle: corners come out exact).
//      Master vertices inside S are kept bit for bit.
//   3. The exact hull of the clipped points (round-off in the crossings cannot leave a
//      reflex vertex), then consecutive vertices closer than kClipMergeTol h (h: the larger
//      side of S's bounding box) are merged (dropping a vertex of a convex polygon keeps it
//      strictly convex). Fewer than 3 vertices, or an area <= kClipAreaTol |S|, is an empty
//      segment (n = 0): touching edges and shared vertices give area 0, never NaN.
//      Both tolerances are at round-off (the crossings carry ~eps h): a merge moves the area
//      by at most kClipMergeTol h diam(P) / 2 and a dropped segment by kClipAreaTol |S|, so
//      the segments of a master tiling still sum to |S| to round-off (the discrete partition
//      of unity mortar needs). Larger tolerances (1e-13) were measured to break that at
//      8e-14 |S| in the tiling test: short edges are kept instead, and their fan triangles get
//      small positive weights (below), which do no harm.
//   orient2d(a, b, c) = (a - c) x (b - c): Shewchuk's error-bounded filter (errbound
//   (3 + 16 eps) eps (|detleft| + |detright|)) and, below the bound, the exact sign: where the
//   four differences are exact (two-sum tails 0), from the two products of the differences,
//   else from the six products a_x b_y - a_x c_y - c_x b_y - a_y b_x + a_y c_x + c_y b_x; the
//   products split into two-products (Dekker) and summed into a non-overlapping expansion
//   (grow-expansion with zero elimination, Shewchuk 1997 Theorem 10), whose largest component
//   has the sign of the determinant. Exact for finite inputs without overflow or underflow of the products
//   (parameter coordinates are O(1)); FMA contraction does not change the result (every
//   partial product of the split is exact).
// Quadrature: a fan of triangles (c, A, B) over P's corners A, B (consecutive), c the average
// of the corners (strictly inside P; near-duplicates once). A vertex within kRuleRunTol of the
// chord of its neighbours (a run of nearly collinear vertices: a sampled master edge along a slave edge of
// aligned meshes, where round-off decides which samples are vertices) is no corner: the strip
// between its run and the chord A B is added to (c, A, B)'s weights, so they sum to |P|, and
// round-off vertices move no point (a flat punch on aligned meshes stalled with mortar when
// they did; the rule's degree holds where there are no runs). On each triangle a rule r of the
// reference triangle (TriangleRule: points (r0, r1), weights summing to 1/2): x = c + r0 (A -
// c) + r1 (B - c), weight w 2|T| (1 + strip / |T|), 2|T| = orient2d(A, B, c) (exactly signed:
// every weight > 0 however short the edge, where the rule's weights are). With the collapsed
// (Duffy) tensor rule of an n-point Gauss rule (triangle_rule_collapsed) a polynomial of total degree d becomes degree d + 1 in xi and d in
// eta, so the rule is exact for degree 2 n - 2 (polygon_rule_degree), with n_v n^2 points; the
// 3-D mortar uses a symmetric rule of Intrepid2 of the same degree (6, 12, 16 points for degree
// 4, 6, 8 instead of 9, 16, 25; solver/contact3d.cpp, triangle_rule).
//
// Data layout: ClipPolygon holds n <= kClipMaxVertices vertices v[k] = (u, v) of the slave
// parameter plane; results are strictly convex and counter-clockwise. The segment of an n_s-gon
// and an n_m-point master set has at most n_s + hull(n_m) vertices: n_s + n_m <= 16 (a
// rectangle and 12 master points) never overflows; beyond, clip_polygons returns
// kClipOverflow with n = 0, and the caller samples the master boundary more coarsely. Flags
// are bits: kClipOverflow, kClipBadInput (a count outside 0..16 or a coordinate not finite).
// Everything lives in fixed arrays on the stack (~3 KB), no std:: containers; each function
// is KOKKOS_INLINE_FUNCTION, to be called per (slave element, master element) pair in a kernel.
//
// Cost per pair: hulls ~ n^2 / 2 comparisons (insertion sort, n <= 16) + 2 n orientation
// tests; clipping n_s (n_m + n_s) tests; ~ 10 flops per filtered test; nearly collinear
// triples (sampled straight edges: every test of the hull) reach the exact fallback, ~ 70
// flops with exact differences, ~ 500 without. Quadrature: n_v r.n points, ~ 10 flops each.
// Measured (BM_PolygonClip, one core): ~ 3e6 clips/s of a rectangle and a 4-point master,
// ~ 6e5 with 12 points sampled on the master's straight edges.
#include "kernels/types.hpp"

namespace iga {

constexpr int kClipMaxVertices = 16;   // vertices of an input or output polygon
constexpr double kClipMergeTol = 1e-15;   // vertex merge distance / the slave's size h
constexpr double kClipAreaTol = 1e-15;    // smallest kept segment area / the slave's area
constexpr int kClipOverflow = 1;          // flag: the segment has more than kClipMaxVertices vertices
constexpr int kClipBadInput = 2;          // flag: a vertex count out of range or a coordinate not finite

/// A polygon of the slave parameter plane: vertices v[0..n) as (u, v).
struct ClipPolygon {
  int n = 0;
  double v[kClipMaxVertices][2] = {};
};

constexpr int kMaxTrianglePoints = kMaxGauss * kMaxGauss;   // the collapsed rule of kMaxGauss points

/// A quadrature rule on the reference triangle (0, 0), (1, 0), (0, 1): points (x[k][0], x[k][1])
/// and weights summing to 1/2. Filled on the host: triangle_rule_collapsed below (Kokkos only),
/// or a symmetric rule of Intrepid2 (solver/contact3d.cpp, triangle_rule), which needs about 1.5
/// times fewer points for the same degree.
struct TriangleRule {
  int n = 0;        // points
  int degree = 0;   // polynomials of this total degree are integrated exactly
  double x[kMaxTrianglePoints][2] = {};
  double w[kMaxTrianglePoints] = {};
};

/// The collapsed (Duffy) tensor rule of the n-point Gauss rule g on the reference triangle:
/// (xi, eta) in (0, 1)^2 -> (xi (1 - eta), xi eta), weight w_xi w_eta xi / 4; n^2 points, exact
/// for degree 2 n - 2 (a polynomial of degree d becomes degree d + 1 in xi and d in eta).
inline TriangleRule triangle_rule_collapsed(const GaussRule& g) {
  TriangleRule t;
  t.n = g.n * g.n;
  t.degree = 2 * g.n - 2;
  for (int i = 0; i < g.n; ++i)
    for (int j = 0; j < g.n; ++j) {
      const double xi = 0.5 * (1 + g.x[i]), eta = 0.5 * (1 + g.x[j]);
      const int k = i * g.n + j;
      t.x[k][0] = xi * (1 - eta);
      t.x[k][1] = xi * eta;
      t.w[k] = 0.25 * g.w[i] * g.w[j] * xi;
    }
  return t;
}

namespace clip_detail {

constexpr int kScratch = 2 * kClipMaxVertices + 8;   // clipped points before the final hull

KOKKOS_INLINE_FUNCTION double absd(double x) { return x < 0 ? -x : x; }
KOKKOS_INLINE_FUNCTION bool finite(double x) { return x - x == 0.0; }   // false for NaN and inf
KOKKOS_INLINE_FUNCTION bool lex_less(const double* a, const double* b) {
  return a[0] < b[0] || (a[0] == b[0] && a[1] < b[1]);
}
KOKKOS_INLINE_FUNCTION void copy2(double* d, const double* s) {
  d[0] = s[0];
  d[1] = s[1];
}

/// x + y = a + b exactly (Knuth).
KOKKOS_INLINE_FUNCTION void two_sum(double a, double b, double& x, double& y) {
  x = a + b;
  const double bv = x - a, av = x - bv;
  y = (a - av) + (b - bv);
}
/// a = hi + lo with hi, lo of at most 26 significant bits each (Veltkamp).
KOKKOS_INLINE_FUNCTION void split(double a, double& hi, double& lo) {
  const double c = 134217729.0 * a;   // 2^27 + 1
  hi = c - (c - a);
  lo = a - hi;
}
/// x + y = a b exactly (Dekker).
KOKKOS_INLINE_FUNCTION void two_product(double a, double b, double& x, double& y) {
  x = a * b;
  double ah, al, bh, bl;
  split(a, ah, al);
  split(b, bh, bl);
  y = al * bl - (((x - ah * bh) - al * bh) - ah * bl);
}

/// The sum of t[0..n) (n <= 12) as a non-overlapping expansion: its largest component (the
/// sign of the sum exactly, the value within a relative eps).
KOKKOS_INLINE_FUNCTION double expansion_sum_largest(const double* t, int n) {
  double e[12];
  int m = 0;
  for (int k = 0; k < n; ++k) {   // grow-expansion with zero elimination, in place (j <= i)
    double q = t[k], h;
    int j = 0;
    for (int i = 0; i < m; ++i) {
      two_sum(q, e[i], q, h);
      if (h != 0.0) e[j++] = h;
    }
    if (q != 0.0) e[j++] = q;
    m = j;
  }
  return m > 0 ? e[m - 1] : 0.0;
}

/// The determinant of orient2d exactly (its expansion's largest component). When the four
/// differences are exact (Sterbenz: coordinates within a factor 2 of each other, the usual
/// case in a parameter plane) two two-products of them suffice; else the six products of the
/// coordinates.
KOKKOS_INLINE_FUNCTION double orient2d_exact(const double* a, const double* b, const double* c) {
  double acx, acy, bcx, bcy, e0, e1, e2, e3;
  two_sum(a[0], -c[0], acx, e0);
  two_sum(a[1], -c[1], acy, e1);
  two_sum(b[0], -c[0], bcx, e2);
  two_sum(b[1], -c[1], bcy, e3);
  double t[12];
  if (e0 == 0.0 && e1 == 0.0 && e2 == 0.0 && e3 == 0.0) {
    two_product(acx, bcy, t[0], t[1]);
    two_product(-acy, bcx, t[2], t[3]);
    return expansion_sum_largest(t, 4);
  }
  two_product(a[0], b[1], t[0], t[1]);
  two_product(-a[0], c[1], t[2], t[3]);
  two_product(-c[0], b[1], t[4], t[5]);
  two_product(-a[1], b[0], t[6], t[7]);
  two_product(a[1], c[0], t[8], t[9]);
  two_product(c[1], b[0], t[10], t[11]);
  return expansion_sum_largest(t, 12);
}

}  // namespace clip_detail

/// (a - c) x (b - c): > 0 when a, b, c turn counter-clockwise, < 0 clockwise, 0 collinear; the
/// sign is exact (adaptive: a filter, then an exact expansion), the value accurate to ~eps.
KOKKOS_INLINE_FUNCTION double orient2d(const double* a, const double* b, const double* c) {
  constexpr double eps = 1.1102230246251565e-16;   // 2^-53
  constexpr double bound = (3.0 + 16.0 * eps) * eps;
  const double detleft = (a[0] - c[0]) * (b[1] - c[1]);
  const double detright = (a[1] - c[1]) * (b[0] - c[0]);
  const double det = detleft - detright;
  double detsum;
  if (detleft > 0) {
    if (detright <= 0) return det;
    detsum = detleft + detright;
  } else if (detleft < 0) {
    if (detright >= 0) return det;
    detsum = -detleft - detright;
  } else {
    return det;   // a difference rounds to 0 only when it is 0: det = -detright exactly signed
  }
  if (clip_detail::absd(det) >= bound * detsum) return det;
  return clip_detail::orient2d_exact(a, b, c);
}

/// The strictly convex hull of p[0..n), counter-clockwise from the lexicographically smallest
/// point, into h (capacity 2 n); p is sorted in place. Returns its vertex count, 0 when the
/// points are collinear or fewer than 3 distinct.
KOKKOS_INLINE_FUNCTION int convex_hull(double (*p)[2], int n, double (*h)[2]) {
  for (int i = 1; i < n; ++i) {   // insertion sort, lexicographic (n is small)
    double x[2];
    clip_detail::copy2(x, p[i]);
    int j = i - 1;
    for (; j >= 0 && clip_detail::lex_less(x, p[j]); --j) clip_detail::copy2(p[j + 1], p[j]);
    clip_detail::copy2(p[j + 1], x);
  }
  if (n < 3) return 0;
  int k = 0;
  for (int i = 0; i < n; ++i) {   // lower chain
    while (k >= 2 && orient2d(h[k - 2], h[k - 1], p[i]) <= 0) --k;
    clip_detail::copy2(h[k++], p[i]);
  }
  for (int i = n - 2, t = k + 1; i >= 0; --i) {   // upper chain
    while (k >= t && orient2d(h[k - 2], h[k - 1], p[i]) <= 0) --k;
    clip_detail::copy2(h[k++], p[i]);
  }
  --k;   // the last point is the first again
  return k >= 3 ? k : 0;
}

/// Signed area of the polygon v[0..n) (> 0 counter-clockwise), by the shoelace formula about v[0].
KOKKOS_INLINE_FUNCTION double polygon_area(const double (*v)[2], int n) {
  double a = 0;
  for (int k = 1; k + 1 < n; ++k)
    a += (v[k][0] - v[0][0]) * (v[k + 1][1] - v[0][1]) - (v[k][1] - v[0][1]) * (v[k + 1][0] - v[0][0]);
  return 0.5 * a;
}
KOKKOS_INLINE_FUNCTION double polygon_area(const ClipPolygon& p) { return polygon_area(p.v, p.n); }

/// The parameter rectangle [u0, u1] x [v0, v1] of a slave element, counter-clockwise.
KOKKOS_INLINE_FUNCTION ClipPolygon parameter_rectangle(double u0, double u1, double v0, double v1) {
  ClipPolygon r;
  r.n = 4;
  r.v[0][0] = u0; r.v[0][1] = v0;
  r.v[1][0] = u1; r.v[1][1] = v0;
  r.v[2][0] = u1; r.v[2][1] = v1;
  r.v[3][0] = u0; r.v[3][1] = v1;
  return r;
}

namespace clip_detail {

/// Sutherland-Hodgman step: in[0..n) clipped by the closed half-plane left of a -> b, into out
/// (capacity cap). Returns the count, or -1 when cap is short.
KOKKOS_INLINE_FUNCTION int clip_half_plane(const double (*in)[2], int n, const double* a, const double* b,
                                           double (*out)[2], int cap) {
  if (n == 0) return 0;
  const bool vertical = a[0] == b[0], horizontal = a[1] == b[1];
  int m = 0;
  const double* s = in[n - 1];
  double os = orient2d(a, b, s);
  for (int i = 0; i < n; ++i) {
    const double* e = in[i];
    const double oe = orient2d(a, b, e);
    if ((os > 0 && oe < 0) || (os < 0 && oe > 0)) {
      if (m >= cap) return -1;
      // from the end point nearer the line (ties by the points' order: the same crossing
      // whichever way a shared master edge is walked)
      const bool from_s = absd(os) < absd(oe) || (absd(os) == absd(oe) && lex_less(s, e));
      const double* p = from_s ? s : e;
      const double* q = from_s ? e : s;
      const double op = from_s ? os : oe, oq = from_s ? oe : os;
      double t = op / (op - oq);
      t = t < 0 ? 0 : (t > 1 ? 1 : t);
      out[m][0] = vertical ? a[0] : p[0] + t * (q[0] - p[0]);
      out[m][1] = horizontal ? a[1] : p[1] + t * (q[1] - p[1]);
      ++m;
    }
    if (oe >= 0) {
      if (m >= cap) return -1;
      copy2(out[m++], e);
    }
    s = e;
    os = oe;
  }
  return m;
}

KOKKOS_INLINE_FUNCTION bool valid_input(const ClipPolygon& p) {
  if (p.n < 0 || p.n > kClipMaxVertices) return false;
  for (int k = 0; k < p.n; ++k)
    if (!finite(p.v[k][0]) || !finite(p.v[k][1])) return false;
  return true;
}

}  // namespace clip_detail

/// The segment out = slave n hull(master) in the slave parameter plane: strictly convex,
/// counter-clockwise, n = 0 when the overlap is empty or below kClipAreaTol of the slave's
/// area. slave: a convex polygon (any orientation; a non-convex one is replaced by its hull);
/// master: the projected master boundary points, in any order. Returns flags (0: fine;
/// kClipOverflow, kClipBadInput with out.n = 0).
KOKKOS_INLINE_FUNCTION int clip_polygons(const ClipPolygon& slave, const ClipPolygon& master, ClipPolygon& out) {
  using namespace clip_detail;
  out.n = 0;
  if (!valid_input(slave) || !valid_input(master)) return kClipBadInput;
  double pa[kScratch][2], pb[kScratch][2], h[2 * kScratch][2];
  // the slave's hull (its edges are the clip lines), its size and area
  for (int k = 0; k < slave.n; ++k) copy2(pa[k], slave.v[k]);
  double sv[kClipMaxVertices + 1][2];
  const int ns = convex_hull(pa, slave.n, h);
  if (ns == 0) return 0;
  for (int k = 0; k < ns; ++k) copy2(sv[k], h[k]);
  copy2(sv[ns], sv[0]);
  double lo[2] = {sv[0][0], sv[0][1]}, hi[2] = {sv[0][0], sv[0][1]};
  for (int k = 1; k < ns; ++k)
    for (int c = 0; c < 2; ++c) {
      lo[c] = sv[k][c] < lo[c] ? sv[k][c] : lo[c];
      hi[c] = sv[k][c] > hi[c] ? sv[k][c] : hi[c];
    }
  const double size = hi[0] - lo[0] > hi[1] - lo[1] ? hi[0] - lo[0] : hi[1] - lo[1];
  const double slave_area = polygon_area(sv, ns);
  // the master's hull, then clipped by each slave edge in turn
  for (int k = 0; k < master.n; ++k) copy2(pa[k], master.v[k]);
  int n = convex_hull(pa, master.n, h);
  for (int k = 0; k < n; ++k) copy2(pa[k], h[k]);
  double(*cur)[2] = pa;
  double(*nxt)[2] = pb;
  for (int e = 0; e < ns && n > 0; ++e) {
    n = clip_half_plane(cur, n, sv[e], sv[e + 1], nxt, kScratch);
    if (n < 0) return kClipOverflow;
    double(*t)[2] = cur;
    cur = nxt;
    nxt = t;
  }
  // exact hull of the clipped points, near-duplicates merged
  n = convex_hull(cur, n, h);
  const double tol = kClipMergeTol * size;
  int m = 0;
  for (int k = 0; k < n; ++k) {
    if (m > 0 && absd(h[k][0] - h[m - 1][0]) <= tol && absd(h[k][1] - h[m - 1][1]) <= tol) continue;
    copy2(h[m++], h[k]);
  }
  while (m >= 2 && absd(h[m - 1][0] - h[0][0]) <= tol && absd(h[m - 1][1] - h[0][1]) <= tol) --m;
  if (m < 3 || polygon_area(h, m) <= kClipAreaTol * slave_area) return 0;
  if (m > kClipMaxVertices) return kClipOverflow;
  out.n = m;
  for (int k = 0; k < m; ++k) copy2(out.v[k], h[k]);
  return 0;
}

/// The polynomial degree the collapsed rule of an n-point Gauss rule integrates exactly.
KOKKOS_INLINE_FUNCTION constexpr int polygon_rule_degree(int n) { return 2 * n - 2; }

/// Vertex k lies within kRuleRunTol |b - a| of the chord a b of its neighbours a, b (the
/// nearest vertices either way farther than kRuleDupTol of P's size from it, so that a
/// near-duplicate neighbour does not hide a corner): inside a run of nearly collinear vertices
/// (a sampled master edge along a slave edge of aligned meshes, crossings of one straight
/// edge). The rule's fan skips such vertices (below).
constexpr double kRuleRunTol = 1e-10;
constexpr double kRuleDupTol = 1e-8;

namespace clip_detail {
KOKKOS_INLINE_FUNCTION int prev_vertex(int k, int n) { return k > 0 ? k - 1 : n - 1; }
KOKKOS_INLINE_FUNCTION int next_vertex(int k, int n) { return k + 1 < n ? k + 1 : 0; }

/// corner[k]: vertex k is a corner of the rule's fan (not inside a run); every vertex when
/// fewer than 3 would be corners. Returns the number of corners.
KOKKOS_INLINE_FUNCTION double rule_dup_distance(const ClipPolygon& p) {
  double lo[2] = {p.v[0][0], p.v[0][1]}, hi[2] = {p.v[0][0], p.v[0][1]};
  for (int k = 1; k < p.n; ++k)
    for (int d = 0; d < 2; ++d) {
      lo[d] = p.v[k][d] < lo[d] ? p.v[k][d] : lo[d];
      hi[d] = p.v[k][d] > hi[d] ? p.v[k][d] : hi[d];
    }
  return kRuleDupTol * (hi[0] - lo[0] > hi[1] - lo[1] ? hi[0] - lo[0] : hi[1] - lo[1]);
}
KOKKOS_INLINE_FUNCTION bool near2(const double* a, const double* b, double tol) {
  return absd(a[0] - b[0]) <= tol && absd(a[1] - b[1]) <= tol;
}
KOKKOS_INLINE_FUNCTION int rule_corners(const ClipPolygon& p, bool corner[kClipMaxVertices]) {
  const double dup = rule_dup_distance(p);
  int m = 0;
  for (int k = 0; k < p.n; ++k) {
    int ia = prev_vertex(k, p.n), ib = next_vertex(k, p.n);
    for (int s = 0; s < p.n && ia != k && near2(p.v[ia], p.v[k], dup); ++s) ia = prev_vertex(ia, p.n);
    for (int s = 0; s < p.n && ib != k && near2(p.v[ib], p.v[k], dup); ++s) ib = next_vertex(ib, p.n);
    corner[k] = true;
    if (ia != k && ib != k && ia != ib) {
      const double* a = p.v[ia];
      const double* b = p.v[ib];
      const double dx = b[0] - a[0], dy = b[1] - a[1];
      const double t = (p.v[k][0] - a[0]) * dy - (p.v[k][1] - a[1]) * dx;   // -(twice the area of a, b, v_k)
      corner[k] = !(absd(t) <= kRuleRunTol * (dx * dx + dy * dy));
    }
    m += corner[k];
  }
  if (m < 3) {
    for (int k = 0; k < p.n; ++k) corner[k] = true;
    m = p.n;
  }
  return m;
}
}  // namespace clip_detail

/// Number of points of the polygon rule: a fan over the corners, t.n points each.
KOKKOS_INLINE_FUNCTION int polygon_rule_size(const ClipPolygon& p, const TriangleRule& t) {
  if (p.n < 3) return 0;
  bool corner[kClipMaxVertices];
  return clip_detail::rule_corners(p, corner) * t.n;
}

/// The apex of the rule's fan: the average of the corners (strictly inside a convex polygon),
/// a corner within kRuleDupTol of P's size from the last (or first) one counted not counted
/// again. Not the average of every vertex: a run vertex, or a corner splitting into two
/// near-duplicates (a master corner crossing a slave edge), that appears or goes with round-off
/// would move it by O(h / n) and with it every point of the rule, a jump of the rule's error in
/// the residual (a flat punch on aligned meshes stalled at relative residual 1e-9 with mortar).
/// (The area centroid would not move either, but on a sliver segment its cross products
/// cancel: an apex 1e-6 h off along the sliver, different on 1 and 2 ranks.)
KOKKOS_INLINE_FUNCTION void polygon_centre(const ClipPolygon& p, const bool corner[kClipMaxVertices], double c[2]) {
  const double tol = clip_detail::rule_dup_distance(p);
  int m = 0, first = -1, last = -1;
  c[0] = c[1] = 0;
  for (int k = 0; k < p.n; ++k) {
    if (!corner[k]) continue;
    if (last >= 0 && (clip_detail::near2(p.v[k], p.v[last], tol) || clip_detail::near2(p.v[k], p.v[first], tol))) continue;
    if (first < 0) first = k;
    last = k;
    c[0] += p.v[k][0];
    c[1] += p.v[k][1];
    ++m;
  }
  if (m < 3) {   // a sliver: every corner (their average is inside, the distinct ones' on an edge)
    m = 0;
    c[0] = c[1] = 0;
    for (int k = 0; k < p.n; ++k)
      if (corner[k]) {
        c[0] += p.v[k][0];
        c[1] += p.v[k][1];
        ++m;
      }
  }
  c[0] /= m;
  c[1] /= m;
}

namespace clip_detail {
/// The fan triangle (c, A, B) from corner A = v_t to the next corner B, and the weight factor
/// that puts the strip between B's run of skipped vertices and the chord A B on it: (|c A B| +
/// |strip|) / |c A B|, the strip's area from the fan (A, v_k, v_k+1) over the run. So the
/// weights still sum to the area of P, and a run's vertices coming and going with round-off
/// change a strip of area ~ their distance from the chord, not the fan's points (which stay
/// inside P). The rule's degree holds where there are no runs; a run moves a polynomial's
/// integral by at most its strip's area times the polynomial's variation over the triangle
/// (round-off for runs of round-off). Returns B; area2 = 2 |c A B|, scale the factor.
KOKKOS_INLINE_FUNCTION int fan_triangle(const ClipPolygon& p, const bool corner[kClipMaxVertices], const double c[2], int t,
                                        double& area2, double& scale) {
  int B = next_vertex(t, p.n);
  double strip2 = 0;
  while (!corner[B]) {
    const int nb = next_vertex(B, p.n);
    strip2 += orient2d(p.v[B], p.v[nb], p.v[t]);   // 2 |A v_k v_k+1|
    B = nb;
  }
  area2 = orient2d(p.v[t], p.v[B], c);
  scale = (area2 + strip2) / area2;
  return B;
}
/// Point k of the triangle rule on (c, a, b): x = c + r0 (a - c) + r1 (b - c), weight w_k 2|T|.
KOKKOS_INLINE_FUNCTION void fan_point(const double* a, const double* b, const TriangleRule& r, const double c[2], double weight2,
                                      int k, double x[2], double& w) {
  x[0] = c[0] + r.x[k][0] * (a[0] - c[0]) + r.x[k][1] * (b[0] - c[0]);
  x[1] = c[1] + r.x[k][0] * (a[1] - c[1]) + r.x[k][1] * (b[1] - c[1]);
  w = r.w[k] * weight2;
}
}  // namespace clip_detail

/// Point k (0 <= k < polygon_rule_size) of the polygon rule: x in the slave parameter plane and
/// its weight (parameter area). Recomputes the corners and the apex (O(p.n)); for_each_polygon_point
/// does that once.
KOKKOS_INLINE_FUNCTION void polygon_rule_point(const ClipPolygon& p, const TriangleRule& r, int k, double x[2], double& w) {
  bool corner[kClipMaxVertices];
  clip_detail::rule_corners(p, corner);
  double c[2];
  polygon_centre(p, corner, c);
  int j = k / r.n, t = 0;
  while (!corner[t]) ++t;
  for (; j > 0; --j) {
    t = clip_detail::next_vertex(t, p.n);
    while (!corner[t]) t = clip_detail::next_vertex(t, p.n);
  }
  double area2, scale;
  const int B = clip_detail::fan_triangle(p, corner, c, t, area2, scale);
  clip_detail::fan_point(p.v[t], p.v[B], r, c, area2 * scale, k % r.n, x, w);
}

/// f(x, w) for every point of the polygon rule (x: double[2] in the slave parameter plane), in
/// the order of polygon_rule_point.
template <class F>
KOKKOS_INLINE_FUNCTION void for_each_polygon_point(const ClipPolygon& p, const TriangleRule& r, F&& f) {
  if (p.n < 3) return;
  bool corner[kClipMaxVertices];
  clip_detail::rule_corners(p, corner);
  double c[2];
  polygon_centre(p, corner, c);
  int first = 0;
  while (!corner[first]) ++first;
  for (int j = 0; j < p.n; ++j) {
    const int t = (first + j) % p.n;
    if (!corner[t]) continue;
    double area2, scale;
    const int B = clip_detail::fan_triangle(p, corner, c, t, area2, scale);
    for (int k = 0; k < r.n; ++k) {
      double x[2], w;
      clip_detail::fan_point(p.v[t], p.v[B], r, c, area2 * scale, k, x, w);
      f(x, w);
    }
  }
}

}  // namespace iga
