#pragma once
// Knot-to-surface (KTS) frictionless contact between faces of solids (3-D): the slave face's
// quadrature points are projected onto the master faces (closest point, contact_surface.hpp)
// and contribute penalty / augmented-Lagrangian forces and the consistent tangent. The 3-D
// form of contact_kts.hpp: one Kokkos::parallel_for over slave points per stage.
//
// Kinematics (current configuration x = X + u)
//   slave point     x_s = sum_a R_a(u, v) x_a          (a slave face of a trivariate patch)
//   master surface  rho(xi^1, xi^2) = sum_b R_b x_b,  a_al = rho_,al,  metric a_ab = a_a.a_b,
//                   A = a^-1, n the outward unit normal, curvature b_ab = n . rho_,ab
//   projection      (x_s - rho(xi)) . a_al = 0 (Newton in contact_surface.hpp)
//   gap             g = (x_s - rho) . n
// Variations over the point's dofs u_e = [slave a (x, y, z) ; master b (x, y, z)]
//   N    = [R_a n ; -R_b n]             delta g = N . delta u
//   T_al = [R_a a_al ; -R_b a_al]       Nb_al = [0 ; R_b,al n]
//   delta xi = H^-1 (T + g Nb) . delta u,   H = a - g b
//   Delta delta g = G = -T^T (A b H^-1) T - g Nb^T H^-1 Nb - (Nb^T H^-1 T + T^T H^-1 Nb)
//   (the 2-D G of contact_kts.hpp with a11 -> the metric; symmetric, since A + g A b H^-1 = H^-1)
// Contributions of an active point (g <= touch), p = max(0, -eps g) (kts_penalty):
//   f_c += -p w N,   K_c += w (eps N N^T - p G),   w = Gauss weights x |X_u x X_v| (reference)
// The force on the slave body is -sum over the slave rows of f_c (a ForceSum: Fx, Fy, Fz, Fn).
//
// Data layout: a contact surface is a list of patch faces (ContactFaces, at most
// kMaxFacesPerSurface), each a SurfaceData (knots, spans, current control points (x, y, z, w))
// with its reference control points X, displacements u and the overlap control-point LIDs of
// the contact matrix (lid). Slave points (SlavePoints3) carry their face, (u, v), element,
// weight, multiplier, and the projection's results (master face, element, (xi^1, xi^2), gap,
// pressure, current point, normal).
// Cost per active point: 2 surface evaluations ((p + 1)^2 x 40 flops each) and the tangent,
// (3 (ns + nm))^2 x ~20 flops for ns, nm control points of the slave and master elements.
// Per-thread storage: basis values of the two elements, 4 x (p + 1)^2 doubles (no dof-sized
// arrays: the tangent is summed one control-point column block at a time).
#include <KokkosSparse_CrsMatrix.hpp>

#include "kernels/contact_kts.hpp"
#include "kernels/contact_surface.hpp"

