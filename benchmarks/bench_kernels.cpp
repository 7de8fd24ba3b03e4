// Kernel microbenchmarks (Google Benchmark). Each reports a rate next to its time, from the
// flop and byte counts stated here and in the kernels' headers:
//   BM_Basis<P>             points/s, GB/s            kernels/basis.hpp
//   BM_ElementStiffness<P>/spline:r  quadrature points/s, elements/s, GFLOP/s (r = 0 Gauss, 1 the spline rule)
//   BM_FiniteStrain<P>/m   the same for the finite-strain residual + tangent at a deformed state
//                           (m = 1 Saint Venant-Kirchhoff, 2 neo-Hookean; element_internal)
//   BM_Scatter<P>/sorted:s  nonzeros/s (element matrices formed and summed into the Tpetra local matrix;
//                           s = 1: rows searched by bisection, 0: linearly)
//   BM_Formation<P>/rows:r  dofs/s, quadrature points/s of the whole tangent (stage 2.2, refilled in place)
//                           on a curved rational patch (quarter annulus, ~ 1.4e4 dofs, spline rule):
//                           r = 0 the element loop, 1 row-wise sum factorisation (solver.formation)
//   BM_Formation3D<P>/m/sf  the 3-D element loop (AssembleInternalT<3, P>: internal force and tangent,
//                           element matrices in the batched work view, summed into a KokkosSparse
//                           matrix) on a box of n^3 elements, Gauss (P + 1)^3 points, at a smooth
//                           displacement; m = 0 linear, 2 neo-Hookean; sf = 1: the tangent by
//                           element-wise sum factorisation (kernels/elasticity_sf3.hpp). dofs/s,
//                           elements/s and GFLOP/s (the element loop's flop count, kernels/elasticity.hpp)
//   BM_ContactProjection/M  projections/s on a degree-2 master curve of M elements
//   BM_SurfaceProjection/n  3-D contact geometry (kernels/contact_surface.hpp): n points around the
//                           face of a sphere octant of 32 x 32 degree-2 elements, each its closest
//                           point through the bin search (a Kokkos parallel_for); projections/s,
//                           and the search grid's build time per call (search:1) or not (0)
//   BM_PolygonClip/pairs/master_points/rule  3-D mortar segmentation (kernels/contact_clip.hpp):
//                           a slave parameter rectangle against a master square of 4 points or
//                           with its straight edges sampled (12 points), rotated and shifted at
//                           random (every pair overlaps), clipped in a Kokkos parallel_for; rule
//                           n > 0: and the fan rule of n^2 points per triangle integrating 1; clips/s
//   BM_SpMV / BM_StreamCopy GB/s of the assembled elasticity matrix, and the copy limit
// Rates are per wall-clock second (UseRealTime), so that threaded runs count every thread.
// Run: build/bin/bench_kernels [--benchmark_filter=...]; with the OpenMP Trilinos,
//      OMP_NUM_THREADS=1 and 2 build-omp/bin/bench_kernels (the context line names the space).
#include <benchmark/benchmark.h>
#include <Tpetra_Core.hpp>

#include <random>
#include <sstream>

#include "kernels/basis.hpp"
#include "kernels/contact_clip.hpp"
#include "kernels/elasticity.hpp"
#include "solver/contact.hpp"
#include "tests/surfaces3d.hpp"
#include "solver/system.hpp"
#include "tests/patches3d.hpp"

using namespace iga;

