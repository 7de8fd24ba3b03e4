#pragma once
// Linear solve of the (boundary-condition-eliminated) tangent system: Belos CG or GMRES
// with an Ifpack2 (RELAXATION, ILUT) or MueLu (smoothed aggregation, rigid-body modes as
// nullspace) preconditioner, or Amesos2 KLU2 on one rank.
#include <string>

#include "model/problem.hpp"
#include "solver/types.hpp"

namespace iga {

struct LinearSolveResult {
  bool converged = false;
  int iterations = 0;
  double achieved_tolerance = 0;
  std::string message;   // on failure: what happened and what to try
};

/// Solves A x = b (x is the initial guess and the result).
LinearSolveResult solve_linear(const LinearOptions& opt, const RCP<Matrix>& A, const RCP<Vector>& x,
                               const RCP<Vector>& b, const RCP<MultiVector>& nullspace,
                               const RCP<MultiVector>& coordinates);

}  // namespace iga
