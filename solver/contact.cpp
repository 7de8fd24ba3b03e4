#include "solver/contact.hpp"

static_assert(iga::kMaxContactQuadrature <= iga::kMaxGauss, "contact quadrature beyond the Gauss table");

#include <Teuchos_CommHelpers.hpp>
#include <Teuchos_TimeMonitor.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace iga {

namespace {
template <class T>
Kokkos::View<T*, MemSpace> dview(const std::string& name, const std::vector<T>& v) {
  Kokkos::View<T*, MemSpace> d(name, v.size());
  auto h = Kokkos::create_mirror_view(d);
  for (size_t k = 0; k < v.size(); ++k) h(k) = v[k];
  Kokkos::deep_copy(d, h);
  return d;
}

CurveData make_curve(const System& sys, const ContactSurface& s, const SurfaceChain& ch, std::vector<GO>& gids) {
  const Curve& c = ch.curve;
  CurveData d;
  d.p = c.degree;
  d.nb = c.ncp();
  const auto spans = c.element_spans();
  d.ne = static_cast<int>(spans.size());
  // the outward normal's sign: side_normal(East, sign) = sign (t_y, -t_x)
  d.side = static_cast<int>(Side::East);
  d.orientation = ch.normal_sign;
  d.U = dview("U", c.knots);
  d.span = dview("span", spans);
  d.X = Kokkos::View<double* [2], MemSpace>("X", d.nb);
  d.u = Kokkos::View<double* [2], MemSpace>("u", d.nb);
  std::vector<double> w(d.nb);
  auto hX = Kokkos::create_mirror_view(d.X);
  gids.resize(d.nb);
  for (int k = 0; k < d.nb; ++k) {
    hX(k, 0) = c.cp[k][0];
    hX(k, 1) = c.cp[k][1];
    w[k] = c.cp[k][2];
    gids[k] = sys.cp_gid(s.body, ch.cp_patch[k], c.patch_index[k]);
  }
  Kokkos::deep_copy(d.X, hX);
  d.w = dview("w", w);
  d.lid = Kokkos::View<int*, MemSpace>("lid", d.nb);
  return d;
}
/// Search grid over the master element boxes (convex hull of their current control points).
SearchGrid build_search_grid(const CurveData& m) {
  Kokkos::View<double* [4], MemSpace> dbox("boxes", m.ne);
  {
    Kokkos::parallel_for("iga::MasterElementBoxes", Kokkos::RangePolicy<ExecSpace>(0, m.ne), KOKKOS_LAMBDA(const int e) {
      double b[4] = {1e300, 1e300, -1e300, -1e300};
      for (int k = m.span(e) - m.p; k <= m.span(e); ++k) {
        const double x = m.X(k, 0) + m.u(k, 0), y = m.X(k, 1) + m.u(k, 1);
        b[0] = x < b[0] ? x : b[0];
        b[1] = y < b[1] ? y : b[1];
        b[2] = x > b[2] ? x : b[2];
        b[3] = y > b[3] ? y : b[3];
      }
      for (int c = 0; c < 4; ++c) dbox(e, c) = b[c];
    });
  }
  // grid cells of twice the largest box size; each box, grown by that size, goes into the
  // cells it overlaps
  auto hbox = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), dbox);
  double ext = 0, X0 = 1e300, Y0 = 1e300, X1 = -1e300, Y1 = -1e300;
  for (int e = 0; e < m.ne; ++e) {
    ext = std::max({ext, hbox(e, 2) - hbox(e, 0), hbox(e, 3) - hbox(e, 1)});
    X0 = std::min(X0, hbox(e, 0)); Y0 = std::min(Y0, hbox(e, 1));
    X1 = std::max(X1, hbox(e, 2)); Y1 = std::max(Y1, hbox(e, 3));
  }
  const double margin = std::max(ext, 1e-12);
  SearchGrid grid;
  grid.h = 2 * margin;
  grid.x0 = X0 - margin;
  grid.y0 = Y0 - margin;
  grid.nx = std::max(1, static_cast<int>(std::ceil((X1 - X0 + 2 * margin) / grid.h)));
  grid.ny = std::max(1, static_cast<int>(std::ceil((Y1 - Y0 + 2 * margin) / grid.h)));
  // (cell, element) pairs sorted by cell: only the non-empty cells are stored
  std::vector<std::pair<long long, int>> pairs;
  pairs.reserve(4 * static_cast<size_t>(m.ne));
  for (int e = 0; e < m.ne; ++e) {
    const int i0 = std::max(0, grid.cell_of(hbox(e, 0) - margin, 0)), i1 = std::min(grid.nx - 1, grid.cell_of(hbox(e, 2) + margin, 0));
    const int j0 = std::max(0, grid.cell_of(hbox(e, 1) - margin, 1)), j1 = std::min(grid.ny - 1, grid.cell_of(hbox(e, 3) + margin, 1));
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i) pairs.emplace_back(i + static_cast<long long>(grid.nx) * j, e);
  }
  std::sort(pairs.begin(), pairs.end());
  std::vector<long long> key;
  std::vector<int> start, elems(pairs.size());
  for (size_t k = 0; k < pairs.size(); ++k) {
    if (k == 0 || pairs[k].first != pairs[k - 1].first) {
      key.push_back(pairs[k].first);
      start.push_back(static_cast<int>(k));
    }
    elems[k] = pairs[k].second;
  }
  start.push_back(static_cast<int>(pairs.size()));
  grid.key = dview("grid_key", key);
  grid.start = dview("grid_start", start);
  grid.elems = dview("grid_elems", elems);
  grid.box = dbox;
  return grid;
}
}  // namespace

