#include "solver/amg.hpp"

namespace iga {

namespace {

const AmgModule& module() {
  static const AmgModule* m = reinterpret_cast<const AmgModule* (*)()>(amg_module_symbol("igacontact_amg_module_v1"))();
  return *m;
}

}  // namespace

RCP<Operator> make_boomeramg(const RCP<Matrix>& A, int functions) { return module().boomeramg(A, functions); }

RCP<Operator> make_muelu(const RCP<Operator>& A, Teuchos::ParameterList& parameters) {
  return module().muelu(A, parameters);
}

}  // namespace iga
