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

FieldPoint BodyField::eval(const double* t, const int* s) const {
  if (dim_ == 3) return eval3(t, s);
  return eval(t[0], t[1], s ? s[0] : -1, s ? s[1] : -1);
}

FieldPoint BodyField::eval(double u, double v, int s0, int s1) const {
  if (dim_ != 2) throw std::logic_error("BodyField::eval(u, v): a 3-D patch needs three parameters");
  if (s0 < 0) s0 = find_span(pd_.n[0], pd_.p[0], u, pd_.U[0].data());
  if (s1 < 0) s1 = find_span(pd_.n[1], pd_.p[1], v, pd_.U[1].data());
  FieldPoint f;
  double g[2][2] = {{0, 0}, {0, 0}};
  dispatch_degree(std::max(pd_.p[0], pd_.p[1]), [&](auto PP) {
    constexpr int P = decltype(PP)::value;
    double R[(P + 1) * (P + 1)], dR[(P + 1) * (P + 1)][2], x[2];
    f.detJ = nurbs_grad<P>(pd_, s0, s1, u, v, R, dR, x);
    f.x = x[0];
    f.y = x[1];
    for (int j = 0; j <= pd_.p[1]; ++j)
      for (int i = 0; i <= pd_.p[0]; ++i) {
        const int a = i + j * (pd_.p[0] + 1);
        const int cp = s0 - pd_.p[0] + i + (s1 - pd_.p[1] + j) * pd_.n[0];
        f.ux += R[a] * u_[2 * cp];
        f.uy += R[a] * u_[2 * cp + 1];
        for (int c = 0; c < 2; ++c)
          for (int d = 0; d < 2; ++d) g[c][d] += dR[a][d] * u_[2 * cp + c];
      }
  });
  // the same material law as the kernels; Cauchy stress sigma = P F^T / J
  double Pk[2][2], P33, s[2][2], s33;
  material_response<false>(mat_, g, Pk, P33, nullptr);
  cauchy_stress(mat_, g, Pk, P33, s, s33);
  f.sxx = s[0][0];
  f.syy = s[1][1];
  f.sxy = 0.5 * (s[0][1] + s[1][0]);
  f.szz = mat_.model != Material::kLinear ? s33 : plane_strain_ ? nu_ * (f.sxx + f.syy) : 0.0;
  return f;
}

// 3-D: x, u and H = Grad u from the trivariate NURBS basis (nurbs_grad on the kernels' patch
// data), then the kernels' law on the full tensors and sigma = P F^T / J (small strain: P).
// Where the map is degenerate (det J = 0 on a face collapsed onto an edge or a point, as the
// pole of a sphere octant) Grad u does not exist: the basis functions' physical gradients are
// unbounded there, and a discrete solution whose control points on the collapsed face differ
// (independent dofs) has a stress growing like 1/distance in a thin layer (measured on a thick
// sphere octant, p = 2, 6 x 6 x 4: sound at 6e-3 of an element from the pole, -47 at 6e-5,
// -6500 at 1e-6, against an exact 7.1; NaN on the pole itself). H is taken at the point moved
// 1 % of the way towards the element's centre, outside that layer (there: 6.9, 6.5, -9.6
// against 7.1, 7.1, -10); x, u and detJ stay those of the point itself. The output's other
// evaluation points lie 1 / p or 1 / s (s <= 64 samples) of an element or more from the face.
FieldPoint BodyField::eval3(const double* t, const int* sp) const {
  int s[3];
  for (int d = 0; d < 3; ++d)
    s[d] = sp && sp[d] >= 0 ? sp[d] : find_span(pd3_.n[d], pd3_.p[d], t[d], pd3_.U[d].data());
  FieldPoint f;
  double g[3][3] = {};
  dispatch_degree(std::max({pd3_.p[0], pd3_.p[1], pd3_.p[2]}), [&](auto PP) {
    constexpr int P = decltype(PP)::value;
    constexpr int nen = kNen<3, P>;
    double R[nen], dR[nen][3], x[3];
    int cps[nen];
    pd3_.local_cps(s, cps);
    // H (and optionally x, u) at the parameters tt; returns det J
    auto at = [&](const double* tt, bool values) {
      const double detJ = nurbs_grad<P>(pd3_, s, tt, R, dR, x);
      double uu[3] = {0, 0, 0};
      for (int c = 0; c < 3; ++c)
        for (int d = 0; d < 3; ++d) g[c][d] = 0;
      for (int a = 0; a < pd3_.nen(); ++a) {
        const double* ua = &u_[3 * static_cast<size_t>(cps[a])];
        for (int c = 0; c < 3; ++c) {
          uu[c] += R[a] * ua[c];
          for (int d = 0; d < 3; ++d) g[c][d] += dR[a][d] * ua[c];
        }
      }
      if (values) {
        f.x = x[0];
        f.y = x[1];
        f.z = x[2];
        f.ux = uu[0];
        f.uy = uu[1];
        f.uz = uu[2];
      }
      return detJ;
    };
    f.detJ = at(t, true);
    // degenerate: |det J| far below the element's scale, (size of its control points' box)^3
    // over the product of its parametric lengths
    double lo[3] = {x[0], x[1], x[2]}, hi[3] = {x[0], x[1], x[2]}, h = 1;
    for (int a = 0; a < pd3_.nen(); ++a)
      for (int c = 0; c < 3; ++c) {
        lo[c] = std::min(lo[c], pd3_.cp(cps[a], c));
        hi[c] = std::max(hi[c], pd3_.cp(cps[a], c));
      }
    const double L = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
    for (int d = 0; d < 3; ++d) h *= pd3_.U[d](s[d] + 1) - pd3_.U[d](s[d]);
    bool finite = true;
    for (int c = 0; c < 3; ++c)
      for (int d = 0; d < 3; ++d) finite = finite && std::isfinite(g[c][d]);
    if (!finite || !(std::abs(f.detJ) > 1e-9 * L * L * L / h)) {
      double tt[3];
      for (int d = 0; d < 3; ++d) {
        const double mid = 0.5 * (pd3_.U[d](s[d]) + pd3_.U[d](s[d] + 1));
        tt[d] = t[d] + 1e-2 * (mid - t[d]);
      }
      at(tt, false);
    }
  });
  double Pk[3][3], P33, sg[3][3], s33;
  material_response<false>(mat_, g, Pk, P33, nullptr);
  cauchy_stress(mat_, g, Pk, P33, sg, s33);
  f.sxx = sg[0][0];
  f.syy = sg[1][1];
  f.szz = sg[2][2];
  f.syz = 0.5 * (sg[1][2] + sg[2][1]);
  f.sxz = 0.5 * (sg[0][2] + sg[2][0]);
  f.sxy = 0.5 * (sg[0][1] + sg[1][0]);
  return f;
}

}  // namespace iga
