// Rational Bezier cells of all bodies as VTK XML (.vtu) and the .pvd collection: see
// io/vtk.hpp for what is computed, the point order and the array shapes.
#include "io/vtk.hpp"

#include <zlib.h>
#ifdef IGACONTACT_HAVE_LIBDEFLATE
#include <libdeflate.h>
#endif

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <functional>
#include <iomanip>
#include <limits>
#include <memory>
#include <sstream>
#include <type_traits>
#include <stdexcept>
#include <thread>

#include "io/fields.hpp"
#include "kernels/nurbs_basis.hpp"
#include "model/bezier.hpp"
#include "model/multipatch.hpp"

namespace iga {

int vtk_quad_point_index(int i, int j, int p0, int p1) {
  const bool ib = (i == 0 || i == p0), jb = (j == 0 || j == p1);
  if (ib && jb) return i ? (j ? 2 : 1) : (j ? 3 : 0);  // corners, counter-clockwise
  if (jb) return 4 + (i - 1) + (j ? (p0 - 1) + (p1 - 1) : 0);          // edges j = 0, j = p1
  if (ib) return 4 + (j - 1) + (i ? (p0 - 1) : 2 * (p0 - 1) + (p1 - 1));  // edges i = p0, i = 0
  return 4 + 2 * (p0 - 1 + p1 - 1) + (i - 1) + (p0 - 1) * (j - 1);    // face, i fastest
}

int vtk_hex_point_index(int i, int j, int k, int p0, int p1, int p2) {
  const bool ib = (i == 0 || i == p0), jb = (j == 0 || j == p1), kb = (k == 0 || k == p2);
  const int n0 = p0 - 1, n1 = p1 - 1, n2 = p2 - 1;   // interior points per edge direction
  const int corner = i ? (j ? 2 : 1) : (j ? 3 : 0);    // of the bottom face, counter-clockwise
  if (ib && jb && kb) return corner + (k ? 4 : 0);
  int off = 8;
  if (jb && kb) return off + (i - 1) + (j ? n0 + n1 : 0) + (k ? 2 * (n0 + n1) : 0);            // edges along i
  if (ib && kb) return off + (j - 1) + (i ? n0 : 2 * n0 + n1) + (k ? 2 * (n0 + n1) : 0);        // edges along j
  off += 4 * (n0 + n1);
  if (ib && jb) return off + (k - 1) + n2 * corner;                                             // edges along k
  off += 4 * n2;
  if (ib) return off + (j - 1) + n1 * (k - 1) + (i ? n1 * n2 : 0);                              // faces i = 0, p0
  off += 2 * n1 * n2;
  if (jb) return off + (i - 1) + n0 * (k - 1) + (j ? n0 * n2 : 0);                              // faces j = 0, p1
  off += 2 * n0 * n2;
  if (kb) return off + (i - 1) + n0 * (j - 1) + (k ? n0 * n1 : 0);                              // faces k = 0, p2
  off += 2 * n0 * n1;
  return off + (i - 1) + n0 * ((j - 1) + n1 * (k - 1));                                         // interior
}

std::vector<std::array<double, 2>> fit_points(int p0, int p1) {
  std::vector<std::array<double, 2>> t;
  for (int j1 = 0; j1 <= p1; ++j1)
    for (int j0 = 0; j0 <= p0; ++j0) t.push_back({static_cast<double>(j0) / p0, static_cast<double>(j1) / p1});
  return t;
}

namespace {

// The Bernstein collocation matrix of one direction, A[j][k] = B_k(j / p), j, k = 0..p, in LU
// form (partial pivoting); apply() multiplies and solve() solves one line of a tensor-product
// array in place (values x[m * stride], m = 0..p).
class Collocation1D {
 public:
  explicit Collocation1D(int p) : n_(p + 1), A_(static_cast<size_t>(n_) * n_), LU_(A_.size()), piv_(n_) {
    for (int j = 0; j < n_; ++j) bernstein(p, static_cast<double>(j) / p, &A_[static_cast<size_t>(j) * n_]);
    LU_ = A_;
    for (int c = 0; c < n_; ++c) {
      int q = c;
      for (int r = c + 1; r < n_; ++r)
        if (std::abs(LU_[r * n_ + c]) > std::abs(LU_[q * n_ + c])) q = r;
      if (LU_[q * n_ + c] == 0.0) throw std::logic_error("fit_rational_bezier: singular collocation matrix");
      piv_[c] = q;
      if (q != c)
        for (int k = 0; k < n_; ++k) std::swap(LU_[c * n_ + k], LU_[q * n_ + k]);
      for (int r = c + 1; r < n_; ++r) {
        LU_[r * n_ + c] /= LU_[c * n_ + c];
        for (int k = c + 1; k < n_; ++k) LU_[r * n_ + k] -= LU_[r * n_ + c] * LU_[c * n_ + k];
      }
    }
  }
  void apply(double* x, size_t stride) const {
    double t[kMaxBasis1D];
    for (int j = 0; j < n_; ++j) {
      t[j] = 0;
      for (int k = 0; k < n_; ++k) t[j] += A_[j * n_ + k] * x[k * stride];
    }
    for (int j = 0; j < n_; ++j) x[j * stride] = t[j];
  }
  void solve(double* x, size_t stride) const {
    double t[kMaxBasis1D];
    for (int j = 0; j < n_; ++j) t[j] = x[j * stride];
    for (int c = 0; c < n_; ++c) std::swap(t[c], t[piv_[c]]);
    for (int r = 1; r < n_; ++r)
      for (int k = 0; k < r; ++k) t[r] -= LU_[r * n_ + k] * t[k];
    for (int r = n_ - 1; r >= 0; --r) {
      for (int k = r + 1; k < n_; ++k) t[r] -= LU_[r * n_ + k] * t[k];
      t[r] /= LU_[r * n_ + r];
    }
    for (int j = 0; j < n_; ++j) x[j * stride] = t[j];
  }

