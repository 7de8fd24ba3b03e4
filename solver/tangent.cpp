#include "solver/tangent.hpp"

#include <Teuchos_CommHelpers.hpp>
#include <Teuchos_TimeMonitor.hpp>

#include <algorithm>
#include <unordered_map>

namespace iga {

// The union of K_el's and K_c's patterns, built in local indices: K_T's column map is K_el's
// followed by the few contact columns K_el's lacks, each row of K_T merges K_el's sorted local
// columns with the contact ones, and the merge gives the entry map K_el -> K_T. Linear in the
// entries, with hash lookups only for K_c's entries (the global-index graph + fillComplete
// used before spent most of its time hashing every entry of K_el; Tpetra::MatrixMatrix::add
// before that took 0.25 s per call at 4.3e4 dofs).
void TangentBuilder::rebuild(const RCP<Matrix>& K_c) {
  Teuchos::TimeMonitor tm(*Teuchos::TimeMonitor::getNewTimer("2c) Tangent: pattern rebuild"));
  ++rebuilds_;
  const auto& rows = *K_->getRowMap();
  const RCP<const Map> colA = K_->getColMap();
  TEUCHOS_TEST_FOR_EXCEPTION(!K_->getCrsGraph()->isSorted(), std::logic_error,
                             "TangentBuilder: K_el's rows must hold sorted local column indices");
  auto A = K_->getLocalMatrixHost();
  const LO n = static_cast<LO>(A.numRows());
  const LO ncA = static_cast<LO>(colA->getNodeNumElements());
  // contact couplings (row, column) in K_el's local ids; columns K_el's column map lacks
  // are numbered ncA, ncA + 1, ...
  std::vector<std::pair<LO, LO>> extra;
  std::vector<GO> newcols;
  std::unordered_map<GO, LO> newlid;
  if (!K_c.is_null()) {
    auto B = K_c->getLocalMatrixHost();
    const auto& cb = *K_c->getColMap();
    const auto& rb = *K_c->getRowMap();
    for (LO r = 0; r < static_cast<LO>(B.numRows()); ++r) {
      if (B.graph.row_map(r + 1) == B.graph.row_map(r)) continue;
      const LO ra = rows.getLocalElement(rb.getGlobalElement(r));
      for (size_t k = B.graph.row_map(r); k < B.graph.row_map(r + 1); ++k) {
        const GO gc = cb.getGlobalElement(B.graph.entries(k));
        LO lc = colA->getLocalElement(gc);
        if (lc == Teuchos::OrdinalTraits<LO>::invalid()) {
          const auto it = newlid.emplace(gc, ncA + static_cast<LO>(newcols.size()));
          if (it.second) newcols.push_back(gc);
          lc = it.first->second;
        }
        extra.emplace_back(ra, lc);
      }
    }
    std::sort(extra.begin(), extra.end());
    extra.erase(std::unique(extra.begin(), extra.end()), extra.end());
  }
  // contact couplings K_el lacks (rows are sorted): K_T's entry count
  const auto in_A = [&](LO r, LO c) {
    const LO* cols = A.graph.entries.data();
    return std::binary_search(cols + A.graph.row_map(r), cols + A.graph.row_map(r + 1), c);
  };
  size_t nnz = A.nnz();
  for (const auto& rc : extra) nnz += in_A(rc.first, rc.second) ? 0 : 1;
  // Nothing new on any rank (no contact, or contact inside K_el's pattern): K_T shares K_el's
  // graph and takes its values by one copy (no graph build, no fillComplete of a new graph).
  int grows = nnz > A.nnz() ? 1 : 0, any_grows = 0;
  Teuchos::reduceAll(*K_->getComm(), Teuchos::REDUCE_MAX, 1, &grows, &any_grows);
  if (!any_grows) {
    KT_ = rcp(new Matrix(K_->getCrsGraph()));
    return;
  }
  // row-wise merge; map(k) = position in K_T of K_el's entry k
  using local_graph = Graph::local_graph_device_type;
  typename local_graph::row_map_type::non_const_type ptr(Kokkos::view_alloc(Kokkos::WithoutInitializing, "tangent_rowptr"), n + 1);
  typename local_graph::entries_type::non_const_type ind(Kokkos::view_alloc(Kokkos::WithoutInitializing, "tangent_colind"), nnz);
  Kokkos::View<size_t*, MemSpace> map(Kokkos::view_alloc(Kokkos::WithoutInitializing, "tangent_map"), A.nnz());
  auto hp = Kokkos::create_mirror_view(ptr);
  auto hi = Kokkos::create_mirror_view(ind);
  auto hm = Kokkos::create_mirror_view(map);
  size_t e = 0, out = 0;
  for (LO r = 0; r < n; ++r) {
    hp(r) = out;
    size_t k = A.graph.row_map(r);
    const size_t kend = A.graph.row_map(r + 1);
    while (k < kend || (e < extra.size() && extra[e].first == r)) {
      const bool has_e = e < extra.size() && extra[e].first == r;
      if (k < kend && (!has_e || A.graph.entries(k) <= extra[e].second)) {
        if (has_e && A.graph.entries(k) == extra[e].second) ++e;
        hm(k) = out;
        hi(out++) = A.graph.entries(k++);
      } else {
        hi(out++) = extra[e++].second;
      }
    }
  }
  hp(n) = out;
  Kokkos::deep_copy(ptr, hp);
  Kokkos::deep_copy(ind, hi);
  Kokkos::deep_copy(map, hm);
  // column map: K_el's, or K_el's columns followed by the new ones (Map construction is
  // collective: every rank takes the same branch). fillComplete, not expertStaticFillComplete:
  // with the latter Ifpack2's Gauss-Seidel and MueLu ran 1.4-1.8x slower on K_T (measured at
  // 1.7e5 dofs), the graph lacking what fillComplete sets up.
  RCP<const Map> colT = colA;
  int mine = newcols.empty() ? 0 : 1, any = 0;
  Teuchos::reduceAll(*K_->getComm(), Teuchos::REDUCE_MAX, 1, &mine, &any);
  if (any) {
    std::vector<GO> gids(colA->getNodeElementList().begin(), colA->getNodeElementList().end());
    gids.insert(gids.end(), newcols.begin(), newcols.end());
    colT = rcp(new Map(Teuchos::OrdinalTraits<Tpetra::global_size_t>::invalid(),
                       Teuchos::ArrayView<const GO>(gids.data(), gids.size()), colA->getIndexBase(), K_->getComm()));
  }
  RCP<Graph> g = rcp(new Graph(K_->getRowMap(), colT, ptr, ind));
  g->fillComplete(K_->getDomainMap(), K_->getRangeMap());
  KT_ = rcp(new Matrix(g));
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
    // K_c's pattern is reserved wider than its values (contact.cpp): only nonzeros must fit
    size_t nz = 0;
    for (size_t k = 0; k < got; ++k)
      if (gv(k) != 0.0) { gc(nz) = gc(k); gv(nz) = gv(k); ++nz; }
    const LO summed = KT_->sumIntoGlobalValues(g, static_cast<LO>(nz), gv.data(), gc.data());
    if (summed != static_cast<LO>(nz)) return false;
  }
  return true;
}

void TangentBuilder::fill_values() {
  auto a = K_->getLocalMatrixDevice().values;
  auto b = KT_->getLocalMatrixDevice().values;
  if (KT_->getCrsGraph() == K_->getCrsGraph()) {   // K_T on K_el's graph: the same entries
    Kokkos::deep_copy(b, a);
    return;
  }
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
