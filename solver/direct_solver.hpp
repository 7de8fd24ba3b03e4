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
// Condensed solves (set_condensed; the Newton core gives the dofs of the contact pairs' sides
// at small strain, where the tangent K_el + K_c changes from one iterate to the next only in
// their rows and columns): the factorisation keeps the factors of the other dofs' block A_II
// and MUMPS' Schur complement S = A_CC - A_CI A_II^-1 A_IC of the set C (ICNTL(19), dense,
// on rank 0), LU-factorised by LAPACK. A later matrix A' that equals the factorised one
// outside the C x C block has the Schur complement S + D, D = A'_CC - A_CC; it is solved by
// MUMPS' reduction (ICNTL(26) = 1), the Woodbury identity on the rows and columns where D is
// not zero, (S + D)^-1 y = z - G_A (I + D_AA G_AA)^-1 D_AA z_A with z = S^-1 y and G_A the
// columns of S^-1 of those dofs (computed once each, kept until the next factorisation), and
// MUMPS' expansion (ICNTL(26) = 2): one forward and backward substitution per Newton
// iteration instead of a factorisation or a Krylov solve. The true residual decides, as for
// every direct solve.
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
  int condensed_size = 0;         // dofs of the condensed set (0: none)
  int condensed_solves = 0;       // solves by the updated Schur complement
  int condensed_rank = 0;         // the largest number of dofs an update D touched
  int condensed_columns = 0;      // columns of S^-1 computed (since the last factorisation)
  bool condensed_fell_back = false;   // condensation given up (a singular Schur complement)
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

  /// The condensed set: sorted global indices (the same on every rank; collective at the
  /// next factorise, which then analyses afresh); empty turns condensation off. own_order:
  /// order the matrix as MUMPS would without the set, the set last (a second analysis; in
  /// 3-D the factors are far smaller than with the AMD MUMPS takes for a Schur analysis, in
  /// 2-D a little larger: the 77k wheel 23.4e6 against 22.5e6 entries)
  void set_condensed(const std::vector<GO>& dofs, bool own_order = false);
  /// Factors with a usable Schur complement exist and A equals the factorised matrix outside
  /// the condensed set's block (pattern and values; collective).
  bool condensed_ready(const Matrix& A, bool symmetric) const;
  /// A x = b by the Schur complement updated with A's block on the set (condensed_ready(A)
  /// must hold; collective).
  LinearSolveResult solve_condensed(const Matrix& A, Vector& x, const Vector& b, bool symmetric);

 private:
  using MUMPS_INT_T = int;   // MUMPS_INT of Debian's build (32-bit indices), checked in the .cpp
  void entries(const Matrix& A, bool symmetric, std::vector<MUMPS_INT_T>& irn, std::vector<MUMPS_INT_T>& jcn,
               std::vector<double>& a, bool change[2]) const;
  LinearSolveResult check_residual(const Matrix& A, const Vector& x, const Vector& b, LinearSolveResult res) const;
  void gather_block(const Matrix& A, bool symmetric, std::vector<long long>& keys, std::vector<double>& values) const;
  struct Impl;
  std::unique_ptr<Impl> d_;
  DirectSolverStats stats_;
};

}  // namespace iga
