#pragma once
// Tpetra types of the project: Scalar double, LocalOrdinal int, GlobalOrdinal long long
// (the instantiation Debian's Trilinos ships), Node from Tpetra's default so that the same
// code builds against a Trilinos with OpenMP or CUDA.
#include <Tpetra_Core.hpp>
#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_Export.hpp>
#include <Tpetra_Import.hpp>
#include <Tpetra_Map.hpp>
#include <Tpetra_MultiVector.hpp>
#include <Tpetra_Vector.hpp>

#include <algorithm>
#include <thread>

#include "kernels/types.hpp"

namespace iga {

using SC = double;
using LO = int;
using GO = long long;
using Node = Tpetra::Map<LO, GO>::node_type;
using Map = Tpetra::Map<LO, GO, Node>;
using Graph = Tpetra::CrsGraph<LO, GO, Node>;
using Matrix = Tpetra::CrsMatrix<SC, LO, GO, Node>;
using Vector = Tpetra::Vector<SC, LO, GO, Node>;
using MultiVector = Tpetra::MultiVector<SC, LO, GO, Node>;
using Import = Tpetra::Import<LO, GO, Node>;
using Export = Tpetra::Export<LO, GO, Node>;
using Comm = Teuchos::Comm<int>;
using Teuchos::RCP;
using Teuchos::rcp;

/// Rank 0's value of s on every rank. Collective. (solver/checks.cpp)
std::string broadcast_string(const Comm& comm, std::string s);

/// Threads a rank may take for work of its own (MUMPS' kernels, the output's cells and
/// compression): the machine's cores not taken by the other ranks, at least 1.
inline int free_cores_per_rank(int ranks) {
  const unsigned hw = std::max(1u, std::thread::hardware_concurrency());
  return static_cast<int>(std::max(1u, hw / static_cast<unsigned>(std::max(1, ranks))));
}

static_assert(std::is_same<Node::execution_space, ExecSpace>::value,
              "the kernels' execution space must be Tpetra's default node's");

}  // namespace iga