namespace iga {


constexpr int kMaxFacesPerSurface = 6;
constexpr int kMaxSurfaceBasis = kMaxBasis1D * kMaxBasis1D;

/// One patch face of a contact surface on the device.
struct ContactFace {
  SurfaceData sd;                                // current control points in sd.cp
  Kokkos::View<double* [4], MemSpace> cur;       // the same view, writable
  Kokkos::View<double* [4], MemSpace> X;         // reference (x, y, z, w)
  Kokkos::View<double* [3], MemSpace> u;         // current displacements
  Kokkos::View<int*, MemSpace> lid;              // overlap cp LID of the contact matrix, -1 absent
  Kokkos::View<int*, MemSpace> aid;              // mortar slave: the control point's index A
  double sign = 1;                               // outward normal = sign (S_u x S_v) / |S_u x S_v|
  // master: bit 2 d + end set where the face's edge at the start (end 0) or end (1) of its
  // parameter direction d lies in a symmetry plane of its body (a planar side held by
  // u . n = 0): the model is cut there and the body goes on as its mirror image, so feet
  // and mortar segments continue past that edge on its elements' polynomials
  int open = 0;
};

struct ContactFaces {
  int n = 0;
  ContactFace f[kMaxFacesPerSurface];
  SurfaceSearch search[kMaxFacesPerSurface];   // master only: bins over the current element boxes
  // master of a mortar pair: per element of face f the unit normal S_u x S_v at its centre and
  // the spread (contact_mortar3.hpp, centre_normal; -1: no normal there), once per update
  Kokkos::View<double* [4], MemSpace> frame[kMaxFacesPerSurface];
  double radius = 0;                        // master only: the search radius
  // mortar slave: the faces' elements numbered face after face (face f's from eoff[f]); the
  // control points A numbered once where faces share them (ContactFace::aid), and A's
  // occurrences (face, control point of the face) in [a_ptr(A), a_ptr(A + 1)) of a_occ
  int eoff[kMaxFacesPerSurface + 1] = {0};
  Kokkos::View<int*, MemSpace> a_ptr;
  Kokkos::View<int* [2], MemSpace> a_occ;
};

struct SlavePoints3 {
  Kokkos::View<int*, MemSpace> face, elem;         // slave face and its element e0 + ne0 e1
  Kokkos::View<double* [2], MemSpace> uv;          // slave parameters
  Kokkos::View<double*, MemSpace> weight;          // reference measure
  Kokkos::View<double* [3], MemSpace> X;           // reference slave point
  // results
  Kokkos::View<int*, MemSpace> valid, mface, melem;
  Kokkos::View<double* [2], MemSpace> muv;
  Kokkos::View<double*, MemSpace> gap, pressure;
  Kokkos::View<double* [3], MemSpace> x, normal;
  // mortar: the slave basis R at each slot (slot, local function), filled after each
  // segmentation (SlotBasis3, contact_mortar3.hpp) for the per-control-point sums
  Kokkos::View<double**, Kokkos::LayoutRight, MemSpace> R;
  double touch = 0;
};


/// Spans of element e of a surface.
KOKKOS_INLINE_FUNCTION void surface_element_spans(const SurfaceData& sd, int e, int s[2]) {
  s[0] = sd.span[0](e % sd.ne[0]);
  s[1] = sd.span[1](e / sd.ne[0]);
}

/// Rational basis R and its parameter derivatives Ru, Rv of the (p0 + 1)(p1 + 1) control
/// points of the element with spans s (local index i + (p0 + 1) j), and their surface indices.
KOKKOS_INLINE_FUNCTION int surface_basis(const SurfaceData& sd, const int s[2], double u, double v, double* R, double* Ru,
                                         double* Rv, int* cp) {
  double N[2][kMaxBasis1D], M[2][kMaxBasis1D];
  bspline_ders(s[0], u, sd.p[0], sd.U[0].data(), 1, N);
  bspline_ders(s[1], v, sd.p[1], sd.U[1].data(), 1, M);
  double W = 0, Wu = 0, Wv = 0;
  int k = 0;
  for (int j = 0; j <= sd.p[1]; ++j)
    for (int i = 0; i <= sd.p[0]; ++i, ++k) {
      const int a = surface_cp(sd, s, i, j);
      const double w = sd.cp(a, 3);
      cp[k] = a;
      R[k] = N[0][i] * M[0][j] * w;
      Ru[k] = N[1][i] * M[0][j] * w;
      Rv[k] = N[0][i] * M[1][j] * w;
      W += R[k];
      Wu += Ru[k];
      Wv += Rv[k];
    }
  for (int m = 0; m < k; ++m) {
    R[m] /= W;
    Ru[m] = (Ru[m] - R[m] * Wu) / W;
    Rv[m] = (Rv[m] - R[m] * Wv) / W;
  }
  return k;
}

KOKKOS_INLINE_FUNCTION void cross3(const double* a, const double* b, double* c) {
  c[0] = a[1] * b[2] - a[2] * b[1];
  c[1] = a[2] * b[0] - a[0] * b[2];
  c[2] = a[0] * b[1] - a[1] * b[0];
}

/// Current control points of every face from X and u (one kernel per face).
inline void update_face_points(const ContactFace& f) {
  const auto cur = f.cur;
  const auto X = f.X;
  const auto u = f.u;
  Kokkos::parallel_for("iga::ContactFacePoints", Kokkos::RangePolicy<ExecSpace>(0, static_cast<int>(cur.extent(0))),
                       KOKKOS_LAMBDA(const int a) {
                         for (int c = 0; c < 3; ++c) cur(a, c) = X(a, c) + u(a, c);
                         cur(a, 3) = X(a, 3);
                       });
}

/// kts_alm in 3-D runs on mortar's kernels at these points (solver/contact3d.cpp: the KTS
/// points in mortar's slots, no segmentation), so its pressure is mortar's field
/// p = sum_A R_A <Lambda_A - eps g_A / w_A>, with no penalty per point.

/// The slave basis R at slave point (or mortar slot) i on its face, and the face's control
/// point indices cp.
KOKKOS_INLINE_FUNCTION int slave_point_basis(const ContactFaces& s, const SlavePoints3& sp, int i, double* R, int* cp) {
  const SurfaceData& sd = s.f[sp.face(i)].sd;
  int es[2];
  surface_element_spans(sd, sp.elem(i), es);
  double Ru[kMaxSurfaceBasis], Rv[kMaxSurfaceBasis];
  return surface_basis(sd, es, sp.uv(i, 0), sp.uv(i, 1), R, Ru, Rv, cp);
}

/// Slave points' current positions and their projections onto the nearest master face (a foot
/// inside that face; beyond every master face's edges: no projection, valid 0).
struct ProjectSlavePoints3 {
  ContactFaces s, m;
  SlavePoints3 sp;
  double eps = 0;

