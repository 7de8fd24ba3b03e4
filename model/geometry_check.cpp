// The sign of det J over a patch, proven with the Bernstein form of D = W^3 det J on each
// Bezier element (see geometry_check.hpp for the formula, the rule for zeros and the cost).
// Coefficients of D are formed "scaled" (c_ij binom(m0, i) binom(m1, j)), in which the
// Bernstein product is a plain 2-D convolution; signs are the same. Layout: c[i + j (m0 + 1)].
// Cost: ~140 ns per element at degree 2 (the header has the counts and the measurement).
#include "model/geometry_check.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <vector>

#include "kernels/types.hpp"
#include "model/bezier.hpp"

namespace iga {
namespace {

constexpr int kMaxP = 5;
constexpr int kMaxM = 3 * kMaxP - 1;   // bidegree of D, rational
constexpr int kN = kMaxM + 1;
constexpr int kMaxBez = (kMaxP + 1) * (kMaxP + 1);
constexpr int kMaxDepth = 12;          // subdivision levels (pieces of 2^-12 of the element)
constexpr int kMaxPieces = 20000;      // per element, a guard
constexpr int kGrid = 10;              // interior sample grid per direction

struct Binomials {
  double b[kN][kN];
};
constexpr Binomials make_binomials() {
  Binomials t{};
  for (int n = 0; n < kN; ++n) {
    t.b[n][0] = t.b[n][n] = 1;
    for (int k = 1; k < n; ++k) t.b[n][k] = t.b[n - 1][k - 1] + t.b[n - 1][k];
  }
  return t;
}
constexpr Binomials kBinom = make_binomials();

// Bivariate Bernstein coefficients of bidegree (m0, m1).
struct Poly {
  int m0 = 0, m1 = 0;
  double c[kN * kN];
  int n0() const { return m0 + 1; }
  int size() const { return (m0 + 1) * (m1 + 1); }
  double& at(int i, int j) { return c[i + j * (m0 + 1)]; }
  double at(int i, int j) const { return c[i + j * (m0 + 1)]; }
  void zero(int a, int b) {
    m0 = a; m1 = b;
    std::fill(c, c + size(), 0.0);
  }
};

// standard <-> scaled coefficients
void scale(Poly& a, bool up) {
  for (int j = 0; j <= a.m1; ++j)
    for (int i = 0; i <= a.m0; ++i) {
      const double f = kBinom.b[a.m0][i] * kBinom.b[a.m1][j];
      a.at(i, j) = up ? a.at(i, j) * f : a.at(i, j) / f;
    }
}

double eval(const Poly& a, double t, double s) {
  double B0[kN], B1[kN];
  bernstein(a.m0, t, B0);
  bernstein(a.m1, s, B1);
  double v = 0;
  for (int j = 0; j <= a.m1; ++j) {
    double r = 0;
    for (int i = 0; i <= a.m0; ++i) r += a.at(i, j) * B0[i];
    v += r * B1[j];
  }
  return v;
}

// de Casteljau at 1/2 along t (d = 0) or s (d = 1)
void split(const Poly& a, int d, Poly& lo, Poly& hi) {
  lo.m0 = hi.m0 = a.m0; lo.m1 = hi.m1 = a.m1;
  const int m = d == 0 ? a.m0 : a.m1, nl = d == 0 ? a.m1 : a.m0;
  double tmp[kN];
  for (int l = 0; l <= nl; ++l) {
    auto idx = [&](int k) { return d == 0 ? k + l * (a.m0 + 1) : l + k * (a.m0 + 1); };
    for (int k = 0; k <= m; ++k) tmp[k] = a.c[idx(k)];
    for (int r = 0; r <= m; ++r) {
      lo.c[idx(r)] = tmp[0];
      hi.c[idx(m - r)] = tmp[m - r];
      for (int k = 0; k < m - r; ++k) tmp[k] = 0.5 * (tmp[k] + tmp[k + 1]);
    }
  }
}

// D = t E (edge t = 0), (1 - t) E (t = 1), s E, (1 - s) E: E from D's standard coefficients
void divide_edge(Poly& a, int edge) {
  Poly e;
  const bool along_t = edge < 2;
  e.m0 = along_t ? a.m0 - 1 : a.m0;
  e.m1 = along_t ? a.m1 : a.m1 - 1;
  for (int j = 0; j <= e.m1; ++j)
    for (int i = 0; i <= e.m0; ++i) {
      switch (edge) {
        case 0: e.at(i, j) = a.at(i + 1, j) * a.m0 / (i + 1); break;
        case 1: e.at(i, j) = a.at(i, j) * a.m0 / (a.m0 - i); break;
        case 2: e.at(i, j) = a.at(i, j + 1) * a.m1 / (j + 1); break;
        default: e.at(i, j) = a.at(i, j) * a.m1 / (a.m1 - j); break;
      }
    }
  a = e;
}

bool edge_vanishes(const Poly& a, int edge, double tol) {
  if (edge < 2 ? a.m0 == 0 : a.m1 == 0) return false;
  if (edge < 2) {
    const int i = edge == 0 ? 0 : a.m0;
    for (int j = 0; j <= a.m1; ++j)
      if (std::abs(a.at(i, j)) > tol) return false;
  } else {
    const int j = edge == 2 ? 0 : a.m1;
    for (int i = 0; i <= a.m0; ++i)
      if (std::abs(a.at(i, j)) > tol) return false;
  }
  return true;
}

// Fixed-size versions for the pass over all elements (bounds known: unrolled, vectorised).
// out += sign * a * b, scaled coefficients of bidegrees (A0, A1) and (B0, B1)
template <int A0, int A1, int B0, int B1>
inline void mul_add(const double* a, const double* b, double sign, double* out) {
  constexpr int O0 = A0 + B0 + 1;
  for (int aj = 0; aj <= A1; ++aj)
    for (int ai = 0; ai <= A0; ++ai) {
      const double av = sign * a[ai + aj * (A0 + 1)];
      for (int bj = 0; bj <= B1; ++bj)
        for (int bi = 0; bi <= B0; ++bi) out[(ai + bi) + (aj + bj) * O0] += av * b[bi + bj * (B0 + 1)];
    }
}

// scaled coefficients of the t- and s-derivatives of standard coefficients f (bidegree P0, P1)
template <int P0, int P1>
inline void scaled_derivatives(const double* f, double* ft, double* fs) {
  for (int j = 0; j <= P1; ++j)
    for (int i = 0; i < P0; ++i)
      ft[i + j * P0] = P0 * (f[i + 1 + j * (P0 + 1)] - f[i + j * (P0 + 1)]) * kBinom.b[P0 - 1][i] * kBinom.b[P1][j];
  for (int j = 0; j < P1; ++j)
    for (int i = 0; i <= P0; ++i)
      fs[i + j * (P0 + 1)] = P1 * (f[i + (j + 1) * (P0 + 1)] - f[i + j * (P0 + 1)]) * kBinom.b[P0][i] * kBinom.b[P1 - 1][j];
}

// scaled coefficients of D from the standard coefficients of W, A1, A2 (bidegree P0, P1)
template <int P0, int P1>
void d_coefficients(const double* W, const double* A1, const double* A2, bool rational, Poly& D) {
  constexpr int N = (P0 + 1) * (P1 + 1), Nt = P0 * (P1 + 1), Ns = (P0 + 1) * P1;
  double A1t[Nt], A1s[Ns], A2t[Nt], A2s[Ns];
  scaled_derivatives<P0, P1>(A1, A1t, A1s);
  scaled_derivatives<P0, P1>(A2, A2t, A2s);
  if (!rational) {
    D.zero(2 * P0 - 1, 2 * P1 - 1);
    mul_add<P0 - 1, P1, P0, P1 - 1>(A1t, A2s, 1.0, D.c);
    mul_add<P0, P1 - 1, P0 - 1, P1>(A1s, A2t, -1.0, D.c);
    return;
  }
  double Wt[Nt], Ws[Ns], Wsc[N], A1sc[N], A2sc[N];
  scaled_derivatives<P0, P1>(W, Wt, Ws);
  for (int j = 0; j <= P1; ++j)
    for (int i = 0; i <= P0; ++i) {
      const double f = kBinom.b[P0][i] * kBinom.b[P1][j];
      const int k = i + j * (P0 + 1);
      Wsc[k] = W[k] * f; A1sc[k] = A1[k] * f; A2sc[k] = A2[k] * f;
    }
  constexpr int M = (2 * P0) * (2 * P1);
  double M1[M] = {}, M2[M] = {}, M3[M] = {};   // cofactors of the first row
  mul_add<P0 - 1, P1, P0, P1 - 1>(A1t, A2s, 1.0, M1);
  mul_add<P0, P1 - 1, P0 - 1, P1>(A1s, A2t, -1.0, M1);
  mul_add<P0 - 1, P1, P0, P1 - 1>(Wt, A2s, 1.0, M2);
  mul_add<P0, P1 - 1, P0 - 1, P1>(Ws, A2t, -1.0, M2);
  mul_add<P0 - 1, P1, P0, P1 - 1>(Wt, A1s, 1.0, M3);
  mul_add<P0, P1 - 1, P0 - 1, P1>(Ws, A1t, -1.0, M3);
  D.zero(3 * P0 - 1, 3 * P1 - 1);
  mul_add<P0, P1, 2 * P0 - 1, 2 * P1 - 1>(Wsc, M1, 1.0, D.c);
  mul_add<P0, P1, 2 * P0 - 1, 2 * P1 - 1>(A1sc, M2, -1.0, D.c);
  mul_add<P0, P1, 2 * P0 - 1, 2 * P1 - 1>(A2sc, M3, 1.0, D.c);
}

using DFunction = void (*)(const double*, const double*, const double*, bool, Poly&);
DFunction d_dispatch(int p0, int p1) {
  static const DFunction table[kMaxP][kMaxP] = {
      {&d_coefficients<1, 1>, &d_coefficients<1, 2>, &d_coefficients<1, 3>, &d_coefficients<1, 4>, &d_coefficients<1, 5>},
      {&d_coefficients<2, 1>, &d_coefficients<2, 2>, &d_coefficients<2, 3>, &d_coefficients<2, 4>, &d_coefficients<2, 5>},
      {&d_coefficients<3, 1>, &d_coefficients<3, 2>, &d_coefficients<3, 3>, &d_coefficients<3, 4>, &d_coefficients<3, 5>},
      {&d_coefficients<4, 1>, &d_coefficients<4, 2>, &d_coefficients<4, 3>, &d_coefficients<4, 4>, &d_coefficients<4, 5>},
      {&d_coefficients<5, 1>, &d_coefficients<5, 2>, &d_coefficients<5, 3>, &d_coefficients<5, 4>, &d_coefficients<5, 5>}};
  return table[p0 - 1][p1 - 1];
}

// The quick test of step 1. D = W M1 - A1 M2 + A2 M3 with M1 = A1_t A2_s - A1_s A2_t,
// M2 = W_t A2_s - W_s A2_t, M3 = W_t A1_s - W_s A1_t. M1 is formed exactly (bidegree
// (2 p0 - 1, 2 p1 - 1); with equal weights D = M1), the rest is bounded by the largest
// coefficients: |A1 M2 - A2 M3| <= R = max|A1| (max|W_t| max|A2_s| + max|W_s| max|A2_t|) + ...,
// so min W min M1 - R > tol proves D > tol (and max M1 < 0 likewise D < -tol). With weights
// that vary slowly over an element R is O(h) smaller than the first term: the full product
// is formed only where this fails.
struct Quick {
  double lo = 0, hi = 0, mean = 0;   // standard coefficients of M1
  double R = 0, wmin = 1, wmean = 1;
};

template <int P0, int P1>
void quick_bound(const double* W, const double* A1, const double* A2, bool rational, const double* inv, Quick& q) {
  constexpr int N = (P0 + 1) * (P1 + 1), Nt = P0 * (P1 + 1), Ns = (P0 + 1) * P1, M = (2 * P0) * (2 * P1);
  double A1t[Nt], A1s[Ns], A2t[Nt], A2s[Ns], M1[M] = {};
  scaled_derivatives<P0, P1>(A1, A1t, A1s);
  scaled_derivatives<P0, P1>(A2, A2t, A2s);
  mul_add<P0 - 1, P1, P0, P1 - 1>(A1t, A2s, 1.0, M1);
  mul_add<P0, P1 - 1, P0 - 1, P1>(A1s, A2t, -1.0, M1);
  double lo = 1e300, hi = -1e300, mean = 0;
  for (int k = 0; k < M; ++k) {
    const double v = M1[k] * inv[k];
    lo = std::min(lo, v); hi = std::max(hi, v); mean += v;
  }
  q.lo = lo; q.hi = hi; q.mean = mean / M;
  q.R = 0; q.wmin = 1; q.wmean = 1;
  if (!rational) return;
  // maxima of the standard coefficients (differences for the derivatives)
  double a1 = 0, a2 = 0, wmin = 1e300, wsum = 0, wt = 0, ws = 0, a1t = 0, a1s = 0, a2t = 0, a2s = 0;
  for (int k = 0; k < N; ++k) {
    a1 = std::max(a1, std::abs(A1[k])); a2 = std::max(a2, std::abs(A2[k]));
    wmin = std::min(wmin, W[k]); wsum += W[k];
  }
  for (int j = 0; j <= P1; ++j)
    for (int i = 0; i < P0; ++i) {
      const int k = i + j * (P0 + 1);
      wt = std::max(wt, std::abs(W[k + 1] - W[k]));
      a1t = std::max(a1t, std::abs(A1[k + 1] - A1[k])); a2t = std::max(a2t, std::abs(A2[k + 1] - A2[k]));
    }
  for (int j = 0; j < P1; ++j)
    for (int i = 0; i <= P0; ++i) {
      const int k = i + j * (P0 + 1);
      ws = std::max(ws, std::abs(W[k + P0 + 1] - W[k]));
      a1s = std::max(a1s, std::abs(A1[k + P0 + 1] - A1[k])); a2s = std::max(a2s, std::abs(A2[k + P0 + 1] - A2[k]));
    }
  const double pp = double(P0) * P1;
  q.R = pp * (a1 * (wt * a2s + ws * a2t) + a2 * (wt * a1s + ws * a1t));
  q.wmin = wmin;
  q.wmean = wsum / N;
}

using QFunction = void (*)(const double*, const double*, const double*, bool, const double*, Quick&);
QFunction q_dispatch(int p0, int p1) {
  static const QFunction table[kMaxP][kMaxP] = {
      {&quick_bound<1, 1>, &quick_bound<1, 2>, &quick_bound<1, 3>, &quick_bound<1, 4>, &quick_bound<1, 5>},
      {&quick_bound<2, 1>, &quick_bound<2, 2>, &quick_bound<2, 3>, &quick_bound<2, 4>, &quick_bound<2, 5>},
      {&quick_bound<3, 1>, &quick_bound<3, 2>, &quick_bound<3, 3>, &quick_bound<3, 4>, &quick_bound<3, 5>},
      {&quick_bound<4, 1>, &quick_bound<4, 2>, &quick_bound<4, 3>, &quick_bound<4, 4>, &quick_bound<4, 5>},
      {&quick_bound<5, 1>, &quick_bound<5, 2>, &quick_bound<5, 3>, &quick_bound<5, 4>, &quick_bound<5, 5>}};
  return table[p0 - 1][p1 - 1];
}

// Homogeneous Bezier points bez[k0 + k1 (P0 + 1)] = (w x, w y, w) of the element on knot spans
// (s0, s1), extraction operators C0, C1 (C[i (p + 1) + k]); true if the element's control
// points have equal weights.
template <int P0, int P1>
bool extract(const Patch& P, int s0, int s1, const double* C0, const double* C1, double (*bez)[3]) {
  constexpr int n0 = P0 + 1, n1 = P1 + 1;
  double hom[n0 * n1][3], tmp[n0 * n1][3];
  const double w0 = P.cp[P.index(s0 - P0, s1 - P1)].w;
  bool equal_w = true;
  for (int j = 0; j < n1; ++j) {
    const ControlPoint* row = &P.cp[P.index(s0 - P0, s1 - P1 + j)];
    for (int i = 0; i < n0; ++i) {
      const ControlPoint& c = row[i];
      hom[i + j * n0][0] = c.w * c.x[0]; hom[i + j * n0][1] = c.w * c.x[1]; hom[i + j * n0][2] = c.w;
      equal_w = equal_w && std::abs(c.w - w0) <= 1e-13 * w0;
    }
  }
  for (int j = 0; j < n1; ++j)
    for (int k0 = 0; k0 < n0; ++k0) {
      double a = 0, b = 0, c = 0;
      for (int i = 0; i < n0; ++i) {
        const double f = C0[i * n0 + k0];
        a += f * hom[i + j * n0][0]; b += f * hom[i + j * n0][1]; c += f * hom[i + j * n0][2];
      }
      tmp[k0 + j * n0][0] = a; tmp[k0 + j * n0][1] = b; tmp[k0 + j * n0][2] = c;
    }
  for (int k1 = 0; k1 < n1; ++k1)
    for (int k0 = 0; k0 < n0; ++k0) {
      double a = 0, b = 0, c = 0;
      for (int j = 0; j < n1; ++j) {
        const double f = C1[j * n1 + k1];
        a += f * tmp[k0 + j * n0][0]; b += f * tmp[k0 + j * n0][1]; c += f * tmp[k0 + j * n0][2];
      }
      bez[k0 + k1 * n0][0] = a; bez[k0 + k1 * n0][1] = b; bez[k0 + k1 * n0][2] = c;
    }
  return equal_w;
}

using EFunction = bool (*)(const Patch&, int, int, const double*, const double*, double (*)[3]);
EFunction e_dispatch(int p0, int p1) {
  static const EFunction table[kMaxP][kMaxP] = {
      {&extract<1, 1>, &extract<1, 2>, &extract<1, 3>, &extract<1, 4>, &extract<1, 5>},
      {&extract<2, 1>, &extract<2, 2>, &extract<2, 3>, &extract<2, 4>, &extract<2, 5>},
      {&extract<3, 1>, &extract<3, 2>, &extract<3, 3>, &extract<3, 4>, &extract<3, 5>},
      {&extract<4, 1>, &extract<4, 2>, &extract<4, 3>, &extract<4, 4>, &extract<4, 5>},
      {&extract<5, 1>, &extract<5, 2>, &extract<5, 3>, &extract<5, 4>, &extract<5, 5>}};
  return table[p0 - 1][p1 - 1];
}

// One Bezier element and the Bernstein coefficients of its D.
struct Element {
  int e0 = 0, e1 = 0;
  double u0 = 0, u1 = 1, v0 = 0, v1 = 1;
  int p0 = 1, p1 = 1;
  double x[kMaxBez], y[kMaxBez], w[kMaxBez];   // Bezier points (Euclidean), weights / max
  bool rational = false;
  double tolJ = 0, tolD = 0;
  double W[kMaxBez], A1[kMaxBez], A2[kMaxBez];   // standard coefficients of W, A1, A2
  Poly D;           // scaled coefficients, after full_D()
};

class Checker {
 public:
  Checker(const Patch& P, int sign) : P_(P), sign_(sign) {
    for (int d = 0; d < 2; ++d) {
      spans_[d] = P.element_spans(d);
      C_[d] = bezier_extraction_1d(P.knots[d], P.degree[d]);
    }
    dfun_ = d_dispatch(P.degree[0], P.degree[1]);
    qfun_ = q_dispatch(P.degree[0], P.degree[1]);
    efun_ = e_dispatch(P.degree[0], P.degree[1]);
    for (int r = 0; r < 2; ++r) {   // 1 / binomial weights of D, equal weights (0) and rational (1)
      const int m0 = (2 + r) * P.degree[0] - 1, m1 = (2 + r) * P.degree[1] - 1;
      for (int j = 0; j <= m1; ++j)
        for (int i = 0; i <= m0; ++i) inv_binom_[r][i + j * (m0 + 1)] = 1.0 / (kBinom.b[m0][i] * kBinom.b[m1][j]);
    }
  }
  int ne(int d) const { return static_cast<int>(spans_[d].size()); }

