#include "solver/direct_solver.hpp"

#include <dmumps_c.h>
#include <mpi.h>

#include <Teuchos_DefaultMpiComm.hpp>
#include <Teuchos_TimeMonitor.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <thread>
#include <vector>

#include "solver/linear_solver.hpp"

namespace iga {

static_assert(std::is_same<MUMPS_INT, int>::value, "igacontact expects MUMPS with 32-bit indices (Debian's)");

namespace {

// MUMPS' arrays are Fortran's: ICNTL(i) is icntl[i - 1]
int& ICNTL(DMUMPS_STRUC_C& id, int i) { return id.icntl[i - 1]; }
int INFOG(const DMUMPS_STRUC_C& id, int i) { return id.infog[i - 1]; }

const char* ordering_name(int k) {
  switch (k) {
    case 0: return "AMD";
    case 1: return "user";
    case 2: return "AMF";
    case 3: return "SCOTCH";
    case 4: return "PORD";
    case 5: return "METIS";
    case 6: return "QAMD";
    default: return "?";
  }
}

MPI_Comm raw_comm(const RCP<const Comm>& comm) {
  auto mpi = Teuchos::rcp_dynamic_cast<const Teuchos::MpiComm<int>>(comm);
  if (mpi.is_null()) throw std::logic_error("DirectSolver needs an MPI communicator");
  return (*mpi->getRawMpiComm())();
}

}  // namespace

struct DirectSolver::Impl {
  DMUMPS_STRUC_C id{};
  MPI_Comm comm = MPI_COMM_NULL;
  int rank = 0, size = 1;
  bool initialised = false, analysed = false, factorised = false, symmetric = false;
  MUMPS_INT n = 0;
  std::vector<MUMPS_INT> irn, jcn;   // this rank's entries, 1-based global indices
  std::vector<double> a;
  std::vector<int> counts, displs;   // rows per rank and their first global index (rank 0 only)
  std::vector<double> rhs;           // the gathered right-hand side / solution (rank 0)

