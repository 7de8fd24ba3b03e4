#include "solver/tangent.hpp"

#include <TpetraExt_MatrixMatrix.hpp>

#include <algorithm>

namespace iga {

void TangentBuilder::rebuild(const RCP<Matrix>& K_c) {
  ++rebuilds_;
  KT_ = K_c.is_null() ? Tpetra::MatrixMatrix::add(1.0, false, *K_, 0.0, false, *K_)
                      : Tpetra::MatrixMatrix::add(1.0, false, *K_, 1.0, false, *K_c);
  // entry map K_el -> K_T (same row map; rows of K_T hold every column of K_el's rows)
  auto A = K_->getLocalMatrixHost();
  auto B = KT_->getLocalMatrixHost();
  const auto& ca = *K_->getColMap();
  const auto& cb = *KT_->getColMap();
  Kokkos::View<size_t*, MemSpace> map("tangent_map", A.nnz());
  auto h = Kokkos::create_mirror_view(map);
  for (int r = 0; r < static_cast<int>(A.numRows()); ++r) {
    const size_t b0 = B.graph.row_map(r), b1 = B.graph.row_map(r + 1);
    for (size_t k = A.graph.row_map(r); k < A.graph.row_map(r + 1); ++k) {
      const LO lb = cb.getLocalElement(ca.getGlobalElement(A.graph.entries(k)));
      size_t j = b0;
      while (j < b1 && B.graph.entries(j) != lb) ++j;
      h(k) = j;  // always found: K_T's pattern contains K_el's
    }
  }
  Kokkos::deep_copy(map, h);
  map_ = map;
}

bool TangentBuilder::sum_into(const Matrix& K_c) {
  const auto& rows = *K_c.getRowMap();
  for (size_t l = 0; l < K_c.getNodeNumRows(); ++l) {
    typename Matrix::global_inds_host_view_type cols;
    typename Matrix::values_host_view_type vals;
    const GO g = rows.getGlobalElement(static_cast<LO>(l));
    const size_t n = K_c.getNumEntriesInGlobalRow(g);
    if (n == 0) continue;
    typename Matrix::nonconst_global_inds_host_view_type gc("cols", n);
    typename Matrix::nonconst_values_host_view_type gv("vals", n);
    size_t got = 0;
    K_c.getGlobalRowCopy(g, gc, gv, got);
    const LO summed = KT_->sumIntoGlobalValues(g, static_cast<LO>(got), gv.data(), gc.data());
    if (summed != static_cast<LO>(got)) return false;
  }
  return true;
}

RCP<Matrix> TangentBuilder::build(const RCP<Matrix>& K_c) {
  if (KT_.is_null()) {
    rebuild(K_c);
    return KT_;
  }
  KT_->resumeFill();
  {
    auto a = K_->getLocalMatrixDevice().values;
    auto b = KT_->getLocalMatrixDevice().values;
    auto map = map_;
    Kokkos::deep_copy(b, 0.0);
    Kokkos::parallel_for("iga::TangentCopy", Kokkos::RangePolicy<ExecSpace>(0, a.extent(0)),
                         KOKKOS_LAMBDA(const size_t k) { b(map(k)) = a(k); });
    Kokkos::fence();
  }
  // all ranks must agree on rebuilding (a collective)
  int ok = K_c.is_null() ? 1 : (sum_into(*K_c) ? 1 : 0), all = 0;
  Teuchos::reduceAll(*KT_->getComm(), Teuchos::REDUCE_MIN, 1, &ok, &all);
  KT_->fillComplete(KT_->getDomainMap(), KT_->getRangeMap());
  if (!all) rebuild(K_c);
  return KT_;
}

}  // namespace iga
