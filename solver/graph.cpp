// The stiffness graph: 1-D coupling ranges of tensor-product patches, the overlap rows' CSR,
// and on several ranks the owned rows' global pattern and the ghost rows (System::owned_ghost).
#include "solver/system.hpp"
#include "solver/system_internal.hpp"

#include "kernels/numbering.hpp"

#include <Teuchos_TimeMonitor.hpp>

#include <algorithm>
#include <numeric>

namespace iga {

using namespace system_detail;

// 1-D coupling range of every control point index along direction d of a patch: the union of
// the supports [s - p, s] of the non-empty spans s in [i, i + p].
System::CouplingRange System::coupling_range(const Patch& pt, int d) {
  if (d >= pt.dim()) return CouplingRange{{0}, {0}};   // an unused direction: one index
  const auto spans = pt.element_spans(d);
  const int p = pt.degree[d], n = static_cast<int>(pt.knots[d].size()) - p - 1;
  CouplingRange r{std::vector<int>(n), std::vector<int>(n)};
  size_t first = 0, last = 0;
  for (int i = 0; i < n; ++i) {
    while (first < spans.size() && spans[first] < i) ++first;            // first span >= i
    while (last + 1 < spans.size() && spans[last + 1] <= i + p) ++last;  // last span <= i + p
    r.lo[i] = spans[first] - p;
    r.hi[i] = spans[last];
  }
  return r;
}

// Calls f(b, row, a') for every control point a' of patch block b coupled with a control point
// a that is a row here (row = row_of(b, a) >= 0), rows in patch order, a' with k' outer, then
// j', i' inner (so in increasing global id within a patch). A control point shared by patches gets
// its couplings from each of them (coupling_csr merges the repeats).
template <class RowOf, class F>
void System::for_each_coupling(RowOf row_of, F f) const {
  for (size_t b = 0; b < blocks_.size(); ++b) {
    const Patch& pt = P_.bodies[blocks_[b].body].patches[blocks_[b].patch];
    const CouplingRange r0 = coupling_range(pt, 0), r1 = coupling_range(pt, 1), r2 = coupling_range(pt, 2);
    const int n0 = static_cast<int>(r0.lo.size()), n1 = static_cast<int>(r1.lo.size()), n2 = static_cast<int>(r2.lo.size());
    for (int k = 0; k < n2; ++k)
      for (int j = 0; j < n1; ++j)
        for (int i = 0; i < n0; ++i) {
          const LO row = row_of(b, pt.index(i, j, k));
          if (row < 0) continue;
          for (int kk = r2.lo[k]; kk <= r2.hi[k]; ++kk)
            for (int jj = r1.lo[j]; jj <= r1.hi[j]; ++jj)
              for (int ii = r0.lo[i]; ii <= r0.hi[i]; ++ii) f(b, row, pt.index(ii, jj, kk));
        }
  }
}

// CSR of the dof rows dof_of(row_of(b, a), c, dim) (control point a of body b; -1: not a row
// here) with the columns dof_of(col_of(b, a'), c', dim) of the control points a' it couples
// with (-1: left out). Columns are sorted when col_of increases with the global id. Two passes
// (count, fill), no sorting; the other components' rows of a control point repeat its first.
template <class RowOf, class ColOf>
void System::coupling_csr(LO nrows, RowOf row_of, ColOf col_of, Teuchos::ArrayRCP<size_t>& rowptr,
                          Teuchos::ArrayRCP<LO>& cols) const {
  const int D = dim();
  rowptr = Teuchos::ArrayRCP<size_t>(D * nrows + 1, 0);
  for_each_coupling(row_of, [&](size_t b, LO row, int a) {
    if (col_of(b, a) >= 0) rowptr[dof_of(row, 0, D) + 1] += D;
  });
  for (LO r = 0; r < nrows; ++r) {
    for (int c = 1; c < D; ++c) rowptr[dof_of(r, c, D) + 1] = rowptr[dof_of(r, 0, D) + 1];   // as many as the first row
    for (int c = 0; c < D; ++c) rowptr[dof_of(r, c, D) + 1] += rowptr[dof_of(r, c, D)];
  }
  cols = Teuchos::ArrayRCP<LO>(rowptr[D * nrows]);
  std::vector<size_t> next(rowptr.begin(), rowptr.begin() + D * nrows);
  for_each_coupling(row_of, [&](size_t b, LO row, int a) {
    const LO c = col_of(b, a);
    if (c < 0) return;
    for (int d = 0; d < D; ++d) {
      size_t& k = next[dof_of(row, d, D)];
      for (int cc = 0; cc < D; ++cc) cols[k++] = dof_of(c, cc, D);
    }
  });
  // several patches: a control point on an interface couples through each of its patches,
  // and its rows hold columns more than once (and out of order): merge them
  if (merged_) {
    size_t out = 0, begin = 0;
    for (LO r = 0; r < D * nrows; ++r) {
      const size_t end = rowptr[r + 1];
      std::sort(cols.begin() + begin, cols.begin() + end);
      const auto last = std::unique(cols.begin() + begin, cols.begin() + end);
      for (auto it = cols.begin() + begin; it != last; ++it) cols[out++] = *it;
      begin = end;
      rowptr[r + 1] = out;
    }
    Teuchos::ArrayRCP<LO> packed(out);
    std::copy(cols.begin(), cols.begin() + out, packed.begin());
    cols = packed;
  }
}

// Several ranks: the global pattern of this rank's owned rows (columns: every control point
// coupled with an owned one, owned ones first in row order, as Tpetra's own column maps have
// it and Ifpack2's relaxation expects, then the others in increasing global id), and the ghost
// rows: control points this rank's elements touch but another rank owns, with the overlap
// numbering as columns. Per body and control point: owned row, owned column, ghost row.
std::unique_ptr<System::OwnedGhost> System::owned_ghost() const {
  auto og = std::make_unique<OwnedGhost>();
  const bool any = owned_->getNodeNumElements() > 0;
  const GO first = any ? point_of_dof(owned_->getMinGlobalIndex(), dim()) : 0,
           last = any ? point_of_dof(owned_->getMaxGlobalIndex(), dim()) + 1 : 0;
  auto owned_row = [&](size_t b, int a) -> LO {
    const GO g = blocks_[b].gid[a];
    return g >= first && g < last ? static_cast<LO>(g - first) : -1;
  };
  // mark the control points coupled with owned ones
  std::vector<LO> colpos(num_cps_, -1);
  for_each_coupling(owned_row, [&](size_t b, LO, int a) { colpos[blocks_[b].gid[a]] = 0; });
  std::vector<GO> dofs;
  auto add = [&](GO g) {
    colpos[g] = static_cast<LO>(dofs.size() / dim());   // control points so far
    for (int c = 0; c < dim(); ++c) dofs.push_back(dof_of(g, c, dim()));
  };
  for (GO g = first; g < last; ++g) add(g);
  for (GO g = 0; g < num_cps_; ++g)
    if (colpos[g] == 0 && (g < first || g >= last)) add(g);
  RCP<const Map> colmap = rcp(new Map(Teuchos::OrdinalTraits<Tpetra::global_size_t>::invalid(), dofs, 0, comm_));

  Teuchos::ArrayRCP<size_t> rowptr;
  Teuchos::ArrayRCP<LO> cols;
  coupling_csr(static_cast<LO>(last - first), owned_row,
               [&](size_t b, int a) { return colpos[blocks_[b].gid[a]]; }, rowptr, cols);
  // rows come out in global order: only those coupling control points owned below this
  // rank's (numbered after the owned ones) need sorting
  for (LO r = 0; r < dim() * static_cast<LO>(last - first); ++r)
    if (!std::is_sorted(cols.begin() + rowptr[r], cols.begin() + rowptr[r + 1]))
      std::sort(cols.begin() + rowptr[r], cols.begin() + rowptr[r + 1]);
  RCP<Graph> g = rcp(new Graph(owned_, colmap, rowptr, cols));
  g->fillComplete(owned_, owned_);
  og->owned = g;

  // ghost rows, in increasing global id (a control point shared by patches: one row)
  std::vector<GO> ghost_dofs;
  std::vector<std::vector<int>> grow(blocks_.size());
  {
    std::vector<GO> ghosts;
    for (size_t b = 0; b < blocks_.size(); ++b)
      for (size_t a = 0; a < blocks_[b].lid.size(); ++a)
        if (blocks_[b].lid[a] >= 0 && owned_row(b, static_cast<int>(a)) < 0) ghosts.push_back(blocks_[b].gid[a]);
    std::sort(ghosts.begin(), ghosts.end());
    ghosts.erase(std::unique(ghosts.begin(), ghosts.end()), ghosts.end());
    for (GO g : ghosts)
      for (int c = 0; c < dim(); ++c) ghost_dofs.push_back(dof_of(g, c, dim()));
    for (size_t b = 0; b < blocks_.size(); ++b) {
      const auto& lid = blocks_[b].lid;
      grow[b].assign(lid.size(), -1);
      for (size_t a = 0; a < lid.size(); ++a)
        if (lid[a] >= 0 && owned_row(b, static_cast<int>(a)) < 0)
          grow[b][a] = static_cast<int>(std::lower_bound(ghosts.begin(), ghosts.end(), blocks_[b].gid[a]) - ghosts.begin());
    }
  }
  og->ghost_map = rcp(new Map(Teuchos::OrdinalTraits<Tpetra::global_size_t>::invalid(), ghost_dofs, 0, comm_));
  coupling_csr(static_cast<LO>(ghost_dofs.size() / dim()), [&](size_t b, int a) { return grow[b][a]; },
               [&](size_t b, int a) { return blocks_[b].lid[a]; }, rowptr, cols);
  RCP<Graph> gg = rcp(new Graph(og->ghost_map, overlap_, rowptr, cols));
  gg->fillComplete(owned_, og->ghost_map);
  og->ghost = gg;
  og->exporter = rcp(new Export(og->ghost_map, owned_));
  for (size_t b = 0; b < blocks_.size(); ++b) {
    const size_t n = blocks_[b].lid.size();
    std::vector<int> orow(n), ocol(n);
    for (size_t a = 0; a < n; ++a) {
      orow[a] = owned_row(b, static_cast<int>(a));
      ocol[a] = colpos[blocks_[b].gid[a]];
    }
    og->orow.push_back(to_device("orow", orow));
    og->ocol.push_back(to_device("ocol", ocol));
    og->grow.push_back(to_device("grow", grow[b]));
  }
  return og;
}

RCP<const Graph> System::stiffness_graph() const {
  if (!graph_.is_null()) return graph_;
  // graph of the overlapping rows: control point couplings through shared elements
  Teuchos::TimeMonitor t1(*Teuchos::TimeMonitor::getNewTimer("2.1) Assembly: graph"));
  // On a tensor-product patch control points (i, j) and (i', j') share an element exactly when
  // i' lies in the 1-D coupling range [lo0(i), hi0(i)] of i and j' in [lo1(j), hi1(j)], the
  // union of the supports of the non-empty spans s in [i, i + p]: contiguous (coupling_csr).
  // One rank: the overlap rows are the owned rows. Several: the owned rows' global pattern and
  // the ghost rows (owned_ghost), built once.
  if (overlap_->isSameAs(*owned_)) {
    const LO nov = static_cast<LO>(overlap_->getNodeNumElements() / dim());
    Teuchos::ArrayRCP<size_t> rowptr;
    Teuchos::ArrayRCP<LO> cols;
    coupling_csr(nov, [&](size_t b, int a) { return blocks_[b].lid[a]; }, [&](size_t b, int a) { return blocks_[b].lid[a]; },
                 rowptr, cols);
    RCP<Graph> g = rcp(new Graph(overlap_, overlap_, rowptr, cols));
    g->fillComplete(owned_, owned_);
    graph_ = g;
  } else {
    if (!split_) split_ = owned_ghost();
    graph_ = split_->owned;
  }
  return graph_;
}


}  // namespace iga