 private:
  int n_;
  std::vector<double> A_, LU_;
  std::vector<int> piv_;
};

// f(x + base, stride) for every line along direction d of an array with counts n[0..dim) and
// ncomp values per entry, laid out c + ncomp (k0 + n0 (k1 + n1 k2)).
template <class F>
void for_each_line(int dim, const int* n, int ncomp, int d, double* x, F f) {
  size_t stride = static_cast<size_t>(ncomp), outer = 1;
  for (int e = 0; e < d; ++e) stride *= static_cast<size_t>(n[e]);
  for (int e = d + 1; e < dim; ++e) outer *= static_cast<size_t>(n[e]);
  for (size_t o = 0; o < outer; ++o)
    for (size_t in = 0; in < stride; ++in) f(x + o * stride * static_cast<size_t>(n[d]) + in, stride);
}

}  // namespace

// The interpolant sum_k B_k(t) w_k c_k / W(t) = v at the tensor grid t_j of fit points means
// (A_0 x .. x A_{D-1}) (w c) = W v with W = (A_0 x .. x A_{D-1}) w, A_d the Bernstein
// collocation matrix of direction d: one small solve per line and direction, O(p^{D+1}) per
// element instead of O(p^{3D}) for the dense system (216 x 216 for a 3-D element at p = 5).
void fit_rational_bezier(int dim, const int* p, const double* w, int ncomp, const double* values, double* coef) {
  int n[3] = {1, 1, 1};
  size_t N = 1;
  std::vector<Collocation1D> A;
  for (int d = 0; d < dim; ++d) {
    n[d] = p[d] + 1;
    N *= static_cast<size_t>(n[d]);
    A.emplace_back(p[d]);
  }
  std::vector<double> W(w, w + N);
  for (int d = 0; d < dim; ++d)
    for_each_line(dim, n, 1, d, W.data(), [&](double* x, size_t s) { A[d].apply(x, s); });
  for (size_t j = 0; j < N; ++j)
    for (int q = 0; q < ncomp; ++q) coef[j * ncomp + q] = W[j] * values[j * ncomp + q];
  for (int d = 0; d < dim; ++d)
    for_each_line(dim, n, ncomp, d, coef, [&](double* x, size_t s) { A[d].solve(x, s); });
  for (size_t k = 0; k < N; ++k)
    for (int q = 0; q < ncomp; ++q) coef[k * ncomp + q] /= w[k];
}

void fit_rational_bezier(int p0, int p1, const double* w, int ncomp, const double* values, double* coef) {
  const int p[2] = {p0, p1};
  fit_rational_bezier(2, p, w, ncomp, values, coef);
}

void clamp_coefficients(int n, int ncomp, const double* lo, const double* hi, double* coef) {
  for (int k = 0; k < n; ++k)
    for (int q = 0; q < ncomp; ++q) coef[k * ncomp + q] = std::clamp(coef[k * ncomp + q], lo[q], hi[q]);
}

namespace {

// First shared Bezier point of each element of one direction, and the number of points. Two
// adjacent elements share their boundary Bezier points where the knot between them has a
// multiplicity below p: the displacement is C^1 there, so the stress is continuous and the
// two elements' stress fits agree on the shared edge. At a C^0 knot (multiplicity p, and
// every knot at p = 1) each element keeps its own points and the stress may jump.
std::vector<int> shared_offsets(const std::vector<double>& U, const std::vector<int>& spans, int p, int& count) {
  std::vector<int> off(spans.size(), 0);
  for (size_t k = 1; k < spans.size(); ++k) {
    const double u = U[spans[k]];
    const auto mult = std::count(U.begin(), U.end(), u);
    off[k] = off[k - 1] + p + (mult < p ? 0 : 1);
  }
  count = spans.empty() ? 0 : off.back() + p + 1;
  return off;
}

}  // namespace

int output_samples(const OutputOptions& o, const Patch& pt) {
  return o.samples(static_cast<int>(pt.element_spans(0).size()), static_cast<int>(pt.element_spans(1).size()),
                   static_cast<long long>(pt.cp.size()));
}

namespace {

// f(i, t) for every item i in [begin, end), each once, on up to `threads` threads (t the thread,
// 0 the caller's); false where an f returned false or threw (nothing may leave a thread: the
// caller reports it on its own).
template <class F>
bool for_each_item(size_t begin, size_t end, int threads, F&& f) {
  std::atomic<size_t> next{begin};
  std::atomic<bool> ok{true};
  auto work = [&](int t) {
    try {
      for (size_t i; (i = next++) < end;)
        if (!f(i, t)) ok = false;
    } catch (...) {
      ok = false;
    }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < threads && static_cast<size_t>(t) < end - begin; ++t) pool.emplace_back(work, t);
  work(0);
  for (std::thread& t : pool) t.join();
  return ok;
}

// One family of cells: the elements of a patch `geo` in Bezier form, bivariate (quadrilaterals:
// a 2-D patch, or a face of a 3-D patch as Patch::face gives it) or trivariate (hexahedra),
// with the displacement per control point of `geo` (ncu components) and the field evaluated at
// geo's parameters.
struct CellFamily {
  const Patch* geo = nullptr;
  const std::vector<double>* u = nullptr;   // ncu per control point of geo
  int ncu = 2;
  int body = 0, patch = 0;
  // 3-D faces: the side of the volume patch (-1: the patch's own elements), its volume
  // patch, and whether the cells are transposed (i <-> j) so that their VTK normal is outward
  int face = -1;
  const Patch* volume = nullptr;
  bool flip = false;
  int samples = 0;   // the bounds grid per element and direction (0: the fit points only)
  // the field at the tensor grid t[d][0 .. n[d]) of geo's parameters in the element of spans s
  // (BodyField::eval_grid), out numbered i0 + n0 (i1 + n1 i2)
  std::function<void(const int* s, const int* n, const double* const* t, FieldPoint* out)> eval;
};

// The stress values of a field point fitted per cell: 2-D sxx, syy, szz, sxy, von Mises; 3-D
// sxx, syy, szz, sxy, syz, sxz (VTK's order), von Mises.
int stress_values(int ncu, const FieldPoint& f, double* v) {
  if (ncu == 2) {
    const double w[5] = {f.sxx, f.syy, f.szz, f.sxy, f.von_mises()};
    std::copy(w, w + 5, v);
    return 5;
  }
  const double w[7] = {f.sxx, f.syy, f.szz, f.sxy, f.syz, f.sxz, f.von_mises()};
  std::copy(w, w + 7, v);
  return 7;
}

// The cells of one family appended to m (points shared within the family, shared_offsets); the
// elements' fits on up to `threads` threads.
void add_cells(BezierMesh& m, const CellFamily& F, int threads) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  const Patch& pt = *F.geo;
  const int cd = pt.dim();   // cell dimension: 2 quadrilaterals, 3 hexahedra
  const BezierPatch B(pt);
  const int nq = F.ncu == 2 ? 5 : 7;   // fitted values: stress components and von Mises
  int p[3] = {B.degree()[0], B.degree()[1], cd == 3 ? B.degree()[2] : 0};
  const int n0 = p[0] + 1, n1 = p[1] + 1, n = B.points_per_element();
  int N[3] = {1, 1, 1};
  std::vector<int> off[3];
  for (int d = 0; d < cd; ++d) off[d] = shared_offsets(pt.knots[d], pt.element_spans(d), p[d], N[d]);
  for (int d = cd; d < 3; ++d) off[d] = {0};
  const size_t base = m.weights.size(), np = static_cast<size_t>(N[0]) * N[1] * N[2];
  m.points.resize(3 * (base + np), 0.0);
  m.weights.resize(base + np);
  m.displacement.resize(3 * (base + np), 0.0);
  m.stress.resize(6 * (base + np), 0.0);
  m.von_mises.resize(base + np);
  // per shared point the sum of the elements' fitted coefficients goes into m.stress and
  // m.von_mises (in element order); the elements that share a point, whose number divides the
  // sum and whose sampled ranges bound the mean, follow from the point's index in each
  // direction: elements first[d][I] .. last[d][I] (no arrays per point: at p = 4 those were
  // 24 MB of fresh pages per state, a third of the cells' time)
  int nel[3] = {1, 1, 1};
  std::vector<int> first[3], last[3];
  for (int d = 0; d < 3; ++d) {
    nel[d] = static_cast<int>(off[d].size());
    first[d].assign(N[d], std::numeric_limits<int>::max());
    last[d].assign(N[d], -1);
    const int pd = d < cd ? p[d] : 0;
    for (int e = 0; e < nel[d]; ++e)
      for (int i = off[d][e]; i <= off[d][e] + pd; ++i) {
        first[d][i] = std::min(first[d][i], e);
        last[d][i] = std::max(last[d][i], e);
      }
  }
  // per element (by its index in each direction) the range of its sampled values
  const size_t nelem = static_cast<size_t>(nel[0]) * nel[1] * nel[2];
  std::vector<double> elem_lo(nq * nelem, inf), elem_hi(nq * nelem, -inf);
  const auto stress_slot = [&](size_t q, int c) -> double& { return c < nq - 1 ? m.stress[6 * q + c] : m.von_mises[q]; };
  // per element the fit points (j0 / p0, j1 / p1[, j2 / p2]), j0 fastest, then the bounds grid
  // of s per element and direction (its points that are fit points too, the same doubles where
  // j s' = k p, give the same values)
  const int s = F.samples;
  int nfit[3] = {1, 1, 1}, nbound[3] = {1, 1, 1};
  bool new_points = false;   // a bounds point that is no fit point (s does not divide p)
  for (int d = 0; d < cd; ++d) {
    nfit[d] = p[d] + 1;
    nbound[d] = s > 0 ? s + 1 : 0;
    new_points = new_points || (s > 0 && p[d] % s != 0);
  }
  const size_t nb = new_points ? static_cast<size_t>(nbound[0]) * nbound[1] * nbound[2] : 0;
  // One element's part that needs no other element: its Bezier points and displacement, the
  // field at its fit points (and bounds grid), the fitted coefficients and the sampled range.
  // Elements go through it in chunks, on `threads` threads, each into its own record; the
  // records are then merged in element order below (the same numbers for any thread count).
  struct Record {
    std::vector<ControlPoint> pts;
    std::vector<double> u, coef, elo, ehi;
    std::array<double, 2> r[3];
    int sp[3], ei[3];
    double umax;
  };
  struct Scratch {
    std::vector<FieldPoint> fp;
    std::vector<double> tfit[3], tbound[3], w, vals;
  };
  auto element = [&](int e, Record& R, Scratch& W) {
    R.pts.resize(n);
    R.u.resize(F.ncu * n);
    R.coef.resize(nq * n);
    R.elo.assign(nq, inf);
    R.ehi.assign(nq, -inf);
    W.fp.resize(static_cast<size_t>(n) + nb);
    W.w.resize(n);
    W.vals.resize(nq * n);
    B.element_points(e, R.pts.data());
    B.element_field(e, F.u->data(), F.ncu, R.u.data());
    const double* tf[3] = {nullptr, nullptr, nullptr};
    const double* tbd[3] = {nullptr, nullptr, nullptr};
    for (int d = 0; d < 3; ++d) {
      R.r[d] = {0, 0};
      R.sp[d] = R.ei[d] = 0;
    }
    for (int d = 0; d < cd; ++d) {
      R.r[d] = B.range(e, d);
      R.sp[d] = B.span(e, d);
      R.ei[d] = B.element_index(e, d);
      W.tfit[d].resize(nfit[d]);
      for (int j = 0; j < nfit[d]; ++j) W.tfit[d][j] = R.r[d][0] + static_cast<double>(j) / p[d] * (R.r[d][1] - R.r[d][0]);
      tf[d] = W.tfit[d].data();
      W.tbound[d].resize(nbound[d]);
      for (int j = 0; j < nbound[d]; ++j) W.tbound[d][j] = R.r[d][0] + static_cast<double>(j) / s * (R.r[d][1] - R.r[d][0]);
      tbd[d] = W.tbound[d].data();
    }
    F.eval(R.sp, nfit, tf, W.fp.data());
    if (nb > 0) F.eval(R.sp, nbound, tbd, W.fp.data() + n);
    R.umax = 0;
    for (size_t j = 0; j < W.fp.size(); ++j) {
      const FieldPoint& f = W.fp[j];
      R.umax = std::max(R.umax, std::sqrt(f.ux * f.ux + f.uy * f.uy + f.uz * f.uz));
      double v[7];
      stress_values(F.ncu, f, v);
      for (int q = 0; q < nq; ++q) {
        R.elo[q] = std::min(R.elo[q], v[q]);
        R.ehi[q] = std::max(R.ehi[q], v[q]);
      }
      if (j < static_cast<size_t>(n)) {
        W.w[j] = R.pts[j].w;
        std::copy(v, v + nq, &W.vals[nq * j]);
      }
    }
    fit_rational_bezier(cd, p, W.w.data(), nq, W.vals.data(), R.coef.data());
  };
  const int ne = B.num_elements(), nthreads = std::max(1, threads);
  m.connectivity.reserve(m.connectivity.size() + static_cast<size_t>(ne) * n);
  m.offsets.reserve(m.offsets.size() + ne);
  m.types.reserve(m.types.size() + ne);
  m.body.reserve(m.body.size() + ne);
  m.patch.reserve(m.patch.size() + ne);
  m.element.reserve(m.element.size() + ne);
  constexpr int kChunk = 1024;
  std::vector<Record> records(static_cast<size_t>(std::min(ne, kChunk)));
  std::vector<Scratch> scratch(static_cast<size_t>(nthreads));
  for (int c0 = 0; c0 < ne; c0 += kChunk) {
    const int c1 = std::min(ne, c0 + kChunk);
    const bool ok = for_each_item(c0, c1, nthreads, [&](size_t e, int t) {
      element(static_cast<int>(e), records[e - c0], scratch[t]);
      return true;
    });
    if (!ok) throw std::runtime_error("the Bezier cells of a patch could not be built (out of memory?)");
  for (int e = c0; e < c1; ++e) {
    const Record& R = records[e - c0];
    const std::vector<ControlPoint>& pts = R.pts;
    const std::vector<double>& u = R.u;
    const std::vector<double>& coef = R.coef;
    const std::vector<double>& elo = R.elo;
    const std::vector<double>& ehi = R.ehi;
    const auto& r = R.r;
    const int* sp = R.sp;
    const int* ei = R.ei;
    m.max_displacement = std::max(m.max_displacement, R.umax);
    const size_t cbase = m.connectivity.size();
    m.connectivity.resize(cbase + n);
    for (int kk = 0; kk < n; ++kk) {
      const int i = kk % n0, j = (kk / n0) % n1, k = kk / (n0 * n1);
      const size_t g = static_cast<size_t>(off[0][ei[0]] + i) +
                       static_cast<size_t>(N[0]) * (static_cast<size_t>(off[1][ei[1]] + j) + static_cast<size_t>(N[1]) * (off[2][ei[2]] + k));
      const size_t q = base + g;
      const int at = cd == 3 ? vtk_hex_point_index(i, j, k, p[0], p[1], p[2])
                             : F.flip ? vtk_quad_point_index(j, i, p[1], p[0]) : vtk_quad_point_index(i, j, p[0], p[1]);
      m.connectivity[cbase + at] = static_cast<std::int64_t>(q);
      m.points[3 * q] = pts[kk].x[0];
      m.points[3 * q + 1] = pts[kk].x[1];
      m.weights[q] = pts[kk].w;
      m.displacement[3 * q] = u[F.ncu * kk];
      m.displacement[3 * q + 1] = u[F.ncu * kk + 1];
      if (F.ncu == 3) {   // (2-D keeps the literal zeros: a 3-D extraction of z = 0 may give -0)
        m.points[3 * q + 2] = pts[kk].x[2];
        m.displacement[3 * q + 2] = u[3 * kk + 2];
      }
      for (int c = 0; c < nq; ++c) stress_slot(q, c) += coef[nq * kk + c];
    }
    const size_t ef = static_cast<size_t>(ei[0]) + static_cast<size_t>(nel[0]) * (ei[1] + static_cast<size_t>(nel[1]) * ei[2]);
    std::copy(elo.begin(), elo.end(), &elem_lo[nq * ef]);
    std::copy(ehi.begin(), ehi.end(), &elem_hi[nq * ef]);
    m.offsets.push_back(static_cast<std::int64_t>(cbase + n));
    m.types.push_back(cd == 3 ? 79 : 77);
    m.body.push_back(F.body);
    m.patch.push_back(F.patch);
    if (F.ncu == 2) {   // 2-D: the patch's own elements
      m.degrees.insert(m.degrees.end(), {p[0], p[1], 0});
      m.element.push_back(e);
      m.element_ij.insert(m.element_ij.end(), {ei[0], ei[1]});
      m.knot_span.insert(m.knot_span.end(), {sp[0], sp[1]});
      m.range.insert(m.range.end(), {r[0][0], r[0][1], r[1][0], r[1][1]});
      continue;
    }
    // 3-D: the volume element the cell is (hexahedra) or lies on (faces)
    if (cd == 3)
      m.degrees.insert(m.degrees.end(), {p[0], p[1], p[2]});
    else if (F.flip)
      m.degrees.insert(m.degrees.end(), {p[1], p[0], 0});
    else
      m.degrees.insert(m.degrees.end(), {p[0], p[1], 0});
    const Patch& V = F.face >= 0 ? *F.volume : pt;
    int vi[3], vs[3];
    std::array<double, 2> vr[3];
    if (F.face < 0) {
      for (int d = 0; d < 3; ++d) {
        vi[d] = ei[d];
        vs[d] = sp[d];
        vr[d] = r[d];
      }
    } else {
      const int fd = side_direction(F.face), end = side_end(F.face);
      for (int d = 0, a = 0; d < 3; ++d) {
        if (d == fd) {
          const std::vector<int> spans = V.element_spans(d);
          vi[d] = end ? static_cast<int>(spans.size()) - 1 : 0;
          vs[d] = spans[vi[d]];
          const double x = end ? V.knots[d].back() : V.knots[d].front();
          vr[d] = {x, x};
        } else {
          vi[d] = ei[a];
          vs[d] = sp[a];
          vr[d] = r[a];
          ++a;
        }
      }
    }
    m.element.push_back(vi[0] + V.num_elements(0) * (vi[1] + V.num_elements(1) * vi[2]));
    m.element_ij.insert(m.element_ij.end(), {vi[0], vi[1], vi[2]});
    m.knot_span.insert(m.knot_span.end(), {vs[0], vs[1], vs[2]});
    m.range.insert(m.range.end(), {vr[0][0], vr[0][1], vr[1][0], vr[1][1], vr[2][0], vr[2][1]});
    m.face.push_back(F.face);
  }
  }
  // the shared coefficients: the mean of the elements' fits (equal to round-off where the
  // stress is continuous), clamped into the union of those elements' sampled ranges
  for (int k = 0; k < N[2]; ++k)
    for (int j = 0; j < N[1]; ++j)
      for (int i = 0; i < N[0]; ++i) {
        const size_t g = static_cast<size_t>(i) + static_cast<size_t>(N[0]) * (j + static_cast<size_t>(N[1]) * k);
        double lo[7], hi[7], c[7];
        std::fill(lo, lo + nq, inf);
        std::fill(hi, hi + nq, -inf);
        for (int e2 = first[2][k]; e2 <= last[2][k]; ++e2)
          for (int e1 = first[1][j]; e1 <= last[1][j]; ++e1)
            for (int e0 = first[0][i]; e0 <= last[0][i]; ++e0) {
              const size_t ef = static_cast<size_t>(e0) + static_cast<size_t>(nel[0]) * (e1 + static_cast<size_t>(nel[1]) * e2);
              for (int q = 0; q < nq; ++q) {
                lo[q] = std::min(lo[q], elem_lo[nq * ef + q]);
                hi[q] = std::max(hi[q], elem_hi[nq * ef + q]);
              }
            }
        const int count = (last[0][i] - first[0][i] + 1) * (last[1][j] - first[1][j] + 1) * (last[2][k] - first[2][k] + 1);
        for (int q = 0; q < nq; ++q) c[q] = stress_slot(base + g, q) / count;
        clamp_coefficients(1, nq, lo, hi, c);
        for (int q = 0; q < nq; ++q) stress_slot(base + g, q) = c[q];
      }
}

}  // namespace

