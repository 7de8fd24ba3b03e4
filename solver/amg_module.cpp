// libigacontact_amg.so: the algebraic multigrid preconditioners, loaded on demand by
// solver/amg_loader.cpp (solver/amg.hpp says why they are a module). Links hypre and MueLu;
// the program does not.
#include <MueLu_CreateTpetraPreconditioner.hpp>
#include <MueLu_MasterList.hpp>

#include "solver/amg.hpp"
#include "solver/hypre_preconditioner.hpp"

namespace {

iga::RCP<iga::Operator> muelu(const iga::RCP<iga::Operator>& A, Teuchos::ParameterList& p) {
  iga::RCP<iga::Operator> op = A;
  return MueLu::CreateTpetraPreconditioner<iga::SC, iga::LO, iga::GO, iga::Node>(op, p);
}

const iga::AmgModule module{&iga::hypre_boomeramg, &muelu};

}  // namespace

#define IGACONTACT_EXPORT extern "C" __attribute__((visibility("default")))

IGACONTACT_EXPORT const iga::AmgModule* igacontact_amg_module_v1() { return &module; }

IGACONTACT_EXPORT Teuchos::RCP<const Teuchos::ParameterList> igacontact_muelu_master_list() {
  return MueLu::MasterList::List();
}
