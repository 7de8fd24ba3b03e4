// dealii_lame: the deal.II peer of a whole igacontact run (issue 34): Lame's thick cylinder
// (examples/lame_cylinder.yaml: quarter annulus a = 1, b = 2, internal pressure 10, E = 2e5,
// nu = 0.3, plane strain; u_y = 0 on the cut along y = 0, u_x = 0 on the cut along x = 0)
// solved to its relative L2 displacement error, one thread, the whole process timed from
// outside by benchmarks/peers/compare_lame.sh.
//
// The discretisation is dealii_assembly's (FESystem(FE_Q(p), 2), MappingQ(p) on a polar
// manifold, QGauss(p + 1), the (r, theta) rectangle NR x NT, NT ~ 2 NR; lame_mesh.hpp), the
// tutorial way (step-8): the local matrix with FEValuesExtractors, the pressure by
// FEFaceValues, the symmetry conditions through AffineConstraints
// (interpolate_boundary_values with a component mask) eliminated while distributing, the
// sparse direct solver UMFPACK (SparseDirectUMFPACK; a direct solver is what both codes'
// whole runs measured fastest at this size and degree), and the error by
// VectorTools::integrate_difference with QGauss(p + 3) against the closed form.
//
// Build: cmake -S benchmarks/peers -B build-peers -DCMAKE_BUILD_TYPE=Release && cmake --build build-peers
// Run:   build-peers/dealii_lame P DOFS|NTxNR   (one JSON line: dofs, error, stage seconds; NTxNR:
//        NT cells around, NR through the wall, instead of the NT ~ 2 NR nearest DOFS)

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
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/sparse_direct.h>
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/sparsity_pattern.h>
#include <deal.II/lac/vector.h>
#include <deal.II/numerics/vector_tools.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "lame_mesh.hpp"

using namespace dealii;
using namespace lame;

