#pragma once
// Coulomb friction with mortar contact between solids (3-D): the 2-D mortar law of
// contact_friction.hpp on a two-dimensional tangent plane, the slip of each quadrature slot from
// contact_friction3.hpp. Kernels, in the order of an update: UpdateFriction3 (mortar: each
// slot's slip vector g_T), MortarFrictionLaw3 (per slave control point A), MortarFrictionPoints3
// (the traction field at the slots); assembly: AssembleFriction3 (mortar: the slots' part at
// fixed traction) and AssembleMortarFriction3 (per A).
//
// Slip of a slot (objective, as for KTS): g_T = a_al(xi) (xi - xi_n)^al, xi the current foot of
//   the slot's slave point, xi_n the foot of the same slave point (the slot's parameter) in the
//   last converged configuration on the last converged master (projected anew at each update,
//   as in 2-D: the slots move with the segmentation). No converged step yet: g_T = 0.
// Weighted slip of slave control point A (a vector in space, tangent to a flat master):
//   s_A = int R_A g_T dGamma_0 / w_A,   w_A = int R_A dGamma_0   (contact_mortar3.hpp)
// Law per A (lambda_A the mortar pressure, A active as for the weighted gap):
//   trial  tr_A = lamT_A - eps_T s_A   (lamT_A the committed traction vector (penalty),
//                                       augmented (ALM))
//   stick  |tr_A| <= mu lambda_A (+ eps_T x the touch tolerance):  tau_A = tr_A
//   slip   otherwise:  tau_A = mu lambda_A tr_A / |tr_A|
//   accumulated slip += (|tr_A| - |tau_A|) / eps_T. The committed traction is a vector in space:
//   where the master turns between steps by an angle theta, its normal part is theta |lamT_A|
//   (2-D keeps a scalar along the tangent).
// Weak form: f_c = -sum_A tau_A . V_A,  V_A = int R_A d g_T / du dGamma_0 (= w_A d s_A / du, 3
//   rows over A's dense dof range, MortarRange3); at the slots, t(xi) = sum_A tau_A R_A(xi) and
//   f_c = -int t . delta g_T dGamma_0, which AssembleFriction3 assembles with its derivative at
//   fixed t. The derivative of tau_A (this file):
//   stick  K_c += eps_T / w_A sum_c V_A,c (x) V_A,c
//   slip   K_c += sum_c V_A,c (x) [mu that_c eps / w_A delta g_A
//                                  + mu lambda_A / |tr_A| eps_T / w_A (V_A,c - that_c that . V_A)]
//          (that = tr_A / |tr_A|, delta g_A = int R_A N dGamma_0; the first term only where
//          lambda_A > 0).
// Where the master ends inside a slave element (contact_mortar3.hpp, MortarEdges3), the covered
//   part's motion adds, at the edge points (as slave points with their own references and slip
//   vectors: ContactSurfaces3's edge points), K_c -= \oint (t . delta g_T) (x) V' dl_0
//   (AssembleMortarFrictionEdge3) and, in the columns of tau_A's derivative, bT_A = \oint R_A g_T
//   (x) V' dl_0 beside V_A and b_A = \oint R_A g V' beside delta g_A (MortarFrictionEdgeVectors3).
// Data layout: Friction3's per-point gv and per-A sA, trA, tauA, lamTA, slipA(_c), stateA;
// scratch rows per A (MortarScratch: dof and row `cap` wide, v0 and v1 8 cap wide: V_A,x,
// V_A,y, V_A,z, delta g_A, then the boundary parts bT_A,x, bT_A,y, bT_A,z, b_A, dense in v0,
// compacted in v1).
// Cost per stick or slip A: its support's slots (about (p + 1)^2 slave elements x slots) x a
// point's Fad set-up (~ 200 Fad operations of 34 flops) and 3 x 3 (ns + nm) columns, plus the
// outer product (3 nnz^2 to 4 nnz^2 flops, nnz the touched dofs, about 3 (2p+1)^2 + 3 (p+3)^2).
#include "kernels/contact_friction3.hpp"
#include "kernels/contact_mortar3.hpp"

namespace iga {

/// The weighted slip, the law and the accumulated slip of every slave control point A.
struct MortarFrictionLaw3 {
  ContactFaces s;
  SlavePoints3 sp;
  MortarState ms;
  Friction3 fr;
  int slots = 1;

