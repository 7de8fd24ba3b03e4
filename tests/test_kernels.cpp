// The Kokkos element-stiffness kernel against a plain host reference (1e-12), the assembled
// Tpetra matrix against the sum of reference element matrices, and kernel invariants.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "kernels/elasticity.hpp"
#include "solver/system.hpp"
#include "support.hpp"

using namespace iga;
using iga::test::distorted_patch;
using iga::test::patch_yaml;

namespace {

// Host reference: Ke = sum_q B^T D B |J| w with B (3 x 2nen) formed explicitly; the rational
// basis and the Jacobian inverse are computed here from the 1-D B-spline values.
std::vector<double> reference_ke(const Patch& P, const Material& m, int s0, int s1) {
  const int p0 = P.degree[0], p1 = P.degree[1], nen = (p0 + 1) * (p1 + 1);
  std::vector<double> K(4 * nen * nen, 0.0);
  const GaussRule g0 = gauss_rule(p0 + 1), g1 = gauss_rule(p1 + 1);
  const double ua = P.knots[0][s0], ub = P.knots[0][s0 + 1], va = P.knots[1][s1], vb = P.knots[1][s1 + 1];
  for (int qj = 0; qj < g1.n; ++qj)
    for (int qi = 0; qi < g0.n; ++qi) {
      const double u = ua + (ub - ua) * (g0.x[qi] + 1) / 2, v = va + (vb - va) * (g1.x[qj] + 1) / 2;
      double N[3][kMaxBasis1D], M[3][kMaxBasis1D];
      bspline_ders(s0, u, p0, P.knots[0].data(), 1, N);
      bspline_ders(s1, v, p1, P.knots[1].data(), 1, M);
      std::vector<double> Nw(nen), Nu(nen), Nv(nen), X(nen), Y(nen);
      double W = 0, Wu = 0, Wv = 0;
      for (int j = 0; j <= p1; ++j)
        for (int i = 0; i <= p0; ++i) {
          const auto& c = P.cp[P.index(s0 - p0 + i, s1 - p1 + j)];
          const int a = i + j * (p0 + 1);
          Nw[a] = N[0][i] * M[0][j] * c.w; Nu[a] = N[1][i] * M[0][j] * c.w; Nv[a] = N[0][i] * M[1][j] * c.w;
          X[a] = c.x[0]; Y[a] = c.x[1];
          W += Nw[a]; Wu += Nu[a]; Wv += Nv[a];
        }
      std::vector<double> Ru(nen), Rv(nen);
      double J[2][2] = {};
      for (int a = 0; a < nen; ++a) {
        Ru[a] = Nu[a] / W - Nw[a] * Wu / (W * W);
        Rv[a] = Nv[a] / W - Nw[a] * Wv / (W * W);
        J[0][0] += Ru[a] * X[a]; J[0][1] += Rv[a] * X[a]; J[1][0] += Ru[a] * Y[a]; J[1][1] += Rv[a] * Y[a];
      }
      const double det = J[0][0] * J[1][1] - J[0][1] * J[1][0];
      std::vector<double> B(3 * 2 * nen, 0.0);
      for (int a = 0; a < nen; ++a) {
        // solve J^T [Rx Ry]^T = [Ru Rv]^T
        const double Rx = (J[1][1] * Ru[a] - J[1][0] * Rv[a]) / det;
        const double Ry = (-J[0][1] * Ru[a] + J[0][0] * Rv[a]) / det;
        B[0 * 2 * nen + 2 * a] = Rx;
        B[1 * 2 * nen + 2 * a + 1] = Ry;
        B[2 * 2 * nen + 2 * a] = Ry;
        B[2 * 2 * nen + 2 * a + 1] = Rx;
      }
      const double wq = std::abs(det) * g0.w[qi] * g1.w[qj] * (ub - ua) * (vb - va) / 4;
      for (int r = 0; r < 2 * nen; ++r)
        for (int c = 0; c < 2 * nen; ++c) {
          double s = 0;
          for (int k = 0; k < 3; ++k)
            for (int l = 0; l < 3; ++l) s += B[k * 2 * nen + r] * m.D[k][l] * B[l * 2 * nen + c];
          K[r * 2 * nen + c] += wq * s;
        }
    }
  return K;
}

}  // namespace

