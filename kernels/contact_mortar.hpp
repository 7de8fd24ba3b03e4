#pragma once
// Segment-to-segment mortar contact (frictionless, normal) between NURBS boundary curves,
// for any degree 1..5 of either curve. Penalty or augmented Lagrangian on weighted gaps.
//
// Weighted gap of slave control point A (reference slave measure dGamma_0, thickness t):
//   g_A = \int_{Gamma_s} R_A(xi) g(xi) dGamma_0,   w_A = \int_{Gamma_s} R_A dGamma_0 (fixed)
//   g(xi) = (x_s(xi) - rho(eta(xi))) . n(eta),  eta(xi) the closest-point projection
// Multiplier (a pressure) and potential
//   lambda_A = <lbar_A - eps g_A / w_A>,   Pi = sum_A w_A / (2 eps) lambda_A^2
//   (penalty: lbar = 0; ALM: lbar <- lambda between Newton solves). Active: lbar_A -
//   eps g_A / w_A >= -eps touch, so a zero weighted gap (and one within round-off of 0,
//   touch = 1e-12 of the smallest slave element) is in contact, as a touching KTS point is.
//   Pressure field
//   p(xi) = sum_A lambda_A R_A(xi): a uniform lambda transmits a uniform pressure exactly
//   (partition of unity), which is why mortar passes the contact patch test.
// Residual and tangent
//   f_c = -sum_A lambda_A delta g_A = -\int p(xi) N dGamma_0          (per quadrature point)
//   K_c = sum_{A active} eps / w_A delta g_A (x) delta g_A             (per slave cp A)
//         - \int p(xi) G dGamma_0                                      (per quadrature point)
//   with delta g = N . delta u and Delta delta g = G of the pointwise gap (contact_kts.hpp).
//   The segment end points move with u, but the integrand is continuous across them, so
//   their derivatives cancel, except at the image of a master end, where the covered part of
//   a slave element ends (MortarEnds: the boundary terms there).
// Segments: a slave element [a, b] is cut where master knots project onto it: for a master
//   knot eta_k with rho_k, t_k the cut xi solves (x_s(xi) - rho_k) . t_k = 0 (the slave point
//   whose closest master point is the knot); candidate knots are those of the master elements
//   in the search-grid cells that the slave element's box overlaps. Each segment gets its own
//   Gauss rule, so the integrand is smooth on every piece. kts_alm uses these kernels with
//   one segment per slave element (segmented = false: its KTS points, no cuts), so the gap's
//   kink at a master knot inside a slave element is left to the Gauss rule.
// Layout: the slave quadrature points are slots of SlavePoints, max_segments x nq per slave
//   element (element-major, segments in increasing xi); unused slots have span = -1.
//   max_segments is a run-time capacity: MortarSegments reports how many segments an element
//   needs (flags(0), a maximum) and the host grows the slots and runs it again, so any ratio
//   of slave to master element sizes is handled. cuts(e, k): scratch for the cut points.
//   Per slave control point A: w_A, g_A, lbar_A, lambda_A, active_A (views over slave cps).
//   The variations of A (delta g_A, and friction's V_A) live on a dense dof range
//   (SupportRange: the slave cps A - p .. A + p and the master cps its support points project
//   into), in per-A scratch rows of a run-time capacity grown the same way (flags(1)).
// Cost per slave element: ~ (candidates) x 10 Newton steps x 20 (p + 1) flops for the cuts;
//   per slave cp A: (p + 1) elements x slots x basis evaluation ~ 15 (p + 1)^2 flops.
#include "kernels/contact_kts.hpp"

