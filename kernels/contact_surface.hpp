#pragma once
// 3-D contact geometry (issue 36, first part): closest-point projection of points onto a NURBS
// surface (a face of a trivariate patch, in its current configuration) and a search over the
// surface's elements by bins. Kokkos only; not yet wired to the contact pairs.
//
// Projection: the foot point S(u, v) of x minimises |x - S|^2 / 2, so it solves
//   F(u, v) = [ (x - S) . S_u ,  (x - S) . S_v ] = 0,
//   dF = [[ -S_u.S_u + (x - S).S_uu,  -S_u.S_v + (x - S).S_uv ],
//         [ -S_u.S_v + (x - S).S_uv,  -S_v.S_v + (x - S).S_vv ]],
// by Newton from the best of a 3 x 3 sample of the element, each iterate clamped to the
// element's parameter box (a clamped foot on the box's edge is a foot of a neighbour element).
// S and its derivatives up to second order come from the rational surface: with A = sum N_i M_j
// w_ij P_ij and W = sum N_i M_j w_ij (and their parameter derivatives), S = A / W,
// S_u = (A_u - S W_u) / W, S_uu = (A_uu - 2 S_u W_u - S W_uu) / W, S_uv = (A_uv - S_u W_v -
// S_v W_u - S W_uv) / W.
// Cost per evaluation: (p + 1)^2 (4 x 10) flops for the sums, ~ 60 for the rational part;
// 2 to 6 Newton steps from the sampled start on smooth surfaces.
//
// Search (SurfaceSearch): per element the bounding box of its (p + 1)^2 control points (the
// element lies in their convex hull); a uniform grid of cell size h holding, sorted by cell
// id, the elements whose boxes meet each cell (only non-empty cells are stored: a surface
// meets O(M) cells of the grid, not O(M^(3/2))). A point is projected on the elements of the
// cells within its search radius, nearest box first, stopping when the next box is farther
// than the best foot found: every rank projects only its own points, each against a few
// elements.
//
// Data layout: SurfaceData holds the surface's knots U[2] (n_d + p_d + 1 each), its non-empty
// spans span[2], and its control points cp(a, 0..3) = (x, y, z, w), a = i + n0 j.
#include <algorithm>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "kernels/nurbs_basis.hpp"
#include "kernels/types.hpp"

