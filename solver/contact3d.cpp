// 3-D contact pairs: faces of solids on the device, slave quadrature points, the replicated
// displacements of both surfaces, search and projection (kernels/contact_kts3.hpp).
#include "solver/contact3d.hpp"
#include "solver/contact.hpp"
#include "solver/contact_internal.hpp"
#include "model/configuration_check.hpp"
#include "solver/system_internal.hpp"
#include "kernels/numbering.hpp"
#include "kernels/sides.hpp"

#include <algorithm>
#include <array>
#include <climits>
#include <map>
#include <set>
#include <cmath>
#include <stdexcept>
#include <type_traits>

#include <Intrepid2_CubatureDirectTriDefault.hpp>
#include <Teuchos_CommHelpers.hpp>
#include <Teuchos_TimeMonitor.hpp>

namespace iga {

TriangleRule triangle_rule(int degree) {
  using Cubature = Intrepid2::CubatureDirectTriDefault<Kokkos::HostSpace::device_type, double, double>;
  constexpr int max_degree = Intrepid2::Parameters::MaxCubatureDegreeTri;
  for (int d = std::max(degree, 0); d <= max_degree; ++d) {
    Cubature c(d);
    const int n = c.getNumPoints();
    if (n > kMaxTrianglePoints) break;
    Kokkos::DynRankView<double, Kokkos::HostSpace> x("triangle_points", n, 2), w("triangle_weights", n);
    c.getCubature(x, w);
    TriangleRule t;
    t.n = n;
    t.degree = d;
    bool ok = true;
    for (int k = 0; k < n; ++k) {
      t.x[k][0] = x(k, 0);
      t.x[k][1] = x(k, 1);
      t.w[k] = w(k);
      ok = ok && w(k) > 0 && x(k, 0) > 0 && x(k, 1) > 0 && x(k, 0) + x(k, 1) < 1;
    }
    if (ok) return t;
  }
  return triangle_rule_collapsed(gauss_rule(std::min((degree + 3) / 2, kMaxGauss)));
}

static_assert(kMaxContactFaces <= kMaxFacesPerSurface, "the problem file allows more contact faces than the kernels hold");

using system_detail::to_device;

namespace {

// One patch face on the device (reference = current control points) and its host data.
template <class HostFace>
ContactFace make_face(const System& sys, int body, const PatchSide& ps, HostFace& h) {
  const Patch& P = sys.problem().bodies[body].patches[ps.patch];
  const Patch F = P.face(ps.side);
  const std::vector<int> idx = P.side_indices(ps.side);
  ContactFace f;
  for (int d = 0; d < 2; ++d) {
    h.p[d] = F.degree[d];
    h.n[d] = F.ncp(d);
    h.span[d] = F.element_spans(d);
    h.ne[d] = static_cast<int>(h.span[d].size());
    f.sd.p[d] = h.p[d];
    f.sd.n[d] = h.n[d];
    f.sd.ne[d] = h.ne[d];
    f.sd.U[d] = to_device("face_knots", F.knots[d]);
    f.sd.span[d] = to_device("face_spans", h.span[d]);
  }
  const int ncp = static_cast<int>(F.cp.size());
  f.X = Kokkos::View<double* [4], MemSpace>("face_X", ncp);
  f.cur = Kokkos::View<double* [4], MemSpace>("face_x", ncp);
  f.u = Kokkos::View<double* [3], MemSpace>("face_u", ncp);
  f.lid = Kokkos::View<int*, MemSpace>("face_lid", ncp);
  auto hX = Kokkos::create_mirror_view(f.X);
  h.gid.resize(ncp);
  for (int a = 0; a < ncp; ++a) {
    for (int c = 0; c < 3; ++c) hX(a, c) = F.cp[a].x[c];
    hX(a, 3) = F.cp[a].w;
    h.gid[a] = sys.cp_gid(body, ps.patch, idx[a]);
  }
  Kokkos::deep_copy(f.X, hX);
  Kokkos::deep_copy(f.cur, hX);
  f.sd.cp = f.cur;
  f.sign = side_normal_sign(static_cast<int>(ps.side)) * P.orientation();
  return f;
}

// ContactFace::open of a master face: its edges that lie in a symmetry plane of the model. The
// face's parameter directions are the patch's other two in order (Patch::face); its edge at
// end e of direction d is on the patch side side_of(pd, e). That side is a symmetry plane when
// it is planar with the normal along an axis c (every control point's x_c the same),
// prescribes u_c = 0 in every stage, and the slave surface reaches the same plane (two of its
// faces' control points on it): a quarter or half model cut there through the contact, the
// bodies going on as their mirror images. (A roller support at the end of a master that a
// slave overhangs is not one: the slave does not end on its plane. An interface to another
// patch is no edge of the body.) slave_x: the slave faces' reference control points.
int open_edges(const Body& body, const PatchSide& ps, const std::vector<std::array<double, 3>>& slave_x) {
  const Patch& P = body.patches[ps.patch];
  double size = 0;
  for (int c = 0; c < 3; ++c) {
    double lo = 1e300, hi = -1e300;
    for (const ControlPoint& cp : P.cp) {
      lo = std::min(lo, cp.x[c]);
      hi = std::max(hi, cp.x[c]);
    }
    size = std::max(size, hi - lo);
  }
  int open = 0;
  for (int d = 0, pd = 0; d < 2; ++d, ++pd) {
    if (pd == side_direction(ps.side)) ++pd;
    for (int e = 0; e < 2; ++e) {
      const Side side = side_of(pd, e);
      if (body.is_interface(PatchSide{ps.patch, side})) continue;
      const SideCondition& sc = body.sides[ps.patch][static_cast<int>(side)];
      const std::vector<int> idx = P.side_indices(side);
      for (int c = 0; c < 3; ++c) {
        if (!sc.fixed[c]) continue;
        bool zero = !sc.value.empty();
        for (const auto& v : sc.value) zero = zero && v[c] == 0.0;
        bool planar = !idx.empty();
        for (int a : idx) planar = planar && std::abs(P.cp[a].x[c] - P.cp[idx[0]].x[c]) <= 1e-12 * size;
        if (!zero || !planar) continue;
        int on = 0;
        for (const auto& x : slave_x) on += std::abs(x[c] - P.cp[idx[0]].x[c]) <= 1e-12 * size;
        if (on >= 2) open |= 1 << (2 * d + e);
      }
    }
  }
  return open;
}

}  // namespace

ContactSurfaces3::ContactSurfaces3(const System& sys, const ContactPair& pr) : pair(pr) {
  const Problem& P = sys.problem();
  rank_ = sys.comm()->getRank();
  nranks_ = sys.comm()->getSize();
  comm_ = sys.comm();
  for (int which = 0; which < 2; ++which) {
    const ContactSurface& cs = which == 0 ? pair.slave : pair.master;
    ContactFaces& faces = which == 0 ? slave : master;
    auto& hf = which == 0 ? hs_ : hm_;
    if (cs.sides.size() > static_cast<size_t>(kMaxContactFaces))
      throw std::invalid_argument("a 3-D contact surface holds at most " + std::to_string(kMaxContactFaces) + " faces");
    hf.resize(cs.sides.size());
    faces.n = static_cast<int>(cs.sides.size());
    for (size_t k = 0; k < cs.sides.size(); ++k) faces.f[k] = make_face(sys, cs.body, cs.sides[k], hf[k]);
  }
  {   // the master faces' edges on symmetry planes that the slave reaches too
    std::vector<std::array<double, 3>> slave_x;
    for (const PatchSide& q : pair.slave.sides)
      for (const ControlPoint& cp : P.bodies[pair.slave.body].patches[q.patch].face(q.side).cp)
        slave_x.push_back({cp.x[0], cp.x[1], cp.x[2]});
    for (int k = 0; k < master.n; ++k) master.f[k].open = open_edges(P.bodies[pair.master.body], pair.master.sides[k], slave_x);
  }
  // kts_alm runs on mortar's weighted gaps, multipliers and pressure field at the KTS points
  // (nq x nq Gauss points on each whole slave element: element-based integration, no
  // segmentation); kts_penalty keeps its penalty per point
  mortar = pair.method != ContactMethod::KtsPenalty;
  segmented = pair.method != ContactMethod::KtsAlm;
  fr.mu = pair.friction;
  fr.epsT = pair.tangential_penalty > 0 ? pair.tangential_penalty : pair.penalty;
  fr.force = ForceSum("friction_force");
  friction = fr.mu > 0;
  if (mortar) {
    // quadrature slots per slave element, filled by MortarSegments3 at every update (they grow
    // to what an element needs); w_A = int R_A dGamma_0 by Gauss on the slave elements
    number_slave_control_points();
    int pmax = 1, ps = 1;
    for (const HostFace& h : hs_) ps = std::max({ps, h.p[0], h.p[1]});
    for (const HostFace& hm : hm_) pmax = std::max({pmax, hm.p[0], hm.p[1]});
    pmax = std::max(pmax, ps);
    // n = p + 2 points per direction (each fan triangle's rule exact to degree 2 n - 2 = 2 p + 2),
    // with friction p + 3: a rule that does not integrate the segments' integrands exactly
    // makes the residual jump where a segment gains or loses a corner as u changes, at the level
    // of its error. With p + 1 (degree 2 p), Newton stalled at relative residuals of 1e-8
    // (p = 2) and 4e-10 (p = 3) on a flat punch pressed into a block, above its 1e-10; with
    // p + 2 it converges quadratically to 1e-12 (docs/verification.md, "3-D contact"). With
    // friction the slip's integrand is of higher degree still (Newton stalled at 1e-7 on a flat
    // p = 2 master with p + 1)
    gauss = gauss_rule(pair.quadrature_points > 0 ? pair.quadrature_points : std::min(pmax + (friction ? 3 : 2), kMaxGauss));
    tri = triangle_rule(polygon_rule_degree(gauss.n));
    slots = 4 * 6 * tri.n;   // room for 4 segments of 6 fan triangles to start with
    if (!segmented) {        // kts_alm: the KTS points of the largest slave element rule
      slots = 1;
      for (const HostFace& h : hs_) slots = std::max(slots, kts_rule(h, 0) * kts_rule(h, 1));
    }
    const int ne = slave.eoff[slave.n], na = num_control_points_;
    allocate_points(ne * slots);
    allocate_edges(segmented ? 8 * gauss.n : 0);   // (kts_alm: no master edges' images)
    ms.wA = Kokkos::View<double*, MemSpace>("wA", na);
    ms.gA = Kokkos::View<double*, MemSpace>("gA", na);
    ms.lbar = Kokkos::View<double*, MemSpace>("lbar", na);
    ms.lambda = Kokkos::View<double*, MemSpace>("lambdaA", na);
    ms.active = Kokkos::View<int*, MemSpace>("activeA", na);
    ms.covered = Kokkos::View<int*, MemSpace>("coveredA", na);
    ms.cwA = Kokkos::View<double*, MemSpace>("coveredWeightA", na);
    if (pair.method != ContactMethod::MortarPenalty) {   // ALM: the penalty per control point
      ms.scale = Kokkos::View<double*, MemSpace>("scaleA", na);
      Kokkos::deep_copy(ms.scale, 1.0);
    }
    ms.flags = Kokkos::View<int*, MemSpace>("flags", 2);
    seg_flags_ = Kokkos::View<int*, MemSpace>("segment_flags", 4);
    if (friction) {
      fr.sA = Kokkos::View<double* [3], MemSpace>("sA", na);
      fr.trA = Kokkos::View<double* [3], MemSpace>("trA", na);
      fr.tauA = Kokkos::View<double* [3], MemSpace>("tauA", na);
      fr.lamTA = Kokkos::View<double* [3], MemSpace>("lamTA", na);
      fr.nA = Kokkos::View<double* [3], MemSpace>("nA", na);
      fr.slipA = Kokkos::View<double*, MemSpace>("slipA", na);
      fr.slipA_c = Kokkos::View<double*, MemSpace>("slipA_c", na);
      fr.stateA = Kokkos::View<int*, MemSpace>("stateA", na);
      stateA_prev_ = Kokkos::View<int*, MemSpace>("stateA_prev", na);
      // the converged configuration's faces: their own current points and displacements
      for (int which = 0; which < 2; ++which) {
        ContactFaces& c = which == 0 ? slave_c_ : master_c_;
        c = which == 0 ? slave : master;
        for (int k = 0; k < c.n; ++k) {
          c.f[k].cur = Kokkos::View<double* [4], MemSpace>("face_x_committed", c.f[k].X.extent(0));
          Kokkos::deep_copy(c.f[k].cur, c.f[k].X);
          c.f[k].sd.cp = c.f[k].cur;
          c.f[k].u = Kokkos::View<double* [3], MemSpace>("face_u_committed", c.f[k].X.extent(0));
        }
      }
    }
    {
      const ContactFaces s = slave;
      const GaussRule g = gauss_rule(std::min(ps + 2, kMaxGauss));
      const auto wA = ms.wA;
      Kokkos::parallel_for("iga::MortarWeights3", Kokkos::RangePolicy<ExecSpace>(0, ne), KOKKOS_LAMBDA(const int eg) {
        int e;
        const int fs = slave_face_of(s, eg, e);
        const SurfaceData ref = reference_surface(s.f[fs]);
        const auto aid = s.f[fs].aid;
        int es[2];
        surface_element_spans(ref, e, es);
        const double a0 = ref.U[0](es[0]), b0 = ref.U[0](es[0] + 1), a1 = ref.U[1](es[1]), b1 = ref.U[1](es[1] + 1);
        for (int q1 = 0; q1 < g.n; ++q1)
          for (int q0 = 0; q0 < g.n; ++q0) {
            const double u = a0 + 0.5 * (b0 - a0) * (g.x[q0] + 1), v = a1 + 0.5 * (b1 - a1) * (g.x[q1] + 1);
            double d[6][3], nn[3], R[kMaxSurfaceBasis], Ru[kMaxSurfaceBasis], Rv[kMaxSurfaceBasis];
            int cp[kMaxSurfaceBasis];
            surface_derivatives(ref, es, u, v, d);
            cross3(d[1], d[2], nn);
            const double w = g.w[q0] * g.w[q1] * 0.25 * (b0 - a0) * (b1 - a1) * kmath::sqrt(dot3(nn, nn));
            const int nb = surface_basis(ref, es, u, v, R, Ru, Rv, cp);
            for (int a = 0; a < nb; ++a) Kokkos::atomic_add(&wA(aid(cp[a])), R[a] * w);
          }
      });
    }
    const auto ra = block_range(na, sys.comm()->getRank(), sys.comm()->getSize());
    a_begin = static_cast<int>(ra.first);
    a_end = static_cast<int>(ra.second);
    segment_range();
    mortar_scratch(kMortarInitialEntries * 3);
  }
  // slave points: nq x nq Gauss points per slave face element (default 2 (p + 1) per direction,
  // as in 2-D), weights in the reference configuration. kts_alm: the same points in mortar's
  // slots, `slots` per element (the unused ones with face -1)
  std::vector<int> face, elem;
  std::vector<double> uv, gw;
  h_min_ = 1e300;
  for (int fi = 0; fi < slave.n; ++fi) {
    const HostFace& h = hs_[fi];
    if (segmented && mortar) break;   // the slots come from the segmentation
    const Patch F = P.bodies[pair.slave.body].patches[pair.slave.sides[fi].patch].face(pair.slave.sides[fi].side);
    const int nq[2] = {kts_rule(h, 0), kts_rule(h, 1)};
    const GaussRule g0 = gauss_rule(nq[0]), g1 = gauss_rule(nq[1]);
    points_per_element = std::max(points_per_element, nq[0] * nq[1]);
    for (int e1 = 0; e1 < h.ne[1]; ++e1)
      for (int e0 = 0; e0 < h.ne[0]; ++e0) {
        const int s0 = h.span[0][e0], s1 = h.span[1][e1];
        const double a0 = F.knots[0][s0], b0 = F.knots[0][s0 + 1], a1 = F.knots[1][s1], b1 = F.knots[1][s1 + 1];
        for (int q1 = 0; q1 < nq[1]; ++q1)
          for (int q0 = 0; q0 < nq[0]; ++q0) {
            face.push_back(fi);
            elem.push_back(e0 + h.ne[0] * e1);
            uv.push_back(a0 + 0.5 * (b0 - a0) * (g0.x[q0] + 1));
            uv.push_back(a1 + 0.5 * (b1 - a1) * (g1.x[q1] + 1));
            gw.push_back(g0.w[q0] * g1.w[q1] * 0.25 * (b0 - a0) * (b1 - a1));
          }
        for (int k = nq[0] * nq[1]; mortar && k < slots; ++k) {   // an unused slot
          face.push_back(-1);
          elem.push_back(0);
          uv.push_back(0);
          uv.push_back(0);
          gw.push_back(0);
        }
      }
  }
  // the smallest slave element (the ALM gap scale and the touch tolerance)
  for (const PatchSide& ps : pair.slave.sides)
    h_min_ = std::min(h_min_, smallest_element_size(P.bodies[pair.slave.body].patches[ps.patch].face(ps.side)));
  if (!(h_min_ < 1e300)) h_min_ = 1;
  sp.touch = 1e-12 * h_min_;   // gaps within round-off of 0 count as closed (touching at the start)
  if (!segmented || !mortar) {
    const int n = static_cast<int>(face.size());
    if (!mortar) allocate_points(n);   // (kts_alm: the slots, allocated above, n of them)
    Kokkos::deep_copy(sp.face, Kokkos::View<int*, Kokkos::HostSpace, Kokkos::MemoryTraits<Kokkos::Unmanaged>>(face.data(), n));
    Kokkos::deep_copy(sp.elem, Kokkos::View<int*, Kokkos::HostSpace, Kokkos::MemoryTraits<Kokkos::Unmanaged>>(elem.data(), n));
    Kokkos::deep_copy(sp.weight, Kokkos::View<double*, Kokkos::HostSpace, Kokkos::MemoryTraits<Kokkos::Unmanaged>>(gw.data(), n));
    {
      auto h = Kokkos::create_mirror_view(sp.uv);
      for (int i = 0; i < n; ++i) { h(i, 0) = uv[2 * i]; h(i, 1) = uv[2 * i + 1]; }
      Kokkos::deep_copy(sp.uv, h);
    }
    // reference points and measures: w = Gauss x |X_u x X_v|
    const ContactFaces s = slave;
    const SlavePoints3 p = sp;
    Kokkos::parallel_for("iga::SlavePoints3", Kokkos::RangePolicy<ExecSpace>(0, n), KOKKOS_LAMBDA(const int i) {
      if (p.face(i) < 0) return;
      const SurfaceData& sd = s.f[p.face(i)].sd;
      int es[2];
      surface_element_spans(sd, p.elem(i), es);
      double d[6][3], nn[3];
      surface_derivatives(sd, es, p.uv(i, 0), p.uv(i, 1), d);
      cross3(d[1], d[2], nn);
      p.weight(i) *= kmath::sqrt(dot3(nn, nn));
      for (int c = 0; c < 3; ++c) p.X(i, c) = d[0][c];
    });
  }
  // every rank holds the displacements of both surfaces (boundary-sized)
  replicated_ = sys.cp_dof_map(surface_gids());
  importer_ = rcp(new Import(sys.owned_map(), replicated_));
  for (int which = 0; which < 2; ++which) {
    const auto& hf = which == 0 ? hs_ : hm_;
    auto& rep = which == 0 ? rep_s_ : rep_m_;
    for (const HostFace& h : hf) {
      Kokkos::View<int* [3], MemSpace> v("replicated_lid", h.gid.size());
      auto hv = Kokkos::create_mirror_view(v);
      for (size_t k = 0; k < h.gid.size(); ++k)
        for (int c = 0; c < 3; ++c) hv(k, c) = replicated_->getLocalElement(dof_of(h.gid[k], c, 3));
      Kokkos::deep_copy(v, hv);
      rep.push_back(v);
    }
  }
  refresh();
}

namespace {

/// Every rank computed its own [begin, end) of v's first index: the others' entries are zeroed
/// and the whole array summed over the ranks, so that every rank holds every entry (host view;
/// any layout: the sum runs over the contiguous span).
template <class V>
void sum_over_ranks(const Comm& comm, const V& v, int begin, int end) {
  using T = typename V::non_const_value_type;
  const int n = static_cast<int>(v.extent(0));
  for (int i = 0; i < n; ++i) {
    if (i >= begin && i < end) continue;
    if constexpr (V::rank == 1) v(i) = 0;
    else
      for (int c = 0; c < static_cast<int>(v.extent(1)); ++c) v(i, c) = 0;
  }
  const int len = static_cast<int>(v.span());
  std::vector<T> out(len);
  Teuchos::reduceAll(comm, Teuchos::REDUCE_SUM, len, v.data(), out.data());
  std::copy(out.begin(), out.end(), v.data());
}

/// The same for a device view (through a host copy).
template <class V>
void sum_device_over_ranks(const Comm& comm, const V& v, int begin, int end) {
  auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), v);
  sum_over_ranks(comm, h, begin, end);
  Kokkos::deep_copy(v, h);
}