ContactPairData::ContactPairData(const System& sys, int index) : pair_(sys.problem().contact[index]), index_(index) {
  thickness = sys.problem().thickness;
  rank_ = sys.comm()->getRank();
  nranks_ = sys.comm()->getSize();
  slave_chain_ = surface_chain(sys.problem(), pair_.slave);
  slave = make_curve(sys, pair_.slave, slave_chain_, slave_gid);
  master = make_curve(sys, pair_.master, surface_chain(sys.problem(), pair_.master), master_gid);
  mortar_ = pair_.method == ContactMethod::MortarPenalty || pair_.method == ContactMethod::MortarAlm;
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
    const GaussRule g = gauss_rule(nq);
    std::vector<double> xi, wt;
    std::vector<int> span;
    for (int s : c.element_spans()) {
      const double a = c.knots[s], b = c.knots[s + 1], h = 0.5 * (b - a);
      for (int q = 0; q < nq; ++q) {
        const double u = a + h * (g.x[q] + 1.0), du = 1e-7 * (b - a);
        const auto p1 = c.eval(std::min(u + du, b)), p0 = c.eval(std::max(u - du, a));
        const double jac = std::hypot(p1[0] - p0[0], p1[1] - p0[1]) / (std::min(u + du, b) - std::max(u - du, a));
        xi.push_back(u);
        wt.push_back(g.w[q] * h * jac * thickness);
        span.push_back(s);
      }
    }
    n = static_cast<int>(xi.size());
    sp_.xi = dview("xi", xi);
    sp_.weight = dview("weight", wt);
    sp_.span = dview("span", span);
  } else {
    // segment quadrature slots (filled by MortarSegments at each update) and, per slave
    // control point, w_A = int R_A dGamma_0 (thickness included)
    const int nq = pair_.quadrature_points > 0 ? pair_.quadrature_points
                                               : std::min(slave.p + master.p + 1, kMaxGauss);
    gauss_ = gauss_rule(nq);
    max_segments_ = kMortarInitialSegments;
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
    ms_.wA = dview("wA", wA);
    ms_.gA = Kokkos::View<double*, MemSpace>("gA", slave.nb);
    ms_.lbar = Kokkos::View<double*, MemSpace>("lbar", slave.nb);
    ms_.lambda = Kokkos::View<double*, MemSpace>("lambdaA", slave.nb);
    ms_.active = Kokkos::View<int*, MemSpace>("activeA", slave.nb);
    ms_.covered = Kokkos::View<int*, MemSpace>("coveredA", slave.nb);
    ms_.flags = Kokkos::View<int*, MemSpace>("flags", 2);
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
      for (int d = 0; d < 2; ++d) h(k, d) = replicated_->getLocalElement(2 * gid[k] + d);
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
  sp_.lambda = Kokkos::View<double*, MemSpace>("lambda", n);
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
    ref_sp_.lambda = Kokkos::View<double*, MemSpace>("ref_lambda", n);
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
      ks.max_segments = max_segments_; ks.cuts = cuts_; ks.flags = ms_.flags;
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
    MortarGaps kg;
    kg.s = slave; kg.sp = sp_; kg.ms = ms_; kg.eps = pair_.penalty; kg.slots = slots; kg.touch = 1e-12 * h_min_;
    Kokkos::parallel_for("iga::MortarGaps", Kokkos::RangePolicy<ExecSpace>(0, slave.nb), kg);
    MortarPointPressure kp;
    kp.s = slave; kp.sp = sp_; kp.ms = ms_;
    Kokkos::parallel_for("iga::MortarPointPressure", Kokkos::RangePolicy<ExecSpace>(0, num_points()), kp);
    Kokkos::fence();
  }
  update_friction();
  Kokkos::fence();
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

