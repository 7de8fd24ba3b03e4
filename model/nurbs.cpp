#include "model/nurbs.hpp"

#include <Teuchos_SerialDenseMatrix.hpp>
#include <Teuchos_SerialDenseSolver.hpp>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "kernels/nurbs_basis.hpp"

namespace iga {

const char* side_name(Side s) {
  switch (s) {
    case Side::West: return "west";
    case Side::East: return "east";
    case Side::South: return "south";
    case Side::North: return "north";
    case Side::Front: return "front";
    case Side::Back: return "back";
  }
  return "?";
}

bool parse_side(const std::string& name, Side& s, int dim) {
  static const char* names[] = {"west", "east", "south", "north", "front", "back"};
  for (int k = 0; k < num_sides(dim); ++k)
    if (name == names[k]) { s = static_cast<Side>(k); return true; }
  return false;
}

std::vector<double> uniform_open_knots(int p, int n) {
  std::vector<double> U(p + 1, 0.0);
  for (int k = 1; k < n; ++k) U.push_back(static_cast<double>(k) / n);
  U.insert(U.end(), p + 1, 1.0);
  return U;
}

std::vector<int> nonempty_spans(const std::vector<double>& U, int p) {
  std::vector<int> s;
  const int nb = static_cast<int>(U.size()) - p - 1;
  for (int k = p; k < nb; ++k)
    if (U[k + 1] > U[k]) s.push_back(k);
  return s;
}

namespace {

// A control point in homogeneous coordinates (w x, w y, w z, w): the last entry is the weight.
using Homogeneous = std::array<double, kMaxDim + 1>;
constexpr int kHom = kMaxDim + 1;

// Homogeneous evaluation of a 1-D B-spline with homogeneous control points Pw at u.
Homogeneous bspline_point(const std::vector<double>& U, int p, const std::vector<Homogeneous>& Pw, double u) {
  const int nb = static_cast<int>(Pw.size());
  const int span = find_span(nb, p, u, U.data());
  double ders[3][kMaxBasis1D];
  bspline_ders(span, u, p, U.data(), 0, ders);
  Homogeneous r{};
  for (int j = 0; j <= p; ++j)
    for (int c = 0; c < kHom; ++c) r[c] += ders[0][j] * Pw[span - p + j][c];
  return r;
}

// Knot insertion of u once into (U, p, Pw) (homogeneous), Boehm's algorithm.
void insert_1d(std::vector<double>& U, int p, std::vector<Homogeneous>& Pw, double u) {
  const int nb = static_cast<int>(Pw.size());
  const int k = find_span(nb, p, u, U.data());
  std::vector<Homogeneous> Q(nb + 1);
  for (int i = 0; i <= k - p; ++i) Q[i] = Pw[i];
  for (int i = k; i < nb; ++i) Q[i + 1] = Pw[i];
  for (int i = k - p + 1; i <= k; ++i) {
    const double alpha = (u - U[i]) / (U[i + p] - U[i]);
    for (int c = 0; c < kHom; ++c) Q[i][c] = alpha * Pw[i][c] + (1.0 - alpha) * Pw[i - 1][c];
  }
  U.insert(U.begin() + k + 1, u);
  Pw = std::move(Q);
}

// Degree elevation by t of (U, p, Pw) by interpolation at the Greville abscissae of the
// elevated space. Returns the new knots; Pw and p are updated.
std::vector<double> elevate_1d(const std::vector<double>& U, int& p, std::vector<Homogeneous>& Pw, int t) {
  std::vector<double> V;
  // every distinct knot gets its multiplicity raised by t
  for (size_t k = 0; k < U.size();) {
    size_t m = k;
    while (m < U.size() && U[m] == U[k]) ++m;
    V.insert(V.end(), (m - k) + t, U[k]);
    k = m;
  }
  const int q = p + t;
  const int nb = static_cast<int>(V.size()) - q - 1;
  Teuchos::SerialDenseMatrix<int, double> A(nb, nb);
  Teuchos::SerialDenseMatrix<int, double> B(nb, kHom), X(nb, kHom);
  for (int i = 0; i < nb; ++i) {
    double g = 0;
    for (int k = 1; k <= q; ++k) g += V[i + k];
    g /= q;
    const int span = find_span(nb, q, g, V.data());
    double ders[3][kMaxBasis1D];
    bspline_ders(span, g, q, V.data(), 0, ders);
    for (int j = 0; j <= q; ++j) A(i, span - q + j) = ders[0][j];
    const Homogeneous r = bspline_point(U, p, Pw, g);
    for (int c = 0; c < kHom; ++c) B(i, c) = r[c];
  }
  Teuchos::SerialDenseSolver<int, double> solver;
  solver.setMatrix(Teuchos::rcpFromRef(A));
  solver.setVectors(Teuchos::rcpFromRef(X), Teuchos::rcpFromRef(B));
  solver.factorWithEquilibration(true);
  if (solver.solve() != 0) throw std::runtime_error("degree elevation: singular collocation matrix");
  Pw.assign(nb, Homogeneous{});
  for (int i = 0; i < nb; ++i)
    for (int c = 0; c < kHom; ++c) Pw[i][c] = X(i, c);
  p = q;
  return V;
}

Homogeneous to_homogeneous(const ControlPoint& P) {
  Homogeneous h;
  for (int c = 0; c < kMaxDim; ++c) h[c] = P.x[c] * P.w;
  h[kMaxDim] = P.w;
  return h;
}
ControlPoint from_homogeneous(const Homogeneous& h) {
  ControlPoint P;
  for (int c = 0; c < kMaxDim; ++c) P.x[c] = h[c] / h[kMaxDim];
  P.w = h[kMaxDim];
  return P;
}

}  // namespace

std::vector<int> Curve::element_spans() const { return nonempty_spans(knots, degree); }

std::array<double, 2> Curve::eval(double u) const {
  std::vector<Homogeneous> Pw(cp.size());
  std::transform(cp.begin(), cp.end(), Pw.begin(), to_homogeneous);
  const Homogeneous r = bspline_point(knots, degree, Pw, u);
  return {r[0] / r[kMaxDim], r[1] / r[kMaxDim]};
}

std::array<double, 2> Curve::derivative(double u) const {
  const int p = degree, nb = ncp();
  const int span = find_span(nb, p, u, knots.data());
  double ders[3][kMaxBasis1D];
  bspline_ders(span, u, p, knots.data(), 1, ders);
  double A[2] = {0, 0}, dA[2] = {0, 0}, W = 0, dW = 0;
  for (int j = 0; j <= p; ++j) {
    const ControlPoint& c = cp[span - p + j];
    for (int k = 0; k < 2; ++k) {
      A[k] += ders[0][j] * c.w * c.x[k];
      dA[k] += ders[1][j] * c.w * c.x[k];
    }
    W += ders[0][j] * c.w;
    dW += ders[1][j] * c.w;
  }
  return {(dA[0] - A[0] / W * dW) / W, (dA[1] - A[1] / W * dW) / W};
}

std::vector<int> Patch::element_spans(int d) const { return nonempty_spans(knots[d], degree[d]); }

std::string Patch::validate() const {
  std::ostringstream os;
  if (pdim != 2 && pdim != 3) return "parametric dimension " + std::to_string(pdim) + " is not 2 or 3";
  for (int d = 0; d < pdim; ++d) {
    const int p = degree[d];
    const auto& U = knots[d];
    if (p < 1 || p > kMaxDegree) {
      os << "degree[" << d << "] = " << p << " is outside 1.." << kMaxDegree;
      return os.str();
    }
    if (static_cast<int>(U.size()) < 2 * (p + 1)) {
      os << "knots[" << d << "] has " << U.size() << " entries, an open knot vector of degree " << p
         << " needs at least " << 2 * (p + 1);
      return os.str();
    }
    for (size_t k = 1; k < U.size(); ++k)
      if (U[k] < U[k - 1]) {
        os << "knots[" << d << "] is not non-decreasing at entry " << k << " (" << U[k - 1] << " > "
           << U[k] << ")";
        return os.str();
      }
    for (int k = 1; k <= p; ++k)
      if (U[k] != U[0] || U[U.size() - 1 - k] != U.back()) {
        os << "knots[" << d << "] is not open: the first and last " << p + 1
           << " knots must be equal for degree " << p;
        return os.str();
      }
    if (!(U.back() > U.front())) {
      os << "knots[" << d << "] spans an empty interval";
      return os.str();
    }
    for (size_t k = p + 1; k + p + 1 < U.size();) {
      size_t m = k;
      while (m < U.size() && U[m] == U[k]) ++m;
      if (static_cast<int>(m - k) > p) {
        os << "knots[" << d << "] repeats the interior knot " << U[k] << " " << (m - k)
           << " times; at most " << p << " keep the patch continuous";
        return os.str();
      }
      k = m;
    }
  }
  long expected = 1;
  for (int d = 0; d < pdim; ++d) expected *= ncp(d);
  if (static_cast<long>(cp.size()) != expected) {
    os << "control_points has " << cp.size() << " points, degrees and knots need " << ncp(0);
    for (int d = 1; d < pdim; ++d) os << " x " << ncp(d);
    os << " = " << expected;
    return os.str();
  }
  for (size_t a = 0; a < cp.size(); ++a)
    if (!(cp[a].w > 0)) {
      os << "control_points[" << a << "] has weight " << cp[a].w << "; weights must be > 0";
      return os.str();
    }
  return "";
}

std::array<double, 2> Patch::eval(double u, double v) const {
  const int n0 = ncp(0), n1 = ncp(1);
  const int s0 = find_span(n0, degree[0], u, knots[0].data());
  const int s1 = find_span(n1, degree[1], v, knots[1].data());
  double N[3][kMaxBasis1D], M[3][kMaxBasis1D];
  bspline_ders(s0, u, degree[0], knots[0].data(), 0, N);
  bspline_ders(s1, v, degree[1], knots[1].data(), 0, M);
  double x = 0, y = 0, w = 0;
  for (int j = 0; j <= degree[1]; ++j)
    for (int i = 0; i <= degree[0]; ++i) {
      const ControlPoint& P = cp[index(s0 - degree[0] + i, s1 - degree[1] + j)];
      const double b = N[0][i] * M[0][j] * P.w;
      x += b * P.x[0]; y += b * P.x[1]; w += b;
    }
  return {x / w, y / w};
}

std::array<double, kMaxDim> Patch::point(const double* t) const {
  double N[kMaxDim][3][kMaxBasis1D];
  int s[kMaxDim] = {0, 0, 0}, m[kMaxDim] = {1, 1, 1};
  for (int d = 0; d < pdim; ++d) {
    s[d] = find_span(ncp(d), degree[d], t[d], knots[d].data());
    bspline_ders(s[d], t[d], degree[d], knots[d].data(), 0, N[d]);
    m[d] = degree[d] + 1;
  }
  for (int d = pdim; d < kMaxDim; ++d) N[d][0][0] = 1.0;
  Homogeneous r{};
  for (int k = 0; k < m[2]; ++k)
    for (int j = 0; j < m[1]; ++j)
      for (int i = 0; i < m[0]; ++i) {
        const int a = index(s[0] - (m[0] - 1) + i, s[1] - (m[1] - 1) + j, s[2] - (m[2] - 1) + k);
        const double b = N[0][0][i] * N[1][0][j] * N[2][0][k] * cp[a].w;
        for (int c = 0; c < kMaxDim; ++c) r[c] += b * cp[a].x[c];
        r[kMaxDim] += b;
      }
  std::array<double, kMaxDim> x{};
  for (int c = 0; c < kMaxDim; ++c) x[c] = r[c] / r[kMaxDim];
  return x;
}

int Patch::orientation() const {
  if (pdim == 3) {
    // det of the central-difference Jacobian at the parametric centre
    double J[3][3];
    for (int d = 0; d < 3; ++d) {
      double tp[3], tm[3];
      for (int e = 0; e < 3; ++e) tp[e] = tm[e] = 0.5 * (knots[e].front() + knots[e].back());
      const double h = 1e-6 * (knots[d].back() - knots[d].front());
      tp[d] += h;
      tm[d] -= h;
      const auto a = point(tp), b = point(tm);
      for (int c = 0; c < 3; ++c) J[c][d] = a[c] - b[c];
    }
    const double det = J[0][0] * (J[1][1] * J[2][2] - J[1][2] * J[2][1]) -
                       J[0][1] * (J[1][0] * J[2][2] - J[1][2] * J[2][0]) +
                       J[0][2] * (J[1][0] * J[2][1] - J[1][1] * J[2][0]);
    return det >= 0 ? 1 : -1;
  }
  const double u = 0.5 * (knots[0].front() + knots[0].back());
  const double v = 0.5 * (knots[1].front() + knots[1].back());
  const double hu = 1e-6 * (knots[0].back() - knots[0].front());
  const double hv = 1e-6 * (knots[1].back() - knots[1].front());
  const auto a = eval(u + hu, v), b = eval(u - hu, v), c = eval(u, v + hv), d = eval(u, v - hv);
  const double det = (a[0] - b[0]) * (c[1] - d[1]) - (a[1] - b[1]) * (c[0] - d[0]);
  return det >= 0 ? 1 : -1;
}

namespace {
// The control point index of position k along direction d of line r (r numbers the lines
// along d by the other directions' indices, the lowest direction fastest).
int line_index(const Patch& P, const int* n, int d, int r, int k) {
  int ij[kMaxDim] = {0, 0, 0};
  for (int e = 0; e < kMaxDim; ++e) {
    if (e == d) continue;
    ij[e] = r % n[e];
    r /= n[e];
  }
  ij[d] = k;
  return P.index(ij[0], ij[1], ij[2]);
}

// Applies a 1-D operation to every line of the homogeneous net along direction d (rows for
// d = 0, columns for d = 1, ...).
template <class Op>
void apply_rows(Patch& P, int d, Op op) {
  int n[kMaxDim];
  for (int e = 0; e < kMaxDim; ++e) n[e] = P.ncp(e);
  const int nline = n[d];
  int nrows = 1;
  for (int e = 0; e < kMaxDim; ++e)
    if (e != d) nrows *= n[e];
  std::vector<std::vector<Homogeneous>> lines(nrows);
  for (int r = 0; r < nrows; ++r) {
    lines[r].resize(nline);
    for (int k = 0; k < nline; ++k) lines[r][k] = to_homogeneous(P.cp[line_index(P, n, d, r, k)]);
  }
  std::vector<double> newU;
  int newp = P.degree[d];
  for (int r = 0; r < nrows; ++r) {
    std::vector<double> U = P.knots[d];
    int p = P.degree[d];
    op(U, p, lines[r]);
    newU = U; newp = p;
  }
  P.knots[d] = newU;
  P.degree[d] = newp;
  const int m = static_cast<int>(lines[0].size());
  P.cp.assign(static_cast<size_t>(m) * nrows, ControlPoint{});
  n[d] = m;
  for (int r = 0; r < nrows; ++r)
    for (int k = 0; k < m; ++k) P.cp[line_index(P, n, d, r, k)] = from_homogeneous(lines[r][k]);
}
}  // namespace

void Patch::insert_knot(int d, double u) {
  apply_rows(*this, d, [u](std::vector<double>& U, int& p, std::vector<Homogeneous>& Pw) { insert_1d(U, p, Pw, u); });
}

void Patch::subdivide(int d, int n) {
  if (n <= 1) return;
  std::vector<double> newknots;
  for (int s : element_spans(d)) {
    const double a = knots[d][s], b = knots[d][s + 1];
    for (int k = 1; k < n; ++k) newknots.push_back(a + (b - a) * k / n);
  }
  apply_rows(*this, d, [&](std::vector<double>& U, int& p, std::vector<Homogeneous>& Pw) {
    for (double u : newknots) insert_1d(U, p, Pw, u);
  });
}

void Patch::elevate(int d, int t) {
  if (t <= 0) return;
  if (degree[d] + t > kMaxDegree)
    throw std::runtime_error("degree elevation beyond the supported maximum degree " + std::to_string(kMaxDegree));
  apply_rows(*this, d, [t](std::vector<double>& U, int& p, std::vector<Homogeneous>& Pw) { U = elevate_1d(U, p, Pw, t); });
}

std::vector<int> Patch::side_indices(Side s) const {
  std::vector<int> idx;
  const int n[kMaxDim] = {ncp(0), ncp(1), ncp(2)};
  if (pdim == 2) {
    for (int k = 0; k < n[side_tangent_direction(s)]; ++k) idx.push_back(side_tensor_index(static_cast<int>(s), &k, n, 2));
    return idx;
  }
  int f[2], fi = 0;
  for (int e = 0; e < 3; ++e)
    if (e != side_direction(s)) f[fi++] = e;
  for (int k1 = 0; k1 < n[f[1]]; ++k1)
    for (int k0 = 0; k0 < n[f[0]]; ++k0) {
      const int k[2] = {k0, k1};
      idx.push_back(side_tensor_index(static_cast<int>(s), k, n, 3));
    }
  return idx;
}

Patch Patch::face(Side s) const {
  Patch F;
  F.pdim = 2;
  for (int e = 0, fi = 0; e < 3; ++e) {
    if (e == side_direction(s)) continue;
    F.degree[fi] = degree[e];
    F.knots[fi] = knots[e];
    ++fi;
  }
  F.degree[2] = 0;
  for (int a : side_indices(s)) F.cp.push_back(cp[a]);
  return F;
}

Curve Patch::side_curve(Side s) const {
  Curve c;
  const int d = side_tangent_direction(s);
  c.degree = degree[d];
  c.knots = knots[d];
  c.patch_index = side_indices(s);
  for (int a : c.patch_index) c.cp.push_back(cp[a]);
  return c;
}

}  // namespace iga