/// Slave point arrays for n points (no projection yet).
SlavePoints3 make_slave_points(int n) {
  SlavePoints3 sp;
  sp.face = Kokkos::View<int*, MemSpace>("face", n);
  sp.elem = Kokkos::View<int*, MemSpace>("elem", n);
  sp.uv = Kokkos::View<double* [2], MemSpace>("uv", n);
  sp.weight = Kokkos::View<double*, MemSpace>("weight", n);
  sp.X = Kokkos::View<double* [3], MemSpace>("X", n);
  sp.valid = Kokkos::View<int*, MemSpace>("valid", n);
  sp.mface = Kokkos::View<int*, MemSpace>("mface", n);
  sp.melem = Kokkos::View<int*, MemSpace>("melem", n);
  Kokkos::deep_copy(sp.mface, -1);
  Kokkos::deep_copy(sp.melem, -1);
  sp.muv = Kokkos::View<double* [2], MemSpace>("muv", n);
  sp.gap = Kokkos::View<double*, MemSpace>("gap", n);
  sp.pressure = Kokkos::View<double*, MemSpace>("pressure", n);
  sp.x = Kokkos::View<double* [3], MemSpace>("x", n);
  sp.normal = Kokkos::View<double* [3], MemSpace>("normal", n);
  return sp;
}

