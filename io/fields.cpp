#include "io/fields.hpp"

#include <cmath>

#include "kernels/material.hpp"
#include "solver/system.hpp"

namespace iga {

double FieldPoint::von_mises() const {
  return std::sqrt(0.5 * ((sxx - syy) * (sxx - syy) + (syy - szz) * (syy - szz) + (szz - sxx) * (szz - sxx)) +
                   3.0 * sxy * sxy);
}

BodyField::BodyField(const Problem& P, int body, const std::vector<double>& u, int patch)
    : patch_(&P.bodies[body].patches[patch]),
      pd_(host_patch_data(P.bodies[body].patches[patch])),
      mat_(body_material(P, body, 1.0)),
      plane_strain_(P.analysis == Analysis::PlaneStrain),
      nu_(P.bodies[body].nu),
      u_(P.bodies[body].patch_values(patch, u)) {}

FieldPoint BodyField::eval(double u, double v, int s0, int s1) const {
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

}  // namespace iga