  // Bezier points, tolerances and the scaled coefficients of D of element (e0, e1).
  void build(int e0, int e1, Element& el) const {
    const int p0 = P_.degree[0], p1 = P_.degree[1], n0 = p0 + 1, n1 = p1 + 1;
    const int s0 = spans_[0][e0], s1 = spans_[1][e1];
    el.e0 = e0; el.e1 = e1; el.p0 = p0; el.p1 = p1;
    el.u0 = P_.knots[0][s0]; el.u1 = P_.knots[0][s0 + 1];
    el.v0 = P_.knots[1][s1]; el.v1 = P_.knots[1][s1 + 1];
    double bez[kMaxBez][3];
    const bool equal_w = efun_(P_, s0, s1, C_[0][e0].data(), C_[1][e1].data(), bez);
    const int nb = n0 * n1;
    double wmax = 0, wmin = 1e300, xmin = 1e300, xmax = -1e300, ymin = 1e300, ymax = -1e300;
    for (int k = 0; k < nb; ++k) {
      el.x[k] = bez[k][0] / bez[k][2]; el.y[k] = bez[k][1] / bez[k][2];
      wmax = std::max(wmax, bez[k][2]); wmin = std::min(wmin, bez[k][2]);
      xmin = std::min(xmin, el.x[k]); xmax = std::max(xmax, el.x[k]);
      ymin = std::min(ymin, el.y[k]); ymax = std::max(ymax, el.y[k]);
    }
    for (int k = 0; k < nb; ++k) el.w[k] = bez[k][2] / wmax;
    el.rational = !equal_w;
    const double L = std::max(xmax - xmin, ymax - ymin);
    const double X = std::max(std::max(std::abs(xmin), std::abs(xmax)), std::max(std::abs(ymin), std::abs(ymax)));
    const double cx = 0.5 * (xmin + xmax), cy = 0.5 * (ymin + ymax);
    el.tolJ = 1e-12 * L * L + 1e-15 * L * X;   // the second term: round-off in the coordinates
    const double wr = el.rational ? wmin / wmax : 1.0;
    el.tolD = el.tolJ * wr * wr * wr;

    // Bernstein coefficients of the homogeneous coordinates (standard), translated by c
    for (int k = 0; k < nb; ++k) {
      const double wk = el.rational ? el.w[k] : 1.0;
      el.W[k] = wk; el.A1[k] = wk * (el.x[k] - cx); el.A2[k] = wk * (el.y[k] - cy);
    }
  }

