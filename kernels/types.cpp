#include "kernels/types.hpp"

#include <cmath>

namespace iga {

GaussRule gauss_rule(int n) {
  if (n < 1 || n > kMaxGauss)
    throw std::invalid_argument("Gauss rule with " + std::to_string(n) + " points (1.." + std::to_string(kMaxGauss) + ")");
  GaussRule g;
  g.n = n;
  // Newton on the Legendre polynomial P_n from Chebyshev-like starting values.
  for (int i = 0; i < n; ++i) {
    double x = std::cos(M_PI * (i + 0.75) / (n + 0.5)), dp = 1;
    for (int it = 0; it < 100; ++it) {
      double p0 = 1, p1 = x;
      for (int k = 2; k <= n; ++k) {
        const double pk = ((2 * k - 1) * x * p1 - (k - 1) * p0) / k;
        p0 = p1; p1 = pk;
      }
      dp = n * (x * p1 - p0) / (x * x - 1);
      const double dx = p1 / dp;
      x -= dx;
      if (std::abs(dx) < 1e-16) break;
    }
    g.x[i] = -x;
    g.w[i] = 2.0 / ((1 - x * x) * dp * dp);
  }
  return g;
}

Material Material::plane(double E, double nu, bool plane_strain, double t) {
  Material m;
  if (plane_strain) {
    const double lam = E * nu / ((1 + nu) * (1 - 2 * nu)), mu = E / (2 * (1 + nu));
    m.D[0][0] = m.D[1][1] = (lam + 2 * mu) * t;
    m.D[0][1] = m.D[1][0] = lam * t;
    m.D[2][2] = mu * t;
  } else {
    const double c = E / (1 - nu * nu);
    m.D[0][0] = m.D[1][1] = c * t;
    m.D[0][1] = m.D[1][0] = c * nu * t;
    m.D[2][2] = c * (1 - nu) / 2 * t;
  }
  return m;
}

Material Material::finite(int model, double E, double nu, double t) {
  Material m = plane(E, nu, true, t);
  m.model = model;
  m.lambda = E * nu / ((1 + nu) * (1 - 2 * nu)) * t;
  m.mu = E / (2 * (1 + nu)) * t;
  return m;
}

Material Material::solid(int model, double E, double nu) {
  Material m;
  m.model = model;
  m.lambda = E * nu / ((1 + nu) * (1 - 2 * nu));
  m.mu = E / (2 * (1 + nu));
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) m.D[i][j] = m.lambda;
    m.D[i][i] = m.lambda + 2 * m.mu;
    m.D[3 + i][3 + i] = m.mu;
  }
  return m;
}

}  // namespace iga
