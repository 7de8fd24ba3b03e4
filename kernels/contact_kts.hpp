#pragma once
// Knot-to-segment (KTS) frictionless contact: closest-point projection of the slave
// quadrature points onto the master curve and their penalty / augmented-Lagrangian
// contributions. One Kokkos::parallel_for over slave points for each stage.
//
// Kinematics (current configuration, x = X + u)
//   slave point     x_s = sum_a N_a(xi_s) x_a              (slave boundary curve)
//   master curve    rho(xi) = sum_b R_b(xi) x_b,  t = rho',  m = rho''
//   projection      f(xi) = (x_s - rho(xi)) . t(xi) = 0, Newton: dxi = -f / f',
//                   f' = -t.t + (x_s - rho) . m                        (report eq. 7-8)
//   gap             g = (x_s - rho(xi_c)) . n, n the master's outward unit normal
// Potential and pressure
//   Pi_c = sum_q w_q 1/2 eps <-g_q>^2 (penalty), p = max(0, -eps g) (kts_penalty; the ALM
//   methods, kts_alm included, pass the mortar pressure field instead: `mortar` below).
// Variations, over the element dofs u_e = [slave a = 0..ps (x,y), master b = 0..pm (x,y)]
//   N  = [N_a n ; -R_b n]    T = [N_a t ; -R_b t]    Nb = [0 ; R_b' n]
//   delta g = N . delta u
//   Delta delta g = G = -(n.m)/(a11 H) T T^T - (g/H) Nb Nb^T - (1/H)(T Nb^T + Nb T^T),
//   a11 = t.t, H = a11 - g n.m            (moving projection point and normal included)
// Contributions of an active point (g <= touch: touching counts, and a gap
// within round-off of 0 (touch = 1e-12 of the smallest slave element) is touching, as in
// mortar: bodies that touch exactly at the start are held by the first solve)
//   f_c += -p w N,     K_c += w (eps N N^T - p G)   (p G times `geometric`: 0 while Newton is
//   far from the solution, where -p G can make K_T indefinite; NewtonCore::newton)
// The contact force on the slave body is what these contributions put on the slave dofs,
// -sum_a f_c[a] (add_slave_force below): the summary reports it, so it equals the reactions.
// w = Gauss weight x |dX_s/dxi| x thickness (reference slave measure).
//
// Search: master element boxes (convex hull of their current control points, so they hold
// the curve) expanded by the largest box size go into a uniform grid; a slave point tests
// only the elements of its cell. Cost per slave point: O(elements per cell) projections of
// ~ 8 Newton steps, each ~ 30 (pm + 1) flops, independent of the number of master elements.
#include <KokkosSparse_CrsMatrix.hpp>

#include "kernels/boundary_load.hpp"
#include "kernels/types.hpp"