/// Friction's per-point arrays for n points (mortar: with the slip vectors).
void make_friction_points(Friction3& fr, int n, bool mortar) {
  fr.ref_face = Kokkos::View<int*, MemSpace>("ref_face", n);
  Kokkos::deep_copy(fr.ref_face, -1);
  fr.ref_uv = Kokkos::View<double* [2], MemSpace>("ref_uv", n);
  fr.lamT = Kokkos::View<double* [2], MemSpace>("lamT", n);
  fr.tau = Kokkos::View<double* [2], MemSpace>("tau", n);
  fr.t = Kokkos::View<double* [3], MemSpace>("traction", n);
  fr.slip = Kokkos::View<double*, MemSpace>("slip", n);
  fr.slip_c = Kokkos::View<double*, MemSpace>("slip_c", n);
  fr.gT = Kokkos::View<double*, MemSpace>("gT", n);
  fr.state = Kokkos::View<int*, MemSpace>("friction_state", n);
  if (mortar) fr.gv = Kokkos::View<double* [3], MemSpace>("slip_vector", n);
}

}  // namespace

// Mortar: the slave faces' elements numbered face after face (ContactFaces::eoff) and their
// control points numbered A = 0, 1, ... in the order of the faces and of each face's control
// points, once where faces share one (the same global control point): w_A, g_A, lambda_A and
// the friction law live per A, and A's support is its elements on every face that holds it.
// One face: A is the face's own control point index.
void ContactSurfaces3::number_slave_control_points() {
  slave.eoff[0] = 0;
  for (int f = 0; f < slave.n; ++f) slave.eoff[f + 1] = slave.eoff[f] + hs_[f].ne[0] * hs_[f].ne[1];
  std::map<GO, int> index;
  std::vector<std::vector<std::pair<int, int>>> occ;
  for (int f = 0; f < slave.n; ++f) {
    const HostFace& h = hs_[f];
    std::vector<int> aid(h.gid.size());
    for (size_t a = 0; a < h.gid.size(); ++a) {
      const auto [it, fresh] = index.emplace(h.gid[a], static_cast<int>(occ.size()));
      if (fresh) occ.emplace_back();
      occ[it->second].push_back({f, static_cast<int>(a)});
      aid[a] = it->second;
    }
    slave.f[f].aid = to_device("face_aid", aid);
  }
  num_control_points_ = static_cast<int>(occ.size());
  a_ptr_h_.assign(1, 0);
  a_occ_h_.clear();
  for (const auto& o : occ) {
    for (const auto& [f, a] : o) {
      a_occ_h_.push_back(f);
      a_occ_h_.push_back(a);
    }
    a_ptr_h_.push_back(static_cast<int>(a_occ_h_.size() / 2));
  }
  slave.a_ptr = to_device("slave_a_ptr", a_ptr_h_);
  slave.a_occ = Kokkos::View<int* [2], MemSpace>("slave_a_occ", a_occ_h_.size() / 2);
  auto h = Kokkos::create_mirror_view(slave.a_occ);
  for (size_t k = 0; k < a_occ_h_.size() / 2; ++k) {
    h(k, 0) = a_occ_h_[2 * k];
    h(k, 1) = a_occ_h_[2 * k + 1];
  }
  Kokkos::deep_copy(slave.a_occ, h);
}