double ContactPairData::max_active_gap_ratio() const {
  double r = 0;
  if (mortar_) {
    const auto g = weighted_gaps(), w = mortar_weights();
    auto act = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ms_.active);
    for (size_t A = 0; A < g.size(); ++A)
      if (act(A)) r = std::max(r, std::abs(g[A] / w[A]));
    if (friction()) {
      auto sA = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), fr_.sA);
      auto stA = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), fr_.stateA);
      for (size_t A = 0; A < g.size(); ++A)
        if (stA(A) == 1) r = std::max(r, std::abs(sA(A)));
    }
    return r / h_min_;
  }
  const auto st = state();
  for (size_t i = 0; i < st.gap.size(); ++i)
    if (st.active[i]) r = std::max(r, std::abs(st.gap[i]));
  if (friction()) {
    auto ds = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), fr_.ds);
    auto fs = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), fr_.state);
    for (int i = 0; i < num_points(); ++i)
      if (fs(i) == 1) r = std::max(r, std::abs(ds(i)));
  }
  return r / h_min_;
}

double ContactPairData::augment() {
  if (mortar_) {
    Kokkos::deep_copy(ms_.lbar, ms_.lambda);
    Kokkos::deep_copy(fr_.lamTA, fr_.tauA);
  } else {
    Kokkos::deep_copy(sp_.lambda, sp_.pressure);
    Kokkos::deep_copy(fr_.lamT, fr_.tau);
  }
  return max_active_gap_ratio();
}

void ContactPairData::commit() {
  auto keep = [](auto& dst, const auto& src) {
    if (!src.data()) return;
    if (dst.extent(0) != src.extent(0)) dst = std::decay_t<decltype(dst)>(std::string(src.label()) + "_committed", src.extent(0));
    Kokkos::deep_copy(dst, src);
  };
  keep(committed_.lambda, sp_.lambda);
  keep(committed_.mxi, sp_.mxi);
  keep(committed_.melem, sp_.melem);
  keep(committed_.mspan, sp_.mspan);
  keep(committed_.valid, sp_.valid);
  if (mortar_) keep(committed_.lbar, ms_.lbar);
  // friction: the converged tractions start the next step's trial (and its ALM multipliers),
  // the accumulated slip moves on, and the converged projections become the references
  if (mortar_) {
    Kokkos::deep_copy(fr_.lamTA, fr_.tauA);
    Kokkos::deep_copy(fr_.slipA_c, fr_.slipA);
    keep(committed_.lamTA, fr_.lamTA);
    Kokkos::deep_copy(slave_c_.u, slave.u);
    Kokkos::deep_copy(master_c_.u, master.u);
    grid_c_ = build_search_grid(master_c_);
  } else {
    Kokkos::deep_copy(fr_.lamT, fr_.tau);
    Kokkos::deep_copy(fr_.slip_c, fr_.slip);
    keep(committed_.lamT, fr_.lamT);
    Kokkos::deep_copy(fr_.ref_mxi, sp_.mxi);
    Kokkos::deep_copy(fr_.ref_valid, sp_.valid);
  }
}

