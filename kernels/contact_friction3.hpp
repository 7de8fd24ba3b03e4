#pragma once
// Coulomb friction on NURBS contact surfaces (3-D, knot-to-surface): the 2-D law of
// contact_friction.hpp with a two-dimensional tangent plane. One Kokkos::parallel_for over
// slave points per stage (the law: UpdateFriction3; residual and tangent: AssembleFriction3).
//
// Slip (objective: built from the convective coordinates of the foot, which a rigid motion
// leaves unchanged, and the current tangent vectors)
//   xi      the current closest-point projection of the slave point onto the master surface
//   xi_n    the projection of the same slave point at the last converged load step, where it
//           was in contact (committed; a point not in contact then, or whose foot is now on
//           another master face: dxi = 0 whatever u, no slip and no traction this step)
//   dxi     = xi - xi_n,   a_al = rho_,al (xi),   slip vector g_T = a_al dxi^al
// Traction: components tau^al on the unit covariant vectors e_al = a_al / |a_al|,
//   t = tau^al e_al   (the traction on the slave body in the tangent plane; in plane strain
//   tau^1 is the 2-D law's tau, so an extruded 2-D problem gives the 2-D answer)
// Law (per point, penalty regularisation and return mapping)
//   trial   tr^al = lamT^al - eps_T |a_al| dxi^al     (lamT: the committed traction
//                                                      (penalty), augmented (ALM))
//   |tr|^2  = tr^al tr^be (e_al . e_be)
//   stick   |tr| <= mu p:  tau = tr
//   slip    otherwise:     tau = mu p tr / |tr|,       p = <-eps g> (contact_kts3.hpp)
//   accumulated slip (a path length) += (|tr| - |tau|) / eps_T. A point touching with p = 0
//   is active: at a zero trial traction it sticks (as in 2-D).
// Weak form: the tangential virtual work is t . delta g_T,
//   delta g_T = delta a_al0 dxi^al + c_be delta xi^be,   c_be = a_be + a_al,be dxi^al,
//   delta xi = H^-1 (a . (delta x_s - delta rho_0) + d . delta a_0),  H = a_al . a_be - d . a_al,be,
//   d = x_s - rho, "_0": at fixed xi (sum_b R_b(xi) delta x_b, and R_b,al for a_al0), so
//   f_c[slave a, c]  = -w R_a Q_s[c],                          Q_s = P_ga a_ga,
//   f_c[master b, c] = -w (-R_b Q_s[c] + R_b,ga Q_ga[c]),       Q_ga = t dxi^ga + P_ga d,
//   P_ga = (t . c_be) H^-1_be,ga,  w the slave point's reference measure.
// Tangent: the exact derivative of f_c by forward automatic differentiation (Sacado SFad) over
// 33 point variables y = [x_s, S, S_1, S_2, S_11, S_12, S_22, S_111, S_112, S_122, S_222] (the
// slave point and the master surface's derivatives at the foot, 3 components each, all linear in
// the element dofs), the foot xi entering as a value with derivative dxi/dy (implicit function
// theorem) and the master quantities as first-order Taylor expansions in xi - xi*; then
//   K[r, (slave a, c)]  = R_a df_r/dx_s[c],
//   K[r, (master b, c)] = sum_k R_b^(k) df_r/dS^(k)[c]   (k over the 10 derivatives).
// Data layout: Friction3 per slave point: the committed foot (face, xi_n), the committed /
// augmented traction lamT^al, the current traction tau^al and vector t, the accumulated slip,
// the slip increment's length |g_T| and the state (0 open, 1 stick, 2 slip).
// Cost per active point: ~ 400 Fad operations of 34 flops (the point variables), plus
// (3 (ns + nm))^2 x ~ 12 flops for the rows and columns (ns, nm = (p + 1)^2 control points of
// the slave and master elements): about 5e4 flops at p = 2, 2.7e5 at p = 4. Per-thread storage:
// the master basis to third order, 10 (p + 1)^2 doubles, and ~ 60 Fad values of 34 doubles.
#include <Sacado.hpp>

#include "kernels/contact_kts3.hpp"

