#include "solver/direct_solver.hpp"

#include <dmumps_c.h>
#include <mpi.h>

#include <Teuchos_BLAS.hpp>
#include <Teuchos_DefaultMpiComm.hpp>
#include <Teuchos_LAPACK.hpp>
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

// below this estimate of 1 / cond_1(S) the Schur complement counts as singular
constexpr double kSchurMinRcond = 1e-13;

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
  // condensed solves (the header's "Condensed solves")
  std::vector<GO> cset;              // the set, sorted global indices (every rank)
  std::vector<int> cpos;             // global index -> position in cset, or -1 (every rank)
  std::vector<MUMPS_INT> listvar;    // cset 1-based (rank 0)
  bool schur_ok = false;             // the last factorisation has a factorised Schur complement
  bool own_order = false;            // the ordering of the whole matrix with the set last, not AMD's
  std::vector<double> S;             // rank 0: S (m x m, by columns), then its LU factors
  std::vector<int> ipiv;
  std::vector<long long> k0;         // rank 0: the factorised matrix's C x C block: i + m j of
  std::vector<double> v0;            // each entry (the upper triangle if symmetric), its value
  std::vector<int> slot;             // rank 0: position in C -> column of G, or -1
  std::vector<double> G;             // rank 0: the columns of S^-1 computed so far (m each)
  std::vector<double> redrhs;        // rank 0: the reduced right-hand side / the set's solution
  std::vector<MUMPS_INT> oi, oj;     // this rank's entries outside the C x C block at the
  std::vector<double> oa;            // factorisation, in for_each_entry's order
  int m() const { return static_cast<int>(cset.size()); }
  bool in_set(MUMPS_INT one_based) const { return cpos[one_based - 1] >= 0; }
  void gather_rhs(const Vector& b);
  void scatter_solution(Vector& x);
  int solve_schur(const std::vector<long long>& keys, const std::vector<double>& values, bool symmetric,
                  int& touched, int& fresh_columns);

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

void DirectSolver::set_condensed(const std::vector<GO>& dofs, bool own_order) {
  Impl& d = *d_;
  if (dofs == d.cset && own_order == d.own_order) return;
  // given up (a singular Schur complement): the set's size stays in the statistics
  if (dofs.empty() && !d.cset.empty()) stats_.condensed_fell_back = true;
  d.cset = dofs;
  d.own_order = own_order;
  d.cpos.clear();
  d.listvar.clear();
  d.schur_ok = false;
  d.analysed = d.factorised = false;   // MUMPS takes the Schur variables at the analysis
  if (!dofs.empty()) stats_.condensed_size = static_cast<int>(dofs.size());
}