  void full_D(Element& el) const { dfun_(el.W, el.A1, el.A2, el.rational, el.D); }

  // Step 1: +1 if D > tolD is proven, -1 if D < -tolD, else 0; the area of the element
  // (approximate: mean of M1 / mean W^2) for the patch's orientation.
  int classify(Element& el, double& area) const {
    Quick q;
    qfun_(el.W, el.A1, el.A2, el.rational, inv_binom_[0], q);
    area = q.mean / (q.wmean * q.wmean);
    if (q.lo > 0 && q.wmin * q.lo - q.R > el.tolD) return 1;
    if (q.hi < 0 && q.wmin * q.hi + q.R < -el.tolD) return -1;
    if (!el.rational) return 0;   // D = M1: nothing more to learn
    full_D(el);
    const Poly& D = el.D;
    const double* inv = inv_binom_[1];
    double lo = 1e300, hi = -1e300;
    for (int k = 0; k < D.size(); ++k) {
      const double v = D.c[k] * inv[k];   // standard coefficient
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
    return lo > el.tolD ? 1 : (hi < -el.tolD ? -1 : 0);
  }

  // det J with respect to the element's local (t, s), and the physical point there.
  static double detJ_local(const Element& el, const Poly& Dstd, double t, double s, double* xy = nullptr) {
    double B0[kMaxP + 1], B1[kMaxP + 1];
    bernstein(el.p0, t, B0);
    bernstein(el.p1, s, B1);
    double W = 0, X = 0, Y = 0;
    for (int j = 0; j <= el.p1; ++j)
      for (int i = 0; i <= el.p0; ++i) {
        const int k = i + j * (el.p0 + 1);
        const double b = B0[i] * B1[j] * el.w[k];
        W += b; X += b * el.x[k]; Y += b * el.y[k];
      }
    if (xy) { xy[0] = X / W; xy[1] = Y / W; }
    const double D = eval(Dstd, t, s);
    return el.rational ? D / (W * W * W) : D;
  }

  bool on_patch_boundary(const Element& el, double t, double s) const {
    return (t == 0.0 && el.e0 == 0) || (t == 1.0 && el.e0 == ne(0) - 1) || (s == 0.0 && el.e1 == 0) ||
           (s == 1.0 && el.e1 == ne(1) - 1);
  }

  enum Kind { Fine, Sign, Zero, ZeroArea, Overflow };
  struct Finding {
    Kind kind = Fine;
    double t = 0.5, s = 0.5;
  };

  // Steps 2 and 3 of the header on an element that step 1 did not prove fine.
  Finding examine(const Element& el, int sigma) const {
    Poly Dstd = el.D;
    scale(Dstd, false);
    Finding f;
    double maxabs = 0;
    for (int k = 0; k < Dstd.size(); ++k) {
      if (!std::isfinite(Dstd.c[k])) { f.kind = Overflow; return f; }
      maxabs = std::max(maxabs, std::abs(Dstd.c[k]));
    }
    if (maxabs <= el.tolD) { f.kind = ZeroArea; return f; }

    // 2. samples: the solver's Gauss points and an interior grid
    std::vector<std::array<double, 2>> pts;
    const GaussRule g0 = gauss_rule(el.p0 + 1), g1 = gauss_rule(el.p1 + 1);
    for (int j = 0; j < g1.n; ++j)
      for (int i = 0; i < g0.n; ++i) pts.push_back({0.5 * (g0.x[i] + 1), 0.5 * (g1.x[j] + 1)});
    for (int j = 0; j < kGrid; ++j)
      for (int i = 0; i < kGrid; ++i) pts.push_back({(i + 0.5) / kGrid, (j + 0.5) / kGrid});
    double worst = 1e300, smallest = 1e300;
    std::array<double, 2> at_worst{0.5, 0.5}, at_smallest{0.5, 0.5};
    for (const auto& q : pts) {
      const double J = sigma * detJ_local(el, Dstd, q[0], q[1]);
      if (J < worst) { worst = J; at_worst = q; }
      if (std::abs(J) < smallest) { smallest = std::abs(J); at_smallest = q; }
    }
    if (worst < -el.tolJ) return {Sign, at_worst[0], at_worst[1]};
    if (smallest <= el.tolJ) return {Zero, at_smallest[0], at_smallest[1]};

    // 3. divide out collapsed patch edges, then subdivide
    Poly E = Dstd;
    bool on_edge[4] = {el.e0 == 0, el.e0 == ne(0) - 1, el.e1 == 0, el.e1 == ne(1) - 1};
    for (int edge = 0; edge < 4; ++edge)
      while (on_edge[edge] && edge_vanishes(E, edge, el.tolD)) divide_edge(E, edge);
    struct Piece {
      Poly c;
      double t0, t1, s0, s1;
      int depth;
    };
    std::vector<Piece> stack;
    stack.push_back({E, 0.0, 1.0, 0.0, 1.0, 0});
    int count = 0;
    while (!stack.empty()) {
      const Piece pc = stack.back();
      stack.pop_back();
      ++count;
      double lo = 1e300;
      for (int k = 0; k < pc.c.size(); ++k) lo = std::min(lo, sigma * pc.c.c[k]);
      if (lo > el.tolD) continue;
      bool boundary_zero = false;
      for (int corner = 0; corner < 4; ++corner) {
        const int i = corner % 2 ? pc.c.m0 : 0, j = corner / 2 ? pc.c.m1 : 0;
        const double t = corner % 2 ? pc.t1 : pc.t0, s = corner / 2 ? pc.s1 : pc.s0;
        const double v = sigma * pc.c.at(i, j);
        if (v < -el.tolD) return inward({Sign, t, s}, el, Dstd, sigma, pc.t0, pc.t1, pc.s0, pc.s1);
        if (std::abs(v) <= el.tolD) {
          if (!on_patch_boundary(el, t, s)) return {Zero, t, s};
          boundary_zero = true;
        }
      }
      if (pc.depth == kMaxDepth || count > kMaxPieces) {
        if (boundary_zero) continue;   // a zero of det J on the patch boundary
        return {Zero, 0.5 * (pc.t0 + pc.t1), 0.5 * (pc.s0 + pc.s1)};   // not provably non-zero
      }
      Poly a, b, q[4];
      split(pc.c, 0, a, b);
      split(a, 1, q[0], q[2]);
      split(b, 1, q[1], q[3]);
      const double tm = 0.5 * (pc.t0 + pc.t1), sm = 0.5 * (pc.s0 + pc.s1);
      stack.push_back({q[0], pc.t0, tm, pc.s0, sm, pc.depth + 1});
      stack.push_back({q[1], tm, pc.t1, pc.s0, sm, pc.depth + 1});
      stack.push_back({q[2], pc.t0, tm, sm, pc.s1, pc.depth + 1});
      stack.push_back({q[3], tm, pc.t1, sm, pc.s1, pc.depth + 1});
    }
    return f;
  }

  // A wrong sign found at a piece corner: a point inside the element with the wrong sign
  // nearby (on a collapsed edge det J itself is 0 at the corner).
  static Finding inward(Finding f, const Element& el, const Poly& Dstd, int sigma, double t0, double t1, double s0, double s1) {
    const double tc = 0.5 * (t0 + t1), sc = 0.5 * (s0 + s1);
    for (double a : {1e-3, 1e-2, 0.1, 0.5}) {
      const double t = f.t + a * (tc - f.t), s = f.s + a * (sc - f.s);
      if (sigma * detJ_local(el, Dstd, t, s) < -el.tolJ) return {Sign, t, s};
    }
    return f;
  }

  std::string message(const Element& el, const Finding& f, int sigma) const {
    Poly Dstd = el.D;
    scale(Dstd, false);
    double xy[2];
    const double J = detJ_local(el, Dstd, f.t, f.s, xy) / ((el.u1 - el.u0) * (el.v1 - el.v0));
    const double xi = el.u0 + f.t * (el.u1 - el.u0), eta = el.v0 + f.s * (el.v1 - el.v0);
    char where[512];
    std::snprintf(where, sizeof where, "element [%.6g, %.6g] x [%.6g, %.6g] (det J = %.3g at xi = %.6g, eta = %.6g, x = (%.6g, %.6g))",
                  el.u0, el.u1, el.v0, el.v1, J, xi, eta, xy[0], xy[1]);
    switch (f.kind) {
      case Sign:
        return std::string("det J changes sign in ") + where + "; the control net folds over" +
               (by_area_ ? (sigma > 0 ? " (det J is positive on most of the patch)" : " (det J is negative on most of the patch)") : "");
      case Zero: return std::string("det J vanishes inside the patch in ") + where + "; the map is degenerate there";
      case ZeroArea: return std::string("det J vanishes (zero area) on all of ") + where + "; the control net is flat there";
      case Overflow: return std::string("det J overflows in ") + where + "; the coordinates are too large";
      default: return "";
    }
  }

  std::string run() {
    const int ne0 = ne(0), ne1 = ne(1);
    std::vector<std::int8_t> cls(static_cast<size_t>(ne0) * ne1);
    Element el;
    double area = 0, area_abs = 0;
    for (int e1 = 0; e1 < ne1; ++e1)
      for (int e0 = 0; e0 < ne0; ++e0) {
        build(e0, e1, el);
        double a = 0;
        cls[e0 + static_cast<size_t>(e1) * ne0] = static_cast<std::int8_t>(classify(el, a));
        area += a;
        area_abs += std::abs(a);
      }
    by_area_ = sign_ == 0 && std::abs(area) > 1e-12 * area_abs;
    const int sigma = sign_ != 0 ? sign_ : by_area_ ? (area > 0 ? 1 : -1) : P_.orientation();
    // elements of the wrong sign throughout first (a fold is then named as such, not by the
    // zero of det J on its crease), then the undecided ones, in element order
    for (const int pass : {-sigma, 0})
      for (int e1 = 0; e1 < ne1; ++e1)
        for (int e0 = 0; e0 < ne0; ++e0) {
          if (cls[e0 + static_cast<size_t>(e1) * ne0] != pass) continue;
          build(e0, e1, el);
          full_D(el);
          const Finding f = examine(el, sigma);
          if (f.kind != Fine) return message(el, f, sigma);
        }
    return "";
  }

 private:
  const Patch& P_;
  std::array<std::vector<int>, 2> spans_;
  std::array<std::vector<std::vector<double>>, 2> C_;
  DFunction dfun_ = nullptr;
  QFunction qfun_ = nullptr;
  EFunction efun_ = nullptr;
  const int sign_;        // the sign det J must have (0: the patch's own, from its area)
  bool by_area_ = true;   // sigma from the signed area (else, a tie, from Patch::orientation())
  double inv_binom_[2][kN * kN];
};

// ---- 3-D: trivariate patches (see geometry_check.hpp, "3-D") ----
namespace three_d {

constexpr int kMaxM3 = 4 * kMaxP - 1;   // degree of D per direction, rational
constexpr int kN3 = kMaxM3 + 1;
constexpr int kMaxDepth3 = 8;           // subdivision levels (pieces of 2^-8 of the element)
constexpr int kMaxPieces3 = 20000;      // per element, a guard
constexpr int kGrid3 = 6;               // interior sample grid per direction

struct Binom3 {
  double b[kN3][kN3];
};
constexpr Binom3 make_binom3() {
  Binom3 t{};
  for (int n = 0; n < kN3; ++n) {
    t.b[n][0] = t.b[n][n] = 1;
    for (int k = 1; k < n; ++k) t.b[n][k] = t.b[n - 1][k - 1] + t.b[n - 1][k];
  }
  return t;
}
constexpr Binom3 kB3 = make_binom3();

// Trivariate Bernstein coefficients of degrees (m0, m1, m2), c[i + (m0 + 1)(j + (m1 + 1) k)].
struct Poly3 {
  std::array<int, 3> m{0, 0, 0};
  std::vector<double> c;
  int n(int d) const { return m[d] + 1; }
  size_t size() const { return c.size(); }
  size_t idx(int i, int j, int k) const { return i + static_cast<size_t>(m[0] + 1) * (j + static_cast<size_t>(m[1] + 1) * k); }
  double& at(int i, int j, int k) { return c[idx(i, j, k)]; }
  double at(int i, int j, int k) const { return c[idx(i, j, k)]; }
  static Poly3 zero(int a, int b, int d) {
    Poly3 p;
    p.m = {a, b, d};
    p.c.assign(static_cast<size_t>(a + 1) * (b + 1) * (d + 1), 0.0);
    return p;
  }
  // the stride of direction d in c
  size_t stride(int d) const { return d == 0 ? 1 : d == 1 ? static_cast<size_t>(m[0] + 1) : static_cast<size_t>(m[0] + 1) * (m[1] + 1); }
};

// standard <-> scaled (c_ijk binom(m0, i) binom(m1, j) binom(m2, k)) coefficients
void scale3(Poly3& a, bool up) {
  for (int k = 0; k <= a.m[2]; ++k)
    for (int j = 0; j <= a.m[1]; ++j)
      for (int i = 0; i <= a.m[0]; ++i) {
        const double f = kB3.b[a.m[0]][i] * kB3.b[a.m[1]][j] * kB3.b[a.m[2]][k];
        a.at(i, j, k) = up ? a.at(i, j, k) * f : a.at(i, j, k) / f;
      }
}

// scaled coefficients of the derivative along d of standard coefficients f
Poly3 derivative(const Poly3& f, int d) {
  std::array<int, 3> m = f.m;
  m[d] -= 1;
  Poly3 g = Poly3::zero(m[0], m[1], m[2]);
  const size_t st = f.stride(d);
  for (int k = 0; k <= m[2]; ++k)
    for (int j = 0; j <= m[1]; ++j)
      for (int i = 0; i <= m[0]; ++i) {
        const size_t a = f.idx(i, j, k);
        g.at(i, j, k) = f.m[d] * (f.c[a + st] - f.c[a]) * kB3.b[m[0]][i] * kB3.b[m[1]][j] * kB3.b[m[2]][k];
      }
  return g;
}

// out += sign * a * b (scaled coefficients; out of degree a.m + b.m)
void mul_add3(const Poly3& a, const Poly3& b, double sign, Poly3& out) {
  for (int ak = 0; ak <= a.m[2]; ++ak)
    for (int aj = 0; aj <= a.m[1]; ++aj)
      for (int ai = 0; ai <= a.m[0]; ++ai) {
        const double av = sign * a.at(ai, aj, ak);
        if (av == 0.0) continue;
        for (int bk = 0; bk <= b.m[2]; ++bk)
          for (int bj = 0; bj <= b.m[1]; ++bj) {
            double* o = &out.c[out.idx(ai, aj + bj, ak + bk)];
            const double* bb = &b.c[b.idx(0, bj, bk)];
            for (int bi = 0; bi <= b.m[0]; ++bi) o[bi] += av * bb[bi];
          }
      }
}

Poly3 product_sum(const Poly3& a, const Poly3& b, const Poly3& c, const Poly3& d) {   // a b - c d
  Poly3 out = Poly3::zero(a.m[0] + b.m[0], a.m[1] + b.m[1], a.m[2] + b.m[2]);
  mul_add3(a, b, 1.0, out);
  mul_add3(c, d, -1.0, out);
  return out;
}

double eval3(const Poly3& a, double t, double s, double r) {
  double B0[kN3], B1[kN3], B2[kN3];
  bernstein(a.m[0], t, B0);
  bernstein(a.m[1], s, B1);
  bernstein(a.m[2], r, B2);
  double v = 0;
  for (int k = 0; k <= a.m[2]; ++k) {
    double vs = 0;
    for (int j = 0; j <= a.m[1]; ++j) {
      double vt = 0;
      for (int i = 0; i <= a.m[0]; ++i) vt += a.at(i, j, k) * B0[i];
      vs += vt * B1[j];
    }
    v += vs * B2[k];
  }
  return v;
}

// de Casteljau at 1/2 along direction d
void split3(const Poly3& a, int d, Poly3& lo, Poly3& hi) {
  lo = a;
  hi = a;
  const int m = a.m[d];
  const size_t st = a.stride(d);
  double tmp[kN3];
  std::array<int, 3> n{a.m[0] + 1, a.m[1] + 1, a.m[2] + 1};
  n[d] = 1;
  for (int k = 0; k < n[2]; ++k)
    for (int j = 0; j < n[1]; ++j)
      for (int i = 0; i < n[0]; ++i) {
        const size_t base = a.idx(i, j, k);
        for (int q = 0; q <= m; ++q) tmp[q] = a.c[base + q * st];
        for (int q = 0; q <= m; ++q) {
          lo.c[base + q * st] = tmp[0];
          hi.c[base + (m - q) * st] = tmp[m - q];
          for (int l = 0; l < m - q; ++l) tmp[l] = 0.5 * (tmp[l] + tmp[l + 1]);
        }
      }
}

// face f = 2 d + end of the element's unit cube: all coefficients there |c| <= tol (and the
// degree along d is >= 1, so a factor can be divided out)
bool face_vanishes(const Poly3& a, int f, double tol) {
  const int d = f / 2;
  if (a.m[d] == 0) return false;
  const int fixed = f % 2 ? a.m[d] : 0;
  for (int k = 0; k <= a.m[2]; ++k)
    for (int j = 0; j <= a.m[1]; ++j)
      for (int i = 0; i <= a.m[0]; ++i) {
        const int ijk[3] = {i, j, k};
        if (ijk[d] != fixed) continue;
        if (std::abs(a.at(i, j, k)) > tol) return false;
      }
  return true;
}

// D = t E (face t = 0) or (1 - t) E (t = 1), t the coordinate of direction f / 2: E from D's
// standard coefficients
void divide_face(Poly3& a, int f) {
  const int d = f / 2, m = a.m[d];
  std::array<int, 3> em = a.m;
  em[d] -= 1;
  Poly3 e = Poly3::zero(em[0], em[1], em[2]);
  for (int k = 0; k <= em[2]; ++k)
    for (int j = 0; j <= em[1]; ++j)
      for (int i = 0; i <= em[0]; ++i) {
        int ijk[3] = {i, j, k};
        const int q = ijk[d];
        if (f % 2 == 0) {
          ijk[d] = q + 1;
          e.at(i, j, k) = a.at(ijk[0], ijk[1], ijk[2]) * m / (q + 1);
        } else {
          e.at(i, j, k) = a.at(i, j, k) * m / (m - q);
        }
      }
  a = e;
}

struct Element3 {
  std::array<int, 3> e{0, 0, 0}, p{1, 1, 1};
  std::array<double, 3> u0{}, u1{};
  std::vector<double> x[3], w;   // Bezier points (Euclidean) and weights / max
  bool rational = false;
  double tolJ = 0, tolD = 0;
  double wmin = 1, wmean = 1;   // of the weights / max
  Poly3 F[4];   // standard coefficients of W, A1, A2, A3
  Poly3 D;      // standard coefficients of D = W^4 det J (W^0 det J with equal weights)
  Poly3 M0;     // rational: standard coefficients of det [A_t; A_s; A_r] (the quick bound)
  bool has_D = false;
};

class Checker3 {
 public:
  Checker3(const Patch& P, int sign) : P_(P), bez_(P), sign_(sign) {
    for (int d = 0; d < 3; ++d) ne_[d] = bez_.num_elements(d);
  }

