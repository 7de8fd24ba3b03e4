#include "solver/contact.hpp"
#include "solver/contact_internal.hpp"
#include "kernels/numbering.hpp"

static_assert(iga::kMaxContactQuadrature <= iga::kMaxGauss, "contact quadrature beyond the Gauss table");

#include <Teuchos_CommHelpers.hpp>
#include <Teuchos_LAPACK.hpp>
#include <Teuchos_TimeMonitor.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace iga {

using namespace contact_detail;
using system_detail::to_device;

ContactPairData::ContactPairData(const System& sys, int index)
    : pair_(sys.problem().contact[index]), index_(index), penalty0_(pair_.penalty) {
  thickness = sys.problem().thickness;
  rank_ = sys.comm()->getRank();
  nranks_ = sys.comm()->getSize();
  if (sys.dim() == 3) {   // faces of solids: contact3d.cpp
    thickness = 1;
    force_ = ForceSum("contact_force");
    s3_ = std::make_shared<ContactSurfaces3>(sys, pair_);
    h_min_ = s3_->h_min();
    commit();
    return;
  }
  slave_chain_ = surface_chain(sys.problem(), pair_.slave);
  slave = make_curve(sys, pair_.slave, slave_chain_, slave_gid);
  master = make_curve(sys, pair_.master, surface_chain(sys.problem(), pair_.master), master_gid);
  // kts_alm runs on mortar's weighted gaps and multipliers per slave control point, at the
  // KTS points (one segment per slave element: element-based integration, no cuts at the
  // master knots' images); kts_penalty keeps its penalty per point
  mortar_ = pair_.method != ContactMethod::KtsPenalty;
  segmented_ = pair_.method != ContactMethod::KtsAlm;
  const Curve& c = slave_chain_.curve;
  h_min_ = 1e300;
  for (int s : c.element_spans()) {
    const double a = c.knots[s], b = c.knots[s + 1];
    h_min_ = std::min(h_min_, std::hypot(c.eval(b)[0] - c.eval(a)[0], c.eval(b)[1] - c.eval(a)[1]));
  }
  force_ = ForceSum("contact_force");
  int n = 0;
  if (!mortar_) {
    // slave quadrature points in the reference configuration
    const int nq = pair_.quadrature_points > 0 ? pair_.quadrature_points : 2 * (c.degree + 1);
    kts_points_per_element_ = nq;
    const GaussRule g = gauss_rule(nq);
    std::vector<double> xi, wt;
    std::vector<int> span;
    for (int s : c.element_spans()) {
      const double a = c.knots[s], b = c.knots[s + 1], h = 0.5 * (b - a);
      for (int q = 0; q < nq; ++q) {
        const double u = a + h * (g.x[q] + 1.0);
        const auto t = c.derivative(u);
        const double jac = std::hypot(t[0], t[1]);
        xi.push_back(u);
        wt.push_back(g.w[q] * h * jac * thickness);
        span.push_back(s);
      }
    }
    n = static_cast<int>(xi.size());
    sp_.xi = to_device("xi", xi);
    sp_.weight = to_device("weight", wt);
    sp_.span = to_device("span", span);
  } else {
    // segment quadrature slots (filled by MortarSegments at each update) and, per slave
    // control point, w_A = int R_A dGamma_0 (thickness included). kts_alm: the KTS rule,
    // 2 (p + 1) points on each whole slave element
    const int nq = pair_.quadrature_points > 0 ? pair_.quadrature_points
                   : segmented_                ? std::min(slave.p + master.p + 1, kMaxGauss)
                                               : std::min(2 * (slave.p + 1), kMaxGauss);
    gauss_ = gauss_rule(nq);
    max_segments_ = segmented_ ? kMortarInitialSegments : 1;
    if (!segmented_) kts_points_per_element_ = nq;
    slots = max_segments_ * nq;
    n = slave.ne * slots;
    const GaussRule g = gauss_rule(kMaxGauss);
    auto hX = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), slave.X);
    auto hw = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), slave.w);
    auto hU = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), slave.U);
    std::vector<double> wA(slave.nb, 0.0);
    for (int s : c.element_spans()) {
      const double a = c.knots[s], b = c.knots[s + 1], h = 0.5 * (b - a);
      for (int q = 0; q < g.n; ++q) {
        double R[3][kMaxBasis1D], X[2], dX[2], ddX[2];
        const int sp = curve_eval(slave.nb, slave.p, hU.data(), hX, hw, a + h * (g.x[q] + 1.0), X, dX, ddX, R);
        for (int k = 0; k <= slave.p; ++k) wA[sp - slave.p + k] += R[0][k] * g.w[q] * h * std::hypot(dX[0], dX[1]) * thickness;
      }
    }
    ms_.wA = to_device("wA", wA);
    ms_.gA = Kokkos::View<double*, MemSpace>("gA", slave.nb);
    ms_.lbar = Kokkos::View<double*, MemSpace>("lbar", slave.nb);
    ms_.lambda = Kokkos::View<double*, MemSpace>("lambdaA", slave.nb);
    ms_.active = Kokkos::View<int*, MemSpace>("activeA", slave.nb);
    ms_.covered = Kokkos::View<int*, MemSpace>("coveredA", slave.nb);
    ms_.cwA = Kokkos::View<double*, MemSpace>("coveredWeightA", slave.nb);
    if (pair_.method != ContactMethod::MortarPenalty) {   // ALM: the penalty per control point
      ms_.scale = Kokkos::View<double*, MemSpace>("scaleA", slave.nb);
      Kokkos::deep_copy(ms_.scale, 1.0);
    }
    ms_.flags = Kokkos::View<int*, MemSpace>("flags", 2);
    ends_.xi = Kokkos::View<double**, Kokkos::LayoutRight, MemSpace>("mortar_end_xi", slave.ne, 2);
    ends_.eta = Kokkos::View<double**, Kokkos::LayoutRight, MemSpace>("mortar_end_eta", slave.ne, 2);
    ends_.sign = Kokkos::View<int**, Kokkos::LayoutRight, MemSpace>("mortar_end_sign", slave.ne, 2);
    ends_.mspan = Kokkos::View<int**, Kokkos::LayoutRight, MemSpace>("mortar_end_mspan", slave.ne, 2);
    const auto ra = block_range(slave.nb, sys.comm()->getRank(), sys.comm()->getSize());
    a_begin = static_cast<int>(ra.first);
    a_end = static_cast<int>(ra.second);
  }
  allocate_points(n);
  // KTS: a gap within round-off of 0 is touching (mortar: MortarGaps' touch, the same 1e-12)
  sp_.touch = 1e-12 * h_min_;
  // every rank holds the displacements of both curves (boundary-sized)
  std::vector<GO> cps(slave_gid);
  cps.insert(cps.end(), master_gid.begin(), master_gid.end());
  std::sort(cps.begin(), cps.end());
  cps.erase(std::unique(cps.begin(), cps.end()), cps.end());
  replicated_ = sys.cp_dof_map(cps);
  importer_ = rcp(new Import(sys.owned_map(), replicated_));
  for (int which = 0; which < 2; ++which) {
    const auto& gid = which == 0 ? slave_gid : master_gid;
    Kokkos::View<int* [2], MemSpace> rep("replicated_lid", gid.size());
    auto h = Kokkos::create_mirror_view(rep);
    for (size_t k = 0; k < gid.size(); ++k)
      for (int d = 0; d < 2; ++d) h(k, d) = replicated_->getLocalElement(dof_of(gid[k], d, sys.dim()));
    Kokkos::deep_copy(rep, h);
    (which == 0 ? slave_rep_ : master_rep_) = rep;
  }
  // friction
  fr_.mu = pair_.friction;
  fr_.epsT = pair_.tangential_penalty > 0 ? pair_.tangential_penalty : pair_.penalty;
  if (mortar_) {
    const int nb = slave.nb;
    fr_.sA = Kokkos::View<double*, MemSpace>("sA", nb);
    fr_.tauA = Kokkos::View<double*, MemSpace>("tauA", nb);
    fr_.slipA = Kokkos::View<double*, MemSpace>("slipA", nb);
    fr_.slipA_c = Kokkos::View<double*, MemSpace>("slipA_c", nb);
    fr_.lamTA = Kokkos::View<double*, MemSpace>("lamTA", nb);
    fr_.stateA = Kokkos::View<int*, MemSpace>("stateA", nb);
    // the committed configuration: curves with their own displacement views, and the
    // reference projections of the slots (sharing the slots' parameters and weights)
    slave_c_ = slave;
    master_c_ = master;
    slave_c_.u = Kokkos::View<double* [2], MemSpace>("u_committed", slave.nb);
    master_c_.u = Kokkos::View<double* [2], MemSpace>("u_committed", master.nb);
    mortar_scratch(kMortarInitialEntries);
  }
  // the state in the reference configuration (u = 0) is the first committed one: the
  // reference projections of friction start there
  refresh();
  commit();
}

