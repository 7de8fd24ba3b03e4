#pragma once
// The run's physical checks on the Tpetra solution (model/configuration_check.hpp computes
// them on the host): after every converged load step, interpenetration of bodies,
// self-penetration and inverted elements; collective, rank 0 computes, every rank gets the
// answer.
#include <string>
#include <vector>

#include "solver/contact.hpp"
#include "solver/system.hpp"

namespace iga {

/// Every body's displacements (2 per merged control point) on rank 0; empty elsewhere. Collective.
std::vector<std::vector<double>> gather_displacements(const System& sys, const Vector& u);

/// "" or one line: the deepest interpenetration or self-penetration beyond what the contact
/// pairs allow, or an inverted element, in the configuration u. Collective; the same answer on
/// every rank. Timer "7) Checks".
std::string check_configuration(const System& sys, const Vector& u, const std::vector<ContactPairData>& contact);

/// "" or one line naming an inverted element (det F <= 0) at u. Collective.
std::string find_inverted_elements(const System& sys, const Vector& u);

}  // namespace iga