class KernelDegree : public ::testing::TestWithParam<int> {};

TEST_P(KernelDegree, ElementStiffnessMatchesHostReference) {
  const int p = GetParam();
  const Patch P = distorted_patch(p);
  const Problem prob = parse_problem(patch_yaml(P), "kernel.yaml", {"solver.quadrature=gauss"});   // the host reference is Gauss
  System sys(prob, Tpetra::getDefaultComm());
  const PatchBlock& bd = sys.blocks()[0];
  const int ne = P.num_elements(), nd = 2 * (p + 1) * (p + 1);
  Kokkos::View<double**, MemSpace> out("Ke", ne, nd * nd);
  const GaussRule g = gauss_rule(p + 1);
  const Material mat = bd.mat;
  dispatch_degree(p, [&](auto PP) {
    constexpr int Q = decltype(PP)::value;
    const PatchData pd = bd.pd;
    Kokkos::parallel_for("test", Kokkos::RangePolicy<ExecSpace>(0, ne), KOKKOS_LAMBDA(const int e) {
      double Ke[2 * (Q + 1) * (Q + 1)][2 * (Q + 1) * (Q + 1)];
      element_stiffness<Q>(pd, mat, g, g, e, Ke);
      for (int r = 0; r < 2 * (Q + 1) * (Q + 1); ++r)
        for (int c = 0; c < 2 * (Q + 1) * (Q + 1); ++c) out(e, r * 2 * (Q + 1) * (Q + 1) + c) = Ke[r][c];
    });
  });
  auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), out);
  const auto sp0 = P.element_spans(0), sp1 = P.element_spans(1);
  for (int e = 0; e < ne; ++e) {
    const auto ref = reference_ke(P, mat, sp0[e % sp0.size()], sp1[e / sp0.size()]);
    double scale = 0;
    for (double v : ref) scale = std::max(scale, std::abs(v));
    for (int k = 0; k < nd * nd; ++k) ASSERT_NEAR(h(e, k), ref[k], 1e-12 * scale) << "element " << e << " entry " << k;
    // rigid-body modes are in the kernel of Ke
    for (int mode = 0; mode < 3; ++mode) {
      double worst = 0;
      for (int r = 0; r < nd; ++r) {
        double s = 0;
        for (int c = 0; c < nd; ++c) {
          const int a = c / 2;
          const auto& cp = P.cp[P.index(sp0[e % sp0.size()] - p + a % (p + 1), sp1[e / sp0.size()] - p + a / (p + 1))];
          const double z = mode == 0 ? (c % 2 == 0) : mode == 1 ? (c % 2 == 1) : (c % 2 == 0 ? -cp.x[1] : cp.x[0]);
          s += h(e, r * nd + c) * z;
        }
        worst = std::max(worst, std::abs(s));
      }
      EXPECT_LT(worst, 1e-10 * scale) << "mode " << mode;
    }
  }
}