  void call(int job) {
    id.job = job;
    dmumps_c(&id);
  }
  ~Impl() {
    if (initialised) call(-2);
  }
};

DirectSolver::DirectSolver(const RCP<const Comm>& comm) : d_(new Impl) {
  d_->comm = raw_comm(comm);
  d_->rank = comm->getRank();
  d_->size = comm->getSize();
}

DirectSolver::~DirectSolver() = default;

bool DirectSolver::factorised() const { return d_->factorised; }

namespace {

// f(row, column, value) for this rank's entries in global 1-based indices (the upper triangle
// if symmetric), row after row, in the order MUMPS is given them; stops where f returns false
// (then false).
template <class F>
bool for_each_entry(const Matrix& A, bool symmetric, const F& f) {
  auto lcl = A.getLocalMatrixHost();
  auto colmap = A.getColMap()->getLocalMap();
  auto lrow = A.getRowMap()->getLocalMap();
  for (LO r = 0; r < static_cast<LO>(lcl.numRows()); ++r) {
    const GO gr = lrow.getGlobalElement(r);
    auto row = lcl.row(r);
    for (int k = 0; k < row.length; ++k) {
      const GO gc = colmap.getGlobalElement(row.colidx(k));
      if (symmetric && gc < gr) continue;
      if (!f(static_cast<MUMPS_INT>(gr + 1), static_cast<MUMPS_INT>(gc + 1), row.value(k))) return false;
    }
  }
  return true;
}

}  // namespace

// This rank's entries in global 1-based indices (the upper triangle if symmetric), and
// whether the pattern (0) or the values (1) differ from the last analysed / factored ones on
// any rank (collective).
void DirectSolver::entries(const Matrix& A, bool symmetric, std::vector<MUMPS_INT_T>& irn,
                           std::vector<MUMPS_INT_T>& jcn, std::vector<double>& a, bool change[2]) const {
  const Impl& d = *d_;
  Teuchos::TimeMonitor t(*Teuchos::TimeMonitor::getNewTimer("4a) Direct: entries and analysis"));
  const auto rowmap = A.getRowMap();
  const GO nglobal = static_cast<GO>(rowmap->getGlobalNumElements());
  if (nglobal > std::numeric_limits<MUMPS_INT>::max() || rowmap->getIndexBase() != 0 ||
      rowmap->getMaxAllGlobalIndex() != nglobal - 1)
    throw std::logic_error("DirectSolver: the row map must number 0 .. N-1");
  {
    // each rank's rows one contiguous block of global indices (the gather relies on it)
    const LO nl = static_cast<LO>(rowmap->getNodeNumElements());
    const GO g0 = nl > 0 ? rowmap->getGlobalElement(0) : 0;
    for (LO r = 0; r < nl; ++r)
      if (rowmap->getGlobalElement(r) != g0 + r)
        throw std::logic_error("DirectSolver: a rank's rows are not one contiguous block of global indices");
  }
  const size_t nnz = A.getLocalMatrixHost().nnz();
  irn.clear(); jcn.clear(); a.clear();
  irn.reserve(nnz); jcn.reserve(nnz); a.reserve(nnz);
  for_each_entry(A, symmetric, [&](MUMPS_INT i, MUMPS_INT j, double v) {
    irn.push_back(i);
    jcn.push_back(j);
    a.push_back(v);
    return true;
  });
  int local_change[2] = {0, 0}, any[2] = {0, 0};
  if (!d.analysed || symmetric != d.symmetric || irn != d.irn || jcn != d.jcn) local_change[0] = 1;
  if (local_change[0] || !d.factorised || a != d.a) local_change[1] = 1;
  MPI_Allreduce(local_change, any, 2, MPI_INT, MPI_MAX, d.comm);
  change[0] = any[0] != 0;
  change[1] = any[1] != 0;
}

// The entries compared where they are, in the order entries() lists them, stopping at the
// first difference (no copy: the factors are kept between Newton iterations only when the
// tangent is bit for bit the factorised one, which a changed tangent shows in its first rows).
bool DirectSolver::unchanged(const Matrix& A, bool symmetric) const {
  const Impl& d = *d_;
  Teuchos::TimeMonitor t(*Teuchos::TimeMonitor::getNewTimer("4a) Direct: entries and analysis"));
  int local = !d.analysed || !d.factorised || symmetric != d.symmetric ? 1 : 0;
  if (!local) {
    size_t k = 0;
    const size_t n = d.a.size();
    const bool same = for_each_entry(A, symmetric, [&](MUMPS_INT i, MUMPS_INT j, double v) {
      if (k == n || d.irn[k] != i || d.jcn[k] != j || d.a[k] != v) return false;
      ++k;
      return true;
    });
    local = same && k == n ? 0 : 1;
  }
  int any = 0;
  MPI_Allreduce(&local, &any, 1, MPI_INT, MPI_MAX, d.comm);
  return any == 0;
}

LinearSolveResult DirectSolver::factorise(const Matrix& A, bool symmetric) {
  Impl& d = *d_;
  LinearSolveResult res;
  auto timer = [](const char* name) { return Teuchos::TimeMonitor::getNewTimer(name); };
  std::vector<MUMPS_INT> irn, jcn;
  std::vector<double> a;
  bool change[2];
  entries(A, symmetric, irn, jcn, a, change);
  const GO nglobal = static_cast<GO>(A.getRowMap()->getGlobalNumElements());
  const bool analyse = change[0], factorise = change[1];

  if (!d.initialised || (analyse && symmetric != d.symmetric)) {
    if (d.initialised) d.call(-2);
    d.id = DMUMPS_STRUC_C{};
    d.id.comm_fortran = static_cast<MUMPS_INT>(MPI_Comm_c2f(d.comm));
    d.id.par = 1;                   // rank 0 works too
    d.id.sym = symmetric ? 2 : 0;   // general symmetric (L D L^T) or unsymmetric (L U)
    d.call(-1);
    d.initialised = true;
    d.symmetric = symmetric;
    d.analysed = d.factorised = false;
    // quiet: errors come back through INFOG, and become our own messages
    ICNTL(d.id, 1) = -1;
    ICNTL(d.id, 2) = -1;
    ICNTL(d.id, 3) = -1;
    ICNTL(d.id, 4) = 0;
    ICNTL(d.id, 18) = 3;    // distributed assembled matrix, each rank its own entries
    ICNTL(d.id, 20) = 0;    // dense right-hand side on rank 0
    ICNTL(d.id, 21) = 0;    // solution gathered on rank 0
    ICNTL(d.id, 7) = 7;     // fill-reducing ordering: MUMPS chooses among those it was built with
    ICNTL(d.id, 14) = 40;   // workspace: 40 % over the analysis' estimate
    ICNTL(d.id, 24) = 1;    // detect null pivots: a singular matrix is reported, not solved
    // OpenMP threads of MUMPS' own kernels: the cores not taken by other ranks
    ICNTL(d.id, 16) = free_cores_per_rank(d.size);
  }

  auto mumps_message = [&](const char* phase) {
    const int e = INFOG(d.id, 1), e2 = INFOG(d.id, 2);
    std::ostringstream os;
    os << "the direct solver (MUMPS) failed in the " << phase << ": ";
    if (e == -10) {
      res.singular = true;
      os << "the matrix is numerically singular (a body free to move, or a contact pair with no active point "
            "holding a body?); check the displacement boundary conditions";
    } else if (e == -13)
      os << "out of memory (allocating " << e2 << (e2 < 0 ? " MB" : " entries") << "); use solver.linear.method: gmres";
    else
      os << "MUMPS error INFOG(1) = " << e << ", INFOG(2) = " << e2;
    return os.str();
  };

  if (analyse) {
    Teuchos::TimeMonitor t(*timer("4a) Direct: entries and analysis"));
    d.irn = std::move(irn);
    d.jcn = std::move(jcn);
    d.n = static_cast<MUMPS_INT>(nglobal);
    d.id.n = d.n;
    d.id.nnz_loc = static_cast<MUMPS_INT8>(d.irn.size());
    d.id.irn_loc = d.irn.data();
    d.id.jcn_loc = d.jcn.data();
    d.call(1);
    if (INFOG(d.id, 1) < 0) {
      d.analysed = false;
      res.message = mumps_message("analysis");
      return res;
    }
    d.analysed = true;
    d.factorised = false;
    ++stats_.analyses;
    stats_.ordering = ordering_name(INFOG(d.id, 7));
  }
  if (factorise) {
    Teuchos::TimeMonitor t(*timer("4b) Direct: factorisation"));
    const auto t0 = std::chrono::steady_clock::now();
    d.a = std::move(a);
    d.id.a_loc = d.a.data();
    d.factorised = false;
    for (int attempt = 0;; ++attempt) {
      d.call(2);
      const int e = INFOG(d.id, 1);
      // workspace too small for the pivoting that happened: more room, again
      const bool room = e == -8 || e == -9 || e == -14 || e == -15 || e == -17 || e == -20;
      if (room && attempt < 4) {
        ICNTL(d.id, 14) = 2 * ICNTL(d.id, 14) + 20;
        continue;
      }
      if (e < 0) {
        res.message = mumps_message("factorisation");
        return res;
      }
      break;
    }
    if (INFOG(d.id, 28) > 0) {
      res.singular = true;
      std::ostringstream os;
      os << "the direct solver (MUMPS) found " << INFOG(d.id, 28)
         << " null pivot(s): the matrix is singular (a body free to move, or a contact pair with no active "
            "point holding a body?); check the displacement boundary conditions";
      res.message = os.str();
      return res;
    }
    d.factorised = true;
    ++stats_.factorisations;
    if (!symmetric) ++stats_.lu_factorisations;
    stats_.factor_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    stats_.factor_bytes = 1e6 * INFOG(d.id, 22);   // MB, all ranks, during the factorisation
    stats_.factor_entries = INFOG(d.id, 29) >= 0 ? INFOG(d.id, 29) : -1000000LL * INFOG(d.id, 29);
    stats_.factor_flops = d.id.rinfog[2];   // RINFOG(3): the same number on every rank
  }

  res.converged = true;
  return res;
}

bool DirectSolver::apply(const Vector& b, Vector& x) {
  Impl& d = *d_;
  const auto rowmap = b.getMap();
  // b gathered on rank 0, the solution scattered back
  {
    const int nloc = static_cast<int>(rowmap->getNodeNumElements());
    const int first = nloc > 0 ? static_cast<int>(rowmap->getGlobalElement(0)) : 0;
    if (d.rank == 0) {
      d.counts.assign(d.size, 0);
      d.displs.assign(d.size, 0);
      d.rhs.assign(d.n, 0.0);
    }
    MPI_Gather(&nloc, 1, MPI_INT, d.counts.data(), 1, MPI_INT, 0, d.comm);
    MPI_Gather(&first, 1, MPI_INT, d.displs.data(), 1, MPI_INT, 0, d.comm);
    {
      auto bv = b.getLocalViewHost(Tpetra::Access::ReadOnly);
      MPI_Gatherv(bv.data(), nloc, MPI_DOUBLE, d.rhs.data(), d.counts.data(), d.displs.data(), MPI_DOUBLE, 0,
                  d.comm);
    }
    d.id.rhs = d.rank == 0 ? d.rhs.data() : nullptr;
    d.id.nrhs = 1;
    d.id.lrhs = d.n;
    d.call(3);
    // every rank learns the outcome (INFOG is global)
    if (INFOG(d.id, 1) < 0) return false;
    {
      auto xv = x.getLocalViewHost(Tpetra::Access::OverwriteAll);
      MPI_Scatterv(d.rhs.data(), d.counts.data(), d.displs.data(), MPI_DOUBLE, xv.data(), nloc, MPI_DOUBLE, 0,
                   d.comm);
    }
    ++stats_.solves;
  }
  return true;
}

LinearSolveResult DirectSolver::solve(const Matrix& A, Vector& x, const Vector& b, bool symmetric) {
  LinearSolveResult res = factorise(A, symmetric);
  if (!res.converged) return res;
  res.converged = false;
  res.iterations = 1;
  {
    Teuchos::TimeMonitor t(*Teuchos::TimeMonitor::getNewTimer("5) Linear solve"));
    if (!apply(b, x)) {
      std::ostringstream os;
      os << "the direct solver (MUMPS) failed in the solve: INFOG(1) = " << INFOG(d_->id, 1);
      res.message = os.str();
      return res;
    }
  }

  // the true relative residual decides (a nearly singular matrix gives a solution that
  // does not solve the system)
  Vector r(b.getMap());
  A.apply(x, r);
  r.update(1.0, b, -1.0);
  const double bn = b.norm2();
  const double rel = bn > 0 ? r.norm2() / bn : 0.0;
  res.achieved_tolerance = rel;
  if (!(rel <= 1e-6)) {
    // far above round-off (MUMPS found no exactly null pivot, but the solution does not solve
    // the system at all: a body free to move in a direction round-off holds): singular, so
    // that the Newton core does not cut an increment whose first tangent cannot change
    if (!(rel <= 1e-2)) res.singular = true;
    std::ostringstream os;
    os << "the direct solver (MUMPS) returned a solution with true relative residual " << rel
       << " (above the 1e-6 a Newton step accepts): the matrix is singular or nearly so; check the displacement "
          "boundary conditions";
    res.message = os.str();
    return res;
  }
  res.converged = true;
  return res;
}

}  // namespace iga
