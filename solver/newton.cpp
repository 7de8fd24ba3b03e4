#include "solver/newton.hpp"
#include "solver/tangent.hpp"
#include "solver/checks.hpp"
#include "model/configuration_check.hpp"

#include <Teuchos_TimeMonitor.hpp>
#include <Teuchos_CommHelpers.hpp>

#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>

namespace iga {

namespace {
Teuchos::Time& timer(const char* name) { return *Teuchos::TimeMonitor::getNewTimer(name); }
}  // namespace

// The nonlinear core (docs/architecture.md, "The nonlinear core"):
//
//   load path    pseudo-time t in [0, K] over the K stages; stage k has n_k load steps; the
//                prescribed values and loads are piecewise linear in t (System::LoadPoint)
//   increment    from the committed state at t_c to t_c + dt: Newton with line search, inside
//                the ALM multiplier updates where a pair uses them
//   commit       a converged increment: u_c <- u, contact history committed, the step handed
//                to the caller (output, summary history)
//   cut          a failed increment (no convergence, divergence, a linear solver failure or
//                exception, a contact state the discretisation cannot represent): u and the
//                contact history restored to the committed state, dt halved; after
//                solver.newton.max_cuts cuts of one load step the run stops (exit 3)
//
// Residual r(u, t) = f(t) - f_int(u) - f_c(u), tangent K_T = K(u) + K_c(u): f_int and K come
// from one element kernel for every material (System::assemble_internal); a small-strain
// linear material's K does not depend on u and is assembled once.
SolveResult solve(const System& sys, const std::function<void(const IterationLog&)>& progress,
                  const std::function<void(const StepState&)>& on_step,
                  const std::function<void(int step, const std::string& why)>& on_cut) {
  const Problem& P = sys.problem();
  const int K_stages = P.num_stages();
  SolveResult res;
  RCP<Matrix> K;
  // loads at the end of each stage are assembled when the stage starts: f(t) = (1 - s) f_prev + s f_end
  RCP<Vector> f_prev, f_end;
  {
    Teuchos::TimeMonitor t(timer("2) Assembly: elasticity"));
    K = sys.assemble_stiffness();   // K(0); refilled at every Newton iterate when it depends on u
    f_prev = rcp(new Vector(sys.owned_map()));
    f_end = sys.assemble_loads(1.0, 0);
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
  RCP<Vector> u_trial = rcp(new Vector(sys.owned_map()));
  RCP<Vector> f = rcp(new Vector(sys.owned_map()));
  RCP<Vector> f_int = rcp(new Vector(sys.owned_map()));
  const bool constant_K = sys.constant_tangent();
  // inexact Newton (solver.linear.forcing; model/problem.cpp says when auto takes it)
  const bool eisenstat_walker = eisenstat_walker_forcing(P);
  // (every ContactPairData starts committed: its state at u = 0, the friction references)

  // r = f - f_int(u) - f_c(u), with the contact state updated at u; its constrained rows (the
  // reactions, which the Newton loop zeroes for the solve) are kept in r_fixed
  std::vector<double> r_fixed;
  LoadPoint lp_now;   // the load point being solved for (follower pressures depend on it)
  auto residual = [&](const Vector& uu, ContactContribution& cc) {
    {
      Teuchos::TimeMonitor t(timer("3) Contact: search and assembly"));
      for (auto& c : res.contact) c.update(uu);
      if (!res.contact.empty()) cc = assemble_contact(sys, res.contact);
    }
    if (constant_K) {
      // small strain, linear material: f_int(u) = K u (the kernel's f_int equals it to
      // round-off, test_finite), one matrix-vector product instead of an element loop
      Teuchos::TimeMonitor t(timer("2a) Internal force"));
      K->apply(uu, *f_int);
    } else {
      sys.assemble_internal(&uu, f_int.get(), nullptr, &lp_now);
    }
    r->update(1.0, *f, -1.0, *f_int, 0.0);
    if (!cc.f.is_null()) r->update(-1.0, *cc.f, 1.0);
    r_fixed = sys.constrained_entries(*r);
  };
  auto finite = [](double x) { return std::isfinite(x); };

  const auto t0 = std::chrono::steady_clock::now();
  auto seconds = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
  PreconditionerCache prec;
  int prec_pattern = -1;   // tangent pattern the kept preconditioner was built for

  // One increment to the load point lp from the committed state: Newton (with line search)
  // inside the ALM updates. Returns "" on convergence, else why not.
  struct Outcome {
    std::string why;
    int newton_its = 0;
    bool final = false;   // no smaller increment can help (a singular tangent at the committed state)
    bool stall = false;   // the ALM multiplier updates stalled
  };
  // the residual at uu; a contact state the discretisation cannot represent fails the increment
  auto evaluate = [&](const Vector& uu, ContactContribution& cc, Outcome& out) {
    try {
      residual(uu, cc);
      return true;
    } catch (const ContactError& e) {
      out.why = e.what();
      return false;
    }
  };
  // K_T(u) = K(u) + K_c, without boundary conditions (K refilled in place where it depends on u:
  // `tangent` holds it)
  auto tangent_at = [&](const ContactContribution& cc) {
    if (!constant_K) sys.assemble_internal(u.get(), nullptr, &K, &lp_now);
    Teuchos::TimeMonitor t(timer("2b) Tangent: K + K_c, Dirichlet"));
    return tangent.build(cc.K);
  };
  // du from K_T du = r with the constrained rows and columns eliminated; false (out.why set)
  // when the linear solver threw (Trilinos' exceptions: a failed increment, not an internal error)
  auto linear_step = [&](const RCP<Matrix>& KT, LinearSolveResult& lr, Outcome& out, double tolerance) {
    {
      Teuchos::TimeMonitor t(timer("2b) Tangent: K + K_c, Dirichlet"));
      sys.apply_dirichlet(*KT);
    }
    // a preconditioner built for another sparsity pattern cannot be applied to this one
    if (tangent.rebuilds() != prec_pattern) { prec.clear(); prec_pattern = tangent.rebuilds(); }
    du->putScalar(0.0);
    try {
      LinearOptions o = P.linear;
      o.tolerance = tolerance;
      lr = solve_linear(o, KT, du, r, Z, X, &prec);
    } catch (const std::exception& e) {
      std::string what = e.what();
      while (!what.empty() && std::isspace(static_cast<unsigned char>(what.back()))) what.pop_back();
      what = what.substr(what.find_last_of('\n') + 1);
      out.why = "the linear solver failed: " + what;
      prec.clear();
      return false;
    }
    res.linear_iterations += lr.iterations;
    return true;
  };
  auto increment = [&](const LoadPoint& lp, int step, int cuts) -> Outcome {
    Outcome out;
    f->update(1.0 - lp.s, *f_prev, lp.s, *f_end, 0.0);
    lp_now = lp;
    prec.clear();
    double ref = 0;
    if (!constant_K) {
      // Predictor for a tangent that depends on u (finite strain): the prescribed increment
      // du_D enters linearised, K_T(u_c) du = r(u_c, t) - K_T(u_c) du_D on the free dofs, and
      // u = u_c + du_D + du. (Moving only the constrained dofs would put the whole increment
      // into the first layer of elements, which can fold them: a folded Saint Venant-Kirchhoff
      // element has a spurious equilibrium that Newton then converges to.)
      Vector d(*u, Teuchos::Copy);
      sys.set_dirichlet(d, lp);
      d.update(-1.0, *u, 1.0);   // du_D: zero on the free dofs
      if (d.normInf() > 0) {
        ContactContribution cc;
        if (!evaluate(*u, cc, out)) return out;
        RCP<Matrix> KT = tangent_at(cc);
        Vector Kd(sys.owned_map());
        KT->apply(d, Kd);
        r->update(-1.0, Kd, 1.0);
        sys.zero_dirichlet(*r);
        ref = r->norm2();
        LinearSolveResult lr;
        if (!linear_step(KT, lr, out, P.linear.tolerance)) return out;
        if (!lr.converged || !finite(du->normInf())) {
          out.why = !lr.converged ? lr.message : "the linear solver returned NaN or Inf";
          return out;
        }
        u->update(1.0, d, 1.0, *du, 1.0);
      }
    }
    sys.set_dirichlet(*u, lp);
    std::vector<double> gap_history;   // ALM: the gaps after each Newton solve, against their tolerances
    for (int aug = 0; aug < max_aug; ++aug) {
      bool newton_ok = false;
      double inc = 1.0;  // last ||alpha du|| / ||u|| (max norms)
      ContactContribution cc;
      if (!evaluate(*u, cc, out)) return out;
      double norm_prev = 0, eta_prev = 0;   // the Eisenstat-Walker forcing's history
      for (int it = 0; it <= P.newton.max_iterations; ++it) {
        sys.zero_dirichlet(*r);
        const double norm = r->norm2();
        if (aug == 0 && it == 0 && ref == 0) ref = norm;
        const double rel = ref > 0 ? norm / ref : 0.0;
        IterationLog log;
        log.step = step; log.augmentation = aug; log.iteration = it; log.lambda = lp.time();
        log.residual = rel; log.active = cc.active; log.cuts = cuts;
        for (const auto& c : res.contact) {
          const FrictionCounts fc = c.friction_counts();
          log.stick += fc.stick; log.slip += fc.slip; log.switches += fc.switches;
        }
        if (!finite(norm) || rel > 1e12) {
          out.why = finite(norm) ? "the residual diverged" : "the residual is not a number (NaN or Inf)";
          // a material law evaluated on a folded element (log J, J^-1) is the usual cause
          const std::string inverted = find_inverted_elements(sys, *u);
          if (!inverted.empty()) out.why += ": " + inverted;
          if (progress) progress(log);
          return out;
        }
        // converged: the relative residual is below the tolerance, or (large penalties) the
        // residual is small and stagnates at round-off while the increment is at machine
        // precision relative to u
        const bool roundoff = it > 0 && rel < 1e-6 && inc < 1e-12;
        if (rel <= P.newton.tolerance || norm == 0.0 || roundoff) {
          log.seconds = seconds();
          if (progress) progress(log);
          newton_ok = true;
          break;
        }
        if (it == P.newton.max_iterations) {
          std::ostringstream os;
          os << "Newton reached solver.newton.max_iterations = " << P.newton.max_iterations
             << " at relative residual " << rel;
          out.why = os.str();
          if (progress) progress(log);
          return out;
        }
        // The linear tolerance (relative to |r|): fixed, or the Eisenstat-Walker forcing term
        // (their choice 2, gamma = 0.9, alpha = 2, with their safeguard against a sudden
        // drop): loose while the residual falls slowly (contact active sets settling), tight
        // as Newton turns quadratic, and never tighter than the Newton tolerance asks
        // (Kelley's safeguard).
        double tol = P.linear.tolerance;
        if (eisenstat_walker) {
          constexpr double gamma = 0.9, alpha = 2.0, eta_max = 0.1;
          double eta = eta_max;
          if (it > 0 && norm_prev > 0) {
            eta = gamma * std::pow(norm / norm_prev, alpha);
            const double previous = gamma * std::pow(eta_prev, alpha);
            if (previous > 0.1) eta = std::max(eta, previous);
          }
          eta_prev = std::min(std::max(eta, 0.5 * P.newton.tolerance * ref / norm), eta_max);
          tol = std::max(tol, eta_prev);
        }
        norm_prev = norm;
        LinearSolveResult lr;
        if (!linear_step(tangent_at(cc), lr, out, tol)) return out;
        log.linear_iterations = lr.iterations;
        if (!lr.converged || !finite(du->normInf())) {
          out.why = !lr.converged ? lr.message : "the linear solver returned NaN or Inf";
          out.final = lr.singular && it == 0;
          log.seconds = seconds();
          if (progress) progress(log);
          return out;
        }
        // backtracking line search: the full step first (its residual is the next iteration's,
        // so an accepted full step costs nothing extra). A step is accepted when it decreases
        // the residual norm sufficiently (Armijo on |r|), or the energy: with the slope of the
        // potential along du, -G(alpha) = -du . r(u + alpha du) (hyperelastic bodies, penalty
        // contact), the trapezoidal estimate Pi(alpha) - Pi(0) = -alpha (G(0) + G(alpha)) / 2
        // must fall below -1e-4 alpha G(0) (Armijo on Pi): G(alpha) >= -(1 - 2e-4) G(0). A slender
        // body's Newton step often raises |r| by orders of magnitude (membrane against bending
        // stiffness) while it lowers the energy, and backtracking on |r| alone then crawls
        // (a cantilever at P L^2 / EI = 1/3 did not converge in 30 iterations; 18 now). The
        // energy test is for finite strain (a tangent that depends on u) only: with small
        // strain it let penalty-contact steps overshoot (the wheel took [11, 7] Newton
        // iterations per step against [6, 7] with the |r| test alone).
        const double G0 = du->dot(*r);
        double alpha = 1.0, best_alpha = 1.0, best_norm = -1.0, last_alpha = -1.0;
        const int max_ls = P.newton.line_search ? 6 : 0;
        for (int ls = 0; ls <= max_ls; ++ls, alpha *= 0.5) {
          u_trial->update(1.0, *u, alpha, *du, 0.0);
          try {
            residual(*u_trial, cc);
          } catch (const ContactError& e) {
            if (ls == max_ls && best_norm < 0) { out.why = e.what(); return out; }
            continue;
          }
          last_alpha = alpha;
          sys.zero_dirichlet(*r);
          const double tn = r->norm2();
          if (!finite(tn)) continue;
          if (tn <= (1.0 - 1e-4 * alpha) * norm ||                           // sufficient decrease of |r|
              (!constant_K && G0 > 0 && du->dot(*r) >= -(1.0 - 2e-4) * G0)) {                 // or of the energy
            best_alpha = alpha; best_norm = tn; break;
          }
          if (best_norm < 0 || tn < best_norm) { best_norm = tn; best_alpha = alpha; }
        }
        if (best_norm < 0) {
          out.why = "the line search found no finite residual";
          u_trial->update(1.0, *u, 1.0, *du, 0.0);
          const std::string inverted = find_inverted_elements(sys, *u_trial);
          if (!inverted.empty()) out.why += "; at the full Newton step: " + inverted;
          return out;
        }
        if (best_alpha != last_alpha) {   // the last trial was not the best: back to the best
          u_trial->update(1.0, *u, best_alpha, *du, 0.0);
          if (!evaluate(*u_trial, cc, out)) return out;
        }
        log.line_search = best_alpha;
        log.seconds = seconds();
        if (progress) progress(log);
        std::swap(u, u_trial);
        const double un = u->normInf();
        inc = un > 0 ? best_alpha * du->normInf() / un : 0.0;
        ++out.newton_its;
      }
      if (!newton_ok) return out;
      if (!alm) return out;
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
      if (gaps_ok) return out;
      // Uzawa converges linearly: at the rate of the last 5 updates, will the gaps reach the
      // tolerance within contact.augmentations? If not, the augmentations stalled (a sharp
      // corner's singular pressure, a penalty too small for the gaps asked for): say so now
      // rather than at the limit, and let the caller stop cutting a stall cuts do not cure.
      // Frictionless pairs only: with friction the stick constraints drift along the
      // stick-slip boundary for a few hundred updates, the gaps growing for a while before
      // they close (docs/friction.md), which a linear rate cannot predict.
      double q = 0;   // the gaps against their tolerances
      bool friction_alm = false;
      for (const auto& c : res.contact)
        if (c.pair().method == ContactMethod::KtsAlm || c.pair().method == ContactMethod::MortarAlm) {
          q = std::max(q, c.max_active_gap_ratio() / c.pair().alm_tolerance);
          friction_alm = friction_alm || c.friction();
        }
      gap_history.push_back(q);
      constexpr int kWindow = 5;
      const int n = static_cast<int>(gap_history.size());
      if (!friction_alm && n > kWindow && aug + 1 < max_aug) {
        const double rate = std::pow(gap_history[n - 1] / gap_history[n - 1 - kWindow], 1.0 / kWindow);
        const double needed = rate < 1 ? std::log(q) / -std::log(rate) : std::numeric_limits<double>::infinity();
        const int left = max_aug - 1 - (aug + 1);
        if (needed > left) {
          std::ostringstream os;
          os << "the augmented Lagrangian stalled: in the last " << kWindow << " multiplier updates the largest gap went from "
             << gap_history[n - 1 - kWindow] << " to " << q << " times contact.alm_tolerance (" << rate
             << " per update), so the " << left << " updates left of contact.augmentations cannot close it";
          os << "; try a penalty method, a larger contact penalty or a looser contact.alm_tolerance";
          out.why = os.str();
          out.stall = true;
          return out;
        }
      }
      if (aug + 1 == max_aug) {
        std::ostringstream os;
        os << "the augmented Lagrangian reached contact.augmentations = " << max_aug - 1
           << " with the largest gap at " << worst
           << " times the slave element size; try more contact.augmentations, a larger contact penalty (faster "
              "multiplier convergence) or a looser contact.alm_tolerance";
        out.why = os.str();
      }
    }
    return out;
  };

  double t_conv = 0.0;
  int step = 0;
  bool failed = false, stopped = false;
  for (int k = 0; k < K_stages && !failed && !stopped; ++k) {
    if (k > 0) {
      Teuchos::TimeMonitor t(timer("2) Assembly: elasticity"));
      f_prev = f_end;
      f_end = sys.assemble_loads(1.0, k);
    }
    const int n = P.stages[k];
    const double dt_nominal = 1.0 / n;
    for (int j = 1; j <= n && !failed && !stopped; ++j) {
      const double t_target = k + static_cast<double>(j) / n;
      double dt = std::min(dt_nominal, t_target - t_conv);
      int cuts = 0, stalls = 0;
      while (t_conv < t_target - 1e-12 * dt_nominal) {
        const double t_try = std::min(t_conv + dt, t_target);
        const LoadPoint lp = LoadPoint::at(t_try, K_stages);
        Outcome o = increment(lp, step + 1, cuts);
        // an ALM stall that one cut did not cure is not cured by more
        if (o.stall && ++stalls >= 2) o.final = true;
        if (o.why.empty()) {
          // commit
          ++step;
          t_conv = t_try;
          u_conv = rcp(new Vector(*u, Teuchos::Copy));
          for (auto& c : res.contact) c.commit();
          res.newton_iterations.push_back(o.newton_its);
          res.steps_converged = step;
          res.lambda = t_try;
          if (on_step) {
            // r is the residual at the converged u (its last evaluation); its constrained rows
            // back in place give the reactions
            sys.set_constrained_entries(*r, r_fixed);
            StepState st;
            st.stage = k + 1;
            st.step = step;
            st.lambda = t_try;
            st.load_factor = lp.s;
            st.cuts = cuts;
            st.u = u.get();
            st.residual = r.get();
            st.contact = &res.contact;
            std::string stop;
            st.stop = &stop;
            on_step(st);
            if (!stop.empty()) {
              res.stopped = stop;
              stopped = true;
              break;
            }
          }
          dt = std::min(2.0 * dt, dt_nominal);   // after a cut, grow back towards the nominal step
          continue;
        }
        // cut: back to the committed state, half the increment
        u = rcp(new Vector(*u_conv, Teuchos::Copy));
        for (auto& c : res.contact) c.restore();
        if (o.final || cuts + 1 > P.newton.max_cuts) {
          std::ostringstream os;
          os << "load step " << j << " of " << n;
          if (K_stages > 1) os << " in stage " << k + 1 << " of " << K_stages;
          if (o.stall)
            os << " stopped after " << cuts << " cut(s) of its increment: " << o.why;
          else if (o.final)
            os << " failed at its first iteration, which no smaller increment changes: " << o.why;
          else
            os << " did not converge after " << P.newton.max_cuts << " cuts of its increment (last at t = " << t_try
               << ", increment " << dt << "): " << o.why;
          if (!o.final && o.why.find("try ") == std::string::npos)
            os << (o.why.find("inverted elements") != std::string::npos
                       ? "; try more load steps or a finer mesh where the elements fold"
                       : P.contact.empty() ? "; try more load steps or more solver.newton.max_iterations"
                                           : "; try more load steps, a smaller contact penalty, or more solver.newton.max_iterations");
          // a penalty far above E / h is a likely cause: name it
          for (size_t c = 0; c < P.contact.size(); ++c) {
            const std::string w = penalty_warning(P, static_cast<int>(c));
            if (!w.empty()) os << "; " << w;
          }
          res.message = os.str();
          failed = true;
          break;
        }
        if (on_cut) on_cut(step + 1, o.why);
        ++res.cuts;
        ++cuts;
        dt *= 0.5;
      }
    }
  }
  res.converged = !failed;
  res.u = u_conv;
  res.tangent_rebuilds = tangent.rebuilds();
  res.preconditioner_builds = prec.builds;
  if (prec.direct) res.direct = prec.direct->stats();
  if (!failed) {
    // the last residual evaluation was at the converged u of the last step: its contact state
    // (stick and slip as the step converged) and residual are the kept ones. (Evaluating
    // again from the committed state would put the slip points at the Coulomb bound with a
    // zero slip increment, where round-off decides between stick and slip.)
    sys.set_constrained_entries(*r, r_fixed);
    res.residual = r;
    return res;
  }
  u = u_conv;
  // not converged: back to the last converged state and its residual
  for (auto& c : res.contact) c.restore();
  const LoadPoint lp = LoadPoint::at(t_conv, K_stages);
  // loads of the kept state: rebuild f at t_conv (its stage's loads may not be f_prev/f_end)
  const RCP<Vector> fa = lp.stage > 0 ? sys.assemble_loads(1.0, lp.stage - 1) : rcp(new Vector(sys.owned_map()));
  const RCP<Vector> fb = sys.assemble_loads(1.0, lp.stage);
  f->update(1.0 - lp.s, *fa, lp.s, *fb, 0.0);
  if (t_conv == 0.0) f->putScalar(0.0);
  lp_now = lp;
  ContactContribution cc;
  residual(*u, cc);
  res.residual = r;
  return res;
}

}  // namespace iga
