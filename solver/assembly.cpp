// The assembly driver: internal force and tangent of every patch block (element loop or
// sum-factorised rows), follower pressure, and the export of ghost rows.
#include "solver/system.hpp"
#include "solver/system_internal.hpp"

#include <Teuchos_TimeMonitor.hpp>

#include <algorithm>
#include <cmath>

#include "kernels/boundary_load.hpp"
#include "kernels/face_load.hpp"
#include "kernels/elasticity.hpp"
#include "kernels/elasticity_sf.hpp"

namespace iga {

using namespace system_detail;

RCP<Matrix> System::assemble_stiffness() const {
  RCP<Matrix> K;
  assemble_internal(nullptr, nullptr, &K);
  return K;
}

RCP<Matrix> System::control_net_stiffness() const {
  Problem low = P_;
  low.kinematics = Kinematics::Small;
  low.quadrature = Quadrature::Gauss;
  for (Body& b : low.bodies)
    for (Patch& q : b.patches)
      for (int d = 0; d < q.dim(); ++d) {
        const int n = q.ncp(d);
        const double a = q.knots[d].front(), c = q.knots[d].back();
        std::vector<double> U = uniform_open_knots(1, n - 1);
        for (double& u : U) u = a + (c - a) * u;
        q.knots[d] = U;
        q.degree[d] = 1;
      }
  System s(low, comm_);
  RCP<Matrix> K = s.assemble_stiffness();
  s.apply_dirichlet(*K);
  return K;
}

bool System::constant_tangent() const {
  for (const Material& m : materials_)
    if (!m.constant_tangent()) return false;
  return true;
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
    // a follower pressure kernel (2-D sides, 3-D faces): this rank's elements, u, and what to form
    const auto follower_io = [&](auto& k) {
      k.e_begin = bd.e_begin;
      k.e_end = bd.e_end;
      k.u = uv;
      k.f = fv;
      k.force = f_int != nullptr;
      k.tangent = K != nullptr;
      if (K) k.scatter = scatter(b);
    };
    if (dim() == 3) {
      // 3-D: the element loop (kernels/elasticity.hpp, AssembleInternalT<3>), the tangent by
      // element-wise sum factorisation from p = 3 (kernels/elasticity_sf3.hpp: 2x faster at
      // p = 3, 3.5x at p = 4; equal at p = 2, slower at p = 1)
      const int pmax = std::max({bd.pd3.p[0], bd.pd3.p[1], bd.pd3.p[2]});
      dispatch_degree(pmax, [&](auto P) {
        AssembleInternalT<3, decltype(P)::value, Local> k{
            bd.pd3, bd.mat, {gauss_rule(bd.pd3.p[0] + 1), gauss_rule(bd.pd3.p[1] + 1), gauss_rule(bd.pd3.p[2] + 1)}, bd.e_begin};
        k.u = uv;
        k.f = fv;
        k.force = f_int != nullptr;
        k.tangent = K != nullptr;
        k.sum_factorized = P_.formation == Formation::SumFactorized && pmax >= 3;
        if (k.tangent) k.scatter = scatter(b);
        k.Kw = element_work_;
        k.run(bd.e_end);
        element_work_ = k.Kw;
      });
      // finite kinematics: pressures follow the deformed faces (kernels/face_load.hpp)
      if (lp && P_.kinematics == Kinematics::Finite)
        for (int face = 0; face < num_sides(3); ++face) {
          const SideCondition& sc = P_.bodies[bd.body].sides[bd.patch][face];
          if (sc.load != LoadKind::Pressure) continue;
          int fd[2];
          face_directions(face, fd);
          dispatch_degree(std::max(bd.pd3.p[fd[0]], bd.pd3.p[fd[1]]), [&](auto P) {
            constexpr int Pm = decltype(P)::value;
            AssembleFollowerFacePressure<(Pm + 1) * (Pm + 1), Local> k;
            k.pd = bd.pd3;
            k.load.face = face;
            k.load.kind = 1;
            k.load.p = (1.0 - lp->s) * (lp->stage > 0 ? sc.p0[lp->stage - 1] : 0.0) + lp->s * sc.p0[lp->stage];
            k.load.orientation = bd.orientation;
            for (int i = 0; i < 2; ++i) k.g[i] = gauss_rule(bd.pd3.p[fd[i]] + 1);
            follower_io(k);
            Kokkos::parallel_for("iga::AssembleFollowerFacePressure", Kokkos::RangePolicy<ExecSpace>(0, k.num_face_elements()), k);
          });
        }
      continue;
    }
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
      for (int side = 0; side < num_sides(dim()); ++side) {
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
        const int d = side_tangent_direction(side);
        k.g = gauss_rule(bd.pd.p[d] + 1);
        follower_io(k);
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


}  // namespace iga