namespace iga {

struct Friction3 {
  double mu = 0, epsT = 0;
  Kokkos::View<int*, MemSpace> ref_face;          // committed master face of the foot, -1 none
  Kokkos::View<double* [2], MemSpace> ref_uv;     // committed foot xi_n
  Kokkos::View<double* [2], MemSpace> lamT, tau;  // traction components on e_al: committed / augmented, current
  Kokkos::View<double* [3], MemSpace> t;          // current traction vector
  Kokkos::View<double*, MemSpace> slip, slip_c;   // accumulated slip: current, committed
  Kokkos::View<double*, MemSpace> gT;             // |g_T| (the ALM check of the stick points)
  Kokkos::View<int*, MemSpace> state;             // 0 open, 1 stick, 2 slip
  ForceSum force;                                 // [Tx, Ty, Tz, -]: the slave rows' sum of -f_c
  // mortar (contact_mortar_friction3.hpp): per point the slip vector g_T; per slave control
  // point A the weighted slip s_A, the trial, the traction (committed / augmented lamTA), the
  // accumulated slip and the state; nA = int R_A n dGamma_0 (the weighted master normal: the
  // ALM check measures s_A's part across it)
  Kokkos::View<double* [3], MemSpace> gv;
  Kokkos::View<double* [3], MemSpace> sA, trA, tauA, lamTA, nA;
  Kokkos::View<double*, MemSpace> slipA, slipA_c;
  Kokkos::View<int*, MemSpace> stateA;
};

/// Rational basis of the element with spans s and its parameter derivatives to third order:
/// R[k][a], k = 0: R, 1: u, 2: v, 3: uu, 4: uv, 5: vv, 6: uuu, 7: uuv, 8: uvv, 9: vvv; local
/// index a = i + (p0 + 1) j, cp[a] its surface index. Returns the number of control points.
KOKKOS_INLINE_FUNCTION int surface_basis3(const SurfaceData& sd, const int s[2], double u, double v,
                                          double R[10][kMaxSurfaceBasis], int* cp) {
  constexpr int ku[10] = {0, 1, 0, 2, 1, 0, 3, 2, 1, 0}, kv[10] = {0, 0, 1, 0, 1, 2, 0, 1, 2, 3};
  double N[4][kMaxBasis1D], M[4][kMaxBasis1D];
  const int du = sd.p[0] < 3 ? sd.p[0] : 3, dv = sd.p[1] < 3 ? sd.p[1] : 3;
  bspline_ders(s[0], u, sd.p[0], sd.U[0].data(), du, N);
  bspline_ders(s[1], v, sd.p[1], sd.U[1].data(), dv, M);
  for (int i = 0; i <= sd.p[0]; ++i)
    for (int d = du + 1; d <= 3; ++d) N[d][i] = 0.0;   // derivatives beyond the degree vanish
  for (int j = 0; j <= sd.p[1]; ++j)
    for (int d = dv + 1; d <= 3; ++d) M[d][j] = 0.0;
  double W[10] = {};
  int n = 0;
  for (int j = 0; j <= sd.p[1]; ++j)
    for (int i = 0; i <= sd.p[0]; ++i, ++n) {
      const int a = surface_cp(sd, s, i, j);
      const double w = sd.cp(a, 3);
      cp[n] = a;
      for (int k = 0; k < 10; ++k) {
        R[k][n] = N[ku[k]][i] * M[kv[k]][j] * w;   // homogeneous A^(k)
        W[k] += R[k][n];
      }
    }
  // R^(k,l) = (A^(k,l) - sum_{(i,j) != (0,0)} C(k,i) C(l,j) W^(i,j) R^(k-i,l-j)) / W, by
  // increasing order (the table index of (k, l) is idx)
  auto idx = [&](int a, int b) {
    const int o = a + b;
    return o == 0 ? 0 : o == 1 ? 1 + b : o == 2 ? 3 + b : 6 + b;
  };
  constexpr int binom[4][4] = {{1, 0, 0, 0}, {1, 1, 0, 0}, {1, 2, 1, 0}, {1, 3, 3, 1}};
  for (int k = 0; k < 10; ++k) {
    const int a = ku[k], b = kv[k];
    for (int m = 0; m < n; ++m) {
      double r = R[k][m];
      for (int i = 0; i <= a; ++i)
        for (int j = 0; j <= b; ++j) {
          if (i == 0 && j == 0) continue;
          r -= binom[a][i] * binom[b][j] * W[idx(i, j)] * R[idx(a - i, b - j)][m];
        }
      R[k][m] = r / W[0];
    }
  }
  return n;
}

/// The traction law at a point, on any scalar type T (double: the state; Fad: the tangent).
/// len: |a_al|, G01 = e_1 . e_2, dxi the slip in convective coordinates; state 1 stick, 2 slip
/// (given: `forced` >= 1; decided here: 0, a trial within `tol` of mu p sticks: a point that
/// touches with p = 0 and a slip of round-off keeps its stick stiffness, without which the
/// first solve of a step would leave the bodies free to slide sideways).
/// Returns the state; tr the trial, tau the traction.
template <class T>
KOKKOS_INLINE_FUNCTION int coulomb3(const double lamT[2], double epsT, double mu, const T& p, const T len[2], const T& G01,
                                    const T dxi[2], T tr[2], T tau[2], T& norm, int forced, double tol = 0) {
  using std::sqrt;
  for (int al = 0; al < 2; ++al) tr[al] = lamT[al] - epsT * len[al] * dxi[al];
  const T n2 = tr[0] * tr[0] + tr[1] * tr[1] + 2.0 * G01 * tr[0] * tr[1];
  norm = n2 > 0.0 ? T(sqrt(n2)) : T(0.0);
  const int st = forced > 0 ? forced : (Sacado::ScalarValue<T>::eval(norm) <= mu * Sacado::ScalarValue<T>::eval(p) + tol ? 1 : 2);
  for (int al = 0; al < 2; ++al) tau[al] = st == 1 ? tr[al] : T(mu * p * tr[al] / norm);
  return st;
}

/// The law at this rank's slave points: state, traction, slip (after ProjectSlavePoints3).
/// `mortar`: the slip vector g_T of every projected point only (fr.gv; the law is per slave
/// control point, contact_mortar_friction3.hpp).
struct UpdateFriction3 {
  ContactFaces m;
  SlavePoints3 sp;
  Friction3 fr;
  double eps = 0;
  bool mortar = false;