void ContactPairData::allocate_points(int n) {
  if (mortar_) {
    sp_.xi = Kokkos::View<double*, MemSpace>("xi", n);
    sp_.weight = Kokkos::View<double*, MemSpace>("weight", n);
    sp_.span = Kokkos::View<int*, MemSpace>("span", n);
    Kokkos::deep_copy(sp_.span, -1);
    cuts_ = Kokkos::View<double**, Kokkos::LayoutRight, MemSpace>("mortar_cuts", slave.ne, max_segments_ + 1);
  }
  sp_.valid = Kokkos::View<int*, MemSpace>("valid", n);
  sp_.mspan = Kokkos::View<int*, MemSpace>("mspan", n);
  sp_.melem = Kokkos::View<int*, MemSpace>("melem", n);
  Kokkos::deep_copy(sp_.melem, -1);
  sp_.mxi = Kokkos::View<double*, MemSpace>("mxi", n);
  sp_.gap = Kokkos::View<double*, MemSpace>("gap", n);
  sp_.pressure = Kokkos::View<double*, MemSpace>("pressure", n);
  sp_.x = Kokkos::View<double* [2], MemSpace>("x", n);
  sp_.normal = Kokkos::View<double* [2], MemSpace>("normal", n);
  const auto r = block_range(n, rank_, nranks_);
  p_begin = static_cast<int>(r.first);
  p_end = static_cast<int>(r.second);
  fr_.ref_valid = Kokkos::View<int*, MemSpace>("ref_valid", n);
  fr_.ref_mxi = Kokkos::View<double*, MemSpace>("ref_mxi", n);
  fr_.ds = Kokkos::View<double*, MemSpace>("ds", n);
  fr_.tau = Kokkos::View<double*, MemSpace>("tau", n);
  fr_.slip = Kokkos::View<double*, MemSpace>("slip", n);
  fr_.slip_c = Kokkos::View<double*, MemSpace>("slip_c", n);
  fr_.lamT = Kokkos::View<double*, MemSpace>("lamT", n);
  fr_.state = Kokkos::View<int*, MemSpace>("state", n);
  fr_.tangent = Kokkos::View<double* [2], MemSpace>("tangent", n);
  state_prev_ = Kokkos::View<int*, MemSpace>("state_prev", n);
  if (mortar_) {
    ref_sp_ = sp_;
    ref_sp_.mspan = Kokkos::View<int*, MemSpace>("ref_mspan", n);
    ref_sp_.melem = Kokkos::View<int*, MemSpace>("ref_melem", n);
    ref_sp_.mxi = fr_.ref_mxi;
    ref_sp_.gap = Kokkos::View<double*, MemSpace>("ref_gap", n);
    ref_sp_.pressure = Kokkos::View<double*, MemSpace>("ref_pressure", n);
    ref_sp_.x = Kokkos::View<double* [2], MemSpace>("ref_x", n);
    ref_sp_.normal = Kokkos::View<double* [2], MemSpace>("ref_normal", n);
    ref_sp_.valid = fr_.ref_valid;   // the projection writes eta_n and its validity into fr_
  }
}