  KOKKOS_INLINE_FUNCTION void operator()(const int i) const {
    if (sp.face(i) < 0) {   // an unused mortar slot
      sp.valid(i) = 0;
      sp.pressure(i) = 0;
      return;
    }
    const int prev_face = sp.mface(i), prev_elem = sp.melem(i);
    sp.valid(i) = 0;
    sp.gap(i) = 1e300;
    sp.pressure(i) = 0;
    sp.mface(i) = -1;
    const SurfaceData& ss = s.f[sp.face(i)].sd;
    int es[2];
    surface_element_spans(ss, sp.elem(i), es);
    double d[6][3];
    surface_derivatives_to<0>(ss, es, sp.uv(i, 0), sp.uv(i, 1), d);
    const double x[3] = {d[0][0], d[0][1], d[0][2]};
    for (int c = 0; c < 3; ++c) sp.x(i, c) = x[c];
    double best = 1e300, buv[2] = {0, 0}, bfoot[3] = {0, 0, 0}, bt[2][3];
    int bface = -1, belem = -1;
    bool have_tangents = false;   // bt holds S_u, S_v at the foot (the warm start's projection)
    auto keep = [&](int f, int e, double d2, const double uv[2], const double foot[3]) {
      best = d2;
      bface = f;
      belem = e;
      buv[0] = uv[0];
      buv[1] = uv[1];
      for (int c = 0; c < 3; ++c) bfoot[c] = foot[c];
    };
    // warm start: Newton from the previous projection on its element; kept without a search
    // when it lands strictly inside that element (the closest point moved continuously)
    if (prev_face >= 0 && prev_elem >= 0) {
      const SurfaceData& sd = m.f[prev_face].sd;
      double uv[2] = {sp.muv(i, 0), sp.muv(i, 1)}, foot[3];
      bool inside = false;
      const int open = m.f[prev_face].open;
      const double d2 = project_on_surface_element(sd, prev_elem, x, uv, foot, inside, true, bt, open);
      int ps[2];
      surface_element_spans(sd, prev_elem, ps);
      bool interior = inside;
      for (int k = 0; k < 2; ++k)   // (past an open edge of the face counts as interior)
        interior = interior && (uv[k] > sd.U[k](ps[k]) || open_past(sd, ps, k, 0, open)) &&
                   (uv[k] < sd.U[k](ps[k] + 1) || open_past(sd, ps, k, 1, open));
      if (interior && d2 <= m.radius * m.radius) {
        keep(prev_face, prev_elem, d2, uv, foot);
        have_tangents = true;
      }
    }
    const int nsearch = bface < 0 ? m.n : 0;   // no warm start: every master face, the nearest foot
    for (int f = 0; f < nsearch; ++f) {
      double uv[2], foot[3], d2;
      bool inside = false;
      const int e = closest_on_surface(m.f[f].sd, m.search[f], x, m.radius, uv, foot, d2, inside, m.f[f].open);
      if (e >= 0 && inside && d2 < best) keep(f, e, d2, uv, foot);
    }
    sp.melem(i) = belem;
    if (bface < 0) return;
    const ContactFace& mf = m.f[bface];
    int ms[2];
    if (have_tangents) {
      for (int c = 0; c < 3; ++c) {
        d[1][c] = bt[0][c];
        d[2][c] = bt[1][c];
      }
    } else {
      surface_element_spans(mf.sd, belem, ms);
      surface_first_derivatives(mf.sd, ms, buv[0], buv[1], d);
    }
    double n[3];
    cross3(d[1], d[2], n);
    const double l = kmath::sqrt(dot3(n, n));
    if (!(l > 0)) return;   // a collapsed point of the master: no normal
    for (int c = 0; c < 3; ++c) n[c] *= mf.sign / l;
    double g = 0;
    for (int c = 0; c < 3; ++c) g += (x[c] - bfoot[c]) * n[c];
    sp.valid(i) = 1;
    sp.mface(i) = bface;
    sp.muv(i, 0) = buv[0];
    sp.muv(i, 1) = buv[1];
    for (int c = 0; c < 3; ++c) sp.normal(i, c) = n[c];
    sp.gap(i) = g;
    const double pr = -eps * g;
    sp.pressure(i) = pr > 0 ? pr : 0.0;
  }
};

using ContactTeam = Kokkos::TeamPolicy<ExecSpace>::member_type;

/// Team scratch (level 1) of sum_segments for blocks of at most nd_max dofs.
inline size_t segment_block_bytes(int nd_max) { return sizeof(double) * nd_max * nd_max + 2 * sizeof(int) * nd_max + 64; }

/// The block of sum_segments in team scratch: add(r, lr, cb, c3, vals) adds three columns of
/// control point cb to row r (dof lr); row(r, lr) gives row r itself (all its columns, in the
/// slot's order 3 cb + cc) and column(k, dof) names column k, for slots that fill whole rows.
struct SegmentBlock {
  static constexpr bool whole_rows = true;
  double* B;
  int* rows;
  int* cols;
  int nd_max;
  int* nd;
  KOKKOS_INLINE_FUNCTION void operator()(int r, int lr, int cb, const int* c3, const double* vals) const {
    rows[r] = lr;
    double* b = B + r * nd_max + 3 * cb;
    if (r == 0)   // a slot's columns are the same in every row
      for (int cc = 0; cc < 3; ++cc) cols[3 * cb + cc] = c3[cc];
    for (int cc = 0; cc < 3; ++cc) b[cc] += vals[cc];
    if (r + 1 > *nd) *nd = r + 1;
  }
  KOKKOS_INLINE_FUNCTION double* row(int r, int lr) const {
    rows[r] = lr;
    if (r + 1 > *nd) *nd = r + 1;
    return B + r * nd_max;
  }
  KOKKOS_INLINE_FUNCTION void column(int k, int dof) const { cols[k] = dof; }
};

/// Mortar by segments: the slots of slave element e = e_first + the team's league rank (those
/// in [p_begin, p_end); `slots` per element) that project onto one master element share their
/// rows and columns. A run of them is summed into a block in team scratch memory (nd_max^2
/// doubles, rows and columns) and scattered into K once: one lookup per entry per segment
/// instead of per slot. slot(i, add) assembles slot i through the SegmentBlock add (three
/// columns at a time, or whole rows where the slot fills them) and returns false where it
/// assembled nothing. One thread of the team does it (team size 1 on the host).
template <class LocalMatrix, class Slot>
KOKKOS_INLINE_FUNCTION void sum_segments(const ContactTeam& t, const SlavePoints3& sp, int e_first, int slots, int p_begin,
                                         int p_end, int nd_max, const LocalMatrix& K, const Slot& slot) {
  const int e = e_first + t.league_rank();
  const int i_lo = e * slots > p_begin ? e * slots : p_begin, i_hi = (e + 1) * slots < p_end ? (e + 1) * slots : p_end;
  double* B = static_cast<double*>(t.team_scratch(1).get_shmem(sizeof(double) * nd_max * nd_max));
  int* rows = static_cast<int*>(t.team_scratch(1).get_shmem(sizeof(int) * nd_max));
  int* cols = static_cast<int*>(t.team_scratch(1).get_shmem(sizeof(int) * nd_max));
  Kokkos::single(Kokkos::PerTeam(t), [&]() {
    int run_face = -1, run_elem = -1, nd = 0;
    for (int k = 0; k < nd_max * nd_max; ++k) B[k] = 0.0;
    auto flush = [&]() {   // scatter the block, and zero the part of it that was used
      for (int r = 0; r < nd; ++r) {
        K.sumIntoValues(rows[r], cols, nd, B + r * nd_max, true, true);
        for (int k = 0; k < nd; ++k) B[r * nd_max + k] = 0.0;
      }
      nd = 0;
    };
    const SegmentBlock add{B, rows, cols, nd_max, &nd};
    for (int i = i_lo; i < i_hi; ++i) {
      if (sp.face(i) < 0 || !sp.valid(i)) continue;
      if (nd > 0 && (sp.mface(i) != run_face || sp.melem(i) != run_elem)) flush();
      run_face = sp.mface(i);
      run_elem = sp.melem(i);
      slot(i, add);
    }
    if (nd > 0) flush();
  });
}

/// Three columns at a time straight into K (KTS: one slot per point, nothing to sum first).
template <class LocalMatrix>
struct DirectColumns {
  static constexpr bool whole_rows = false;
  LocalMatrix K;
  KOKKOS_INLINE_FUNCTION void operator()(int, int lr, int, const int* cols, const double* vals) const {
    K.sumIntoValues(lr, cols, 3, vals, true, true);   // rows sorted (assemble_contact): binary search
  }
};

/// Residual and consistent tangent of the active slave points [p_begin, p_end) (see header).
/// `mortar`: the pressure is the mortar field already in sp.pressure (contact_mortar3.hpp) and
/// the eps N N^T part is assembled per slave control point instead (AssembleMortarGap3).
template <class LocalMatrix, class FView>
struct AssembleKts3 {
  ContactFaces s, m;
  SlavePoints3 sp;
  double eps = 0;
  int p_begin = 0, p_end = 0;
  bool mortar = false;
  LocalMatrix K;
  FView f;
  ForceSum force;   // [Fx, Fy, Fz, Fn]: the force the assembly puts on the slave body
  double geometric = 1;   // the -p G part of the tangent on (1) or off (0): ContactPairData::geometric

