// dealii_sphere: the deal.II peer of a whole igacontact run in 3-D (issue 35, item 7): the
// thick-walled sphere under internal pressure (examples/thick_sphere.yaml: the octant
// x, y, z >= 0 of the shell a = 1 <= r <= 2, E = 1000, nu = 0.3, internal pressure 1, outer
// surface free, normal displacement zero on the three symmetry planes) solved to its relative
// L2 displacement error, one thread, the whole process timed from outside by
// benchmarks/peers/compare_sphere.sh.
//
// The discretisation the tutorial way (step-8, as dealii_lame.cpp): the octant by
// GridGenerator::quarter_hyper_shell (3 cells in 3-D, a SphericalManifold on every object, so
// MappingQ(p)'s support points interpolate the exact sphere: isoparametric, the curved geometry
// converges with the field) refined globally K times (3 * 8^K cells), FESystem(FE_Q(p), 3),
// QGauss(p + 1), the local matrix with FEValuesExtractors, the pressure by FEFaceValues on the
// inner surface, the symmetry conditions (u_x = 0 on x = 0, u_y = 0 on y = 0, u_z = 0 on z = 0)
// through AffineConstraints eliminated while distributing, and the error by
// VectorTools::integrate_difference with QGauss(p + 2) against the closed form
//   u = u_r(r) x / r,  u_r = p a^3 / (E (b^3 - a^3)) ((1 - 2 nu) r + (1 + nu) b^3 / (2 r^2)),
// relative to the L2 norm of u.
//
// The linear solver (third argument):
//   umfpack  SparseDirectUMFPACK (the default; dealii_lame.cpp's)
//   mumps    PETSc's MUMPS through PETScWrappers::SparseDirectMUMPS (LU; the matrix assembled
//            into a PETSc matrix directly)
//   amg      CG to a relative residual of 1e-12 preconditioned by Trilinos ML
//            (TrilinosWrappers::PreconditionAMG, elliptic, higher_order_elements, the three
//            constant modes of DoFTools::extract_constant_modes), matrix assembled into a
//            Trilinos matrix directly
//
// Build: benchmarks/peers/build_peers.sh dealii_sphere (build-peers/, Release)
// Run:   build-peers/dealii_sphere P K [umfpack|mumps|amg]   (one JSON line: dofs, error, stage seconds)

#include <deal.II/base/function.h>
#include <deal.II/base/index_set.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/multithread_info.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/base/revision.h>
#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/mapping_q.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/manifold_lib.h>
#include <deal.II/grid/tria.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/petsc_solver.h>
#include <deal.II/lac/petsc_sparse_matrix.h>
#include <deal.II/lac/petsc_vector.h>
#include <deal.II/lac/solver_cg.h>
#include <deal.II/lac/solver_control.h>
#include <deal.II/lac/sparse_direct.h>
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/sparsity_pattern.h>
#include <deal.II/lac/trilinos_precondition.h>
#include <deal.II/lac/trilinos_solver.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>
#include <deal.II/lac/trilinos_vector.h>
#include <deal.II/lac/vector.h>
#include <deal.II/numerics/vector_tools.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

using namespace dealii;

