#include "solver/linear_solver.hpp"
#include "solver/amg.hpp"

#include <BelosSolverFactory.hpp>
#include <BelosTpetraAdapter.hpp>
#include <Ifpack2_Factory.hpp>
#include <Teuchos_CommHelpers.hpp>
#include <Teuchos_TimeMonitor.hpp>
#include <TpetraExt_MatrixMatrix.hpp>

#include <sstream>

namespace iga {


namespace {

RCP<Operator> make_preconditioner(const LinearOptions& opt, const RCP<Matrix>& A,
                                  const RCP<MultiVector>& nullspace, const RCP<MultiVector>& coords,
                                  const RCP<Matrix>& low_order, const RCP<const Matrix>& contact) {
  const int ranks = A->getComm()->getSize();
  const int dim = opt.dofs_per_node;   // interleaved displacement components
  switch (opt.preconditioner) {
    case Preconditioner::None: return Teuchos::null;
    case Preconditioner::BoomerAMG: return make_boomeramg(A, dim);
    case Preconditioner::ControlNet: {
      if (low_order.is_null()) return make_boomeramg(A, dim);
      if (contact.is_null()) return make_boomeramg(low_order, dim);
      // the control nets' stiffness and the contact tangent share the control-point dofs
      RCP<Matrix> sum = Tpetra::MatrixMatrix::add(1.0, false, *low_order, 1.0, false, *contact);
      return make_boomeramg(sum, dim);
    }
    case Preconditioner::Relaxation: {
      auto prec = Ifpack2::Factory::create<Tpetra::RowMatrix<SC, LO, GO, Node>>("RELAXATION", A);
      Teuchos::ParameterList p;
      p.set("relaxation: type", "Symmetric Gauss-Seidel");
      p.set("relaxation: sweeps", 1);
      prec->setParameters(p);
      prec->initialize();
      prec->compute();
      return prec;
    }
    case Preconditioner::ILUT: {
      auto prec = Ifpack2::Factory::create<Tpetra::RowMatrix<SC, LO, GO, Node>>("SCHWARZ", A);
      Teuchos::ParameterList p;
      p.set("schwarz: inner preconditioner name", "ILUT");
      p.set("schwarz: overlap level", 0);
      Teuchos::ParameterList inner;
      inner.set("fact: ilut level-of-fill", 2.0);
      inner.set("fact: drop tolerance", 0.0);
      p.set("schwarz: inner preconditioner parameters", inner);
      prec->setParameters(p);
      prec->initialize();
      prec->compute();
      return prec;
    }
    case Preconditioner::MueLu: {
      Teuchos::ParameterList p;
      p.set("verbosity", "none");
      p.set("multigrid algorithm", "sa");
      p.set("number of equations", dim);
      p.set("coarse: max size", 1000);
      // W-cycle: the coarse levels are small (operator complexity ~1.1 with the 5 x 5
      // aggregates of a p = 2 control net), so visiting them twice costs little and keeps the
      // iterations flat as levels are added (V: 12 -> 16, W: 12 -> 12 from 1.1e4 to 1.0e6 dofs
      // in the first Newton step of examples/two_blocks_scaling.yaml; solve 6.3 -> 5.2 s at 1e6)
      p.set("cycle type", "W");
      // symmetric Gauss-Seidel keeps the V-cycle symmetric positive definite (for CG);
      // Chebyshev with MueLu's default eigenvalue estimate was not, on the wheel example
      p.set("smoother: type", "RELAXATION");
      Teuchos::ParameterList sm;
      sm.set("relaxation: type", "Symmetric Gauss-Seidel");
      sm.set("relaxation: sweeps", 1);
      p.set("smoother: params", sm);
      p.set("aggregation: type", "uncoupled");
      // Aggregates never straddle two bodies, and follow the mesh's anisotropy: MueLu drops
      // graph edges by the distance Laplacian of the coordinates it is given, the control
      // points with each body moved far from the others (System::aggregation_coordinates):
      // every contact coupling is dropped, and within a body the couplings to control points
      // more than about three times further away than the nearest (graded meshes). The
      // prolongator is still smoothed with the full tangent (not the filtered one), so the
      // coarse spaces of the bodies meet through the contact stiffness. Frictionless contact
      // lets the two sides of the interface slide (and, with a penalty, separate a little):
      // aggregates across it forced the coarse space to move both sides together.
      // Measured (docs/performance.md): GMRES iterations per Newton step on
      // examples/two_blocks_scaling.yaml from 1.1e4 to 1.0e6 dofs 18 -> 36 before, 12 -> 12
      // with this and the W-cycle; examples/wheel.yaml (graded) 1758 -> 618 iterations.
      // MueLu's Kokkos factories (its default on a threaded node) have no distance-Laplacian
      // dropping for 2 equations per node ("Block filtering is not implemented" in 13.2):
      // the classic factories on every node, so that all builds aggregate alike.
      p.set("use kokkos refactor", false);
      p.set("aggregation: drop scheme", "distance laplacian");
      p.set("aggregation: drop tol", 1e-2);
      p.set("sa: use filtered matrix", false);
      // Amesos2 KLU2 is wrong on several ranks: relax on the coarse level there.
      p.set("coarse: type", ranks == 1 ? "KLU2" : "RELAXATION");
      if (ranks > 1) {
        Teuchos::ParameterList cp;
        cp.set("relaxation: type", "Symmetric Gauss-Seidel");
        cp.set("relaxation: sweeps", 4);
        p.set("coarse: params", cp);
      }
      p.set("repartition: enable", false);
      // the user's parameters (solver.linear.muelu_xml, read with the problem) last
      if (!opt.muelu_parameters.is_null()) p.setParameters(*opt.muelu_parameters);
      Teuchos::ParameterList& user = p.sublist("user data");
      user.set("Nullspace", nullspace);
      user.set("Coordinates", coords);
      return make_muelu(A, p);
    }
  }
  return Teuchos::null;
}

// Belos CG or GMRES on A x = b with the preconditioner M (null: none).
LinearSolveResult krylov_solve(const LinearOptions& opt, const RCP<Matrix>& A, const RCP<Vector>& x,
                               const RCP<Vector>& b, const RCP<Operator>& M) {
  LinearSolveResult res;
  Teuchos::TimeMonitor t(*Teuchos::TimeMonitor::getNewTimer("5) Linear solve"));
  using Problem = Belos::LinearProblem<SC, MultiVector, Operator>;
  RCP<Problem> problem = rcp(new Problem(A, x, b));
  // CG needs a symmetric operator: precondition on the left; GMRES on the right, so that
  // its residual norm is the true one
  if (!M.is_null()) {
    if (opt.method == LinearMethod::CG) problem->setLeftPrec(M);
    else problem->setRightPrec(M);
  }
  problem->setProblem();
  RCP<Teuchos::ParameterList> params = rcp(new Teuchos::ParameterList);
  params->set("Convergence Tolerance", opt.tolerance);
  params->set("Maximum Iterations", opt.max_iterations);
  params->set("Verbosity", Belos::Errors);
  Belos::SolverFactory<SC, MultiVector, Operator> factory;
  std::string name = "CG";
  if (opt.method == LinearMethod::GMRES) {
    name = "GMRES";
    params->set("Num Blocks", std::min(opt.max_iterations, 300));
  }
  auto solver = factory.create(name, params);
  solver->setProblem(problem);
  const Belos::ReturnType ret = solver->solve();
  res.iterations = solver->getNumIters();
  res.achieved_tolerance = solver->achievedTol();
  res.converged = ret == Belos::Converged;
  double explicit_rel = -1;   // the true relative residual, where it decided
  if (!res.converged) {
    // Belos also fails when only its explicit-residual check misses the tolerance (loss of
    // accuracy on ill-conditioned systems, e.g. large contact penalties). An inexact step is
    // fine inside Newton, whose own residual test decides convergence: accept a true
    // relative residual below 1e-6.
    Vector r(b->getMap());
    A->apply(*x, r);
    r.update(1.0, *b, -1.0);
    const double bn = b->norm2();
    const double rel = bn > 0 ? r.norm2() / bn : 0.0;
    explicit_rel = rel;
    if (rel <= std::max(opt.tolerance, 1e-6)) {
      res.converged = true;
      res.achieved_tolerance = rel;
    }
  }
  if (!res.converged) {
    std::ostringstream os;
    // the figure that decided: the true relative residual |b - A x| / |b| (Belos' own
    // estimate can lie below the tolerance when the implicit and explicit residuals part)
    os << "the linear solver (" << name << ") did not reach the tolerance " << opt.tolerance << " in "
       << res.iterations << " iterations (true relative residual " << explicit_rel
       << ", above the " << std::max(opt.tolerance, 1e-6) << " a Newton step accepts; Belos' estimate "
       << res.achieved_tolerance << "); the system may be singular (a body free to move?) or ill-conditioned: try "
          "solver.linear.method: direct, solver.linear.preconditioner: muelu, or more solver.linear.max_iterations";
    res.message = os.str();
  }
  return res;
}

// The factors of an earlier matrix as a preconditioner: y = alpha A_f^-1 x + beta y.
class FactorsOperator : public Operator {
 public:
  FactorsOperator(std::shared_ptr<DirectSolver> s, RCP<const Map> map) : s_(std::move(s)), map_(std::move(map)) {}
  RCP<const Map> getDomainMap() const override { return map_; }
  RCP<const Map> getRangeMap() const override { return map_; }
  void apply(const MultiVector& X, MultiVector& Y, Teuchos::ETransp = Teuchos::NO_TRANS, SC alpha = 1.0,
             SC beta = 0.0) const override {
    Vector t(map_);
    for (size_t j = 0; j < X.getNumVectors(); ++j) {
      if (!s_->apply(*X.getVector(j), t)) throw std::runtime_error("the MUMPS solve with kept factors failed");
      Y.getVectorNonConst(j)->update(alpha, t, beta);
    }
  }