  KOKKOS_INLINE_FUNCTION void operator()(const int i) const {
    fr.state(i) = 0;
    fr.gT(i) = 0;
    for (int al = 0; al < 2; ++al) fr.tau(i, al) = 0;
    for (int c = 0; c < 3; ++c) fr.t(i, c) = 0;
    fr.slip(i) = fr.slip_c(i);
    if (mortar) {
      for (int c = 0; c < 3; ++c) fr.gv(i, c) = 0;
      if (sp.face(i) < 0 || !sp.valid(i) || fr.ref_face(i) != sp.mface(i)) return;
      const ContactFace& mf = m.f[sp.mface(i)];
      int ms[2];
      surface_element_spans(mf.sd, sp.melem(i), ms);
      double d[6][3];
      surface_first_derivatives(mf.sd, ms, sp.muv(i, 0), sp.muv(i, 1), d);
      const double dxi[2] = {sp.muv(i, 0) - fr.ref_uv(i, 0), sp.muv(i, 1) - fr.ref_uv(i, 1)};
      for (int c = 0; c < 3; ++c) fr.gv(i, c) = d[1][c] * dxi[0] + d[2][c] * dxi[1];
      return;
    }
    if (sp.face(i) < 0 || !sp.valid(i) || !kts_active(sp.gap(i), sp.touch)) return;
    const ContactFace& mf = m.f[sp.mface(i)];
    int ms[2];
    surface_element_spans(mf.sd, sp.melem(i), ms);
    double d[6][3];
    surface_first_derivatives(mf.sd, ms, sp.muv(i, 0), sp.muv(i, 1), d);
    double len[2], e[2][3], dxi[2] = {0, 0};
    for (int al = 0; al < 2; ++al) {
      len[al] = kmath::sqrt(dot3(d[1 + al], d[1 + al]));
      for (int c = 0; c < 3; ++c) e[al][c] = d[1 + al][c] / len[al];
    }
    if (fr.ref_face(i) == sp.mface(i))
      for (int al = 0; al < 2; ++al) dxi[al] = sp.muv(i, al) - fr.ref_uv(i, al);
    const double lamT[2] = {fr.lamT(i, 0), fr.lamT(i, 1)};
    const double pl = -eps * sp.gap(i), p = pl > 0 ? pl : 0.0;
    double tr[2], tau[2], norm;
    // round-off: eps_T times the touch tolerance (1e-12 of the smallest slave element)
    const int st = coulomb3<double>(lamT, fr.epsT, fr.mu, p, len, dot3(e[0], e[1]), dxi, tr, tau, norm, 0, fr.epsT * sp.touch);
    fr.state(i) = st;
    double gT[3], tn2 = tau[0] * tau[0] + tau[1] * tau[1] + 2 * dot3(e[0], e[1]) * tau[0] * tau[1];
    for (int c = 0; c < 3; ++c) {
      gT[c] = d[1][c] * dxi[0] + d[2][c] * dxi[1];
      fr.t(i, c) = tau[0] * e[0][c] + tau[1] * e[1][c];
    }
    for (int al = 0; al < 2; ++al) fr.tau(i, al) = tau[al];
    fr.gT(i) = kmath::sqrt(dot3(gT, gT));
    fr.slip(i) = fr.slip_c(i) + (norm - kmath::sqrt(tn2 > 0 ? tn2 : 0.0)) / fr.epsT;
  }
};

/// One slave point's variables for the slip's variation (header): the slave and master bases,
/// the foot xi as a Fad over the 33 point variables y, and the master quantities at the foot
/// (tangents a_al, their derivatives a_al,be, the distance d = x_s - rho) to first order in
/// xi - xi*, and the slip in convective coordinates dxi (0 without a reference on this face).
struct FrictionPoint3 {
  static constexpr int NY = 33;
  using F = Sacado::Fad::SFad<double, NY>;
  int ns = 0, nm = 0;
  double Rs[kMaxSurfaceBasis], Rm[10][kMaxSurfaceBasis];
  int cps[kMaxSurfaceBasis], cpm[kMaxSurfaceBasis];
  F xi[2], a[2][3], aa[3][3], d[3], dxi[2];