  // Bezier points, tolerances, the coefficients of W and A; with full, D too (else, for a
  // rational element, only M0: see classify).
  void build(int e, Element3& el, bool full) const {
    const auto& p = bez_.degree();
    for (int d = 0; d < 3; ++d) {
      el.e[d] = bez_.element_index(e, d);
      el.p[d] = p[d];
      const auto r = bez_.range(e, d);
      el.u0[d] = r[0];
      el.u1[d] = r[1];
    }
    const int nb = bez_.points_per_element();
    std::vector<ControlPoint> pts(nb);
    bez_.element_points(e, pts.data());
    double wmax = 0, wmin = 1e300, lo[3] = {1e300, 1e300, 1e300}, hi[3] = {-1e300, -1e300, -1e300};
    for (const auto& q : pts) {
      wmax = std::max(wmax, q.w);
      wmin = std::min(wmin, q.w);
      for (int d = 0; d < 3; ++d) lo[d] = std::min(lo[d], q.x[d]), hi[d] = std::max(hi[d], q.x[d]);
    }
    el.rational = wmax - wmin > 1e-13 * wmax;
    el.w.resize(nb);
    for (int d = 0; d < 3; ++d) el.x[d].resize(nb);
    double L = 0, X = 0, c[3];
    for (int d = 0; d < 3; ++d) {
      L = std::max(L, hi[d] - lo[d]);
      X = std::max(X, std::max(std::abs(lo[d]), std::abs(hi[d])));
      c[d] = 0.5 * (lo[d] + hi[d]);
    }
    el.tolJ = 1e-12 * L * L * L + 1e-15 * L * L * X;
    const double wr = el.rational ? wmin / wmax : 1.0;
    el.tolD = el.tolJ * wr * wr * wr * wr;
    // standard coefficients of W and A_d = W (x_d - c_d), and the scaled ones of their derivatives
    Poly3* F = el.F;
    for (int a = 0; a < 4; ++a) F[a] = Poly3::zero(p[0], p[1], p[2]);
    el.wmin = wmin / wmax;
    el.wmean = 0;
    for (int k = 0; k < nb; ++k) el.wmean += pts[k].w / wmax;
    el.wmean = el.rational ? el.wmean / nb : 1.0;
    for (int k = 0; k < nb; ++k) {
      el.w[k] = pts[k].w / wmax;
      const double wk = el.rational ? el.w[k] : 1.0;
      F[0].c[k] = wk;
      for (int d = 0; d < 3; ++d) {
        el.x[d][k] = pts[k].x[d];
        F[d + 1].c[k] = wk * (pts[k].x[d] - c[d]);
      }
    }
    // D = det of rows (f, f_t, f_s, f_r), columns f = W, A1, A2, A3 (rational), or of rows
    // (f_t, f_s, f_r), columns A1, A2, A3 (equal weights). The 2 x 2 minors of rows (f_s, f_r)
    // are shared by the 3 x 3 cofactors.
    const int c0 = el.rational && full ? 0 : 1;
    Poly3 dt[4], ds[4], dr[4];
    for (int a = c0; a < 4; ++a) {
      dt[a] = derivative(F[a], 0);
      ds[a] = derivative(F[a], 1);
      dr[a] = derivative(F[a], 2);
    }
    Poly3 minor[4][4];
    for (int a = c0; a < 4; ++a)
      for (int b = a + 1; b < 4; ++b) minor[a][b] = product_sum(ds[a], dr[b], dr[a], ds[b]);
    // cofactor of column x: det of rows (t, s, r) over the other columns a < b < c
    auto det3 = [&](int a, int b, int cc) {
      Poly3 out = Poly3::zero(dt[a].m[0] + minor[b][cc].m[0], dt[a].m[1] + minor[b][cc].m[1], dt[a].m[2] + minor[b][cc].m[2]);
      mul_add3(dt[a], minor[b][cc], 1.0, out);
      mul_add3(dt[b], minor[a][cc], -1.0, out);
      mul_add3(dt[cc], minor[a][b], 1.0, out);
      return out;
    };
    el.has_D = !el.rational || full;
    if (!el.rational) {
      el.D = det3(1, 2, 3);
    } else if (!full) {
      el.M0 = det3(1, 2, 3);
      scale3(el.M0, false);
      return;
    } else {
      Poly3 Fs[4];
      for (int a = 0; a < 4; ++a) {
        Fs[a] = F[a];
        scale3(Fs[a], true);
      }
      const Poly3 M[4] = {det3(1, 2, 3), det3(0, 2, 3), det3(0, 1, 3), det3(0, 1, 2)};
      el.D = Poly3::zero(M[0].m[0] + p[0], M[0].m[1] + p[1], M[0].m[2] + p[2]);
      for (int a = 0; a < 4; ++a) mul_add3(Fs[a], M[a], a % 2 ? -1.0 : 1.0, el.D);
    }
    scale3(el.D, false);
  }

