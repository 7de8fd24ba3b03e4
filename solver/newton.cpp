#include "solver/newton.hpp"
#include "solver/tangent.hpp"
#include "solver/checks.hpp"
#include "model/configuration_check.hpp"
#include "model/rigid_modes.hpp"

#include <Teuchos_TimeMonitor.hpp>
#include <Teuchos_CommHelpers.hpp>

#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
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
//                solver.newton.max_cuts cuts in a row (no converged increment between them),
//                or below the smallest increment dt_nominal / 2^max_cuts, the run stops (exit 3)
//   grow         after a converged increment dt doubles, up to the load step's dt_nominal
//
// Residual r(u, t) = f(t) - f_int(u) - f_c(u), tangent K_T = K(u) + K_c(u): f_int and K come
// from one element kernel for every material (System::assemble_internal); a small-strain
// linear material's K does not depend on u and is assembled once.
namespace {

// One increment's outcome: "" on convergence, else why not.
struct Outcome {
  std::string why;
  int newton_its = 0;
  bool final = false;   // no smaller increment can help (a singular tangent at the committed state)
  bool stall = false;   // the ALM multiplier updates stalled
};

bool is_alm(const ContactPair& c) { return c.method == ContactMethod::KtsAlm || c.method == ContactMethod::MortarAlm; }

// The nonlinear core's state over one solve, its seams as methods: the stage loop (run), one
// increment (increment: predictor, then Newton inside the ALM updates), one Newton solve
// (newton), its step length (line_search), the multiplier updates (augment), and the commit
// or cut of an increment (commit, cut_message).
class NewtonCore {
 public:
  NewtonCore(const System& sys, const std::function<void(const IterationLog&)>& progress,
             const std::function<void(const StepState&)>& on_step,
             const std::function<void(int step, const std::string& why)>& on_cut);
  SolveResult run();

 private:
  void residual(const Vector& uu, ContactContribution& cc);
  bool evaluate(const Vector& uu, ContactContribution& cc, Outcome& out);
  RCP<Matrix> tangent_at(const ContactContribution& cc);
  bool linear_step(const RCP<Matrix>& KT, LinearSolveResult& lr, Outcome& out, double tolerance);
  bool predictor(const LoadPoint& lp, double& ref, Outcome& out);
  double forcing(int it, double norm, double ref, double norm_prev, double& eta_prev) const;
  bool line_search(double norm, ContactContribution& cc, Outcome& out, double& alpha, bool& decrease);
  void set_geometric(double on, ContactContribution* cc = nullptr);
  bool solve_without_geometric(ContactContribution& cc, LinearSolveResult& lr, Outcome& out, double tol);
  void close_gaps(const Vector& uu, ContactContribution& cc);
  std::string held_apart() const;
  bool newton(const LoadPoint& lp, int step, int cuts, int aug, double& ref, Outcome& out);
  bool augment(int aug, std::vector<double>& gap_history, Outcome& out);
  Outcome increment(const LoadPoint& lp, int step, int cuts, double dt);
  bool commit(int stage, const LoadPoint& lp, double t, int cuts, int newton_its);
  std::string cut_message(const Outcome& o, int j, int n, int k, int cuts, double t_try, double dt) const;
  SolveResult finish(bool failed, double t_conv);

  const System& sys_;
  const Problem& P_;
  const std::function<void(const IterationLog&)>& progress_;
  const std::function<void(const StepState&)>& on_step_;
  const std::function<void(int step, const std::string& why)>& on_cut_;
  const int K_stages_;
  SolveResult res_;
  RCP<Matrix> K_;
  // loads at the end of each stage are assembled when the stage starts: f(t) = (1 - s) f_prev + s f_end
  RCP<Vector> f_prev_, f_end_;
  RCP<MultiVector> Z_, X_;
  bool alm_ = false;
  int max_aug_ = 1;
  std::unique_ptr<TangentBuilder> tangent_;
  RCP<Vector> u_, u_conv_, r_, du_, u_trial_, f_, f_int_;
  // solver.newton.extrapolate: the converged state before u_conv_ and its increment, while in
  // the same stage (null otherwise)
  RCP<Vector> u_prev_;
  double dt_prev_ = 0;
  double ref_prev_ = 0;   // the last converged increment's reference residual norm
  const bool extrapolate_ = extrapolated_start(P_);
  bool constant_K_;
  // the contact tangents' geometric part (ContactPairData::geometric): off at the start of
  // each Newton solve and after a consistent step the line search shortens below
  // simple_alpha_ (or cannot make lower |r| enough); on below simple_back_ of the increment's
  // first residual
  double geometric_ = 1;
  static constexpr double simple_alpha_ = 0.25, simple_back_ = 1e-3;
  static constexpr double kHoldFloor = 1e-3;
  double force_scale() const;   // |(f_ext, reactions)| at the last evaluation (collective)
  // inexact Newton (solver.linear.forcing; model/problem.cpp says when auto takes it)
  bool eisenstat_walker_;
  // r = f - f_int(u) - f_c(u), with the contact state updated at u; its constrained rows (the
  // reactions, which the Newton loop zeroes for the solve) are kept in r_fixed
  std::vector<double> r_fixed_;
  LoadPoint lp_now_;   // the load point being solved for (follower pressures depend on it)
  std::chrono::steady_clock::time_point t0_;
  PreconditionerCache prec_;
  ContactGraphCache contact_graph_;   // the contact graph while the couplings stay the same
  int prec_pattern_ = -1;   // tangent pattern the kept preconditioner was built for
  // the contact pairs of a body held only by contact (its supports leave a rigid-body mode:
  // force control); close_gaps holds it where none of its points is active
  std::vector<int> held_;

