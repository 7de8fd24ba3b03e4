#pragma once
// hypre's BoomerAMG (Debian's libhypre-dev) as a preconditioner for Belos: one V-cycle per
// application, on a copy of the tangent in hypre's ParCSR format (the default preconditioner
// of gmres and cg: measured against MueLu in docs/performance.md, "BoomerAMG beside MueLu").
//
// The system's owned rows are a contiguous range of global dofs per rank (System: control
// points in blocks, dofs 2 g, 2 g + 1), which is what hypre's IJ interface asks for: the rows
// and columns are copied with their global ids as they are, Dirichlet rows included (identity
// rows, their columns zeroed), two functions per node, interleaved.
#include "solver/types.hpp"

namespace iga {

/// BoomerAMG of A with `functions` interleaved dofs per node (the dimension). Throws where a
/// rank's rows are not one contiguous range of global ids. Part of the AMG module
/// (solver/amg.hpp): the program calls make_boomeramg, which loads it.
RCP<Tpetra::Operator<SC, LO, GO, Node>> hypre_boomeramg(const RCP<Matrix>& A, int functions);

}  // namespace iga