  /// Slot i's residual (into f, atomically) and its force share (into fs); its tangent block
  /// by addK(r, lr, cb, cols, vals): row r (dof lr) of the slot's 3 (ns + nm) dofs, the three
  /// columns of control point cb. False where the slot is empty or not active.
  template <class AddK>
  KOKKOS_INLINE_FUNCTION bool slot(const int i, AddK&& addK, double fs[4]) const {
    if (sp.face(i) < 0 || !sp.valid(i)) return false;
    const double g = sp.gap(i);
    if (mortar ? !(sp.pressure(i) > 0) : !kts_active(g, sp.touch)) return false;
    const double pl = -eps * g;
    const double pr = mortar ? sp.pressure(i) : (pl > 0 ? pl : 0.0);
    const double epsN = mortar ? 0.0 : eps;
    const double w = sp.weight(i);
    const ContactFace& sf = s.f[sp.face(i)];
    const ContactFace& mf = m.f[sp.mface(i)];
    // basis of the slave and master elements: B[0] slave R, B[1..3] master R, R_1, R_2
    double Rs[kMaxSurfaceBasis], Rsu[kMaxSurfaceBasis], Rsv[kMaxSurfaceBasis];
    double Rm[kMaxSurfaceBasis], Rm1[kMaxSurfaceBasis], Rm2[kMaxSurfaceBasis];
    int cps[kMaxSurfaceBasis], cpm[kMaxSurfaceBasis];
    int es[2], ms[2];
    surface_element_spans(sf.sd, sp.elem(i), es);
    surface_element_spans(mf.sd, sp.melem(i), ms);
    const int ns = surface_basis(sf.sd, es, sp.uv(i, 0), sp.uv(i, 1), Rs, Rsu, Rsv, cps);
    const int nm = surface_basis(mf.sd, ms, sp.muv(i, 0), sp.muv(i, 1), Rm, Rm1, Rm2, cpm);
    double d[6][3];
    surface_derivatives(mf.sd, ms, sp.muv(i, 0), sp.muv(i, 1), d);
    const double n[3] = {sp.normal(i, 0), sp.normal(i, 1), sp.normal(i, 2)};
    // metric, its inverse A, curvature b, H = a - g b and its inverse; C = A b H^-1
    const double a00 = dot3(d[1], d[1]), a01 = dot3(d[1], d[2]), a11 = dot3(d[2], d[2]);
    const double deta = a00 * a11 - a01 * a01;
    const double A[2][2] = {{a11 / deta, -a01 / deta}, {-a01 / deta, a00 / deta}};
    const double b[2][2] = {{dot3(n, d[3]), dot3(n, d[4])}, {dot3(n, d[4]), dot3(n, d[5])}};
    const double H[2][2] = {{a00 - g * b[0][0], a01 - g * b[0][1]}, {a01 - g * b[1][0], a11 - g * b[1][1]}};
    const double detH = H[0][0] * H[1][1] - H[0][1] * H[1][0];
    const double Hi[2][2] = {{H[1][1] / detH, -H[0][1] / detH}, {-H[1][0] / detH, H[0][0] / detH}};
    double Ab[2][2], C[2][2];
    for (int r = 0; r < 2; ++r)
      for (int c = 0; c < 2; ++c) Ab[r][c] = A[r][0] * b[0][c] + A[r][1] * b[1][c];
    for (int r = 0; r < 2; ++r)
      for (int c = 0; c < 2; ++c) C[r][c] = Ab[r][0] * Hi[0][c] + Ab[r][1] * Hi[1][c];
    // per dof: N, T_al, Nb_al and its row in the contact matrix
    auto dof = [&](int r, double& N, double t[2], double nb[2], int& lid) {
      const int cpk = r / 3, c = r % 3;
      if (cpk < ns) {
        N = Rs[cpk] * n[c];
        t[0] = Rs[cpk] * d[1][c];
        t[1] = Rs[cpk] * d[2][c];
        nb[0] = nb[1] = 0.0;
        lid = dof_of(sf.lid(cps[cpk]), c, 3);
      } else {
        const int q = cpk - ns;
        N = -Rm[q] * n[c];
        t[0] = -Rm[q] * d[1][c];
        t[1] = -Rm[q] * d[2][c];
        nb[0] = Rm1[q] * n[c];
        nb[1] = Rm2[q] * n[c];
        lid = dof_of(mf.lid(cpm[q]), c, 3);
      }
    };
    const int nd = 3 * (ns + nm);
    int cl[2 * kMaxSurfaceBasis];   // the columns' control points (local ids), slave then master
    for (int cb = 0; cb < ns + nm; ++cb) cl[cb] = cb < ns ? sf.lid(cps[cb]) : mf.lid(cpm[cb - ns]);
    // whole rows (a segment's block) or three columns at a time
    constexpr bool rows = std::remove_reference_t<AddK>::whole_rows;
    if constexpr (rows)
      for (int k = 0; k < nd; ++k) addK.column(k, dof_of(cl[k / 3], k % 3, 3));
    for (int r = 0; r < nd; ++r) {
      double Nr, tr[2], nbr[2];
      int lr;
      dof(r, Nr, tr, nbr, lr);
      const double fr = -pr * w * Nr;
      Kokkos::atomic_add(&f(lr), fr);
      if (r < 3 * ns) {
        fs[r % 3] -= fr;
        fs[3] -= fr * n[r % 3];
      }
      // Hi t_r, Hi nb_r, C^T t_r: the row's 2-vectors
      double Htr[2], Hnbr[2], Ctr[2];
      for (int al = 0; al < 2; ++al) {
        Htr[al] = tr[0] * Hi[0][al] + tr[1] * Hi[1][al];
        Hnbr[al] = nbr[0] * Hi[0][al] + nbr[1] * Hi[1][al];
        Ctr[al] = tr[0] * C[0][al] + tr[1] * C[1][al];
      }
      // G(r, c) = -(Ctr . tc) - g (Hnbr . nbc) - (Hnbr . tc) - (Htr . nbc), with column c =
      // (control point cb, component cc) of sign s (+1 slave, -1 master): tc = s R_cb
      // (d1[cc], d2[cc]), nbc = (R1_cb, R2_cb) n[cc] (master only), Nc = s R_cb n[cc]. So
      // G = -s R_cb X[cc] - n[cc] (Y . (R1_cb, R2_cb)) with X[cc] = (Ctr + Hnbr) . (d1[cc], d2[cc])
      // and Y = g Hnbr + Htr, the row's factors formed once. Entry: w (eps N_r N_c - p G).
      const double Xa[2] = {Ctr[0] + Hnbr[0], Ctr[1] + Hnbr[1]};
      const double Y[2] = {g * Hnbr[0] + Htr[0], g * Hnbr[1] + Htr[1]};
      double X[3], EN[3];
      for (int cc = 0; cc < 3; ++cc) {
        X[cc] = Xa[0] * d[1][cc] + Xa[1] * d[2][cc];
        EN[cc] = epsN * Nr * n[cc];
      }
      // the entry w (EN[cc] s R_cb - p G) = s R_cb al[cc] + Yn be[cc]
      double al[3], be[3];
      const double pg = geometric * pr;
      for (int cc = 0; cc < 3; ++cc) {
        al[cc] = w * (EN[cc] + pg * X[cc]);
        be[cc] = w * pg * n[cc];
      }
      if constexpr (rows) {   // the block's row, in place
        double* b = addK.row(r, lr);
        for (int cb = 0; cb < ns; ++cb)   // slave columns: s R_cb = R_cb, no curvature part
          for (int cc = 0; cc < 3; ++cc) b[3 * cb + cc] += Rs[cb] * al[cc];
        for (int cb = ns; cb < ns + nm; ++cb) {   // master columns: s R_cb = -R_cb
          const double Yn = Y[0] * Rm1[cb - ns] + Y[1] * Rm2[cb - ns], R = -Rm[cb - ns];
          for (int cc = 0; cc < 3; ++cc) b[3 * cb + cc] += R * al[cc] + Yn * be[cc];
        }
        continue;
      }
      for (int cb = 0; cb < ns + nm; ++cb) {
        double vals[3];
        int cols[3];
        const bool slave = cb < ns;
        const double R = slave ? Rs[cb] : -Rm[cb - ns];   // s R_cb
        const double Yn = slave ? 0.0 : Y[0] * Rm1[cb - ns] + Y[1] * Rm2[cb - ns];
        for (int cc = 0; cc < 3; ++cc) {
          cols[cc] = dof_of(cl[cb], cc, 3);
          vals[cc] = R * al[cc] + Yn * be[cc];
        }
        addK(r, lr, cb, cols, vals);
      }
    }
    return true;
  }

  KOKKOS_INLINE_FUNCTION void add_forces(const double fs[4]) const {
    for (int c = 0; c < 4; ++c) Kokkos::atomic_add(&force(c), fs[c]);
  }

  /// One point (KTS): its block straight into K.
  KOKKOS_INLINE_FUNCTION void operator()(const int k) const {
    double fs[4] = {0, 0, 0, 0};
    const bool on = slot(p_begin + k, DirectColumns<LocalMatrix>{K}, fs);
    if (on) add_forces(fs);
  }

  /// Mortar by segments (sum_segments above): the slots of slave element e_first + league rank.
  int slots = 0, e_first = 0, nd_max = 0;
  KOKKOS_INLINE_FUNCTION void operator()(const ContactTeam& t) const {
    double fs[4] = {0, 0, 0, 0};
    sum_segments(t, sp, e_first, slots, p_begin, p_end, nd_max, K, [&](int i, const auto& add) { return slot(i, add, fs); });
    Kokkos::single(Kokkos::PerTeam(t), [&]() { add_forces(fs); });
  }
};

}  // namespace iga