namespace iga {

constexpr int kMortarInitialSegments = 16;   // segments per slave element to start with
constexpr int kMortarInitialEntries = 160;   // dofs per delta g_A to start with

struct MortarState {
  Kokkos::View<double*, MemSpace> wA, gA, lbar, lambda;
  Kokkos::View<int*, MemSpace> active, covered;
  /// The covered part of w_A (int R_A over the support's slots that have a projection); where
  /// it is a sliver of w_A (a master's end inside A's support) the multiplier acts on that
  /// sliver only and cannot close g_A: the ALM test leaves such A out (sliver())
  Kokkos::View<double*, MemSpace> cwA;
  /// A's support covered on less than 1e-3 of w_A (host copies cw, w of cwA, wA)
  static bool sliver(double cw, double w) { return cw < 1e-3 * w; }
  /// ALM: a factor on the penalty per control point, w_A / cw_A where the master covers A's
  /// support in part (at most kMaxScale; 1 elsewhere; empty: 1 everywhere), set at each
  /// multiplier update and held through the Newton solve that follows (scale_partly_covered).
  /// A multiplier that acts on a part cw_A of its support closes g_A as a penalty of
  /// eps cw_A / w_A would: a slave wider than its master stalled at 0.89 per update. The
  /// converged answer (g_A = 0 where lambda_A > 0) does not depend on it.
  Kokkos::View<double*, MemSpace> scale;
  static constexpr double kMaxScale = 100;
  // maxima of what was needed where a capacity was short: [0] segments of one slave
  // element, [1] dofs of one delta g_A (0: every capacity sufficed)
  Kokkos::View<int*, MemSpace> flags;
};

/// Per-A scratch rows of the assembly kernels (row k for A = a_begin + k): dof ids and up to
/// two value arrays and a matrix row, `cap` entries each.
struct MortarScratch {
  Kokkos::View<int**, Kokkos::LayoutRight, MemSpace> dof;
  Kokkos::View<double**, Kokkos::LayoutRight, MemSpace> v0, v1, row;
  KOKKOS_INLINE_FUNCTION int cap() const { return static_cast<int>(dof.extent(1)); }
};

/// Reference control point positions (for the reference Jacobian).
struct RefCP {
  Kokkos::View<double* [2], MemSpace> X;
  KOKKOS_INLINE_FUNCTION double operator()(int i, int c) const { return X(i, c); }
};

/// Cuts of slave element e by the master knots, and its quadrature slots.
struct MortarSegments {
  CurveData s, m;
  SlavePoints sp;
  SearchGrid grid;
  GaussRule gauss;
  double thickness = 1;
  int max_segments = kMortarInitialSegments;
  /// false: one segment per slave element, its Gauss rule on the whole element (kts_alm:
  /// element-based integration of the weighted gaps, no cuts at the master knots' images)
  bool segmented = true;
  Kokkos::View<double**, Kokkos::LayoutRight, MemSpace> cuts;   // ne x (max_segments + 1) scratch
  Kokkos::View<int*, MemSpace> flags;

  KOKKOS_INLINE_FUNCTION int slots() const { return max_segments * gauss.n; }

  // root of (x_s(xi) - rho) . t on the slave element [a, b] of span `span` (bracketed
  // Newton); xa, xb are the slave's current points at a and b. false if no sign change.
  KOKKOS_INLINE_FUNCTION bool cut(int span, double a, double b, const double xa[2], const double xb[2],
                                  const double rho[2], const double t[2], double& xi) const {
    const CurrentCP cp{s.X, s.u};
    double R[3][kMaxBasis1D], x[2], dx[2], ddx[2];
    const double fa = (xa[0] - rho[0]) * t[0] + (xa[1] - rho[1]) * t[1];
    const double fb = (xb[0] - rho[0]) * t[0] + (xb[1] - rho[1]) * t[1];
    if ((fa > 0 && fb > 0) || (fa < 0 && fb < 0) || fa == 0 || fb == 0) return false;
    double lo = a, hi = b;
    const bool up = fa < 0;   // f increasing from lo to hi
    xi = a + (b - a) * fa / (fa - fb);
    for (int it = 0; it < 100; ++it) {
      curve_eval_span(span, s.p, s.U.data(), cp, s.w, xi, x, dx, ddx, R);
      const double f = (x[0] - rho[0]) * t[0] + (x[1] - rho[1]) * t[1];
      const double fp = dx[0] * t[0] + dx[1] * t[1];
      if (f == 0) break;
      if ((f < 0) == up) lo = xi; else hi = xi;
      double nxi = fp != 0 ? xi - f / fp : 0.5 * (lo + hi);
      if (!(nxi > lo && nxi < hi)) nxi = 0.5 * (lo + hi);
      const double moved = kmath::fabs(nxi - xi);
      xi = nxi;
      if (moved <= 1e-16 * (b - a) || hi - lo <= 1e-16 * (b - a)) break;
    }
    return true;
  }