void ContactSurfaces3::allocate_edges(int per) {
  const int ne = slave.eoff[slave.n];
  edges.per = per;
  edges.elem = Kokkos::View<int*, MemSpace>("edge_elem", ne * per);
  edges.sface = Kokkos::View<int*, MemSpace>("edge_sface", ne * per);
  edges.melem = Kokkos::View<int*, MemSpace>("edge_melem", ne * per);
  edges.mface = Kokkos::View<int*, MemSpace>("edge_mface", ne * per);
  edges.d = Kokkos::View<double* [kEdgeData], MemSpace>("edge_data", ne * per);
  Kokkos::deep_copy(edges.elem, -1);
  const auto r = block_range(ne * per, rank_, nranks_);
  e_begin = static_cast<int>(r.first);
  e_end = static_cast<int>(r.second);
  segment_range();
  if (friction) {   // the edge points as slave points, with references and slip vectors
    esp = make_slave_points(ne * per);
    efr = fr;
    make_friction_points(efr, ne * per, true);
  }
}

void ContactSurfaces3::allocate_points(int n) {
  const double touch = sp.touch;
  sp = make_slave_points(n);
  sp.touch = touch;
  const auto r = block_range(n, rank_, nranks_);
  p_begin = static_cast<int>(r.first);
  p_end = static_cast<int>(r.second);
  if (mortar) {
    segment_range();
    int nb = 1;
    for (const HostFace& h : hs_) nb = std::max(nb, (h.p[0] + 1) * (h.p[1] + 1));
    sp.R = Kokkos::View<double**, Kokkos::LayoutRight, MemSpace>("slot_basis", n, nb);
  }
  make_friction_points(fr, n, mortar && friction);
  state_prev_ = Kokkos::View<int*, MemSpace>("friction_state_prev", n);
}

// Mortar: the slave elements this rank segments and projects, [c_begin, c_end): those of its
// slots [p_begin, p_end) and edge points [e_begin, e_end) (which it assembles), and those in
// the support of its control points [a_begin, a_end) (whose weighted gaps and slips it sums).
// Control point (i, j) of a face lies in the support of the element rows whose span s1 has
// s1 - p1 <= j <= s1; per face the rows between those of its lowest and highest j of this
// rank's control points are taken whole (a superset), so the range stays one interval.
void ContactSurfaces3::segment_range() {
  const int ne = slave.eoff[slave.n];
  int lo = ne, hi = 0;
  auto take = [&](int first, int last) {   // elements [first, last)
    if (last <= first) return;
    lo = std::min(lo, first);
    hi = std::max(hi, last);
  };
  if (slots > 0 && p_end > p_begin) take(p_begin / slots, (p_end - 1) / slots + 1);
  if (edges.per > 0 && e_end > e_begin) take(e_begin / edges.per, (e_end - 1) / edges.per + 1);
  support_[0] = ne;
  support_[1] = 0;
  if (a_end > a_begin) {
    std::vector<int> j_lo(slave.n, INT_MAX), j_hi(slave.n, -1);
    for (int k = a_ptr_h_[a_begin]; k < a_ptr_h_[a_end]; ++k) {
      const int f = a_occ_h_[2 * k], j = a_occ_h_[2 * k + 1] / hs_[f].n[0];
      j_lo[f] = std::min(j_lo[f], j);
      j_hi[f] = std::max(j_hi[f], j);
    }
    for (int f = 0; f < slave.n; ++f) {
      const HostFace& h = hs_[f];
      const int ne0 = h.ne[0], e0 = slave.eoff[f];
      for (int e1 = 0; e1 < h.ne[1]; ++e1)
        if (h.span[1][e1] - h.p[1] <= j_hi[f] && h.span[1][e1] >= j_lo[f]) {
          take(e0 + e1 * ne0, e0 + (e1 + 1) * ne0);
          support_[0] = std::min(support_[0], e0 + e1 * ne0);
          support_[1] = std::max(support_[1], e0 + (e1 + 1) * ne0);
        }
    }
  }
  c_begin = std::min(lo, hi);
  c_end = hi;
}

// Mortar on several ranks: the slots' assembly (the pressure and friction terms of
// [p_begin, p_end)) follows the active slots, which gather where the bodies touch, not the
// slot numbering: where the ranks' shares of the last update's active slots differ by more than
// 10 %, the slave elements are split anew into ranges of equal active slots (every rank
// computes the same split from the same counts), each range kept inside the support of its
// rank's control points (which that rank segments anyway: the segmented elements do not grow).
void ContactSurfaces3::balance_slots() {
  const int ne = static_cast<int>(elem_load_.size());
  if (nranks_ < 2 || ne == 0 || slots <= 0) return;
  std::vector<long long> pre(ne + 1, 0);
  for (int e = 0; e < ne; ++e) pre[e + 1] = pre[e] + elem_load_[e];
  const long long W = pre[ne];
  if (W == 0) return;
  // the largest share of the present split (an element cut by a range counts for both)
  long long most = 0;
  // every rank's present slot range and control points' support, in elements
  int mine[4] = {p_begin / slots, (p_end + slots - 1) / slots, support_[0], support_[1]};
  std::vector<int> all(4 * nranks_);
  Teuchos::gatherAll(*comm_, 4, mine, 4 * nranks_, all.data());
  for (int r = 0; r < nranks_; ++r) {
    const int a = std::clamp(all[4 * r], 0, ne), b = std::clamp(all[4 * r + 1], 0, ne);
    most = std::max(most, b > a ? pre[b] - pre[a] : 0LL);
  }
  if (most * nranks_ <= 1.1 * W) return;
  // the first element of rank r's range: the first e with pre[e] >= r W / n, within the
  // overlap of the supports of ranks r - 1 and r (a range empty of control points keeps none)
  std::vector<int> first(nranks_ + 1, 0);
  first[nranks_] = ne;
  for (int r = 1; r < nranks_; ++r) {
    int e = 0;
    while (e < ne && pre[e] * nranks_ < static_cast<long long>(r) * W) ++e;
    const int lo = std::min(all[4 * r + 2], ne), hi = std::max(all[4 * (r - 1) + 3], 0);
    if (lo <= hi) e = std::clamp(e, lo, hi);
    first[r] = std::max(e, first[r - 1]);
  }
  p_begin = first[rank_] * slots;
  p_end = first[rank_ + 1] * slots;
  segment_range();
}

