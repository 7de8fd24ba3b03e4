#include "solver/system.hpp"
#include "solver/system_internal.hpp"

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

using namespace system_detail;

Material body_material(const Problem& P, int b, double thickness) {
  const Body& body = P.bodies[b];
  if (P.analysis == Analysis::Solid) {
    const int model = P.kinematics == Kinematics::Small ? Material::kLinear
                      : body.model == MaterialModel::NeoHookean ? Material::kNeoHookean
                                                                : Material::kSaintVenantKirchhoff;
    return Material::solid(model, body.E, body.nu);
  }
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
      if (pt.dim() == 3)
        bd.pd3 = make_patch_data3(pt);
      else
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
  // owned control points: a contiguous block per rank; dofs dim g + c (kernels/numbering.hpp)
  const auto cpr = block_range(num_cps_, rank, size);
  std::vector<GO> owned;
  owned.reserve(dim() * (cpr.second - cpr.first));
  for (GO g = cpr.first; g < cpr.second; ++g)
    for (int c = 0; c < dim(); ++c) owned.push_back(dof_of(g, c, dim()));
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
    std::vector<int> sp[3];
    int nspan[3] = {1, 1, 1}, deg[3] = {0, 0, 0};
    for (int d = 0; d < pt.dim(); ++d) {
      sp[d] = pt.element_spans(d);
      nspan[d] = static_cast<int>(sp[d].size());
      deg[d] = pt.degree[d];
    }
    for (int d = pt.dim(); d < 3; ++d) sp[d] = {0};
    for (int e = bd.e_begin; e < bd.e_end; ++e) {
      int ij[3];
      tensor_ij(e, nspan, 3, ij);
      const int s0 = sp[0][ij[0]], s1 = sp[1][ij[1]], s2 = sp[2][ij[2]];
      for (int k = s2 - deg[2]; k <= s2; ++k)
        for (int j = s1 - deg[1]; j <= s1; ++j)
          for (int i = s0 - deg[0]; i <= s0; ++i) touched.push_back(bd.gid[pt.index(i, j, k)]);
    }
  }
  std::sort(touched.begin(), touched.end());
  touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
  overlap_ = cp_dof_map(touched);
  for (PatchBlock& bd : blocks_) {
    const int ncp = static_cast<int>(bd.gid.size());
    std::vector<int> lid(ncp, -1);
    for (int a = 0; a < ncp; ++a) {
      const LO l = overlap_->getLocalElement(dof_of(bd.gid[a], 0, dim()));
      if (l != Teuchos::OrdinalTraits<LO>::invalid()) lid[a] = point_of_dof(l, dim());
    }
    (P_.bodies[bd.body].patches[bd.patch].dim() == 3 ? bd.pd3.lid : bd.pd.lid) = to_device("lid", lid);
    bd.lid = std::move(lid);
  }

  // Dirichlet dofs owned here (sides, then corner points); a dof constrained by several is
  // reported under the first
  std::map<GO, DirichletDof> dd;
  auto constrain = [&](int blk, int slot, const SideCondition& sc, const std::vector<int>& cps) {
    for (int a : cps)
      for (int c = 0; c < dim(); ++c)
        if (sc.fixed[c]) {
          const GO dof = dof_of(blocks_[blk].gid[a], c, dim());
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
    for (int s = 0; s < num_sides(dim()); ++s) constrain(static_cast<int>(k), s, body.sides[blocks_[k].patch][s], pt.side_indices(static_cast<Side>(s)));
  }
  for (size_t k = 0; k < blocks_.size(); ++k) {
    const Body& body = P_.bodies[blocks_[k].body];
    const Patch& pt = body.patches[blocks_[k].patch];
    for (int c = 0; c < 4; ++c)
      constrain(static_cast<int>(k), kCornerSlot + c, body.corners[blocks_[k].patch][c], {corner_index(pt, static_cast<Corner>(c))});
  }
  for (const auto& kv : dd) {
    dirichlet_.push_back(kv.second);
    dirichlet_lids_.push_back(owned_->getLocalElement(kv.first));
  }
}

RCP<const Map> System::cp_dof_map(const std::vector<GO>& cps, bool) const {
  std::vector<GO> dofs;
  dofs.reserve(dim() * cps.size());
  for (GO g : cps)
    for (int c = 0; c < dim(); ++c) dofs.push_back(dof_of(g, c, dim()));
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

const ControlPoint& System::control_point(GO g) const { return cp_pos_[g]; }

}  // namespace iga
