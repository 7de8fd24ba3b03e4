// dealii_assembly: the deal.II peer of igacontact's element formation (issue 18).
//
// What it measures. igacontact's Lame cylinder (examples/lame_cylinder.yaml: quarter annulus,
// inner radius 1, outer radius 2, centre (0, 0), E = 2e5, nu = 0.3, plane strain) discretised
// the deal.II way and assembled on one core:
//   - FESystem(FE_Q<2>(p), 2) (Gauss-Lobatto support points), MappingQ<2>(p), QGauss<2>(p + 1);
//   - the mesh: a subdivided (r, theta) rectangle [1, 2] x [0, pi/2] of NR x NT cells mapped
//     onto the quarter annulus, every object (cells, faces) on a PolarManifold about the centre,
//     so MappingQ's support points (boundary and interior) interpolate the exact polar map
//     (the equivalent of a spherical manifold on the arcs plus transfinite interpolation
//     inside, and exact for this domain). NT = 2 NR or 2 NR +- 1, the lame_cylinder.yaml aspect
//     ([16, 8]), chosen so that the dof count 2 (p NR + 1)(p NT + 1) is nearest the target;
//   - no dof renumbering (distribute_dofs' own cell-by-cell order).
// Two phases, each timed R times; the medians (and the first, cold, repetition) are printed:
//   (a) setup: distribute_dofs, DynamicSparsityPattern + DoFTools::make_sparsity_pattern,
//       SparsityPattern::copy_from, SparseMatrix::reinit (allocates and zeroes the values);
//       with --mapping cache also MappingQCache::initialize.
//   (b) assembly: matrix = 0, then the cell loop: FEValues::reinit (update_gradients |
//       update_JxW_values), the local matrix, SparseMatrix::add(local_dof_indices, cell_matrix)
//       (--add constraints: AffineConstraints::distribute_local_to_global with empty constraints).
// Local matrix forms (--form):
//   blocked (default): component-wise, per pair (a, b) of scalar FE_Q shape functions with
//     b >= a, the four sums S_cd = sum_q JxW d_c phi_a d_d phi_b (4 multiply-adds per pair and
//     point), then K(ac, bd) = lambda S_cd + mu S_dc + mu delta_cd (S_xx + S_yy), mirrored;
//   extractor: the usual FEValuesExtractors::Vector form, lambda div phi_i div phi_j
//     + 2 mu eps(phi_i) : eps(phi_j), q outer, j >= i, symmetric gradients precomputed per q.
// Check (cheap, after the timings): K applied to the interpolants of a rigid translation
// (1, 0) and a rigid rotation (-y, x) (exact in the iso-parametric space), max |K u| relative
// to max |K_ii|; exit status 1 when either exceeds 1e-9.
//
// Single thread: MPI_InitFinalize(argc, argv, 1) and MultithreadInfo::set_thread_limit(1).
//
// Build (separate CMake project, never built by CI; needs Debian's libdeal.ii-dev):
//   cmake -S benchmarks/peers -B build-peers -DCMAKE_BUILD_TYPE=Release
//   cmake --build build-peers -j1
// Run:
//   build-peers/dealii_assembly P [DOFS]            (P = 1..8, DOFS default 1e5)
//   build-peers/dealii_assembly --degree 4 --dofs 1e5 --reps 5 [--mapping q|cache]
//       [--form blocked|extractor] [--add direct|constraints] [--subdivide NT NR] [--verbose]
// One JSON line on stdout. benchmarks/peers/compare_assembly.sh runs it against igacontact.

#include <deal.II/base/function.h>
#include <deal.II/base/multithread_info.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/base/revision.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/mapping_q.h>
#include <deal.II/fe/mapping_q_cache.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/grid/manifold_lib.h>
#include <deal.II/grid/tria.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/sparsity_pattern.h>
#include <deal.II/lac/vector.h>
#include <deal.II/numerics/vector_tools.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "lame_mesh.hpp"

using namespace dealii;