  KOKKOS_INLINE_FUNCTION void operator()(const int e) const {
    const int span = s.span(e);
    const double a = s.U(span), b = s.U(span + 1);
    double* bp = &cuts(e, 1);   // interior cuts; cuts(e, 0) = a, cuts(e, nbp + 1) = b
    int nbp = 0, found = 0;     // stored, and found (more than stored where short of room)
    // box of the slave element (its current control points hold it)
    double lo[2] = {1e300, 1e300}, hi[2] = {-1e300, -1e300};
    for (int k = span - s.p; k <= span; ++k)
      for (int c = 0; c < 2; ++c) {
        const double v = s.X(k, c) + s.u(k, c);
        lo[c] = v < lo[c] ? v : lo[c];
        hi[c] = v > hi[c] ? v : hi[c];
      }
    const int cx0 = grid.cell_of(lo[0], 0), cx1 = grid.cell_of(hi[0], 0);
    const int cy0 = grid.cell_of(lo[1], 1), cy1 = grid.cell_of(hi[1], 1);
    const CurrentCP mcp{m.X, m.u};
    double xa[2], xb[2];
    {
      double R[3][kMaxBasis1D], dx[2], ddx[2];
      curve_eval_span(span, s.p, s.U.data(), CurrentCP{s.X, s.u}, s.w, a, xa, dx, ddx, R);
      curve_eval_span(span, s.p, s.U.data(), CurrentCP{s.X, s.u}, s.w, b, xb, dx, ddx, R);
    }
    for (int cy = cy0 < 0 ? 0 : cy0; segmented && cy <= cy1 && cy < grid.ny; ++cy)
      for (int cx = cx0 < 0 ? 0 : cx0; cx <= cx1 && cx < grid.nx; ++cx) {
        int k0, k1;
        grid.cell_range(cx, cy, k0, k1);
        for (int k = k0; k < k1; ++k) {
          const int me = grid.elems(k);
          for (int end = 0; end < 2; ++end) {
            const double eta = m.U(m.span(me) + end);
            double R[3][kMaxBasis1D], rho[2], t[2], dd[2];
            curve_eval(m.nb, m.p, m.U.data(), mcp, m.w, eta, rho, t, dd, R);
            double xi;
            if (!cut(span, a, b, xa, xb, rho, t, xi)) continue;
            if (xi <= a + 1e-12 * (b - a) || xi >= b - 1e-12 * (b - a)) continue;
            bool dup = false;
            for (int j = 0; j < nbp; ++j) dup = dup || kmath::fabs(bp[j] - xi) <= 1e-12 * (b - a);
            if (dup) continue;
            ++found;   // an upper bound once storage is short (duplicates are not seen then)
            if (nbp + 1 < max_segments) bp[nbp++] = xi;
          }
        }
      }
    if (found > nbp) {   // short of room: report what is needed, leave the slots to the rerun
      Kokkos::atomic_fetch_max(&flags(0), found + 1);
      return;
    }
    // sorted cut points with the element ends
    for (int i = 1; i < nbp; ++i)
      for (int j = i; j > 0 && bp[j - 1] > bp[j]; --j) {
        const double tmp = bp[j]; bp[j] = bp[j - 1]; bp[j - 1] = tmp;
      }
    cuts(e, 0) = a;
    cuts(e, nbp + 1) = b;
    const int base = e * slots();
    const RefCP ref{s.X};
    for (int seg = 0; seg < max_segments; ++seg)
      for (int q = 0; q < gauss.n; ++q) {
        const int i = base + seg * gauss.n + q;
        sp.melem(i) = -1;   // slots move between updates: no warm start
        if (seg > nbp) {
          sp.span(i) = -1;
          sp.xi(i) = a;
          sp.weight(i) = 0;
          continue;
        }
        const double h = 0.5 * (cuts(e, seg + 1) - cuts(e, seg));
        const double xi = cuts(e, seg) + h * (gauss.x[q] + 1.0);
        double R[3][kMaxBasis1D], X[2], dX[2], ddX[2];
        curve_eval_span(span, s.p, s.U.data(), ref, s.w, xi, X, dX, ddX, R);
        sp.span(i) = span;
        sp.xi(i) = xi;
        sp.weight(i) = gauss.w[q] * h * kmath::sqrt(dX[0] * dX[0] + dX[1] * dX[1]) * thickness;
      }
  }
};

/// Where the master ends inside a slave element (a punch as the master of a longer slave), the
/// slots of that element's segments on one side of the master end's image xi_c have a
/// projection and those on the other none: the covered part of the element ends at xi_c,
/// which moves with u. The integrals over the covered part then have boundary terms (the
/// integrand jumps there to 0; at the images of interior master knots it is continuous and
/// their derivatives cancel):
///   d/du int_cov f dGamma_0 = ... + s f(xi_c) j0(xi_c) dxi_c/du,   s = +1 where the covered
///   part lies below xi_c, -1 above; j0 = |X_s'| thickness.
/// xi_c solves F = (x_s(xi) - rho_e) . t_e = 0 (MortarSegments' cut), rho_e and t_e = rho'
/// at the master's end eta_e, so dxi_c/du = V = -(dF/du) / (x_s' . t_e) with
///   dF/du_s(a) = R_s,a(xi_c) t_e,   dF/du_m(b) = -R_m,b(eta_e) t_e + (x_s - rho_e) R'_m,b(eta_e).
/// The tangent gets (AssembleMortarGap, AssembleMortarEnds):
///   eps / w_A (int R_A N) (x) s R_A(xi_c) j0 g(xi_c) V     (the weighted gap's limit)
///   - s p(xi_c) j0 N(xi_c) (x) V                           (the pressure term's limit)
/// The residual keeps -int_cov p N (as in 3-D, kernels/contact_mortar3.hpp). Frictionless
/// terms only: mortar friction's slip integrals have no boundary terms in 2-D.
struct MortarEnds {
  Kokkos::View<double**, Kokkos::LayoutRight, MemSpace> xi, eta;   // (ne, 2): xi_c, eta_e
  Kokkos::View<int**, Kokkos::LayoutRight, MemSpace> sign, mspan;  // (ne, 2): s (0: none), eta_e's span
};

/// Per slave element: the cuts between two segments whose neighbouring slots differ in
/// having a projection, where the cut is the image of one of the master curve's ends (up to 2).
struct FindMortarEnds {
  CurveData s, m;
  SlavePoints sp;
  MortarEnds ends;
  Kokkos::View<double**, Kokkos::LayoutRight, MemSpace> cuts;
  int nq = 1, max_segments = 1;