namespace iga {

struct SurfaceData {
  int p[2] = {1, 1}, n[2] = {2, 2}, ne[2] = {1, 1};
  Kokkos::View<const double*, MemSpace> U[2];
  Kokkos::View<const int*, MemSpace> span[2];
  Kokkos::View<const double* [4], MemSpace> cp;   // current coordinates and weight
};

/// The surface index of the control point (i, j), i, j in 0..p, of the element with spans s
/// (the first direction fastest, as the kernels' local basis order i + (p0 + 1) j).
KOKKOS_INLINE_FUNCTION int surface_cp(const SurfaceData& sd, const int s[2], int i, int j) {
  return (s[0] - sd.p[0] + i) + sd.n[0] * (s[1] - sd.p[1] + j);
}

/// S and its first and second parameter derivatives at (u, v) in the element with spans s.
/// d[0] = S, d[1] = S_u, d[2] = S_v, d[3] = S_uu, d[4] = S_uv, d[5] = S_vv.
/// The surface point and its derivatives at (u, v) in element span s: d[0] the point, d[1],
/// d[2] the first derivatives and, for Order = 2, d[3..5] the second (uu, uv, vv); Order = 1
/// fills d[0..2] only and Order = 0 the point d[0] only, with the same arithmetic (the lower
/// orders' entries are bit-identical to Order = 2's, from 3 or 1 of its 6 homogeneous sums and
/// fewer basis derivatives: the shots of the mortar segmentation and the normals need no
/// curvature, a sample no tangent).
template <int Order>
KOKKOS_INLINE_FUNCTION void surface_derivatives_to(const SurfaceData& sd, const int s[2], double u, double v, double d[][3]) {
  static_assert(Order >= 0 && Order <= 2, "surface_derivatives_to: orders 0, 1, 2");
  constexpr int K = Order == 0 ? 1 : Order == 1 ? 3 : 6;
  double N[Order + 1][kMaxBasis1D], M[Order + 1][kMaxBasis1D];
  bspline_ders(s[0], u, sd.p[0], sd.U[0].data(), Order, N);
  bspline_ders(s[1], v, sd.p[1], sd.U[1].data(), Order, M);
  // homogeneous sums h[k][0..3]: k as d (value, u, v, uu, uv, vv); component 3 the weight
  double h[K][4] = {};
  for (int j = 0; j <= sd.p[1]; ++j)
    for (int i = 0; i <= sd.p[0]; ++i) {
      const int a = surface_cp(sd, s, i, j);
      const double w = sd.cp(a, 3);
      double b[K];
      b[0] = N[0][i] * M[0][j];
      if constexpr (Order >= 1) {
        b[1] = N[1][i] * M[0][j];
        b[2] = N[0][i] * M[1][j];
      }
      if constexpr (Order == 2) {
        b[3] = N[2][i] * M[0][j];
        b[4] = N[1][i] * M[1][j];
        b[5] = N[0][i] * M[2][j];
      }
      for (int k = 0; k < K; ++k) {
        const double bw = b[k] * w;
        for (int c = 0; c < 3; ++c) h[k][c] += bw * sd.cp(a, c);
        h[k][3] += bw;
      }
    }
  const double W = h[0][3];
  for (int c = 0; c < 3; ++c) {
    d[0][c] = h[0][c] / W;
    if constexpr (Order >= 1) {
      d[1][c] = (h[1][c] - d[0][c] * h[1][3]) / W;
      d[2][c] = (h[2][c] - d[0][c] * h[2][3]) / W;
    }
    if constexpr (Order == 2) {
      d[3][c] = (h[3][c] - 2 * d[1][c] * h[1][3] - d[0][c] * h[3][3]) / W;
      d[4][c] = (h[4][c] - d[1][c] * h[2][3] - d[2][c] * h[1][3] - d[0][c] * h[4][3]) / W;
      d[5][c] = (h[5][c] - 2 * d[2][c] * h[2][3] - d[0][c] * h[5][3]) / W;
    }
  }
}

KOKKOS_INLINE_FUNCTION void surface_derivatives(const SurfaceData& sd, const int s[2], double u, double v, double d[6][3]) {
  surface_derivatives_to<2>(sd, s, u, v, d);
}

/// The point and its first derivatives only (d[0..2]).
KOKKOS_INLINE_FUNCTION void surface_first_derivatives(const SurfaceData& sd, const int s[2], double u, double v, double d[][3]) {
  surface_derivatives_to<1>(sd, s, u, v, d);
}

KOKKOS_INLINE_FUNCTION double dot3(const double* a, const double* b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/// Closest point to x on element e = e0 + ne0 e1 of the surface (Newton on F from the best of
/// a 3 x 3 sample, iterates clamped to the element). Returns the squared distance; uv the foot's
/// parameters, foot its position; `inside` false where the foot is clamped on an edge of the
/// surface itself with F pointing out of it (the closest point lies beyond the surface). A foot
/// clamped on an edge between elements stays inside: the neighbour's own projection is then
/// as near or nearer, and the search takes the nearest (a foot on an element corner, which all
/// four elements reach clamped, is found as such).
/// Stops when a Newton step is below 1e-12 of the element's parameter size (quadratic
/// convergence: the error after it is ~ 1e-24) or after 30 steps.
/// `warm`: Newton starts from uv as given (the previous projection) instead of the sample.
/// `tangents` (when given): S_u and S_v at the foot.
/// Whether element spans s lie at the face's edge `end` (0: start, 1: end) of direction k and
/// that edge is open (ContactFace::open: a symmetry plane; the face goes on past it).
KOKKOS_INLINE_FUNCTION bool open_past(const SurfaceData& sd, const int s[2], int k, int end, int open) {
  if (!(open & (1 << (2 * k + end)))) return false;
  return end == 0 ? s[k] == sd.p[k] : s[k] + 1 == sd.n[k];
}

/// `open` (ContactFace::open): past an open edge of the surface the element's polynomial goes
/// on (by an eighth of the element's width, as the mortar segments do), so a foot there is not
/// clamped and is inside.
KOKKOS_INLINE_FUNCTION double project_on_surface_element(const SurfaceData& sd, int e, const double x[3], double uv[2],
                                                         double foot[3], bool& inside, bool warm = false,
                                                         double (*tangents)[3] = nullptr, int open = 0) {
  const int ei[2] = {e % sd.ne[0], e / sd.ne[0]};
  int s[2];
  double lo[2], hi[2];
  for (int k = 0; k < 2; ++k) {
    s[k] = sd.span[k](ei[k]);
    lo[k] = sd.U[k](s[k]);
    hi[k] = sd.U[k](s[k] + 1);
  }
  double clo[2] = {lo[0], lo[1]}, chi[2] = {hi[0], hi[1]};   // where Newton's iterates are clamped
  for (int k = 0; k < 2; ++k) {
    if (open_past(sd, s, k, 0, open)) clo[k] = lo[k] - 0.125 * (hi[k] - lo[k]);
    if (open_past(sd, s, k, 1, open)) chi[k] = hi[k] + 0.125 * (hi[k] - lo[k]);
  }
  double d[6][3];
  double best = 1e300;
  if (warm && !(uv[0] >= clo[0] && uv[0] <= chi[0] && uv[1] >= clo[1] && uv[1] <= chi[1])) warm = false;
  for (int b = 0; b <= 2 && !warm; ++b)
    for (int a = 0; a <= 2; ++a) {
      const double t[2] = {lo[0] + 0.5 * a * (hi[0] - lo[0]), lo[1] + 0.5 * b * (hi[1] - lo[1])};
      surface_derivatives_to<0>(sd, s, t[0], t[1], d);
      double r[3];
      for (int c = 0; c < 3; ++c) r[c] = x[c] - d[0][c];
      const double dist2 = dot3(r, r);
      if (dist2 < best) {
        best = dist2;
        uv[0] = t[0];
        uv[1] = t[1];
      }
    }
  bool at_lo[2] = {false, false}, at_hi[2] = {false, false};
  double F[2] = {0, 0};
  for (int it = 0; it < 30; ++it) {
    surface_derivatives(sd, s, uv[0], uv[1], d);
    double r[3];
    for (int c = 0; c < 3; ++c) r[c] = x[c] - d[0][c];
    F[0] = dot3(r, d[1]);
    F[1] = dot3(r, d[2]);
    const double J00 = -dot3(d[1], d[1]) + dot3(r, d[3]), J01 = -dot3(d[1], d[2]) + dot3(r, d[4]),
                 J11 = -dot3(d[2], d[2]) + dot3(r, d[5]);
    const double det = J00 * J11 - J01 * J01;
    double du[2];
    if (det > 0 && J00 < 0) {   // dF negative definite: a minimum of the distance nearby
      du[0] = -(J11 * F[0] - J01 * F[1]) / det;
      du[1] = -(-J01 * F[0] + J00 * F[1]) / det;
    } else {                    // far from the surface or near a saddle: a gradient step
      const double g0 = dot3(d[1], d[1]), g1 = dot3(d[2], d[2]);
      du[0] = g0 > 0 ? F[0] / g0 : 0.0;
      du[1] = g1 > 0 ? F[1] / g1 : 0.0;
    }
    double step = 0;
    for (int k = 0; k < 2; ++k) {
      const double old = uv[k];
      uv[k] = uv[k] + du[k];
      at_lo[k] = uv[k] <= clo[k];
      at_hi[k] = uv[k] >= chi[k];
      if (at_lo[k]) uv[k] = clo[k];
      if (at_hi[k]) uv[k] = chi[k];
      const double rel = kmath::fabs(uv[k] - old) / (hi[k] - lo[k]);
      step = rel > step ? rel : step;
    }
    if (step < 1e-12) break;
  }
  surface_first_derivatives(sd, s, uv[0], uv[1], d);
  double r[3];
  for (int c = 0; c < 3; ++c) {
    foot[c] = d[0][c];
    r[c] = x[c] - d[0][c];
    if (tangents) {
      tangents[0][c] = d[1][c];
      tangents[1][c] = d[2][c];
    }
  }
  F[0] = dot3(r, d[1]);
  F[1] = dot3(r, d[2]);
  inside = true;
  for (int k = 0; k < 2; ++k) {
    const double scale = kmath::sqrt(dot3(d[1 + k], d[1 + k]) * dot3(r, r)) + 1e-300;
    const double first = sd.U[k](sd.p[k]), last = sd.U[k](sd.n[k]);   // the surface's parameter range
    if ((uv[k] <= clo[k] && lo[k] <= first && F[k] < -1e-10 * scale) || (uv[k] >= chi[k] && hi[k] >= last && F[k] > 1e-10 * scale))
      inside = false;
  }
  return dot3(r, r);
}

/// The search grid over a surface's element boxes (see the header). Built on the host from the
/// surface's control points (SurfaceSearch::build), read in kernels.
struct SurfaceSearch {
  double x0[3] = {0, 0, 0}, h = 1;
  int nc[3] = {1, 1, 1};
  Kokkos::View<long long*, MemSpace> key;   // non-empty cell ids cx + nx (cy + ny cz), increasing
  Kokkos::View<int*, MemSpace> start;       // nkeys + 1
  Kokkos::View<int*, MemSpace> elems;       // element ids per cell
  Kokkos::View<double* [6], MemSpace> box;  // per element: min x, y, z, max x, y, z

  KOKKOS_INLINE_FUNCTION int cell_of(double x, int d) const { return static_cast<int>(kmath::floor((x - x0[d]) / h)); }
  /// Range [k0, k1) of elems in cell c (empty outside the grid or for an empty cell).
  KOKKOS_INLINE_FUNCTION void cell_range(const int c[3], int& k0, int& k1) const {
    k0 = k1 = 0;
    for (int d = 0; d < 3; ++d)
      if (c[d] < 0 || c[d] >= nc[d]) return;
    const long long id = c[0] + static_cast<long long>(nc[0]) * (c[1] + static_cast<long long>(nc[1]) * c[2]);
    int lo = 0, hi = static_cast<int>(key.extent(0));
    while (lo < hi) {
      const int mid = (lo + hi) / 2;
      if (key(mid) < id) lo = mid + 1; else hi = mid;
    }
    if (lo < static_cast<int>(key.extent(0)) && key(lo) == id) { k0 = start(lo); k1 = start(lo + 1); }
  }
  /// f(e) for the element ids listed in the cells that the box [lo, hi] meets (cells in z, y,
  /// x order; an element listed in several of them comes once per cell).
  template <class F>
  KOKKOS_INLINE_FUNCTION void for_each_in_box(const double lo[3], const double hi[3], const F& f) const {
    int c0[3], c1[3];
    for (int d = 0; d < 3; ++d) {
      c0[d] = cell_of(lo[d], d);
      c1[d] = cell_of(hi[d], d);
      if (c0[d] < 0) c0[d] = 0;
      if (c1[d] > nc[d] - 1) c1[d] = nc[d] - 1;
    }
    for (int cz = c0[2]; cz <= c1[2]; ++cz)
      for (int cy = c0[1]; cy <= c1[1]; ++cy)
        for (int cx = c0[0]; cx <= c1[0]; ++cx) {
          const int c[3] = {cx, cy, cz};
          int k0, k1;
          cell_range(c, k0, k1);
          for (int k = k0; k < k1; ++k) f(elems(k));
        }
  }
  KOKKOS_INLINE_FUNCTION double box_distance2(int e, const double x[3]) const {
    double s = 0;
    for (int d = 0; d < 3; ++d) {
      const double t = x[d] < box(e, d) ? box(e, d) - x[d] : (x[d] > box(e, 3 + d) ? x[d] - box(e, 3 + d) : 0.0);
      s += t * t;
    }
    return s;
  }

  /// Builds the grid for the surface's current control points (host; cell size: the mean
  /// element box edge, so that a box meets a few cells). Cost O(M log M) for M elements.
  static SurfaceSearch build(const SurfaceData& sd) {
    SurfaceSearch g;
    const int ne = sd.ne[0] * sd.ne[1];
    auto cp = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), sd.cp);
    auto sp0 = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), sd.span[0]);
    auto sp1 = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), sd.span[1]);
    Kokkos::View<double* [6], MemSpace> box("surface_boxes", ne);
    auto hb = Kokkos::create_mirror_view(box);
    double lo[3] = {1e300, 1e300, 1e300}, hi[3] = {-1e300, -1e300, -1e300}, edge = 0;
    for (int e = 0; e < ne; ++e) {
      const int s0 = sp0(e % sd.ne[0]), s1 = sp1(e / sd.ne[0]);
      for (int d = 0; d < 3; ++d) {
        hb(e, d) = 1e300;
        hb(e, 3 + d) = -1e300;
      }
      for (int j = s1 - sd.p[1]; j <= s1; ++j)
        for (int i = s0 - sd.p[0]; i <= s0; ++i)
          for (int d = 0; d < 3; ++d) {
            const double x = cp(i + sd.n[0] * j, d);
            hb(e, d) = x < hb(e, d) ? x : hb(e, d);
            hb(e, 3 + d) = x > hb(e, 3 + d) ? x : hb(e, 3 + d);
          }
      double m = 0;
      for (int d = 0; d < 3; ++d) {
        lo[d] = hb(e, d) < lo[d] ? hb(e, d) : lo[d];
        hi[d] = hb(e, 3 + d) > hi[d] ? hb(e, 3 + d) : hi[d];
        const double w = hb(e, 3 + d) - hb(e, d);
        m = w > m ? w : m;
      }
      edge += m;
    }
    g.h = ne > 0 && edge > 0 ? edge / ne : 1.0;
    for (int d = 0; d < 3; ++d) {
      g.x0[d] = lo[d];
      g.nc[d] = static_cast<int>((hi[d] - lo[d]) / g.h) + 1;
    }
    std::vector<std::pair<long long, int>> pairs;
    for (int e = 0; e < ne; ++e) {
      int c0[3], c1[3];
      for (int d = 0; d < 3; ++d) {
        c0[d] = static_cast<int>((hb(e, d) - g.x0[d]) / g.h);
        c1[d] = static_cast<int>((hb(e, 3 + d) - g.x0[d]) / g.h);
        c1[d] = c1[d] < g.nc[d] ? c1[d] : g.nc[d] - 1;
      }
      for (int cz = c0[2]; cz <= c1[2]; ++cz)
        for (int cy = c0[1]; cy <= c1[1]; ++cy)
          for (int cx = c0[0]; cx <= c1[0]; ++cx)
            pairs.push_back({cx + static_cast<long long>(g.nc[0]) * (cy + static_cast<long long>(g.nc[1]) * cz), e});
    }
    std::sort(pairs.begin(), pairs.end());
    std::vector<long long> keys;
    std::vector<int> start, elems;
    for (size_t k = 0; k < pairs.size(); ++k) {
      if (k == 0 || pairs[k].first != pairs[k - 1].first) {
        keys.push_back(pairs[k].first);
        start.push_back(static_cast<int>(k));
      }
      elems.push_back(pairs[k].second);
    }
    start.push_back(static_cast<int>(pairs.size()));
    auto to_dev = [](const std::string& name, const auto& v) {
      using T = typename std::decay_t<decltype(v)>::value_type;
      Kokkos::View<T*, MemSpace> d(name, v.size());
      auto h = Kokkos::create_mirror_view(d);
      for (size_t k = 0; k < v.size(); ++k) h(k) = v[k];
      Kokkos::deep_copy(d, h);
      return d;
    };
    g.key = to_dev("surface_keys", keys);
    g.start = to_dev("surface_start", start);
    g.elems = to_dev("surface_elems", elems);
    Kokkos::deep_copy(box, hb);
    g.box = box;
    return g;
  }
};

