#pragma once
// The nonlinear core: load path over stages, Newton-Raphson with a backtracking line search,
// automatic cutting of failed load increments, contact history committed at converged steps
// (newton.cpp says how). The contact active set is re-evaluated every iteration; augmented
// Lagrangian methods wrap the Newton solve in multiplier updates.
#include <functional>
#include <string>
#include <vector>

#include "solver/contact.hpp"
#include "solver/direct_solver.hpp"
#include "solver/linear_solver.hpp"
#include "solver/system.hpp"

namespace iga {

struct IterationLog {
  int step = 0, augmentation = 0, iteration = 0;
  double lambda = 0, residual = 0;   // residual relative to the step's first residual
  int active = 0, linear_iterations = 0;
  int stick = 0, slip = 0, switches = 0;   // friction: points in stick, in slip, that changed state
  int cuts = 0;               // cuts of this load step's increment so far
  double line_search = 1.0;   // step length the line search took (1: the full Newton step)
  double seconds = 0;
};

struct SolveResult {
  bool converged = false;
  std::string message;                     // why it stopped, and what to try
  std::vector<int> newton_iterations;      // per converged load step
  int linear_iterations = 0;               // total
  int steps_converged = 0;
  int cuts = 0;                            // failed increments retried with half the step
  int tangent_rebuilds = 0;                // times K_T's pattern was built (tangent.hpp)
  int preconditioner_builds = 0;           // preconditioners built (kept over Newton iterations)
  DirectSolverStats direct;                // the direct solver's analyses, factorisations, memory
  double lambda = 0;                       // load path time t of the kept (last converged) state
  RCP<Vector> u;                           // displacement of the kept state
  RCP<Vector> residual;                    // lambda f - K u - f_c at u (reactions: minus it)
  std::vector<ContactPairData> contact;    // contact state at u
  /// Set where the caller stopped the run after a converged step (StepState::stop): why (a
  /// physical check failed); converged stays true for the steps that were solved.
  std::string stopped;
};

/// The state at a converged load step, handed to the caller before the next step starts
/// (output of the time series, the summary's history). Valid only during the call.
struct StepState {
  int stage = 1;              // load stage, 1-based
  int step = 0;               // converged load steps so far (all stages, cuts included), 1-based
  double lambda = 0;          // load path time t in (0, K]: stage - 1 + load_factor
  double load_factor = 0;     // fraction of the stage
  int cuts = 0;               // cuts this step needed
  const Vector* u = nullptr;
  const Vector* residual = nullptr;               // lambda f - K u - f_c at u (reactions: minus it)
  const std::vector<ContactPairData>* contact = nullptr;   // contact state at u
  /// The caller may stop the run here: a non-empty *stop (the same on every rank) ends the
  /// load path after this step (SolveResult::stopped).
  std::string* stop = nullptr;
};

/// progress: after every Newton iteration; on_step: at every converged load step; on_cut: when
/// an increment fails and is cut (the load step, and why it failed).
SolveResult solve(const System& sys, const std::function<void(const IterationLog&)>& progress = {},
                  const std::function<void(const StepState&)>& on_step = {},
                  const std::function<void(int step, const std::string& why)>& on_cut = {});

}  // namespace iga