  double seconds() const { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count(); }
  static bool finite(double x) { return std::isfinite(x); }
};

NewtonCore::NewtonCore(const System& sys, const std::function<void(const IterationLog&)>& progress,
                       const std::function<void(const StepState&)>& on_step,
                       const std::function<void(int step, const std::string& why)>& on_cut)
    : sys_(sys), P_(sys.problem()), progress_(progress), on_step_(on_step), on_cut_(on_cut), K_stages_(P_.num_stages()) {
  {
    Teuchos::TimeMonitor t(timer("2) Assembly: elasticity"));
    K_ = sys_.assemble_stiffness();   // K(0); refilled at every Newton iterate when it depends on u
    f_prev_ = rcp(new Vector(sys_.owned_map()));
    f_end_ = sys_.assemble_loads(1.0, 0);
  }
  if (P_.linear.preconditioner == Preconditioner::ControlNet && P_.linear.method != LinearMethod::Direct) {
    Teuchos::TimeMonitor t(timer("4) Preconditioner setup"));
    prec_.low_order = sys_.control_net_stiffness();
  }
  if (P_.linear.preconditioner == Preconditioner::MueLu && P_.linear.method != LinearMethod::Direct) {
    Z_ = sys_.rigid_body_modes();
    X_ = sys_.aggregation_coordinates();
  }
  {
    Teuchos::TimeMonitor t(timer("3) Contact: search and assembly"));
    for (size_t k = 0; k < P_.contact.size(); ++k) res_.contact.emplace_back(sys_, static_cast<int>(k));
  }
  for (size_t k = 0; k < P_.contact.size(); ++k) {
    const auto free = [&](int b) { return detail::rigid_rank(P_.bodies[b]) < num_rigid_modes(P_.dim()); };
    if (free(P_.contact[k].slave.body) || free(P_.contact[k].master.body)) held_.push_back(static_cast<int>(k));
  }
  for (const auto& c : P_.contact)
    if (is_alm(c)) {
      alm_ = true;
      max_aug_ = std::max(max_aug_, c.augmentations + 1);
    }
  tangent_ = std::make_unique<TangentBuilder>(K_);
  u_ = rcp(new Vector(sys_.owned_map()));
  u_conv_ = rcp(new Vector(*u_, Teuchos::Copy));
  r_ = rcp(new Vector(sys_.owned_map()));
  du_ = rcp(new Vector(sys_.owned_map()));
  u_trial_ = rcp(new Vector(sys_.owned_map()));
  f_ = rcp(new Vector(sys_.owned_map()));
  f_int_ = rcp(new Vector(sys_.owned_map()));
  constant_K_ = sys_.constant_tangent();
  if (P_.linear.method == LinearMethod::Direct && P_.condensed_contact() && constant_K_) {
    // small strain, linear materials: the tangent changes only where K_c lives, in the rows
    // and columns of the contact sides' control points; each solve condensed onto them
    std::vector<GO> dofs;
    for (const auto& c : res_.contact) {
      const auto d = c.side_dofs();
      dofs.insert(dofs.end(), d.begin(), d.end());
    }
    std::sort(dofs.begin(), dofs.end());
    dofs.erase(std::unique(dofs.begin(), dofs.end()), dofs.end());
    if (static_cast<long long>(dofs.size()) <= LinearOptions::kCondenseMaxDofs) prec_.condensed = std::move(dofs);
    prec_.condensed_own_order = P_.dim() == 3;
  }
  eisenstat_walker_ = eisenstat_walker_forcing(P_);
  // (every ContactPairData starts committed: its state at u = 0, the friction references)
  t0_ = std::chrono::steady_clock::now();
}

void NewtonCore::residual(const Vector& uu, ContactContribution& cc) {
  {
    Teuchos::TimeMonitor t(timer("3) Contact: search and assembly"));
    {
      Teuchos::TimeMonitor t1(timer("3.1) Contact: search, segments, gaps"));
      for (auto& c : res_.contact) c.update(uu);
    }
    Teuchos::TimeMonitor t2(timer("3.2) Contact: residual and tangent"));
    if (!res_.contact.empty()) cc = assemble_contact(sys_, res_.contact, &contact_graph_);
    Kokkos::fence();
  }
  if (constant_K_) {
    // small strain, linear material: f_int(u) = K u (the kernel's f_int equals it to
    // round-off, test_finite), one matrix-vector product instead of an element loop
    Teuchos::TimeMonitor t(timer("2a) Internal force"));
    K_->apply(uu, *f_int_);
  } else {
    sys_.assemble_internal(&uu, f_int_.get(), nullptr, &lp_now_);
  }
  r_->update(1.0, *f_, -1.0, *f_int_, 0.0);
  if (!cc.f.is_null()) r_->update(-1.0, *cc.f, 1.0);
  r_fixed_ = sys_.constrained_entries(*r_);
}

// the residual at uu; a contact state the discretisation cannot represent fails the increment
bool NewtonCore::evaluate(const Vector& uu, ContactContribution& cc, Outcome& out) {
  try {
    residual(uu, cc);
    return true;
  } catch (const ContactError& e) {
    out.why = e.what();
    return false;
  }
}

// K_T(u) = K(u) + K_c, without boundary conditions (K refilled in place where it depends on u:
// `tangent_` holds it)
RCP<Matrix> NewtonCore::tangent_at(const ContactContribution& cc) {
  if (!constant_K_) sys_.assemble_internal(u_.get(), nullptr, &K_, &lp_now_);
  Teuchos::TimeMonitor t(timer("2b) Tangent: K + K_c, Dirichlet"));
  if (!prec_.low_order.is_null() && !cc.K.is_null()) {
    // control_net with contact: its BoomerAMG is built of the control nets' stiffness + K_c
    RCP<Matrix> kc = rcp(new Matrix(*cc.K, Teuchos::Copy));
    sys_.apply_dirichlet(*kc);
    prec_.contact = kc;
  }
  return tangent_->build(cc.K);
}

// du from K_T du = r with the constrained rows and columns eliminated; false (out.why set)
// when the linear solver threw (Trilinos' exceptions: a failed increment, not an internal error)
bool NewtonCore::linear_step(const RCP<Matrix>& KT, LinearSolveResult& lr, Outcome& out, double tolerance) {
  {
    Teuchos::TimeMonitor t(timer("2b) Tangent: K + K_c, Dirichlet"));
    sys_.apply_dirichlet(*KT);
  }
  // a preconditioner built for another sparsity pattern cannot be applied to this one
  if (tangent_->rebuilds() != prec_pattern_) { prec_.clear(); prec_pattern_ = tangent_->rebuilds(); }
  du_->putScalar(0.0);
  try {
    LinearOptions o = P_.linear;
    o.tolerance = tolerance;
    // a 2-D mortar pair whose master ends inside a slave element has a non-symmetric tangent
    // there (its boundary terms): L U, and GMRES for CG
    for (const auto& c : res_.contact)
      if (!c.symmetric_tangent()) {
        o.symmetric = false;
        if (o.method == LinearMethod::CG) o.method = LinearMethod::GMRES;
      }
    lr = solve_linear(o, KT, du_, r_, Z_, X_, &prec_);
  } catch (const std::exception& e) {
    std::string what = e.what();
    while (!what.empty() && std::isspace(static_cast<unsigned char>(what.back()))) what.pop_back();
    what = what.substr(what.find_last_of('\n') + 1);
    out.why = "the linear solver failed: " + what;
    prec_.clear();
    return false;
  }
  res_.linear_iterations += lr.iterations;
  return true;
}

// Predictor for a tangent that depends on u (finite strain): the prescribed increment du_D
// enters linearised, K_T(u_c) du = r(u_c, t) - K_T(u_c) du_D on the free dofs, and u = u_c +
// du_D + du. (Moving only the constrained dofs would put the whole increment into the first
// layer of elements, which can fold them: a folded Saint Venant-Kirchhoff element has a
// spurious equilibrium that Newton then converges to.) ref: the predictor's residual norm.
bool NewtonCore::predictor(const LoadPoint& lp, double& ref, Outcome& out) {
  Vector d(*u_, Teuchos::Copy);
  sys_.set_dirichlet(d, lp);
  d.update(-1.0, *u_, 1.0);   // du_D: zero on the free dofs
  if (!(d.normInf() > 0)) return true;
  ContactContribution cc;
  set_geometric(1.0);
  if (!evaluate(*u_, cc, out)) return false;
  if (cc.active == 0 && !held_.empty()) close_gaps(*u_, cc);
  RCP<Matrix> KT = tangent_at(cc);
  Vector Kd(sys_.owned_map());
  KT->apply(d, Kd);
  r_->update(-1.0, Kd, 1.0);
  sys_.zero_dirichlet(*r_);
  ref = r_->norm2();
  LinearSolveResult lr;
  if (!linear_step(KT, lr, out, P_.linear.tolerance)) return false;
  if (!lr.converged || !finite(du_->normInf())) {
    out.why = !lr.converged ? lr.message : "the linear solver returned NaN or Inf";
    return false;
  }
  u_->update(1.0, d, 1.0, *du_, 1.0);
  return true;
}

// The linear tolerance (relative to |r|): fixed, or the Eisenstat-Walker forcing term (their
// choice 2, gamma = 0.9, alpha = 2, with their safeguard against a sudden drop): loose while
// the residual falls slowly (contact active sets settling), tight as Newton turns quadratic,
// and never tighter than the Newton tolerance asks (Kelley's safeguard). eta_prev: the last
// forcing term, updated.
double NewtonCore::forcing(int it, double norm, double ref, double norm_prev, double& eta_prev) const {
  double tol = P_.linear.tolerance;
  if (eisenstat_walker_) {
    constexpr double gamma = 0.9, alpha = 2.0, eta_max = 0.1;
    double eta = eta_max;
    if (it > 0 && norm_prev > 0) {
      eta = gamma * std::pow(norm / norm_prev, alpha);
      const double previous = gamma * std::pow(eta_prev, alpha);
      if (previous > 0.1) eta = std::max(eta, previous);
    }
    eta_prev = std::min(std::max(eta, 0.5 * P_.newton.tolerance * ref / norm), eta_max);
    tol = std::max(tol, eta_prev);
  }
  return tol;
}

// Backtracking line search along du_ from u_ (residual norm `norm` there): the full step first
// (its residual is the next iteration's, so an accepted full step costs nothing extra). A
// step is accepted when it decreases the residual norm sufficiently (Armijo on |r|), or the
// energy: with the slope of the potential along du, -G(alpha) = -du . r(u + alpha du)
// (hyperelastic bodies, penalty contact), the trapezoidal estimate Pi(alpha) - Pi(0) =
// -alpha (G(0) + G(alpha)) / 2 must fall below -1e-4 alpha G(0) (Armijo on Pi): G(alpha) >=
// -(1 - 2e-4) G(0). A slender body's Newton step often raises |r| by orders of magnitude
// (membrane against bending stiffness) while it lowers the energy, and backtracking on |r|
// alone then crawls (a cantilever at P L^2 / EI = 1/3 did not converge in 30 iterations; 18
// now). The energy test is for finite strain (a tangent that depends on u) only: with small
// strain it let penalty-contact steps overshoot (the wheel took [11, 7] Newton iterations per
// step against [6, 7] with the |r| test alone). On success u_trial_ holds the accepted point,
// r_ and cc its residual and contact state, alpha the step length.
bool NewtonCore::line_search(double norm, ContactContribution& cc, Outcome& out, double& alpha_taken, bool& decrease) {
  const double G0 = du_->dot(*r_);
  decrease = false;
  double alpha = 1.0, best_alpha = 1.0, best_norm = -1.0, last_alpha = -1.0;
  const int max_ls = P_.newton.line_search ? 6 : 0;
  for (int ls = 0; ls <= max_ls; ++ls, alpha *= 0.5) {
    u_trial_->update(1.0, *u_, alpha, *du_, 0.0);
    try {
      residual(*u_trial_, cc);
    } catch (const ContactError& e) {
      if (ls == max_ls && best_norm < 0) { out.why = e.what(); return false; }
      continue;
    }
    last_alpha = alpha;
    sys_.zero_dirichlet(*r_);
    const double tn = r_->norm2();
    if (!finite(tn)) continue;
    if (tn <= (1.0 - 1e-4 * alpha) * norm ||                           // sufficient decrease of |r|
        (!constant_K_ && G0 > 0 && du_->dot(*r_) >= -(1.0 - 2e-4) * G0)) {                 // or of the energy
      best_alpha = alpha; best_norm = tn; decrease = true; break;
    }
    if (best_norm < 0 || tn < best_norm) { best_norm = tn; best_alpha = alpha; }
  }
  if (best_norm < 0) {
    out.why = "the line search found no finite residual";
    u_trial_->update(1.0, *u_, 1.0, *du_, 0.0);
    const std::string inverted = find_inverted_elements(sys_, *u_trial_);
    if (!inverted.empty()) out.why += "; at the full Newton step: " + inverted;
    return false;
  }
  if (best_alpha != last_alpha) {   // the last trial was not the best: back to the best
    u_trial_->update(1.0, *u_, best_alpha, *du_, 0.0);
    if (!evaluate(*u_trial_, cc, out)) return false;
  }
  alpha_taken = best_alpha;
  return true;
}

void NewtonCore::set_geometric(double on, ContactContribution* cc) {
  geometric_ = on;
  for (auto& c : res_.contact) c.geometric = on;
  if (cc == nullptr || res_.contact.empty()) return;
  // K_c anew at the contact state of the last evaluation (no search, no internal force: f_c
  // and so r_ come out as they were)
  Teuchos::TimeMonitor t(timer("3) Contact: search and assembly"));
  Teuchos::TimeMonitor t2(timer("3.2) Contact: residual and tangent"));
  *cc = assemble_contact(sys_, res_.contact, &contact_graph_);
  Kokkos::fence();
}

// The Newton step from u_ again with the contact tangents' geometric part off (it stays off
// for the increment until |r| < simple_back_ of its first residual): false (out.why set)
// when the contact state or the linear solver threw; lr says whether the solve converged.
bool NewtonCore::solve_without_geometric(ContactContribution& cc, LinearSolveResult& lr, Outcome& out, double tol) {
  set_geometric(0.0);
  if (!evaluate(*u_, cc, out)) return false;
  sys_.zero_dirichlet(*r_);
  return linear_step(tangent_at(cc), lr, out, tol);
}

// The size of the forces in equilibrium at the last evaluation: the external load vector and
// the reactions (the residual's constrained rows), in one 2-norm over the ranks.
double NewtonCore::force_scale() const {
  double local = 0, global = 0;
  for (double v : r_fixed_) local += v * v;
  Teuchos::reduceAll<int, double>(*sys_.comm(), Teuchos::REDUCE_SUM, 1, &local, &global);
  const double f = f_->norm2();
  return std::sqrt(global + f * f);
}

// Where no point of the pairs that hold a body is active after Newton's last iteration: the
// body (held by contact alone) and how far it still is from the other (collective), for the
// failure line. The band of close_gaps gives the first tangent the penalty stiffness of the
// points near contact, so a body that starts apart by more than about load / (penalty x
// contact length) creeps towards the other and never arrives.
std::string NewtonCore::held_apart() const {
  const int n = static_cast<int>(held_.size());
  if (n == 0) return "";
  std::vector<double> mine(n), g(n);
  for (int k = 0; k < n; ++k) mine[k] = res_.contact[held_[k]].local_min_gap();
  Teuchos::reduceAll<int, double>(*sys_.comm(), Teuchos::REDUCE_MIN, n, mine.data(), g.data());
  const auto free = [&](int b) { return detail::rigid_rank(P_.bodies[b]) < num_rigid_modes(P_.dim()); };
  const ContactPair& c = P_.contact[held_[0]];
  const bool slave_free = free(c.slave.body);
  const std::string body = P_.bodies[slave_free ? c.slave.body : c.master.body].name;
  const std::string other = P_.bodies[slave_free ? c.master.body : c.slave.body].name;
  std::ostringstream os;
  os << "body " << body << " is held by contact alone (contact[" << held_[0] << "]) and touched " << other
     << " nowhere";
  if (!std::isfinite(g[0])) {
    // no slave point has a projection on the master: the sides do not face each other here
    os << " (no slave point of contact[" << held_[0] << "] lies in front of its master: check where the bodies are)";
    return os.str();
  }
  if (g[0] >= 0)
    os << " (still " << check_number(g[0]) << " apart)";
  else   // mortar and kts_alm: a point inside while every weighted gap (a mean) is open
    os << " (a point of it " << check_number(-g[0]) << " inside " << other
       << " while no slave control point's weighted gap, a mean over its support, is closed)";
  // the load on the free body along the contact normal at its closest point (the master's
  // outward normal, pointing to the slave): where it points away from the other body no
  // contact can hold it (a wheel pulled off its block by a traction got the line below)
  {
    const ContactPointState st = res_.contact[held_[0]].state(true);   // (collective)
    size_t near = st.gap.size();
    for (size_t i = 0; i < st.gap.size(); ++i)
      if (std::isfinite(st.gap[i]) && (near == st.gap.size() || st.gap[i] < st.gap[near])) near = i;
    const int dim = P_.dim();
    const size_t fb = slave_free ? c.slave.body : c.master.body;
    double F[3] = {0, 0, 0}, Fg[3];
    auto fv = f_->getLocalViewHost(Tpetra::Access::ReadOnly);
    const auto map = f_->getMap();
    for (size_t l = 0; l < fv.extent(0); ++l) {
      const GO d = map->getGlobalElement(static_cast<LO>(l));
      if (sys_.body_of(point_of_dof(d, dim)) == fb) F[component_of_dof(d, dim)] += fv(l, 0);
    }
    Teuchos::reduceAll<int, double>(*sys_.comm(), Teuchos::REDUCE_SUM, 3, F, Fg);
    if (near < st.gap.size()) {
      const double n[3] = {st.nx[near], st.ny[near], dim == 3 ? st.nz[near] : 0.0};
      const double Fn = (Fg[0] * n[0] + Fg[1] * n[1] + Fg[2] * n[2]) * (slave_free ? 1.0 : -1.0);
      const double Fabs = std::sqrt(Fg[0] * Fg[0] + Fg[1] * Fg[1] + Fg[2] * Fg[2]);
      if (Fn > 1e-9 * Fabs && Fabs > 0) {
        os << ": its load pulls it away from " << other
           << " (the load's part along the contact normal points away), and contact only pushes; reverse the "
              "load, or support "
           << body << " by a prescribed displacement";
        return os.str();
      }
    }
  }
  os << ": it started farther from " << other
     << " than its load moves it over the contact stiffness (about load / (penalty x contact length)); start the "
        "bodies touching, bring them into contact by a prescribed displacement first, or take a smaller penalty";
  // mortar's gap of a slave control point is the mean over its support: bodies that touch at
  // one point start apart by that mean, the more so on a coarse slave (a ball on a block on
  // 8 x 8 x 4 elements, found by a problem written from the docs; KTS converges there)
  if (c.method != ContactMethod::KtsPenalty)   // (kts_alm: mortar's weighted gaps at the KTS points)
    os << " (with " << contact_method_name(c.method)
       << " the gap of a slave control point is the mean over its support, so bodies touching at one point "
          "start apart by it: refine the slave where they touch, or take kts_penalty)";
  else   // a cylinder pressed by a load onto a block it touches at one point, on 4 slave
         // elements (found by a problem written from the docs: the smaller penalty the line
         // advised then ended in the check's interpenetration, the points too sparse)
    os << " (with kts_penalty the slave's quadrature points lie off the point where bodies touch, the farther "
          "the coarser the slave: refine the slave where they touch)";
  return os.str();
}

// A body held only by contact whose pairs have no active point makes the tangent singular:
// force control, a wheel pressed by a load onto a block it touches at one point (no slave
// quadrature point there), or bodies that start a little apart (less than about load /
// (penalty x contact length), else held_apart says why it fails). For this tangent only, gaps
// up to a band count as touching: those points are active with zero pressure, so the
// tangent gets their penalty stiffness and the residual no force (the answer is unchanged);
// the solve then moves the body in by the load over that stiffness, and the next iterate's
// contact is the real one. The band is 4x the pairs' smallest gap, widened x4 until a point
// is active (at most 8 times); where none is (no projection at all), the tangent stays as it
// was and the linear solver says it is singular.
void NewtonCore::close_gaps(const Vector& uu, ContactContribution& cc) {
  const int n = static_cast<int>(held_.size());
  std::vector<double> mine(n), g(n);
  for (int k = 0; k < n; ++k) mine[k] = res_.contact[held_[k]].local_min_gap();
  Teuchos::reduceAll<int, double>(*sys_.comm(), Teuchos::REDUCE_MIN, n, mine.data(), g.data());
  Teuchos::TimeMonitor t(timer("3) Contact: search and assembly"));
  ContactContribution wide;
  for (double f = 4; f <= std::pow(4.0, 8); f *= 4) {
    bool any = false;
    for (int k = 0; k < n; ++k)
      if (finite(g[k])) {
        res_.contact[held_[k]].set_touch(f * std::max(g[k], 0.0));
        res_.contact[held_[k]].update(uu);
        any = true;
      }
    if (!any) break;
    wide = assemble_contact(sys_, res_.contact, &contact_graph_);
    if (wide.active > 0) break;
  }
  for (int k = 0; k < n; ++k) res_.contact[held_[k]].set_touch(0);   // (the next update uses it)
  if (wide.active > 0) {
    wide.active = 0;   // (the real contact has none)
    cc = wide;
  }
}

// One Newton solve at the load point lp (inside ALM update aug) from u_: true when it
// converged, false with out.why set when it failed. ref: the increment's first residual norm.
bool NewtonCore::newton(const LoadPoint& lp, int step, int cuts, int aug, double& ref, Outcome& out) {
  double inc = 1.0;  // last ||alpha du|| / ||u|| (max norms)
  ContactContribution cc;
  set_geometric(0.0);   // eps N N^T until |r| < simple_back_ of the increment's first residual
  if (!evaluate(*u_, cc, out)) return false;
  double norm_prev = 0, eta_prev = 0;   // the Eisenstat-Walker forcing's history
  for (int it = 0; it <= P_.newton.max_iterations; ++it) {
    sys_.zero_dirichlet(*r_);
    const double norm = r_->norm2();
    // the increment's reference: its first residual, but at least 1e-3 of the forces in
    // equilibrium (loads and reactions): an increment that changes nothing (a stage that holds
    // its load) starts at a round-off residual, which Newton cannot reduce by the tolerance
    // (it never converged: every held stage, linear or not, ended in cuts and exit 3)
    if (aug == 0 && it == 0 && ref == 0) ref = std::max(norm, kHoldFloor * force_scale());
    const double rel = ref > 0 ? norm / ref : 0.0;
    IterationLog log;
    log.step = step; log.augmentation = aug; log.iteration = it; log.lambda = lp.time();
    log.residual = rel; log.active = cc.active; log.cuts = cuts;
    for (const auto& c : res_.contact) {
      const FrictionCounts fc = c.friction_counts();
      log.stick += fc.stick; log.slip += fc.slip; log.switches += fc.switches;
    }
    if (!finite(norm) || rel > 1e12) {
      out.why = finite(norm) ? "the residual diverged" : "the residual is not a number (NaN or Inf)";
      // a material law evaluated on a folded element (log J, J^-1) is the usual cause
      const std::string inverted = find_inverted_elements(sys_, *u_);
      if (!inverted.empty()) out.why += ": " + inverted;
      if (progress_) progress_(log);
      return false;
    }
    // converged: the relative residual is below the tolerance, or (large penalties) the
    // residual is small and stagnates at round-off while the increment is at machine
    // precision relative to u
    const bool roundoff = it > 0 && rel < 1e-6 && inc < 1e-12;
    if (rel <= P_.newton.tolerance || norm == 0.0 || roundoff) {
      log.seconds = seconds();
      if (progress_) progress_(log);
      return true;
    }
    if (it == P_.newton.max_iterations) {
      std::ostringstream os;
      os << "Newton reached solver.newton.max_iterations = " << P_.newton.max_iterations
         << " at relative residual " << rel;
      // a body held by contact alone that never touched: smaller increments move it less
      const std::string apart = cc.active == 0 ? held_apart() : std::string();
      if (!apart.empty()) {
        os << "; " << apart;
        out.stall = true;
      }
      out.why = os.str();
      if (progress_) progress_(log);
      return false;
    }
    if (geometric_ == 0 && rel < simple_back_) set_geometric(1.0, &cc);
    const double tol = forcing(it, norm, ref, norm_prev, eta_prev);
    norm_prev = norm;
    if (cc.active == 0 && !held_.empty()) close_gaps(*u_, cc);
    // pressed: the contact tangent at u_ has a geometric part (some pair carries a force)
    bool pressed = false;
    for (const auto& c : res_.contact) pressed = pressed || c.assembled_normal_force() > 0;
    LinearSolveResult lr;
    if (!linear_step(tangent_at(cc), lr, out, tol)) return false;
    log.linear_iterations = lr.iterations;
    if (!lr.converged || !finite(du_->normInf())) {
      out.why = !lr.converged ? lr.message : "the linear solver returned NaN or Inf";
      out.final = lr.singular && it == 0;
      // a body held by contact alone that touches nothing: say which, and why
      if (cc.active == 0) {
        const std::string apart = held_apart();
        if (!apart.empty()) out.why += "; " + apart;
      }
      log.seconds = seconds();
      if (progress_) progress_(log);
      return false;
    }
    double alpha = 1.0;
    bool decrease = false;
    if (!line_search(norm, cc, out, alpha, decrease)) return false;
    if (geometric_ > 0 && !res_.contact.empty() && (!decrease || alpha < simple_alpha_)) {
      // The consistent direction was poor: far from the solution the contact tangent's
      // geometric part (-p G, with pressures many times their converged values) can make K_T
      // indefinite. The increment goes on with eps N N^T alone until |r| < 1e-3 of its first
      // residual; where this iterate's tangent had that part (a pair carried a force), its
      // direction is solved again from u_ without it.
      if (pressed) {
        if (!solve_without_geometric(cc, lr, out, tol)) return false;
        log.linear_iterations += lr.iterations;
        if (!lr.converged || !finite(du_->normInf())) {
          out.why = !lr.converged ? lr.message : "the linear solver returned NaN or Inf";
          return false;
        }
        if (!line_search(norm, cc, out, alpha, decrease)) return false;
      } else {
        set_geometric(0.0, &cc);   // the accepted point's tangent without it
      }
    }
    log.line_search = alpha;
    log.seconds = seconds();
    if (progress_) progress_(log);
    std::swap(u_, u_trial_);
    const double un = u_->normInf();
    inc = un > 0 ? alpha * du_->normInf() / un : 0.0;
    ++out.newton_its;
  }
  return false;   // not reached: the last iteration returns
}

// Augmented Lagrangian, after a converged Newton solve: true when the gaps are closed (the
// increment converged), else the multipliers are updated and false; out.why is set when the
// updates stalled or ran out (the increment failed).
bool NewtonCore::augment(int aug, std::vector<double>& gap_history, Outcome& out) {
  double worst = 0;
  bool gaps_ok = true;
  for (auto& c : res_.contact) {
    if (!is_alm(c.pair())) continue;
    const double ratio = c.max_active_gap_ratio();
    worst = std::max(worst, ratio);
    if (ratio > c.pair().alm_tolerance) { gaps_ok = false; c.augment(); }
  }
  if (gaps_ok) return true;
  // Uzawa converges linearly: at the rate of the last 5 updates, will the gaps reach the
  // tolerance within contact.augmentations? If not, the augmentations stalled (a sharp
  // corner's singular pressure, a penalty too small for the gaps asked for): say so now
  // rather than at the limit, and let the caller stop cutting a stall cuts do not cure.
  // Frictionless pairs only: with friction the stick constraints drift along the
  // stick-slip boundary for a few hundred updates, the gaps growing for a while before
  // they close (docs/friction.md), which a linear rate cannot predict.
  double q = 0;   // the gaps against their tolerances
  bool friction_alm = false;
  for (const auto& c : res_.contact)
    if (is_alm(c.pair())) {
      q = std::max(q, c.max_active_gap_ratio() / c.pair().alm_tolerance);
      friction_alm = friction_alm || c.friction();
    }
  // The method of multipliers' penalty update (Bertsekas 1982; Nocedal and Wright, 17.3):
  // where an update closed the gaps by less than kShrink, the penalty of the next solves is
  // raised by kRaise, up to kMaxRatio E / h (E the smaller modulus, times the moduli's ratio
  // up to 100, below; the top of the range configuration_check
  // advises; a larger one only worsens the tangent) or the problem file's penalty where that
  // is larger. Uzawa closes the gaps by about k / (k + eps) per update, k the stiffness behind
  // a contact point, so a penalty near E / h (the r = E / h GetFEM's Alart-Curnier takes)
  // would need hundreds of updates; the converged answer does not depend on the penalty. The
  // window of the stall test restarts. With friction too: mortar_alm's normal gaps at a flat punch's edge (a singular pressure)
  // closed by 0.88 per update at the problem file's penalty (a box pressed on a block, 50
  // updates not enough), and to 5e-12 of the element size with the raise.
  constexpr double kShrink = 0.25, kRaise = 10, kMaxRatio = 100;
  if (!gap_history.empty() && q > kShrink * gap_history.back()) {
    bool raised = false;
    for (auto& c : res_.contact) {
      if (!is_alm(c.pair())) continue;
      const double ratio = penalty_ratio(P_, c.pair());   // (in the smaller modulus' E / h)
      // the cap: kMaxRatio times the ratio of the two moduli, at most 100 (the 1e4 E / h above
      // which configuration_check warns): a stiff punch on a soft block stalled at 0.85 per
      // update at 100 E / h of the block (the stiffness behind its contact points is the
      // punch's) and converges at 1250
      const double Es = P_.bodies[c.pair().slave.body].E, Em = P_.bodies[c.pair().master.body].E;
      const double rE = std::max(Es, Em) / std::min(Es, Em);
      const double cap = kMaxRatio * (std::isfinite(rE) ? std::min(rE, 100.0) : 1.0);
      const double f = ratio > 0 ? std::min(kRaise, cap / ratio) : kRaise;
      if (f > 1 + 1e-12) {
        c.raise_penalty(f);
        raised = true;
      }
    }
    if (raised) gap_history.clear();
  }
  gap_history.push_back(q);
  constexpr int kWindow = 5;
  const int n = static_cast<int>(gap_history.size());
  // mortar_alm with friction (one stick constraint per slave control point; no rate test, as
  // above): gaps and stick slips that moved less than 10 % over the last 10 updates have
  // stalled, rather than spend the rest of contact.augmentations (a box pressed on a block
  // spent two attempts of 50 updates, 5 min, on a stick slip that sat at 5 x alm_tolerance
  // for 30 of them: its part along the normal, which the check no longer counts)
  constexpr int kFlat = 10;
  if (friction_alm && n > kFlat && aug + 1 < max_aug_ && q > 0.9 * gap_history[n - 1 - kFlat]) {
    std::ostringstream os;
    os << "the augmented Lagrangian stalled: in the last " << kFlat << " multiplier updates the largest gap or stick slip went from "
       << gap_history[n - 1 - kFlat] << " to " << q
       << " times contact.alm_tolerance (less than 10 % closer); with friction a looser contact.alm_tolerance (the stick "
          "slip is measured against it too) or mortar_penalty";
    out.why = os.str();
    out.stall = true;
    return false;
  }
  // (a window that starts at 0, an update with no active point to close, has no rate: a
  // finite-strain punch with kts_alm stopped with 'from 0 to 1.135 (inf per update)')
  if (!friction_alm && n > kWindow && aug + 1 < max_aug_ && gap_history[n - 1 - kWindow] > 0) {
    const double rate = std::pow(gap_history[n - 1] / gap_history[n - 1 - kWindow], 1.0 / kWindow);
    const double needed = rate < 1 ? std::log(q) / -std::log(rate) : std::numeric_limits<double>::infinity();
    const int left = max_aug_ - 1 - (aug + 1);
    if (needed > left) {
      std::ostringstream os;
      os << "the augmented Lagrangian stalled: in the last " << kWindow << " multiplier updates the largest gap went from "
         << gap_history[n - 1 - kWindow] << " to " << q << " times contact.alm_tolerance (" << rate
         << " per update), so the " << left << " updates left of contact.augmentations cannot close it";
      os << "; try a penalty method, a larger contact penalty or a looser contact.alm_tolerance";
      out.why = os.str();
      out.stall = true;
      return false;
    }
  }
  if (aug + 1 == max_aug_) {
    std::ostringstream os;
    os << "the augmented Lagrangian reached contact.augmentations = " << max_aug_ - 1
       << " with the largest gap at " << worst
       << " times the slave element size; try more contact.augmentations, a larger contact penalty (faster "
          "multiplier convergence) or a looser contact.alm_tolerance";
    // the limit counts as a stall (two in a load step end the run: the cuts between them did
    // not help, and each costs contact.augmentations solves). With friction the stall test
    // above is off, so the limit is where a stall shows; without, the rate test needs more
    // than kWindow updates since the last penalty raise, so a small contact.augmentations
    // reaches the limit first: with 2 the two-block press was cut into 256 increments, each
    // a state written (a helper's problem wrote 932 MB in 215 cuts), where it now stops
    // after one cut with this line.
    out.stall = true;
    out.why = os.str();
  }
  return false;
}

// One increment to the load point lp from the committed state: Newton (with line search)
// inside the ALM updates. Outcome::why is "" on convergence, else why not.
Outcome NewtonCore::increment(const LoadPoint& lp, int step, int cuts, double dt) {
  Outcome out;
  f_->update(1.0 - lp.s, *f_prev_, lp.s, *f_end_, 0.0);
  lp_now_ = lp;
  // A preconditioner of the tangent itself (BoomerAMG, MueLu, ILUT, relaxation) is kept from the
  // last converged increment: the tangent at this increment's first iterate is that increment's
  // last (small strain: the same active set), and PreconditionerCache's budget rebuilds it where
  // it no longer serves. Rebuilt after a cut, and for the control nets' preconditioner, whose
  // fresh build at each increment was measured cheaper (docs/performance.md, "A preconditioner
  // kept across load steps"); each increment tries the control nets' preconditioner first.
  if (cuts > 0 || prec_.tangent_amg || P_.linear.preconditioner == Preconditioner::ControlNet) prec_.clear();
  prec_.tangent_amg = false;
  double ref = 0;
  // the first iterate: the last increment continued (solver.newton.extrapolate; not on a
  // retry after a cut, nor at a stage's first increment), else the linearised predictor where
  // the tangent depends on u. The convergence test is relative to the increment's first
  // residual, which from a continued start is small: its reference is then the last
  // increment's, scaled by the increment (a plain start's residual grows with the increment).
  const bool extrapolate = extrapolate_ && !u_prev_.is_null() && cuts == 0 && dt_prev_ > 0 && ref_prev_ > 0;
  if (extrapolate) {
    const double a = dt / dt_prev_;
    u_->update(-a, *u_prev_, 1.0 + a);
    ref = ref_prev_ * a;
  } else if (!constant_K_ && !predictor(lp, ref, out)) {
    return out;
  }
  sys_.set_dirichlet(*u_, lp);
  std::vector<double> gap_history;   // ALM: the gaps after each Newton solve, against their tolerances
  for (int aug = 0; aug < max_aug_; ++aug) {
    if (!newton(lp, step, cuts, aug, ref, out)) return out;
    ref_prev_ = ref;
    if (!alm_) return out;
    if (augment(aug, gap_history, out) || !out.why.empty()) return out;
  }
  return out;
}

// A converged increment to t (load point lp, stage index `stage`): u_c <- u, the contact
// history committed, the step handed to the caller; false when the caller stopped the run.
bool NewtonCore::commit(int stage, const LoadPoint& lp, double t, int cuts, int newton_its) {
  u_conv_ = rcp(new Vector(*u_, Teuchos::Copy));
  for (auto& c : res_.contact) c.commit();
  res_.newton_iterations.push_back(newton_its);
  ++res_.steps_converged;
  res_.lambda = t;
  if (!on_step_) return true;
  // r is the residual at the converged u (its last evaluation); its constrained rows back in
  // place give the reactions
  sys_.set_constrained_entries(*r_, r_fixed_);
  StepState st;
  st.stage = stage + 1;
  st.step = res_.steps_converged;
  st.lambda = t;
  st.load_factor = lp.s;
  st.cuts = cuts;
  st.u = u_.get();
  st.residual = r_.get();
  st.contact = &res_.contact;
  std::string stop;
  st.stop = &stop;
  on_step_(st);
  if (stop.empty()) return true;
  res_.stopped = stop;
  return false;
}

// Why the run stops at load step j of n in stage k (0-based) after `cuts` cuts.
std::string NewtonCore::cut_message(const Outcome& o, int j, int n, int k, int cuts, double t_try, double dt) const {
  std::ostringstream os;
  os << "load step " << j << " of " << n;
  if (K_stages_ > 1) os << " in stage " << k + 1 << " of " << K_stages_;
  if (o.stall)
    os << " stopped after " << cuts << " cut(s) of its increment: " << o.why;
  else if (o.final)
    os << " failed at its first iteration, which no smaller increment changes: " << o.why;
  else
    os << " did not converge after " << cuts << " cuts of its increment in a row (last at t = " << t_try
       << ", increment " << dt << "): " << o.why;
  if (!o.final && o.why.find("try ") == std::string::npos)
    os << (o.why.find("inverted elements") != std::string::npos
               ? "; try more load steps or a finer mesh where the elements fold"
               : P_.contact.empty() ? "; try more load steps or more solver.newton.max_iterations"
                                    : "; try more load steps, a smaller contact penalty, or more solver.newton.max_iterations");
  // a penalty far above E / h is a likely cause: name it
  for (size_t c = 0; c < P_.contact.size(); ++c) {
    const std::string w = penalty_warning(P_, static_cast<int>(c));
    if (!w.empty()) os << "; " << w;
  }
  // so are moduli far apart across a pair: a neo-Hookean block (E = 1) slid over a base of
  // E = 1e9 stalled at relative residual 1e-3 (round-off of the stiff body in the tangent),
  // where E = 1e8 converged in 3 iterations a step (found by a problem written from the docs)
  for (const ContactPair& c : P_.contact) {
    const Body &a = P_.bodies[c.slave.body], &b = P_.bodies[c.master.body];
    const double r = std::max(a.E, b.E) / std::min(a.E, b.E);
    if (!(r > 1e6)) continue;
    const Body& stiff = a.E > b.E ? a : b;
    const Body& soft = a.E > b.E ? b : a;
    std::ostringstream m;
    m.precision(2);
    m << "; " << stiff.name << "'s Young's modulus is " << r << " times " << soft.name
      << "'s: give it 1e3-1e4 times (it stays rigid to within that) so that round-off does not swamp the tangent";
    os << m.str();
    break;
  }
  return os.str();
}

// The load path: stages, their load steps, each step's increments (cut and grown back).
SolveResult NewtonCore::run() {
  double t_conv = 0.0;
  bool failed = false, stopped = false;
  for (int k = 0; k < K_stages_ && !failed && !stopped; ++k) {
    if (k > 0) {
      Teuchos::TimeMonitor t(timer("2) Assembly: elasticity"));
      f_prev_ = f_end_;
      f_end_ = sys_.assemble_loads(1.0, k);
    }
    const int n = P_.stages[k];
    const double dt_nominal = 1.0 / n;
    u_prev_ = Teuchos::null;   // a new stage: no increment of it to continue yet
    RCP<Vector> u_keep;
    for (int j = 1; j <= n && !failed && !stopped; ++j) {
      const double t_target = k + static_cast<double>(j) / n;
      double dt = std::min(dt_nominal, t_target - t_conv);
      // cuts: in this load step (the progress table's column, StepState::cuts); row: since the
      // last converged increment, the limit's count (a stage given as one load step may need
      // many increments, each cut once where the doubled increment fails: each converged
      // increment restarts the count, the smallest increment bounds the run)
      int cuts = 0, row = 0, stalls = 0;
      const double dt_min = std::ldexp(dt_nominal, -P_.newton.max_cuts) * (1.0 - 1e-12);
      // a folded state Newton converged to from t_conv (its t), and whether it is now taken
      double fold_to = -1;
      bool take_fold = false;
      while (t_conv < t_target - 1e-12 * dt_nominal) {
        const double t_try = take_fold ? fold_to : std::min(t_conv + dt, t_target);
        const LoadPoint lp = LoadPoint::at(t_try, K_stages_);
        if (extrapolate_) u_keep = u_conv_;   // (commit replaces u_conv_, never writes into it)
        Outcome o = increment(lp, res_.steps_converged + 1, cuts, t_try - t_conv);
        // at finite strain Newton can converge to a folded state (det F <= 0 somewhere: no
        // hyperelastic law admits it; an ironing stage slid in one increment does this): that
        // is a failed increment, cut like one, so a smaller increment can follow the physical
        // branch (the check after the step would otherwise stop the run there). Where the cuts
        // do not avoid it (a body that passes into itself without a self-contact pair folds
        // whatever the increment), the folded state is taken after all, and the checks after
        // the step name the fold and its cause (exit 5)
        if (o.why.empty() && P_.kinematics == Kinematics::Finite && !take_fold) {
          const std::string inverted = find_inverted_elements(sys_, *u_);
          if (!inverted.empty()) {
            o.why = "Newton converged to a state with inverted elements: " + inverted;
            fold_to = t_try;
          }
        }
        // an ALM stall that one cut did not cure is not cured by more
        if (o.stall && ++stalls >= 2) o.final = true;
        if (o.why.empty()) {
          if (extrapolate_) {   // this increment, for the next one's first iterate
            u_prev_ = u_keep;
            dt_prev_ = t_try - t_conv;
          }
          t_conv = t_try;
          row = 0;
          fold_to = -1;
          take_fold = false;
          if (!commit(k, lp, t_try, cuts, o.newton_its)) {
            stopped = true;
            break;
          }
          dt = std::min(2.0 * dt, dt_nominal);   // after a cut, grow back towards the nominal step
          continue;
        }
        // cut: back to the committed state, half the increment
        u_ = rcp(new Vector(*u_conv_, Teuchos::Copy));
        for (auto& c : res_.contact) c.restore();
        if (o.final || row + 1 > P_.newton.max_cuts || 0.5 * dt < dt_min) {
          if (fold_to > 0 && !take_fold) {   // back to the folded state, for the checks to name
            take_fold = true;
            continue;
          }
          res_.message = cut_message(o, j, n, k, row, t_try, dt);
          failed = true;
          break;
        }
        if (on_cut_) on_cut_(res_.steps_converged + 1, o.why);
        ++res_.cuts;
        ++cuts;
        ++row;
        dt *= 0.5;
      }
    }
  }
  return finish(failed, t_conv);
}

SolveResult NewtonCore::finish(bool failed, double t_conv) {
  res_.converged = !failed;
  res_.u = u_conv_;
  res_.tangent_rebuilds = tangent_->rebuilds();
  res_.preconditioner_builds = prec_.builds;
  if (prec_.direct) res_.direct = prec_.direct->stats();
  if (!failed) {
    // the last residual evaluation was at the converged u of the last step: its contact state
    // (stick and slip as the step converged) and residual are the kept ones. (Evaluating
    // again from the committed state would put the slip points at the Coulomb bound with a
    // zero slip increment, where round-off decides between stick and slip.)
    sys_.set_constrained_entries(*r_, r_fixed_);
    res_.residual = r_;
    return res_;
  }
  u_ = u_conv_;
  // not converged: back to the last converged state and its residual
  for (auto& c : res_.contact) c.restore();
  const LoadPoint lp = LoadPoint::at(t_conv, K_stages_);
  // loads of the kept state: rebuild f at t_conv (its stage's loads may not be f_prev/f_end)
  const RCP<Vector> fa = lp.stage > 0 ? sys_.assemble_loads(1.0, lp.stage - 1) : rcp(new Vector(sys_.owned_map()));
  const RCP<Vector> fb = sys_.assemble_loads(1.0, lp.stage);
  f_->update(1.0 - lp.s, *fa, lp.s, *fb, 0.0);
  if (t_conv == 0.0) f_->putScalar(0.0);
  lp_now_ = lp;
  ContactContribution cc;
  residual(*u_, cc);
  res_.residual = r_;
  return res_;
}

}  // namespace

SolveResult solve(const System& sys, const std::function<void(const IterationLog&)>& progress,
                  const std::function<void(const StepState&)>& on_step,
                  const std::function<void(int step, const std::string& why)>& on_cut) {
  return NewtonCore(sys, progress, on_step, on_cut).run();
}

}  // namespace iga
