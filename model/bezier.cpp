#include "model/bezier.hpp"

#include <algorithm>
#include <stdexcept>

namespace iga {

std::vector<std::vector<double>> bezier_extraction_1d(const std::vector<double>& U, int p) {
  // Algorithm 1 of Borden et al. (2011), written with the paper's 1-based indices: U1(i) is
  // U[i - 1], C(c, i, k) the (i, k) entry of operator c.
  const int m = static_cast<int>(U.size());
  auto U1 = [&](int i) { return U[i - 1]; };
  const int n1 = p + 1;
  auto identity = [&] {
    std::vector<double> I(n1 * n1, 0.0);
    for (int i = 0; i < n1; ++i) I[i * n1 + i] = 1.0;
    return I;
  };
  std::vector<std::vector<double>> C{identity()};
  auto at = [&](int c, int i, int k) -> double& { return C[c - 1][(i - 1) * n1 + (k - 1)]; };
  std::vector<double> alphas(p + 2, 0.0);
  int a = p + 1, b = a + 1, nb = 1;
  while (b < m) {
    C.push_back(identity());
    const int i = b;
    while (b < m && U1(b + 1) == U1(b)) ++b;
    const int mult = b - i + 1;
    if (mult < p) {
      const double numer = U1(b) - U1(a);
      for (int j = p; j > mult; --j) alphas[j - mult] = numer / (U1(a + j) - U1(a));
      const int r = p - mult;
      for (int j = 1; j <= r; ++j) {
        const int save = r - j + 1, s = mult + j;
        for (int k = p + 1; k > s; --k) {
          const double alpha = alphas[k - s];
          for (int row = 1; row <= n1; ++row) at(nb, row, k) = alpha * at(nb, row, k) + (1.0 - alpha) * at(nb, row, k - 1);
        }
        if (b < m)
          for (int q = 0; q <= j; ++q) at(nb + 1, save + q, save) = at(nb, p - j + 1 + q, p + 1);
      }
    }
    ++nb;
    if (b < m) { a = b; ++b; }
  }
  // one operator per non-empty span; the algorithm leaves a last identity behind the end
  int ne = 0;
  for (int s = p; s + 1 < m - p; ++s)
    if (U[s + 1] > U[s]) ++ne;
  C.resize(ne);
  return C;
}

void bernstein(int p, double t, double* B) {
  // de Casteljau-style build-up: B^q_k = (1 - t) B^{q-1}_k + t B^{q-1}_{k-1}
  B[0] = 1.0;
  for (int q = 1; q <= p; ++q) {
    double saved = 0.0;
    for (int k = 0; k < q; ++k) {
      const double tmp = B[k];
      B[k] = saved + (1.0 - t) * tmp;
      saved = t * tmp;
    }
    B[q] = saved;
  }
}

BezierPatch::BezierPatch(const Patch& patch) : patch_(&patch), dim_(patch.dim()) {
  for (int d = 0; d < dim_; ++d) {
    p_[d] = patch.degree[d];
    spans_[d] = patch.element_spans(d);
    ne_[d] = static_cast<int>(spans_[d].size());
    C_[d] = bezier_extraction_1d(patch.knots[d], p_[d]);
    if (static_cast<int>(C_[d].size()) != ne_[d]) throw std::logic_error("bezier_extraction_1d: operator count");
  }
  for (int d = dim_; d < 3; ++d) {
    spans_[d] = {0};
    C_[d] = {{1.0}};
  }
}

std::array<double, 2> BezierPatch::range(int e, int d) const {
  const int s = span(e, d);
  return {patch_->knots[d][s], patch_->knots[d][s + 1]};
}

int BezierPatch::local_cp(int e, int i, int j, int k) const {
  return patch_->index(span(e, 0) - p_[0] + i, span(e, 1) - p_[1] + j, span(e, 2) - p_[2] + k);
}

void BezierPatch::extract(int e, int ncomp, const std::vector<double>& hom, double* out) const {
  // hom: the element's local control points (i fastest), nc = ncomp + 1 values each. One 1-D
  // contraction per direction d: out[.. k_d ..] = sum_i C_d[i][k_d] in[.. i ..], in increasing i.
  const int nc = ncomp + 1;
  const int n[3] = {p_[0] + 1, p_[1] + 1, p_[2] + 1};
  const size_t len = static_cast<size_t>(n[0]) * n[1] * n[2] * nc;
  std::vector<double> in(hom.begin(), hom.begin() + len), res(len);
  for (int d = 0; d < dim_; ++d) {
    const auto& C = C_[d][element_index(e, d)];
    const int stride = d == 0 ? 1 : (d == 1 ? n[0] : n[0] * n[1]);
    const int outer = static_cast<int>(len / nc) / (n[d] * stride);
    std::fill(res.begin(), res.end(), 0.0);
    for (int o = 0; o < outer; ++o)
      for (int k = 0; k < n[d]; ++k)
        for (int i = 0; i < n[d]; ++i) {
          const double c = C[i * n[d] + k];
          if (c == 0.0) continue;
          for (int r = 0; r < stride; ++r) {
            const size_t base = static_cast<size_t>(o) * n[d] * stride + r;
            const double* src = &in[(base + static_cast<size_t>(i) * stride) * nc];
            double* dst = &res[(base + static_cast<size_t>(k) * stride) * nc];
            for (int q = 0; q < nc; ++q) dst[q] += c * src[q];
          }
        }
    in.swap(res);
  }
  std::copy(in.begin(), in.end(), out);
}

void BezierPatch::element_points(int e, ControlPoint* out) const {
  const int n0 = p_[0] + 1, n1 = p_[1] + 1, n2 = p_[2] + 1, m = n0 * n1 * n2;
  constexpr int nc = kMaxDim + 1;
  std::vector<double> hom(m * nc), bez(m * nc);
  for (int k = 0; k < n2; ++k)
    for (int j = 0; j < n1; ++j)
      for (int i = 0; i < n0; ++i) {
        const ControlPoint& c = patch_->cp[local_cp(e, i, j, k)];
        double* h = &hom[(i + n0 * (j + n1 * k)) * nc];
        for (int q = 0; q < kMaxDim; ++q) h[q] = c.w * c.x[q];
        h[kMaxDim] = c.w;
      }
  extract(e, kMaxDim, hom, bez.data());
  for (int a = 0; a < m; ++a) {
    const double* b = &bez[a * nc];
    out[a].w = b[kMaxDim];
    for (int q = 0; q < kMaxDim; ++q) out[a].x[q] = b[q] / b[kMaxDim];
  }
}

void BezierPatch::element_field(int e, const double* f, int ncomp, double* out) const {
  const int n0 = p_[0] + 1, n1 = p_[1] + 1, n2 = p_[2] + 1, m = n0 * n1 * n2, nc = ncomp + 1;
  std::vector<double> hom(m * nc), bez(m * nc);
  for (int k = 0; k < n2; ++k)
    for (int j = 0; j < n1; ++j)
      for (int i = 0; i < n0; ++i) {
        const int a = local_cp(e, i, j, k);
        const double w = patch_->cp[a].w;
        double* h = &hom[(i + n0 * (j + n1 * k)) * nc];
        for (int c = 0; c < ncomp; ++c) h[c] = w * f[a * ncomp + c];
        h[ncomp] = w;
      }
  extract(e, ncomp, hom, bez.data());
  for (int k = 0; k < m; ++k)
    for (int c = 0; c < ncomp; ++c) out[k * ncomp + c] = bez[k * nc + c] / bez[k * nc + ncomp];
}

}  // namespace iga
