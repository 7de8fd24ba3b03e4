#pragma once
// The algebraic multigrid preconditioners, BoomerAMG (hypre) and MueLu, live in a module of
// their own, libigacontact_amg.so beside the program, loaded the first time one is built
// (solver/amg_loader.hpp). A run that never builds one (MUMPS, ILUT, relaxation: every small
// problem) does not load hypre, MueLu and the 34 libraries MueLu pulls in (Teko,
// Stratimikos, ML, Epetra, Zoltan, Thyra...): the program's start-up 0.18 -> 0.11 s,
// docs/performance.md ("Start-up: the multigrid libraries on demand").
#include "solver/amg_loader.hpp"
#include "solver/types.hpp"

namespace iga {

using Operator = Tpetra::Operator<SC, LO, GO, Node>;

/// The module's entry points (solver/amg_module.cpp), found by the symbol
/// "igacontact_amg_module_v1" (another version of this struct gets another name).
struct AmgModule {
  RCP<Operator> (*boomeramg)(const RCP<Matrix>& A, int functions);
  RCP<Operator> (*muelu)(const RCP<Operator>& A, Teuchos::ParameterList& parameters);
};

/// BoomerAMG of A with `functions` interleaved dofs per node (the dimension); the operator
/// is hypre's V-cycle (solver/hypre_preconditioner.cpp). Throws where a rank's rows are not
/// one contiguous range of global ids, or the module cannot be loaded.
RCP<Operator> make_boomeramg(const RCP<Matrix>& A, int functions = 2);

/// MueLu::CreateTpetraPreconditioner(A, parameters).
RCP<Operator> make_muelu(const RCP<Operator>& A, Teuchos::ParameterList& parameters);

}  // namespace iga
