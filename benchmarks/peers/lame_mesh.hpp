#pragma once
// The Lame cylinder of examples/lame_cylinder.yaml the deal.II way, shared by the peer
// programs (dealii_assembly.cpp, dealii_lame.cpp): a subdivided (r, theta) rectangle
// [a, b] x [0, pi/2] of NR x NT cells mapped onto the quarter annulus, every object (cells,
// faces) on a PolarManifold about the centre, so MappingQ's support points (boundary and
// interior) interpolate the exact polar map (exact for this domain). NT = 2 NR or 2 NR +- 1,
// the lame_cylinder.yaml aspect ([16, 8]), chosen so that the dof count 2 (p NR + 1)(p NT + 1)
// is nearest the target. Boundary ids (colorised): 0 r = a (the inner surface, pressure),
// 1 r = b, 2 theta = 0 (the cut along y = 0), 3 theta = pi / 2 (the cut along x = 0).
#include <deal.II/base/numbers.h>
#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/grid/manifold_lib.h>
#include <deal.II/grid/tria.h>

#include <cmath>
#include <vector>

namespace lame {

constexpr double inner_radius = 1.0;
constexpr double outer_radius = 2.0;
constexpr double youngs_modulus = 2.0e5;
constexpr double poisson_ratio = 0.3;

// vector dofs of FESystem(FE_Q(p), 2) on nt x nr cells
inline unsigned long long n_dofs_of(unsigned p, unsigned nt, unsigned nr) {
  return 2ULL * (1ULL * p * nt + 1) * (1ULL * p * nr + 1);
}

// NT ~ 2 NR, the dof count nearest the target
inline void choose_subdivision(unsigned p, double target, unsigned& nt, unsigned& nr) {
  double best = 1e300;
  for (unsigned r = 1; r < 100000; ++r) {
    if (n_dofs_of(p, 2 * r - 1, r) > 4 * target) break;
    for (unsigned t : {2 * r - 1, 2 * r, 2 * r + 1}) {
      if (t < 1) continue;
      const double d = std::abs(static_cast<double>(n_dofs_of(p, t, r)) - target);
      if (d < best) { best = d; nt = t; nr = r; }
    }
  }
}

inline void make_mesh(dealii::Triangulation<2>& tria, unsigned nt, unsigned nr) {
  using dealii::Point;
  // (r, theta) rectangle: x = r, y = theta; repetitions {nr, nt}
  dealii::GridGenerator::subdivided_hyper_rectangle(tria, {nr, nt}, Point<2>(inner_radius, 0.0),
                                                    Point<2>(outer_radius, 0.5 * dealii::numbers::PI), true);
  dealii::GridTools::transform(
      [](const Point<2>& q) { return Point<2>(q[0] * std::cos(q[1]), q[0] * std::sin(q[1])); }, tria);
  tria.set_all_manifold_ids(0);
  tria.set_manifold(0, dealii::PolarManifold<2>(Point<2>(0.0, 0.0)));
}

// The local elasticity matrix the tutorial way (step-8), FEValuesExtractors::Vector:
// lambda div phi_i div phi_j + 2 mu eps(phi_i) : eps(phi_j), q outer, j >= i, then mirrored;
// eps and div are scratch of n_dofs_per_cell entries.
inline void extractor_local_matrix(const dealii::FEValues<2>& fv, double lambda, double mu,
                                   std::vector<dealii::SymmetricTensor<2, 2>>& eps, std::vector<double>& div,
                                   dealii::FullMatrix<double>& K) {
  const dealii::FEValuesExtractors::Vector disp(0);
  const unsigned dpc = K.m();
  K = 0;
  for (unsigned q = 0; q < fv.n_quadrature_points; ++q) {
    const double w = fv.JxW(q);
    for (unsigned i = 0; i < dpc; ++i) {
      eps[i] = fv[disp].symmetric_gradient(i, q);
      div[i] = fv[disp].divergence(i, q);
    }
    for (unsigned i = 0; i < dpc; ++i) {
      const dealii::SymmetricTensor<2, 2> e = 2 * mu * w * eps[i];
      const double d = lambda * w * div[i];
      for (unsigned j = i; j < dpc; ++j) K(i, j) += d * div[j] + e * eps[j];
    }
  }
  for (unsigned i = 0; i < dpc; ++i)
    for (unsigned j = i + 1; j < dpc; ++j) K(j, i) = K(i, j);
}

}  // namespace lame