BezierMesh bezier_mesh(const Problem& P, const std::vector<std::vector<double>>& cp_displacement, int threads) {
  if (cp_displacement.size() != P.bodies.size())
    throw std::invalid_argument("bezier_mesh: one displacement vector per body expected");
  const int dim = P.dim();
  BezierMesh m;
  m.dim = dim;
  for (size_t b = 0; b < P.bodies.size(); ++b) {
    if (cp_displacement[b].size() != static_cast<size_t>(dim) * static_cast<size_t>(P.bodies[b].num_cps))
      throw std::invalid_argument("bezier_mesh: body " + P.bodies[b].name + ": " + std::to_string(dim) +
                                  " displacements per control point expected");
    m.body_names.push_back(P.bodies[b].name);
  }
  // cells patch after patch of each body; points shared within a patch (shared_offsets), in
  // 3-D within a face
  for (size_t b = 0; b < P.bodies.size(); ++b)
    for (size_t k = 0; k < P.bodies[b].patches.size(); ++k) {
      const Body& body = P.bodies[b];
      const Patch& pt = body.patches[k];
      const BodyField field(P, static_cast<int>(b), cp_displacement[b], static_cast<int>(k));
      const std::vector<double> ucp = body.patch_values(static_cast<int>(k), cp_displacement[b]);
      CellFamily F;
      F.ncu = dim;
      F.body = static_cast<int>(b);
      F.patch = static_cast<int>(k);
      if (dim == 2 || P.output.volume_cells) {
        // the patch's elements: 2-D quadrilaterals, bounds from the fit points and the output
        // grid of result.xdmf; 3-D hexahedra, bounds from the fit points and, where
        // output.samples_per_element is given, that grid
        F.geo = &pt;
        F.u = &ucp;
        F.samples = dim == 2 ? output_samples(P.output, pt) : P.output.samples_per_element;
        F.eval = [&](const int* s, const int* n, const double* const* t, FieldPoint* out) { field.eval_grid(s, n, t, out); };
        add_cells(m, F, threads);
        continue;
      }
      // 3-D faces: the patch's boundary faces that are not interfaces, each a bivariate patch
      // of its own (Patch::face: the free directions in increasing order) with the volume's
      // field on it; cells transposed where that order's normal points inwards
      for (int sd = 0; sd < num_sides(3); ++sd) {
        const Side side = static_cast<Side>(sd);
        if (body.is_interface(PatchSide{static_cast<int>(k), side})) continue;
        // a face collapsed onto a curve or a point (a sphere octant's pole) has no area: no
        // boundary, no cells (the same rule as the configuration check's)
        if (side_collapsed(pt, side, body.tolerance)) continue;
        const Patch face = pt.face(side);
        const std::vector<int> idx = pt.side_indices(side);
        std::vector<double> uf(3 * idx.size());
        for (size_t a = 0; a < idx.size(); ++a)
          for (int c = 0; c < 3; ++c) uf[3 * a + c] = ucp[3 * static_cast<size_t>(idx[a]) + c];
        const int fd = side_direction(side), end = side_end(side);
        int fdirs[2], fi = 0;
        for (int d = 0; d < 3; ++d)
          if (d != fd) fdirs[fi++] = d;
        const std::vector<int> fixed_spans = pt.element_spans(fd);
        const double x_fixed = end ? pt.knots[fd].back() : pt.knots[fd].front();
        const int s_fixed = end ? fixed_spans.back() : fixed_spans.front();
        F.geo = &face;
        F.u = &uf;
        F.face = sd;
        F.volume = &pt;
        F.flip = side_normal_sign(side) * pt.orientation() < 0;
        F.samples = output_samples(P.output, face);
        F.eval = [&](const int* s, const int* n, const double* const* t, FieldPoint* out) {
          int s3[3], n3[3];
          const double* t3[3];
          t3[fd] = &x_fixed;
          s3[fd] = s_fixed;
          n3[fd] = 1;
          for (int a = 0; a < 2; ++a) {
            t3[fdirs[a]] = t[a];
            s3[fdirs[a]] = s[a];
            n3[fdirs[a]] = n[a];
          }
          field.eval_grid(s3, n3, t3, out);
        };
        add_cells(m, F, threads);
      }
    }
  return m;
}