void ContactPairData::mortar_scratch(int cap) {
  const int na = std::max(a_end - a_begin, 0);
  scratch_.dof = Kokkos::View<int**, Kokkos::LayoutRight, MemSpace>("mortar_dof", na, cap);
  scratch_.v0 = Kokkos::View<double**, Kokkos::LayoutRight, MemSpace>("mortar_v0", na, cap);
  scratch_.v1 = Kokkos::View<double**, Kokkos::LayoutRight, MemSpace>("mortar_v1", na, cap);
  scratch_.row = Kokkos::View<double**, Kokkos::LayoutRight, MemSpace>("mortar_row", na, cap);
}

void ContactPairData::update(const Vector& u) {
  if (s3_) {
    s3_->update(u);
    return;
  }
  Vector ur(replicated_);
  ur.doImport(u, *importer_, Tpetra::INSERT);
  {
    auto v = ur.getLocalViewDevice(Tpetra::Access::ReadOnly);
    for (CurveData* c : {&slave, &master}) {
      const auto rep = c == &slave ? slave_rep_ : master_rep_;
      const auto cu = c->u;
      Kokkos::parallel_for("iga::GatherCurveDisplacements", Kokkos::RangePolicy<ExecSpace>(0, c->nb), KOKKOS_LAMBDA(const int k) {
        cu(k, 0) = v(rep(k, 0), 0);
        cu(k, 1) = v(rep(k, 1), 0);
      });
    }
  }
  refresh();
}