namespace iga {

/// A boundary curve on the device with its current displacements.
struct CurveData {
  int p = 1, nb = 0, ne = 0;
  int side = 0, orientation = 1;
  Kokkos::View<double*, MemSpace> U;        // knots
  Kokkos::View<int*, MemSpace> span;        // element spans
  Kokkos::View<double* [2], MemSpace> X;    // reference control point positions
  Kokkos::View<double*, MemSpace> w;        // weights
  Kokkos::View<double* [2], MemSpace> u;    // current control point displacements
  Kokkos::View<int*, MemSpace> lid;         // overlap cp LID for assembly, -1 if absent
};

/// Current control point positions of a curve, as curve_eval wants them.
struct CurrentCP {
  Kokkos::View<double* [2], MemSpace> X, u;
  KOKKOS_INLINE_FUNCTION double operator()(int i, int c) const { return X(i, c) + u(i, c); }
};

/// Per slave point: reference data (fixed) and projection results (per iteration).
struct SlavePoints {
  Kokkos::View<double*, MemSpace> xi, weight;  // parameter, w = Gauss x |dX/dxi| x thickness
  Kokkos::View<int*, MemSpace> span;           // slave element span
  // results
  Kokkos::View<int*, MemSpace> valid;          // 1: projection found on the master
  Kokkos::View<int*, MemSpace> mspan;          // master span of the projection
  Kokkos::View<int*, MemSpace> melem;          // master element of the projection (-1: none)
  Kokkos::View<double*, MemSpace> mxi, gap, pressure;
  Kokkos::View<double* [2], MemSpace> x;       // current slave point
  Kokkos::View<double* [2], MemSpace> normal;  // master outward normal at the projection
  double touch = 0;                            // gaps up to this count as closed (KTS)
};

/// KTS (penalty): a point with gap g is active when g <= touch (touching counts; touch absorbs
/// the round-off of an exactly closed gap).
KOKKOS_INLINE_FUNCTION bool kts_active(double g, double touch) {
  return g <= touch;
}

/// Per pair: the contact force the assembly kernels put on the slave dofs, summed as it is
/// assembled (-f_c over the slave rows): [Fx, Fy, Fn, Ft]; Fn sums each point's normal part
/// (AssembleKts: along the master normal n there) along n, Ft each point's friction part
/// (AssembleFriction: along the master tangent there) along the unit tangent e. A kernel
/// passes the direction of its own part and 0 for the other.
using ForceSum = Kokkos::View<double[4], MemSpace>;

/// Adds the slave rows' share of a point's residual contribution fr[0..nds) (pairs x, y).
KOKKOS_INLINE_FUNCTION void add_slave_force(const ForceSum& F, const double* fr, int nds, const double n[2],
                                            const double e[2]) {
  double s[4] = {0, 0, 0, 0};
  for (int r = 0; r < nds; ++r) {
    const int c = component_of_dof(r, kBoundaryDim);
    s[c] -= fr[r];
    s[2] -= fr[r] * n[c];
    s[3] -= fr[r] * e[c];
  }
  for (int k = 0; k < 4; ++k) Kokkos::atomic_add(&F(k), s[k]);
}

/// Search grid over master element boxes: a uniform grid of cell size h from (x0, y0), of
/// which only the non-empty cells are stored (a curve crosses O(M) of the grid's cells, not
/// O(M^2)): their ids cx + nx cy sorted in `key`, element ids of key[c] in
/// elems[start[c] .. start[c + 1]).
struct SearchGrid {
  double x0 = 0, y0 = 0, h = 1;
  int nx = 1, ny = 1;
  Kokkos::View<long long*, MemSpace> key;   // non-empty cell ids, increasing
  Kokkos::View<int*, MemSpace> start;       // nkeys + 1
  Kokkos::View<int*, MemSpace> elems;       // element ids per cell
  Kokkos::View<double* [4], MemSpace> box;  // per master element: xmin, ymin, xmax, ymax