// Active slots per slave element after an update, every rank's (the ranks that segmented an
// element counted the same slots: the maximum over the ranks).
void ContactSurfaces3::count_element_loads() {
  const int ne = slave.eoff[slave.n], per = slots;
  // counted where the slots live (ne numbers come back, not the slots)
  Kokkos::View<int*, MemSpace> load("element_load", ne);
  const SlavePoints3 p = sp;
  Kokkos::parallel_for("iga::MortarElementLoads3", Kokkos::RangePolicy<ExecSpace>(c_begin, c_end), KOKKOS_LAMBDA(const int e) {
    int n = 0;
    for (int i = e * per; i < (e + 1) * per; ++i) n += p.valid(i) && p.pressure(i) > 0;
    load(e) = n;
  });
  auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), load);
  elem_load_.assign(ne, 0);
  Teuchos::reduceAll(*comm_, Teuchos::REDUCE_MAX, ne, h.data(), elem_load_.data());
}

void ContactSurfaces3::mortar_scratch(int cap) {
  const int na = std::max(a_end - a_begin, 0);
  scratch.dof = Kokkos::View<int**, Kokkos::LayoutRight, MemSpace>("mortar_dof", na, cap);
  scratch.v0 = Kokkos::View<double**, Kokkos::LayoutRight, MemSpace>("mortar_v0", na, cap);
  scratch.v1 = Kokkos::View<double**, Kokkos::LayoutRight, MemSpace>("mortar_v1", na, cap);
  scratch.row = Kokkos::View<double**, Kokkos::LayoutRight, MemSpace>("mortar_row", na, cap);
  if (friction) {
    fscratch.dof = Kokkos::View<int**, Kokkos::LayoutRight, MemSpace>("mortar_friction_dof", na, cap);
    fscratch.v0 = Kokkos::View<double**, Kokkos::LayoutRight, MemSpace>("mortar_friction_v0", na, 8 * cap);
    fscratch.v1 = Kokkos::View<double**, Kokkos::LayoutRight, MemSpace>("mortar_friction_v1", na, 8 * cap);
    fscratch.row = Kokkos::View<double**, Kokkos::LayoutRight, MemSpace>("mortar_friction_row", na, cap);
  }
}

double ContactSurfaces3::potential() const {
  double pi = 0;
  if (mortar) {
    auto l = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ms.lambda);
    auto w = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ms.wA);
    std::vector<double> s(l.extent(0), 1.0);   // the penalty's scale per control point (ALM)
    if (ms.scale.extent(0) > 0) {
      auto hs = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ms.scale);
      for (size_t A = 0; A < s.size(); ++A) s[A] = hs(A);
    }
    for (size_t A = 0; A < l.extent(0); ++A) pi += 0.5 / (pair.penalty * s[A]) * w(A) * l(A) * l(A);
    return pi;
  }
  ContactPointState st;
  state(st, false);
  for (size_t i = 0; i < st.gap.size(); ++i)
    if (st.active[i]) pi += 0.5 / pair.penalty * st.pressure[i] * st.pressure[i] * st.weight[i];
  return pi;
}

double ContactSurfaces3::max_active_gap() const {
  if (!mortar) return 0;   // kts_penalty: no multipliers (ALM pairs are on the mortar path)
  double r = 0;
  auto g = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ms.gA);
  auto w = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ms.wA);
  auto act = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ms.active);
  auto cw = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ms.cwA);
  // not the control points the master covers on a sliver (as in 2-D, ContactPairData::
  // max_active_gap_ratio): their multipliers act on the sliver alone
  for (size_t A = 0; A < g.extent(0); ++A)
    if (act(A) && !MortarState::sliver(cw(A), w(A))) r = std::max(r, std::abs(g(A) / w(A)));
  if (friction) {   // the stick control points' weighted slip, its part along the contact plane
    // (s_A sums slip vectors tangent to the master at the slots; where the master is curved
    // or dented under the load their sum has a part along A's normal, which is no slip and
    // which the tangential multipliers cannot close: measured, it held a box pressed on a
    // block at 5 x alm_tolerance while the rest went to 1e-10)
    auto sA = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), fr.sA);
    auto nA = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), fr.nA);
    auto stA = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), fr.stateA);
    for (size_t A = 0; A < sA.extent(0); ++A) {
      if (stA(A) != 1) continue;
      double s[3] = {sA(A, 0), sA(A, 1), sA(A, 2)};
      const double nn = std::sqrt(nA(A, 0) * nA(A, 0) + nA(A, 1) * nA(A, 1) + nA(A, 2) * nA(A, 2));
      if (nn > 0) {
        const double sn = (s[0] * nA(A, 0) + s[1] * nA(A, 1) + s[2] * nA(A, 2)) / (nn * nn);
        for (int c = 0; c < 3; ++c) s[c] -= sn * nA(A, c);
      }
      r = std::max(r, std::sqrt(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]));
    }
  }
  return r;
}

void ContactSurfaces3::update_friction() {
  if (mortar) {
    update_mortar_friction();
    return;
  }
  UpdateFriction3 k;
  k.m = master; k.sp = sp; k.fr = fr; k.eps = pair.penalty;
  Kokkos::parallel_for("iga::UpdateFriction3", Kokkos::RangePolicy<ExecSpace>(p_begin, p_end), k);
  // stick / slip counts and the points that changed state since the previous update (all ranks)
  const auto st = fr.state, prev = state_prev_;
  int loc[3] = {0, 0, 0};
  Kokkos::parallel_reduce("iga::FrictionCounts3", Kokkos::RangePolicy<ExecSpace>(p_begin, p_end),
                          KOKKOS_LAMBDA(const int i, int& stick, int& slip, int& sw) {
                            stick += st(i) == 1;
                            slip += st(i) == 2;
                            sw += st(i) != prev(i);
                          },
                          loc[0], loc[1], loc[2]);
  Kokkos::deep_copy(state_prev_, fr.state);
  Teuchos::reduceAll(*comm_, Teuchos::REDUCE_SUM, 3, loc, counts);
}

