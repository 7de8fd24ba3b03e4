#pragma once
// Loading libigacontact_amg.so, the module that holds the algebraic multigrid preconditioners
// (BoomerAMG from hypre, MueLu), on first use; solver/amg.hpp says why they are a module.
// This header needs no Tpetra: the problem-file reader uses it to check MueLu's parameters.
#include <string>

#include <Teuchos_RCP.hpp>

namespace Teuchos {
class ParameterList;
}

namespace iga {

/// The address of `symbol` in the module, loading it the first time (from the program's own
/// folder, else the dynamic loader's search path). Throws std::runtime_error naming the file
/// and the reason where it cannot be loaded or lacks the symbol.
void* amg_module_symbol(const char* symbol);

/// MueLu's master list: every parameter name MueLu knows (checks solver.linear.muelu_xml).
Teuchos::RCP<const Teuchos::ParameterList> muelu_master_list();

}  // namespace iga