namespace {

// f(row, column, value) for this rank's entries in global 1-based indices (the upper triangle
// if upper) in the rows keep(global row) accepts, row after row, in the order MUMPS is given
// them; stops where f returns false (then false)
template <class Keep, class F>
bool for_each_entry_of_rows(const Matrix& A, bool upper, const Keep& keep, const F& f) {
  auto lcl = A.getLocalMatrixHost();
  auto colmap = A.getColMap()->getLocalMap();
  auto lrow = A.getRowMap()->getLocalMap();
  for (LO r = 0; r < static_cast<LO>(lcl.numRows()); ++r) {
    const GO gr = lrow.getGlobalElement(r);
    if (!keep(gr)) continue;
    auto row = lcl.row(r);
    for (int k = 0; k < row.length; ++k) {
      const GO gc = colmap.getGlobalElement(row.colidx(k));
      if (upper && gc < gr) continue;
      if (!f(static_cast<MUMPS_INT>(gr + 1), static_cast<MUMPS_INT>(gc + 1), row.value(k))) return false;
    }
  }
  return true;
}

// every row's entries (the upper triangle if symmetric)
template <class F>
bool for_each_entry(const Matrix& A, bool symmetric, const F& f) {
  return for_each_entry_of_rows(A, symmetric, [](GO) { return true; }, f);
}

// the entries of the rows in the condensed set (cpos not -1)
template <class F>
bool for_each_entry_in_set_rows(const Matrix& A, const std::vector<int>& cpos, bool upper, const F& f) {
  return for_each_entry_of_rows(A, upper, [&](GO gr) { return cpos[static_cast<size_t>(gr)] >= 0; }, f);
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

  const bool condense = !d.cset.empty();
  if (condense && d.cpos.size() != static_cast<size_t>(nglobal)) {
    d.cpos.assign(static_cast<size_t>(nglobal), -1);
    d.listvar.clear();
    for (size_t k = 0; k < d.cset.size(); ++k) {
      d.cpos[static_cast<size_t>(d.cset[k])] = static_cast<int>(k);
      d.listvar.push_back(static_cast<MUMPS_INT>(d.cset[k] + 1));
    }
  }
  if (analyse) {
    Teuchos::TimeMonitor t(*timer("4a) Direct: entries and analysis"));
    ICNTL(d.id, 19) = 0;
    ICNTL(d.id, 7) = 7;
    d.id.size_schur = 0;
    d.id.listvar_schur = nullptr;
    d.id.perm_in = nullptr;
    d.schur_ok = false;
    d.irn = std::move(irn);
    d.jcn = std::move(jcn);
    d.n = static_cast<MUMPS_INT>(nglobal);
    d.id.n = d.n;
    d.id.nnz_loc = static_cast<MUMPS_INT8>(d.irn.size());
    d.id.irn_loc = d.irn.data();
    d.id.jcn_loc = d.jcn.data();
    // the Schur complement of the set (whole, ICNTL(19) = 3) on a 1 x 1 process grid (rank 0),
    // by columns, leading dimension m; MUMPS orders such an analysis by AMD
    auto ask_schur = [&] {
      ICNTL(d.id, 19) = 3;
      d.id.size_schur = d.m();
      d.id.listvar_schur = d.listvar.data();
      d.id.nprow = d.id.npcol = 1;
      d.id.mblock = d.id.nblock = std::max(1, d.m());
    };
    if (condense && !d.own_order) ask_schur();
    d.call(1);
    stats_.ordering = ordering_name(INFOG(d.id, 7));   // (own_order: the one the set's order follows)
    if (condense && d.own_order && INFOG(d.id, 1) >= 0) {
      // AMD, which MUMPS takes for a Schur analysis, fills far more in 3-D (the Hertz ball:
      // 71e6 entries in the factors, against 57e6 so): MUMPS' own choice for the whole matrix
      // (METIS, SCOTCH or PORD) with the set moved last is given instead (ICNTL(7) = 1)
      std::vector<MUMPS_INT> perm;
      if (d.rank == 0) {
        std::vector<std::pair<MUMPS_INT, MUMPS_INT>> order;   // (position, variable) outside the set
        order.reserve(static_cast<size_t>(d.n));
        for (MUMPS_INT v = 0; v < d.n; ++v)
          if (d.cpos[static_cast<size_t>(v)] < 0) order.emplace_back(d.id.sym_perm[v], v);
        std::sort(order.begin(), order.end());
        perm.assign(static_cast<size_t>(d.n), 0);
        MUMPS_INT next = 1;
        for (const auto& o : order) perm[static_cast<size_t>(o.second)] = next++;
        for (GO g : d.cset) perm[static_cast<size_t>(g)] = next++;
      }
      ICNTL(d.id, 7) = 1;
      d.id.perm_in = d.rank == 0 ? perm.data() : nullptr;
      ask_schur();
      d.call(1);
      d.id.perm_in = nullptr;
    }
    if (INFOG(d.id, 1) < 0) {
      d.analysed = false;
      res.message = mumps_message("analysis");
      return res;
    }
    d.analysed = true;
    d.factorised = false;
    ++stats_.analyses;
  }
  if (factorise) {
    Teuchos::TimeMonitor t(*timer("4b) Direct: factorisation"));
    const auto t0 = std::chrono::steady_clock::now();
    d.a = std::move(a);
    d.id.a_loc = d.a.data();
    d.factorised = false;
    d.schur_ok = false;
    if (condense) {
      if (d.rank == 0) d.S.assign(static_cast<size_t>(d.m()) * d.m(), 0.0);
      d.id.schur = d.rank == 0 ? d.S.data() : nullptr;
      d.id.schur_lld = d.m();
    }
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
    if (condense) {
      Teuchos::TimeMonitor t2(*timer("4c) Direct: Schur complement"));
      // the set's rows' entries in the other columns (A_CI), which a later matrix must repeat:
      // K_c has its entries in the set's rows and columns only, and the other rows are the
      // elastic stiffness's, constant at small strain (the caller's condition for a set)
      d.oi.clear(); d.oj.clear(); d.oa.clear();
      for_each_entry_in_set_rows(A, d.cpos, false, [&](MUMPS_INT i, MUMPS_INT j, double v) {
        if (!d.in_set(j)) {
          d.oi.push_back(i);
          d.oj.push_back(j);
          d.oa.push_back(v);
        }
        return true;
      });
      gather_block(A, symmetric, d.k0, d.v0);
      int info = 0;
      if (d.rank == 0) {
        if (d.id.schur_mloc != d.m() || d.id.schur_nloc != d.m()) throw std::logic_error("DirectSolver: MUMPS' Schur complement is not whole on rank 0");
        d.ipiv.assign(static_cast<size_t>(d.m()), 0);
        Teuchos::LAPACK<int, double> lapack;
        std::vector<double> work(4 * static_cast<size_t>(d.m()));
        std::vector<int> iwork(static_cast<size_t>(d.m()));
        double norm = 0;   // the 1-norm: the largest column sum of |S|
        for (size_t j = 0; j < static_cast<size_t>(d.m()); ++j) {
          double col = 0;
          for (size_t i = 0; i < static_cast<size_t>(d.m()); ++i) col += std::abs(d.S[i + j * static_cast<size_t>(d.m())]);
          norm = std::max(norm, col);
        }
        lapack.GETRF(d.m(), d.m(), d.S.data(), d.m(), d.ipiv.data(), &info);
        // a Schur complement singular to round-off (a body held by contact alone: its rigid
        // motions live in the set) is no use: the ordinary path then says the matrix is singular
        if (info == 0) {
          double rcond = 0;
          lapack.GECON('1', d.m(), d.S.data(), d.m(), norm, &rcond, work.data(), iwork.data(), &info);
          if (info == 0 && !(rcond > kSchurMinRcond)) info = 1;
        }
        d.slot.assign(static_cast<size_t>(d.m()), -1);
        d.G.clear();
      }
      MPI_Bcast(&info, 1, MPI_INT, 0, d.comm);
      d.schur_ok = info == 0;
      stats_.condensed_columns = 0;
    }
  }

  res.converged = true;
  return res;
}

// b gathered on rank 0 into MUMPS' right-hand side (the row map's contiguous blocks)
void DirectSolver::Impl::gather_rhs(const Vector& b) {
  Impl& d = *this;
  const auto rowmap = b.getMap();
  const int nloc = static_cast<int>(rowmap->getNodeNumElements());
  const int first = nloc > 0 ? static_cast<int>(rowmap->getGlobalElement(0)) : 0;
  if (d.rank == 0) {
    d.counts.assign(d.size, 0);
    d.displs.assign(d.size, 0);
    d.rhs.assign(d.n, 0.0);
  }
  MPI_Gather(&nloc, 1, MPI_INT, d.counts.data(), 1, MPI_INT, 0, d.comm);
  MPI_Gather(&first, 1, MPI_INT, d.displs.data(), 1, MPI_INT, 0, d.comm);
  auto bv = b.getLocalViewHost(Tpetra::Access::ReadOnly);
  MPI_Gatherv(bv.data(), nloc, MPI_DOUBLE, d.rhs.data(), d.counts.data(), d.displs.data(), MPI_DOUBLE, 0, d.comm);
  d.id.rhs = d.rank == 0 ? d.rhs.data() : nullptr;
  d.id.nrhs = 1;
  d.id.lrhs = d.n;
}

// MUMPS' solution on rank 0 scattered back onto x's map
void DirectSolver::Impl::scatter_solution(Vector& x) {
  Impl& d = *this;
  const int nloc = static_cast<int>(x.getMap()->getNodeNumElements());
  auto xv = x.getLocalViewHost(Tpetra::Access::OverwriteAll);
  MPI_Scatterv(d.rhs.data(), d.counts.data(), d.displs.data(), MPI_DOUBLE, xv.data(), nloc, MPI_DOUBLE, 0, d.comm);
}

bool DirectSolver::apply(const Vector& b, Vector& x) {
  Impl& d = *d_;
  if (!d.cset.empty()) return false;   // the factors are A_II's only: solve_condensed
  d.gather_rhs(b);
  d.call(3);
  // every rank learns the outcome (INFOG is global)
  if (INFOG(d.id, 1) < 0) return false;
  d.scatter_solution(x);
  ++stats_.solves;
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

  return check_residual(A, x, b, res);
}

// the true relative residual decides (a nearly singular matrix gives a solution that does not
// solve the system)
LinearSolveResult DirectSolver::check_residual(const Matrix& A, const Vector& x, const Vector& b,
                                               LinearSolveResult res) const {
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

// A's entries in the condensed set's rows and columns (the upper triangle if symmetric) on
// rank 0: key i + m j of positions in the set, and value, in the ranks' row order (collective)
void DirectSolver::gather_block(const Matrix& A, bool symmetric, std::vector<long long>& keys,
                                std::vector<double>& values) const {
  const Impl& d = *d_;
  const long long m = d.m();
  std::vector<double> mine;   // (key, value) pairs; keys below 2^53 (m <= kCondenseMaxDofs)
  for_each_entry_in_set_rows(A, d.cpos, symmetric, [&](MUMPS_INT i, MUMPS_INT j, double v) {
    const int pj = d.cpos[j - 1];
    if (pj >= 0) {
      mine.push_back(static_cast<double>(d.cpos[i - 1] + m * pj));
      mine.push_back(v);
    }
    return true;
  });
  const int count = static_cast<int>(mine.size());
  std::vector<int> counts(d.rank == 0 ? d.size : 0), displs(d.rank == 0 ? d.size : 0);
  MPI_Gather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, d.comm);
  std::vector<double> all;
  if (d.rank == 0) {
    int total = 0;
    for (int r = 0; r < d.size; ++r) {
      displs[r] = total;
      total += counts[r];
    }
    all.resize(static_cast<size_t>(total));
  }
  MPI_Gatherv(mine.data(), count, MPI_DOUBLE, all.data(), counts.data(), displs.data(), MPI_DOUBLE, 0, d.comm);
  if (d.rank != 0) return;
  keys.resize(all.size() / 2);
  values.resize(all.size() / 2);
  for (size_t k = 0; k < keys.size(); ++k) {
    keys[k] = static_cast<long long>(all[2 * k]);
    values[k] = all[2 * k + 1];
  }
}

bool DirectSolver::condensed_ready(const Matrix& A, bool symmetric) const {
  const Impl& d = *d_;
  Teuchos::TimeMonitor t(*Teuchos::TimeMonitor::getNewTimer("4d) Direct: unchanged outside the contact sides"));
  int local = !d.schur_ok || !d.factorised || symmetric != d.symmetric || d.cset.empty() ? 1 : 0;
  if (!local) {
    size_t k = 0;
    const size_t n = d.oa.size();
    const bool same = for_each_entry_in_set_rows(A, d.cpos, false, [&](MUMPS_INT i, MUMPS_INT j, double v) {
      if (d.in_set(j)) return true;
      if (k == n || d.oi[k] != i || d.oj[k] != j || d.oa[k] != v) return false;
      ++k;
      return true;
    });
    local = same && k == n ? 0 : 1;
  }
  int any = 0;
  MPI_Allreduce(&local, &any, 1, MPI_INT, MPI_MAX, d.comm);
  return any == 0;
}

// Rank 0: redrhs = y on entry, x_C = (S + D)^-1 y on return, D = the condensed block of A
// (keys, values) less the factorised one's, by the Woodbury identity on the dofs D touches;
// touched: how many, fresh_columns: the columns of S^-1 made for them. Returns LAPACK's info.
int DirectSolver::Impl::solve_schur(const std::vector<long long>& keys, const std::vector<double>& values,
                                    bool symmetric, int& touched, int& fresh_columns) {
  Impl& d = *this;
  const int m = d.m();
  int info = 0;
  Teuchos::LAPACK<int, double> lapack;
  Teuchos::BLAS<int, double> blas;
  const size_t M = static_cast<size_t>(m);
  // the update D = A_CC - A0_CC, entry by entry (the same pattern as at the factorisation
  // unless the tangent's graph was rebuilt since: then matched by key)
  std::vector<std::pair<long long, double>> D;
  if (keys == d.k0) {
    for (size_t k = 0; k < keys.size(); ++k)
      if (values[k] != d.v0[k]) D.emplace_back(keys[k], values[k] - d.v0[k]);
  } else {
    std::vector<std::pair<long long, double>> now, then;
    for (size_t k = 0; k < keys.size(); ++k) now.emplace_back(keys[k], values[k]);
    for (size_t k = 0; k < d.k0.size(); ++k) then.emplace_back(d.k0[k], -d.v0[k]);
    now.insert(now.end(), then.begin(), then.end());
    std::sort(now.begin(), now.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
    for (size_t k = 0; k < now.size();) {
      double sum = 0;
      size_t e = k;
      for (; e < now.size() && now[e].first == now[k].first; ++e) sum += now[e].second;
      if (sum != 0) D.emplace_back(now[k].first, sum);
      k = e;
    }
  }
  // the dofs whose rows or columns D touches, and their place among them
  std::vector<int> place(M, -1), act;
  for (const auto& e : D)
    for (long long p : {e.first % m, e.first / m})
      if (place[static_cast<size_t>(p)] < 0) {
        place[static_cast<size_t>(p)] = 0;
        act.push_back(static_cast<int>(p));
      }
  std::sort(act.begin(), act.end());
  for (size_t k = 0; k < act.size(); ++k) place[static_cast<size_t>(act[k])] = static_cast<int>(k);
  const int a = static_cast<int>(act.size());
  touched = a;
  // z = S^-1 y
  lapack.GETRS('N', m, 1, d.S.data(), m, d.ipiv.data(), d.redrhs.data(), m, &info);
  if (info == 0 && a > 0) {
    // the columns of S^-1 of the touched dofs not computed yet
    std::vector<int> fresh;
    for (int p : act)
      if (d.slot[static_cast<size_t>(p)] < 0) fresh.push_back(p);
    if (!fresh.empty()) {
      const size_t old = d.G.size();
      const int first = static_cast<int>(old / M);
      d.G.resize(old + fresh.size() * M, 0.0);
      for (size_t k = 0; k < fresh.size(); ++k) {
        d.G[old + k * M + static_cast<size_t>(fresh[k])] = 1.0;
        d.slot[static_cast<size_t>(fresh[k])] = first + static_cast<int>(k);
      }
      lapack.GETRS('N', m, static_cast<int>(fresh.size()), d.S.data(), m, d.ipiv.data(), d.G.data() + old, m, &info);
      fresh_columns = static_cast<int>(fresh.size());
    }
    if (info == 0) {
      // W = I + D_AA G_AA, w = D_AA z_A; solve W w' = w; x_C = z - G_A w'
      const size_t A_ = static_cast<size_t>(a);
      std::vector<double> Daa(A_ * A_, 0.0), Gaa(A_ * A_), W(A_ * A_, 0.0), w(A_, 0.0);
      for (const auto& e : D) {
        const size_t r = static_cast<size_t>(place[static_cast<size_t>(e.first % m)]);
        const size_t c = static_cast<size_t>(place[static_cast<size_t>(e.first / m)]);
        Daa[r + c * A_] = e.second;
        if (symmetric) Daa[c + r * A_] = e.second;   // (the upper triangle was gathered)
      }
      for (size_t c = 0; c < A_; ++c) {
        const double* gcol = d.G.data() + static_cast<size_t>(d.slot[static_cast<size_t>(act[c])]) * M;
        for (size_t r = 0; r < A_; ++r) Gaa[r + c * A_] = gcol[static_cast<size_t>(act[r])];
        W[c + c * A_] = 1.0;
      }
      blas.GEMM(Teuchos::NO_TRANS, Teuchos::NO_TRANS, a, a, a, 1.0, Daa.data(), a, Gaa.data(), a, 1.0, W.data(), a);
      std::vector<double> zA(A_);
      for (size_t r = 0; r < A_; ++r) zA[r] = d.redrhs[static_cast<size_t>(act[r])];
      blas.GEMV(Teuchos::NO_TRANS, a, a, 1.0, Daa.data(), a, zA.data(), 1, 0.0, w.data(), 1);
      std::vector<int> piv(A_);
      lapack.GESV(a, 1, W.data(), a, piv.data(), w.data(), a, &info);
      if (info == 0)
        for (size_t c = 0; c < A_; ++c)
          blas.AXPY(m, -w[c], d.G.data() + static_cast<size_t>(d.slot[static_cast<size_t>(act[c])]) * M, 1,
                    d.redrhs.data(), 1);
    }
  }
  return info;
}

LinearSolveResult DirectSolver::solve_condensed(const Matrix& A, Vector& x, const Vector& b, bool symmetric) {
  Impl& d = *d_;
  LinearSolveResult res;
  res.iterations = 1;
  std::vector<long long> keys;
  std::vector<double> values;
  Teuchos::TimeMonitor t(*Teuchos::TimeMonitor::getNewTimer("5) Linear solve"));
  {
    Teuchos::TimeMonitor tq(*Teuchos::TimeMonitor::getNewTimer("5.2) Linear solve: condensed, Schur update"));
    gather_block(A, symmetric, keys, values);
  }
  const int m = d.m();
  auto failed = [&](const std::string& what) {
    res.message = "the direct solver (MUMPS, condensed onto the contact sides) failed in the " + what;
    return res;
  };
  // reduction: the Schur system's right-hand side y = b_C - A_CI A_II^-1 b_I
  d.gather_rhs(b);
  if (d.rank == 0) d.redrhs.assign(static_cast<size_t>(m), 0.0);
  d.id.redrhs = d.rank == 0 ? d.redrhs.data() : nullptr;
  d.id.lredrhs = m;
  ICNTL(d.id, 26) = 1;
  { Teuchos::TimeMonitor tq(*Teuchos::TimeMonitor::getNewTimer("5.1) Linear solve: condensed, reduction")); d.call(3); }
  ICNTL(d.id, 26) = 0;
  if (INFOG(d.id, 1) < 0) return failed("reduction: INFOG(1) = " + std::to_string(INFOG(d.id, 1)));
  int info = 0, rank_d = 0, fresh_columns = 0;
  {
    Teuchos::TimeMonitor tq(*Teuchos::TimeMonitor::getNewTimer("5.2) Linear solve: condensed, Schur update"));
    if (d.rank == 0) info = d.solve_schur(keys, values, symmetric, rank_d, fresh_columns);
  }
  {
    int out[3] = {info, rank_d, fresh_columns};   // every rank learns the outcome and the counts
    MPI_Bcast(out, 3, MPI_INT, 0, d.comm);
    info = out[0], rank_d = out[1], fresh_columns = out[2];
  }
  if (info != 0) return failed("update of the Schur complement: LAPACK info = " + std::to_string(info));
  stats_.condensed_rank = std::max(stats_.condensed_rank, rank_d);
  stats_.condensed_columns += fresh_columns;
  // expansion: x_I = A_II^-1 (b_I - A_IC x_C), the whole solution on rank 0
  ICNTL(d.id, 26) = 2;
  { Teuchos::TimeMonitor tq(*Teuchos::TimeMonitor::getNewTimer("5.3) Linear solve: condensed, expansion")); d.call(3); }
  ICNTL(d.id, 26) = 0;
  if (INFOG(d.id, 1) < 0) return failed("expansion: INFOG(1) = " + std::to_string(INFOG(d.id, 1)));
  d.scatter_solution(x);
  ++stats_.solves;
  ++stats_.condensed_solves;
  Teuchos::TimeMonitor tq4(*Teuchos::TimeMonitor::getNewTimer("5.4) Linear solve: condensed, true residual"));
  return check_residual(A, x, b, res);
}

}  // namespace iga
