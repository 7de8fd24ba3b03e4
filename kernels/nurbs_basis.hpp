#pragma once
// NURBS basis evaluation, callable from host and from any Kokkos execution space.
//
// B-spline basis and derivatives follow Piegl & Tiller, "The NURBS Book", A2.1 (span search)
// and A2.3 (derivatives). All arrays are fixed-size (kMaxDegree), so nothing here allocates;
// the functions are KOKKOS_INLINE_FUNCTION and used both inside kernels and by host code
// (refinement, sampling, tests), which keeps one definition of the basis in the project.
//
// Conventions
//   U      knot vector, nb + p + 1 entries, open (first and last knot repeated p + 1 times)
//   nb     number of basis functions
//   span   index s with U[s] <= u < U[s+1]; the functions N_{s-p..s} are the non-zero ones
//   ders[k][j]  k-th derivative of N_{s-p+j}(u), k = 0..nd, j = 0..p
#include <Kokkos_Core.hpp>

namespace iga {

// Device math: Kokkos 3.4 has it under Kokkos::Experimental, later versions under Kokkos.
#if KOKKOS_VERSION >= 30700
namespace kmath { using Kokkos::sqrt; using Kokkos::fabs; using Kokkos::floor; using Kokkos::log; using Kokkos::nan; }
#else
namespace kmath { using Kokkos::Experimental::sqrt; using Kokkos::Experimental::fabs; using Kokkos::Experimental::floor; using Kokkos::Experimental::log; using Kokkos::Experimental::nan; }
#endif

constexpr int kMaxDegree = 5;
constexpr int kMaxBasis1D = kMaxDegree + 1;

/// Knot span containing u. At the right end (u == U[nb]) the last non-empty span is returned.
KOKKOS_INLINE_FUNCTION int find_span(int nb, int p, double u, const double* U) {
  const int n = nb - 1;
  if (u >= U[n + 1]) return n;
  if (u <= U[p]) return p;
  int lo = p, hi = n + 1, mid = (lo + hi) / 2;
  while (u < U[mid] || u >= U[mid + 1]) {
    if (u < U[mid]) hi = mid; else lo = mid;
    mid = (lo + hi) / 2;
  }
  return mid;
}

/// B-spline basis functions and derivatives up to order nd (<= 3; ders has nd + 1 rows) at u
/// in span `span`, for the compile-time degree p (loops unrolled); bspline_ders below picks p
/// at run time.
template <int p>
KOKKOS_INLINE_FUNCTION void bspline_ders_p(int span, double u, const double* U, int nd,
                                           double ders[][kMaxBasis1D]) {
  double left[kMaxBasis1D], right[kMaxBasis1D];
  double ndu[kMaxBasis1D][kMaxBasis1D];
  double inv[kMaxBasis1D][kMaxBasis1D];   // inv[j][r] = 1 / ndu[j][r] (knot differences)
  double a[2][kMaxBasis1D];
  ndu[0][0] = 1.0;
  for (int j = 1; j <= p; ++j) {
    left[j] = u - U[span + 1 - j];
    right[j] = U[span + j] - u;
    double saved = 0.0;
    for (int r = 0; r < j; ++r) {
      ndu[j][r] = right[r + 1] + left[j - r];
      inv[j][r] = 1.0 / ndu[j][r];
      const double temp = ndu[r][j - 1] * inv[j][r];
      ndu[r][j] = saved + right[r + 1] * temp;
      saved = left[j - r] * temp;
    }
    ndu[j][j] = saved;
  }
  for (int j = 0; j <= p; ++j) ders[0][j] = ndu[j][p];
  const int ne = nd < p ? nd : p;  // derivatives above the degree vanish
  for (int k = ne + 1; k <= nd; ++k)
    for (int j = 0; j <= p; ++j) ders[k][j] = 0.0;
  for (int r = 0; r <= p; ++r) {
    int s1 = 0, s2 = 1;
    a[0][0] = 1.0;
    for (int k = 1; k <= ne; ++k) {
      double d = 0.0;
      const int rk = r - k, pk = p - k;
      if (r >= k) {
        a[s2][0] = a[s1][0] * inv[pk + 1][rk];
        d = a[s2][0] * ndu[rk][pk];
      }
      const int j1 = (rk >= -1) ? 1 : -rk;
      const int j2 = (r - 1 <= pk) ? k - 1 : p - r;
      for (int j = j1; j <= j2; ++j) {
        a[s2][j] = (a[s1][j] - a[s1][j - 1]) * inv[pk + 1][rk + j];
        d += a[s2][j] * ndu[rk + j][pk];
      }
      if (r <= pk) {
        a[s2][k] = -a[s1][k - 1] * inv[pk + 1][r];
        d += a[s2][k] * ndu[r][pk];
      }
      ders[k][r] = d;
      const int t = s1; s1 = s2; s2 = t;
    }
  }
  double fac = p;
  for (int k = 1; k <= ne; ++k) {
    for (int j = 0; j <= p; ++j) ders[k][j] *= fac;
    fac *= (p - k);
  }
}

/// B-spline basis functions and derivatives up to order nd (<= 3) at u in span `span`: the
/// one switch from the run-time degree to bspline_ders_p (degrees 1..kMaxDegree; the problem
/// loader rejects others before any kernel runs).
KOKKOS_INLINE_FUNCTION void bspline_ders(int span, double u, int p, const double* U, int nd,
                                         double ders[][kMaxBasis1D]) {
  switch (p) {
    case 1: bspline_ders_p<1>(span, u, U, nd, ders); break;
    case 2: bspline_ders_p<2>(span, u, U, nd, ders); break;
    case 3: bspline_ders_p<3>(span, u, U, nd, ders); break;
    case 4: bspline_ders_p<4>(span, u, U, nd, ders); break;
    case 5: bspline_ders_p<5>(span, u, U, nd, ders); break;
    default: Kokkos::abort("bspline_ders: degree outside 1..5");
  }
}

/// Rational (NURBS) curve basis R_j and its first two derivatives from B-spline derivatives
/// and the weights w[j] of the p + 1 active control points.
KOKKOS_INLINE_FUNCTION void rationalize_1d(int p, const double ders[3][kMaxBasis1D],
                                           const double* w, double R[3][kMaxBasis1D]) {
  double W = 0, W1 = 0, W2 = 0;
  for (int j = 0; j <= p; ++j) {
    W += ders[0][j] * w[j];
    W1 += ders[1][j] * w[j];
    W2 += ders[2][j] * w[j];
  }
  const double iW = 1.0 / W;
  for (int j = 0; j <= p; ++j) {
    R[0][j] = ders[0][j] * w[j] * iW;
    R[1][j] = (ders[1][j] * w[j] - R[0][j] * W1) * iW;
    R[2][j] = (ders[2][j] * w[j] - 2.0 * R[1][j] * W1 - R[0][j] * W2) * iW;
  }
}

/// Rational curve basis R_j and its derivatives up to the third (Leibniz on R w-weighted):
///   R''' = (N''' w - 3 R'' W' - 3 R' W'' - R W''') / W.
KOKKOS_INLINE_FUNCTION void rationalize_1d_3(int p, const double ders[4][kMaxBasis1D], const double* w,
                                             double R[4][kMaxBasis1D]) {
  double W[4] = {0, 0, 0, 0};
  for (int k = 0; k < 4; ++k)
    for (int j = 0; j <= p; ++j) W[k] += ders[k][j] * w[j];
  const double iW = 1.0 / W[0];
  for (int j = 0; j <= p; ++j) {
    R[0][j] = ders[0][j] * w[j] * iW;
    R[1][j] = (ders[1][j] * w[j] - R[0][j] * W[1]) * iW;
    R[2][j] = (ders[2][j] * w[j] - 2.0 * R[1][j] * W[1] - R[0][j] * W[2]) * iW;
    R[3][j] = (ders[3][j] * w[j] - 3.0 * R[2][j] * W[1] - 3.0 * R[1][j] * W[2] - R[0][j] * W[3]) * iW;
  }
}

/// NURBS curve basis functions of span `span` and their first three parametric derivatives at u.
template <class WView>
KOKKOS_INLINE_FUNCTION void curve_basis3_span(int span, int p, const double* U, const WView& wgt, double u,
                                              double R[4][kMaxBasis1D]) {
  double ders[4][kMaxBasis1D], w[kMaxBasis1D];
  bspline_ders(span, u, p, U, 3, ders);
  for (int j = 0; j <= p; ++j) w[j] = wgt(span - p + j);
  rationalize_1d_3(p, ders, w, R);
}

/// Point, first and second parametric derivative of a NURBS curve at u in the given span
/// (U[span] <= u <= U[span + 1]). cp(i, 0..1) are the (current) control point positions,
/// wgt(i) the weights.
template <class CPView, class WView>
KOKKOS_INLINE_FUNCTION void curve_eval_span(int span, int p, const double* U, const CPView& cp, const WView& wgt,
                                            double u, double x[2], double dx[2], double ddx[2],
                                            double R[3][kMaxBasis1D]) {
  double ders[3][kMaxBasis1D], w[kMaxBasis1D];
  bspline_ders(span, u, p, U, 2, ders);
  for (int j = 0; j <= p; ++j) w[j] = wgt(span - p + j);
  rationalize_1d(p, ders, w, R);
  for (int c = 0; c < 2; ++c) x[c] = dx[c] = ddx[c] = 0.0;
  for (int j = 0; j <= p; ++j) {
    const int i = span - p + j;
    for (int c = 0; c < 2; ++c) {
      x[c] += R[0][j] * cp(i, c);
      dx[c] += R[1][j] * cp(i, c);
      ddx[c] += R[2][j] * cp(i, c);
    }
  }
}

/// As curve_eval_span, with the span found from u. Returns the span used, so callers can
/// gather the active control points.
template <class CPView, class WView>
KOKKOS_INLINE_FUNCTION int curve_eval(int nb, int p, const double* U, const CPView& cp,
                                      const WView& wgt, double u, double x[2], double dx[2],
                                      double ddx[2], double R[3][kMaxBasis1D]) {
  const int span = find_span(nb, p, u, U);
  curve_eval_span(span, p, U, cp, wgt, u, x, dx, ddx, R);
  return span;
}

}  // namespace iga