void ContactPairData::refresh() {
  const SearchGrid grid = build_search_grid(master);
  if (mortar_) {
    // segments; where a slave element needs more than the slots hold (a slave much coarser
    // than the master), grow the slots to what was reported and segment again
    for (;;) {
      MortarSegments ks;
      ks.s = slave; ks.m = master; ks.sp = sp_; ks.grid = grid; ks.gauss = gauss_; ks.thickness = thickness;
      ks.max_segments = max_segments_; ks.segmented = segmented_; ks.cuts = cuts_; ks.flags = ms_.flags;
      Kokkos::deep_copy(ms_.flags, 0);
      Kokkos::parallel_for("iga::MortarSegments", Kokkos::RangePolicy<ExecSpace>(0, slave.ne), ks);
      auto fl = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ms_.flags);
      if (fl(0) == 0) break;
      max_segments_ = std::max(fl(0), max_segments_ + max_segments_ / 2);
      slots = max_segments_ * gauss_.n;
      allocate_points(slave.ne * slots);
    }
  }
  ProjectSlavePoints k;
  k.s = slave; k.m = master; k.sp = sp_; k.grid = grid; k.eps = pair_.penalty;
  Kokkos::parallel_for("iga::ProjectSlavePoints", Kokkos::RangePolicy<ExecSpace>(0, num_points()), k);
  if (mortar_) {
    find_mortar_ends();
    MortarGaps kg;
    kg.s = slave; kg.sp = sp_; kg.ms = ms_; kg.eps = pair_.penalty; kg.slots = slots; kg.touch = sp_.touch;
    Kokkos::parallel_for("iga::MortarGaps", Kokkos::RangePolicy<ExecSpace>(0, slave.nb), kg);
    MortarPointPressure kp;
    kp.s = slave; kp.sp = sp_; kp.ms = ms_;
    Kokkos::parallel_for("iga::MortarPointPressure", Kokkos::RangePolicy<ExecSpace>(0, num_points()), kp);
    Kokkos::fence();
  }
  update_friction();
  Kokkos::fence();
}

// The master ends' images in the slave elements (kernels/contact_mortar.hpp, MortarEnds), for
// frictionless pairs: with friction only the normal part's boundary terms would be consistent,
// and Newton took more iterations than with neither (the sliding block as the master of its
// foundation, mortar_penalty: 20-22 per load step against at most 15), so friction pairs keep
// none (ends_found_ false: the tangent is taken as before).
void ContactPairData::find_mortar_ends() {
  ends_found_ = false;
  if (fr_.mu > 0) return;
  FindMortarEnds ke;
  ke.s = slave; ke.m = master; ke.sp = sp_; ke.ends = ends_; ke.cuts = cuts_; ke.nq = gauss_.n;
  ke.max_segments = max_segments_;
  Kokkos::parallel_for("iga::FindMortarEnds", Kokkos::RangePolicy<ExecSpace>(0, slave.ne), ke);
  auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ends_.sign);
  for (size_t e = 0; e < h.extent(0); ++e) ends_found_ = ends_found_ || h(e, 0) != 0 || h(e, 1) != 0;
}