  KOKKOS_INLINE_FUNCTION void operator()(const int A) const {
    double sum[3] = {0, 0, 0}, nsum[3] = {0, 0, 0};
    const SlavePoints3& p = sp;
    const Friction3& f = fr;
    for_each_support_slot3(s, sp, slots, A, [&](int i, double RA, int, const int*) {
      for (int c = 0; c < 3; ++c) sum[c] += RA * p.weight(i) * f.gv(i, c);
      if (p.valid(i))
        for (int c = 0; c < 3; ++c) nsum[c] += RA * p.weight(i) * p.normal(i, c);
    });
    for (int c = 0; c < 3; ++c) {
      fr.nA(A, c) = nsum[c];
      fr.sA(A, c) = sum[c] / ms.wA(A);
      fr.trA(A, c) = 0;
      fr.tauA(A, c) = 0;
    }
    fr.stateA(A) = 0;
    fr.slipA(A) = fr.slipA_c(A);
    if (!ms.active(A)) return;
    double tr[3], n2 = 0;
    for (int c = 0; c < 3; ++c) {
      tr[c] = fr.lamTA(A, c) - fr.epsT * fr.sA(A, c);
      n2 += tr[c] * tr[c];
    }
    const double norm = kmath::sqrt(n2), bound = fr.mu * ms.lambda(A);
    // a control point touching with lambda = 0 and a trial of round-off sticks (as for KTS)
    const int st = norm <= bound + fr.epsT * sp.touch ? 1 : 2;
    double tn = 0;
    for (int c = 0; c < 3; ++c) {
      fr.trA(A, c) = tr[c];
      fr.tauA(A, c) = st == 1 ? tr[c] : bound * tr[c] / norm;
      tn += fr.tauA(A, c) * fr.tauA(A, c);
    }
    fr.stateA(A) = st;
    fr.slipA(A) = fr.slipA_c(A) + (norm - kmath::sqrt(tn)) / fr.epsT;
  }
};

/// The traction field t = sum_A tau_A R_A at the slots, the accumulated slip sum_A slip_A R_A,
/// |g_T|, and the state of the control point that contributes most of the slot's pressure (0
/// where the slot carries none).
struct MortarFrictionPoints3 {
  ContactFaces s;
  SlavePoints3 sp;
  MortarState ms;
  Friction3 fr;

  KOKKOS_INLINE_FUNCTION void operator()(const int i) const {
    for (int c = 0; c < 3; ++c) fr.t(i, c) = 0;
    fr.slip(i) = 0;
    fr.state(i) = 0;
    fr.gT(i) = kmath::sqrt(fr.gv(i, 0) * fr.gv(i, 0) + fr.gv(i, 1) * fr.gv(i, 1) + fr.gv(i, 2) * fr.gv(i, 2));
    if (sp.face(i) < 0 || !sp.valid(i)) return;
    double R[kMaxSurfaceBasis];
    int cp[kMaxSurfaceBasis];
    const int n = slave_point_basis(s, sp, i, R, cp);
    const ContactFace& sf = s.f[sp.face(i)];
    double slip = 0, best = -1;
    int st = 0;
    for (int a = 0; a < n; ++a) {
      const int A = sf.aid(cp[a]);
      for (int c = 0; c < 3; ++c) fr.t(i, c) += fr.tauA(A, c) * R[a];
      slip += fr.slipA(A) * R[a];
      if (ms.lambda(A) * R[a] > best) {
        best = ms.lambda(A) * R[a];
        st = fr.stateA(A);
      }
    }
    fr.slip(i) = slip;
    fr.state(i) = sp.pressure(i) > 0 ? st : 0;
  }
};

/// The derivative of tau_A (header) for this rank's slave control points [a_begin, ...), in three
/// passes: MortarFrictionRanges3 (per A: its dense range, zeroed), MortarFrictionVectors3 (per
/// slot, its slip variation evaluated once and added, times w R_A, to V_A of each A of its
/// element; delta g_A where A slips), AssembleMortarFriction3 (per A: compacted to the touched
/// overlap dofs, sorted, summed as outer products).
struct MortarFrictionRanges3 {
  ContactFaces s, m;
  SlavePoints3 sp;
  MortarState ms;
  Friction3 fr;
  MortarScratch sc;
  Kokkos::View<MortarRange3*, MemSpace> range;   // per A of this rank; size 0: nothing to add
  Kokkos::View<int*, MemSpace> size;
  MortarEdges3 ed;
  int slots = 1, a_begin = 0;