  // Step 1 on an element built without full: +1 if D > tolD is proven, -1 if D < -tolD, else
  // 0; the element's volume (approximately: the integral of D over the unit cube, the mean
  // coefficient, over the mean weight to the 4th; rational: of M0 over its 3rd) for the
  // patch's orientation. Rational elements first by a quick bound: D = W M0 - A1 M1 + A2 M2 -
  // A3 M3 (the cofactor expansion along the first row), M0 = det [A_t; A_s; A_r] formed
  // exactly, |A_a M_a| bounded by the largest coefficients (|M_a| <= the permanent of the
  // largest derivatives' coefficients of its columns), so min W min M0 - R > tol proves D >
  // tol; where it fails, all coefficients of D.
  int classify(Element3& el, double& volume) const {
    auto range = [](const Poly3& a, double& lo, double& hi, double& mean) {
      lo = 1e300, hi = -1e300, mean = 0;
      for (double v : a.c) lo = std::min(lo, v), hi = std::max(hi, v), mean += v;
      mean /= static_cast<double>(a.size());
    };
    double lo, hi, mean;
    if (!el.rational) {
      range(el.D, lo, hi, mean);
      volume = mean;
      return lo > el.tolD ? 1 : (hi < -el.tolD ? -1 : 0);
    }
    range(el.M0, lo, hi, mean);
    volume = mean / (el.wmean * el.wmean * el.wmean);
    // the largest |coefficient| of each F[a] (h) and of its derivatives (g[a][d])
    double h[4], g[4][3];
    for (int a = 0; a < 4; ++a) {
      const Poly3& f = el.F[a];
      h[a] = 0;
      for (double v : f.c) h[a] = std::max(h[a], std::abs(v));
      for (int d = 0; d < 3; ++d) {
        const size_t st = f.stride(d);
        double m = 0;
        for (int k = 0; k <= f.m[2]; ++k)
          for (int j = 0; j <= f.m[1]; ++j)
            for (int i = 0; i <= f.m[0]; ++i) {
              const int ijk[3] = {i, j, k};
              if (ijk[d] == f.m[d]) continue;
              const size_t q = f.idx(i, j, k);
              m = std::max(m, std::abs(f.c[q + st] - f.c[q]));
            }
        g[a][d] = f.m[d] * m;
      }
    }
    auto permanent = [&](int a, int b, int c) {
      return g[a][0] * (g[b][1] * g[c][2] + g[b][2] * g[c][1]) + g[a][1] * (g[b][0] * g[c][2] + g[b][2] * g[c][0]) +
             g[a][2] * (g[b][0] * g[c][1] + g[b][1] * g[c][0]);
    };
    const double R = h[1] * permanent(0, 2, 3) + h[2] * permanent(0, 1, 3) + h[3] * permanent(0, 1, 2);
    if (lo > 0 && el.wmin * lo - R > el.tolD) return 1;
    if (hi < 0 && el.wmin * hi + R < -el.tolD) return -1;
    full_D(el);
    range(el.D, lo, hi, mean);
    return lo > el.tolD ? 1 : (hi < -el.tolD ? -1 : 0);
  }

