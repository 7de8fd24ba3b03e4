#include "io/fields.hpp"

#include <cmath>
#include <stdexcept>

#include "kernels/material.hpp"
#include "solver/system.hpp"

namespace iga {

double FieldPoint::von_mises() const {
  // (the 3-D shear terms are exactly 0 in 2-D: adding them leaves the 2-D value's bits)
  return std::sqrt(0.5 * ((sxx - syy) * (sxx - syy) + (syy - szz) * (syy - szz) + (szz - sxx) * (szz - sxx)) +
                   3.0 * sxy * sxy + 3.0 * (syz * syz + sxz * sxz));
}

BodyField::BodyField(const Problem& P, int body, const std::vector<double>& u, int patch)
    : patch_(&P.bodies[body].patches[patch]),
      dim_(P.bodies[body].patches[patch].dim()),
      mat_(body_material(P, body, 1.0)),   // 3-D: the full-tensor laws (Material::solid)
      plane_strain_(P.analysis == Analysis::PlaneStrain),
      nu_(P.bodies[body].nu),
      u_(P.bodies[body].patch_values(patch, u)) {
  if (dim_ == 3)
    pd3_ = host_patch_data3(*patch_);
  else
    pd_ = host_patch_data(*patch_);
}

FieldPoint BodyField::eval(const double* t, const int* sp) const {
  int s[3];
  const int D = dim_;
  for (int d = 0; d < D; ++d) {
    const int nb = D == 3 ? pd3_.n[d] : pd_.n[d], p = D == 3 ? pd3_.p[d] : pd_.p[d];
    const double* U = D == 3 ? pd3_.U[d].data() : pd_.U[d].data();
    s[d] = sp && sp[d] >= 0 ? sp[d] : find_span(nb, p, t[d], U);
  }
  const int n[3] = {1, 1, 1};
  const double* tt[3] = {&t[0], &t[1], D == 3 ? &t[2] : nullptr};
  FieldPoint f;
  eval_grid(s, n, tt, &f);
  return f;
}

FieldPoint BodyField::eval(double u, double v, int s0, int s1) const {
  if (dim_ != 2) throw std::logic_error("BodyField::eval(u, v): a 3-D patch needs three parameters");
  const double t[2] = {u, v};
  const int s[2] = {s0, s1};
  return eval(t, s);
}

void BodyField::eval_grid(const int* s, const int* n, const double* const* t, FieldPoint* out) const {
  if (dim_ == 3)
    grid<3>(pd3_, s, n, t, out);
  else
    grid<2>(pd_, s, n, t, out);
}

// x, u and H = Grad u from the NURBS basis (nurbs_grad_tensor on the kernels' patch data: the
// same arithmetic as nurbs_grad at each point), then the kernels' law and sigma = P F^T / J
// (small strain: P).
// 3-D: where the map is degenerate (det J = 0 on a face collapsed onto an edge or a point, as
// the pole of a sphere octant) Grad u does not exist: the basis functions' physical gradients
// are unbounded there, and a discrete solution whose control points on the collapsed face
// differ (independent dofs) has a stress growing like 1/distance in a thin layer (measured on a
// thick sphere octant, p = 2, 6 x 6 x 4: sound at 6e-3 of an element from the pole, -47 at
// 6e-5, -6500 at 1e-6, against an exact 7.1; NaN on the pole itself). H is taken at the point
// moved 1 % of the way towards the element's centre, outside that layer (there: 6.9, 6.5, -9.6
// against 7.1, 7.1, -10); x, u and detJ stay those of the point itself. The output's other
// evaluation points lie 1 / p or 1 / s (s <= 64 samples) of an element or more from the face.
template <int D, class PD>
void BodyField::grid(const PD& pd, const int* s, const int* n, const double* const* t, FieldPoint* out) const {
  int pmax = 1;
  for (int d = 0; d < D; ++d) pmax = std::max(pmax, pd.p[d]);
  // each direction's 1-D B-spline values and first derivatives, per parameter (on the stack
  // for up to kSmall parameters: one point, an element's fit points)
  constexpr int kSmall = kMaxBasis1D, kPer = 3 * kMaxBasis1D;
  double small[D][kSmall * kPer];
  std::vector<double> large[D];
  double* N[D];
  for (int d = 0; d < D; ++d) {
    if (n[d] <= kSmall) {
      N[d] = small[d];
    } else {
      large[d].resize(static_cast<size_t>(n[d]) * kPer);
      N[d] = large[d].data();
    }
    for (int i = 0; i < n[d]; ++i)
      bspline_ders(s[d], t[d][i], pd.p[d], pd.U[d].data(), 1, reinterpret_cast<double(*)[kMaxBasis1D]>(N[d] + static_cast<size_t>(i) * kPer));
  }
  dispatch_degree(pmax, [&](auto PP) {
    constexpr int P = decltype(PP)::value;
    constexpr int nen = kNen<D, P>;
    double cw[nen][D + 1], R[nen], dR[nen][D], x[D];
    int cps[nen];
    element_homogeneous_cp<P>(pd, s, cw);
    pd.local_cps(s, cps);
    const int ne = pd.nen();
    const int n2 = D == 3 ? n[2] : 1;
    FieldPoint* f = out;
    for (int i2 = 0; i2 < n2; ++i2)
      for (int i1 = 0; i1 < n[1]; ++i1)
        for (int i0 = 0; i0 < n[0]; ++i0, ++f) {
          const int ii[3] = {i0, i1, i2};
          const double(*B[D])[kMaxBasis1D];
          for (int d = 0; d < D; ++d)
            B[d] = reinterpret_cast<const double(*)[kMaxBasis1D]>(N[d] + static_cast<size_t>(ii[d]) * kPer);
          *f = FieldPoint{};
          double g[D][D] = {}, uu[D] = {};
          // H = Grad u from the basis gradients (and u where `values`)
          auto contract = [&](bool values) {
            for (int c = 0; c < D; ++c)
              for (int e = 0; e < D; ++e) g[c][e] = 0;
            for (int a = 0; a < ne; ++a) {
              const double* ua = &u_[static_cast<size_t>(D) * static_cast<size_t>(cps[a])];
              for (int c = 0; c < D; ++c) {
                if (values) uu[c] += R[a] * ua[c];
                for (int e = 0; e < D; ++e) g[c][e] += dR[a][e] * ua[c];
              }
            }
          };
          f->detJ = nurbs_grad_tensor<D, P>(pd.p, B, cw, R, dR, x);
          contract(true);
          f->x = x[0];
          f->y = x[1];
          f->ux = uu[0];
          f->uy = uu[1];
          if constexpr (D == 2) {
            double Pk[2][2], P33, sg[2][2], s33;
            material_response<false>(mat_, g, Pk, P33, nullptr);
            cauchy_stress(mat_, g, Pk, P33, sg, s33);
            f->sxx = sg[0][0];
            f->syy = sg[1][1];
            f->sxy = 0.5 * (sg[0][1] + sg[1][0]);
            f->szz = mat_.model != Material::kLinear ? s33 : plane_strain_ ? nu_ * (f->sxx + f->syy) : 0.0;
          } else {
            f->z = x[2];
            f->uz = uu[2];
            // degenerate: |det J| far below the element's scale, (size of its control points'
            // box)^3 over the product of its parametric lengths
            double lo[3] = {x[0], x[1], x[2]}, hi[3] = {x[0], x[1], x[2]}, h = 1;
            for (int a = 0; a < ne; ++a)
              for (int c = 0; c < 3; ++c) {
                lo[c] = std::min(lo[c], pd.cp(cps[a], c));
                hi[c] = std::max(hi[c], pd.cp(cps[a], c));
              }
            const double L = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
            for (int d = 0; d < 3; ++d) h *= pd.U[d](s[d] + 1) - pd.U[d](s[d]);
            bool finite = true;
            for (int c = 0; c < 3; ++c)
              for (int d = 0; d < 3; ++d) finite = finite && std::isfinite(g[c][d]);
            if (!finite || !(std::abs(f->detJ) > 1e-9 * L * L * L / h)) {
              double tt[3];
              for (int d = 0; d < 3; ++d) {
                const double mid = 0.5 * (pd.U[d](s[d]) + pd.U[d](s[d] + 1));
                tt[d] = t[d][ii[d]] + 1e-2 * (mid - t[d][ii[d]]);
              }
              nurbs_grad<P>(pd, s, tt, R, dR, x);
              contract(false);
            }
            double Pk[3][3], P33, sg[3][3], s33;
            material_response<false>(mat_, g, Pk, P33, nullptr);
            cauchy_stress(mat_, g, Pk, P33, sg, s33);
            f->sxx = sg[0][0];
            f->syy = sg[1][1];
            f->szz = sg[2][2];
            f->syz = 0.5 * (sg[1][2] + sg[2][1]);
            f->sxz = 0.5 * (sg[0][2] + sg[2][0]);
            f->sxy = 0.5 * (sg[0][1] + sg[1][0]);
          }
        }
  });
}

}  // namespace iga