  KOKKOS_INLINE_FUNCTION void operator()(const int k) const {
    const int A = a_begin + k;
    size(k) = 0;
    if (fr.stateA(A) == 0) return;
    MortarRange3 rg;
    const int n = rg.init(s, m, sp, slots, ed, A);
    if (n > sc.cap()) {
      Kokkos::atomic_fetch_max(&ms.flags(1), n);
      return;
    }
    range(k) = rg;
    size(k) = n;
    for (int q = 0; q < 8 * n; ++q) sc.v0(k, q) = 0;
  }
};

struct MortarFrictionVectors3 {
  ContactFaces s, m;
  SlavePoints3 sp;
  MortarState ms;
  Friction3 fr;
  MortarScratch sc;
  Kokkos::View<MortarRange3*, MemSpace> range;
  Kokkos::View<int*, MemSpace> size;
  int a_begin = 0, a_end = 0;

  KOKKOS_INLINE_FUNCTION void operator()(const int i) const {
    using F = FrictionPoint3::F;
    if (sp.face(i) < 0 || !sp.valid(i)) return;
    const int fs = sp.face(i), mf = sp.mface(i);
    const ContactFace& sf = s.f[fs];
    const SurfaceData& md = m.f[mf].sd;
    double Rs[kMaxSurfaceBasis], Ru[kMaxSurfaceBasis], Rv[kMaxSurfaceBasis], Rm[kMaxSurfaceBasis];
    int cps[kMaxSurfaceBasis], cpm[kMaxSurfaceBasis], mspn[2];
    const int ns = slave_point_basis(s, sp, i, Rs, cps);
    bool any = false, slip = false;
    for (int a = 0; a < ns; ++a) {
      const int A = sf.aid(cps[a]), k = A - a_begin;
      if (A < a_begin || A >= a_end || size(k) == 0) continue;
      any = true;
      slip = slip || (fr.stateA(A) == 2 && ms.lambda(A) > 0);
    }
    if (!any) return;
    const bool ref = fr.ref_face(i) == sp.mface(i);
    if (!ref && !slip) return;   // no reference: g_T = 0 whatever u
    surface_element_spans(md, sp.melem(i), mspn);
    const int nm = surface_basis(md, mspn, sp.muv(i, 0), sp.muv(i, 1), Rm, Ru, Rv, cpm);
    FrictionPoint3 P;
    F g[3];
    if (ref) {
      friction_point3(s, m, sp, fr, i, P);
      P.slip(g);
    }
    const double n[3] = {sp.normal(i, 0), sp.normal(i, 1), sp.normal(i, 2)};
    for (int a = 0; a < ns; ++a) {
      const int A = sf.aid(cps[a]), k = A - a_begin;
      if (A < a_begin || A >= a_end || size(k) == 0) continue;
      const MortarRange3& rg = range(k);
      const int sz = size(k);
      const double w = Rs[a] * sp.weight(i);
      if (fr.stateA(A) == 2 && ms.lambda(A) > 0)   // delta g_A, as AssembleMortarGap3
        add_gap_variation(rg, fs, Rs, cps, ns, mf, Rm, cpm, nm, n, w,
                          [&](int q, double v) { Kokkos::atomic_add(&sc.v0(k, 3 * sz + q), v); });
      if (!ref) continue;
      for (int cb = 0; cb < P.ns + P.nm; ++cb) {
        const int q0 = cb < P.ns ? rg.slave(fs, P.cps[cb]) : rg.master(mf, P.cpm[cb - P.ns]);
        for (int cc = 0; cc < 3; ++cc)
          for (int c = 0; c < 3; ++c) Kokkos::atomic_add(&sc.v0(k, c * sz + q0 + cc), w * P.column(g[c], cb, cc));
      }
    }
  }
};

/// The references of slots and edge points (esp / efr: either): the slave point in the converged
/// configuration (sc) projected onto the polynomial piece of its current foot's element on the
/// converged master (mc), extended beyond the element and the face (not clamped), from the
/// current foot. So the slip a_al(xi) (xi - xi_n) is measured in one polynomial chart, that of
/// the foot's element: an edge point's foot lies on the master's boundary, where a clamped
/// projection would lose half of them; a slot whose foot crossed into another face of a master
/// list, or across a C^0 edge inside a face, during the step keeps its slip (the reference
/// projected onto the whole face, following its elements, made the tangent miss 4e-3 of the
/// largest column across a C^0 ridge inside one face: Mortar3FrictionTangent.AcrossAC0Ridge).
struct MortarReferences3 {
  ContactFaces sc, mc;
  SlavePoints3 esp;
  Friction3 efr;