void ContactPairData::restore() {
  if (!committed_.lambda.data()) return;   // nothing committed yet: the initial state stands
  // mortar slots are segmented anew at every update (and may have grown since): their
  // per-slot state is not history; the multipliers per control point are
  if (!mortar_) {
    Kokkos::deep_copy(sp_.lambda, committed_.lambda);
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
  if (mortar_) {
    Kokkos::deep_copy(ms_.lbar, 0.0);
    Kokkos::deep_copy(fr_.lamTA, 0.0);
  } else {
    Kokkos::deep_copy(sp_.lambda, 0.0);
    Kokkos::deep_copy(fr_.lamT, 0.0);
  }
}

namespace {
std::vector<double> host_vector(const Kokkos::View<double*, MemSpace>& v) {
  auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), v);
  return std::vector<double>(h.data(), h.data() + h.extent(0));
}
}  // namespace

std::vector<double> ContactPairData::weighted_gaps() const { return mortar_ ? host_vector(ms_.gA) : std::vector<double>{}; }
std::vector<double> ContactPairData::mortar_weights() const { return mortar_ ? host_vector(ms_.wA) : std::vector<double>{}; }
std::vector<double> ContactPairData::mortar_multipliers() const {
  return mortar_ ? host_vector(ms_.lambda) : std::vector<double>{};
}

double ContactPairData::potential() const {
  double pi = 0;
  if (mortar_) {
    const auto l = mortar_multipliers(), w = mortar_weights();
    for (size_t A = 0; A < l.size(); ++A) pi += 0.5 / pair_.penalty * w[A] * l[A] * l[A];
    return pi;
  }
  const auto st = state();
  for (size_t i = 0; i < st.gap.size(); ++i)
    if (st.active[i]) pi += 0.5 / pair_.penalty * st.pressure[i] * st.pressure[i] * st.weight[i];
  return pi;
}

ContactPointState ContactPairData::state(bool projected_only) const {
  ContactPointState s;
  const int n = num_points();
  auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), sp_.x);
  auto nrm = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), sp_.normal);
  auto xi = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), sp_.xi);
  auto gap = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), sp_.gap);
  auto pr = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), sp_.pressure);
  auto lam = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), sp_.lambda);
  auto valid = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), sp_.valid);
  auto w = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), sp_.weight);
  auto span = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), sp_.span);
  auto tau = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), fr_.tau);
  auto slip = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), fr_.slip);
  auto fst = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), fr_.state);
  auto tan = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), fr_.tangent);
  for (int i = 0; i < n; ++i) {
    if (span(i) < 0) continue;   // unused mortar slot
    // a point without a projection on the master (beyond its ends, far from it) has no gap
    // and takes no part in the contact: NaN gap here, left out of the outputs
    if (projected_only && !valid(i)) continue;
    s.x.push_back(x(i, 0));
    s.y.push_back(x(i, 1));
    s.nx.push_back(valid(i) ? nrm(i, 0) : 0.0);
    s.ny.push_back(valid(i) ? nrm(i, 1) : 0.0);
    s.xi.push_back(xi(i));
    s.gap.push_back(valid(i) ? gap(i) : std::nan(""));
    s.pressure.push_back(pr(i));
    s.weight.push_back(w(i));
    if (mortar_) s.active.push_back(valid(i) && pr(i) > 0 ? 1 : 0);
    else s.active.push_back(valid(i) && kts_active(lam(i), pair_.penalty, gap(i), sp_.touch) ? 1 : 0);
    s.tangential.push_back(tau(i));
    s.slip.push_back(slip(i));
    s.state.push_back(fst(i));
    s.tx.push_back(tan(i, 0));
    s.ty.push_back(tan(i, 1));
  }
  return s;
}

