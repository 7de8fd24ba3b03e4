#include "model/bezier.hpp"

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

BezierPatch::BezierPatch(const Patch& patch) : patch_(&patch), p_(patch.degree) {
  for (int d = 0; d < 2; ++d) {
    spans_[d] = patch.element_spans(d);
    ne_[d] = static_cast<int>(spans_[d].size());
    C_[d] = bezier_extraction_1d(patch.knots[d], p_[d]);
    if (static_cast<int>(C_[d].size()) != ne_[d]) throw std::logic_error("bezier_extraction_1d: operator count");
  }
}

std::array<double, 2> BezierPatch::range(int e, int d) const {
  const int s = span(e, d);
  return {patch_->knots[d][s], patch_->knots[d][s + 1]};
}

void BezierPatch::extract(int e, int ncomp, const std::vector<double>& hom, double* out) const {
  // hom: (p0 + 1)(p1 + 1) local control points (i fastest), nc = ncomp + 1 values each.
  // out[(k0 + k1 (p0 + 1)) * nc + c] = sum_{i,j} C0[i][k0] C1[j][k1] hom[(i + j (p0 + 1)) * nc + c]
  const int nc = ncomp + 1, n0 = p_[0] + 1, n1 = p_[1] + 1;
  const auto& C0 = C_[0][element_index(e, 0)];
  const auto& C1 = C_[1][element_index(e, 1)];
  std::vector<double> tmp(static_cast<size_t>(n0) * n1 * nc, 0.0);   // contracted in xi
  for (int j = 0; j < n1; ++j)
    for (int k0 = 0; k0 < n0; ++k0)
      for (int i = 0; i < n0; ++i) {
        const double c = C0[i * n0 + k0];
        if (c == 0.0) continue;
        for (int q = 0; q < nc; ++q) tmp[(k0 + j * n0) * nc + q] += c * hom[(i + j * n0) * nc + q];
      }
  for (int k = 0; k < n0 * n1 * nc; ++k) out[k] = 0.0;
  for (int k1 = 0; k1 < n1; ++k1)
    for (int j = 0; j < n1; ++j) {
      const double c = C1[j * n1 + k1];
      if (c == 0.0) continue;
      for (int k0 = 0; k0 < n0; ++k0)
        for (int q = 0; q < nc; ++q) out[(k0 + k1 * n0) * nc + q] += c * tmp[(k0 + j * n0) * nc + q];
    }
}

void BezierPatch::element_points(int e, ControlPoint* out) const {
  const int n0 = p_[0] + 1, n1 = p_[1] + 1, s0 = span(e, 0), s1 = span(e, 1);
  std::vector<double> hom(n0 * n1 * 3), bez(n0 * n1 * 3);
  for (int j = 0; j < n1; ++j)
    for (int i = 0; i < n0; ++i) {
      const ControlPoint& c = patch_->cp[patch_->index(s0 - p_[0] + i, s1 - p_[1] + j)];
      double* h = &hom[(i + j * n0) * 3];
      h[0] = c.w * c.x[0]; h[1] = c.w * c.x[1]; h[2] = c.w;
    }
  extract(e, 2, hom, bez.data());
  for (int k = 0; k < n0 * n1; ++k) out[k] = ControlPoint{{bez[3 * k] / bez[3 * k + 2], bez[3 * k + 1] / bez[3 * k + 2]}, bez[3 * k + 2]};
}

void BezierPatch::element_field(int e, const double* f, int ncomp, double* out) const {
  const int n0 = p_[0] + 1, n1 = p_[1] + 1, nc = ncomp + 1, s0 = span(e, 0), s1 = span(e, 1);
  std::vector<double> hom(n0 * n1 * nc), bez(n0 * n1 * nc);
  for (int j = 0; j < n1; ++j)
    for (int i = 0; i < n0; ++i) {
      const int a = patch_->index(s0 - p_[0] + i, s1 - p_[1] + j);
      const double w = patch_->cp[a].w;
      double* h = &hom[(i + j * n0) * nc];
      for (int c = 0; c < ncomp; ++c) h[c] = w * f[a * ncomp + c];
      h[ncomp] = w;
    }
  extract(e, ncomp, hom, bez.data());
  for (int k = 0; k < n0 * n1; ++k)
    for (int c = 0; c < ncomp; ++c) out[k * ncomp + c] = bez[k * nc + c] / bez[k * nc + ncomp];
}

}  // namespace iga