namespace {

using namespace lame;

struct Options {
  unsigned int degree = 2;
  double dofs = 1e5;
  unsigned int reps = 5;
  std::string mapping = "q";      // q | cache
  std::string form = "blocked";   // blocked | extractor
  std::string add = "direct";     // direct | constraints
  unsigned int nt = 0, nr = 0;    // --subdivide NT NR (angular, radial); 0: from the dof target
  bool verbose = false;
};

[[noreturn]] void usage(const std::string& why) {
  std::cerr << "dealii_assembly: " << why << "\n"
            << "usage: dealii_assembly [P [DOFS]] [--degree P] [--dofs N] [--reps R] [--mapping q|cache]\n"
            << "       [--form blocked|extractor] [--add direct|constraints] [--subdivide NT NR] [--verbose]\n";
  std::exit(2);
}

Options parse(int argc, char** argv) {
  Options o;
  int positional = 0;
  for (int k = 1; k < argc; ++k) {
    const std::string a = argv[k];
    const auto next = [&]() -> std::string {
      if (k + 1 >= argc) usage(a + " needs a value");
      return argv[++k];
    };
    try {
      if (a == "--degree") o.degree = std::stoul(next());
      else if (a == "--dofs") o.dofs = std::stod(next());
      else if (a == "--reps") o.reps = std::stoul(next());
      else if (a == "--mapping") o.mapping = next();
      else if (a == "--form") o.form = next();
      else if (a == "--add") o.add = next();
      else if (a == "--subdivide") { o.nt = std::stoul(next()); o.nr = std::stoul(next()); }
      else if (a == "--verbose") o.verbose = true;
      else if (a == "-h" || a == "--help") usage("help");
      else if (!a.empty() && a[0] != '-' && positional == 0) { o.degree = std::stoul(a); ++positional; }
      else if (!a.empty() && a[0] != '-' && positional == 1) { o.dofs = std::stod(a); ++positional; }
      else usage("unknown argument " + a);
    } catch (const std::invalid_argument&) {
      usage("bad value in " + a);
    }
  }
  if (o.degree < 1 || o.degree > 8) usage("degree must be 1..8");
  if (o.reps < 1) usage("--reps must be >= 1");
  if (o.mapping != "q" && o.mapping != "cache") usage("--mapping q|cache");
  if (o.form != "blocked" && o.form != "extractor") usage("--form blocked|extractor");
  if (o.add != "direct" && o.add != "constraints") usage("--add direct|constraints");
  if (o.dofs < 8) usage("--dofs too small");
  return o;
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

void choose_subdivision(Options& o) {
  if (o.nt > 0 && o.nr > 0) return;
  lame::choose_subdivision(o.degree, o.dofs, o.nt, o.nr);
}

class Rotation : public Function<2> {
 public:
  Rotation() : Function<2>(2) {}
  double value(const Point<2>& x, const unsigned int c) const override { return c == 0 ? -x[1] : x[0]; }
};

}  // namespace

int main(int argc, char** argv) {
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  MultithreadInfo::set_thread_limit(1);
  Options opt = parse(argc, argv);
  choose_subdivision(opt);
  const unsigned p = opt.degree;

  const double lambda = youngs_modulus * poisson_ratio / ((1 + poisson_ratio) * (1 - 2 * poisson_ratio));
  const double mu = youngs_modulus / (2 * (1 + poisson_ratio));

  Triangulation<2> tria;
  make_mesh(tria, opt.nt, opt.nr);
  const FESystem<2> fe(FE_Q<2>(p), 2);
  const QGauss<2> quadrature(p + 1);
  const MappingQ<2> mapping_q(p);
  MappingQCache<2> mapping_cache(p);
  const Mapping<2>& mapping = opt.mapping == "cache" ? static_cast<const Mapping<2>&>(mapping_cache)
                                                     : static_cast<const Mapping<2>&>(mapping_q);
  DoFHandler<2> dof_handler(tria);
  SparsityPattern sparsity;
  SparseMatrix<double> matrix;
  AffineConstraints<double> constraints;
  constraints.close();

  const unsigned dpc = fe.n_dofs_per_cell();
  const unsigned nb = dpc / 2;   // scalar FE_Q functions per cell
  const unsigned nq = quadrature.size();
  // system index of (component c, scalar function a)
  std::vector<unsigned> sys_index[2];
  for (unsigned c = 0; c < 2; ++c)
    for (unsigned a = 0; a < nb; ++a) sys_index[c].push_back(fe.component_to_system_index(c, a));

  std::vector<double> setup_t, assembly_t, cache_t;
  for (unsigned rep = 0; rep < opt.reps; ++rep) {
    // (a) set-up
    auto t0 = std::chrono::steady_clock::now();
    double tc = 0.0;
    if (opt.mapping == "cache") {
      const auto tc0 = std::chrono::steady_clock::now();
      mapping_cache.initialize(mapping_q, tria);
      tc = seconds_since(tc0);
    }
    matrix.clear();
    dof_handler.distribute_dofs(fe);
    const double t_dofs = seconds_since(t0);
    double t_dsp, t_copy;
    {
      DynamicSparsityPattern dsp(dof_handler.n_dofs());
      DoFTools::make_sparsity_pattern(dof_handler, dsp);
      t_dsp = seconds_since(t0);
      sparsity.copy_from(dsp);
      t_copy = seconds_since(t0);
    }
    matrix.reinit(sparsity);
    setup_t.push_back(seconds_since(t0));
    if (opt.verbose)
      std::fprintf(stderr, "rep %u setup: distribute_dofs %.6f, make_sparsity_pattern %.6f, copy_from %.6f, reinit %.6f s\n",
                   rep, t_dofs - tc, t_dsp - t_dofs, t_copy - t_dsp, setup_t.back() - t_copy);
    cache_t.push_back(tc);

    // (b) assembly
    t0 = std::chrono::steady_clock::now();
    matrix = 0;
    FEValues<2> fe_values(mapping, fe, quadrature, update_gradients | update_JxW_values);
    FullMatrix<double> cell_matrix(dpc, dpc);
    std::vector<types::global_dof_index> dof_indices(dpc);
    // blocked form: scalar gradients (weighted and not) and the four sums, nb x nb each
    std::vector<double> gx(nb), gy(nb), wgx(nb), wgy(nb);
    std::vector<double> Sxx(nb * nb), Sxy(nb * nb), Syx(nb * nb), Syy(nb * nb);
    // extractor form
    std::vector<SymmetricTensor<2, 2>> eps(dpc);
    std::vector<double> div(dpc);
    for (const auto& cell : dof_handler.active_cell_iterators()) {
      fe_values.reinit(cell);
      if (opt.form == "blocked") {
        std::fill(Sxx.begin(), Sxx.end(), 0.0);
        std::fill(Sxy.begin(), Sxy.end(), 0.0);
        std::fill(Syx.begin(), Syx.end(), 0.0);
        std::fill(Syy.begin(), Syy.end(), 0.0);
        for (unsigned q = 0; q < nq; ++q) {
          const double w = fe_values.JxW(q);
          for (unsigned a = 0; a < nb; ++a) {
            const Tensor<1, 2>& g = fe_values.shape_grad(sys_index[0][a], q);
            gx[a] = g[0];
            gy[a] = g[1];
            wgx[a] = w * g[0];
            wgy[a] = w * g[1];
          }
          for (unsigned a = 0; a < nb; ++a) {
            const double ax = wgx[a], ay = wgy[a];
            double* sxx = &Sxx[a * nb];
            double* sxy = &Sxy[a * nb];
            double* syx = &Syx[a * nb];
            double* syy = &Syy[a * nb];
            for (unsigned b = a; b < nb; ++b) {
              sxx[b] += ax * gx[b];
              sxy[b] += ax * gy[b];
              syx[b] += ay * gx[b];
              syy[b] += ay * gy[b];
            }
          }
        }
        for (unsigned a = 0; a < nb; ++a) {
          const unsigned ax = sys_index[0][a], ay = sys_index[1][a];
          for (unsigned b = a; b < nb; ++b) {
            const unsigned bx = sys_index[0][b], by = sys_index[1][b];
            const unsigned k = a * nb + b;
            const double kxx = (lambda + 2 * mu) * Sxx[k] + mu * Syy[k];
            const double kxy = lambda * Sxy[k] + mu * Syx[k];
            const double kyx = lambda * Syx[k] + mu * Sxy[k];
            const double kyy = (lambda + 2 * mu) * Syy[k] + mu * Sxx[k];
            cell_matrix(ax, bx) = kxx;
            cell_matrix(ax, by) = kxy;
            cell_matrix(ay, bx) = kyx;
            cell_matrix(ay, by) = kyy;
            cell_matrix(bx, ax) = kxx;   // (b, a) block = (a, b) block transposed
            cell_matrix(by, ax) = kxy;
            cell_matrix(bx, ay) = kyx;
            cell_matrix(by, ay) = kyy;
          }
        }
      } else {
        extractor_local_matrix(fe_values, lambda, mu, eps, div, cell_matrix);
      }
      cell->get_dof_indices(dof_indices);
      if (opt.add == "direct") matrix.add(dof_indices, cell_matrix);
      else constraints.distribute_local_to_global(cell_matrix, dof_indices, matrix);
    }
    assembly_t.push_back(seconds_since(t0));
    if (opt.verbose)
      std::fprintf(stderr, "rep %u: setup %.6f s (mapping cache %.6f s), assembly %.6f s\n", rep, setup_t.back(), tc,
                   assembly_t.back());
  }

  // check: rigid translation and rotation
  double max_diag = 0.0;
  for (types::global_dof_index i = 0; i < matrix.m(); ++i) max_diag = std::max(max_diag, std::abs(matrix.diag_element(i)));
  const auto residual = [&](const Function<2>& f) {
    Vector<double> u(dof_handler.n_dofs()), r(dof_handler.n_dofs());
    VectorTools::interpolate(mapping_q, dof_handler, f, u);
    matrix.vmult(r, u);
    return r.linfty_norm() / max_diag;
  };
  const double res_t = residual(Functions::ConstantFunction<2>(std::vector<double>{1.0, 0.0}));
  const double res_r = residual(Rotation());
  const bool pass = res_t < 1e-9 && res_r < 1e-9;

  const double n = static_cast<double>(dof_handler.n_dofs());
  const double s = median(setup_t), a = median(assembly_t);
  std::printf(
      "{\"code\": \"deal.II %s\", \"degree\": %u, \"subdivide\": [%u, %u], \"cells\": %u, \"dofs\": %llu, "
      "\"quadrature_points\": %llu, \"nonzeros\": %llu, \"mapping\": \"%s\", \"form\": \"%s\", \"add\": \"%s\", "
      "\"renumbering\": \"none\", \"reps\": %u, \"setup_s\": %.6g, \"assembly_s\": %.6g, \"setup_us_per_dof\": %.6g, "
      "\"assembly_us_per_dof\": %.6g, \"element_matrices_per_s\": %.6g, \"mapping_cache_s\": %.6g, "
      "\"setup_s_first\": %.6g, \"assembly_s_first\": %.6g, \"translation_residual\": %.3g, "
      "\"rotation_residual\": %.3g, \"check\": \"%s\"}\n",
      DEAL_II_PACKAGE_VERSION, p, opt.nt, opt.nr, tria.n_active_cells(),
      static_cast<unsigned long long>(dof_handler.n_dofs()), 1ULL * tria.n_active_cells() * nq,
      static_cast<unsigned long long>(sparsity.n_nonzero_elements()), opt.mapping.c_str(), opt.form.c_str(),
      opt.add.c_str(), opt.reps, s, a, 1e6 * s / n, 1e6 * a / n, tria.n_active_cells() / a, median(cache_t),
      setup_t.front(), assembly_t.front(), res_t, res_r, pass ? "pass" : "FAIL");
  return pass ? 0 : 1;
}