ContactSummary ContactPairData::summary() const {
  const auto st = state(true);
  ContactSummary c;
  // the forces: what the last assembly put on the slave dofs (assemble_contact), so that
  // they are the residual's and equal the reactions
  c.fx = assembled_[0];
  c.fy = assembled_[1];
  c.normal_force = assembled_[2];
  c.tangential_force = assembled_[3];
  for (size_t i = 0; i < st.x.size(); ++i) {
    if (!st.active[i]) continue;
    ++c.active_points;
    if (st.state[i] == 1) c.stick_length += st.weight[i] / thickness;
    if (st.state[i] == 2) c.slip_length += st.weight[i] / thickness;
    c.max_pressure = std::max(c.max_pressure, st.pressure[i]);
    c.contact_length += st.weight[i] / thickness;
    c.max_penetration = std::max(c.max_penetration, -st.gap[i]);
  }
  return c;
}

ContactContribution assemble_contact(const System& sys, std::vector<ContactPairData>& pairs) {
  // 1) the dofs this rank's contributions couple: overlap map and graph. A group is a set
  //    of control points coupled all to all: the element pair of a quadrature point (KTS,
  //    and the mortar pressure term), or the support of delta g_A (mortar). The pattern is
  //    reserved beyond what is active now: every point with a projection, with its master
  //    element widened by two neighbours on each side, and every weighted gap with such
  //    points; only active ones get values. So K_T's pattern, rebuilt when K_c has a
  //    nonzero outside it (tangent.hpp), seldom changes as the contact zone grows or
  //    points slide: once per run on the scaling problem, where it was twice per load step.
  std::vector<GO> cps;
  std::vector<std::vector<GO>> groups;
  int active = 0;
  for (size_t k = 0; k < pairs.size(); ++k) {
    auto& pd = pairs[k];
    auto valid = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), pd.sp_.valid);
    auto gap = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), pd.sp_.gap);
    auto lam = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), pd.sp_.lambda);
    auto sspan = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), pd.sp_.span);
    auto mspan = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), pd.sp_.mspan);
    const int nm = static_cast<int>(pd.master_gid.size());
    // two elements each side: on the scaling problem at 6.6e5 dofs the edge of the slave
    // block slides across more than one master element (one gave two builds there)
    constexpr int kWiden = 2;
    auto point_group = [&](int i) {
      std::vector<GO> g;
      for (int a = sspan(i) - pd.slave.p; a <= sspan(i); ++a) g.push_back(pd.slave_gid[a]);
      for (int b = std::max(0, mspan(i) - pd.master.p - kWiden); b <= std::min(nm - 1, mspan(i) + kWiden); ++b)
        g.push_back(pd.master_gid[b]);
      return g;
    };
    for (int i = pd.p_begin; i < pd.p_end; ++i) {
      if (sspan(i) < 0 || !valid(i)) continue;
      if (!pd.mortar() && kts_active(lam(i), pd.pair().penalty, gap(i), pd.sp_.touch)) ++active;
      groups.push_back(point_group(i));
    }
    if (pd.mortar()) {
      auto act = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), pd.ms_.active);
      auto espan = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), pd.slave.span);
      for (int A = pd.a_begin; A < pd.a_end; ++A) {
        if (act(A)) ++active;
        std::vector<GO> g;
        for (int e = 0; e < pd.slave.ne; ++e) {
          if (espan(e) < A || espan(e) > A + pd.slave.p) continue;
          for (int i = e * pd.slots; i < (e + 1) * pd.slots; ++i)
            if (sspan(i) >= 0 && valid(i)) {
              const auto pg = point_group(i);
              g.insert(g.end(), pg.begin(), pg.end());
            }
        }
        std::sort(g.begin(), g.end());
        g.erase(std::unique(g.begin(), g.end()), g.end());
        if (!g.empty()) groups.push_back(std::move(g));
      }
    }
  }
  for (const auto& g : groups) cps.insert(cps.end(), g.begin(), g.end());
  std::sort(cps.begin(), cps.end());
  cps.erase(std::unique(cps.begin(), cps.end()), cps.end());
  RCP<const Map> ov = sys.cp_dof_map(cps);
  auto lid_of = [&](GO g) { return static_cast<LO>(std::lower_bound(cps.begin(), cps.end(), g) - cps.begin()); };
  std::vector<std::vector<LO>> nbr(cps.size());
  std::vector<LO> el;
  for (const auto& g : groups) {
    el.clear();
    for (GO c : g) el.push_back(lid_of(c));
    for (LO r : el) nbr[r].insert(nbr[r].end(), el.begin(), el.end());
  }
  const LO n = static_cast<LO>(cps.size());
  Teuchos::ArrayRCP<size_t> rowptr(2 * n + 1);
  rowptr[0] = 0;
  for (LO r = 0; r < n; ++r) {
    auto& v = nbr[r];
    std::sort(v.begin(), v.end());
    v.erase(std::unique(v.begin(), v.end()), v.end());
    rowptr[2 * r + 1] = rowptr[2 * r] + 2 * v.size();
    rowptr[2 * r + 2] = rowptr[2 * r + 1] + 2 * v.size();
  }
  Teuchos::ArrayRCP<LO> cols(std::max<size_t>(rowptr[2 * n], 1));
  for (LO r = 0; r < n; ++r)
    for (int c = 0; c < 2; ++c) {
      size_t k = rowptr[2 * r + c];
      for (LO l : nbr[r]) { cols[k++] = 2 * l; cols[k++] = 2 * l + 1; }
    }
  cols = cols.persistingView(0, rowptr[2 * n]);
  RCP<Graph> graph = rcp(new Graph(ov, ov, rowptr, cols));
  graph->fillComplete(sys.owned_map(), sys.owned_map());
  RCP<Matrix> K = rcp(new Matrix(graph));
  Vector f(ov);
  // 2) kernels: every pair's active points of this rank. A mortar weighted gap whose dofs
  // outgrow its pair's scratch rows reports what it needs: the rows grow and the kernels run
  // again on zeroed K and f (once per growth, so rarely after the first steps)
  for (bool again = false, first = true; first || again; first = false) {
    auto lcl = K->getLocalMatrixDevice();
    auto fv = Kokkos::subview(f.getLocalViewDevice(Tpetra::Access::ReadWrite), Kokkos::ALL(), 0);
    if (again) {   // a rerun: the first pass's sums go (K and f start at zero)
      Kokkos::deep_copy(lcl.values, 0.0);
      Kokkos::deep_copy(fv, 0.0);
    }
    again = false;
    for (auto& pd : pairs) {
      if (pd.mortar()) Kokkos::deep_copy(pd.ms_.flags, 0);
      Kokkos::deep_copy(pd.force_, 0.0);
    }
    for (auto& pd : pairs) {
      for (CurveData* c : {&pd.slave, &pd.master}) {
        const auto& gid = c == &pd.slave ? pd.slave_gid : pd.master_gid;
        auto h = Kokkos::create_mirror_view(c->lid);
        for (int k = 0; k < c->nb; ++k) {
          auto it = std::lower_bound(cps.begin(), cps.end(), gid[k]);
          h(k) = (it != cps.end() && *it == gid[k]) ? static_cast<int>(it - cps.begin()) : -1;
        }
        Kokkos::deep_copy(c->lid, h);
      }
      if (pd.p_end > pd.p_begin)
        dispatch_degree(std::max(pd.slave.p, pd.master.p), [&](auto P) {
          AssembleKts<decltype(P)::value, decltype(lcl), decltype(fv)> k;
          k.s = pd.slave; k.m = pd.master; k.sp = pd.sp_; k.eps = pd.pair().penalty;
          k.p_begin = pd.p_begin; k.mortar = pd.mortar(); k.K = lcl; k.f = fv; k.force = pd.force_;
          Kokkos::parallel_for(pd.mortar() ? "iga::AssembleMortarPressure" : "iga::AssembleKts",
                               Kokkos::RangePolicy<ExecSpace>(0, pd.p_end - pd.p_begin), k);
        });
      if (pd.friction() && pd.p_end > pd.p_begin)
        dispatch_degree(std::max(pd.slave.p, pd.master.p), [&](auto P) {
          AssembleFriction<decltype(P)::value, decltype(lcl), decltype(fv)> k;
          k.s = pd.slave; k.m = pd.master; k.sp = pd.sp_; k.fr = pd.fr_; k.eps = pd.pair().penalty;
          k.p_begin = pd.p_begin; k.mortar = pd.mortar(); k.K = lcl; k.f = fv; k.force = pd.force_;
          Kokkos::parallel_for("iga::AssembleFriction", Kokkos::RangePolicy<ExecSpace>(0, pd.p_end - pd.p_begin), k);
        });
      if (pd.friction() && pd.mortar() && pd.a_end > pd.a_begin)
        dispatch_degree(std::max(pd.slave.p, pd.master.p), [&](auto P) {
          AssembleMortarFriction<decltype(P)::value, decltype(lcl)> k;
          k.s = pd.slave; k.m = pd.master; k.sp = pd.sp_; k.ms = pd.ms_; k.fr = pd.fr_; k.eps = pd.pair().penalty;
          k.sc = pd.scratch_; k.slots = pd.slots; k.a_begin = pd.a_begin; k.K = lcl;
          Kokkos::parallel_for("iga::AssembleMortarFriction", Kokkos::RangePolicy<ExecSpace>(0, pd.a_end - pd.a_begin), k);
        });
      if (pd.mortar() && pd.a_end > pd.a_begin) {
        AssembleMortarGap<decltype(lcl)> k;
        k.s = pd.slave; k.m = pd.master; k.sp = pd.sp_; k.ms = pd.ms_; k.eps = pd.pair().penalty;
        k.sc = pd.scratch_; k.slots = pd.slots; k.a_begin = pd.a_begin; k.K = lcl;
        Kokkos::parallel_for("iga::AssembleMortarGap", Kokkos::RangePolicy<ExecSpace>(0, pd.a_end - pd.a_begin), k);
        Kokkos::fence();
        auto fl = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), pd.ms_.flags);
        if (fl(1) > 0) {
          pd.mortar_scratch(std::max(fl(1), pd.scratch_.cap() + pd.scratch_.cap() / 2));
          again = true;
        }
      }
    }
    Kokkos::fence();
  }
  K->fillComplete(sys.owned_map(), sys.owned_map());
  // each pair's force on its slave body: this rank's points summed by the kernels, all ranks'
  for (auto& pd : pairs) {
    auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), pd.force_);
    double loc[4] = {h(0), h(1), h(2), h(3)};
    Teuchos::reduceAll(*sys.comm(), Teuchos::REDUCE_SUM, 4, loc, pd.assembled_);
  }
  ContactContribution out;
  out.K = sys.export_matrix(K);
  out.f = sys.export_vector(f);
  Teuchos::reduceAll(*sys.comm(), Teuchos::REDUCE_SUM, 1, &active, &out.active);
  return out;
}

}  // namespace iga