namespace {

std::string xml_escape(const std::string& s) {
  std::string o;
  for (char c : s) {
    switch (c) {
      case '&': o += "&amp;"; break;
      case '<': o += "&lt;"; break;
      case '>': o += "&gt;"; break;
      case '"': o += "&quot;"; break;
      case '\'': o += "&apos;"; break;
      default: o += c;
    }
  }
  return o;
}

bool little_endian() {
  const std::uint16_t one = 1;
  unsigned char c;
  std::memcpy(&c, &one, 1);
  return c == 1;
}

// VTK XML string array values in ascii: the bytes of each string as integers, each string
// followed by 0.
std::string ascii_strings(const std::vector<std::string>& v) {
  std::string o;
  for (const std::string& s : v) {
    for (unsigned char c : s) o += std::to_string(static_cast<int>(c)) + " ";
    o += "0 ";
  }
  return o;
}

// Writes the DataArray elements either inline (ascii) or into the appended block.
class ArrayWriter {
 public:
  ArrayWriter(std::ostringstream& xml, VtkEncoding enc, int threads) : xml_(xml), enc_(enc), threads_(std::max(1, threads)) {}

  template <class T>
  void array(const char* type, const std::string& name, int ncomp, const std::vector<T>& v, const std::string& indent) {
    xml_ << indent << "<DataArray type=\"" << type << "\"";
    if (!name.empty()) xml_ << " Name=\"" << xml_escape(name) << "\"";
    if (ncomp > 0) xml_ << " NumberOfComponents=\"" << ncomp << "\"";
    if (enc_ == VtkEncoding::Ascii) {
      xml_ << " format=\"ascii\">\n" << indent << " ";
      std::ostringstream line;
      if constexpr (std::is_floating_point_v<T>) line << std::setprecision(std::numeric_limits<T>::max_digits10);
      for (size_t k = 0; k < v.size(); ++k) {
        if constexpr (sizeof(T) == 1)
          line << static_cast<int>(v[k]);
        else
          line << v[k];
        line << ((k + 1) % 12 == 0 && k + 1 < v.size() ? "\n " + indent : " ");
      }
      xml_ << line.str() << "\n" << indent << "</DataArray>\n";
    } else {
      const std::uint64_t bytes = v.size() * sizeof(T);
      const char* data = reinterpret_cast<const char*>(v.data());
      if (enc_ == VtkEncoding::AppendedZlib) {
        // compressed with the others in finish(): the offset is a marker until then
        xml_ << " format=\"appended\" offset=\"" << marker(payloads_.size()) << "\"/>\n";
      } else {
        xml_ << " format=\"appended\" offset=\"" << raw_offset_ << "\"/>\n";
        raw_offset_ += sizeof(bytes) + bytes;
      }
      payloads_.emplace_back(data, bytes);
    }
  }