namespace {

constexpr double inner_radius = 1.0, outer_radius = 2.0;
constexpr double youngs_modulus = 1000.0, poisson_ratio = 0.3, pressure = 1.0;

class Exact : public Function<3> {
 public:
  Exact() : Function<3>(3) {}
  double value(const Point<3>& x, const unsigned int comp) const override {
    const double a = inner_radius, b = outer_radius, nu = poisson_ratio, r = x.norm();
    const double ur = pressure * a * a * a / (youngs_modulus * (b * b * b - a * a * a)) *
                      ((1 - 2 * nu) * r + (1 + nu) * b * b * b / (2 * r * r));
    return ur * x[comp] / r;
  }
};

double since(std::chrono::steady_clock::time_point& t0) {
  const auto t = std::chrono::steady_clock::now();
  const double s = std::chrono::duration<double>(t - t0).count();
  t0 = t;
  return s;
}

// The local elasticity matrix the tutorial way (FEValuesExtractors, as lame_mesh.hpp's in 2-D):
// lambda div phi_i div phi_j + 2 mu eps(phi_i) : eps(phi_j), j >= i, then mirrored.
void local_matrix(const FEValues<3>& fv, double lambda, double mu, std::vector<SymmetricTensor<2, 3>>& eps,
                  std::vector<double>& div, FullMatrix<double>& K) {
  const FEValuesExtractors::Vector disp(0);
  const unsigned dpc = K.m();
  K = 0;
  for (unsigned q = 0; q < fv.n_quadrature_points; ++q) {
    const double w = fv.JxW(q);
    for (unsigned i = 0; i < dpc; ++i) {
      eps[i] = fv[disp].symmetric_gradient(i, q);
      div[i] = fv[disp].divergence(i, q);
    }
    for (unsigned i = 0; i < dpc; ++i) {
      const SymmetricTensor<2, 3> e = 2 * mu * w * eps[i];
      const double d = lambda * w * div[i];
      for (unsigned j = i; j < dpc; ++j) K(i, j) += d * div[j] + e * eps[j];
    }
  }
  for (unsigned i = 0; i < dpc; ++i)
    for (unsigned j = i + 1; j < dpc; ++j) K(j, i) = K(i, j);
}

// element loop: K and f of any deal.II matrix / vector type distribute_local_to_global takes
template <class MatrixT, class VectorT>
void assemble(const DoFHandler<3>& dofs, const Mapping<3>& mapping, const AffineConstraints<double>& constraints,
              unsigned p, MatrixT& K, VectorT& f) {
  const double nu = poisson_ratio, E = youngs_modulus;
  const double lambda = E * nu / ((1 + nu) * (1 - 2 * nu)), mu = E / (2 * (1 + nu));
  const FiniteElement<3>& fe = dofs.get_fe();
  const QGauss<3> quadrature(p + 1);
  const QGauss<2> face_quadrature(p + 1);
  FEValues<3> fv(mapping, fe, quadrature, update_gradients | update_JxW_values);
  FEFaceValues<3> ffv(mapping, fe, face_quadrature, update_values | update_normal_vectors | update_JxW_values);
  const unsigned dpc = fe.n_dofs_per_cell();
  FullMatrix<double> Ke(dpc, dpc);
  Vector<double> fe_rhs(dpc);
  std::vector<types::global_dof_index> idx(dpc);
  const FEValuesExtractors::Vector disp(0);
  std::vector<SymmetricTensor<2, 3>> eps(dpc);
  std::vector<double> div(dpc);
  for (const auto& cell : dofs.active_cell_iterators()) {
    fv.reinit(cell);
    local_matrix(fv, lambda, mu, eps, div, Ke);
    fe_rhs = 0;
    for (const auto face : cell->face_indices())
      if (cell->face(face)->at_boundary() && cell->face(face)->boundary_id() == 0) {
        ffv.reinit(cell, face);
        for (unsigned q = 0; q < face_quadrature.size(); ++q) {
          const Tensor<1, 3> t = -pressure * ffv.normal_vector(q);   // outward normal: the pressure pushes along -n
          for (unsigned i = 0; i < dpc; ++i) fe_rhs(i) += t * ffv[disp].value(i, q) * ffv.JxW(q);
        }
      }
    cell->get_dof_indices(idx);
    constraints.distribute_local_to_global(Ke, fe_rhs, idx, K, f);
  }
  K.compress(VectorOperation::add);
  f.compress(VectorOperation::add);
}

}  // namespace