namespace {

// A square block of n x n elements of degree P (distorted geometry is irrelevant for cost).
Problem block_problem(int P, int n, const std::string& quadrature = "gauss") {
  std::ostringstream os;
  os << "solver: {quadrature: " << quadrature << "}\n";
  os << "bodies:\n  - name: b\n    material: {youngs_modulus: 1.0, poisson_ratio: 0.3}\n"
     << "    geometry: {rectangle: {origin: [0, 0], size: [1, 1]}}\n"
     << "    refine: {degree_elevate: " << P - 1 << ", subdivide: [" << n << ", " << n << "]}\n"
     << "    boundary: {south: {displacement: {x: 0, y: 0}}}\n";
  return parse_problem(os.str(), "bench.yaml");
}

int elements_for(int P) { return P <= 2 ? 128 : 64; }

template <int P>
void BM_Basis(benchmark::State& st) {
  const Problem prob = block_problem(P, elements_for(P));
  System sys(prob, Tpetra::getDefaultComm());
  EvaluateBasis<P> k;
  k.pd = sys.blocks()[0].pd; k.g[0] = gauss_rule(P + 1); k.g[1] = gauss_rule(P + 1);
  const int ne = prob.bodies[0].patches[0].num_elements();
  k.run(ne);
  for (auto _ : st) { k.run(ne); Kokkos::fence(); }
  const double pts = static_cast<double>(ne) * (P + 1) * (P + 1) * st.iterations();
  st.counters["points/s"] = benchmark::Counter(pts, benchmark::Counter::kIsRate);
  st.counters["GB/s"] = benchmark::Counter(pts * EvaluateBasis<P>::bytes_per_point() * 1e-9, benchmark::Counter::kIsRate);
}

// range(0): 0 Gauss, p + 1 points per element and direction; 1 the spline rule
// (solver.quadrature: spline), about (p + 2) / 2. elements/s compares the two.
template <int P>
void BM_ElementStiffness(benchmark::State& st) {
  const Problem prob = block_problem(P, elements_for(P), st.range(0) ? "spline" : "gauss");
  System sys(prob, Tpetra::getDefaultComm());
  const PatchData pd = sys.blocks()[0].pd;
  const Material mat = sys.material(0);
  const GaussRule g = gauss_rule(P + 1);
  const int ne = prob.bodies[0].patches[0].num_elements();
  Kokkos::View<double*, MemSpace> trace("trace", ne);
  for (auto _ : st) {
    Kokkos::parallel_for("bench::ElementStiffness", Kokkos::RangePolicy<ExecSpace>(0, ne), KOKKOS_LAMBDA(const int e) {
      double Ke[2 * (P + 1) * (P + 1)][2 * (P + 1) * (P + 1)];
      element_stiffness<P>(pd, mat, g, g, e, Ke);
      double t = 0;
      for (int r = 0; r < 2 * (P + 1) * (P + 1); ++r) t += Ke[r][r];
      trace(e) = t;
    });
    Kokkos::fence();
  }
  constexpr double nen = (P + 1) * (P + 1);
  const double qp = static_cast<double>(sys.blocks()[0].quadrature_points) * st.iterations();
  // basis + Jacobian ~ 25 nen + 9 P + 30 (kernels/elasticity.hpp), stiffness 13 flops per 2x2
  // block for nen (nen + 1) / 2 blocks
  const double flops = 25 * nen + 9 * P + 30 + 6.5 * nen * (nen + 1);
  st.counters["qp/s"] = benchmark::Counter(qp, benchmark::Counter::kIsRate);
  st.counters["elements/s"] = benchmark::Counter(static_cast<double>(ne) * st.iterations(), benchmark::Counter::kIsRate);
  st.counters["GFLOP/s"] = benchmark::Counter(qp * flops * 1e-9, benchmark::Counter::kIsRate);
}

template <int P>
void BM_FiniteStrain(benchmark::State& st) {
  const Problem prob = block_problem(P, elements_for(P));
  System sys(prob, Tpetra::getDefaultComm());
  const PatchData pd = sys.blocks()[0].pd;
  const Material mat = Material::finite(static_cast<int>(st.range(0)), 1.0, 0.3, 1.0);
  const GaussRule g = gauss_rule(P + 1);
  const int ne = prob.bodies[0].patches[0].num_elements();
  // a smooth displacement of the control points: u = 0.1 (sin y, x y)
  const int ncp = pd.n[0] * pd.n[1];
  Kokkos::View<double*, MemSpace> u("u", 2 * ncp);
  Kokkos::parallel_for("bench::FiniteU", Kokkos::RangePolicy<ExecSpace>(0, ncp), KOKKOS_LAMBDA(const int a) {
    u(2 * a) = 0.1 * Kokkos::Experimental::sin(pd.cp(a, 1));
    u(2 * a + 1) = 0.1 * pd.cp(a, 0) * pd.cp(a, 1);
  });
  Kokkos::View<double*, MemSpace> trace("trace", ne);
  for (auto _ : st) {
    Kokkos::parallel_for("bench::FiniteStrain", Kokkos::RangePolicy<ExecSpace>(0, ne), KOKKOS_LAMBDA(const int e) {
      constexpr int nd = 2 * (P + 1) * (P + 1);
      double Ke[nd][nd], fe[nd], ue[nd / 2][2];
      for (int a = 0; a < nd / 2; ++a) {
        const int cp = element_cp(pd, e, a);
        ue[a][0] = u(2 * cp);
        ue[a][1] = u(2 * cp + 1);
      }
      element_internal<P, true, true>(pd, mat, g, g, e, ue, fe, Ke);
      double t = 0;
      for (int r = 0; r < nd; ++r) t += Ke[r][r] + fe[r];
      trace(e) = t;
    });
    Kokkos::fence();
  }
  constexpr double nen = (P + 1) * (P + 1);
  const double qp = static_cast<double>(ne) * (P + 1) * (P + 1) * st.iterations();
  // basis ~ 25 nen + 9 P + 30, gradient 4 nen, material ~ 200, force 4 nen, tangent
  // 32 nen + 8 nen (nen + 1) (kernels/elasticity.hpp)
  const double flops = 25 * nen + 9 * P + 30 + 4 * nen + 200 + 4 * nen + 32 * nen + 8 * nen * (nen + 1);
  st.counters["qp/s"] = benchmark::Counter(qp, benchmark::Counter::kIsRate);
  st.counters["GFLOP/s"] = benchmark::Counter(qp * flops * 1e-9, benchmark::Counter::kIsRate);
}

template <int P>
void BM_Formation(benchmark::State& st) {
  std::ostringstream os;
  const int nv = 56, nu = 2 * nv;   // ~ 2 (nu + P)(nv + P) dofs
  os << "solver: {formation: " << (st.range(0) ? "sum_factorized" : "elements") << "}\n"
     << "bodies:\n  - name: c\n    material: {youngs_modulus: 1.0, poisson_ratio: 0.3}\n"
     << "    geometry: {quarter_annulus: {center: [0, 0], inner_radius: 1.0, outer_radius: 2.0, start_angle: 0}}\n"
     << "    refine: {degree_elevate: [" << P - 2 << ", " << P - 1 << "], subdivide: [" << nu << ", " << nv << "]}\n"
     << "    boundary: {west: {displacement: {x: 0, y: 0}}}\n";
  const Problem prob = parse_problem(os.str(), "bench.yaml");
  System sys(prob, Tpetra::getDefaultComm());
  RCP<Matrix> K;
  sys.assemble_internal(nullptr, nullptr, &K);   // graph, tables, first touch
  for (auto _ : st) {
    sys.assemble_internal(nullptr, nullptr, &K);
    Kokkos::fence();
  }
  st.counters["dofs/s"] = benchmark::Counter(static_cast<double>(sys.num_dofs()) * st.iterations(), benchmark::Counter::kIsRate);
  st.counters["qp/s"] = benchmark::Counter(static_cast<double>(sys.blocks()[0].quadrature_points) * st.iterations(),
                                           benchmark::Counter::kIsRate);
  st.counters["dofs"] = static_cast<double>(sys.num_dofs());
}

template <int P>
void BM_Scatter(benchmark::State& st) {
  const Problem prob = block_problem(P, elements_for(P));
  System sys(prob, Tpetra::getDefaultComm());
  RCP<Matrix> A = sys.assemble_stiffness();
  const PatchBlock& bd = sys.blocks()[0];
  const int ne = prob.bodies[0].patches[0].num_elements();
  auto lcl = A->getLocalMatrixDevice();
  const GaussRule g = gauss_rule(P + 1);
  for (auto _ : st) {
    A->resumeFill();
    A->setAllToScalar(0.0);
    AssembleInternal<P, decltype(lcl)> k{bd.pd, bd.mat, g, g, 0};
    k.scatter.A = lcl;
    k.scatter.sorted_A = st.range(0) == 1;   // one patch, one rank: the rows ascend (System checks it)
    k.tangent = true;
    k.run(ne);
    Kokkos::fence();
    A->fillComplete();
  }
  const double entries = static_cast<double>(ne) * std::pow(2.0 * (P + 1) * (P + 1), 2) * st.iterations();
  st.counters["elem.nonzeros/s"] = benchmark::Counter(entries, benchmark::Counter::kIsRate);
  st.counters["matrix nnz"] = static_cast<double>(A->getGlobalNumEntries());
}

// 3-D: the element loop on a box of n^3 elements of degree P (tests/patches3d.hpp).
template <int P>
void BM_Formation3D(benchmark::State& st) {
  const int n = P == 1 ? 12 : P == 2 ? 8 : P == 3 ? 5 : 3;
  const test3d::Block3 b = test3d::box({P, P, P}, {n, n, n});
  const HostPatchData3 hpd = test3d::patch_data<Kokkos::HostSpace>(b);
  const int ncp = static_cast<int>(b.cp.size()), ne = hpd.num_elements();
  std::vector<double> u(3 * ncp);
  for (int a = 0; a < ncp; ++a)
    for (int c = 0; c < 3; ++c) u[3 * a + c] = 0.05 * std::sin(b.cp[a][(c + 1) % 3] + c);
  test3d::Crs K = test3d::make_matrix(hpd);
  const GaussRule g = gauss_rule(P + 1);
  AssembleInternalT<3, P, test3d::Crs> k{test3d::patch_data<MemSpace>(b), Material::solid(static_cast<int>(st.range(0)), 1.0, 0.3),
                                         {g, g, g}, 0};
  k.scatter.A = K;
  k.scatter.sorted_A = true;
  k.u = test3d::to_view<double, MemSpace>("u", u);
  k.f = Kokkos::View<double*, MemSpace>("f", 3 * ncp);
  k.force = k.tangent = true;
  k.sum_factorized = st.range(1) != 0;
  for (auto _ : st) {
    Kokkos::deep_copy(K.values, 0.0);
    Kokkos::deep_copy(k.f, 0.0);
    k.run(ne);
    Kokkos::fence();
  }
  constexpr double nen = (P + 1) * (P + 1) * (P + 1);
  const double qp = static_cast<double>(ne) * nen * st.iterations();   // (P + 1)^3 Gauss points
  // the element loop's count, whichever way the tangent is formed (so that GFLOP/s compares as
  // time): basis 41 nen + 80, gradient 18 nen, material ~ 900 (neo-Hookean; linear ~ 54), force
  // 18 nen, tangent rows 162 nen + blocks a <= b 27 nen (nen + 1) (kernels/elasticity.hpp)
  const double flops = 41 * nen + 80 + 18 * nen + (st.range(0) == 0 ? 54 : 900) + 18 * nen + 162 * nen + 27 * nen * (nen + 1);
  st.counters["dofs/s"] = benchmark::Counter(3.0 * ncp * st.iterations(), benchmark::Counter::kIsRate);
  st.counters["elements/s"] = benchmark::Counter(static_cast<double>(ne) * st.iterations(), benchmark::Counter::kIsRate);
  st.counters["GFLOP/s"] = benchmark::Counter(qp * flops * 1e-9, benchmark::Counter::kIsRate);
  st.counters["dofs"] = 3.0 * ncp;
}

// Master: the outer arc (radius 2, 0..90 degrees) of a ring of M degree-2 elements. Slave: the
// inner arc of a concentric ring 1e-3 outside it, 1024 degree-2 elements x 4 Gauss points =
// 4096 slave points, every one with its closest point on the master. One iteration is
// ContactPairData::update: import of the curves' displacements, search grid over the master
// element boxes (host), then search + Newton projection of every slave point (kernel).
//   warm (range(1) = 1): the previous projection is kept, as in Newton iterations after the
//        first: one Newton projection per point, no grid candidates tried.
//   cold (range(1) = 0): no previous projection (a load step's first update): every grid
//        candidate whose box is nearer than the best projection so far is projected.
// The time per projection must not grow with M: the search is not slave points x master
// elements. Cost per projection ~ (3 + iterations + 1) curve evaluations of ~ 100 flops.
void BM_ContactProjection(benchmark::State& st) {
  const int M = static_cast<int>(st.range(0));
  const bool warm = st.range(1) != 0;
  std::ostringstream os;
  os << "bodies:\n  - name: ring\n    material: {youngs_modulus: 1.0, poisson_ratio: 0.3}\n"
     << "    geometry: {quarter_annulus: {center: [0, 0], inner_radius: 1.0, outer_radius: 2.0, start_angle: 0}}\n"
     << "    refine: {subdivide: [" << M << ", 1]}\n    boundary: {south: {displacement: {x: 0, y: 0}}}\n"
     << "  - name: shell\n    material: {youngs_modulus: 1.0, poisson_ratio: 0.3}\n"
     << "    geometry: {quarter_annulus: {center: [0, 0], inner_radius: 2.001, outer_radius: 2.5, start_angle: 0}}\n"
     << "    refine: {subdivide: [1024, 1]}\n    boundary: {north: {displacement: {x: 0, y: 0}}}\n"
     << "contact:\n  - {master: {body: ring, side: north}, slave: {body: shell, side: south}, penalty: 1.0, quadrature_points: 4}\n";
  const Problem prob = parse_problem(os.str(), "bench.yaml");
  System sys(prob, Tpetra::getDefaultComm());
  ContactPairData c(sys, 0);
  Vector u(sys.owned_map());
  c.update(u);
  for (auto _ : st) {
    if (!warm) {
      st.PauseTiming();
      Kokkos::deep_copy(c.sp_.melem, -1);
      st.ResumeTiming();
    }
    c.update(u);
  }
  const auto state = c.state();
  int found = 0;
  for (size_t i = 0; i < state.gap.size(); ++i) found += std::abs(state.gap[i] - 1e-3) < 1e-9;
  if (found != c.num_points()) st.SkipWithError("not every slave point found its closest point");
  st.counters["projections/s"] = benchmark::Counter(static_cast<double>(c.num_points()) * st.iterations(),
                                                    benchmark::Counter::kIsRate);
  st.counters["master elements"] = M;
}

void BM_SurfaceProjection(benchmark::State& st) {
  const int n = static_cast<int>(st.range(0));
  const bool rebuild = st.range(1) != 0;
  const double R = 2.0;
  const SurfaceData sd = test3d::surface_of(test3d::sphere_octant(R, 32).face(Side::Back));
  SurfaceSearch g = SurfaceSearch::build(sd);
  Kokkos::View<double* [3], MemSpace> X("X", n);
  auto hX = Kokkos::create_mirror_view(X);
  for (int k = 0; k < n; ++k) {   // a deterministic spread over the octant's cone, radii R +- 0.05
    const double lon = (0.05 + 0.9 * ((k * 0.618034) - std::floor(k * 0.618034))) * M_PI / 2;
    const double lat = (0.05 + 0.9 * ((k * 0.414214) - std::floor(k * 0.414214))) * M_PI / 2;
    const double r = R + 0.05 * std::sin(1.0 + k);
    hX(k, 0) = r * std::cos(lat) * std::cos(lon);
    hX(k, 1) = r * std::cos(lat) * std::sin(lon);
    hX(k, 2) = r * std::sin(lat);
  }
  Kokkos::deep_copy(X, hX);
  Kokkos::View<int*, MemSpace> found("found", n);
  for (auto _ : st) {
    if (rebuild) g = SurfaceSearch::build(sd);
    const SurfaceSearch gg = g;
    Kokkos::parallel_for("bench::SurfaceProjection", Kokkos::RangePolicy<ExecSpace>(0, n), KOKKOS_LAMBDA(const int k) {
      const double x[3] = {X(k, 0), X(k, 1), X(k, 2)};
      double uv[2], foot[3], d2;
      bool inside = false;
      found(k) = closest_on_surface(sd, gg, x, 0.2, uv, foot, d2, inside) >= 0 && inside;
    });
    Kokkos::fence();
  }
  int ok = 0;
  Kokkos::parallel_reduce("bench::Count", Kokkos::RangePolicy<ExecSpace>(0, n), KOKKOS_LAMBDA(const int k, int& s) { s += found(k); }, ok);
  if (ok != n) st.SkipWithError("not every point found its foot inside an element");
  st.counters["projections/s"] = benchmark::Counter(static_cast<double>(n) * st.iterations(), benchmark::Counter::kIsRate);
  st.counters["surface elements"] = sd.ne[0] * sd.ne[1];
}

void BM_PolygonClip(benchmark::State& st) {
  const int n = static_cast<int>(st.range(0)), per_edge = static_cast<int>(st.range(1)) / 4;
  const TriangleRule g = triangle_rule_collapsed(gauss_rule(std::max(1, static_cast<int>(st.range(2)))));
  const bool rule = st.range(2) > 0;
  Kokkos::View<double* [4], MemSpace> slave("slave", n);
  Kokkos::View<double* [kClipMaxVertices][2], MemSpace> master("master", n);
  auto hs = Kokkos::create_mirror_view(slave);
  auto hm = Kokkos::create_mirror_view(master);
  std::mt19937 gen(1);
  std::uniform_real_distribution<double> U(0, 1);
  for (int k = 0; k < n; ++k) {
    const double u0 = U(gen), v0 = U(gen), h = 0.5 + 0.5 * U(gen);
    hs(k, 0) = u0;
    hs(k, 1) = u0 + h;
    hs(k, 2) = v0;
    hs(k, 3) = v0 + h;
    const double cx = u0 + h * (1.4 * U(gen) - 0.2), cy = v0 + h * (1.4 * U(gen) - 0.2), r = 0.4 * h, th = 6 * U(gen);
    const double corner[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
    for (int e = 0; e < 4; ++e)
      for (int s = 0; s < per_edge; ++s) {
        const double t = static_cast<double>(s) / per_edge;
        const double a = corner[e][0] + t * (corner[(e + 1) % 4][0] - corner[e][0]);
        const double b = corner[e][1] + t * (corner[(e + 1) % 4][1] - corner[e][1]);
        hm(k, e * per_edge + s, 0) = cx + r * (std::cos(th) * a - std::sin(th) * b);
        hm(k, e * per_edge + s, 1) = cy + r * (std::sin(th) * a + std::cos(th) * b);
      }
  }
  Kokkos::deep_copy(slave, hs);
  Kokkos::deep_copy(master, hm);
  const int nm = 4 * per_edge;
  Kokkos::View<double*, MemSpace> area("area", n);
  for (auto _ : st) {
    Kokkos::parallel_for("bench::PolygonClip", Kokkos::RangePolicy<ExecSpace>(0, n), KOKKOS_LAMBDA(const int k) {
      const ClipPolygon S = parameter_rectangle(slave(k, 0), slave(k, 1), slave(k, 2), slave(k, 3));
      ClipPolygon M, P;
      M.n = nm;
      for (int a = 0; a < nm; ++a) {
        M.v[a][0] = master(k, a, 0);
        M.v[a][1] = master(k, a, 1);
      }
      clip_polygons(S, M, P);
      double w = 0;
      if (rule)
        for_each_polygon_point(P, g, [&](const double*, double wq) { w += wq; });
      else
        w = polygon_area(P);
      area(k) = w;
    });
    Kokkos::fence();
  }
  int overlaps = 0;
  Kokkos::parallel_reduce("bench::Overlaps", Kokkos::RangePolicy<ExecSpace>(0, n), KOKKOS_LAMBDA(const int k, int& c) { c += area(k) > 0; }, overlaps);
  st.counters["clips/s"] = benchmark::Counter(static_cast<double>(n) * st.iterations(), benchmark::Counter::kIsRate);
  st.counters["overlapping"] = static_cast<double>(overlaps) / n;
}

void BM_SpMV(benchmark::State& st) {
  const Problem prob = block_problem(2, static_cast<int>(st.range(0)));
  System sys(prob, Tpetra::getDefaultComm());
  RCP<Matrix> A = sys.assemble_stiffness();
  Vector x(sys.owned_map()), y(sys.owned_map());
  x.putScalar(1.0);
  for (auto _ : st) { A->apply(x, y); Kokkos::fence(); }
  const double nnz = static_cast<double>(A->getNodeNumEntries()), rows = static_cast<double>(A->getNodeNumRows());
  // values (8) + column indices (4) per entry, row offsets (8), x read once (8), y written (8)
  const double bytes = nnz * 12 + rows * (8 + 8 + 8);
  st.counters["GB/s"] = benchmark::Counter(bytes * 1e-9 * st.iterations(), benchmark::Counter::kIsRate);
  st.counters["dofs"] = rows;
  st.counters["nnz"] = nnz;
}

void BM_StreamCopy(benchmark::State& st) {
  const size_t n = static_cast<size_t>(st.range(0));
  Kokkos::View<double*, MemSpace> a("a", n), b("b", n);
  Kokkos::deep_copy(a, 1.0);
  for (auto _ : st) {
    Kokkos::parallel_for("bench::Copy", Kokkos::RangePolicy<ExecSpace>(0, n), KOKKOS_LAMBDA(const size_t i) { b(i) = a(i); });
    Kokkos::fence();
  }
  st.counters["GB/s"] = benchmark::Counter(16.0 * n * 1e-9 * st.iterations(), benchmark::Counter::kIsRate);
}

}  // namespace

BENCHMARK(BM_SurfaceProjection)->ArgNames({"points", "search"})->Args({1000, 0})->Args({10000, 0})->Args({100000, 0})->Args({10000, 1})->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_TEMPLATE(BM_Basis, 1)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_TEMPLATE(BM_Basis, 2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_TEMPLATE(BM_Basis, 3)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_TEMPLATE(BM_Basis, 4)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_TEMPLATE(BM_ElementStiffness, 1)->ArgName("spline")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_TEMPLATE(BM_ElementStiffness, 2)->ArgName("spline")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_TEMPLATE(BM_ElementStiffness, 3)->ArgName("spline")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_TEMPLATE(BM_ElementStiffness, 4)->ArgName("spline")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_TEMPLATE(BM_ElementStiffness, 5)->ArgName("spline")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_TEMPLATE(BM_FiniteStrain, 1)->ArgName("model")->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_TEMPLATE(BM_FiniteStrain, 2)->ArgName("model")->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_TEMPLATE(BM_FiniteStrain, 3)->ArgName("model")->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_TEMPLATE(BM_FiniteStrain, 4)->ArgName("model")->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_TEMPLATE(BM_Scatter, 1)->ArgName("sorted")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_TEMPLATE(BM_Scatter, 2)->ArgName("sorted")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_TEMPLATE(BM_Scatter, 3)->ArgName("sorted")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_TEMPLATE(BM_Scatter, 4)->ArgName("sorted")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_TEMPLATE(BM_Formation, 2)->ArgName("rows")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_TEMPLATE(BM_Formation, 3)->ArgName("rows")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_TEMPLATE(BM_Formation, 4)->ArgName("rows")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_TEMPLATE(BM_Formation, 5)->ArgName("rows")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_TEMPLATE(BM_Formation3D, 1)->ArgNames({"model", "sf"})->ArgsProduct({{0, 2}, {0, 1}})->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_TEMPLATE(BM_Formation3D, 2)->ArgNames({"model", "sf"})->ArgsProduct({{0, 2}, {0, 1}})->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_TEMPLATE(BM_Formation3D, 3)->ArgNames({"model", "sf"})->ArgsProduct({{0, 2}, {0, 1}})->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_TEMPLATE(BM_Formation3D, 4)->ArgNames({"model", "sf"})->ArgsProduct({{0, 2}, {0, 1}})->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_ContactProjection)->ArgNames({"M", "warm"})->ArgsProduct({{16, 64, 256, 1024, 4096}, {0, 1}})->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_PolygonClip)->ArgNames({"pairs", "master_points", "rule"})->Args({10000, 4, 0})->Args({100000, 4, 0})->Args({100000, 12, 0})->Args({100000, 4, 3})->Args({100000, 12, 3})->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_SpMV)->Arg(64)->Arg(256)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_StreamCopy)->Arg(1 << 16)->Arg(1 << 25)->Unit(benchmark::kMillisecond)->UseRealTime();

int main(int argc, char** argv) {
  Tpetra::ScopeGuard guard(&argc, &argv);
  benchmark::Initialize(&argc, argv);
  // threads: the kernels run on Tpetra's default execution space (OMP_NUM_THREADS for OpenMP)
  benchmark::AddCustomContext("kokkos execution space", ExecSpace::name());
  benchmark::AddCustomContext("kokkos threads", std::to_string(ExecSpace::concurrency()));
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