namespace {

constexpr double pressure = 10.0;

// u = u_r(r) e_r, u_r = (1 + nu) / E c ((1 - 2 nu) r + b^2 / r), c = p a^2 / (b^2 - a^2)
class Exact : public Function<2> {
 public:
  Exact() : Function<2>(2) {}
  double value(const Point<2>& x, const unsigned int comp) const override {
    const double a = inner_radius, b = outer_radius, nu = poisson_ratio;
    const double c = pressure * a * a / (b * b - a * a), r = x.norm();
    const double ur = (1 + nu) / youngs_modulus * c * ((1 - 2 * nu) * r + b * b / r);
    return ur * x[comp] / r;
  }
};

double since(std::chrono::steady_clock::time_point& t0) {
  const auto t = std::chrono::steady_clock::now();
  const double s = std::chrono::duration<double>(t - t0).count();
  t0 = t;
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  MultithreadInfo::set_thread_limit(1);
  if (argc < 3) {
    std::fprintf(stderr, "usage: dealii_lame P DOFS|NTxNR\n");
    return 2;
  }
  const unsigned p = std::stoul(argv[1]);
  unsigned nt = 0, nr = 0;
  const std::string size = argv[2];   // a dof count (NT ~ 2 NR), or NTxNR cells
  const auto x = size.find('x');
  if (x != std::string::npos) {
    nt = std::stoul(size.substr(0, x));
    nr = std::stoul(size.substr(x + 1));
  } else {
    choose_subdivision(p, std::stod(size), nt, nr);
  }
  const double lambda = youngs_modulus * poisson_ratio / ((1 + poisson_ratio) * (1 - 2 * poisson_ratio));
  const double mu = youngs_modulus / (2 * (1 + poisson_ratio));

  auto t0 = std::chrono::steady_clock::now();
  Triangulation<2> tria;
  make_mesh(tria, nt, nr);   // boundary ids: 0 r = a (pressure), 1 r = b, 2 theta = 0, 3 theta = pi / 2
  const FESystem<2> fe(FE_Q<2>(p), 2);
  const MappingQ<2> mapping(p);
  DoFHandler<2> dofs(tria);
  dofs.distribute_dofs(fe);
  AffineConstraints<double> constraints;
  VectorTools::interpolate_boundary_values(mapping, dofs, 2, Functions::ZeroFunction<2>(2), constraints,
                                           ComponentMask(std::vector<bool>{false, true}));
  VectorTools::interpolate_boundary_values(mapping, dofs, 3, Functions::ZeroFunction<2>(2), constraints,
                                           ComponentMask(std::vector<bool>{true, false}));
  constraints.close();
  SparsityPattern sparsity;
  {
    DynamicSparsityPattern dsp(dofs.n_dofs());
    DoFTools::make_sparsity_pattern(dofs, dsp, constraints, false);
    sparsity.copy_from(dsp);
  }
  SparseMatrix<double> K(sparsity);
  Vector<double> f(dofs.n_dofs()), u(dofs.n_dofs());
  const double t_setup = since(t0);

  const QGauss<2> quadrature(p + 1);
  const QGauss<1> face_quadrature(p + 1);
  FEValues<2> fv(mapping, fe, quadrature, update_gradients | update_JxW_values);
  FEFaceValues<2> ffv(mapping, fe, face_quadrature, update_values | update_normal_vectors | update_JxW_values);
  const unsigned dpc = fe.n_dofs_per_cell();
  FullMatrix<double> Ke(dpc, dpc);
  Vector<double> fe_rhs(dpc);
  std::vector<types::global_dof_index> idx(dpc);
  const FEValuesExtractors::Vector disp(0);
  std::vector<SymmetricTensor<2, 2>> eps(dpc);
  std::vector<double> div(dpc);
  for (const auto& cell : dofs.active_cell_iterators()) {
    fv.reinit(cell);
    extractor_local_matrix(fv, lambda, mu, eps, div, Ke);
    fe_rhs = 0;
    for (const auto face : cell->face_indices())
      if (cell->face(face)->at_boundary() && cell->face(face)->boundary_id() == 0) {
        ffv.reinit(cell, face);
        for (unsigned q = 0; q < face_quadrature.size(); ++q) {
          const Tensor<1, 2> t = -pressure * ffv.normal_vector(q);   // the pressure pushes along -n
          for (unsigned i = 0; i < dpc; ++i) fe_rhs(i) += t * ffv[disp].value(i, q) * ffv.JxW(q);
        }
      }
    cell->get_dof_indices(idx);
    constraints.distribute_local_to_global(Ke, fe_rhs, idx, K, f);
  }
  const double t_assembly = since(t0);

  SparseDirectUMFPACK solver;
  solver.initialize(K);
  solver.vmult(u, f);
  constraints.distribute(u);
  const double t_solve = since(t0);

  // relative L2 error of the displacement
  const QGauss<2> error_quadrature(p + 3);
  Vector<float> cellwise(tria.n_active_cells());
  VectorTools::integrate_difference(mapping, dofs, u, Exact(), cellwise, error_quadrature, VectorTools::L2_norm);
  const double err = VectorTools::compute_global_error(tria, cellwise, VectorTools::L2_norm);
  Vector<double> zero(dofs.n_dofs());
  VectorTools::integrate_difference(mapping, dofs, zero, Exact(), cellwise, error_quadrature, VectorTools::L2_norm);
  const double norm = VectorTools::compute_global_error(tria, cellwise, VectorTools::L2_norm);
  const double t_error = since(t0);

  std::printf("{\"code\": \"deal.II %s\", \"degree\": %u, \"subdivide\": [%u, %u], \"dofs\": %u, \"l2_error\": %.6g, "
              "\"setup_s\": %.6g, \"assembly_s\": %.6g, \"solve_s\": %.6g, \"error_s\": %.6g}\n",
              DEAL_II_PACKAGE_VERSION, p, nt, nr, dofs.n_dofs(), err / norm, t_setup, t_assembly, t_solve, t_error);
  return 0;
}