  /// Range [k0, k1) of elems in cell (cx, cy); empty outside the grid or for an empty cell.
  KOKKOS_INLINE_FUNCTION void cell_range(int cx, int cy, int& k0, int& k1) const {
    k0 = k1 = 0;
    if (cx < 0 || cy < 0 || cx >= nx || cy >= ny) return;
    const long long c = cx + static_cast<long long>(nx) * cy;
    int lo = 0, hi = static_cast<int>(key.extent(0));
    while (lo < hi) {
      const int mid = (lo + hi) / 2;
      if (key(mid) < c) lo = mid + 1; else hi = mid;
    }
    if (lo < static_cast<int>(key.extent(0)) && key(lo) == c) { k0 = start(lo); k1 = start(lo + 1); }
  }
  /// Cell index of coordinate x along x (d = 0) or y (d = 1), unclamped.
  KOKKOS_INLINE_FUNCTION int cell_of(double x, int d) const {
    return static_cast<int>(kmath::floor((x - (d == 0 ? x0 : y0)) / h));
  }
};

/// Squared distance from x to an axis-aligned box.
KOKKOS_INLINE_FUNCTION double box_distance2(const SearchGrid& g, int e, const double x[2]) {
  const double dx = x[0] < g.box(e, 0) ? g.box(e, 0) - x[0] : (x[0] > g.box(e, 2) ? x[0] - g.box(e, 2) : 0.0);
  const double dy = x[1] < g.box(e, 1) ? g.box(e, 1) - x[1] : (x[1] > g.box(e, 3) ? x[1] - g.box(e, 3) : 0.0);
  return dx * dx + dy * dy;
}

/// Closest point on the master curve to x within the element of span s: Newton on
/// (x - rho) . rho' = 0 from the best of a few samples, clamped to the element.
/// Returns the squared distance and xi; `inside` is false when the projection is clamped at
/// an element end with the foot point beyond it (f = (x - rho) . t pointing out of the
/// element by more than 1e-10 of the element's length; 1e-6 at the ends of the whole curve,
/// see below). Points on the curve itself (gap 0,
/// as augmented Lagrangian solutions have) are judged by that sign, not by a ratio to the
/// distance, which round-off would decide.
/// `warm`: start Newton from xi as given (the previous projection) instead of sampling.
/// rho, t: the curve point and tangent at the returned xi.
/// Newton converges quadratically, so once a Newton step is below 1e-9 of the element's
/// parameter length the error after it is ~ 1e-18 of it: the loop stops there (a gradient
/// step, taken where f' >= 0 far from the curve, converges linearly and never stops it).
/// Cost: (3 cold) + iterations + 1 curve evaluations of ~ (12 p^2 + 30 p) flops each.
KOKKOS_INLINE_FUNCTION double project_on_element(const CurveData& m, int s, const double x[2], double& xi,
                                                 bool& inside, double rho[2], double tan[2], bool warm = false) {
  const CurrentCP cp{m.X, m.u};
  const double a = m.U(s), b = m.U(s + 1);
  const double* U = m.U.data();
  double R[3][kMaxBasis1D], r[2], t[2], dd[2];
  if (!warm || xi < a || xi > b) {
    double best = 1e300;
    const int ns = 2;
    for (int k = 0; k <= ns; ++k) {
      const double s_xi = a + (b - a) * k / ns;
      curve_eval_span(s, m.p, U, cp, m.w, s_xi, r, t, dd, R);
      const double d2 = (x[0] - r[0]) * (x[0] - r[0]) + (x[1] - r[1]) * (x[1] - r[1]);
      if (d2 < best) { best = d2; xi = s_xi; }
    }
  }
  for (int it = 0; it < 50; ++it) {
    curve_eval_span(s, m.p, U, cp, m.w, xi, r, t, dd, R);
    const double dx = x[0] - r[0], dy = x[1] - r[1];
    const double f = dx * t[0] + dy * t[1];
    const double fp = -(t[0] * t[0] + t[1] * t[1]) + dx * dd[0] + dy * dd[1];
    // Newton; a non-descent step (f' >= 0 far from the curve) falls back to a gradient step
    const bool newton = fp < 0.0;
    const double step = newton ? -f / fp : f / (t[0] * t[0] + t[1] * t[1]);
    double nxi = xi + step;
    if (nxi < a) nxi = a;
    if (nxi > b) nxi = b;
    const double moved = kmath::fabs(nxi - xi);
    xi = nxi;
    if (moved <= 1e-15 * (b - a) || (newton && moved <= 1e-9 * (b - a))) break;
  }
  curve_eval_span(s, m.p, U, cp, m.w, xi, r, t, dd, R);
  const double dx = x[0] - r[0], dy = x[1] - r[1];
  const double f = dx * t[0] + dy * t[1];
  // at an end of the whole curve a foot up to 1e-6 of the element length beyond it still
  // counts (the end itself is the closest point): where the master ends on a symmetry axis
  // its discrete end tangent tilts a little, and the slave points next to the axis, which
  // carry the peak pressure, would otherwise have no projection
  const double rel_a = s == m.p ? 1e-6 : 1e-10, rel_b = s == m.nb - 1 ? 1e-6 : 1e-10;
  const double tt = (t[0] * t[0] + t[1] * t[1]) * (b - a);
  inside = !((xi <= a && f < -rel_a * tt) || (xi >= b && f > rel_b * tt));
  for (int c = 0; c < 2; ++c) { rho[c] = r[c]; tan[c] = t[c]; }
  return dx * dx + dy * dy;
}

/// Slave point positions and projections onto the master (all slave points). The previous
/// projection (melem, mxi) is tried first and kept when it lands strictly inside its element
/// (the search runs when it is clamped at an element end or absent); melem = -1: none.
struct ProjectSlavePoints {
  CurveData s, m;
  SlavePoints sp;
  SearchGrid grid;