  KOKKOS_INLINE_FUNCTION void operator()(const int e) const {
    ends.sign(e, 0) = ends.sign(e, 1) = 0;
    const int span = s.span(e), base = e * max_segments * nq;
    const double a = s.U(span), b = s.U(span + 1);
    int n = 0;
    for (int seg = 0; seg + 1 < max_segments && n < 2; ++seg) {
      const int lo = base + seg * nq + nq - 1, hi = base + (seg + 1) * nq;
      if (sp.span(hi) < 0) break;   // no segment above this one
      if ((sp.valid(lo) != 0) == (sp.valid(hi) != 0)) continue;
      const double xi = cuts(e, seg + 1);
      double R[3][kMaxBasis1D], x[2], dx[2], dd[2], xa[2], xb[2];
      curve_eval_span(span, s.p, s.U.data(), CurrentCP{s.X, s.u}, s.w, a, xa, dx, dd, R);
      curve_eval_span(span, s.p, s.U.data(), CurrentCP{s.X, s.u}, s.w, b, xb, dx, dd, R);
      curve_eval_span(span, s.p, s.U.data(), CurrentCP{s.X, s.u}, s.w, xi, x, dx, dd, R);
      const double chord = kmath::sqrt((xb[0] - xa[0]) * (xb[0] - xa[0]) + (xb[1] - xa[1]) * (xb[1] - xa[1]));
      // the master end whose cut this is: F = (x - rho) . t / |t| at round-off
      int best = -1;
      double bd = 1e300;
      for (int end = 0; end < 2; ++end) {
        const int ms = m.span(end == 0 ? 0 : m.ne - 1);
        const double eta = m.U(end == 0 ? ms : ms + 1);
        double Rm[3][kMaxBasis1D], rho[2], t[2], mm[2];
        curve_eval_span(ms, m.p, m.U.data(), CurrentCP{m.X, m.u}, m.w, eta, rho, t, mm, Rm);
        const double tl = kmath::sqrt(t[0] * t[0] + t[1] * t[1]);
        const double F = ((x[0] - rho[0]) * t[0] + (x[1] - rho[1]) * t[1]) / tl;
        const double d = (x[0] - rho[0]) * (x[0] - rho[0]) + (x[1] - rho[1]) * (x[1] - rho[1]);
        if (kmath::fabs(F) <= 1e-9 * chord && d < bd) {
          bd = d;
          best = end;
          ends.eta(e, n) = eta;
          ends.mspan(e, n) = ms;
        }
      }
      if (best < 0) continue;
      ends.xi(e, n) = xi;
      ends.sign(e, n) = sp.valid(lo) ? 1 : -1;
      ++n;
    }
  }
};

/// At end record (e, k): the slave basis Rs at xi_c, the master basis Rm at eta_e, the
/// master normal n there, the gap g, j0 and V = dxi_c/du on the slave span's dofs (Vs, 2 per
/// cp) and the master span's (Vm).
KOKKOS_INLINE_FUNCTION void mortar_end_point(const CurveData& s, const CurveData& m, const MortarEnds& ends, int e,
                                             int k, double thickness, double Rs[3][kMaxBasis1D],
                                             double Rm[3][kMaxBasis1D], double n[2], double& g, double& j0,
                                             double* Vs, double* Vm) {
  const int span = s.span(e), ms = ends.mspan(e, k);
  const double xi = ends.xi(e, k);
  double x[2], dx[2], dd[2], X[2], dX[2], rho[2], t[2], mm[2];
  curve_eval_span(span, s.p, s.U.data(), RefCP{s.X}, s.w, xi, X, dX, dd, Rs);
  j0 = kmath::sqrt(dX[0] * dX[0] + dX[1] * dX[1]) * thickness;
  curve_eval_span(span, s.p, s.U.data(), CurrentCP{s.X, s.u}, s.w, xi, x, dx, dd, Rs);
  curve_eval_span(ms, m.p, m.U.data(), CurrentCP{m.X, m.u}, m.w, ends.eta(e, k), rho, t, mm, Rm);
  side_normal(m.side, m.orientation, t, n);
  const double d[2] = {x[0] - rho[0], x[1] - rho[1]};
  g = d[0] * n[0] + d[1] * n[1];
  const double D = dx[0] * t[0] + dx[1] * t[1];
  for (int a = 0; a <= s.p; ++a)
    for (int c = 0; c < 2; ++c) Vs[2 * a + c] = -Rs[0][a] * t[c] / D;
  for (int b = 0; b <= m.p; ++b)
    for (int c = 0; c < 2; ++c) Vm[2 * b + c] = (Rm[0][b] * t[c] - d[c] * Rm[1][b]) / D;
}

/// The pressure term's boundary part, K_c -= s p(xi_c) j0 N(xi_c) (x) V, at the end records
/// of this rank's slave elements [e_begin, e_end) (each element on the rank of its first slot).
template <class LocalMatrix>
struct AssembleMortarEnds {
  CurveData s, m;
  MortarState ms;
  MortarEnds ends;
  double thickness = 1;
  int e_begin = 0;
  LocalMatrix K;

