#include "solver/newton.hpp"
#include "solver/tangent.hpp"

#include <Teuchos_TimeMonitor.hpp>
#include <Teuchos_CommHelpers.hpp>

#include <chrono>
#include <cmath>
#include <sstream>

namespace iga {

namespace {
Teuchos::Time& timer(const char* name) { return *Teuchos::TimeMonitor::getNewTimer(name); }
}  // namespace

SolveResult solve(const System& sys, const std::function<void(const IterationLog&)>& progress,
                  const std::function<void(const StepState&)>& on_step) {
  const Problem& P = sys.problem();
  SolveResult res;
  RCP<Matrix> K;
  RCP<Vector> f;
  {
    Teuchos::TimeMonitor t(timer("2) Assembly: elasticity"));
    K = sys.assemble_stiffness();
    f = sys.assemble_loads(1.0);
  }
  RCP<MultiVector> Z, X;
  if (P.linear.preconditioner == Preconditioner::MueLu && P.linear.method != LinearMethod::Direct) {
    Z = sys.rigid_body_modes();
    X = sys.aggregation_coordinates();
  }
  {
    Teuchos::TimeMonitor t(timer("3) Contact: search and assembly"));
    for (size_t k = 0; k < P.contact.size(); ++k) res.contact.emplace_back(sys, static_cast<int>(k));
  }
  bool alm = false;
  int max_aug = 1;
  for (const auto& c : P.contact)
    if (c.method == ContactMethod::KtsAlm || c.method == ContactMethod::MortarAlm) {
      alm = true;
      max_aug = std::max(max_aug, c.augmentations + 1);
    }

  TangentBuilder tangent(K);
  RCP<Vector> u = rcp(new Vector(sys.owned_map()));
  RCP<Vector> u_conv = rcp(new Vector(*u, Teuchos::Copy));
  RCP<Vector> r = rcp(new Vector(sys.owned_map()));
  RCP<Vector> du = rcp(new Vector(sys.owned_map()));

  // r = lambda f - K u - f_c(u), with the contact state updated at u
  auto residual = [&](double lambda, ContactContribution& cc) {
    {
      Teuchos::TimeMonitor t(timer("3) Contact: search and assembly"));
      for (auto& c : res.contact) c.update(*u);
      if (!res.contact.empty()) cc = assemble_contact(sys, res.contact);
    }
    K->apply(*u, *r);
    r->update(lambda, *f, -1.0);
    if (!cc.f.is_null()) r->update(-1.0, *cc.f, 1.0);
  };

  const auto t0 = std::chrono::steady_clock::now();
  // the preconditioner is built at a load step's first Newton iteration and kept while it
  // serves (linear_solver.hpp): the active set changes most when the load does
  PreconditionerCache prec;
  for (int step = 1; step <= P.load_steps; ++step) {
    const double lambda = static_cast<double>(step) / P.load_steps;
    prec.clear();
    sys.set_dirichlet(*u, lambda);
    bool step_ok = false;
    int newton_its = 0;
    double ref = 0;
    std::string why;
    for (int aug = 0; aug < max_aug && !step_ok; ++aug) {
      bool newton_ok = false;
      double increment = 1.0;  // last ||du|| / ||u|| (max norms)
      for (int it = 0; it <= P.newton.max_iterations; ++it) {
        ContactContribution cc;
        try {
          residual(lambda, cc);
        } catch (const ContactError& e) {   // e.g. the mortar segmentation of a diverging state
          why = e.what();
          break;
        }
        sys.zero_dirichlet(*r);
        const double norm = r->norm2();
        if (aug == 0 && it == 0) ref = norm;
        const double rel = ref > 0 ? norm / ref : 0.0;
        IterationLog log;
        log.step = step; log.augmentation = aug; log.iteration = it; log.lambda = lambda;
        log.residual = rel; log.active = cc.active;
        if (!std::isfinite(norm) || rel > 1e12) { why = "the residual diverged"; break; }
        // converged: the relative residual is below the tolerance, or (large penalties) the
        // residual is small and stagnates at round-off while the increment is at machine
        // precision relative to u
        const bool roundoff = it > 0 && rel < 1e-6 && increment < 1e-12;
        if (rel <= P.newton.tolerance || norm == 0.0 || roundoff) {
          log.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
          if (progress) progress(log);
          newton_ok = true;
          break;
        }
        if (it == P.newton.max_iterations) {
          std::ostringstream os;
          os << "Newton reached solver.newton.max_iterations = " << P.newton.max_iterations
             << " at relative residual " << rel;
          why = os.str();
          if (progress) progress(log);
          break;
        }
        RCP<Matrix> KT;
        {
          Teuchos::TimeMonitor t(timer("2b) Tangent: K + K_c, Dirichlet"));
          KT = tangent.build(cc.K);
          sys.apply_dirichlet(*KT);
        }
        du->putScalar(0.0);
        const LinearSolveResult lr = solve_linear(P.linear, KT, du, r, Z, X, &prec);
        res.linear_iterations += lr.iterations;
        log.linear_iterations = lr.iterations;
        log.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        if (progress) progress(log);
        if (!lr.converged) { why = lr.message; break; }
        u->update(1.0, *du, 1.0);
        const double un = u->normInf();
        increment = un > 0 ? du->normInf() / un : 0.0;
        ++newton_its;
      }
      if (!newton_ok) break;
      if (!alm) { step_ok = true; break; }
      // augmented Lagrangian: stop when the gaps are closed, else update the multipliers
      double worst = 0;
      bool gaps_ok = true;
      for (auto& c : res.contact) {
        const bool is_alm = c.pair().method == ContactMethod::KtsAlm || c.pair().method == ContactMethod::MortarAlm;
        if (!is_alm) continue;
        const double ratio = c.max_active_gap_ratio();
        worst = std::max(worst, ratio);
        if (ratio > c.pair().alm_tolerance) { gaps_ok = false; c.augment(); }
      }
      if (gaps_ok) step_ok = true;
      else if (aug + 1 == max_aug) {
        std::ostringstream os;
        os << "the augmented Lagrangian reached contact.augmentations = " << max_aug - 1
           << " with the largest gap at " << worst
           << " times the slave element size; try more contact.augmentations, a larger contact penalty (faster "
              "multiplier convergence) or a looser contact.alm_tolerance";
        why = os.str();
      }
    }
    if (!step_ok) {
      std::ostringstream os;
      os << "load step " << step << " of " << P.load_steps << " did not converge: " << why;
      if (why.find("try ") == std::string::npos)
        os << "; try more analysis.load_steps, a smaller contact penalty, or more solver.newton.max_iterations";
      res.message = os.str();
      u = u_conv;
      break;
    }
    res.newton_iterations.push_back(newton_its);
    res.steps_converged = step;
    res.lambda = lambda;
    u_conv = rcp(new Vector(*u, Teuchos::Copy));
    if (on_step) {
      // the residual at u with its constrained rows (the Newton loop zeroes them): reactions
      ContactContribution cc;
      residual(lambda, cc);
      StepState st;
      st.step = step;
      st.lambda = lambda;
      st.u = u.get();
      st.residual = r.get();
      st.contact = &res.contact;
      on_step(st);
    }
  }
  res.converged = res.steps_converged == P.load_steps;
  res.u = u_conv;
  u = u_conv;
  ContactContribution cc;
  residual(res.lambda, cc);
  res.residual = r;
  res.tangent_rebuilds = tangent.rebuilds();
  res.preconditioner_builds = prec.builds;
  return res;
}

}  // namespace iga