  /// The file in pieces, in order: `xml` (the text before the appended block, offset markers
  /// replaced where zlib), each array's header and bytes (AppendedRaw) or its compressed blocks
  /// (AppendedZlib), then `tail`. The pieces point into `keep` (which takes the XML, the
  /// headers and the blocks) and into the arrays given to array(): written in turn, no byte is
  /// copied into one string (those copies of tens of MB onto fresh pages were half the
  /// encoding at p = 4).
  void finish(std::string xml, const char* tail, VtuFile& out) {
    struct Keep {
      std::string xml;
      std::vector<std::uint64_t> raw_headers;
      Compressed z;
    };
    auto keep = std::make_shared<Keep>();
    std::vector<std::string_view>& parts = out.parts;
    parts.clear();
    if (enc_ != VtkEncoding::AppendedZlib) {
      keep->xml = std::move(xml);
      for (const auto& pl : payloads_) keep->raw_headers.push_back(pl.second);
      parts.emplace_back(keep->xml);
      for (size_t k = 0; k < payloads_.size(); ++k) {
        parts.emplace_back(reinterpret_cast<const char*>(&keep->raw_headers[k]), sizeof(std::uint64_t));
        if (payloads_[k].second) parts.emplace_back(payloads_[k].first, payloads_[k].second);
      }
    } else {
      keep->z = compress_all();
      const Compressed& z = keep->z;
      std::uint64_t at = 0;
      for (size_t k = 0; k < payloads_.size(); ++k) {
        const std::string mk = marker(k);
        xml.replace(xml.find(mk), mk.size(), std::to_string(at));
        at += z.header[k].size() * sizeof(std::uint64_t);
        for (size_t j = z.first[k]; j < z.first[k + 1]; ++j) at += z.len[j];
      }
      keep->xml = std::move(xml);
      parts.emplace_back(keep->xml);
      for (size_t k = 0; k < payloads_.size(); ++k) {
        parts.emplace_back(reinterpret_cast<const char*>(z.header[k].data()), z.header[k].size() * sizeof(std::uint64_t));
        for (size_t j = z.first[k]; j < z.first[k + 1]; ++j) parts.emplace_back(reinterpret_cast<const char*>(z.block[j].get()), z.len[j]);
      }
    }
    parts.emplace_back(tail);
    out.keep.push_back(std::move(keep));
  }