int main(int argc, char** argv) {
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  MultithreadInfo::set_thread_limit(1);
  if (argc < 3) {
    std::fprintf(stderr, "usage: dealii_sphere P K [umfpack|mumps|amg]   (degree, global refinements of the 3-cell octant)\n");
    return 2;
  }
  const unsigned p = std::stoul(argv[1]), levels = std::stoul(argv[2]);
  const std::string method = argc > 3 ? argv[3] : "umfpack";
  if (method != "umfpack" && method != "mumps" && method != "amg") {
    std::fprintf(stderr, "dealii_sphere: unknown solver '%s' (umfpack, mumps, amg)\n", method.c_str());
    return 2;
  }

  auto t0 = std::chrono::steady_clock::now();
  Triangulation<3> tria;
  // boundary ids (colorised): 0 r = a (pressure), 1 r = b (free), 2 x = 0, 3 y = 0, 4 z = 0;
  // manifold id 0 (a SphericalManifold about the origin) on every object
  GridGenerator::quarter_hyper_shell(tria, Point<3>(), inner_radius, outer_radius, 0, true);
  tria.refine_global(levels);
  const FESystem<3> fe(FE_Q<3>(p), 3);
  const MappingQ<3> mapping(p);
  DoFHandler<3> dofs(tria);
  dofs.distribute_dofs(fe);
  const unsigned n = dofs.n_dofs();
  AffineConstraints<double> constraints;
  for (unsigned c = 0; c < 3; ++c) {   // boundary id 2 + c is the plane x_c = 0: u_c = 0 there
    std::vector<bool> mask(3, false);
    mask[c] = true;
    VectorTools::interpolate_boundary_values(mapping, dofs, 2 + c, Functions::ZeroFunction<3>(3), constraints,
                                             ComponentMask(mask));
  }
  constraints.close();
  SparsityPattern sparsity;
  {
    DynamicSparsityPattern dsp(n);
    DoFTools::make_sparsity_pattern(dofs, dsp, constraints, false);
    sparsity.copy_from(dsp);
  }
  Vector<double> u(n);
  double t_setup = 0, t_assembly = 0, t_solve = 0;
  unsigned iterations = 0;

  if (method == "umfpack") {
    SparseMatrix<double> K(sparsity);
    Vector<double> f(n);
    t_setup = since(t0);
    assemble(dofs, mapping, constraints, p, K, f);
    t_assembly = since(t0);
    SparseDirectUMFPACK solver;
    solver.initialize(K);
    solver.vmult(u, f);
  } else if (method == "mumps") {
    const IndexSet all = complete_index_set(n);
    PETScWrappers::MPI::SparseMatrix K;
    K.reinit(all, all, sparsity, MPI_COMM_WORLD);
    PETScWrappers::MPI::Vector f(all, MPI_COMM_WORLD), x(all, MPI_COMM_WORLD);
    t_setup = since(t0);
    assemble(dofs, mapping, constraints, p, K, f);
    t_assembly = since(t0);
    SolverControl control(1, 0);
    PETScWrappers::SparseDirectMUMPS solver(control, MPI_COMM_WORLD);
    solver.set_symmetric_mode(true);
    solver.solve(K, x, f);
    for (unsigned i = 0; i < n; ++i) u(i) = x(i);
  } else {
    TrilinosWrappers::SparseMatrix K;
    K.reinit(sparsity);
    TrilinosWrappers::MPI::Vector f(complete_index_set(n), MPI_COMM_WORLD), x(complete_index_set(n), MPI_COMM_WORLD);
    t_setup = since(t0);
    assemble(dofs, mapping, constraints, p, K, f);
    t_assembly = since(t0);
    TrilinosWrappers::PreconditionAMG amg;
    TrilinosWrappers::PreconditionAMG::AdditionalData data;
    data.elliptic = true;
    data.higher_order_elements = p > 1;
    data.smoother_sweeps = 2;
    DoFTools::extract_constant_modes(dofs, ComponentMask(), data.constant_modes);
    amg.initialize(K, data);
    SolverControl control(5000, 1e-12 * f.l2_norm());
    SolverCG<TrilinosWrappers::MPI::Vector> cg(control);
    cg.solve(K, x, f, amg);
    iterations = control.last_step();
    for (unsigned i = 0; i < n; ++i) u(i) = x(i);
  }
  constraints.distribute(u);
  t_solve = since(t0);

  // relative L2 error of the displacement
  const QGauss<3> error_quadrature(p + 2);
  Vector<float> cellwise(tria.n_active_cells());
  VectorTools::integrate_difference(mapping, dofs, u, Exact(), cellwise, error_quadrature, VectorTools::L2_norm);
  const double err = VectorTools::compute_global_error(tria, cellwise, VectorTools::L2_norm);
  Vector<double> zero(n);
  VectorTools::integrate_difference(mapping, dofs, zero, Exact(), cellwise, error_quadrature, VectorTools::L2_norm);
  const double norm = VectorTools::compute_global_error(tria, cellwise, VectorTools::L2_norm);
  const double t_error = since(t0);

  std::printf("{\"code\": \"deal.II %s\", \"degree\": %u, \"refinements\": %u, \"cells\": %u, \"dofs\": %u, "
              "\"solver\": \"%s\", \"cg_iterations\": %u, \"l2_error\": %.6g, \"setup_s\": %.6g, \"assembly_s\": %.6g, "
              "\"solve_s\": %.6g, \"error_s\": %.6g}\n",
              DEAL_II_PACKAGE_VERSION, p, levels, tria.n_active_cells(), n, method.c_str(), iterations, err / norm,
              t_setup, t_assembly, t_solve, t_error);
  return 0;
}
