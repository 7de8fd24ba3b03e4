// Generalised Gaussian quadrature for spline spaces (model/quadrature.hpp).
#include "model/quadrature.hpp"

#include <Teuchos_LAPACK.hpp>

#include <algorithm>
#include <cmath>
#include <sstream>

#include "kernels/types.hpp"
#include "model/nurbs.hpp"

namespace iga {

static_assert(kMaxNodesPerElement == kMaxGauss, "the kernels hold an element's nodes in arrays of kMaxGauss");

void host_bspline(const std::vector<double>& T, int d, int s, double u, double* N, double* d1) {
  // Cox-de Boor (The NURBS Book A2.2), keeping the degree d - 1 values for the derivative
  double left[16], right[16], prev[16];
  N[0] = 1.0;
  for (int j = 1; j <= d; ++j) {
    left[j] = u - T[s + 1 - j];
    right[j] = T[s + j] - u;
    if (j == d)
      for (int r = 0; r < d; ++r) prev[r] = N[r];
    double saved = 0.0;
    for (int r = 0; r < j; ++r) {
      const double den = right[r + 1] + left[j - r];
      const double temp = den != 0.0 ? N[r] / den : 0.0;
      N[r] = saved + right[r + 1] * temp;
      saved = left[j - r] * temp;
    }
    N[j] = saved;
  }
  if (!d1) return;
  if (d == 0) { d1[0] = 0.0; return; }
  // N'_{i,d} = d (N_{i,d-1} / (t_{i+d} - t_i) - N_{i+1,d-1} / (t_{i+d+1} - t_{i+1})), i = s - d + r;
  // prev[k] = N_{s-d+1+k, d-1}, k = 0..d-1
  for (int r = 0; r <= d; ++r) {
    const int i = s - d + r;
    double v = 0.0;
    if (r >= 1) {
      const double den = T[i + d] - T[i];
      if (den != 0.0) v += prev[r - 1] / den;
    }
    if (r <= d - 1) {
      const double den = T[i + d + 1] - T[i + 1];
      if (den != 0.0) v -= prev[r] / den;
    }
    d1[r] = d * v;
  }
}

namespace {

// Groups sorted nodes by element; false if an element gets more than kMaxNodesPerElement.
bool group(const std::vector<double>& U, int p, const std::vector<double>& x, const std::vector<double>& w,
           SplineRule& r) {
  const std::vector<int> spans = nonempty_spans(U, p);
  r.x.clear();
  r.w.clear();
  r.off.assign(1, 0);
  size_t j = 0;
  for (size_t k = 0; k < spans.size(); ++k) {
    const double hi = U[spans[k] + 1];
    const bool last = k + 1 == spans.size();
    int count = 0;
    while (j < x.size() && (last || x[j] < hi)) {
      r.x.push_back(x[j]);
      r.w.push_back(w[j]);
      ++j;
      ++count;
    }
    if (count > kMaxNodesPerElement) return false;
    r.off.push_back(static_cast<int>(r.x.size()));
  }
  return true;
}

}  // namespace

namespace {

// The Gaussian rule of the spline space of degree d on knot vector T (open on [a, b]): Newton's
// method on the moment equations from the initial rule below. drop >= 0 (an odd dimension):
// one node stays fixed at the Greville point of function `drop`, which it takes in the initial
// rule. Returns "" (x, w set) or why it failed.
std::string gaussian_rule(const std::vector<double>& T, int d, int drop, std::vector<double>& x, std::vector<double>& w,
                          int& iterations, double& error, bool start_from_xw = false) {
  const double a = T.front(), b = T.back();
  const int N = static_cast<int>(T.size()) - d - 1;
  std::vector<double> I(N), g(N);   // integrals and Greville abscissae of the B-splines
  for (int i = 0; i < N; ++i) {
    I[i] = (T[i + d + 1] - T[i]) / (d + 1);
    double s = 0;
    for (int k = 1; k <= d; ++k) s += T[i + k];
    g[i] = s / d;
  }
  // initial rule: nodes between consecutive Greville points, weights the pairs' integrals
  // (or the x, w given, start_from_xw: a continuation step, drop < 0)
  const int n = (N + 1) / 2;
  std::vector<int> fixed_node(n, 0);
  if (start_from_xw && (drop >= 0 || static_cast<int>(x.size()) != n)) return "continuation: wrong initial rule";
  if (!start_from_xw) {
    x.clear();
    w.clear();
    std::vector<int> idx;
    for (int i = 0; i < N; ++i)
      if (i != drop) idx.push_back(i);
    for (size_t k = 0; k + 1 < idx.size(); k += 2) {
      x.push_back(0.5 * (g[idx[k]] + g[idx[k + 1]]));
      w.push_back(I[idx[k]] + I[idx[k + 1]]);
    }
    if (drop >= 0) {
      const size_t at = std::upper_bound(x.begin(), x.end(), g[drop]) - x.begin();
      x.insert(x.begin() + at, g[drop]);
      w.insert(w.begin() + at, I[drop]);
      fixed_node[at] = 1;
    }
  }
  // unknowns: (x_j, w_j) per node, w_j alone for the fixed node
  std::vector<int> cx(n, -1), cw(n, -1);
  for (int j = 0, col = 0; j < n; ++j) {
    if (!fixed_node[j]) cx[j] = col++;
    cw[j] = col++;
  }
  auto span_of = [&](double u) {
    const int s = static_cast<int>(std::upper_bound(T.begin(), T.end(), u) - T.begin()) - 1;
    return std::min(std::max(s, d), N - 1);
  };
  auto residual = [&](const std::vector<double>& xx, const std::vector<double>& ww, std::vector<double>& F) {
    F.assign(N, 0.0);
    for (int i = 0; i < N; ++i) F[i] = -I[i];
    double Nv[16];
    for (int j = 0; j < n; ++j) {
      const int s = span_of(xx[j]);
      host_bspline(T, d, s, xx[j], Nv, nullptr);
      for (int r = 0; r <= d; ++r) F[s - d + r] += ww[j] * Nv[r];
    }
    double e = 0;
    for (int i = 0; i < N; ++i) e = std::max(e, std::abs(F[i]) / I[i]);
    return e;
  };
  auto admissible = [&](const std::vector<double>& xx, const std::vector<double>& ww) {
    for (int j = 0; j < n; ++j) {
      if (!(ww[j] > 0) || !(xx[j] >= a) || !(xx[j] <= b)) return false;
      if (j > 0 && !(xx[j] > xx[j - 1])) return false;
    }
    return true;
  };
  std::vector<double> F;
  double err = residual(x, w, F);
  Teuchos::LAPACK<int, double> lapack;
  int it = 0;
  for (; it < 60 && err > 1e-14; ++it) {
    // banded Jacobian: columns cx[j] (x_j) and cw[j] (w_j); LAPACK band storage
    std::vector<std::vector<std::pair<int, double>>> cols(N);
    double Nv[16], Dv[16];
    for (int j = 0; j < n; ++j) {
      const int s = span_of(x[j]);
      host_bspline(T, d, s, x[j], Nv, Dv);
      for (int r = 0; r <= d; ++r) {
        cols[cw[j]].push_back({s - d + r, Nv[r]});
        if (cx[j] >= 0) cols[cx[j]].push_back({s - d + r, w[j] * Dv[r]});
      }
    }
    int kl = 0, ku = 0;
    for (int c = 0; c < N; ++c)
      for (const auto& e : cols[c]) {
        kl = std::max(kl, e.first - c);
        ku = std::max(ku, c - e.first);
      }
    const int ldab = 2 * kl + ku + 1;
    std::vector<double> AB(static_cast<size_t>(ldab) * N, 0.0);
    for (int c = 0; c < N; ++c)
      for (const auto& e : cols[c]) AB[static_cast<size_t>(c) * ldab + kl + ku + e.first - c] += e.second;
    std::vector<int> piv(N);
    std::vector<double> delta(N);
    for (int i = 0; i < N; ++i) delta[i] = -F[i];
    int info = 0;
    lapack.GBTRF(N, N, kl, ku, AB.data(), ldab, piv.data(), &info);
    if (info != 0) return "singular Jacobian of the moment equations (Newton iteration " + std::to_string(it) + ")";
    lapack.GBTRS('N', N, kl, ku, 1, AB.data(), ldab, piv.data(), delta.data(), N, &info);
    // damped step: the largest of 1, 1/2, ... that keeps the rule admissible and lowers the error
    double alpha = 1.0;
    std::vector<double> xt(n), wt(n), Ft;
    bool taken = false;
    for (int k = 0; k < 30 && !taken; ++k, alpha *= 0.5) {
      for (int j = 0; j < n; ++j) {
        xt[j] = cx[j] >= 0 ? x[j] + alpha * delta[cx[j]] : x[j];
        wt[j] = w[j] + alpha * delta[cw[j]];
      }
      if (!admissible(xt, wt)) continue;
      const double et = residual(xt, wt, Ft);
      if (et < err) {
        x = xt;
        w = wt;
        F = Ft;
        err = et;
        taken = true;
      }
    }
    if (!taken) break;
  }
  iterations = std::max(iterations, it);
  if (!(err <= 1e-12)) {
    std::ostringstream os;
    os << "Newton's method for the nodes did not converge on [" << a << ", " << b << "] (moment error " << err
       << " after " << it << " iterations)";
    return os.str();
  }
  error = std::max(error, err);
  return admissible(x, w) ? "" : "the rule has a non-positive weight or nodes out of order";
}

// The Gaussian rule of T by continuation (when Newton from the Greville start fails, as on
// strongly graded knots at high degree): from the knot vector with the same multiplicities
// and evenly spaced values, whose rule Newton finds, to T in steps, each solved from the last
// rule mapped span by span (node positions relative to their spans, weights scaled by the
// spans' lengths); a step that fails is halved, down to 1/4096.
std::string continued_rule(const std::vector<double>& T, int d, std::vector<double>& x, std::vector<double>& w,
                           int& iterations, double& error) {
  std::vector<double> D;   // distinct knot values
  for (double t : T)
    if (D.empty() || t > D.back()) D.push_back(t);
  const size_t m = D.size();
  std::vector<double> Du(m);
  for (size_t k = 0; k < m; ++k) Du[k] = D.front() + (D.back() - D.front()) * static_cast<double>(k) / (m - 1);
  auto knots_at = [&](double s, std::vector<double>& Ts, std::vector<double>& Ds) {
    Ds.resize(m);
    for (size_t k = 0; k < m; ++k) Ds[k] = (1 - s) * Du[k] + s * D[k];
    Ds.front() = D.front();
    Ds.back() = D.back();
    Ts.clear();
    for (double t : T) Ts.push_back(Ds[std::lower_bound(D.begin(), D.end(), t) - D.begin()]);
  };
  auto map_rule = [&](const std::vector<double>& from, const std::vector<double>& to) {
    for (size_t j = 0; j < x.size(); ++j) {
      size_t k = std::upper_bound(from.begin(), from.end(), x[j]) - from.begin();
      k = std::min(std::max<size_t>(k, 1), m - 1) - 1;
      const double r = (to[k + 1] - to[k]) / (from[k + 1] - from[k]);
      x[j] = to[k] + (x[j] - from[k]) * r;
      w[j] *= r;
    }
  };
  std::vector<double> Ts, Ds, Dprev;
  knots_at(0.0, Ts, Dprev);
  std::string why = gaussian_rule(Ts, d, -1, x, w, iterations, error);
  if (!why.empty()) return "continuation: no rule on evenly spaced knots (" + why + ")";
  double s = 0.0, step = 0.25;
  while (s < 1.0) {
    const double s1 = std::min(1.0, s + step);
    const std::vector<double> xs = x, ws = w;
    knots_at(s1, Ts, Ds);
    map_rule(Dprev, Ds);
    why = gaussian_rule(Ts, d, -1, x, w, iterations, error, true);
    if (why.empty()) {
      s = s1;
      Dprev = Ds;
      step = std::min(0.5, 2 * step);
    } else {
      x = xs;
      w = ws;
      step *= 0.5;
      if (step < 1.0 / 4096) return "continuation to the knots stalled at " + std::to_string(s) + " (" + why + ")";
    }
  }
  return "";
}

// The rule of one piece of the knot vector without C^-1 lines in the target space (no interior
// knot of multiplicity p): appends its nodes and weights; returns "" or why it failed.
std::string segment_rule(const std::vector<double>& U, int p, std::vector<double>& xs, std::vector<double>& ws,
                         int& iterations, double& error) {
  const int d = 2 * p;
  // the target space: degree 2p, each interior knot of multiplicity m repeated p + m + 1 times
  const double a = U[p], b = U[U.size() - p - 1];
  std::vector<double> T(d + 1, a);
  for (size_t k = p + 1; k < U.size() - p - 1;) {
    size_t m = 1;
    while (k + m < U.size() - p - 1 && U[k + m] == U[k]) ++m;
    T.insert(T.end(), std::min(d + 1, p + static_cast<int>(m) + 1), U[k]);
    k += m;
  }
  T.insert(T.end(), d + 1, b);
  const int N = static_cast<int>(T.size()) - d - 1;
  std::vector<double> x, w;
  std::string why;
  if (N % 2 == 0) {
    why = gaussian_rule(T, d, -1, x, w, iterations, error);
    if (!why.empty()) why = continued_rule(T, d, x, w, iterations, error);
  } else {
    // An odd dimension has no Gaussian rule of N / 2 nodes. To keep a symmetric knot vector's
    // rule symmetric (a rule anchored at one end would make a patch and its mirror image
    // differ by the quadrature error), first the space enlarged by one more copy of the knot
    // at the middle c of [a, b] (or a new knot there), then a node fixed at c (the middle
    // function's Greville point), and last a node fixed at a.
    const double c = 0.5 * (a + b);
    const auto near = std::min_element(T.begin(), T.end(), [&](double u, double v) { return std::abs(u - c) < std::abs(v - c); });
    const double v = std::abs(*near - c) <= 1e-14 * (b - a) ? *near : c;   // the knot's own value, bit for bit
    why = "no rule";
    if (std::count(T.begin(), T.end(), v) < d) {
      std::vector<double> T1 = T;
      T1.insert(std::upper_bound(T1.begin(), T1.end(), v), v);
      why = gaussian_rule(T1, d, -1, x, w, iterations, error);
      if (!why.empty()) why = continued_rule(T1, d, x, w, iterations, error);
    }
    if (!why.empty()) why = gaussian_rule(T, d, N / 2, x, w, iterations, error);
    if (!why.empty()) why = gaussian_rule(T, d, 0, x, w, iterations, error);
  }
  if (!why.empty()) return why;
  xs.insert(xs.end(), x.begin(), x.end());
  ws.insert(ws.end(), w.begin(), w.end());
  return "";
}

}  // namespace

SplineRule spline_gauss_rule(const std::vector<double>& U, int p) {
  SplineRule rule;
  // C0 lines (an interior knot of multiplicity >= p) make the target space discontinuous
  // there: the pieces between them get rules of their own
  std::vector<double> x, w;
  const size_t end = U.size() - p - 1;   // index of the last knot's first copy
  double left = U[0];        // the piece's left end
  size_t first = p + 1;      // index of its first interior knot
  for (size_t k = p + 1; k <= end;) {
    size_t m = 1;
    while (k + m < U.size() && U[k + m] == U[k]) ++m;
    if (k == end || static_cast<int>(m) >= p) {
      std::vector<double> piece(p + 1, left);
      for (size_t i = first; i < k; ++i) piece.push_back(U[i]);
      piece.insert(piece.end(), p + 1, U[k]);
      const std::string why = segment_rule(piece, p, x, w, rule.newton_iterations, rule.moment_error);
      if (!why.empty()) {
        rule.failure = why;
        return rule;
      }
      if (k == end) break;
      left = U[k];
      first = k + m;
    }
    k += m;
  }
  if (!group(U, p, x, w, rule))
    rule.failure = "more than " + std::to_string(kMaxNodesPerElement) + " nodes in one element";
  return rule;
}

}  // namespace iga