  /// d v / d u of point dof (control point cb of [slave 0..ns, master 0..nm), component cc)
  /// from the derivatives of v over y.
  KOKKOS_INLINE_FUNCTION double column(const F& v, int cb, int cc) const {
    if (cb < ns) return Rs[cb] * v.fastAccessDx(cc);
    const int b = cb - ns;
    double r = 0;
    for (int kk = 0; kk < 10; ++kk) r += Rm[kk][b] * v.fastAccessDx(3 * (1 + kk) + cc);
    return r;
  }
  /// The slip vector g_T = a_al dxi^al.
  KOKKOS_INLINE_FUNCTION void slip(F g[3]) const {
    for (int c = 0; c < 3; ++c) g[c] = a[0][c] * dxi[0] + a[1][c] * dxi[1];
  }
};

KOKKOS_INLINE_FUNCTION void friction_point3(const ContactFaces& s, const ContactFaces& m, const SlavePoints3& sp,
                                            const Friction3& fr, int i, FrictionPoint3& P) {
  using F = FrictionPoint3::F;
  constexpr int NY = FrictionPoint3::NY;
  const ContactFace& sf = s.f[sp.face(i)];
  const ContactFace& mf = m.f[sp.mface(i)];
  double Rsu[kMaxSurfaceBasis], Rsv[kMaxSurfaceBasis];
  int es[2], ms[2];
  surface_element_spans(sf.sd, sp.elem(i), es);
  surface_element_spans(mf.sd, sp.melem(i), ms);
  P.ns = surface_basis(sf.sd, es, sp.uv(i, 0), sp.uv(i, 1), P.Rs, Rsu, Rsv, P.cps);
  P.nm = surface_basis3(mf.sd, ms, sp.muv(i, 0), sp.muv(i, 1), P.Rm, P.cpm);
  // the point variables' values: x_s and the master's derivatives S^(k) at the foot
  double Y[11][3] = {};
  for (int a = 0; a < P.ns; ++a)
    for (int c = 0; c < 3; ++c) Y[0][c] += P.Rs[a] * sf.sd.cp(P.cps[a], c);
  for (int kk = 0; kk < 10; ++kk)
    for (int b = 0; b < P.nm; ++b)
      for (int c = 0; c < 3; ++c) Y[1 + kk][c] += P.Rm[kk][b] * mf.sd.cp(P.cpm[b], c);
  auto var = [&](int kk, int c) { return F(NY, 3 * kk + c, Y[kk][c]); };
  // the foot's derivative over y: H dxi = a . (dx_s - dS) + d . dS_al
  double dv[3], Hv[2][2];
  for (int c = 0; c < 3; ++c) dv[c] = Y[0][c] - Y[1][c];
  Hv[0][0] = dot3(Y[2], Y[2]) - dot3(dv, Y[4]);
  Hv[0][1] = Hv[1][0] = dot3(Y[2], Y[3]) - dot3(dv, Y[5]);
  Hv[1][1] = dot3(Y[3], Y[3]) - dot3(dv, Y[6]);
  const double detv = Hv[0][0] * Hv[1][1] - Hv[0][1] * Hv[1][0];
  const double Hiv[2][2] = {{Hv[1][1] / detv, -Hv[0][1] / detv}, {-Hv[1][0] / detv, Hv[0][0] / detv}};
  for (int be = 0; be < 2; ++be) {
    P.xi[be] = F(NY, 0.0);
    for (int r = 0; r < NY; ++r) P.xi[be].fastAccessDx(r) = 0.0;
    for (int al = 0; al < 2; ++al)
      for (int c = 0; c < 3; ++c) {
        P.xi[be].fastAccessDx(c) += Hiv[be][al] * Y[2 + al][c];          // x_s
        P.xi[be].fastAccessDx(3 + c) -= Hiv[be][al] * Y[2 + al][c];      // S
        P.xi[be].fastAccessDx(3 * (2 + al) + c) += Hiv[be][al] * dv[c];  // S_al
      }
  }
  // master quantities at the foot, first order in xi - xi*
  const F* xi = P.xi;
  for (int c = 0; c < 3; ++c) {
    const F rho = var(1, c) + var(2, c) * xi[0] + var(3, c) * xi[1];
    P.a[0][c] = var(2, c) + var(4, c) * xi[0] + var(5, c) * xi[1];
    P.a[1][c] = var(3, c) + var(5, c) * xi[0] + var(6, c) * xi[1];
    P.aa[0][c] = var(4, c) + var(7, c) * xi[0] + var(8, c) * xi[1];   // a_11
    P.aa[1][c] = var(5, c) + var(8, c) * xi[0] + var(9, c) * xi[1];   // a_12
    P.aa[2][c] = var(6, c) + var(9, c) * xi[0] + var(10, c) * xi[1];  // a_22
    P.d[c] = var(0, c) - rho;
  }
  // no reference on this face (the point was not in contact on it at the last converged
  // step): no slip this step, dxi = 0 whatever u (UpdateFriction3)
  const bool same = fr.ref_face(i) == sp.mface(i);
  for (int al = 0; al < 2; ++al) P.dxi[al] = same ? F(sp.muv(i, al) - fr.ref_uv(i, al) + xi[al]) : F(0.0);
}

/// Tangential residual and its exact tangent at the active points [p_begin, p_end) (header).
/// `mortar`: the traction t of each point is given (fr.t, the field sum_A tau_A R_A of
/// contact_mortar_friction3.hpp), and this kernel assembles -w t . delta g_T and its
/// derivative at fixed t; the derivative of t is assembled per slave control point.
template <class LocalMatrix, class FView>
struct AssembleFriction3 {
  using F = FrictionPoint3::F;
  ContactFaces s, m;
  SlavePoints3 sp;
  Friction3 fr;
  double eps = 0;
  int p_begin = 0;
  bool mortar = false;
  LocalMatrix K;
  FView f;
  ForceSum force;   // the pair's [Fx, Fy, Fz, Fn]; fr.force gets [Tx, Ty, Tz]