// Mortar: each slot's reference foot (its slave point in the converged configuration projected
// onto the converged master; none before the first converged step), its slip vector and the
// slots' traction field for the slave elements this rank segments, the law of this rank's
// slave control points (then summed over the ranks: every rank holds every control point's),
// and the counts of this rank's control points.
void ContactSurfaces3::update_mortar_friction() {
  // this rank's segmented elements: their slots and edge points
  const int first = c_begin * slots, last = c_end * slots;
  const int e_first = c_begin * edges.per, e_last = c_end * edges.per;
  if (have_committed_) {
    // each slot's slave point in the converged configuration projected onto the converged
    // master face of its current foot, that face's polynomial not clamped (as the edge points'):
    // the slip is then defined where the foot crossed into another face of a master list
    // during the step, or where the reference lies a little beyond the master's boundary
    MortarReferences3 k;
    k.sc = slave_c_; k.mc = master_c_; k.esp = sp; k.efr = fr;
    Kokkos::parallel_for("iga::MortarFrictionReferences3", Kokkos::RangePolicy<ExecSpace>(first, last), k);
  } else {
    Kokkos::deep_copy(fr.ref_face, -1);
  }
  UpdateFriction3 ku;
  ku.m = master; ku.sp = sp; ku.fr = fr; ku.eps = pair.penalty; ku.mortar = true;
  Kokkos::parallel_for("iga::MortarSlip3", Kokkos::RangePolicy<ExecSpace>(first, last), ku);
  // the edge points (where the master ends inside slave elements): feet, references, slip vectors
  MortarEdgePoints3 kep;
  kep.s = slave; kep.m = master; kep.ed = edges; kep.esp = esp;
  Kokkos::parallel_for("iga::MortarEdgePoints3", Kokkos::RangePolicy<ExecSpace>(e_first, e_last), kep);
  if (have_committed_) {
    MortarReferences3 ker;
    ker.sc = slave_c_; ker.mc = master_c_; ker.esp = esp; ker.efr = efr;
    Kokkos::parallel_for("iga::MortarEdgeReferences3", Kokkos::RangePolicy<ExecSpace>(e_first, e_last), ker);
  } else {
    Kokkos::deep_copy(efr.ref_face, -1);
  }
  UpdateFriction3 kue;
  kue.m = master; kue.sp = esp; kue.fr = efr; kue.eps = pair.penalty; kue.mortar = true;
  Kokkos::parallel_for("iga::MortarEdgeSlip3", Kokkos::RangePolicy<ExecSpace>(e_first, e_last), kue);
  MortarFrictionLaw3 kl;
  kl.s = slave; kl.sp = sp; kl.ms = ms; kl.fr = fr; kl.slots = slots;
  Kokkos::parallel_for("iga::MortarFrictionLaw3", Kokkos::RangePolicy<ExecSpace>(a_begin, a_end), kl);
  if (nranks_ > 1) {   // every rank holds every control point's law
    sum_device_over_ranks(*comm_, fr.sA, a_begin, a_end);
    sum_device_over_ranks(*comm_, fr.nA, a_begin, a_end);
    sum_device_over_ranks(*comm_, fr.trA, a_begin, a_end);
    sum_device_over_ranks(*comm_, fr.tauA, a_begin, a_end);
    sum_device_over_ranks(*comm_, fr.slipA, a_begin, a_end);
    sum_device_over_ranks(*comm_, fr.stateA, a_begin, a_end);
  }
  MortarFrictionPoints3 kp;
  kp.s = slave; kp.sp = sp; kp.ms = ms; kp.fr = fr;
  Kokkos::parallel_for("iga::MortarFrictionPoints3", Kokkos::RangePolicy<ExecSpace>(first, last), kp);
  const auto st = fr.stateA, prev = stateA_prev_;
  int loc[3] = {0, 0, 0};
  Kokkos::parallel_reduce("iga::MortarFrictionCounts3", Kokkos::RangePolicy<ExecSpace>(a_begin, a_end),
                          KOKKOS_LAMBDA(const int A, int& stick, int& slip, int& sw) {
                            stick += st(A) == 1;
                            slip += st(A) == 2;
                            sw += st(A) != prev(A);
                          },
                          loc[0], loc[1], loc[2]);
  Kokkos::deep_copy(stateA_prev_, fr.stateA);
  Teuchos::reduceAll(*comm_, Teuchos::REDUCE_SUM, 3, loc, counts);
}

// History: the multipliers (the projection is searched anew) and friction's committed foot,
// traction and accumulated slip. Every rank copies every point: the others' entries are its own
// zeros or stale values that its kernels never read (each rank updates only its own points).
void ContactSurfaces3::commit() {
  if (mortar) contact_detail::keep_copy(committed_.lambda, ms.lbar);   // (KTS: no multipliers)
  if (!friction) return;
  if (mortar) {
    Kokkos::deep_copy(fr.lamTA, fr.tauA);
    contact_detail::keep_copy(committed_.lamTA, fr.lamTA);
    Kokkos::deep_copy(fr.slipA_c, fr.slipA);
    // the converged configuration: the reference of the next step's slots
    double hmax = 0;
    for (int which = 0; which < 2; ++which) {
      ContactFaces& c = which == 0 ? slave_c_ : master_c_;
      const ContactFaces& cur = which == 0 ? slave : master;
      for (int k = 0; k < c.n; ++k) {
        Kokkos::deep_copy(c.f[k].u, cur.f[k].u);
        update_face_points(c.f[k]);
      }
    }
    Kokkos::fence();
    for (int k = 0; k < master_c_.n; ++k) {
      master_c_.search[k] = SurfaceSearch::build(master_c_.f[k].sd);
      hmax = std::max(hmax, master_c_.search[k].h);
    }
    master_c_.radius = 2 * hmax;
    have_committed_ = true;
    return;
  }
  Kokkos::deep_copy(fr.lamT, fr.tau);
  contact_detail::keep_copy(committed_.lamT, fr.lamT);
  Kokkos::deep_copy(fr.slip_c, fr.slip);
  const auto f = fr;
  const SlavePoints3 p = sp;
  Kokkos::parallel_for("iga::CommitFriction3", Kokkos::RangePolicy<ExecSpace>(0, num_points()), KOKKOS_LAMBDA(const int i) {
    f.ref_face(i) = p.valid(i) && f.state(i) != 0 ? p.mface(i) : -1;   // a point in contact
    f.ref_uv(i, 0) = p.muv(i, 0);
    f.ref_uv(i, 1) = p.muv(i, 1);
  });
  Kokkos::fence();
}

void ContactSurfaces3::restore() {
  // (nothing committed yet: the initial state stands)
  if (mortar && committed_.lambda.data()) Kokkos::deep_copy(ms.lbar, committed_.lambda);
  if (friction && mortar && committed_.lamTA.data()) Kokkos::deep_copy(fr.lamTA, committed_.lamTA);
  else if (friction && !mortar && committed_.lamT.data()) Kokkos::deep_copy(fr.lamT, committed_.lamT);
}

// (ALM pairs only, which are all on the mortar path: mortar_alm and kts_alm)
void ContactSurfaces3::augment() {
  Kokkos::deep_copy(ms.lbar, ms.lambda);
  if (ms.scale.extent(0) > 0) scale_partly_covered(ms);
  if (friction) Kokkos::deep_copy(fr.lamTA, fr.tauA);
}

void ContactSurfaces3::reset_multipliers() {
  if (mortar) Kokkos::deep_copy(ms.lbar, 0.0);
  if (friction && mortar) Kokkos::deep_copy(fr.lamTA, 0.0);
  else if (friction) Kokkos::deep_copy(fr.lamT, 0.0);
}

std::vector<GO> ContactSurfaces3::surface_gids() const {
  std::vector<GO> cps;
  for (const auto* hf : {&hs_, &hm_})
    for (const HostFace& h : *hf) cps.insert(cps.end(), h.gid.begin(), h.gid.end());
  std::sort(cps.begin(), cps.end());
  cps.erase(std::unique(cps.begin(), cps.end()), cps.end());
  return cps;
}

void ContactSurfaces3::update(const Vector& u) {
  Vector ur(replicated_);
  ur.doImport(u, *importer_, Tpetra::INSERT);
  auto v = ur.getLocalViewDevice(Tpetra::Access::ReadOnly);
  for (int which = 0; which < 2; ++which) {
    ContactFaces& faces = which == 0 ? slave : master;
    const auto& rep = which == 0 ? rep_s_ : rep_m_;
    for (int k = 0; k < faces.n; ++k) {
      const auto fu = faces.f[k].u;
      const auto rk = rep[k];
      Kokkos::parallel_for("iga::GatherFaceDisplacements", Kokkos::RangePolicy<ExecSpace>(0, static_cast<int>(fu.extent(0))),
                           KOKKOS_LAMBDA(const int a) {
                             for (int c = 0; c < 3; ++c) fu(a, c) = v(rk(a, c), 0);
                           });
    }
  }
  refresh();
}

