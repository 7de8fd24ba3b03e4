// Contact assembly: the contact graph (groups of coupled control points) and the KTS, mortar
// and friction kernels of every pair into one matrix and residual.
#include "solver/contact.hpp"
#include "solver/contact_internal.hpp"
#include "kernels/numbering.hpp"

#include <Teuchos_CommHelpers.hpp>
#include <Teuchos_TimeMonitor.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace iga {

ContactContribution assemble_contact(const System& sys, std::vector<ContactPairData>& pairs, ContactGraphCache* cache) {
  // 1) the dofs this rank's contributions couple: overlap map and graph. A group is a set
  //    of control points coupled all to all: the element pair of a quadrature point (KTS,
  //    and the mortar pressure term), or the support of delta g_A (mortar). The pattern is
  //    reserved beyond what is active now: every point with a projection, with its master
  //    element widened by two neighbours on each side, and every weighted gap with such
  //    points; only active ones get values. So K_T's pattern, rebuilt when K_c has a
  //    nonzero outside it (tangent.hpp), seldom changes as the contact zone grows or
  //    points slide: once per run on the scaling problem, where it was twice per load step.
  std::vector<GO> cps;
  std::vector<std::vector<GO>> groups;
  int active = 0;
  for (size_t k = 0; k < pairs.size(); ++k) {
    auto& pd = pairs[k];
    if (pd.s3_) {   // 3-D: the slave and (widened) master element of each point with a projection
      pd.s3_->groups(groups, active);
      continue;
    }
    auto valid = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), pd.sp_.valid);
    auto gap = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), pd.sp_.gap);
    auto sspan = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), pd.sp_.span);
    auto mspan = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), pd.sp_.mspan);
    const int nm = static_cast<int>(pd.master_gid.size());
    // two elements each side: on the scaling problem at 6.6e5 dofs the edge of the slave
    // block slides across more than one master element (one gave two builds there)
    constexpr int kWiden = 2;
    auto point_group = [&](int i) {
      std::vector<GO> g;
      for (int a = sspan(i) - pd.slave.p; a <= sspan(i); ++a) g.push_back(pd.slave_gid[a]);
      for (int b = std::max(0, mspan(i) - pd.master.p - kWiden); b <= std::min(nm - 1, mspan(i) + kWiden); ++b)
        g.push_back(pd.master_gid[b]);
      return g;
    };
    for (int i = pd.p_begin; i < pd.p_end; ++i) {
      if (sspan(i) < 0 || !valid(i)) continue;
      if (!pd.mortar() && kts_active(gap(i), pd.sp_.touch)) ++active;
      groups.push_back(point_group(i));
    }
    if (pd.mortar()) {
      auto act = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), pd.ms_.active);
      auto espan = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), pd.slave.span);
      for (int A = pd.a_begin; A < pd.a_end; ++A) {
        if (act(A)) ++active;
        std::vector<GO> g;
        for (int e = 0; e < pd.slave.ne; ++e) {
          if (espan(e) < A || espan(e) > A + pd.slave.p) continue;
          for (int i = e * pd.slots; i < (e + 1) * pd.slots; ++i)
            if (sspan(i) >= 0 && valid(i)) {
              const auto pg = point_group(i);
              g.insert(g.end(), pg.begin(), pg.end());
            }
        }
        std::sort(g.begin(), g.end());
        g.erase(std::unique(g.begin(), g.end()), g.end());
        if (!g.empty()) groups.push_back(std::move(g));
      }
    }
  }
  if (sys.comm()->getSize() == 1) {
    // one rank: every control point a row, so the rows are the owned map itself and K_c needs
    // no export (exportAndFillCompleteCrsMatrix sorts and merges every entry again); the rows
    // outside the contact stay empty
    cps.resize(static_cast<size_t>(sys.num_dofs() / sys.dim()));
    for (size_t a = 0; a < cps.size(); ++a) cps[a] = static_cast<GO>(a);
  } else {
    for (const auto& g : groups) cps.insert(cps.end(), g.begin(), g.end());
    std::sort(cps.begin(), cps.end());
    cps.erase(std::unique(cps.begin(), cps.end()), cps.end());
  }
  // Each coupled control point's neighbours: the union of the groups it is in, found through
  // the groups of each point (incidence) with a mark per neighbour, so a neighbour is written
  // once per row instead of once per group (mortar's groups in 3-D hold hundreds of control
  // points, each point in dozens of them). The rows come out sorted, as before.
  const LO n = static_cast<LO>(cps.size());
  auto lid_of = [&](GO g) { return static_cast<LO>(std::lower_bound(cps.begin(), cps.end(), g) - cps.begin()); };
  std::vector<size_t> gptr(groups.size() + 1, 0);
  for (size_t k = 0; k < groups.size(); ++k) gptr[k + 1] = gptr[k] + groups[k].size();
  std::vector<LO> members(gptr.back());
  std::vector<size_t> iptr(static_cast<size_t>(n) + 1, 0);
  for (size_t k = 0; k < groups.size(); ++k)
    for (size_t j = 0; j < groups[k].size(); ++j) {
      const LO r = lid_of(groups[k][j]);
      members[gptr[k] + j] = r;
      ++iptr[r + 1];
    }
  for (LO r = 0; r < n; ++r) iptr[r + 1] += iptr[r];
  std::vector<size_t> incidence(iptr[n]);
  {
    std::vector<size_t> fill(iptr.begin(), iptr.end() - 1);
    for (size_t k = 0; k < groups.size(); ++k)
      for (size_t j = gptr[k]; j < gptr[k + 1]; ++j) incidence[fill[members[j]]++] = k;
  }
  std::vector<size_t> nptr(static_cast<size_t>(n) + 1, 0);
  std::vector<LO> nbr;
  {
    std::vector<LO> mark(n, -1);
    for (LO r = 0; r < n; ++r) {
      for (size_t q = iptr[r]; q < iptr[r + 1]; ++q) {
        const size_t k = incidence[q];
        for (size_t j = gptr[k]; j < gptr[k + 1]; ++j)
          if (mark[members[j]] != r) {
            mark[members[j]] = r;
            nbr.push_back(members[j]);
          }
      }
      std::sort(nbr.begin() + nptr[r], nbr.end());
      nptr[r + 1] = nbr.size();
    }
  }
  // the same control points and neighbours as the last call's (the contact zone and the
  // projections' elements unchanged, as in the late Newton iterations of a step): its graph
  // (collective: the graph's fillComplete is, so every rank must take the same branch)
  RCP<const Graph> graph;
  int same = cache && cache->graph && cache->cps == cps && cache->nptr == nptr && cache->nbr == nbr ? 1 : 0;
  if (cache) {
    int all = 0;
    Teuchos::reduceAll(*sys.comm(), Teuchos::REDUCE_MIN, 1, &same, &all);
    same = all;
  }
  if (same) {
    graph = cache->graph;
  } else {
    RCP<const Map> ov = sys.cp_dof_map(cps);
    const int D = sys.dim();
    Teuchos::ArrayRCP<size_t> rowptr(D * n + 1);
    rowptr[0] = 0;
    for (LO r = 0; r < n; ++r)
      for (int c = 0; c < D; ++c)
        rowptr[dof_of(r, c, D) + 1] = rowptr[dof_of(r, c, D)] + D * (nptr[r + 1] - nptr[r]);
    Teuchos::ArrayRCP<LO> cols(std::max<size_t>(rowptr[D * n], 1));
    for (LO r = 0; r < n; ++r)
      for (int c = 0; c < D; ++c) {
        size_t k = rowptr[dof_of(r, c, D)];
        for (size_t q = nptr[r]; q < nptr[r + 1]; ++q)
          for (int cc = 0; cc < D; ++cc) cols[k++] = dof_of(nbr[q], cc, D);
      }
    cols = cols.persistingView(0, rowptr[D * n]);
    RCP<Graph> g = rcp(new Graph(ov, ov, rowptr, cols));
    g->fillComplete(sys.owned_map(), sys.owned_map());
    graph = g;
    if (cache) {
      cache->graph = graph;
      cache->cps = cps;
      cache->nptr = std::move(nptr);
      cache->nbr = std::move(nbr);
    }
  }
  const RCP<const Map> ov = graph->getRowMap();
  RCP<Matrix> K = rcp(new Matrix(graph));
  Vector f(ov);
  // 2) kernels: every pair's active points of this rank. A mortar weighted gap whose dofs
  // outgrow its pair's scratch rows reports what it needs: the rows grow and the kernels run
  // again on zeroed K and f (once per growth, so rarely after the first steps)
  for (bool again = false, first = true; first || again; first = false) {
    auto lcl = K->getLocalMatrixDevice();
    auto fv = Kokkos::subview(f.getLocalViewDevice(Tpetra::Access::ReadWrite), Kokkos::ALL(), 0);
    if (again) {   // a rerun: the first pass's sums go (K and f start at zero)
      Kokkos::deep_copy(lcl.values, 0.0);
      Kokkos::deep_copy(fv, 0.0);
    }
    again = false;
    for (auto& pd : pairs) {
      if (pd.mortar()) Kokkos::deep_copy(pd.ms_.flags, 0);
      Kokkos::deep_copy(pd.force_, 0.0);
    }
    for (auto& pd : pairs) {
      if (pd.s3_) {
        ContactSurfaces3& c3 = *pd.s3_;
        c3.set_lids(cps);
        // mortar: by segments, the slots of one slave element and master element summed into
        // one block before the scatter (sum_segments; a team per slave element, scratch memory)
        auto most = [](const ContactFaces& fs) {
          int m = 0;
          for (int j = 0; j < fs.n; ++j) m = std::max(m, (fs.f[j].sd.p[0] + 1) * (fs.f[j].sd.p[1] + 1));
          return m;
        };
        const int nd_max = 3 * (most(c3.slave) + most(c3.master));
        const int e_first = c3.mortar && c3.p_end > c3.p_begin ? c3.p_begin / c3.slots : 0;
        const int league = c3.mortar && c3.p_end > c3.p_begin ? (c3.p_end - 1) / c3.slots - e_first + 1 : 0;
        const auto segments = Kokkos::TeamPolicy<ExecSpace>(league, 1).set_scratch_size(1, Kokkos::PerTeam(segment_block_bytes(nd_max)));
        if (c3.p_end > c3.p_begin) {
          AssembleKts3<decltype(lcl), decltype(fv)> k;
          k.s = c3.slave; k.m = c3.master; k.sp = c3.sp; k.eps = c3.pair.penalty; k.mortar = c3.mortar;
          k.geometric = pd.geometric;
          k.p_begin = c3.p_begin; k.K = lcl; k.f = fv; k.force = pd.force_;
          if (c3.mortar) {
            k.p_end = c3.p_end; k.slots = c3.slots; k.e_first = e_first; k.nd_max = nd_max;
            Kokkos::parallel_for("iga::AssembleMortarPressure3", segments, k);
          } else {
            Kokkos::parallel_for("iga::AssembleKts3", Kokkos::RangePolicy<ExecSpace>(0, c3.p_end - c3.p_begin), k);
          }
        }
        if (c3.mortar && c3.e_end > c3.e_begin) {
          AssembleMortarEdge3<decltype(lcl)> k;
          k.s = c3.slave; k.m = c3.master; k.ed = c3.edges; k.ms = c3.ms; k.e_begin = c3.e_begin; k.K = lcl;
          Kokkos::parallel_for("iga::AssembleMortarEdge3", Kokkos::RangePolicy<ExecSpace>(0, c3.e_end - c3.e_begin), k);
          if (c3.friction) {
            AssembleMortarFrictionEdge3<decltype(lcl)> kf;
            kf.s = c3.slave; kf.m = c3.master; kf.ed = c3.edges; kf.esp = c3.esp; kf.efr = c3.efr; kf.fr = c3.fr;
            kf.e_begin = c3.e_begin; kf.K = lcl;
            Kokkos::parallel_for("iga::AssembleMortarFrictionEdge3", Kokkos::RangePolicy<ExecSpace>(0, c3.e_end - c3.e_begin), kf);
          }
        }
        if (c3.friction) Kokkos::deep_copy(c3.fr.force, 0.0);
        if (c3.friction && c3.p_end > c3.p_begin) {
          AssembleFriction3<decltype(lcl), decltype(fv)> k;
          k.s = c3.slave; k.m = c3.master; k.sp = c3.sp; k.fr = c3.fr; k.eps = c3.pair.penalty; k.mortar = c3.mortar;
          k.p_begin = c3.p_begin; k.K = lcl; k.f = fv; k.force = pd.force_;
          if (c3.mortar) {
            k.p_end = c3.p_end; k.slots = c3.slots; k.e_first = e_first; k.nd_max = nd_max;
            Kokkos::parallel_for("iga::AssembleMortarFrictionSlots3", segments, k);
          } else {
            Kokkos::parallel_for("iga::AssembleFriction3", Kokkos::RangePolicy<ExecSpace>(0, c3.p_end - c3.p_begin), k);
          }
        }
        if (c3.mortar && c3.a_end > c3.a_begin) {
          Kokkos::deep_copy(c3.ms.flags, 0);
          if (c3.friction) {
            const int na = c3.a_end - c3.a_begin;
            Kokkos::View<MortarRange3*, MemSpace> range("mortar_friction_range", na);
            Kokkos::View<int*, MemSpace> size("mortar_friction_size", na);
            MortarFrictionRanges3 kr;
            kr.s = c3.slave; kr.m = c3.master; kr.sp = c3.sp; kr.ms = c3.ms; kr.fr = c3.fr; kr.sc = c3.fscratch;
            kr.range = range; kr.size = size; kr.ed = c3.edges; kr.slots = c3.slots; kr.a_begin = c3.a_begin;
            Kokkos::parallel_for("iga::MortarFrictionRanges3", Kokkos::RangePolicy<ExecSpace>(0, na), kr);
            MortarFrictionVectors3 kv;
            kv.s = c3.slave; kv.m = c3.master; kv.sp = c3.sp; kv.ms = c3.ms; kv.fr = c3.fr; kv.sc = c3.fscratch;
            kv.range = range; kv.size = size; kv.a_begin = c3.a_begin; kv.a_end = c3.a_end;
            Kokkos::parallel_for("iga::MortarFrictionVectors3", Kokkos::RangePolicy<ExecSpace>(c3.c_begin * c3.slots, c3.c_end * c3.slots), kv);
            MortarFrictionEdgeVectors3 kev;
            kev.s = c3.slave; kev.m = c3.master; kev.ed = c3.edges; kev.esp = c3.esp; kev.efr = c3.efr; kev.ms = c3.ms;
            kev.fr = c3.fr; kev.sc = c3.fscratch; kev.range = range; kev.size = size; kev.a_begin = c3.a_begin;
            kev.a_end = c3.a_end;
            Kokkos::parallel_for("iga::MortarFrictionEdgeVectors3",
                                 Kokkos::RangePolicy<ExecSpace>(c3.c_begin * c3.edges.per, c3.c_end * c3.edges.per), kev);
            AssembleMortarFriction3<decltype(lcl)> k;
            k.s = c3.slave; k.m = c3.master; k.ms = c3.ms; k.fr = c3.fr; k.sc = c3.fscratch;
            k.range = range; k.size = size; k.eps = c3.pair.penalty; k.a_begin = c3.a_begin; k.K = lcl;
            Kokkos::parallel_for("iga::AssembleMortarFriction3", Kokkos::RangePolicy<ExecSpace>(0, na), k);
          }
          AssembleMortarGap3<decltype(lcl)> k;
          k.s = c3.slave; k.m = c3.master; k.sp = c3.sp; k.ed = c3.edges; k.ms = c3.ms; k.sc = c3.scratch; k.eps = c3.pair.penalty;
          k.slots = c3.slots; k.a_begin = c3.a_begin; k.K = lcl;
          Kokkos::parallel_for("iga::AssembleMortarGap3", Kokkos::RangePolicy<ExecSpace>(0, c3.a_end - c3.a_begin), k);
          Kokkos::fence();
          auto fl = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), c3.ms.flags);
          if (fl(1) > 0) {
            c3.mortar_scratch(std::max(fl(1), c3.scratch.cap() + c3.scratch.cap() / 2));
            again = true;
          }
        }
        continue;
      }
      for (CurveData* c : {&pd.slave, &pd.master}) {
        const auto& gid = c == &pd.slave ? pd.slave_gid : pd.master_gid;
        auto h = Kokkos::create_mirror_view(c->lid);
        for (int k = 0; k < c->nb; ++k) {
          auto it = std::lower_bound(cps.begin(), cps.end(), gid[k]);
          h(k) = (it != cps.end() && *it == gid[k]) ? static_cast<int>(it - cps.begin()) : -1;
        }
        Kokkos::deep_copy(c->lid, h);
      }
      if (pd.p_end > pd.p_begin)
        dispatch_degree(std::max(pd.slave.p, pd.master.p), [&](auto P) {
          AssembleKts<decltype(P)::value, decltype(lcl), decltype(fv)> k;
          k.s = pd.slave; k.m = pd.master; k.sp = pd.sp_; k.eps = pd.pair().penalty;
          k.p_begin = pd.p_begin; k.mortar = pd.mortar(); k.K = lcl; k.f = fv; k.force = pd.force_;
          k.geometric = pd.geometric;
          Kokkos::parallel_for(pd.mortar() ? "iga::AssembleMortarPressure" : "iga::AssembleKts",
                               Kokkos::RangePolicy<ExecSpace>(0, pd.p_end - pd.p_begin), k);
        });
      if (pd.friction() && pd.p_end > pd.p_begin)
        dispatch_degree(std::max(pd.slave.p, pd.master.p), [&](auto P) {
          AssembleFriction<decltype(P)::value, decltype(lcl), decltype(fv)> k;
          k.s = pd.slave; k.m = pd.master; k.sp = pd.sp_; k.fr = pd.fr_; k.eps = pd.pair().penalty;
          k.p_begin = pd.p_begin; k.mortar = pd.mortar(); k.K = lcl; k.f = fv; k.force = pd.force_;
          Kokkos::parallel_for("iga::AssembleFriction", Kokkos::RangePolicy<ExecSpace>(0, pd.p_end - pd.p_begin), k);
        });
      if (pd.friction() && pd.mortar() && pd.a_end > pd.a_begin)
        dispatch_degree(std::max(pd.slave.p, pd.master.p), [&](auto P) {
          AssembleMortarFriction<decltype(P)::value, decltype(lcl)> k;
          k.s = pd.slave; k.m = pd.master; k.sp = pd.sp_; k.ms = pd.ms_; k.fr = pd.fr_; k.eps = pd.pair().penalty;
          k.sc = pd.scratch_; k.slots = pd.slots; k.a_begin = pd.a_begin; k.K = lcl;
          Kokkos::parallel_for("iga::AssembleMortarFriction", Kokkos::RangePolicy<ExecSpace>(0, pd.a_end - pd.a_begin), k);
        });
      if (pd.mortar() && pd.slots > 0) {
        // the pressure term's boundary part at the master ends' images: each slave element on
        // the rank of its first slot
        const int e_begin = std::min((pd.p_begin + pd.slots - 1) / pd.slots, pd.slave.ne);
        const int e_end = std::min((pd.p_end + pd.slots - 1) / pd.slots, pd.slave.ne);
        if (e_end > e_begin) {
          AssembleMortarEnds<decltype(lcl)> k;
          k.s = pd.slave; k.m = pd.master; k.ms = pd.ms_; k.ends = pd.ends_; k.thickness = pd.thickness;
          k.e_begin = e_begin; k.K = lcl;
          Kokkos::parallel_for("iga::AssembleMortarEnds", Kokkos::RangePolicy<ExecSpace>(0, e_end - e_begin), k);
        }
      }
      if (pd.mortar() && pd.a_end > pd.a_begin) {
        AssembleMortarGap<decltype(lcl)> k;
        k.s = pd.slave; k.m = pd.master; k.sp = pd.sp_; k.ms = pd.ms_; k.eps = pd.pair().penalty;
        k.sc = pd.scratch_; k.slots = pd.slots; k.a_begin = pd.a_begin; k.K = lcl;
        k.ends = pd.ends_; k.thickness = pd.thickness;
        Kokkos::parallel_for("iga::AssembleMortarGap", Kokkos::RangePolicy<ExecSpace>(0, pd.a_end - pd.a_begin), k);
        Kokkos::fence();
        auto fl = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), pd.ms_.flags);
        if (fl(1) > 0) {
          pd.mortar_scratch(std::max(fl(1), pd.scratch_.cap() + pd.scratch_.cap() / 2));
          again = true;
        }
      }
    }
    Kokkos::fence();
  }
  K->fillComplete(sys.owned_map(), sys.owned_map());
  // each pair's force on its slave body: this rank's points summed by the kernels, all ranks'
  for (auto& pd : pairs) {
    // one reduction: [Fx, Fy, Fz | Fn, .. ] and, with 3-D friction, [Tx, Ty, Tz]
    const bool fr3 = pd.s3_ && pd.s3_->friction;
    auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), pd.force_);
    double loc[7] = {h(0), h(1), h(2), h(3), 0, 0, 0}, all[7];
    if (fr3) {
      auto t = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), pd.s3_->fr.force);
      for (int k = 0; k < 3; ++k) loc[4 + k] = t(k);
    }
    Teuchos::reduceAll(*sys.comm(), Teuchos::REDUCE_SUM, fr3 ? 7 : 4, loc, all);
    std::copy(all, all + 4, pd.assembled_);
    if (fr3) std::copy(all + 4, all + 7, pd.s3_->assembled_t);
  }
  ContactContribution out;
  out.K = sys.export_matrix(K);
  out.f = sys.export_vector(f);
  Teuchos::reduceAll(*sys.comm(), Teuchos::REDUCE_SUM, 1, &active, &out.active);
  return out;
}

}  // namespace iga