  /// Slot i's residual (into f, atomically) and force share (into fs); its tangent block by
  /// addK(r, lr, cb, cols, vals) (AssembleKts3::slot). False where nothing is assembled.
  template <class AddK>
  KOKKOS_INLINE_FUNCTION bool slot(const int i, AddK&& addK, double fs[4]) const {
    if (sp.face(i) < 0 || !sp.valid(i)) return false;
    const int st = fr.state(i);
    if (mortar ? fr.t(i, 0) == 0 && fr.t(i, 1) == 0 && fr.t(i, 2) == 0 : st == 0) return false;
    const ContactFace& sf = s.f[sp.face(i)];
    const ContactFace& mf = m.f[sp.mface(i)];
    FrictionPoint3 P;
    friction_point3(s, m, sp, fr, i, P);
    const F* xi = P.xi;
    const F(*a)[3] = P.a;
    const F(*aa)[3] = P.aa;
    const F* d = P.d;
    const F* dxi = P.dxi;
    auto dot = [](const F* x, const F* y) { return F(x[0] * y[0] + x[1] * y[1] + x[2] * y[2]); };
    using std::sqrt;
    const F H00 = dot(a[0], a[0]) - dot(d, aa[0]), H01 = dot(a[0], a[1]) - dot(d, aa[1]), H11 = dot(a[1], a[1]) - dot(d, aa[2]);
    const F detH = H00 * H11 - H01 * H01;
    const F Hi[2][2] = {{H11 / detH, -H01 / detH}, {-H01 / detH, H00 / detH}};
    F t[3];
    if (mortar) {
      for (int c = 0; c < 3; ++c) t[c] = F(fr.t(i, c));
    } else {
      F len[2], e[2][3];
      for (int al = 0; al < 2; ++al) {
        len[al] = sqrt(dot(a[al], a[al]));
        for (int c = 0; c < 3; ++c) e[al][c] = a[al][c] / len[al];
      }
      const F G01 = dot(e[0], e[1]);
      // the pressure: <-eps g>, g = d . n
      F nrm[3] = {a[0][1] * a[1][2] - a[0][2] * a[1][1], a[0][2] * a[1][0] - a[0][0] * a[1][2], a[0][0] * a[1][1] - a[0][1] * a[1][0]};
      const F nl = sqrt(dot(nrm, nrm));
      F g = dot(d, nrm) * (mf.sign / nl);
      F p = -eps * g;
      if (!(p.val() > 0)) p = F(0.0);
      const double lamT[2] = {fr.lamT(i, 0), fr.lamT(i, 1)};
      F tr[2], tau[2], norm;
      coulomb3<F>(lamT, fr.epsT, fr.mu, p, len, G01, dxi, tr, tau, norm, st);
      for (int c = 0; c < 3; ++c) t[c] = tau[0] * e[0][c] + tau[1] * e[1][c];
    }
    F P_[2], Qs[3], Q[2][3];
    // c_be = a_be + a_al,be dxi^al; P_ga = (t . c_be) H^-1_be,ga
    F tc[2];
    for (int be = 0; be < 2; ++be) {
      F cb[3];
      for (int c = 0; c < 3; ++c) cb[c] = a[be][c] + aa[be][c] * dxi[0] + aa[be + 1][c] * dxi[1];
      tc[be] = dot(t, cb);
    }
    for (int ga = 0; ga < 2; ++ga) P_[ga] = tc[0] * Hi[0][ga] + tc[1] * Hi[1][ga];
    for (int c = 0; c < 3; ++c) {
      Qs[c] = P_[0] * a[0][c] + P_[1] * a[1][c];
      for (int ga = 0; ga < 2; ++ga) Q[ga][c] = t[c] * dxi[ga] + P_[ga] * d[c];
    }
    // Rows: slave control point a, component c: f = -w R_a Qs_c; master control point b:
    // f = -w (-R_b Qs_c + R_b,1 Q_0c + R_b,2 Q_1c), R_b and its derivatives at the foot moved by
    // xi (linear in xi, whose value is 0). Collected by the master basis' coefficients
    // Rm[k][b], k < 6: f = -w sum_k Rm[k][b] G_kc with G_0 = -Qs, G_1 = Q_0 - xi_0 Qs,
    // G_2 = Q_1 - xi_1 Qs, G_3 = xi_0 Q_0, G_4 = xi_1 Q_0 + xi_0 Q_1, G_5 = xi_1 Q_1; so each
    // column of the block needs the 18 G's columns once (P.column), not one per row.
    const double w = sp.weight(i);
    const int ns = P.ns, nm = P.nm, nd = 3 * (ns + nm);
    const double nv[3] = {sp.normal(i, 0), sp.normal(i, 1), sp.normal(i, 2)};
    const double(*Rm)[kMaxSurfaceBasis] = P.Rm;
    auto row_dof = [&](int r) {
      const int cp = r / 3, c = r % 3;
      return cp < ns ? dof_of(sf.lid(P.cps[cp]), c, 3) : dof_of(mf.lid(P.cpm[cp - ns]), c, 3);
    };
    for (int r = 0; r < nd; ++r) {
      const int cp = r / 3, c = r % 3;
      double v;
      if (cp < ns) {
        v = -w * P.Rs[cp] * Qs[c].val();
        fs[c] -= v;
        fs[3] -= v * nv[c];
      } else {
        const int b = cp - ns;
        v = -w * (-Rm[0][b] * Qs[c].val() + Rm[1][b] * Q[0][c].val() + Rm[2][b] * Q[1][c].val());
      }
      Kokkos::atomic_add(&f(row_dof(r)), v);
    }
    F G[5][3];   // G_1 .. G_5 (G_0 = -Qs)
    for (int c = 0; c < 3; ++c) {
      G[0][c] = Q[0][c] - xi[0] * Qs[c];
      G[1][c] = Q[1][c] - xi[1] * Qs[c];
      G[2][c] = xi[0] * Q[0][c];
      G[3][c] = xi[1] * Q[0][c] + xi[0] * Q[1][c];
      G[4][c] = xi[1] * Q[1][c];
    }
    for (int cb = 0; cb < ns + nm; ++cb) {
      int cols[3];
      double cq[3][3], cg[5][3][3];   // columns (cb, cc) of Qs_c and G_kc
      for (int cc = 0; cc < 3; ++cc) {
        cols[cc] = cb < ns ? dof_of(sf.lid(P.cps[cb]), cc, 3) : dof_of(mf.lid(P.cpm[cb - ns]), cc, 3);
        for (int c = 0; c < 3; ++c) {
          cq[c][cc] = P.column(Qs[c], cb, cc);
          for (int k = 0; k < 5; ++k) cg[k][c][cc] = P.column(G[k][c], cb, cc);
        }
      }
      for (int r = 0; r < nd; ++r) {
        const int cp = r / 3, c = r % 3;
        double vals[3];
        if (cp < ns) {
          const double a = -w * P.Rs[cp];
          for (int cc = 0; cc < 3; ++cc) vals[cc] = a * cq[c][cc];
        } else {
          const int b = cp - ns;
          for (int cc = 0; cc < 3; ++cc) {
            double v = -Rm[0][b] * cq[c][cc];
            for (int k = 0; k < 5; ++k) v += Rm[1 + k][b] * cg[k][c][cc];
            vals[cc] = -w * v;
          }
        }
        addK(r, row_dof(r), cb, cols, vals);
      }
    }
    return true;
  }