  KOKKOS_INLINE_FUNCTION void operator()(const int i) const {
    double R[3][kMaxBasis1D], x[2], t[2], dd[2];
    sp.valid(i) = 0;
    sp.gap(i) = 1e300;
    sp.pressure(i) = 0;
    if (sp.span(i) < 0) return;   // an unused mortar slot
    curve_eval_span(sp.span(i), s.p, s.U.data(), CurrentCP{s.X, s.u}, s.w, sp.xi(i), x, t, dd, R);
    sp.x(i, 0) = x[0];
    sp.x(i, 1) = x[1];
    int k0, kc1;
    grid.cell_range(grid.cell_of(x[0], 0), grid.cell_of(x[1], 1), k0, kc1);
    if (k0 == kc1) return;   // no master element near
    double best = 1e300, bxi = 0, brho[2] = {0, 0}, bt[2] = {1, 0};
    int bspan = -1, belem = -1;
    // projects onto master element e (from xi when warm); the nearest orthogonal projection is
    // kept. Returns whether it landed inside the element.
    auto consider = [&](int e, double xi, bool warm) {
      double r[2], tn[2];
      bool inside;
      const double d2 = project_on_element(m, m.span(e), x, xi, inside, r, tn, warm);
      if (inside && d2 < best) {
        best = d2; bxi = xi; bspan = m.span(e); belem = e;
        for (int c = 0; c < 2; ++c) { brho[c] = r[c]; bt[c] = tn[c]; }
      }
      return inside;
    };
    // warm start: the previous projection's element, from its parameter; kept without search
    // when it lands strictly inside (the closest point moved continuously)
    const int prev = sp.melem(i);
    const bool settled = prev >= 0 && consider(prev, sp.mxi(i), true) && bxi > m.U(m.span(prev)) &&
                         bxi < m.U(m.span(prev) + 1);
    // candidates of the cell in the order of their box distance, nearest first: an element
    // whose box is farther than the best projection so far cannot hold a nearer one, so the
    // search usually ends after the one or two elements whose boxes hold the point. The
    // first 64 candidates are ordered (a bit mask marks those tried); any beyond follow in
    // cell order.
    const int k1 = settled ? k0 : kc1;
    const int kord = k1 - k0 < 64 ? k1 - k0 : 64;
    unsigned long long tried = 0;
    for (int pass = 0; pass < kord; ++pass) {
      int kbest = -1;
      double dbest = best;
      for (int k = 0; k < kord; ++k) {
        if (tried >> k & 1ull) continue;
        const double d = box_distance2(grid, grid.elems(k0 + k), x);
        if (d < dbest) { dbest = d; kbest = k; }
      }
      if (kbest < 0) break;   // every box left is farther than the best projection
      tried |= 1ull << kbest;
      const int e = grid.elems(k0 + kbest);
      if (e != belem) consider(e, 0.0, false);
    }
    for (int k = k0 + kord; k < k1; ++k) {
      const int e = grid.elems(k);
      if (e != belem && box_distance2(grid, e, x) < best) consider(e, 0.0, false);
    }
    sp.melem(i) = belem;
    // none: beyond the master's ends, or outside a kink; not in contact
    if (bspan < 0) return;
    double n[2];
    side_normal(m.side, m.orientation, bt, n);
    sp.valid(i) = 1;
    sp.mspan(i) = bspan;
    sp.mxi(i) = bxi;
    sp.normal(i, 0) = n[0];
    sp.normal(i, 1) = n[1];
    sp.gap(i) = (sp.x(i, 0) - brho[0]) * n[0] + (sp.x(i, 1) - brho[1]) * n[1];
    const double pr = -eps * sp.gap(i);
    sp.pressure(i) = pr > 0 ? pr : 0.0;
  }
  double eps = 0;
};

/// kts_alm in 2-D runs on mortar's kernels at these points (one segment per slave element:
/// contact_mortar.hpp, MortarSegments::segmented), so its pressure is mortar's field
/// p = sum_A R_A <Lambda_A - eps g_A / w_A>, with no penalty per point; kts_penalty alone
/// keeps p_i = <-eps g_i> per point.

/// Residual and consistent tangent of the active slave points [p_begin, p_end).
/// Degree template P bounds both curves' degrees. `mortar`: the pressure is the mortar
/// field sum_A lambda_A R_A already in sp.pressure, and the eps N N^T part is assembled per
/// slave control point instead (contact_mortar.hpp).
template <int P, class LocalMatrix, class FView>
struct AssembleKts {
  CurveData s, m;
  SlavePoints sp;
  double eps = 0;
  int p_begin = 0;
  bool mortar = false;
  LocalMatrix K;
  FView f;
  ForceSum force;   // the slave rows' sum of -f_c (add_slave_force)
  double geometric = 1;   // the -p G part of the tangent on (1) or off (0): ContactPairData::geometric