  void full_D(Element3& el) const {
    if (el.has_D) return;
    build(current_, el, true);
  }

  // det J with respect to the element's local (t, s, r), and the physical point there
  static double detJ_local(const Element3& el, const Poly3& D, double t, double s, double r, double* xyz = nullptr) {
    double B0[kMaxP + 1], B1[kMaxP + 1], B2[kMaxP + 1];
    bernstein(el.p[0], t, B0);
    bernstein(el.p[1], s, B1);
    bernstein(el.p[2], r, B2);
    double W = 0, X[3] = {0, 0, 0};
    int k = 0;
    for (int c = 0; c <= el.p[2]; ++c)
      for (int j = 0; j <= el.p[1]; ++j)
        for (int i = 0; i <= el.p[0]; ++i, ++k) {
          const double b = B0[i] * B1[j] * B2[c] * el.w[k];
          W += b;
          for (int d = 0; d < 3; ++d) X[d] += b * el.x[d][k];
        }
    if (xyz)
      for (int d = 0; d < 3; ++d) xyz[d] = X[d] / W;
    const double v = eval3(D, t, s, r);
    return el.rational ? v / (W * W * W * W) : v;
  }

  bool on_patch_boundary(const Element3& el, const double* t) const {
    for (int d = 0; d < 3; ++d)
      if ((t[d] == 0.0 && el.e[d] == 0) || (t[d] == 1.0 && el.e[d] == ne_[d] - 1)) return true;
    return false;
  }

