#include "solver/hypre_preconditioner.hpp"

#include <stdexcept>
#include <vector>

#include <HYPRE.h>
#include <HYPRE_IJ_mv.h>
#include <HYPRE_parcsr_ls.h>
#include <Teuchos_DefaultMpiComm.hpp>

namespace iga {

namespace {

using Operator = Tpetra::Operator<SC, LO, GO, Node>;

class BoomerAMG : public Operator {
 public:
  BoomerAMG(const RCP<Matrix>& A, int functions) : map_(A->getRowMap()) {
    auto mpi = Teuchos::rcp_dynamic_cast<const Teuchos::MpiComm<int>>(A->getComm(), true);
    comm_ = (*mpi->getRawMpiComm())();
    static bool initialised = false;
    if (!initialised) {
      HYPRE_Init();
      initialised = true;
    }
    const LO n = static_cast<LO>(map_->getNodeNumElements());
    lo_ = static_cast<HYPRE_BigInt>(map_->getMinGlobalIndex());
    const HYPRE_BigInt hi = lo_ + n - 1;
    idx_.resize(n);
    for (LO i = 0; i < n; ++i) {
      idx_[i] = lo_ + i;
      // hypre's IJ interface wants each rank's rows as one range of global ids, in order
      if (map_->getGlobalElement(i) != static_cast<GO>(idx_[i]))
        throw std::runtime_error("BoomerAMG: this rank's rows are not one contiguous range of global ids");
    }
    buf_.resize(n);

    // the matrix, row by row with global column ids
    std::vector<HYPRE_Int> ncols(n);
    std::vector<HYPRE_BigInt> cols;
    std::vector<double> vals;
    cols.reserve(A->getNodeNumEntries());
    vals.reserve(A->getNodeNumEntries());
    {
      auto lcl = A->getLocalMatrixHost();
      auto colmap = A->getColMap();
      for (LO r = 0; r < n; ++r) {
        const auto b = lcl.graph.row_map(r), e = lcl.graph.row_map(r + 1);
        ncols[r] = static_cast<HYPRE_Int>(e - b);
        for (auto k = b; k < e; ++k) {
          cols.push_back(static_cast<HYPRE_BigInt>(colmap->getGlobalElement(lcl.graph.entries(k))));
          vals.push_back(lcl.values(k));
        }
      }
    }
    HYPRE_IJMatrixCreate(comm_, lo_, hi, lo_, hi, &ij_);
    HYPRE_IJMatrixSetObjectType(ij_, HYPRE_PARCSR);
    HYPRE_IJMatrixSetRowSizes(ij_, ncols.data());
    HYPRE_IJMatrixInitialize(ij_);
    HYPRE_IJMatrixSetValues(ij_, n, ncols.data(), idx_.data(), cols.data(), vals.data());
    HYPRE_IJMatrixAssemble(ij_);
    HYPRE_IJMatrixGetObject(ij_, reinterpret_cast<void**>(&A_));
    make_vector(&bij_, &b_);
    make_vector(&xij_, &x_);

    // Settings measured against MueLu on the wheel, the two blocks and the graded C0 block
    // (docs/performance.md, "BoomerAMG beside MueLu"): the unknown approach (the two
    // displacement components coarsened apart, interleaved dofs), strong threshold 0.8 (2-D
    // elasticity; 0.5 doubled the Krylov iterations on the wheel, 0.6 too), HMIS coarsening
    // with one level of aggressive coarsening (operator complexity low, set-up 3x cheaper),
    // extended+i interpolation truncated to 4 entries a row (operator complexity 1.31 on the
    // 77,380-dof wheel), l1-scaled hybrid symmetric Gauss-Seidel (symmetric: CG may use it).
    // Its sweeps are about half of a wheel run (perf); a forward sweep down and a backward one
    // up (relax types 13/14) cut one GMRES iteration from 29 to 18 ms but took 30 % more of
    // them: the whole run the same (5 pairs, ratio 0.99). Nodal coarsening with the rotation
    // added to the interpolation (Baker, Kolev and Yang 2010) took 7x the iterations.
    HYPRE_BoomerAMGCreate(&amg_);
    HYPRE_BoomerAMGSetPrintLevel(amg_, 0);
    HYPRE_BoomerAMGSetMaxIter(amg_, 1);
    HYPRE_BoomerAMGSetTol(amg_, 0.0);
    // 3-D: one function per displacement component as well; the strong threshold 0.5 that
    // hypre's documentation suggests for 3-D (0.8 was measured in 2-D only)
    HYPRE_BoomerAMGSetNumFunctions(amg_, functions);
    HYPRE_BoomerAMGSetStrongThreshold(amg_, functions == 3 ? 0.5 : 0.8);
    HYPRE_BoomerAMGSetCoarsenType(amg_, 10);
    HYPRE_BoomerAMGSetAggNumLevels(amg_, 1);
    HYPRE_BoomerAMGSetInterpType(amg_, 6);
    HYPRE_BoomerAMGSetPMaxElmts(amg_, 4);
    HYPRE_BoomerAMGSetRelaxType(amg_, 8);
    HYPRE_BoomerAMGSetup(amg_, A_, b_, x_);
  }

