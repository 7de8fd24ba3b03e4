#include "solver/tangent.hpp"

#include <Teuchos_CommHelpers.hpp>
#include <Teuchos_TimeMonitor.hpp>

#include <algorithm>

namespace iga {

// The union of K_el's and K_c's patterns, row by row in global column ids (both have the owned
// row map), as a fill-complete graph; K_T = a matrix on it, with the entry map K_el -> K_T.
// Linear in the number of entries (Tpetra::MatrixMatrix::add took 0.25 s per call at 4.3e4
// dofs and dominated the run).
void TangentBuilder::rebuild(const RCP<Matrix>& K_c) {
  Teuchos::TimeMonitor tm(*Teuchos::TimeMonitor::getNewTimer("2c) Tangent: pattern rebuild"));
  ++rebuilds_;
  const auto& rows = *K_->getRowMap();
  const auto& ca = *K_->getColMap();
  auto A = K_->getLocalMatrixHost();
  const LO n = static_cast<LO>(A.numRows());
  // contact columns per local row of K_el (K_c's rows are few)
  std::vector<std::vector<GO>> extra(n);
  if (!K_c.is_null()) {
    auto B = K_c->getLocalMatrixHost();
    const auto& cb = *K_c->getColMap();
    const auto& rb = *K_c->getRowMap();
    for (LO r = 0; r < static_cast<LO>(B.numRows()); ++r) {
      if (B.graph.row_map(r + 1) == B.graph.row_map(r)) continue;
      const LO ra = rows.getLocalElement(rb.getGlobalElement(r));
      for (size_t k = B.graph.row_map(r); k < B.graph.row_map(r + 1); ++k)
        extra[ra].push_back(cb.getGlobalElement(B.graph.entries(k)));
    }
  }
  Teuchos::Array<size_t> count(n);
  std::vector<GO> cols;
  std::vector<std::vector<GO>> merged(n);
  for (LO r = 0; r < n; ++r) {
    if (extra[r].empty()) { count[r] = A.graph.row_map(r + 1) - A.graph.row_map(r); continue; }
    auto& m = merged[r];
    for (size_t k = A.graph.row_map(r); k < A.graph.row_map(r + 1); ++k) m.push_back(ca.getGlobalElement(A.graph.entries(k)));
    m.insert(m.end(), extra[r].begin(), extra[r].end());
    std::sort(m.begin(), m.end());
    m.erase(std::unique(m.begin(), m.end()), m.end());
    count[r] = m.size();
  }
  RCP<Graph> g = rcp(new Graph(K_->getRowMap(), count()));
  for (LO r = 0; r < n; ++r) {
    const GO gr = rows.getGlobalElement(r);
    if (merged[r].empty()) {
      cols.clear();
      for (size_t k = A.graph.row_map(r); k < A.graph.row_map(r + 1); ++k) cols.push_back(ca.getGlobalElement(A.graph.entries(k)));
      g->insertGlobalIndices(gr, static_cast<LO>(cols.size()), cols.data());
    } else {
      g->insertGlobalIndices(gr, static_cast<LO>(merged[r].size()), merged[r].data());
    }
  }
  g->fillComplete(K_->getDomainMap(), K_->getRangeMap());
  KT_ = rcp(new Matrix(g));
  // entry map K_el -> K_T (K_T's rows hold every column of K_el's rows; both sorted by local id)
  auto B = KT_->getLocalMatrixHost();
  const auto& cb = *KT_->getColMap();
  Kokkos::View<size_t*, MemSpace> map("tangent_map", A.nnz());
  auto h = Kokkos::create_mirror_view(map);
  for (LO r = 0; r < n; ++r) {
    const size_t b0 = B.graph.row_map(r), b1 = B.graph.row_map(r + 1);
    for (size_t k = A.graph.row_map(r); k < A.graph.row_map(r + 1); ++k) {
      const LO lb = cb.getLocalElement(ca.getGlobalElement(A.graph.entries(k)));
      size_t j = b0;
      while (j < b1 && B.graph.entries(j) != lb) ++j;
      h(k) = j;
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

void TangentBuilder::fill_values() {
  auto a = K_->getLocalMatrixDevice().values;
  auto b = KT_->getLocalMatrixDevice().values;
  auto map = map_;
  Kokkos::deep_copy(b, 0.0);
  Kokkos::parallel_for("iga::TangentCopy", Kokkos::RangePolicy<ExecSpace>(0, a.extent(0)),
                       KOKKOS_LAMBDA(const size_t k) { b(map(k)) = a(k); });
  Kokkos::fence();
}

RCP<Matrix> TangentBuilder::build(const RCP<Matrix>& K_c) {
  if (KT_.is_null()) rebuild(K_c);
  else KT_->resumeFill();
  fill_values();
  // all ranks must agree on rebuilding (a collective)
  int ok = K_c.is_null() ? 1 : (sum_into(*K_c) ? 1 : 0), all = 0;
  Teuchos::reduceAll(*KT_->getComm(), Teuchos::REDUCE_MIN, 1, &ok, &all);
  if (!all) {
    rebuild(K_c);   // the contact pattern grew: K_T's graph is the new union
    fill_values();
    if (!K_c.is_null()) sum_into(*K_c);
  }
  KT_->fillComplete(KT_->getDomainMap(), KT_->getRangeMap());
  return KT_;
}

}  // namespace iga