  KOKKOS_INLINE_FUNCTION void add_forces(const double fs[4]) const {
    for (int c = 0; c < 4; ++c) Kokkos::atomic_add(&force(c), fs[c]);
    for (int c = 0; c < 3; ++c) Kokkos::atomic_add(&fr.force(c), fs[c]);
  }

  /// One point (KTS): its block straight into K.
  KOKKOS_INLINE_FUNCTION void operator()(const int k) const {
    double fs[4] = {0, 0, 0, 0};
    const bool on = slot(p_begin + k, [&](int, int lr, int, const int* cols, const double* vals) {
      K.sumIntoValues(lr, cols, 3, vals, true, true);
    }, fs);
    if (on) add_forces(fs);
  }

  /// Mortar by segments (sum_segments, contact_kts3.hpp): the slots of slave element
  /// e_first + league rank.
  int p_end = 0, slots = 0, e_first = 0, nd_max = 0;
  KOKKOS_INLINE_FUNCTION void operator()(const ContactTeam& t) const {
    double fs[4] = {0, 0, 0, 0};
    sum_segments(t, sp, e_first, slots, p_begin, p_end, nd_max, K, [&](int i, const auto& add) { return slot(i, add, fs); });
    Kokkos::single(Kokkos::PerTeam(t), [&]() { add_forces(fs); });
  }
};

}  // namespace iga