 private:
  static std::string marker(size_t k) { return "\x01" + std::to_string(k) + "\x01"; }
  struct Compressed {
    std::vector<std::vector<std::uint64_t>> header;        // per array
    std::vector<size_t> first;                             // per array, its first block (and the end)
    std::vector<std::unique_ptr<unsigned char[]>> block;   // per block, uninitialised but its len bytes
    std::vector<size_t> len;
  };
  // vtkZLibDataCompressor's layout (header_type UInt64), per array: the number of blocks, the
  // block size, the size of the last block where it is partial (else 0), each block's
  // compressed size, then the blocks; each block compressed on its own in zlib's format at
  // level 1 (2.3x smaller on the cells of degree 4), by libdeflate where the build has it
  // (half zlib's time, 4 % more bytes: docs/performance.md), else by zlib. All arrays' blocks
  // are shared among threads_ threads in one pass (the bytes do not depend on how many).
  Compressed compress_all() {
    constexpr std::uint64_t block = 1 << 20;
    struct Block { size_t array; std::uint64_t at, n; };
    std::vector<Block> blocks;
    Compressed z;
    for (size_t k = 0; k < payloads_.size(); ++k) {
      z.first.push_back(blocks.size());
      for (std::uint64_t at = 0; at < payloads_[k].second; at += block)
        blocks.push_back({k, at, std::min(block, payloads_[k].second - at)});
    }
    z.first.push_back(blocks.size());
    z.block.resize(blocks.size());
    z.len.assign(blocks.size(), 0);
#ifdef IGACONTACT_HAVE_LIBDEFLATE
    // one compressor per thread (each holds its hash tables)
    std::vector<std::unique_ptr<libdeflate_compressor, void (*)(libdeflate_compressor*)>> comp;
    for (int t = 0; t < threads_; ++t) {
      comp.emplace_back(libdeflate_alloc_compressor(1), libdeflate_free_compressor);
      if (!comp.back()) throw std::runtime_error("libdeflate could not allocate a compressor for the .vtu (out of memory?)");
    }
#endif
    const bool ok = for_each_item(0, blocks.size(), threads_, [&](size_t b, int t) {
      const Block& B = blocks[b];
      const void* in = payloads_[B.array].first + B.at;
#ifdef IGACONTACT_HAVE_LIBDEFLATE
      libdeflate_compressor* c = comp[static_cast<size_t>(t)].get();
      const size_t bound = libdeflate_zlib_compress_bound(c, B.n);
      z.block[b].reset(new unsigned char[bound]);
      z.len[b] = libdeflate_zlib_compress(c, in, B.n, z.block[b].get(), bound);
      return z.len[b] > 0;
#else
      (void)t;
      uLongf len = compressBound(static_cast<uLong>(B.n));
      z.block[b].reset(new unsigned char[len]);
      const bool done = compress2(z.block[b].get(), &len, static_cast<const Bytef*>(in), static_cast<uLong>(B.n), 1) == Z_OK;
      z.len[b] = len;
      return done;
#endif
    });
    if (!ok) throw std::runtime_error("could not compress a block of the .vtu");
    for (size_t k = 0; k < payloads_.size(); ++k) {
      const std::uint64_t bytes = payloads_[k].second, nb = z.first[k + 1] - z.first[k];
      std::vector<std::uint64_t>& h = z.header.emplace_back(3 + nb);
      h[0] = nb;
      h[1] = block;
      h[2] = bytes % block;
      for (std::uint64_t j = 0; j < nb; ++j) h[3 + j] = z.len[z.first[k] + j];
    }
    return z;
  }