void ContactSurfaces3::refresh() {
  for (int which = 0; which < 2; ++which) {
    ContactFaces& faces = which == 0 ? slave : master;
    for (int k = 0; k < faces.n; ++k) update_face_points(faces.f[k]);
  }
  Kokkos::fence();
  // bins over the master's current element boxes; the search radius: twice the largest
  // bin size (a point farther from every master element is not in contact)
  double hmax = 0;
  for (int k = 0; k < master.n; ++k) {
    master.search[k] = SurfaceSearch::build(master.f[k].sd);
    hmax = std::max(hmax, master.search[k].h);
  }
  master.radius = 2 * hmax;
  if (mortar) {
    // this rank's slots: a share of the last update's active slots (several ranks)
    balance_slots();
  }
  if (mortar && segmented) {
    // segments; where an element needs more slots than it has, grow them and segment again
    Teuchos::TimeMonitor ts(*Teuchos::TimeMonitor::getNewTimer("3.1.1) Contact: segmentation"));
    const int ne = slave.eoff[slave.n];
    // the slave elements certainly out of contact, then the control points all of whose
    // support is (every element, not only this rank's: a control point's support may reach
    // beyond [c_begin, c_end))
    if (static_cast<int>(far_.extent(0)) != ne) far_ = Kokkos::View<int*, MemSpace>("mortar_far", ne);
    if (static_cast<int>(out_.extent(0)) != num_control_points_) out_ = Kokkos::View<int*, MemSpace>("mortar_out", num_control_points_);
    for (int k = 0; k < master.n; ++k) {   // the master elements' centre normals, for every candidate test
      const int nm = master.f[k].sd.ne[0] * master.f[k].sd.ne[1];
      if (static_cast<int>(master.frame[k].extent(0)) != nm) master.frame[k] = Kokkos::View<double* [4], MemSpace>("master_frames", nm);
      MasterFrames3 kfr;
      kfr.ms = master.f[k].sd;
      kfr.frame = master.frame[k];
      Kokkos::parallel_for("iga::MasterFrames3", Kokkos::RangePolicy<ExecSpace>(0, nm), kfr);
    }
    // (every rank marks every element and control point: a control point's support may reach
    // beyond the rank's range. Until 2026-11-28 one rank only: on two the skip changed the
    // Newton path, since round-off decided the tangent's boundary terms where the master's
    // edge lay on the slave's own edge at a symmetry plane; ContactFace::open, docs/performance.md)
    if (!skip_out) {
      Kokkos::deep_copy(out_, 0);
    } else {
      MortarFar3 kf;
      kf.s = slave; kf.m = master; kf.far = far_; kf.touch = sp.touch;
      Kokkos::parallel_for("iga::MortarFar3", Kokkos::RangePolicy<ExecSpace>(0, ne), kf);
      MortarOut3 ko;
      ko.s = slave; ko.ms = ms; ko.far = far_; ko.out = out_;
      Kokkos::parallel_for("iga::MortarOut3", Kokkos::RangePolicy<ExecSpace>(0, num_control_points_), ko);
    }
    for (;;) {
      MortarSegments3 ks;
      ks.s = slave; ks.m = master; ks.sp = sp; ks.ed = edges; ks.gauss = gauss; ks.tri = tri; ks.slots = slots; ks.flags = seg_flags_;
      // the element images of a master of degree > 1 are cut into 2 x 2 cells (straight edges
      // per cell follow the curved images: the tangent's consistency error on the curved test
      // surfaces of tests/test_kts3d.cpp falls from up to 1e-3 with whole elements below their
      // 5e-4, and the coarse Hertz ball's fitted p0 from +2.1 % to +1.9 %); a degree-1 master's
      // elements whole. contact.segment_cells sets it: whole elements (1) have 2.3x fewer slots
      // and halve the Hertz ball's contact stage (docs/performance.md)
      int pm = 1;
      for (const HostFace& hm : hm_) pm = std::max({pm, hm.p[0], hm.p[1]});
      static_assert(kMaxSegmentCells <= kMaxCells, "contact.segment_cells beyond the segmentation's cells");
      const int asked = cells > 0 ? cells : pair.segment_cells;   // a test's setting, else the problem file's
      ks.sub = asked > 0 ? std::min(asked, kMaxCells) : pm > 1 ? 2 : 1;
      ks.smooth = friction ? 2 : 1;
      if (static_cast<int>(cand_.extent(0)) != ne) cand_ = decltype(cand_)("mortar_candidates", ne, kMortar3Candidates);
      ks.cand = cand_;
      ks.skip = out_;
      Kokkos::deep_copy(seg_flags_, 0);
      Kokkos::parallel_for("iga::MortarSegments3", Kokkos::RangePolicy<ExecSpace>(c_begin, c_end), ks);
      auto fl = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), seg_flags_);
      if (nranks_ > 1) {   // every rank grows the same capacities (the slots' numbering is global)
        int mx[4];
        Teuchos::reduceAll(*comm_, Teuchos::REDUCE_MAX, 4, fl.data(), mx);
        std::copy(mx, mx + 4, fl.data());
      }
      if (fl(2) != 0) throw ContactError("3-D mortar: a clipped segment has more vertices than the segmentation holds");
      if (fl(0) == 0 && fl(1) == 0 && fl(3) == 0) break;
      if (fl(3) > 0) allocate_edges(std::max(fl(3), edges.per + edges.per / 2));
      if (fl(1) > 0) cand_ = decltype(cand_)("mortar_candidates", ne, std::max<int>(fl(1), cand_.extent(1) * 3 / 2));
      if (fl(0) > 0) {
        slots = std::max(fl(0), slots + slots / 2);
        allocate_points(ne * slots);
      }
    }
  }
  if (mortar) {   // the slave basis at the segmented slots, once for the sums per control point
    SlotBasis3 kb;
    kb.s = slave;
    kb.sp = sp;
    Kokkos::parallel_for("iga::SlotBasis3", Kokkos::RangePolicy<ExecSpace>(c_begin * slots, c_end * slots), kb);
  }
  ProjectSlavePoints3 k;
  k.s = slave;
  k.m = master;
  k.sp = sp;
  k.eps = pair.penalty;
  // this rank's points only: KTS its own (their assembly is this rank's; state() sums the
  // others' in), mortar the slots of the elements it segmented (segment_range)
  const int first = mortar ? c_begin * slots : p_begin, last = mortar ? c_end * slots : p_end;
  Kokkos::parallel_for("iga::ProjectSlavePoints3", Kokkos::RangePolicy<ExecSpace>(first, last), k);
  if (friction && !mortar) update_friction();
  if (mortar) {
    // the weighted gaps of this rank's control points, then every rank holds all of them
    MortarGaps3 kg;
    kg.s = slave; kg.sp = sp; kg.ms = ms; kg.eps = pair.penalty; kg.touch = sp.touch; kg.slots = slots; kg.out = out_;
    Kokkos::parallel_for("iga::MortarGaps3", Kokkos::RangePolicy<ExecSpace>(a_begin, a_end), kg);
    if (nranks_ > 1) {
      sum_device_over_ranks(*comm_, ms.gA, a_begin, a_end);
      sum_device_over_ranks(*comm_, ms.lambda, a_begin, a_end);
      sum_device_over_ranks(*comm_, ms.active, a_begin, a_end);
      sum_device_over_ranks(*comm_, ms.covered, a_begin, a_end);
      sum_device_over_ranks(*comm_, ms.cwA, a_begin, a_end);
    }
    MortarPointPressure3 kp;
    kp.s = slave; kp.sp = sp; kp.ms = ms;
    Kokkos::parallel_for("iga::MortarPointPressure3", Kokkos::RangePolicy<ExecSpace>(first, last), kp);
    if (nranks_ > 1) count_element_loads();
    if (friction) update_friction();   // the law per control point needs lambda_A
  }
  Kokkos::fence();
}

std::vector<int> ContactSurfaces3::out_of_contact() const {
  auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), out_);
  return std::vector<int>(h.data(), h.data() + h.extent(0));
}