/// The closest foot point to x on the surface within distance `radius` (searching the cells
/// the ball of that radius meets, candidate elements nearest box first). Returns the element
/// (-1: none within the radius), with uv, foot, the squared distance and `inside`.
/// At most kMaxCandidates boxes are projected on, nearest first: enough for points within a
/// few element sizes of a smooth surface.
constexpr int kMaxSurfaceCandidates = 64;
KOKKOS_INLINE_FUNCTION int closest_on_surface(const SurfaceData& sd, const SurfaceSearch& g, const double x[3], double radius,
                                              double uv[2], double foot[3], double& dist2, bool& inside, int open = 0) {
  int cand[kMaxSurfaceCandidates];
  double cd[kMaxSurfaceCandidates];
  int nc = 0;
  const double r2 = radius * radius;
  const double lo[3] = {x[0] - radius, x[1] - radius, x[2] - radius}, hi[3] = {x[0] + radius, x[1] + radius, x[2] + radius};
  g.for_each_in_box(lo, hi, [&](const int e) {
    const double b2 = g.box_distance2(e, x);
    if (b2 > r2) return;
    bool seen = false;
    for (int m = 0; m < nc && !seen; ++m) seen = cand[m] == e;
    if (seen) return;
    // insertion, nearest box first; beyond the capacity the farthest is dropped
    int pos = nc < kMaxSurfaceCandidates ? nc++ : kMaxSurfaceCandidates - 1;
    if (pos == kMaxSurfaceCandidates - 1 && nc == kMaxSurfaceCandidates && b2 >= cd[pos]) return;
    while (pos > 0 && cd[pos - 1] > b2) {
      cand[pos] = cand[pos - 1];
      cd[pos] = cd[pos - 1];
      --pos;
    }
    cand[pos] = e;
    cd[pos] = b2;
  });
  int best = -1;
  dist2 = 1e300;
  for (int m = 0; m < nc; ++m) {
    if (cd[m] > dist2) break;   // boxes farther than the best foot cannot hold a nearer one
    double t[2], f[3];
    bool in = false;
    const double d2 = project_on_surface_element(sd, cand[m], x, t, f, in, false, nullptr, open);
    // the nearest foot; of two equally near (a foot on an edge two elements share), the one
    // inside its element
    const bool tie = kmath::fabs(d2 - dist2) <= 1e-14 * (d2 + dist2) + 1e-300;
    if (best < 0 || (tie ? (in && !inside) : d2 < dist2)) {
      best = cand[m];
      dist2 = d2;
      inside = in;
      uv[0] = t[0];
      uv[1] = t[1];
      for (int c = 0; c < 3; ++c) foot[c] = f[c];
    }
  }
  return dist2 <= r2 ? best : -1;
}

}  // namespace iga