 private:
  std::shared_ptr<DirectSolver> s_;
  RCP<const Map> map_;
};

constexpr int kKeptFactorsMaxIterations = 30;
// A forward and backward substitution runs at memory bandwidth, the factorisation at BLAS-3
// speed: per operation a substitution costs about 10 factorisation operations here (the
// factor that makes this count reproduce the timed rule it replaced on cattaneo_mindlin,
// cooks_membrane and whole_wheel: 14, 9, 12 factorisations against 11, 9, 10, the same
// linear-solve times to the run-to-run noise).
constexpr double kSubstitutionCost = 10;

LinearSolveResult direct_solve(const LinearOptions& opt, const RCP<Matrix>& A, const RCP<Vector>& x,
                               const RCP<Vector>& b, PreconditionerCache& cache) {
  if (!cache.direct) cache.direct = std::make_shared<DirectSolver>(A->getComm());
  DirectSolver& ds = *cache.direct;
  if (!cache.condensed.empty()) {
    // condensed onto the contact sides: factorised when A changed outside their block, and
    // every solve by the updated Schur complement
    ds.set_condensed(cache.condensed, cache.condensed_own_order);
    if (!ds.condensed_ready(*A, opt.symmetric)) {
      LinearSolveResult f = ds.factorise(*A, opt.symmetric);
      if (!f.converged && !f.singular) return f;
    }
    if (ds.condensed_ready(*A, opt.symmetric)) {
      LinearSolveResult res = ds.solve_condensed(*A, *x, *b, opt.symmetric);
      if (res.converged) return res;
    }
    // no usable Schur complement (a body held by contact alone leaves S singular), or an
    // inaccurate update: the ordinary factorisation from here on
    cache.condensed.clear();
    ds.set_condensed({});
  }
  int spent = 0;
  // the matrix of the factors (elasticity over load steps): solved directly, no GMRES
  if (ds.factorised() && ds.unchanged(*A, opt.symmetric)) return ds.solve(*A, *x, *b, opt.symmetric);
  if (opt.reuse_preconditioner && ds.factorised() && !cache.refactorise) {
    LinearOptions o = opt;
    o.method = LinearMethod::GMRES;
    o.max_iterations = std::min(opt.max_iterations, kKeptFactorsMaxIterations);
    LinearSolveResult res = krylov_solve(o, A, x, b, rcp(new FactorsOperator(cache.direct, A->getRowMap())));
    if (res.converged && res.iterations < kKeptFactorsMaxIterations) {
      // more than half a factorisation's work (a fresh factorisation also solves, and the
      // next tangent is further from the factored one): the next solve factorises. Counted
      // in operations, not read off a clock, so that a run on one rank repeats itself exactly
      // (on several, to MUMPS' parallel round-off): one
      // iteration is a forward and a backward substitution, about 4 operations per entry of
      // the factors; the factorisation's count is MUMPS' (the same on every rank).
      const double work = kSubstitutionCost * 4.0 * static_cast<double>(ds.stats().factor_entries) * res.iterations;
      cache.refactorise = work > 0.5 * ds.stats().factor_flops;
      return res;
    }
    spent = res.iterations;
    x->putScalar(0.0);
  }
  cache.refactorise = false;
  LinearSolveResult res = ds.solve(*A, *x, *b, opt.symmetric);
  res.iterations += spent;
  return res;
}

}  // namespace

LinearSolveResult solve_linear(const LinearOptions& opt, const RCP<Matrix>& A, const RCP<Vector>& x,
                               const RCP<Vector>& b, const RCP<MultiVector>& nullspace,
                               const RCP<MultiVector>& coords, PreconditionerCache* cache) {
  PreconditionerCache once;
  if (cache == nullptr) cache = &once;
  if (opt.method == LinearMethod::Direct) return direct_solve(opt, A, x, b, *cache);
  if (!opt.reuse_preconditioner) cache->clear();
  const bool kept = !cache->M.is_null();
  // control_net with contact pairs: BoomerAMG of the control nets' stiffness + K_c (some 40
  // GMRES iterations on the Hertz ball) can fail where the contact coupling dominates (the
  // first iterate of a load step with thousands of deeply penetrating points: 1,008
  // iterations without converging at 1e5 dofs); a fresh one gets
  // LinearOptions::control_net_contact_limit iterations, then the solve is taken up with
  // BoomerAMG of the tangent itself (PreconditionerCache::tangent_amg)
  const bool control_net_contact = opt.preconditioner == Preconditioner::ControlNet && !cache->contact.is_null();
  LinearOptions build = opt;
  if (control_net_contact && cache->tangent_amg) build.preconditioner = Preconditioner::BoomerAMG;
  if (!kept) {
    Teuchos::TimeMonitor t(*Teuchos::TimeMonitor::getNewTimer("4) Preconditioner setup"));
    cache->M = make_preconditioner(build, A, nullspace, coords, cache->low_order, cache->contact);
    ++cache->builds;
  }
  if (!kept && control_net_contact && !cache->tangent_amg && opt.max_iterations > opt.control_net_contact_limit) {
    LinearOptions o = opt;
    o.max_iterations = opt.control_net_contact_limit;
    LinearSolveResult res = krylov_solve(o, A, x, b, cache->M);
    if (res.converged) {
      cache->fresh_iterations = res.iterations;
      return res;
    }
    cache->tangent_amg = true;
    cache->clear();
    const int spent = res.iterations;
    res = solve_linear(opt, A, x, b, nullspace, coords, cache);
    res.iterations += spent;
    return res;
  }
  // A kept preconditioner gets the iterations a fresh one needed, 1.5 x + 5, and no more: a
  // tangent whose contact has changed much (the first contact of a load step, penalty 5e5 on
  // a block of E = 1000) can be beyond it altogether (3000 GMRES iterations without
  // converging, where a fresh one took 35: 53 of the 67 s of the 20,268-dof wheel)
  LinearOptions o = opt;
  const int kept_limit = static_cast<int>(1.5 * cache->fresh_iterations) + 5;
  if (kept) o.max_iterations = std::min(opt.max_iterations, kept_limit);
  LinearSolveResult res = krylov_solve(o, A, x, b, cache->M);
  if (!kept) {
    cache->fresh_iterations = res.iterations;
  } else if (!res.converged || res.iterations >= kept_limit) {
    // the kept preconditioner no longer fits the tangent: the next solve builds one, and an
    // unfinished solve is taken up again from where it stopped with a new one
    cache->clear();
    if (!res.converged) {
      const int spent = res.iterations;
      res = solve_linear(opt, A, x, b, nullspace, coords, cache);
      res.iterations += spent;
    }
  }
  return res;
}

}  // namespace iga