  enum Kind { Fine, Sign, Zero, ZeroVolume, Overflow };
  struct Finding {
    Kind kind = Fine;
    std::array<double, 3> t{0.5, 0.5, 0.5};
  };

  Finding examine(const Element3& el, int sigma) const {
    Finding f;
    double maxabs = 0;
    for (double v : el.D.c) {
      if (!std::isfinite(v)) { f.kind = Overflow; return f; }
      maxabs = std::max(maxabs, std::abs(v));
    }
    if (maxabs <= el.tolD) { f.kind = ZeroVolume; return f; }

    // 2. samples: the solver's Gauss points and an interior grid
    std::vector<std::array<double, 3>> pts;
    const GaussRule g[3] = {gauss_rule(el.p[0] + 1), gauss_rule(el.p[1] + 1), gauss_rule(el.p[2] + 1)};
    for (int k = 0; k < g[2].n; ++k)
      for (int j = 0; j < g[1].n; ++j)
        for (int i = 0; i < g[0].n; ++i) pts.push_back({0.5 * (g[0].x[i] + 1), 0.5 * (g[1].x[j] + 1), 0.5 * (g[2].x[k] + 1)});
    for (int k = 0; k < kGrid3; ++k)
      for (int j = 0; j < kGrid3; ++j)
        for (int i = 0; i < kGrid3; ++i) pts.push_back({(i + 0.5) / kGrid3, (j + 0.5) / kGrid3, (k + 0.5) / kGrid3});
    double worst = 1e300, smallest = 1e300;
    std::array<double, 3> at_worst{0.5, 0.5, 0.5}, at_smallest{0.5, 0.5, 0.5};
    for (const auto& q : pts) {
      const double J = sigma * detJ_local(el, el.D, q[0], q[1], q[2]);
      if (J < worst) { worst = J; at_worst = q; }
      if (std::abs(J) < smallest) { smallest = std::abs(J); at_smallest = q; }
    }
    if (worst < -el.tolJ) return {Sign, at_worst};
    if (smallest <= el.tolJ) return {Zero, at_smallest};

    // 3. divide out the faces of the patch where D vanishes identically (a face collapsed
    // onto an edge or a point), then subdivide
    Poly3 E = el.D;
    for (int face = 0; face < 6; ++face) {
      const int d = face / 2;
      const bool on_boundary = face % 2 ? el.e[d] == ne_[d] - 1 : el.e[d] == 0;
      while (on_boundary && face_vanishes(E, face, el.tolD)) divide_face(E, face);
    }
    struct Piece {
      Poly3 c;
      std::array<double, 3> a, b;
      int depth;
    };
    std::vector<Piece> stack;
    stack.push_back({E, {0.0, 0.0, 0.0}, {1.0, 1.0, 1.0}, 0});
    int count = 0;
    while (!stack.empty()) {
      Piece pc = std::move(stack.back());
      stack.pop_back();
      ++count;
      double lo = 1e300;
      for (double v : pc.c.c) lo = std::min(lo, sigma * v);
      if (lo > el.tolD) continue;
      bool boundary_zero = false;
      for (int corner = 0; corner < 8; ++corner) {
        int ijk[3];
        double t[3];
        for (int d = 0; d < 3; ++d) {
          const bool hi = (corner >> d) & 1;
          ijk[d] = hi ? pc.c.m[d] : 0;
          t[d] = hi ? pc.b[d] : pc.a[d];
        }
        const double v = sigma * pc.c.at(ijk[0], ijk[1], ijk[2]);
        if (v < -el.tolD) return inward({Sign, {t[0], t[1], t[2]}}, el, sigma, pc.a, pc.b);
        if (std::abs(v) <= el.tolD) {
          if (!on_patch_boundary(el, t)) return {Zero, {t[0], t[1], t[2]}};
          boundary_zero = true;
        }
      }
      if (pc.depth == kMaxDepth3 || count > kMaxPieces3) {
        if (boundary_zero) continue;   // a zero of det J on the patch boundary
        return {Zero, {0.5 * (pc.a[0] + pc.b[0]), 0.5 * (pc.a[1] + pc.b[1]), 0.5 * (pc.a[2] + pc.b[2])}};
      }
      // split into 8 octants
      std::vector<Piece> parts{std::move(pc)};
      for (int d = 0; d < 3; ++d) {
        std::vector<Piece> next;
        for (const Piece& q : parts) {
          Piece l{Poly3(), q.a, q.b, q.depth}, h{Poly3(), q.a, q.b, q.depth};
          split3(q.c, d, l.c, h.c);
          const double mid = 0.5 * (q.a[d] + q.b[d]);
          l.b[d] = mid;
          h.a[d] = mid;
          next.push_back(std::move(l));
          next.push_back(std::move(h));
        }
        parts.swap(next);
      }
      for (Piece& q : parts) {
        q.depth += 1;
        stack.push_back(std::move(q));
      }
    }
    return f;
  }

