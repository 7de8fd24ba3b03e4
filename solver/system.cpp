#include "solver/system.hpp"

#include "model/quadrature.hpp"

#include <Teuchos_TimeMonitor.hpp>
#include <Tpetra_Details_makeColMap.hpp>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "kernels/boundary_load.hpp"
#include "kernels/elasticity.hpp"
#include "kernels/elasticity_sf.hpp"

namespace iga {

namespace {

template <class T>
Kokkos::View<T*, MemSpace> to_device(const std::string& name, const std::vector<T>& v) {
  Kokkos::View<T*, MemSpace> d(name, v.size());
  auto h = Kokkos::create_mirror_view(d);
  for (size_t k = 0; k < v.size(); ++k) h(k) = v[k];
  Kokkos::deep_copy(d, h);
  return d;
}

// Degrees, basis functions and elements per direction: the part of the kernels' patch data
// that is the same on the device and on the host.
template <class PD>
void set_patch_shape(PD& pd, const Patch& P) {
  for (int d = 0; d < 2; ++d) {
    pd.p[d] = P.degree[d];
    pd.n[d] = P.ncp(d);
    pd.ne[d] = static_cast<int>(P.element_spans(d).size());
  }
}

PatchData make_patch_data(const Patch& P) {
  PatchData pd;
  set_patch_shape(pd, P);
  pd.U[0] = to_device("U0", P.knots[0]);
  pd.U[1] = to_device("U1", P.knots[1]);
  pd.span[0] = to_device("span0", P.element_spans(0));
  pd.span[1] = to_device("span1", P.element_spans(1));
  Kokkos::View<double* [3], MemSpace> cp("cp", P.cp.size());
  auto h = Kokkos::create_mirror_view(cp);
  for (size_t a = 0; a < P.cp.size(); ++a)
    for (int c = 0; c < 3; ++c) h(a, c) = P.cp[a][c];
  Kokkos::deep_copy(cp, h);
  pd.cp = cp;
  return pd;
}

// The element rule of the patch (solver.quadrature): Gauss leaves PatchData's rule empty
// (the kernels map the Gauss rule onto each span); spline puts each direction's generalised
// Gaussian rule there, or keeps Gauss in a direction where it cannot be built.
void set_quadrature(PatchBlock& bd, const Patch& pt, Quadrature q) {
  int nodes[2];
  std::string what[2];
  for (int d = 0; d < 2; ++d) {
    nodes[d] = static_cast<int>(pt.element_spans(d).size()) * (pt.degree[d] + 1);
    what[d] = "gauss";
    if (q != Quadrature::Spline) continue;
    const SplineRule r = spline_gauss_rule(pt.knots[d], pt.degree[d]);
    if (!r.failure.empty()) {
      what[d] = "gauss (the spline rule: " + r.failure + ")";
      continue;
    }
    what[d] = "spline";
    nodes[d] = static_cast<int>(r.x.size());
    bd.pd.qx[d] = to_device(d == 0 ? "qx0" : "qx1", r.x);
    bd.pd.qw[d] = to_device(d == 0 ? "qw0" : "qw1", r.w);
    bd.pd.qoff[d] = to_device(d == 0 ? "qoff0" : "qoff1", r.off);
  }
  bd.quadrature_points = nodes[0] * nodes[1];
  bd.quadrature = what[0] == what[1] ? what[0] : what[0] + " x " + what[1];
}

}  // namespace

Material body_material(const Problem& P, int b, double thickness) {
  const Body& body = P.bodies[b];
  if (P.kinematics == Kinematics::Small)
    return Material::plane(body.E, body.nu, P.analysis == Analysis::PlaneStrain, thickness);
  return Material::finite(body.model == MaterialModel::NeoHookean ? Material::kNeoHookean : Material::kSaintVenantKirchhoff,
                          body.E, body.nu, thickness);
}

System::System(const Problem& problem, RCP<const Comm> comm) : P_(problem), comm_(comm) {
  const int rank = comm_->getRank(), size = comm_->getSize();
  long long num_elements = 0;
  for (size_t b = 0; b < P_.bodies.size(); ++b) {
    const Body& body = P_.bodies[b];
    body_offset_.push_back(num_cps_);
    materials_.push_back(body_material(P_, static_cast<int>(b), P_.thickness));
    cp_pos_.resize(num_cps_ + body.num_cps);
    for (size_t k = 0; k < body.patches.size(); ++k) {
      const Patch& pt = body.patches[k];
      PatchBlock bd;
      bd.pd = make_patch_data(pt);
      set_quadrature(bd, pt, P_.quadrature);
      bd.body = static_cast<int>(b);
      bd.patch = static_cast<int>(k);
      bd.orientation = pt.orientation();
      bd.mat = materials_.back();
      bd.gid.resize(pt.cp.size());
      for (size_t a = 0; a < pt.cp.size(); ++a) {
        bd.gid[a] = num_cps_ + body.cp_index[k][a];
        cp_pos_[bd.gid[a]] = pt.cp[a];
      }
      num_elements += pt.num_elements();
      blocks_.push_back(std::move(bd));
    }
    num_cps_ += body.num_cps;
    size_t total = 0;
    for (const Patch& pt : body.patches) total += pt.cp.size();
    merged_ = merged_ || total != static_cast<size_t>(body.num_cps);
  }
  // owned control points: a contiguous block per rank; dofs 2g, 2g+1
  const auto cpr = block_range(num_cps_, rank, size);
  std::vector<GO> owned;
  owned.reserve(2 * (cpr.second - cpr.first));
  for (GO g = cpr.first; g < cpr.second; ++g) { owned.push_back(2 * g); owned.push_back(2 * g + 1); }
  owned_ = rcp(new Map(Teuchos::OrdinalTraits<Tpetra::global_size_t>::invalid(), owned, 0, comm_));

  // elements: a contiguous block of the global element list (block after block) per rank
  const auto er = block_range(num_elements, rank, size);
  long long e0 = 0;
  std::vector<GO> touched;
  for (PatchBlock& bd : blocks_) {
    const Patch& pt = P_.bodies[bd.body].patches[bd.patch];
    const long long ne = pt.num_elements();
    bd.e_begin = static_cast<int>(std::clamp(er.first - e0, 0LL, ne));
    bd.e_end = static_cast<int>(std::clamp(er.second - e0, 0LL, ne));
    e0 += ne;
    const auto sp0 = pt.element_spans(0), sp1 = pt.element_spans(1);
    for (int e = bd.e_begin; e < bd.e_end; ++e) {
      const int s0 = sp0[e % sp0.size()], s1 = sp1[e / sp0.size()];
      for (int j = s1 - pt.degree[1]; j <= s1; ++j)
        for (int i = s0 - pt.degree[0]; i <= s0; ++i) touched.push_back(bd.gid[pt.index(i, j)]);
    }
  }
  std::sort(touched.begin(), touched.end());
  touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
  overlap_ = cp_dof_map(touched);
  for (PatchBlock& bd : blocks_) {
    const int ncp = static_cast<int>(bd.gid.size());
    std::vector<int> lid(ncp, -1);
    for (int a = 0; a < ncp; ++a) {
      const LO l = overlap_->getLocalElement(2 * bd.gid[a]);
      if (l != Teuchos::OrdinalTraits<LO>::invalid()) lid[a] = l / 2;
    }
    bd.pd.lid = to_device("lid", lid);
    bd.lid = std::move(lid);
  }

  // Dirichlet dofs owned here (sides, then corner points); a dof constrained by several is
  // reported under the first
  std::map<GO, DirichletDof> dd;
  auto constrain = [&](int blk, int slot, const SideCondition& sc, const std::vector<int>& cps) {
    for (int a : cps)
      for (int c = 0; c < 2; ++c)
        if (sc.fixed[c]) {
          const GO dof = 2 * blocks_[blk].gid[a] + c;
          if (owned_->isNodeGlobalElement(dof) && !dd.count(dof)) {
            std::vector<double> v;
            for (const auto& e : sc.value) v.push_back(e[c]);
            dd[dof] = DirichletDof{dof, blk, slot, v};
          }
        }
  };
  for (size_t k = 0; k < blocks_.size(); ++k) {
    const Body& body = P_.bodies[blocks_[k].body];
    const Patch& pt = body.patches[blocks_[k].patch];
    for (int s = 0; s < 4; ++s) constrain(static_cast<int>(k), s, body.sides[blocks_[k].patch][s], pt.side_indices(static_cast<Side>(s)));
  }
  for (size_t k = 0; k < blocks_.size(); ++k) {
    const Body& body = P_.bodies[blocks_[k].body];
    const Patch& pt = body.patches[blocks_[k].patch];
    for (int c = 0; c < 4; ++c)
      constrain(static_cast<int>(k), 4 + c, body.corners[blocks_[k].patch][c], {corner_index(pt, static_cast<Corner>(c))});
  }
  for (const auto& kv : dd) {
    dirichlet_.push_back(kv.second);
    dirichlet_lids_.push_back(owned_->getLocalElement(kv.first));
  }
}

RCP<const Map> System::cp_dof_map(const std::vector<GO>& cps, bool) const {
  std::vector<GO> dofs;
  dofs.reserve(2 * cps.size());
  for (GO g : cps) { dofs.push_back(2 * g); dofs.push_back(2 * g + 1); }
  return rcp(new Map(Teuchos::OrdinalTraits<Tpetra::global_size_t>::invalid(), dofs, 0, comm_));
}

RCP<Matrix> System::export_matrix(const RCP<Matrix>& overlap) const {
  if (overlap->getRowMap()->isSameAs(*owned_)) return overlap;
  Export exporter(overlap->getRowMap(), owned_);
  return Tpetra::exportAndFillCompleteCrsMatrix<Matrix>(overlap, exporter, owned_, owned_);
}

RCP<Vector> System::export_vector(const Vector& overlap) const {
  RCP<Vector> v = rcp(new Vector(owned_));
  Export exporter(overlap.getMap(), owned_);
  v->doExport(overlap, exporter, Tpetra::ADD);
  return v;
}

// 1-D coupling range of every control point index along direction d of a patch: the union of
// the supports [s - p, s] of the non-empty spans s in [i, i + p].
System::CouplingRange System::coupling_range(const Patch& pt, int d) {
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
// a that is a row here (row = row_of(b, a) >= 0), rows in patch order, a' with j' outer, i'
// inner (so in increasing global id within a patch). A control point shared by patches gets
// its couplings from each of them (coupling_csr merges the repeats).
template <class RowOf, class F>
void System::for_each_coupling(RowOf row_of, F f) const {
  for (size_t b = 0; b < blocks_.size(); ++b) {
    const Patch& pt = P_.bodies[blocks_[b].body].patches[blocks_[b].patch];
    const CouplingRange r0 = coupling_range(pt, 0), r1 = coupling_range(pt, 1);
    const int n0 = static_cast<int>(r0.lo.size()), n1 = static_cast<int>(r1.lo.size());
    for (int j = 0; j < n1; ++j)
      for (int i = 0; i < n0; ++i) {
        const LO row = row_of(b, pt.index(i, j));
        if (row < 0) continue;
        for (int jj = r1.lo[j]; jj <= r1.hi[j]; ++jj)
          for (int ii = r0.lo[i]; ii <= r0.hi[i]; ++ii) f(b, row, pt.index(ii, jj));
      }
  }
}

// CSR of the dof rows 2 row_of(b, a) + c (control point a of body b; -1: not a row here)
// with the columns 2 col_of(b, a') + c' of the control points a' it couples with (-1: left
// out). Columns are sorted when col_of increases with the global id. Two passes (count,
// fill), no sorting; the y row of a control point repeats its x row.
template <class RowOf, class ColOf>
void System::coupling_csr(LO nrows, RowOf row_of, ColOf col_of, Teuchos::ArrayRCP<size_t>& rowptr,
                          Teuchos::ArrayRCP<LO>& cols) const {
  rowptr = Teuchos::ArrayRCP<size_t>(2 * nrows + 1, 0);
  for_each_coupling(row_of, [&](size_t b, LO row, int a) {
    if (col_of(b, a) >= 0) rowptr[2 * row + 1] += 2;
  });
  for (LO r = 0; r < nrows; ++r) {
    rowptr[2 * r + 2] = rowptr[2 * r + 1];                  // y row: as many as the x row
    rowptr[2 * r + 1] += rowptr[2 * r];
    rowptr[2 * r + 2] += rowptr[2 * r + 1];
  }
  cols = Teuchos::ArrayRCP<LO>(rowptr[2 * nrows]);
  std::vector<size_t> next(rowptr.begin(), rowptr.begin() + 2 * nrows);
  for_each_coupling(row_of, [&](size_t b, LO row, int a) {
    const LO c = col_of(b, a);
    if (c < 0) return;
    for (int d = 0; d < 2; ++d) {
      size_t& k = next[2 * row + d];
      cols[k++] = 2 * c;
      cols[k++] = 2 * c + 1;
    }
  });
  // several patches: a control point on an interface couples through each of its patches,
  // and its rows hold columns more than once (and out of order): merge them
  if (merged_) {
    size_t out = 0, begin = 0;
    for (LO r = 0; r < 2 * nrows; ++r) {
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
  const GO first = any ? owned_->getMinGlobalIndex() / 2 : 0, last = any ? owned_->getMaxGlobalIndex() / 2 + 1 : 0;
  auto owned_row = [&](size_t b, int a) -> LO {
    const GO g = blocks_[b].gid[a];
    return g >= first && g < last ? static_cast<LO>(g - first) : -1;
  };
  // mark the control points coupled with owned ones
  std::vector<LO> colpos(num_cps_, -1);
  for_each_coupling(owned_row, [&](size_t b, LO, int a) { colpos[blocks_[b].gid[a]] = 0; });
  std::vector<GO> dofs;
  auto add = [&](GO g) {
    colpos[g] = static_cast<LO>(dofs.size() / 2);
    dofs.push_back(2 * g);
    dofs.push_back(2 * g + 1);
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
  for (LO r = 0; r < 2 * static_cast<LO>(last - first); ++r)
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
    for (GO g : ghosts) { ghost_dofs.push_back(2 * g); ghost_dofs.push_back(2 * g + 1); }
    for (size_t b = 0; b < blocks_.size(); ++b) {
      const auto& lid = blocks_[b].lid;
      grow[b].assign(lid.size(), -1);
      for (size_t a = 0; a < lid.size(); ++a)
        if (lid[a] >= 0 && owned_row(b, static_cast<int>(a)) < 0)
          grow[b][a] = static_cast<int>(std::lower_bound(ghosts.begin(), ghosts.end(), blocks_[b].gid[a]) - ghosts.begin());
    }
  }
  og->ghost_map = rcp(new Map(Teuchos::OrdinalTraits<Tpetra::global_size_t>::invalid(), ghost_dofs, 0, comm_));
  coupling_csr(static_cast<LO>(ghost_dofs.size() / 2), [&](size_t b, int a) { return grow[b][a]; },
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

RCP<Matrix> System::assemble_stiffness() const {
  RCP<Matrix> K;
  assemble_internal(nullptr, nullptr, &K);
  return K;
}

bool System::constant_tangent() const {
  for (const Material& m : materials_)
    if (!m.constant_tangent()) return false;
  return true;
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
    const LO nov = static_cast<LO>(overlap_->getNodeNumElements() / 2);
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

struct System::SumFactorCache {
  SumFactorPatch tables;
  Kokkos::View<double***, Kokkos::LayoutRight, MemSpace> C;
  Kokkos::View<double****, Kokkos::LayoutRight, MemSpace> U;
  Kokkos::View<double***, Kokkos::LayoutRight, MemSpace> Ac;
};

// One element loop for the internal force and the tangent of every material
// (kernels/elasticity.hpp, AssembleInternal): the small-strain stiffness is its tangent at any u.
// solver.formation: sum_factorized forms the tangent row by row instead
// (kernels/elasticity_sf.hpp, SumFactorizedTangent); the element loop then forms f_int only.
void System::assemble_internal(const Vector* u, Vector* f_int, RCP<Matrix>* K, const LoadPoint* lp) const {
  const bool one = overlap_->isSameAs(*owned_);
  const RCP<const Graph> graph = K ? stiffness_graph() : Teuchos::null;
  // displacements on the overlap (the control points this rank's elements touch)
  Kokkos::View<const double*, MemSpace> uv;
  if (u) {
    if (one) {
      uv = Kokkos::subview(u->getLocalViewDevice(Tpetra::Access::ReadOnly), Kokkos::ALL(), 0);
    } else {
      if (ov_import_.is_null()) {
        ov_import_ = rcp(new Import(owned_, overlap_));
        u_ov_ = rcp(new Vector(overlap_));
      }
      u_ov_->doImport(*u, *ov_import_, Tpetra::INSERT);
      uv = Kokkos::subview(u_ov_->getLocalViewDevice(Tpetra::Access::ReadOnly), Kokkos::ALL(), 0);
    }
  }
  RCP<Vector> f_ov;
  Kokkos::View<double*, MemSpace> fv;
  if (f_int) {
    if (!one && f_ov_.is_null()) f_ov_ = rcp(new Vector(overlap_));
    f_ov = one ? rcp(f_int, false) : f_ov_;
    f_ov->putScalar(0.0);
    fv = Kokkos::subview(f_ov->getLocalViewDevice(Tpetra::Access::ReadWrite), Kokkos::ALL(), 0);
  }
  RCP<Matrix> G;
  Teuchos::TimeMonitor t2(*Teuchos::TimeMonitor::getNewTimer(K ? "2.2) Assembly: element loop" : "2a) Internal force"));
  if (K) {
    if (K->is_null()) *K = rcp(new Matrix(graph));   // values allocated here, zeroed
    else {
      (*K)->resumeFill();
      (*K)->setAllToScalar(0.0);
    }
    if (!one) G = rcp(new Matrix(split_->ghost));
  }
  using Local = Matrix::local_matrix_device_type;
  Local lk, lg;
  if (K) lk = (*K)->getLocalMatrixDevice();
  if (G) lg = G->getLocalMatrixDevice();
  // rows whose local column indices ascend let sumIntoValues search them by bisection
  // (else linearly from the row's start wherever the last position is no hint): checked once
  const auto ascending = [](const Local& m) {
    auto ptr = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), m.graph.row_map);
    auto ind = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), m.graph.entries);
    for (size_t r = 0; r + 1 < ptr.extent(0); ++r)
      for (size_t k = ptr(r) + 1; k < ptr(r + 1); ++k)
        if (ind(k - 1) >= ind(k)) return 0;
    return 1;
  };
  if (K && graph_sorted_ < 0) graph_sorted_ = ascending(lk);
  if (G && ghost_sorted_ < 0) ghost_sorted_ = ascending(lg);
  const auto scatter = [&](size_t b) {
    ElementScatter<Local> sc;
    sc.A = lk;
    sc.sorted_A = graph_sorted_ == 1;
    if (!one) {
      sc.G = lg;
      sc.sorted_G = ghost_sorted_ == 1;
      sc.orow = split_->orow[b];
      sc.ocol = split_->ocol[b];
      sc.grow = split_->grow[b];
    }
    return sc;
  };
  for (size_t b = 0; b < blocks_.size(); ++b) {
    const PatchBlock& bd = blocks_[b];
    if (bd.e_end <= bd.e_begin) continue;
    const GaussRule g0 = gauss_rule(bd.pd.p[0] + 1), g1 = gauss_rule(bd.pd.p[1] + 1);
    const bool rows = K && P_.formation == Formation::SumFactorized;
    dispatch_degree(std::max(bd.pd.p[0], bd.pd.p[1]), [&](auto P) {
      AssembleInternal<decltype(P)::value, Local> k{bd.pd, bd.mat, g0, g1, bd.e_begin};
      k.u = uv;
      k.f = fv;
      k.force = f_int != nullptr;
      k.tangent = K != nullptr && !rows;
      if (k.tangent) k.scatter = scatter(b);
      if (k.force || k.tangent) k.run(bd.e_end);
      if (rows) {
        if (sum_factor_.size() != blocks_.size()) sum_factor_.resize(blocks_.size());
        if (!sum_factor_[b]) {
          sum_factor_[b] = std::make_shared<SumFactorCache>();
          sum_factor_[b]->tables = sum_factor_tables(bd.pd, g0, g1);
        }
        SumFactorCache& c = *sum_factor_[b];
        SumFactorizedTangent<decltype(P)::value, Local> s;
        s.pd = bd.pd;
        s.mat = bd.mat;
        s.t = c.tables.dev;
        s.e_begin = bd.e_begin;
        s.e_end = bd.e_end;
        s.scatter = scatter(b);
        s.u = uv;
        s.C = c.C;
        s.Uw = c.U;
        s.Ac = c.Ac;
        s.run(c.tables.host);
        c.C = s.C;
        c.U = s.Uw;
        c.Ac = s.Ac;
      }
    });
    // finite kinematics: pressures follow the deformed sides (kernels/boundary_load.hpp)
    if (lp && P_.kinematics == Kinematics::Finite)
      for (int side = 0; side < 4; ++side) {
        const SideCondition& sc = P_.bodies[bd.body].sides[bd.patch][side];
        if (sc.load != LoadKind::Pressure && sc.load != LoadKind::LinearPressure) continue;
        AssembleFollowerPressure<Local> k;
        k.pd = bd.pd;
        k.load.side = side;
        k.load.kind = 1;
        const auto at = [&](const std::vector<double>& v) {
          return (1.0 - lp->s) * (lp->stage > 0 ? v[lp->stage - 1] : 0.0) + lp->s * v[lp->stage];
        };
        k.load.p0 = at(sc.p0);
        k.load.p1 = at(sc.p1);
        k.load.scale = P_.thickness;
        k.load.orientation = bd.orientation;
        const int d = side <= 1 ? 1 : 0;
        k.g = gauss_rule(bd.pd.p[d] + 1);
        k.e_begin = bd.e_begin;
        k.e_end = bd.e_end;
        k.u = uv;
        k.f = fv;
        k.force = f_int != nullptr;
        k.tangent = K != nullptr;
        if (K) k.scatter = scatter(b);
        Kokkos::parallel_for("iga::AssembleFollowerPressure", Kokkos::RangePolicy<ExecSpace>(0, bd.pd.ne[d]), k);
      }
  }
  Kokkos::fence();
  fv = {};
  uv = {};
  if (f_int && !one) {
    if (ov_export_.is_null()) ov_export_ = rcp(new Export(overlap_, owned_));
    f_int->putScalar(0.0);
    f_int->doExport(*f_ov, *ov_export_, Tpetra::ADD);
  }
  if (K) {
    // several ranks: sum the ghost rows into their owners' rows (static graphs: values only)
    Teuchos::TimeMonitor t3(*Teuchos::TimeMonitor::getNewTimer("2.3) Assembly: fillComplete + export"));
    lk = {};
    lg = {};
    if (!one) {
      G->fillComplete(owned_, split_->ghost_map);
      (*K)->doExport(*G, *split_->exporter, Tpetra::ADD);
    }
    (*K)->fillComplete(owned_, owned_);
  }
}

HostPatchData host_patch_data(const Patch& P) {
  HostPatchData pd;
  set_patch_shape(pd, P);
  pd.U[0] = Kokkos::View<const double*, Kokkos::HostSpace>(P.knots[0].data(), P.knots[0].size());
  pd.U[1] = Kokkos::View<const double*, Kokkos::HostSpace>(P.knots[1].data(), P.knots[1].size());
  pd.cp = Kokkos::View<const double* [3], Kokkos::HostSpace>(P.cp[0].data(), P.cp.size());
  return pd;
}

LoadPoint LoadPoint::at(double t, int num_stages) {
  LoadPoint lp;
  lp.stage = std::clamp(static_cast<int>(std::ceil(t)) - 1, 0, num_stages - 1);
  lp.s = t - lp.stage;
  return lp;
}

RCP<Vector> System::assemble_loads(double lambda, int stage) const {
  if (stage < 0) stage = P_.num_stages() - 1;
  Vector f_ov(overlap_);
  {
    auto f = Kokkos::subview(f_ov.getLocalViewDevice(Tpetra::Access::ReadWrite), Kokkos::ALL(), 0);
    for (const PatchBlock& bd : blocks_) {
      for (int s = 0; s < 4; ++s) {
        const SideCondition& sc = P_.bodies[bd.body].sides[bd.patch][s];
        if (sc.load == LoadKind::None) continue;
        // finite kinematics: pressures are follower loads, in assemble_internal
        if (sc.load != LoadKind::Traction && P_.kinematics == Kinematics::Finite) continue;
        AssembleSideLoad<decltype(f)> k;
        k.pd = bd.pd;
        k.load.side = s;
        k.load.kind = sc.load == LoadKind::Traction ? 3 : 1;
        k.load.p0 = sc.p0[stage]; k.load.p1 = sc.p1[stage];
        k.load.t[0] = sc.traction[stage][0]; k.load.t[1] = sc.traction[stage][1];
        k.load.scale = lambda * P_.thickness;
        k.load.orientation = bd.orientation;
        const int d = s <= 1 ? 1 : 0;
        k.g = gauss_rule(bd.pd.p[d] + 1);
        k.f = f;
        k.e_begin = bd.e_begin; k.e_end = bd.e_end;
        Kokkos::parallel_for("iga::AssembleSideLoad", Kokkos::RangePolicy<ExecSpace>(0, bd.pd.ne[d]), k);
      }
    }
    Kokkos::fence();
  }
  if (!user_tractions_.empty()) {
    auto h = f_ov.getLocalViewHost(Tpetra::Access::ReadWrite);
    for (const auto& ut : user_tractions_) {
      const PatchBlock& bd = blocks_[block_of(ut.body, ut.patch)];
      const Curve c = P_.bodies[ut.body].patches[ut.patch].side_curve(ut.side);
      const GaussRule g = gauss_rule(c.degree + 2);
      const auto spans = c.element_spans();
      for (size_t k = 0; k < spans.size(); ++k) {
        const int s = spans[k];
        // the side element belongs to the rank owning its patch element
        const int side = static_cast<int>(ut.side), ne0 = bd.pd.ne[0], ne1 = bd.pd.ne[1], kk = static_cast<int>(k);
        const int pe = side == 0 ? kk * ne0 : side == 1 ? ne0 - 1 + kk * ne0 : side == 2 ? kk : kk + (ne1 - 1) * ne0;
        if (pe < bd.e_begin || pe >= bd.e_end) continue;
        const double a = c.knots[s], b = c.knots[s + 1], hh = 0.5 * (b - a);
        for (int q = 0; q < g.n; ++q) {
          const double u = a + hh * (g.x[q] + 1.0);
          double ders[3][kMaxBasis1D], w[kMaxBasis1D], R[3][kMaxBasis1D];
          bspline_ders(s, u, c.degree, c.knots.data(), 1, ders);
          for (int j = 0; j <= c.degree; ++j) { w[j] = c.cp[s - c.degree + j][2]; ders[2][j] = 0; }
          rationalize_1d(c.degree, ders, w, R);
          double x[2] = {0, 0}, t[2] = {0, 0};
          for (int j = 0; j <= c.degree; ++j)
            for (int d = 0; d < 2; ++d) {
              x[d] += R[0][j] * c.cp[s - c.degree + j][d];
              t[d] += R[1][j] * c.cp[s - c.degree + j][d];
            }
          const auto tr = ut.t(x[0], x[1]);
          const double wq = lambda * g.w[q] * hh * std::hypot(t[0], t[1]) * P_.thickness;
          for (int j = 0; j <= c.degree; ++j) {
            const int l = bd.lid[c.patch_index[s - c.degree + j]];
            for (int d = 0; d < 2; ++d) h(2 * l + d, 0) += R[0][j] * tr[d] * wq;
          }
        }
      }
    }
  }
  if (!user_body_forces_.empty()) {
    auto h = f_ov.getLocalViewHost(Tpetra::Access::ReadWrite);
    for (const auto& ub : user_body_forces_)
      for (const PatchBlock& bd : blocks_) {
        if (bd.body != ub.body) continue;
        const Patch& pt = P_.bodies[bd.body].patches[bd.patch];
        const HostPatchData pd = host_patch_data(pt);
        const auto sp0 = pt.element_spans(0), sp1 = pt.element_spans(1);
        const GaussRule g0 = gauss_rule(pd.p[0] + 2), g1 = gauss_rule(pd.p[1] + 2);
        dispatch_degree(std::max(pd.p[0], pd.p[1]), [&](auto PP) {
          constexpr int P = decltype(PP)::value;
          double R[(P + 1) * (P + 1)], dR[(P + 1) * (P + 1)][2], x[2];
          for (int e = bd.e_begin; e < bd.e_end; ++e) {
            const int s0 = sp0[e % pd.ne[0]], s1 = sp1[e / pd.ne[0]];
            const double ua = pt.knots[0][s0], ub0 = pt.knots[0][s0 + 1], va = pt.knots[1][s1], vb = pt.knots[1][s1 + 1];
            for (int qj = 0; qj < g1.n; ++qj)
              for (int qi = 0; qi < g0.n; ++qi) {
                const double u = ua + 0.5 * (ub0 - ua) * (g0.x[qi] + 1), v = va + 0.5 * (vb - va) * (g1.x[qj] + 1);
                const double det = nurbs_grad<P>(pd, s0, s1, u, v, R, dR, x);
                const auto b = ub.b(x[0], x[1]);
                const double w = lambda * std::abs(det) * g0.w[qi] * g1.w[qj] * 0.25 * (ub0 - ua) * (vb - va) * P_.thickness;
                for (int j = 0; j <= pd.p[1]; ++j)
                  for (int i = 0; i <= pd.p[0]; ++i) {
                    const int l = bd.lid[s0 - pd.p[0] + i + (s1 - pd.p[1] + j) * pd.n[0]];
                    const double Rw = R[i + j * (pd.p[0] + 1)] * w;
                    h(2 * l, 0) += Rw * b[0];
                    h(2 * l + 1, 0) += Rw * b[1];
                  }
              }
          }
        });
      }
  }
  return export_vector(f_ov);
}

void System::set_dirichlet(Vector& u, const LoadPoint& lp) const {
  auto h = u.getLocalViewHost(Tpetra::Access::ReadWrite);
  for (size_t k = 0; k < dirichlet_.size(); ++k) {
    const auto& v = dirichlet_[k].values;
    const double prev = lp.stage > 0 ? v[lp.stage - 1] : 0.0;
    h(dirichlet_lids_[k], 0) = (1.0 - lp.s) * prev + lp.s * v[lp.stage];
  }
}

std::vector<double> System::constrained_entries(const Vector& v) const {
  auto h = v.getLocalViewHost(Tpetra::Access::ReadOnly);
  std::vector<double> e;
  e.reserve(dirichlet_lids_.size());
  for (int l : dirichlet_lids_) e.push_back(h(l, 0));
  return e;
}

void System::set_constrained_entries(Vector& v, const std::vector<double>& entries) const {
  auto h = v.getLocalViewHost(Tpetra::Access::ReadWrite);
  for (size_t k = 0; k < dirichlet_lids_.size(); ++k) h(dirichlet_lids_[k], 0) = entries[k];
}

void System::zero_dirichlet(Vector& v) const {
  auto h = v.getLocalViewHost(Tpetra::Access::ReadWrite);
  for (int l : dirichlet_lids_) h(l, 0) = 0.0;
}

void System::apply_dirichlet(Matrix& A) const {
  Vector flag(owned_);
  {
    auto h = flag.getLocalViewHost(Tpetra::Access::OverwriteAll);
    Kokkos::deep_copy(h, 0.0);
    for (int l : dirichlet_lids_) h(l, 0) = 1.0;
  }
  Vector colflag(A.getColMap());
  Import importer(owned_, A.getColMap());
  colflag.doImport(flag, importer, Tpetra::INSERT);
  auto rowf = Kokkos::subview(flag.getLocalViewDevice(Tpetra::Access::ReadOnly), Kokkos::ALL(), 0);
  auto colf = Kokkos::subview(colflag.getLocalViewDevice(Tpetra::Access::ReadOnly), Kokkos::ALL(), 0);
  auto lcl = A.getLocalMatrixDevice();
  auto rowmap = A.getRowMap()->getLocalMap();
  auto colmap = A.getColMap()->getLocalMap();
  Kokkos::parallel_for("iga::ApplyDirichlet", Kokkos::RangePolicy<ExecSpace>(0, lcl.numRows()),
                       KOKKOS_LAMBDA(const int r) {
    auto row = lcl.row(r);
    const GO grow = rowmap.getGlobalElement(r);
    for (int k = 0; k < row.length; ++k) {
      const bool diag = colmap.getGlobalElement(row.colidx(k)) == grow;
      if (diag) continue;
      if (rowf(r) != 0.0 || colf(row.colidx(k)) != 0.0) row.value(k) = 0.0;
    }
  });
  Kokkos::fence();
}

size_t System::body_of(GO g) const {
  return static_cast<size_t>(std::upper_bound(body_offset_.begin(), body_offset_.end(), g) - body_offset_.begin()) - 1;
}

size_t System::block_of(int body, int patch) const {
  for (size_t k = 0; k < blocks_.size(); ++k)
    if (blocks_[k].body == body && blocks_[k].patch == patch) return k;
  throw std::out_of_range("no patch " + std::to_string(patch) + " in body " + std::to_string(body));
}

const Point3& System::control_point(GO g) const { return cp_pos_[g]; }

RCP<MultiVector> System::rigid_body_modes() const {
  RCP<MultiVector> Z = rcp(new MultiVector(owned_, 3));
  auto h = Z->getLocalViewHost(Tpetra::Access::OverwriteAll);
  for (size_t l = 0; l < owned_->getNodeNumElements(); ++l) {
    const GO dof = owned_->getGlobalElement(l);
    const auto& cp = control_point(dof / 2);
    const int c = static_cast<int>(dof % 2);
    h(l, 0) = c == 0 ? 1.0 : 0.0;
    h(l, 1) = c == 1 ? 1.0 : 0.0;
    h(l, 2) = c == 0 ? -cp[1] : cp[0];
  }
  return Z;
}

RCP<MultiVector> System::aggregation_coordinates() const {
  // one row per owned control point: MueLu's node map (node g holds dofs 2 g, 2 g + 1)
  const size_t n = owned_->getNodeNumElements() / 2;
  std::vector<GO> gids(n);
  for (size_t l = 0; l < n; ++l) gids[l] = owned_->getGlobalElement(2 * l) / 2;
  RCP<const Map> nodes = rcp(new Map(Teuchos::OrdinalTraits<Tpetra::global_size_t>::invalid(), gids.data(), n, 0, comm_));
  RCP<MultiVector> X = rcp(new MultiVector(nodes, 2));

  // D: the diameter of all control nets together. Body b is moved by 1e3 D b along x, so
  // that the distance-Laplacian weight between two bodies, <= 1e-6 / D^2, is far below the
  // drop tolerance times the weights within a body (>= 1 / D^2). Each control point is also
  // nudged by 1e-6 D times its place (i / n_xi, j / n_eta) in the net: coincident control
  // points (a collapsed edge) then have distinct coordinates, strongly coupled to each other;
  // elsewhere the nudge is far below the element size.
  double lo[2] = {1e300, 1e300}, hi[2] = {-1e300, -1e300};
  for (const auto& c : cp_pos_)
    for (int d = 0; d < 2; ++d) lo[d] = std::min(lo[d], c[d]), hi[d] = std::max(hi[d], c[d]);
  const double D = std::max(std::hypot(hi[0] - lo[0], hi[1] - lo[1]), 1e-300);
  // the nudge: each control point's place in the net of the first patch it belongs to
  std::vector<std::array<double, 2>> place(num_cps_, {-1.0, -1.0});
  for (const PatchBlock& bd : blocks_) {
    const Patch& q = P_.bodies[bd.body].patches[bd.patch];
    for (size_t a = 0; a < bd.gid.size(); ++a)
      if (place[bd.gid[a]][0] < 0)
        place[bd.gid[a]] = {static_cast<double>(a % q.ncp(0)) / q.ncp(0) + bd.patch, static_cast<double>(a / q.ncp(0)) / q.ncp(1)};
  }
  auto h = X->getLocalViewHost(Tpetra::Access::OverwriteAll);
  for (size_t l = 0; l < n; ++l) {
    const size_t b = body_of(gids[l]);
    const Point3& c = cp_pos_[gids[l]];
    h(l, 0) = c[0] + 1e-6 * D * place[gids[l]][0] + 1e3 * D * static_cast<double>(b);
    h(l, 1) = c[1] + 1e-6 * D * place[gids[l]][1];
  }
  return X;
}

}  // namespace iga