void ContactPairData::update_friction() {
  const int n = num_points();
  if (mortar_) {
    // eta_n of every slot: its committed slave point projected onto the committed master
    if (grid_c_.key.data()) {
      Kokkos::deep_copy(ref_sp_.melem, -1);
      ProjectSlavePoints k;
      k.s = slave_c_; k.m = master_c_; k.sp = ref_sp_; k.grid = grid_c_; k.eps = pair_.penalty;
      Kokkos::parallel_for("iga::ProjectCommittedSlavePoints", Kokkos::RangePolicy<ExecSpace>(0, n), k);
    } else {
      Kokkos::deep_copy(fr_.ref_valid, 0);
    }
  }
  FrictionPointUpdate k;
  k.m = master; k.sp = sp_; k.fr = fr_; k.eps = pair_.penalty; k.mortar = mortar_;
  Kokkos::parallel_for("iga::FrictionPointUpdate", Kokkos::RangePolicy<ExecSpace>(0, n), k);
  if (mortar_) {
    MortarFrictionLaw kl;
    kl.s = slave; kl.sp = sp_; kl.ms = ms_; kl.fr = fr_; kl.slots = slots;
    Kokkos::parallel_for("iga::MortarFrictionLaw", Kokkos::RangePolicy<ExecSpace>(0, slave.nb), kl);
    MortarFrictionPoints kp;
    kp.s = slave; kp.sp = sp_; kp.ms = ms_; kp.fr = fr_;
    Kokkos::parallel_for("iga::MortarFrictionPoints", Kokkos::RangePolicy<ExecSpace>(0, n), kp);
  }
  // stick / slip counts and the points that changed state since the previous update
  FrictionCounts c;
  const auto st = fr_.state, prev = state_prev_;
  Kokkos::parallel_reduce("iga::FrictionCounts", Kokkos::RangePolicy<ExecSpace>(0, n),
                          KOKKOS_LAMBDA(const int i, int& stick, int& slip, int& sw) {
                            stick += st(i) == 1;
                            slip += st(i) == 2;
                            sw += st(i) != prev(i);
                          },
                          c.stick, c.slip, c.switches);
  Kokkos::deep_copy(state_prev_, fr_.state);
  counts_ = c;
}

void ContactPairData::set_touch(double band) {
  const double t = band > 0 ? band : 1e-12 * (s3_ ? s3_->h_min() : h_min_);
  if (s3_)
    s3_->sp.touch = t;
  else
    sp_.touch = t;
}

double ContactPairData::local_min_gap() const {
  const auto& gap_d = s3_ ? s3_->sp.gap : sp_.gap;
  const auto& valid_d = s3_ ? s3_->sp.valid : sp_.valid;
  const int b = s3_ ? s3_->p_begin : 0, e = s3_ ? s3_->p_end : num_points();   // (2-D: every rank projects every point)
  auto gap = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), gap_d);
  auto valid = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), valid_d);
  double g = std::numeric_limits<double>::infinity();
  for (int i = b; i < e; ++i)
    if (valid(i) && std::isfinite(gap(i))) g = std::min(g, gap(i));
  return g;
}

double ContactPairData::max_active_gap_ratio() const {
  if (s3_) return s3_->max_active_gap() / h_min_;
  if (!mortar_) return 0;   // kts_penalty: no multipliers (ALM pairs are on the mortar path)
  double r = 0;
  const auto g = weighted_gaps(), w = mortar_weights();
  auto act = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ms_.active);
  auto cw = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ms_.cwA);
  // a control point whose support the master covers only on a sliver (MortarState::sliver: a
  // master's end, e.g. a punch's corner, just inside its support) is left out: its
  // multiplier acts on the sliver alone, so g_A stays as it is however it grows (a flat punch
  // as the master of a soft block: g_A / w_A = 2.2e-9 over 38 updates, the covered part
  // 3e-5 of w_A, with its neighbours closed)
  for (size_t A = 0; A < g.size(); ++A)
    if (act(A) && !MortarState::sliver(cw(A), w[A])) r = std::max(r, std::abs(g[A] / w[A]));
  if (friction()) {
    auto sA = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), fr_.sA);
    auto stA = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), fr_.stateA);
    for (size_t A = 0; A < g.size(); ++A)
      if (stA(A) == 1) r = std::max(r, std::abs(sA(A)));
  }
  return r / h_min_;
}