void ContactSurfaces3::groups(std::vector<std::vector<GO>>& out, int& active) const {
  auto valid = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), sp.valid);
  auto gap = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), sp.gap);
  auto face = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), sp.face);
  auto elem = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), sp.elem);
  auto mface = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), sp.mface);
  auto melem = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), sp.melem);
  // the control points of element e of a face, widened by w control points each way
  auto element_cps = [](const HostFace& h, int e, int w, std::vector<GO>& g) {
    const int s0 = h.span[0][e % h.ne[0]], s1 = h.span[1][e / h.ne[0]];
    for (int j = std::max(0, s1 - h.p[1] - w); j <= std::min(h.n[1] - 1, s1 + w); ++j)
      for (int i = std::max(0, s0 - h.p[0] - w); i <= std::min(h.n[0] - 1, s0 + w); ++i) g.push_back(h.gid[i + h.n[0] * j]);
  };
  // one group per (slave element, master element) pair: the points of a slave element mostly
  // share a few master elements
  std::set<std::array<int, 4>> seen;
  auto pressure = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), sp.pressure);
  for (int i = p_begin; i < p_end; ++i) {
    if (face(i) < 0 || !valid(i)) continue;
    if (!mortar && kts_active(gap(i), sp.touch)) ++active;
    if (!seen.insert({face(i), elem(i), mface(i), melem(i)}).second) continue;
    std::vector<GO> g;
    element_cps(hs_[face(i)], elem(i), 0, g);
    element_cps(hm_[mface(i)], melem(i), 1, g);
    out.push_back(std::move(g));
  }
  if (!mortar) return;
  // mortar: delta g_A couples every control point of its support's slots: per slave element
  // the union of its slots' groups, per A of this rank the union over its elements
  const int ne = slave.eoff[slave.n];
  std::vector<std::vector<GO>> per_elem(ne);
  auto eelem = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), edges.elem);
  auto emelem = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), edges.melem);
  auto emface = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), edges.mface);
  for (int e = c_begin; e < c_end; ++e) {   // the elements this rank segmented
    std::set<std::pair<int, int>> melems;   // (master face, element)
    for (int i = e * slots; i < (e + 1) * slots; ++i)
      if (face(i) >= 0 && valid(i)) melems.insert({mface(i), melem(i)});
    if (melems.empty()) continue;
    for (int i = e * edges.per; i < (e + 1) * edges.per && eelem(i) >= 0; ++i) melems.insert({emface(i), emelem(i)});
    const int f = static_cast<int>(std::upper_bound(slave.eoff + 1, slave.eoff + slave.n, e) - (slave.eoff + 1));
    element_cps(hs_[f], e - slave.eoff[f], 0, per_elem[e]);
    for (const auto& [f, E] : melems) element_cps(hm_[f], E, 1, per_elem[e]);
  }
  auto act = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ms.active);
  for (int A = a_begin; A < a_end; ++A) {
    if (act(A)) ++active;
    std::vector<GO> g;
    for (int k = a_ptr_h_[A]; k < a_ptr_h_[A + 1]; ++k) {   // A's elements on every face that holds it
      const int f = a_occ_h_[2 * k], a = a_occ_h_[2 * k + 1];
      const HostFace& hs = hs_[f];
      const int ia = a % hs.n[0], ja = a / hs.n[0];
      for (int e1 = 0; e1 < hs.ne[1]; ++e1)
        for (int e0 = 0; e0 < hs.ne[0]; ++e0) {
          const int s0 = hs.span[0][e0], s1 = hs.span[1][e1];
          if (s0 < ia || s0 > ia + hs.p[0] || s1 < ja || s1 > ja + hs.p[1]) continue;
          const auto& pe = per_elem[slave.eoff[f] + e0 + hs.ne[0] * e1];
          g.insert(g.end(), pe.begin(), pe.end());
        }
    }
    std::sort(g.begin(), g.end());
    g.erase(std::unique(g.begin(), g.end()), g.end());
    if (!g.empty()) out.push_back(std::move(g));
  }
}

void ContactSurfaces3::set_lids(const std::vector<GO>& cps) {
  for (int which = 0; which < 2; ++which) {
    ContactFaces& faces = which == 0 ? slave : master;
    const auto& hf = which == 0 ? hs_ : hm_;
    for (int k = 0; k < faces.n; ++k) {
      auto h = Kokkos::create_mirror_view(faces.f[k].lid);
      for (size_t a = 0; a < hf[k].gid.size(); ++a) {
        auto it = std::lower_bound(cps.begin(), cps.end(), hf[k].gid[a]);
        h(a) = (it != cps.end() && *it == hf[k].gid[a]) ? static_cast<int>(it - cps.begin()) : -1;
      }
      Kokkos::deep_copy(faces.f[k].lid, h);
    }
  }
}

int ContactSurfaces3::active_elements() const {
  const int ne = slave.eoff[slave.n];
  auto face = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), sp.face);
  auto elem = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), sp.elem);
  auto valid = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), sp.valid);
  auto pr = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), sp.pressure);
  std::vector<int> mine(ne, 0), all(ne, 0);
  for (int i = p_begin; i < p_end; ++i)   // (this rank's slots: disjoint ranges that cover all)
    if (face(i) >= 0 && valid(i) && pr(i) > 0) mine[slave.eoff[face(i)] + elem(i)] = 1;
  if (ne > 0) Teuchos::reduceAll(*comm_, Teuchos::REDUCE_MAX, ne, mine.data(), all.data());
  return static_cast<int>(std::count(all.begin(), all.end(), 1));
}

int ContactSurfaces3::active_master_elements() const {
  std::vector<int> off(master.n + 1, 0);
  for (int f = 0; f < master.n; ++f) off[f + 1] = off[f] + master.f[f].sd.ne[0] * master.f[f].sd.ne[1];
  const int ne = off[master.n];
  auto mface = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), sp.mface);
  auto melem = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), sp.melem);
  auto valid = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), sp.valid);
  auto pr = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), sp.pressure);
  std::vector<int> mine(ne, 0), all(ne, 0);
  for (int i = p_begin; i < p_end; ++i)   // (this rank's points or slots, as in active_elements)
    if (valid(i) && pr(i) > 0 && mface(i) >= 0 && mface(i) < master.n && melem(i) >= 0 && off[mface(i)] + melem(i) < off[mface(i) + 1])
      mine[off[mface(i)] + melem(i)] = 1;
  if (ne > 0) Teuchos::reduceAll(*comm_, Teuchos::REDUCE_MAX, ne, mine.data(), all.data());
  return static_cast<int>(std::count(all.begin(), all.end(), 1));
}

void ContactSurfaces3::state(ContactPointState& s, bool projected_only) const {
  const int n = num_points();
  auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), sp.x);
  auto X = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), sp.X);
  auto nrm = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), sp.normal);
  auto uv = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), sp.uv);
  auto gap = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), sp.gap);
  auto pr = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), sp.pressure);
  auto valid = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), sp.valid);
  auto w = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), sp.weight);
  auto face = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), sp.face);
  auto trac = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), fr.t);
  auto slip = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), fr.slip);
  auto gT = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), fr.gT);
  auto fst = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), fr.state);
  if (nranks_ > 1) {
    // each rank projects its own points (KTS) or segments its own elements (mortar): the
    // others' entries are summed in over the ranks ([p_begin, p_end) are disjoint and cover all
    // points), so that every rank holds every point's state
    auto sum = [&](auto& v) { sum_over_ranks(*comm_, v, p_begin, p_end); };
    sum(x);
    sum(nrm);
    sum(gap);
    sum(pr);
    sum(valid);
    if (mortar) {   // the slots themselves come from the segmentation
      sum(X);
      sum(uv);
      sum(w);
      sum(face);
    }
    if (friction) {
      sum(trac);
      sum(slip);
      sum(gT);
      sum(fst);
    }
  }
  for (int i = 0; i < n; ++i) {
    if (face(i) < 0) continue;   // an unused mortar slot
    if (projected_only && !valid(i)) continue;
    s.x.push_back(x(i, 0));
    s.y.push_back(x(i, 1));
    s.z.push_back(x(i, 2));
    for (int c = 0; c < 3; ++c) s.X.push_back(X(i, c));
    s.nx.push_back(valid(i) ? nrm(i, 0) : 0.0);
    s.ny.push_back(valid(i) ? nrm(i, 1) : 0.0);
    s.nz.push_back(valid(i) ? nrm(i, 2) : 0.0);
    s.xi.push_back(uv(i, 0));
    s.eta.push_back(uv(i, 1));
    s.face.push_back(face(i));
    s.gap.push_back(valid(i) ? gap(i) : std::nan(""));
    s.pressure.push_back(pr(i));
    s.weight.push_back(w(i));
    s.active.push_back(valid(i) && (mortar ? pr(i) > 0 : kts_active(gap(i), sp.touch)) ? 1 : 0);
    const double t[3] = {trac(i, 0), trac(i, 1), trac(i, 2)};
    s.tangential.push_back(std::sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]));
    s.slip.push_back(slip(i));
    s.slip_increment.push_back(gT(i));
    s.state.push_back(fst(i));
    s.tx.push_back(t[0]);
    s.ty.push_back(t[1]);
    s.tz.push_back(t[2]);
  }
}

}  // namespace iga