  KOKKOS_INLINE_FUNCTION void operator()(const int k0) const {
    const int e = e_begin + k0;
    for (int k = 0; k < 2; ++k) {
      if (ends.sign(e, k) == 0) continue;
      double Rs[3][kMaxBasis1D], Rm[3][kMaxBasis1D], n[2], g, j0, Vs[2 * kMaxBasis1D], Vm[2 * kMaxBasis1D];
      mortar_end_point(s, m, ends, e, k, thickness, Rs, Rm, n, g, j0, Vs, Vm);
      const int span = s.span(e), mspan = ends.mspan(e, k);
      double pr = 0;
      for (int a = 0; a <= s.p; ++a) pr += ms.lambda(span - s.p + a) * Rs[0][a];
      if (!(pr > 0)) continue;
      const double c = -ends.sign(e, k) * pr * j0;
      const int ns = 2 * (s.p + 1), nd = ns + 2 * (m.p + 1);
      int lid[4 * kMaxBasis1D];
      double N[4 * kMaxBasis1D], V[4 * kMaxBasis1D], row[4 * kMaxBasis1D];
      for (int a = 0; a <= s.p; ++a)
        for (int q = 0; q < 2; ++q) {
          const int cp = s.lid(span - s.p + a);
          lid[2 * a + q] = cp < 0 ? -1 : dof_of(cp, q, kBoundaryDim);
          N[2 * a + q] = Rs[0][a] * n[q];
          V[2 * a + q] = Vs[2 * a + q];
        }
      for (int b = 0; b <= m.p; ++b)
        for (int q = 0; q < 2; ++q) {
          const int cp = m.lid(mspan - m.p + b);
          lid[ns + 2 * b + q] = cp < 0 ? -1 : dof_of(cp, q, kBoundaryDim);
          N[ns + 2 * b + q] = -Rm[0][b] * n[q];
          V[ns + 2 * b + q] = Vm[2 * b + q];
        }
      for (int r = 0; r < nd; ++r) {
        if (lid[r] < 0 || N[r] == 0) continue;
        int cols[4 * kMaxBasis1D], nc = 0;
        for (int q = 0; q < nd; ++q) {
          if (lid[q] < 0 || V[q] == 0) continue;
          cols[nc] = lid[q];
          row[nc++] = c * N[r] * V[q];
        }
        if (nc > 0) K.sumIntoValues(lid[r], cols, nc, row, false, true);
      }
    }
  }
};

/// The first slave element whose span is >= A (element spans increase): with those after it
/// whose span is <= A + p, the elements of slave control point A's support.
KOKKOS_INLINE_FUNCTION int first_support_element(const CurveData& s, int A) {
  int lo = 0, hi = s.ne;
  while (lo < hi) {
    const int mid = (lo + hi) / 2;
    if (s.span(mid) < A) lo = mid + 1; else hi = mid;
  }
  return lo;
}

/// Loops over the valid quadrature slots in the support of slave control point A:
/// f(i, slave span). Support: slave elements with span in [A, A + p].
template <class F>
KOKKOS_INLINE_FUNCTION void for_each_support_slot(const CurveData& s, const SlavePoints& sp, int slots, int A, const F& f) {
  for (int e = first_support_element(s, A); e < s.ne && s.span(e) <= A + s.p; ++e)
    for (int i = e * slots; i < (e + 1) * slots; ++i) {
      if (sp.span(i) < 0 || !sp.valid(i)) continue;
      const int a = A - (sp.span(i) - s.p);
      if (a < 0 || a > s.p) continue;
      f(i, sp.span(i));
    }
}

/// The same slots with the slave basis evaluated there: f(i, R_A(xi_i), Rs, slave span).
template <class F>
KOKKOS_INLINE_FUNCTION void for_each_support_point(const CurveData& s, const SlavePoints& sp, int slots, int A,
                                                   const F& f) {
  for_each_support_slot(s, sp, slots, A, [&](int i, int span) {
    double R[3][kMaxBasis1D], x[2], dx[2], ddx[2];
    curve_eval_span(span, s.p, s.U.data(), CurrentCP{s.X, s.u}, s.w, sp.xi(i), x, dx, ddx, R);
    f(i, R[0][A - (span - s.p)], R, span);
  });
}

/// The penalty of control point A: eps times its scale (MortarState::scale).
KOKKOS_INLINE_FUNCTION double mortar_eps(const MortarState& ms, int A, double eps) {
  return ms.scale.extent(0) > 0 ? eps * ms.scale(A) : eps;
}

/// Slave control point A's weighted gap g (cov: some slot of its support has a projection),
/// multiplier and activity: lambda_A = <lbar_A - eps_A g / w_A> (eps_A = mortar_eps), active at
/// >= -eps touch. One rule for 2-D and 3-D (MortarGaps, MortarGaps3).
KOKKOS_INLINE_FUNCTION void mortar_multiplier(const MortarState& ms, int A, double g, int cov, double eps, double touch) {
  ms.gA(A) = g;
  ms.covered(A) = cov;
  const double l = ms.lbar(A) - mortar_eps(ms, A, eps) * g / ms.wA(A);
  ms.active(A) = cov && l >= -eps * touch ? 1 : 0;
  ms.lambda(A) = cov && l > 0 ? l : 0.0;
}

/// MortarState::scale from the covered weights of the last update (ALM: at each multiplier
/// update, so that it is held through the Newton solve that follows and the tangent stays
/// consistent). Slivers (MortarState::sliver) and fully covered points keep 1.
inline void scale_partly_covered(const MortarState& ms) {
  const auto w = ms.wA, cw = ms.cwA, s = ms.scale;
  Kokkos::parallel_for("iga::MortarScale", Kokkos::RangePolicy<ExecSpace>(0, static_cast<int>(s.extent(0))),
                       KOKKOS_LAMBDA(const int A) {
                         const double r = cw(A) >= 1e-3 * w(A) && cw(A) < w(A) ? w(A) / cw(A) : 1.0;
                         s(A) = r < MortarState::kMaxScale ? r : MortarState::kMaxScale;
                       });
}

/// Weighted gaps, multipliers and the active set of every slave control point.
struct MortarGaps {
  CurveData s;
  SlavePoints sp;
  MortarState ms;
  double eps = 0;
  double touch = 0;   // gaps below this count as touching (round-off of exactly closed gaps)
  int slots = 1;