// (ALM pairs only, which are all on the mortar path: mortar_alm and kts_alm)
double ContactPairData::augment() {
  if (s3_) {
    s3_->augment();
  } else {
    Kokkos::deep_copy(ms_.lbar, ms_.lambda);
    Kokkos::deep_copy(fr_.lamTA, fr_.tauA);
    if (ms_.scale.extent(0) > 0) scale_partly_covered(ms_);
  }
  return max_active_gap_ratio();
}

void ContactPairData::raise_penalty(double factor) {
  pair_.penalty *= factor;
  if (s3_) s3_->pair.penalty = pair_.penalty;
}

void ContactPairData::commit() {
  if (s3_) {
    s3_->commit();
    return;
  }
  keep_copy(committed_.mxi, sp_.mxi);
  keep_copy(committed_.melem, sp_.melem);
  keep_copy(committed_.mspan, sp_.mspan);
  keep_copy(committed_.valid, sp_.valid);
  if (mortar_) keep_copy(committed_.lbar, ms_.lbar);
  // friction: the converged tractions start the next step's trial (and its ALM multipliers),
  // the accumulated slip moves on, and the converged projections become the references
  if (mortar_) {
    Kokkos::deep_copy(fr_.lamTA, fr_.tauA);
    Kokkos::deep_copy(fr_.slipA_c, fr_.slipA);
    keep_copy(committed_.lamTA, fr_.lamTA);
    Kokkos::deep_copy(slave_c_.u, slave.u);
    Kokkos::deep_copy(master_c_.u, master.u);
    grid_c_ = build_search_grid(master_c_);
  } else {
    Kokkos::deep_copy(fr_.lamT, fr_.tau);
    Kokkos::deep_copy(fr_.slip_c, fr_.slip);
    keep_copy(committed_.lamT, fr_.lamT);
    Kokkos::deep_copy(fr_.ref_mxi, sp_.mxi);
    Kokkos::deep_copy(fr_.ref_valid, sp_.valid);
  }
}

void ContactPairData::restore() {
  if (s3_) {
    s3_->restore();
    return;
  }
  if (!committed_.valid.data()) return;   // nothing committed yet: the initial state stands
  // mortar slots are segmented anew at every update (and may have grown since): their
  // per-slot state is not history; the multipliers per control point are
  if (!mortar_) {
    Kokkos::deep_copy(sp_.mxi, committed_.mxi);
    Kokkos::deep_copy(sp_.melem, committed_.melem);
    Kokkos::deep_copy(sp_.mspan, committed_.mspan);
    Kokkos::deep_copy(sp_.valid, committed_.valid);
  }
  if (mortar_) Kokkos::deep_copy(ms_.lbar, committed_.lbar);
  if (mortar_) Kokkos::deep_copy(fr_.lamTA, committed_.lamTA);
  else Kokkos::deep_copy(fr_.lamT, committed_.lamT);
}

void ContactPairData::reset_multipliers() {
  if (s3_) {
    s3_->reset_multipliers();
  } else if (mortar_) {
    Kokkos::deep_copy(ms_.lbar, 0.0);
    Kokkos::deep_copy(fr_.lamTA, 0.0);
  } else {
    Kokkos::deep_copy(fr_.lamT, 0.0);
  }
}

std::vector<GO> ContactPairData::side_dofs() const {
  const RCP<const Map>& m = s3_ ? s3_->surface_dofs() : replicated_;
  const auto list = m->getNodeElementList();
  std::vector<GO> dofs(list.begin(), list.end());
  std::sort(dofs.begin(), dofs.end());
  return dofs;
}

}  // namespace iga