  KOKKOS_INLINE_FUNCTION void operator()(const int i) const {
    efr.ref_face(i) = -1;
    if (esp.face(i) < 0 || !esp.valid(i)) return;
    int es[2], ms[2];
    const SurfaceData& sd = sc.f[esp.face(i)].sd;
    surface_element_spans(sd, esp.elem(i), es);
    double ds[6][3], dm[6][3];
    surface_derivatives_to<0>(sd, es, esp.uv(i, 0), esp.uv(i, 1), ds);
    double xi = esp.muv(i, 0), eta = esp.muv(i, 1);
    surface_element_spans(mc.f[esp.mface(i)].sd, esp.melem(i), ms);
    closest_point_unclamped(mc.f[esp.mface(i)].sd, ds[0], xi, eta, ms, false, dm);
    if (!(kmath::fabs(xi) < 1e300 && kmath::fabs(eta) < 1e300)) return;   // Newton ran away
    efr.ref_face(i) = esp.mface(i);
    efr.ref_uv(i, 0) = xi;
    efr.ref_uv(i, 1) = eta;
  }
};

/// The boundary parts of the columns (header): per edge point, for each A of its slave element
/// on this rank with a range, bT_A += w R_A g_T (x) V' and, where A slips with a pressure,
/// b_A += w R_A g V'. esp / efr: the edge points as slave points and their slip vectors.
struct MortarFrictionEdgeVectors3 {
  ContactFaces s, m;
  MortarEdges3 ed;
  SlavePoints3 esp;
  Friction3 efr;
  MortarState ms;
  Friction3 fr;
  MortarScratch sc;
  Kokkos::View<MortarRange3*, MemSpace> range;
  Kokkos::View<int*, MemSpace> size;
  int a_begin = 0, a_end = 0;

  KOKKOS_INLINE_FUNCTION void operator()(const int i) const {
    if (ed.elem(i) < 0 || !esp.valid(i)) return;
    const int fs = ed.sface(i), mf = ed.mface(i);
    const ContactFace& sf = s.f[fs];
    const SurfaceData& sd = sf.sd;
    const SurfaceData& md = m.f[mf].sd;
    double Rs[kMaxSurfaceBasis];
    int cps[kMaxSurfaceBasis], es[2], mspn[2];
    const int ns = slave_point_basis(s, esp, i, Rs, cps);
    surface_element_spans(sd, ed.elem(i), es);
    surface_element_spans(md, ed.melem(i), mspn);
    const double gT[3] = {efr.gv(i, 0), efr.gv(i, 1), efr.gv(i, 2)}, g = esp.gap(i);
    for (int a = 0; a < ns; ++a) {
      const int A = sf.aid(cps[a]), k = A - a_begin;
      if (A < a_begin || A >= a_end || size(k) == 0) continue;
      const MortarRange3& rg = range(k);
      const int sz = size(k);
      const double w = Rs[a] * ed.d(i, 3);
      const bool dlam = fr.stateA(A) == 2 && ms.lambda(A) > 0;
      edge_velocity(sd, es, md, mspn, ed, i, [&](bool master, int, int cp, int c, double v) {
        const int q = (master ? rg.master(mf, cp) : rg.slave(fs, cp)) + c;
        for (int cc = 0; cc < 3; ++cc)
          if (gT[cc] != 0) Kokkos::atomic_add(&sc.v0(k, (4 + cc) * sz + q), w * gT[cc] * v);
        if (dlam) Kokkos::atomic_add(&sc.v0(k, 7 * sz + q), w * g * v);
      });
    }
  }
};

/// The boundary term of the traction part, K_c -= \oint (t . delta g_T) (x) V' dl_0, at this
/// rank's edge points [e_begin, ...) with a reference (elsewhere g_T = 0 whatever u).
template <class LocalMatrix>
struct AssembleMortarFrictionEdge3 {
  ContactFaces s, m;
  MortarEdges3 ed;
  SlavePoints3 esp;
  Friction3 efr;
  Friction3 fr;
  int e_begin = 0;
  LocalMatrix K;

