#pragma once
// The sparse direct solver: MUMPS (Debian's libmumps, through its C interface dmumps_c) on the
// distributed assembled matrix. Each rank hands MUMPS its own rows of the Tpetra matrix
// (ICNTL(18) = 3, global 1-based indices); the right-hand side is gathered to rank 0 and the
// solution scattered back (MPI_Gatherv / MPI_Scatterv over the row map's contiguous blocks).
//
// Reuse, the point of keeping one DirectSolver over a run:
//  - the symbolic analysis (ordering, elimination tree; JOB = 1) is done once per sparsity
//    pattern: a solve whose matrix has the same entries' positions as the last one analysed
//    (compared entry by entry on every rank) goes straight to the factorisation;
//  - the numerical factorisation (JOB = 2) is kept while the matrix values are unchanged
//    (elasticity without contact over several load steps): only the solve (JOB = 3) runs.
// With `symmetric`, only the upper triangle is passed and MUMPS factors L D L^T (SYM = 2),
// half the work and memory of L U.
//
// Failures become a LinearSolveResult with a one-line message, never an exception:
// a numerically singular matrix (INFOG(1) = -10, or null pivots found by ICNTL(24)), memory
// (the workspace estimate is raised and the factorisation retried, then "out of memory"),
// and a solution whose true relative residual |b - A x| / |b| exceeds 1e-6.
#include <memory>
#include <string>
#include <vector>

#include "solver/types.hpp"

namespace iga {

struct LinearSolveResult;

struct DirectSolverStats {
  int analyses = 0;          // symbolic analyses (sparsity patterns seen)
  int factorisations = 0;    // numerical factorisations
  int lu_factorisations = 0; // of them L U (a non-symmetric matrix; the others L D L^T)
  int solves = 0;
  double factor_bytes = 0;   // memory of the last factorisation, all ranks (MUMPS INFOG(22), MB)
  long long factor_entries = 0;   // entries in the factors (INFOG(29))
  std::string ordering;      // the fill-reducing ordering MUMPS chose (INFOG(7))
  double factor_seconds = 0;      // wall time of the last factorisation
  double factor_flops = 0;        // operations of the last factorisation, all ranks (MUMPS RINFOG(3))
};

class DirectSolver {
 public:
  explicit DirectSolver(const RCP<const Comm>& comm);
  ~DirectSolver();
  DirectSolver(const DirectSolver&) = delete;
  DirectSolver& operator=(const DirectSolver&) = delete;

  /// Solves A x = b. A's row map must give each rank one contiguous block of global indices
  /// (System's owned map does); b and x live on that map.
  LinearSolveResult solve(const Matrix& A, Vector& x, const Vector& b, bool symmetric);
  /// Analysis (if the pattern is new) and factorisation (if the values changed) of A.
  LinearSolveResult factorise(const Matrix& A, bool symmetric);
  /// x = A^-1 b with the factors of the last factorise (collective); false on a MUMPS error.
  bool apply(const Vector& b, Vector& x);
  bool factorised() const;
  /// A is the matrix of the last factorisation (pattern and values; collective).
  bool unchanged(const Matrix& A, bool symmetric) const;
  const DirectSolverStats& stats() const { return stats_; }

 private:
  using MUMPS_INT_T = int;   // MUMPS_INT of Debian's build (32-bit indices), checked in the .cpp
  void entries(const Matrix& A, bool symmetric, std::vector<MUMPS_INT_T>& irn, std::vector<MUMPS_INT_T>& jcn,
               std::vector<double>& a, bool change[2]) const;
  struct Impl;
  std::unique_ptr<Impl> d_;
  DirectSolverStats stats_;
};

}  // namespace iga