TEST_P(KernelDegree, AssembledTpetraMatrixMatchesSumOfReferenceElements) {
  const int p = GetParam();
  // seed 12: with seed 11 the random net folds at p = 5 (x < 0 within 1e-5 of the west side,
  // det J < 0 there), which the loader's geometry check now refuses
  const Patch P = distorted_patch(p, 12);
  const Problem prob = parse_problem(patch_yaml(P), "kernel.yaml", {"solver.quadrature=gauss"});   // the host reference is Gauss
  System sys(prob, Tpetra::getDefaultComm());
  RCP<Matrix> K = sys.assemble_stiffness();
  // y = K v with v_g = sin(g): compare with the reference sum on every owned row
  Vector v(sys.owned_map()), y(sys.owned_map());
  {
    auto hv = v.getLocalViewHost(Tpetra::Access::OverwriteAll);
    for (size_t l = 0; l < v.getLocalLength(); ++l) hv(l, 0) = std::sin(1.0 + sys.owned_map()->getGlobalElement(l));
  }
  K->apply(v, y);
  const int ndof = 2 * static_cast<int>(P.cp.size());
  std::vector<double> ref(ndof, 0.0);
  const auto sp0 = P.element_spans(0), sp1 = P.element_spans(1);
  const int nen = (p + 1) * (p + 1);
  double scale = 0;
  for (int s1 : sp1)
    for (int s0 : sp0) {
      const auto Ke = reference_ke(P, sys.material(0), s0, s1);
      std::vector<int> dofs;
      for (int a = 0; a < nen; ++a) {
        const int g = P.index(s0 - p + a % (p + 1), s1 - p + a / (p + 1));
        dofs.push_back(2 * g);
        dofs.push_back(2 * g + 1);
      }
      for (int r = 0; r < 2 * nen; ++r)
        for (int c = 0; c < 2 * nen; ++c) {
          ref[dofs[r]] += Ke[r * 2 * nen + c] * std::sin(1.0 + dofs[c]);
          scale = std::max(scale, std::abs(Ke[r * 2 * nen + c]));
        }
    }
  auto hy = y.getLocalViewHost(Tpetra::Access::ReadOnly);
  for (size_t l = 0; l < y.getLocalLength(); ++l)
    EXPECT_NEAR(hy(l, 0), ref[sys.owned_map()->getGlobalElement(l)], 1e-12 * scale * 30);
}

INSTANTIATE_TEST_SUITE_P(Degrees, KernelDegree, ::testing::Range(1, 6));

#include "kernels/basis.hpp"

// The stored basis: partition of unity, zero-sum gradients, and the quadrature weights add up
// to the patch area (the annulus sector is exact: 3 pi / 4 for radii 1 and 2).
TEST(BasisKernel, PartitionOfUnityAndExactArea) {
  for (int p = 2; p <= 4; ++p) {
    const std::string yaml =
        "bodies:\n  - name: b\n    material: {youngs_modulus: 1.0, poisson_ratio: 0.3}\n"
        "    geometry: {quarter_annulus: {center: [0, 0], inner_radius: 1, outer_radius: 2}}\n"
        "    refine: {degree_elevate: [" + std::to_string(p - 2) + ", " + std::to_string(p - 1) + "], subdivide: [5, 3]}\n"
        "    boundary: {west: {displacement: {x: 0, y: 0}}}\n";
    const Problem prob = parse_problem(yaml, "basis.yaml");
    System sys(prob, Tpetra::getDefaultComm());
    const PatchBlock& bd = sys.blocks()[0];
    double area = 0, worst_sum = 0, worst_grad = 0;
    dispatch_degree(p, [&](auto PP) {
      EvaluateBasis<decltype(PP)::value> k;
      k.pd = bd.pd; k.g[0] = gauss_rule(p + 1); k.g[1] = gauss_rule(p + 1); k.e_begin = 0;
      const int ne = prob.bodies[0].patches[0].num_elements();
      k.run(ne);
      auto R = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), k.R);
      auto dR = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), k.dR);
      auto J = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), k.JxW);
      for (size_t e = 0; e < R.extent(0); ++e)
        for (size_t q = 0; q < R.extent(1); ++q) {
          double s = 0, gx = 0, gy = 0;
          for (size_t a = 0; a < R.extent(2); ++a) { s += R(e, q, a); gx += dR(e, q, a, 0); gy += dR(e, q, a, 1); }
          worst_sum = std::max(worst_sum, std::abs(s - 1));
          worst_grad = std::max({worst_grad, std::abs(gx), std::abs(gy)});
          area += J(e, q);
        }
    });
    EXPECT_LT(worst_sum, 1e-14);
    EXPECT_LT(worst_grad, 1e-11);
    // the Jacobian of the rational map is not a polynomial: (p+1)-point Gauss integrates it
    // to ~3e-9 on 5 x 3 elements at p = 2 (better at higher p), not to round-off
    EXPECT_NEAR(area, 0.75 * M_PI, 1e-8) << "p = " << p;
  }
}
