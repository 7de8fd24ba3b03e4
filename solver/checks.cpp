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

std::string check_configuration(const System& sys, const Vector& u, const std::vector<ContactPairData>& contact) {
  Teuchos::TimeMonitor t(*Teuchos::TimeMonitor::getNewTimer("7) Checks: penetration, inverted elements"));
  std::vector<double> pen;
  for (const auto& c : contact) pen.push_back(c.summary().max_penetration);
  const auto disp = gather_displacements(sys, u);
  std::string why;
  if (sys.comm()->getRank() == 0) {
    // both, where both are found (a crease that folds where a body closes on itself)
    const std::string inverted = find_inverted(sys.problem(), disp);
    const std::string penetration = find_penetration(sys.problem(), disp, pen);
    why = inverted.empty() ? penetration : penetration.empty() ? inverted : inverted + "; " + penetration;
  }
  return broadcast_string(*sys.comm(), why);
}

std::string find_inverted_elements(const System& sys, const Vector& u) {
  const auto disp = gather_displacements(sys, u);
  return broadcast_string(*sys.comm(), sys.comm()->getRank() == 0 ? find_inverted(sys.problem(), disp) : std::string());
}

}  // namespace iga