  KOKKOS_INLINE_FUNCTION void operator()(const int A) const {
    double g = 0;
    int cov = 0;
    const SlavePoints& p = sp;
    double cw = 0;
    for_each_support_point(s, sp, slots, A, [&](int i, double RA, const double (*)[kMaxBasis1D], int) {
      g += RA * p.weight(i) * p.gap(i);
      cw += RA * p.weight(i);
      cov = 1;
    });
    if (A < static_cast<int>(ms.cwA.extent(0))) ms.cwA(A) = cw;
    mortar_multiplier(ms, A, g, cov, eps, touch);
  }
};

/// Pressure at the quadrature slots: p(xi) = sum_A lambda_A R_A(xi).
struct MortarPointPressure {
  CurveData s;
  SlavePoints sp;
  MortarState ms;

  KOKKOS_INLINE_FUNCTION void operator()(const int i) const {
    if (sp.span(i) < 0 || !sp.valid(i)) { sp.pressure(i) = 0; return; }
    double R[3][kMaxBasis1D], x[2], dx[2], ddx[2];
    const int span = sp.span(i);
    curve_eval_span(span, s.p, s.U.data(), CurrentCP{s.X, s.u}, s.w, sp.xi(i), x, dx, ddx, R);
    double pr = 0;
    for (int a = 0; a <= s.p; ++a) pr += ms.lambda(span - s.p + a) * R[0][a];
    sp.pressure(i) = pr;
  }
};

/// The dofs that the variations of slave control point A touch, as one dense range: the
/// slave cps A - p .. A + p, then the master cps [m_lo, m_lo + nm) into which A's support
/// points project; entry index of (cp, component) by slave() / master(). One helper for the
/// gap (AssembleMortarGap) and friction (AssembleMortarFriction) tangents.
struct SupportRange {
  int s_lo = 0, ns = 0, m_lo = 0, nm = 0;
  KOKKOS_INLINE_FUNCTION int size() const { return kBoundaryDim * (ns + nm); }
  KOKKOS_INLINE_FUNCTION int slave(int cp, int c) const { return dof_of(cp - s_lo, c, kBoundaryDim); }
  KOKKOS_INLINE_FUNCTION int master(int cp, int c) const { return dof_of(ns + cp - m_lo, c, kBoundaryDim); }
};

KOKKOS_INLINE_FUNCTION SupportRange support_range(const CurveData& s, const CurveData& m, const SlavePoints& sp,
                                                  int slots, int A) {
  SupportRange r;
  r.s_lo = A - s.p;
  r.ns = 2 * s.p + 1;
  int lo = m.nb, hi = -1;
  for_each_support_slot(s, sp, slots, A, [&](int i, int) {
    const int ms = sp.mspan(i);
    lo = ms - m.p < lo ? ms - m.p : lo;
    hi = ms > hi ? ms : hi;
  });
  r.m_lo = hi < 0 ? 0 : lo;
  r.nm = hi < 0 ? 0 : hi - lo + 1;
  return r;
}

/// Scratch row k, zeroed over the range; false (and flags(1) raised to what is needed) when
/// the capacity is short.
KOKKOS_INLINE_FUNCTION bool support_scratch(const MortarScratch& sc, int k, const SupportRange& r,
                                            const Kokkos::View<int*, MemSpace>& flags) {
  if (r.size() > sc.cap()) {
    Kokkos::atomic_fetch_max(&flags(1), r.size());
    return false;
  }
  for (int q = 0; q < r.size(); ++q) { sc.v0(k, q) = 0; sc.v1(k, q) = 0; }
  return true;
}

/// Compacts scratch row k to the entries that were touched (a non-zero value): their
/// overlap dofs in sc.dof(k, .), the values moved along; returns their count.
KOKKOS_INLINE_FUNCTION int support_compact(const MortarScratch& sc, int k, const SupportRange& r, const CurveData& s,
                                           const CurveData& m) {
  int n = 0;
  for (int q = 0; q < r.size(); ++q) {
    if (sc.v0(k, q) == 0 && sc.v1(k, q) == 0) continue;
    const int cp = point_of_dof(q, kBoundaryDim), c = component_of_dof(q, kBoundaryDim);
    const int lid = cp < r.ns ? s.lid(r.s_lo + cp) : m.lid(r.m_lo + cp - r.ns);
    if (lid < 0) continue;
    sc.dof(k, n) = dof_of(lid, c, kBoundaryDim);
    sc.v0(k, n) = sc.v0(k, q);
    sc.v1(k, n++) = sc.v1(k, q);
  }
  return n;
}

/// Sums c a (x) b over the compacted row k into K (a, b: v0 or v1 of the row).
template <class LocalMatrix>
KOKKOS_INLINE_FUNCTION void support_outer(const MortarScratch& sc, int k, int n, double c, bool b_is_v1,
                                          const LocalMatrix& K) {
  int* dof = &sc.dof(k, 0);
  double* row = &sc.row(k, 0);
  for (int r = 0; r < n; ++r) {
    for (int q = 0; q < n; ++q) row[q] = c * sc.v0(k, r) * (b_is_v1 ? sc.v1(k, q) : sc.v0(k, q));
    K.sumIntoValues(dof[r], dof, n, row, false, true);
  }
}

/// K_c += eps / w_A delta g_A (x) delta g_A for the active slave control points [a_begin, ...).
/// delta g_A = sum over A's support points of R_A w (N_s . n - N_m . n) (contact_kts.hpp).
template <class LocalMatrix>
struct AssembleMortarGap {
  CurveData s, m;
  SlavePoints sp;
  MortarState ms;
  MortarScratch sc;
  MortarEnds ends;          // the master ends' images (none: empty views)
  double thickness = 1;
  double eps = 0;
  int slots = 1, a_begin = 0;
  LocalMatrix K;