  // A wrong sign found at a piece corner: a point inside the element with the wrong sign nearby
  // (on a collapsed face det J itself is 0 at the corner).
  static Finding inward(Finding f, const Element3& el, int sigma, const std::array<double, 3>& a, const std::array<double, 3>& b) {
    for (double s : {1e-3, 1e-2, 0.1, 0.5}) {
      std::array<double, 3> t;
      for (int d = 0; d < 3; ++d) t[d] = f.t[d] + s * (0.5 * (a[d] + b[d]) - f.t[d]);
      if (sigma * detJ_local(el, el.D, t[0], t[1], t[2]) < -el.tolJ) return {Sign, t};
    }
    return f;
  }

  std::string message(const Element3& el, const Finding& f, int sigma) const {
    double xyz[3];
    double vol = 1;
    for (int d = 0; d < 3; ++d) vol *= el.u1[d] - el.u0[d];
    const double J = detJ_local(el, el.D, f.t[0], f.t[1], f.t[2], xyz) / vol;
    double xi[3];
    for (int d = 0; d < 3; ++d) xi[d] = el.u0[d] + f.t[d] * (el.u1[d] - el.u0[d]);
    char where[640];
    std::snprintf(where, sizeof where,
                  "element [%.6g, %.6g] x [%.6g, %.6g] x [%.6g, %.6g] (det J = %.3g at xi = %.6g, eta = %.6g, zeta = %.6g, x = (%.6g, %.6g, %.6g))",
                  el.u0[0], el.u1[0], el.u0[1], el.u1[1], el.u0[2], el.u1[2], J, xi[0], xi[1], xi[2], xyz[0], xyz[1], xyz[2]);
    switch (f.kind) {
      case Sign:
        return std::string("det J changes sign in ") + where + "; the control net folds over" +
               (by_volume_ ? (sigma > 0 ? " (det J is positive on most of the patch)" : " (det J is negative on most of the patch)") : "");
      case Zero: return std::string("det J vanishes inside the patch in ") + where + "; the map is degenerate there";
      case ZeroVolume: return std::string("det J vanishes (zero volume) on all of ") + where + "; the control net is flat there";
      case Overflow: return std::string("det J overflows in ") + where + "; the coordinates are too large";
      default: return "";
    }
  }

  std::string run() {
    const int n = bez_.num_elements();
    std::vector<std::int8_t> cls(static_cast<size_t>(n));
    Element3 el;
    double vol = 0, vol_abs = 0;
    for (int e = 0; e < n; ++e) {
      current_ = e;
      build(e, el, false);
      double v = 0;
      cls[e] = static_cast<std::int8_t>(classify(el, v));
      vol += v;
      vol_abs += std::abs(v);
    }
    by_volume_ = sign_ == 0 && std::abs(vol) > 1e-12 * vol_abs;
    const int sigma = sign_ != 0 ? sign_ : by_volume_ ? (vol > 0 ? 1 : -1) : P_.orientation();
    for (const int pass : {-sigma, 0})
      for (int e = 0; e < n; ++e) {
        if (cls[e] != pass) continue;
        build(e, el, true);
        const Finding f = examine(el, sigma);
        if (f.kind != Fine) return message(el, f, sigma);
      }
    return "";
  }

 private:
  const Patch& P_;
  BezierPatch bez_;
  const int sign_;
  std::array<int, 3> ne_{1, 1, 1};
  bool by_volume_ = true;
  mutable int current_ = 0;   // the element classify works on
};

}  // namespace three_d

}  // namespace

std::string check_jacobian(const Patch& patch, int sign) {
  if (patch.dim() == 3) {
    for (int d = 0; d < 3; ++d)
      if (patch.degree[d] < 1 || patch.degree[d] > kMaxP) return "degree outside 1.." + std::to_string(kMaxP);
    return three_d::Checker3(patch, sign).run();
  }
  if (patch.degree[0] < 1 || patch.degree[0] > kMaxP || patch.degree[1] < 1 || patch.degree[1] > kMaxP)
    return "degree outside 1.." + std::to_string(kMaxP);
  return Checker(patch, sign).run();
}

}  // namespace iga