  KOKKOS_INLINE_FUNCTION void operator()(const int k) const {
    using F = FrictionPoint3::F;
    const int i = e_begin + k;
    if (ed.elem(i) < 0 || !esp.valid(i) || efr.ref_face(i) != esp.mface(i)) return;
    const ContactFace& sf = s.f[ed.sface(i)];
    const SurfaceData& sd = sf.sd;
    double Rs[kMaxSurfaceBasis];
    int cps[kMaxSurfaceBasis];
    const int ns = slave_point_basis(s, esp, i, Rs, cps);
    double t[3] = {0, 0, 0};
    for (int a = 0; a < ns; ++a)
      for (int c = 0; c < 3; ++c) t[c] += fr.tauA(sf.aid(cps[a]), c) * Rs[a];
    if (t[0] == 0 && t[1] == 0 && t[2] == 0) return;
    FrictionPoint3 P;
    friction_point3(s, m, esp, efr, i, P);
    F g[3];
    P.slip(g);
    F tg = t[0] * g[0] + t[1] * g[1] + t[2] * g[2];
    const int nd = 3 * (P.ns + P.nm);
    double vel[3 * 2 * kMaxSurfaceBasis];
    for (int q = 0; q < nd; ++q) vel[q] = 0;
    int es[2], mspn[2];
    const ContactFace& mf = m.f[ed.mface(i)];
    surface_element_spans(sd, ed.elem(i), es);
    surface_element_spans(mf.sd, ed.melem(i), mspn);
    edge_velocity(sd, es, mf.sd, mspn, ed, i,
                  [&](bool master, int a, int, int c, double v) { vel[3 * (a + (master ? P.ns : 0)) + c] += v; });
    const double w = ed.d(i, 3);
    auto lid = [&](int r) {
      const int cp = r / 3;
      const int l = cp < P.ns ? sf.lid(P.cps[cp]) : mf.lid(P.cpm[cp - P.ns]);
      return l < 0 ? -1 : dof_of(l, r % 3, 3);
    };
    add_edge_outer(K, P.ns + P.nm, w, [&](int r) { return P.column(tg, r / 3, r % 3); }, vel, lid);
  }
};

template <class LocalMatrix>
struct AssembleMortarFriction3 {
  ContactFaces s, m;
  MortarState ms;
  Friction3 fr;
  MortarScratch sc;
  Kokkos::View<MortarRange3*, MemSpace> range;
  Kokkos::View<int*, MemSpace> size;
  double eps = 0;
  int a_begin = 0;
  LocalMatrix K;

  KOKKOS_INLINE_FUNCTION void operator()(const int k) const {
    const int A = a_begin + k;
    const int st = fr.stateA(A), sz = size(k);
    if (st == 0 || sz == 0) return;
    const MortarRange3& rg = range(k);
    const bool dlam = st == 2 && ms.lambda(A) > 0;
    // compact to the entries touched in any of the eight vectors with an overlap dof, sorted by
    // dof; per entry: the rows' V_A (3) and delta g_A, then the columns' V_A + bT_A (3) and
    // delta g_A + b_A
    int nnz = 0;
    for (int q = 0; q < sz; ++q) {
      double val[8];
      bool any = false;
      for (int b = 0; b < 8; ++b) {
        val[b] = sc.v0(k, b * sz + q);
        any = any || val[b] != 0;
      }
      if (!any) continue;
      const int dof = rg.dof(q, s, m);
      if (dof < 0) continue;
      for (int b = 4; b < 8; ++b) val[b] += val[b - 4];
      merge_sorted_dof(dof, val, 8, nnz, [&](int r) -> int& { return sc.dof(k, r); },
                       [&](int r, int b) -> double& { return sc.v1(k, 8 * r + b); });
    }
    const double wA = ms.wA(A), cT = fr.epsT / wA;
    double that[3] = {0, 0, 0}, cs = 0, cn = 0;
    if (st == 2) {
      double n2 = 0;
      for (int c = 0; c < 3; ++c) n2 += fr.trA(A, c) * fr.trA(A, c);
      const double norm = kmath::sqrt(n2);
      for (int c = 0; c < 3; ++c) that[c] = fr.trA(A, c) / norm;
      cs = fr.mu * ms.lambda(A) / norm * cT;   // the turn of the slip direction
      cn = dlam ? fr.mu * mortar_eps(ms, A, eps) / wA : 0.0;     // the pressure's change
    }
    int* dof = &sc.dof(k, 0);
    double* row = &sc.row(k, 0);
    for (int r = 0; r < nnz; ++r) {
      const double* Vr = &sc.v1(k, 8 * r);
      if (Vr[0] == 0 && Vr[1] == 0 && Vr[2] == 0) continue;
      for (int q = 0; q < nnz; ++q) {
        const double* Vq = &sc.v1(k, 8 * q + 4);
        double v = 0;
        if (st == 1) {
          for (int c = 0; c < 3; ++c) v += Vr[c] * Vq[c];
          v *= cT;
        } else {
          const double tVq = that[0] * Vq[0] + that[1] * Vq[1] + that[2] * Vq[2];
          for (int c = 0; c < 3; ++c) v += Vr[c] * (cn * that[c] * Vq[3] + cs * (Vq[c] - that[c] * tVq));
        }
        row[q] = v;
      }
      K.sumIntoValues(dof[r], dof, nnz, row, true, true);
    }
  }
};

}  // namespace iga