  ~BoomerAMG() override {
    HYPRE_BoomerAMGDestroy(amg_);
    HYPRE_IJVectorDestroy(bij_);
    HYPRE_IJVectorDestroy(xij_);
    HYPRE_IJMatrixDestroy(ij_);
  }

  RCP<const Map> getDomainMap() const override { return map_; }
  RCP<const Map> getRangeMap() const override { return map_; }

  void apply(const MultiVector& X, MultiVector& Y, Teuchos::ETransp = Teuchos::NO_TRANS, SC alpha = 1.0,
             SC beta = 0.0) const override {
    for (size_t j = 0; j < X.getNumVectors(); ++j) {
      set(bij_, *X.getVector(j));
      HYPRE_ParVectorSetConstantValues(x_, 0.0);
      HYPRE_BoomerAMGSolve(amg_, A_, b_, x_);
      HYPRE_IJVectorGetValues(xij_, static_cast<HYPRE_Int>(idx_.size()), idx_.data(), buf_.data());
      auto y = Y.getVectorNonConst(j);
      auto h = y->getLocalViewHost(Tpetra::Access::ReadWrite);
      for (size_t i = 0; i < idx_.size(); ++i) h(i, 0) = alpha * buf_[i] + (beta == 0.0 ? 0.0 : beta * h(i, 0));
    }
  }

 private:
  void make_vector(HYPRE_IJVector* v, HYPRE_ParVector* pv) const {
    const HYPRE_BigInt hi = lo_ + static_cast<HYPRE_BigInt>(idx_.size()) - 1;
    HYPRE_IJVectorCreate(comm_, lo_, hi, v);
    HYPRE_IJVectorSetObjectType(*v, HYPRE_PARCSR);
    HYPRE_IJVectorInitialize(*v);
    HYPRE_IJVectorAssemble(*v);
    HYPRE_IJVectorGetObject(*v, reinterpret_cast<void**>(pv));
  }

  void set(HYPRE_IJVector v, const Vector& src) const {
    auto h = src.getLocalViewHost(Tpetra::Access::ReadOnly);
    for (size_t i = 0; i < idx_.size(); ++i) buf_[i] = h(i, 0);
    HYPRE_IJVectorSetValues(v, static_cast<HYPRE_Int>(idx_.size()), idx_.data(), buf_.data());
  }

  RCP<const Map> map_;
  MPI_Comm comm_;
  HYPRE_BigInt lo_ = 0;
  std::vector<HYPRE_BigInt> idx_;
  mutable std::vector<double> buf_;
  HYPRE_IJMatrix ij_ = nullptr;
  HYPRE_ParCSRMatrix A_ = nullptr;
  HYPRE_IJVector bij_ = nullptr, xij_ = nullptr;
  HYPRE_ParVector b_ = nullptr, x_ = nullptr;
  HYPRE_Solver amg_ = nullptr;
};

}  // namespace

RCP<Tpetra::Operator<SC, LO, GO, Node>> hypre_boomeramg(const RCP<Matrix>& A, int functions) {
  return rcp(new BoomerAMG(A, functions));
}

}  // namespace iga