  std::ostringstream& xml_;
  VtkEncoding enc_;
  int threads_;
  std::uint64_t raw_offset_ = 0;   // AppendedRaw: the next array's offset
  // each array's bytes until finish() (the caller's vectors outlive it: see vtu_file, whose
  // pieces keep its converted copies)
  std::vector<std::pair<const char*, std::uint64_t>> payloads_;
};

}  // namespace

VtuFile vtu_file(const BezierMesh& m, double load_factor, const std::string& run_id, VtkEncoding enc, int threads) {
  const size_t np = m.num_points(), nc = m.num_cells();
  VtuFile out;
  // the converted arrays, which the pieces point into
  struct Converted {
    std::vector<float> stress32, vm32;
    std::vector<std::int32_t> conn32, off32;
    std::vector<std::uint8_t> types;
  };
  auto cv = std::make_shared<Converted>();
  out.keep.push_back(cv);
  std::ostringstream x;
  x << "<?xml version=\"1.0\"?>\n"
    << "<!-- igacontact run_id " << run_id << " -->\n"   // VTK writes string arrays as character codes
    // version 2.2 where hexahedra may be written: VTK >= 9.1 reads the higher-order hexahedra
    // of an older file in the legacy point order (two edges' points swapped) and converts them
    << "<VTKFile type=\"UnstructuredGrid\" version=\"" << (m.dim == 3 ? "2.2" : "1.0") << "\" byte_order=\"" << (little_endian() ? "LittleEndian" : "BigEndian")
    << "\" header_type=\"UInt64\"" << (enc == VtkEncoding::AppendedZlib ? " compressor=\"vtkZLibDataCompressor\"" : "")
    << ">\n"
    << " <UnstructuredGrid>\n"
    << "  <FieldData>\n"
    << "   <DataArray type=\"Float64\" Name=\"TimeValue\" NumberOfTuples=\"1\" format=\"ascii\">"
    << std::setprecision(17) << load_factor << "</DataArray>\n"
    << "   <Array type=\"String\" Name=\"run_id\" NumberOfTuples=\"1\" format=\"ascii\">" << ascii_strings({run_id})
    << "</Array>\n"
    << "   <Array type=\"String\" Name=\"body_names\" NumberOfTuples=\"" << m.body_names.size() << "\" format=\"ascii\">"
    << ascii_strings(m.body_names) << "</Array>\n"
    << "  </FieldData>\n"
    << "  <Piece NumberOfPoints=\"" << np << "\" NumberOfCells=\"" << nc << "\">\n";
  ArrayWriter w(x, enc, threads);
  const std::string in = "    ";
  x << "   <PointData Scalars=\"von_mises\" Vectors=\"displacement\" Tensors=\"stress\" RationalWeights=\"RationalWeights\">\n";
  w.array("Float64", "RationalWeights", 0, m.weights, in);
  w.array("Float64", "displacement", 3, m.displacement, in);
  // the stress fit is a picture of a field that is not in the spline space: Float32 (the
  // geometry and the displacement, exact, stay Float64)
  // (the converted arrays live as long as the pieces: finish() compresses every array at the end)
  cv->stress32.assign(m.stress.begin(), m.stress.end());
  cv->vm32.assign(m.von_mises.begin(), m.von_mises.end());
  w.array("Float32", "stress", 6, cv->stress32, in);
  w.array("Float32", "von_mises", 0, cv->vm32, in);
  x << "   </PointData>\n"
    << "   <CellData Scalars=\"body\" HigherOrderDegrees=\"HigherOrderDegrees\">\n";
  w.array("Int32", "HigherOrderDegrees", 3, m.degrees, in);
  w.array("Int32", "body", 0, m.body, in);
  w.array("Int32", "patch", 0, m.patch, in);
  w.array("Int32", "element", 0, m.element, in);
  w.array("Int32", "element_ij", m.dim, m.element_ij, in);
  w.array("Int32", "knot_span", m.dim, m.knot_span, in);
  w.array("Float64", "parametric_range", 2 * m.dim, m.range, in);
  if (m.dim == 3) w.array("Int32", "face", 0, m.face, in);
  x << "   </CellData>\n   <Points>\n";
  w.array("Float64", "Points", 3, m.points, in);
  x << "   </Points>\n   <Cells>\n";
  // VTK_BEZIER_QUADRILATERAL (77), VTK_BEZIER_HEXAHEDRON (79)
  const std::vector<std::uint8_t>& types = m.types.size() == nc ? m.types : (cv->types.assign(nc, 77), cv->types);
  if (m.connectivity.size() < static_cast<size_t>(std::numeric_limits<std::int32_t>::max())) {
    cv->conn32.assign(m.connectivity.begin(), m.connectivity.end());
    cv->off32.assign(m.offsets.begin(), m.offsets.end());
    w.array("Int32", "connectivity", 0, cv->conn32, in);
    w.array("Int32", "offsets", 0, cv->off32, in);
  } else {
    w.array("Int64", "connectivity", 0, m.connectivity, in);
    w.array("Int64", "offsets", 0, m.offsets, in);
  }
  w.array("UInt8", "types", 0, types, in);
  x << "   </Cells>\n  </Piece>\n </UnstructuredGrid>\n";
  if (enc == VtkEncoding::Ascii) {
    x << "</VTKFile>\n";
    auto text = std::make_shared<std::string>(x.str());
    out.parts.emplace_back(*text);
    out.keep.push_back(text);
    return out;
  }
  x << " <AppendedData encoding=\"raw\">\n  _";
  w.finish(x.str(), "\n </AppendedData>\n</VTKFile>\n", out);   // zlib: the arrays compressed, their offsets into the XML
  return out;
}

