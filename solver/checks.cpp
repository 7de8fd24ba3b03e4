#include "solver/checks.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include <Teuchos_CommHelpers.hpp>
#include <Teuchos_TimeMonitor.hpp>

#include "kernels/numbering.hpp"
#include "model/configuration_check.hpp"

namespace iga {

std::vector<std::vector<double>> gather_displacements(const System& sys, const Vector& u) {
  const bool root = sys.comm()->getRank() == 0;
  std::vector<GO> all;
  if (root)
    for (GO g = 0; g < sys.num_dofs(); ++g) all.push_back(g);
  RCP<const Map> m = rcp(new Map(Teuchos::OrdinalTraits<Tpetra::global_size_t>::invalid(), all, 0, sys.comm()));
  Vector full(m);
  Import importer(u.getMap(), m);
  full.doImport(u, importer, Tpetra::INSERT);
  std::vector<std::vector<double>> out;
  if (!root) return out;
  auto h = full.getLocalViewHost(Tpetra::Access::ReadOnly);
  for (size_t b = 0; b < sys.problem().bodies.size(); ++b) {
    const size_t n = static_cast<size_t>(sys.problem().bodies[b].num_cps);
    std::vector<double> v(sys.dim() * n);
    for (size_t k = 0; k < sys.dim() * n; ++k) v[k] = h(dof_of(sys.body_offset(static_cast<int>(b)), 0, sys.dim()) + k, 0);
    out.push_back(std::move(v));
  }
  return out;
}

std::string broadcast_string(const Comm& comm, std::string s) {
  int n = static_cast<int>(s.size());
  Teuchos::broadcast(comm, 0, &n);
  s.resize(static_cast<size_t>(n));
  if (n > 0) Teuchos::broadcast(comm, 0, n, s.data());
  return s;
}

// 3-D kts_alm closes the weighted gaps of the slave control points (its multipliers), and each
// quadrature point keeps its penalty p_i = <lambda_i - eps g_i>. (2-D kts_alm has mortar's
// pressure field sum_A R_A lambda_A, no penalty per point, and nothing to lift off.) Where the quadrature points
// over-constrain the interface (a stiff flat punch as the slave of a soft block: its edges'
// singular pressure) the pointwise gaps oscillate about the closed weighted ones: points where
// the multipliers press lift off (p_i = 0), the pressure runs in bands, and the answer depends
// on the penalty (the 3-D punch of docs/contact-methods.md: normal force 5.47 at 100 E/h, 5.69
// at 1000 E/h, against mortar_alm's 4.97 at either; contact area 0.30 and 0.14 of the
// footprint). Measured by the share of the multipliers' force, sum w_i lambda_i, that acts at
// lifted points: 0 to 0.025 on the examples (the band where the multipliers' support reaches
// past a curved contact edge, coarse Hertz balls included), 0.24 and 0.44 on stiff punches.
// kLiftedShare is the line between them; "" or one line naming the pair. Collective (a 3-D
// pair's state is summed over the ranks); the same answer on every rank.
constexpr double kLiftedShare = 0.1;
std::string kts_alm_lifted(const Problem& P, const std::vector<ContactPairData>& contact) {
  for (size_t k = 0; k < contact.size(); ++k) {
    const ContactPairData& c = contact[k];
    if (c.pair().method != ContactMethod::KtsAlm || c.mortar()) continue;   // (2-D kts_alm: mortar's pressure field)
    const ContactPointState st = c.state(true);
    double all = 0, lifted = 0, gmax = 0;
    for (size_t i = 0; i < st.lambda.size(); ++i) {
      if (!(st.lambda[i] > 0)) continue;
      all += st.weight[i] * st.lambda[i];
      if (st.active[i]) continue;
      lifted += st.weight[i] * st.lambda[i];
      gmax = std::max(gmax, st.gap[i]);
    }
    if (!(all > 0) || lifted <= kLiftedShare * all) continue;
    const ContactPair& cp = c.pair();
    std::ostringstream os;
    os << "kts_alm lifted off: contact[" << k << "] (" << P.bodies[cp.slave.body].name << "." << cp.slave.label
       << " on " << P.bodies[cp.master.body].name << "." << cp.master.label << "): "
       << static_cast<int>(std::lround(100 * lifted / all))
       << " % of the force its multipliers carry acts at slave points that have lifted off (gaps up to "
       << check_number(gmax)
       << " where the weighted gaps are closed): the constraints at the slave quadrature points lock on this "
          "interface (a stiff flat slave's edges), so the answer depends on the penalty; take mortar_alm, or "
          "kts_penalty";
    return os.str();
  }
  return "";
}

std::string check_configuration(const System& sys, const Vector& u, const std::vector<ContactPairData>& contact) {
  Teuchos::TimeMonitor t(*Teuchos::TimeMonitor::getNewTimer("7) Checks: penetration, inverted elements"));
  std::vector<double> pen;
  for (const auto& c : contact) pen.push_back(c.summary().max_penetration);
  const auto disp = gather_displacements(sys, u);
  // on every rank: a 3-D pair's state sums its points over the ranks (collective)
  const std::string lifted = kts_alm_lifted(sys.problem(), contact);
  std::string why;
  if (sys.comm()->getRank() == 0) {
    // both, where both are found (a crease that folds where a body closes on itself)
    const std::string inverted = find_inverted(sys.problem(), disp);
    const std::string penetration = find_penetration(sys.problem(), disp, pen);
    why = inverted.empty() ? penetration : penetration.empty() ? inverted : inverted + "; " + penetration;
    if (why.empty()) why = lifted;
  }
  return broadcast_string(*sys.comm(), why);
}

std::string find_inverted_elements(const System& sys, const Vector& u) {
  const auto disp = gather_displacements(sys, u);
  return broadcast_string(*sys.comm(), sys.comm()->getRank() == 0 ? find_inverted(sys.problem(), disp) : std::string());
}

}  // namespace iga
