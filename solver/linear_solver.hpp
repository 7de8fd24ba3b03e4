#pragma once
// Linear solve of the (boundary-condition-eliminated) tangent system: Belos CG or GMRES
// with an Ifpack2 (RELAXATION, ILUT) or MueLu (smoothed aggregation, rigid-body modes as
// nullspace) preconditioner, or the sparse direct solver MUMPS (solver/direct_solver.hpp) on
// any number of ranks.
#include <memory>
#include <string>
#include <vector>

#include "model/problem.hpp"
#include "solver/direct_solver.hpp"
#include "solver/types.hpp"

namespace iga {

struct LinearSolveResult {
  bool converged = false;
  int iterations = 0;
  double achieved_tolerance = 0;
  std::string message;   // on failure: what happened and what to try
  bool singular = false;  // the direct solver found the matrix singular
};

/// A preconditioner kept from one solve to the next (Newton iterations of a load step): the
/// tangent changes little once the active set has settled, and a preconditioner of the
/// previous tangent still serves (the Krylov solver works with the current one, so the
/// solution is the same). solve_linear rebuilds it when a solve with the kept one fails or
/// needs more than 1.5 x (+ 5) the iterations of the solve it was built for.
struct PreconditionerCache {
  RCP<Tpetra::Operator<SC, LO, GO, Node>> M;
  int fresh_iterations = 0;   // iterations of the solve M was built for
  int builds = 0;             // preconditioners built (all solves)
  /// the direct solver, kept over the whole run (its analysis serves every solve with the
  /// same sparsity pattern, its factors precondition GMRES on the tangents that follow);
  /// clear() leaves it alone
  std::shared_ptr<DirectSolver> direct;
  bool refactorise = false;   // the last solve with kept factors cost more than a factorisation
  /// solver.linear.preconditioner: control_net: the matrix BoomerAMG is built of (the control
  /// nets' degree-1 stiffness, Dirichlet rows eliminated; set by the caller, kept by clear())
  RCP<Matrix> low_order;
  /// control_net with contact pairs: K_c at the iterate being solved, Dirichlet rows and
  /// columns eliminated (set by the caller before each solve); BoomerAMG is then built of
  /// low_order + contact, so that the bodies' coupling through contact is in it
  RCP<const Matrix> contact;
  /// control_net with contact: a fresh one failed to reach the tolerance within
  /// LinearOptions::control_net_contact_limit iterations, so BoomerAMG of the tangent itself is built instead
  /// (until the caller resets it: the Newton core at each increment; clear() keeps it)
  bool tangent_amg = false;
  /// direct: the dofs a condensed solve keeps (DirectSolver::set_condensed; set by the caller:
  /// the contact sides' dofs at small strain), empty for none; cleared here for the rest of the
  /// run when the condensed factorisation fails (a singular interior block or Schur complement:
  /// a body held by contact alone), the ordinary factorisation then serving
  std::vector<GO> condensed;
  bool condensed_own_order = false;   // DirectSolver::set_condensed's own_order (3-D)
  void clear() { M = Teuchos::null; }
};

/// Solves A x = b (x is the initial guess and the result). With a cache (and
/// opt.reuse_preconditioner), its preconditioner is used if it has one, else built and kept.
LinearSolveResult solve_linear(const LinearOptions& opt, const RCP<Matrix>& A, const RCP<Vector>& x,
                               const RCP<Vector>& b, const RCP<MultiVector>& nullspace,
                               const RCP<MultiVector>& coordinates, PreconditionerCache* cache = nullptr);

}  // namespace iga