  KOKKOS_INLINE_FUNCTION void operator()(const int k) const {
    constexpr int MaxDof = 4 * (P + 1);
    const int i = p_begin + k;
    if (!sp.valid(i)) return;
    const double g = sp.gap(i);
    if (mortar ? !(sp.pressure(i) > 0) : !kts_active(g, sp.touch)) return;
    const double pl = -eps * g;
    const double pr = mortar ? sp.pressure(i) : (pl > 0 ? pl : 0.0);
    const double epsN = mortar ? 0.0 : eps;
    const double w = sp.weight(i);
    // slave basis at xi_s
    double Rs[3][kMaxBasis1D], Rm[3][kMaxBasis1D], xs[2], ts[2], dds[2], rho[2], t[2], mm[2];
    const int ss = sp.span(i);
    curve_eval_span(ss, s.p, s.U.data(), CurrentCP{s.X, s.u}, s.w, sp.xi(i), xs, ts, dds, Rs);
    const int ms = sp.mspan(i);
    curve_eval_span(ms, m.p, m.U.data(), CurrentCP{m.X, m.u}, m.w, sp.mxi(i), rho, t, mm, Rm);
    const double n[2] = {sp.normal(i, 0), sp.normal(i, 1)};
    const double a11 = t[0] * t[0] + t[1] * t[1];
    const double nm = n[0] * mm[0] + n[1] * mm[1];
    const double H = a11 - g * nm;
    const int nds = kBoundaryDim * (s.p + 1), nd = nds + kBoundaryDim * (m.p + 1);
    double N[MaxDof], T[MaxDof], Nb[MaxDof];
    int lid[MaxDof];
    for (int a = 0; a <= s.p; ++a)
      for (int c = 0; c < 2; ++c) {
        const int r = dof_of(a, c, kBoundaryDim);
        N[r] = Rs[0][a] * n[c];
        T[r] = Rs[0][a] * t[c];
        Nb[r] = 0.0;
        lid[r] = dof_of(s.lid(ss - s.p + a), c, kBoundaryDim);
      }
    for (int b = 0; b <= m.p; ++b)
      for (int c = 0; c < 2; ++c) {
        const int r = nds + dof_of(b, c, kBoundaryDim);
        N[r] = -Rm[0][b] * n[c];
        T[r] = -Rm[0][b] * t[c];
        Nb[r] = Rm[1][b] * n[c];
        lid[r] = dof_of(m.lid(ms - m.p + b), c, kBoundaryDim);
      }
    const double cTT = -nm / (a11 * H), cNN = -g / H, cTN = -1.0 / H;
    double row[MaxDof], fr[MaxDof];
    for (int r = 0; r < nd; ++r) fr[r] = -pr * w * N[r];
    const double none[2] = {0.0, 0.0};
    add_slave_force(force, fr, nds, n, none);
    for (int r = 0; r < nd; ++r) {
      Kokkos::atomic_add(&f(lid[r]), fr[r]);
      for (int c = 0; c < nd; ++c) {
        const double G = cTT * T[r] * T[c] + cNN * Nb[r] * Nb[c] + cTN * (T[r] * Nb[c] + Nb[r] * T[c]);
        row[c] = w * (epsN * N[r] * N[c] - geometric * pr * G);
      }
      K.sumIntoValues(lid[r], lid, nd, row, false, true);
    }
  }
};

}  // namespace iga