  KOKKOS_INLINE_FUNCTION void operator()(const int k) const {
    const int A = a_begin + k;
    if (!ms.active(A)) return;
    const SupportRange r = support_range(s, m, sp, slots, A);
    if (!support_scratch(sc, k, r, ms.flags)) return;
    const SlavePoints& p = sp;
    const MortarScratch& S = sc;
    const CurveData& M = m;
    for_each_support_point(s, sp, slots, A, [&](int i, double RA, const double (*Rs)[kMaxBasis1D], int span) {
      const double w = RA * p.weight(i);
      const double nn[2] = {p.normal(i, 0), p.normal(i, 1)};
      for (int a = 0; a <= s.p; ++a)
        for (int c = 0; c < 2; ++c) S.v0(k, r.slave(span - s.p + a, c)) += w * Rs[0][a] * nn[c];
      double Rm[3][kMaxBasis1D], rho[2], t[2], dd[2];
      const int mspan = p.mspan(i);
      curve_eval_span(mspan, M.p, M.U.data(), CurrentCP{M.X, M.u}, M.w, p.mxi(i), rho, t, dd, Rm);
      for (int b = 0; b <= M.p; ++b)
        for (int c = 0; c < 2; ++c) S.v0(k, r.master(mspan - M.p + b, c)) -= w * Rm[0][b] * nn[c];
    });
    // the weighted gap's boundary terms where a master end's image lies in A's support
    for (int q = 0; q < r.size(); ++q) S.v1(k, q) = S.v0(k, q);
    if (ends.sign.extent(0) > 0) {
      for (int e = first_support_element(s, A); e < s.ne && s.span(e) <= A + s.p; ++e)
        for (int j = 0; j < 2; ++j) {
          if (ends.sign(e, j) == 0) continue;
          double Rs[3][kMaxBasis1D], Rm[3][kMaxBasis1D], n[2], g, j0, Vs[2 * kMaxBasis1D], Vm[2 * kMaxBasis1D];
          mortar_end_point(s, m, ends, e, j, thickness, Rs, Rm, n, g, j0, Vs, Vm);
          const int span = s.span(e), mspan = ends.mspan(e, j);
          const double c = ends.sign(e, j) * Rs[0][A - (span - s.p)] * j0 * g;
          for (int a = 0; a <= s.p; ++a)
            for (int q = 0; q < 2; ++q) S.v1(k, r.slave(span - s.p + a, q)) += c * Vs[2 * a + q];
          for (int b = 0; b <= m.p; ++b) {
            const int cp = mspan - m.p + b;
            if (cp < r.m_lo || cp >= r.m_lo + r.nm) continue;   // (not in A's support: not reached)
            for (int q = 0; q < 2; ++q) S.v1(k, r.master(cp, q)) += c * Vm[2 * b + q];
          }
        }
    }
    const int n = support_compact(sc, k, r, s, m);
    support_outer(sc, k, n, mortar_eps(ms, A, eps) / ms.wA(A), true, K);
  }
};

}  // namespace iga