std::size_t VtuFile::size() const {
  std::size_t n = 0;
  for (const std::string_view& p : parts) n += p.size();
  return n;
}

std::string VtuFile::str() const {
  std::string s;
  s.reserve(size());
  for (const std::string_view& p : parts) s.append(p);
  return s;
}

std::string vtu_text(const BezierMesh& m, double load_factor, const std::string& run_id, VtkEncoding enc, int threads) {
  return vtu_file(m, load_factor, run_id, enc, threads).str();
}

std::size_t vtu_raw_bytes(const BezierMesh& m) {
  const std::size_t np = m.num_points(), nc = m.num_cells();
  // points, weights, displacement (Float64), stress and von Mises (Float32); the cell data
  // (Int32 but the parametric ranges), connectivity, offsets, types
  return np * (3 * 8 + 8 + 3 * 8 + 6 * 4 + 4) + nc * (3 + 3 + 2 * m.dim + 1) * 4 + nc * 2 * m.dim * 8 +
         m.connectivity.size() * 4 + nc * (4 + 1);
}

std::string bezier_vtu(const Problem& P, const std::vector<std::vector<double>>& cp_displacement, double load_factor,
                       const std::string& run_id, VtkEncoding encoding) {
  return vtu_text(bezier_mesh(P, cp_displacement), load_factor, run_id, encoding);
}

std::string pvd_collection(const std::vector<std::pair<double, std::string>>& steps) {
  std::ostringstream x;
  x << std::setprecision(17);
  x << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\""
    << (little_endian() ? "LittleEndian" : "BigEndian") << "\">\n <Collection>\n";
  for (const auto& s : steps)
    x << "  <DataSet timestep=\"" << s.first << "\" group=\"\" part=\"0\" file=\"" << xml_escape(s.second) << "\"/>\n";
  x << " </Collection>\n</VTKFile>\n";
  return x.str();
}

}  // namespace iga
