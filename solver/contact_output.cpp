// What a contact pair reports: host copies of its mortar vectors, its potential, the state
// of its points and its summary.
#include "solver/contact.hpp"
#include "solver/contact_internal.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace iga {

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
  if (s3_) return s3_->potential();
  double pi = 0;
  if (mortar_) {
    const auto l = mortar_multipliers(), w = mortar_weights();
    std::vector<double> s(l.size(), 1.0);   // the penalty's scale per control point (ALM)
    if (ms_.scale.extent(0) > 0) s = host_vector(ms_.scale);
    for (size_t A = 0; A < l.size(); ++A) pi += 0.5 / (pair_.penalty * s[A]) * w[A] * l[A] * l[A];
    return pi;
  }
  const auto st = state();
  for (size_t i = 0; i < st.gap.size(); ++i)
    if (st.active[i]) pi += 0.5 / pair_.penalty * st.pressure[i] * st.pressure[i] * st.weight[i];
  return pi;
}

ContactPointState ContactPairData::state(bool projected_only) const {
  ContactPointState s;
  if (s3_) {
    s3_->state(s, projected_only);
    return s;
  }
  const int n = num_points();
  auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), sp_.x);
  auto nrm = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), sp_.normal);
  auto xi = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), sp_.xi);
  auto gap = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), sp_.gap);
  auto pr = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), sp_.pressure);
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
    else s.active.push_back(valid(i) && kts_active(gap(i), sp_.touch) ? 1 : 0);
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
  if (s3_) {
    c.fx = assembled_[0];
    c.fy = assembled_[1];
    c.fz = assembled_[2];
    c.normal_force = assembled_[3];
    for (int k = 0; k < 3; ++k) c.tangential[k] = s3_->assembled_t[k];
  } else {
    c.fx = assembled_[0];
    c.fy = assembled_[1];
    c.normal_force = assembled_[2];
    c.tangential_force = assembled_[3];
  }
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

namespace {

// The distinct ids (>= 0) of the points with a projection under pressure (2-D: every rank holds
// every point).
int distinct_under_pressure(const Kokkos::View<int*, MemSpace>& ids, const SlavePoints& sp) {
  auto id = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ids);
  auto valid = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), sp.valid);
  auto pr = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), sp.pressure);
  std::vector<int> v;
  for (size_t i = 0; i < id.extent(0); ++i)
    if (id(i) >= 0 && valid(i) && pr(i) > 0) v.push_back(id(i));
  std::sort(v.begin(), v.end());
  return static_cast<int>(std::unique(v.begin(), v.end()) - v.begin());
}

}  // namespace

int ContactPairData::active_slave_elements() const {
  return s3_ ? s3_->active_elements() : distinct_under_pressure(sp_.span, sp_);
}

int ContactPairData::active_master_elements() const {
  return s3_ ? s3_->active_master_elements() : distinct_under_pressure(sp_.melem, sp_);
}

std::string ContactPairData::pair_text(int index, const Problem& P) const {
  return "contact[" + std::to_string(index) + "] (" + P.bodies[pair_.slave.body].name + "." + pair_.slave.label + " on " +
         P.bodies[pair_.master.body].name + "." + pair_.master.label + ")";
}

std::string ContactPairData::unresolved_zone(int index, const Problem& P) const {
  const bool solid = s3_ != nullptr;
  // (2-D: a zone of two slave elements gave max_pressure -43 % of Hertz with kts_alm, one of
  // 1.1 master elements +46 % with mortar; three of each +8..16 %)
  const int need_elements = solid ? 4 : 3;
  std::ostringstream os;
  os.precision(2);
  os << pair_text(index, P) << ": the contact zone covers about ";
  const char* advice = ": max_pressure and the pressure's shape are not resolved there (the forces are); refine "
                       "both bodies where they touch";
  // the master elements under the points with pressure (a coarse master under a fine slave:
  // the pressure follows the master's element polynomials)
  const int nm = active_master_elements();   // (collective in 3-D)
  // mortar: the slave elements under pressure (its field spreads over the supports of the
  // active control points, so this counts the zone generously); a coarse 3-D ball gave
  // max_pressure +104 % of Hertz with mortar_alm and no word (found by a problem written from
  // the docs)
  if (solid ? s3_->mortar && s3_->segmented : mortar_ && segmented_) {
    const int ne = active_slave_elements();   // (collective in 3-D)
    if (ne == 0 || (ne >= need_elements && nm >= need_elements)) return "";
    os << ne << " slave element(s) (those with pressure) and " << nm << " master element(s)" << advice;
    return os.str();
  }
  // KTS and kts_alm: their points, a fixed number per slave element
  const int per = solid ? s3_->points_per_element : kts_points_per_element_;
  const int need = need_elements * per;
  const ContactSummary sm = summary();
  if (per <= 0 || sm.active_points == 0 || (sm.active_points >= need && nm >= need_elements)) return "";
  os << static_cast<double>(sm.active_points) / per << " slave element(s) (" << sm.active_points << " active points, "
     << per << " per element) and " << nm << " master element(s)" << advice;
  return os.str();
}

}  // namespace iga
