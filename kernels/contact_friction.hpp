#pragma once
// Coulomb friction on NURBS contact curves, for KTS (per slave quadrature point) and mortar
// (per slave control point) contact. Penalty regularisation with return mapping; with ALM
// the tangential multipliers are augmented beside the normal ones.
//
// Slip measure (objective: it is built from the projection parameter, which a rigid motion
// leaves unchanged, and the length of the current master tangent)
//   ds(u) = |t(eta)| (eta - eta_n)
//   eta    the current closest-point projection of the slave point onto the master curve
//   eta_n  the projection of the same slave material point at the last converged load step
//          (committed; KTS: the committed projection of the point, mortar: the committed
//          slave point at the slot's parameter projected onto the committed master curve)
//   t      = rho'(eta), the master tangent; e = t / |t| the unit tangent (increasing eta)
// Law (traction on the slave body along e, per point (KTS) or per slave control point A
// (mortar, on the weighted slip s_A = int R_A ds dGamma_0 / w_A))
//   trial   tau_tr = lambda_T - eps_T ds        (lambda_T: the committed traction (penalty),
//                                                augmented to the current one (ALM))
//   stick   |tau_tr| <= mu p:  tau = tau_tr
//   slip    otherwise:         tau = mu p sign(tau_tr)
//   p the normal pressure (KTS: <-eps g>, mortar: lambda_A). A point (control point)
//   that touches with p = 0 is active: at a zero trial traction it sticks, and its stick
//   tangent holds a body that friction alone keeps in place from the first solve.
// Weak form: the tangential virtual work is tau times the variation of the slip measure,
//   f_c += -w tau S,   S = d(ds)/du = |t| D + (eta - eta_n) e . dt/du,
//   D = d eta / du = (T + g Nb) / H  (contact_kts.hpp), dt/du = [0 ; R_b' I] + m D,
// so that in stick (penalty) the tangential force derives from the potential
// w/(2 eps_T) (lambda_T - eps_T ds)^2 and its tangent is symmetric; in slip
//   K_c += -w (S (x) d tau/du + tau dS/du),  d tau/du = mu sign(tau_tr) dp/du,
// which is not symmetric. mu = 0 assembles nothing (the frictionless path is unchanged).
// Mortar: f_c = -sum_A tau_A V_A, V_A = int R_A S dGamma_0 (= w_A d s_A / du), and
//   K_c += -int tau(xi) dS/du dGamma_0 (per point, tau(xi) = sum_A tau_A R_A)
//          + eps_T / w_A V_A (x) V_A            (stick A)
//          + mu sign eps / w_A V_A (x) delta g_A (slip A with lambda_A > 0).
// Derivatives: the tangent of a point is the exact derivative of its residual, computed by
// forward automatic differentiation (Sacado SFad, N = 4 (P + 1) derivative slots over the
// element dofs u_e = [slave a (x, y), master b (x, y)]): the projection eta enters as a
// value with derivative D (implicit function theorem), the master basis as its first-order
// Taylor expansion in eta - eta* (R^(k) + R^(k+1) d eta, k = 0..2; third derivatives of the
// master basis), so dS/du holds every term, the curvature change included.
// Cost per point: ~ 60 (p_s + p_m + 2) Fad operations of N + 1 flops each, i.e. about
// 1.5e4 flops at p = 2, 5e4 at p = 4, plus one master basis evaluation to third order.
#include <Sacado.hpp>

#include "kernels/contact_mortar.hpp"

namespace iga {

template <int N>
using FadN = Sacado::Fad::SFad<double, N>;

/// Friction state of a pair. Per point (KTS points or mortar slots): the reference projection
/// eta_n (committed), the slip increment measure ds, the traction, the state and the
/// accumulated slip. Per slave control point (mortar): the same quantities of the law.
struct FrictionData {
  double mu = 0, epsT = 0;
  // per point
  Kokkos::View<int*, MemSpace> ref_valid;           // 1: eta_n exists
  Kokkos::View<double*, MemSpace> ref_mxi;          // eta_n
  Kokkos::View<double*, MemSpace> ds, tau, slip, slip_c, lamT;   // lamT, slip_c: KTS only
  Kokkos::View<int*, MemSpace> state;               // 0 open, 1 stick, 2 slip
  Kokkos::View<double* [2], MemSpace> tangent;       // unit master tangent e at the projection
  // per slave control point (mortar)
  Kokkos::View<double*, MemSpace> sA, tauA, slipA, slipA_c, lamTA;
  Kokkos::View<int*, MemSpace> stateA;
};

/// The return mapping of the law above. Returns the state (1 stick, 2 slip) and tau.
/// Frictionless (mu = 0) points slip, whatever their slip increment (one with ds = 0, e.g. no
/// reference projection yet, was reported as stick).
KOKKOS_INLINE_FUNCTION int coulomb(double lamT, double epsT, double ds, double mu, double p, double& tau) {
  const double tr = lamT - epsT * ds, bound = mu * p;
  if (mu > 0 && kmath::fabs(tr) <= bound) { tau = tr; return 1; }
  tau = tr >= 0 ? bound : -bound;
  return 2;
}

/// Slip increment measure ds = |t| (eta - eta_n), the unit tangent e and the traction law of
/// every point (KTS: the law itself; mortar: ds only, the law is per control point).
struct FrictionPointUpdate {
  CurveData m;
  SlavePoints sp;
  FrictionData fr;
  double eps = 0;
  bool mortar = false;

  KOKKOS_INLINE_FUNCTION void operator()(const int i) const {
    fr.ds(i) = 0;
    fr.tangent(i, 0) = fr.tangent(i, 1) = 0;
    if (sp.span(i) < 0 || !sp.valid(i)) {
      if (!mortar) { fr.tau(i) = 0; fr.state(i) = 0; fr.slip(i) = fr.slip_c(i); }
      return;
    }
    double R[3][kMaxBasis1D], rho[2], t[2], mm[2];
    curve_eval_span(sp.mspan(i), m.p, m.U.data(), CurrentCP{m.X, m.u}, m.w, sp.mxi(i), rho, t, mm, R);
    const double len = kmath::sqrt(t[0] * t[0] + t[1] * t[1]);
    fr.tangent(i, 0) = t[0] / len;
    fr.tangent(i, 1) = t[1] / len;
    if (fr.ref_valid(i)) fr.ds(i) = len * (sp.mxi(i) - fr.ref_mxi(i));
    if (mortar) return;
    if (!kts_active(sp.gap(i), sp.touch)) {
      fr.tau(i) = 0; fr.state(i) = 0; fr.slip(i) = fr.slip_c(i); return;
    }
    // touching (p = 0) counts: at a zero trial traction it is stick, whose tangent eps_T S S^T
    // holds a body that friction alone keeps in place from the first solve
    const double pl = -eps * sp.gap(i), pr = pl > 0 ? pl : 0.0;
    double tau;
    fr.state(i) = coulomb(fr.lamT(i), fr.epsT, fr.ds(i), fr.mu, pr, tau);
    fr.tau(i) = tau;
    fr.slip(i) = fr.slip_c(i) + fr.ds(i) + (tau - fr.lamT(i)) / fr.epsT;
  }
};

/// Mortar: weighted slip s_A, the law per slave control point, and the accumulated slip.
struct MortarFrictionLaw {
  CurveData s;
  SlavePoints sp;
  MortarState ms;
  FrictionData fr;
  int slots = 1;

  KOKKOS_INLINE_FUNCTION void operator()(const int A) const {
    double sum = 0;
    const SlavePoints& p = sp;
    const FrictionData& f = fr;
    for_each_support_point(s, sp, slots, A, [&](int i, double RA, const double (*)[kMaxBasis1D], int) {
      sum += RA * p.weight(i) * f.ds(i);
    });
    const double sA = sum / ms.wA(A);
    fr.sA(A) = sA;
    if (!ms.active(A)) { fr.stateA(A) = 0; fr.tauA(A) = 0; fr.slipA(A) = fr.slipA_c(A); return; }
    double tau;
    fr.stateA(A) = coulomb(fr.lamTA(A), fr.epsT, sA, fr.mu, ms.lambda(A), tau);
    fr.tauA(A) = tau;
    fr.slipA(A) = fr.slipA_c(A) + sA + (tau - fr.lamTA(A)) / fr.epsT;
  }
};

/// Mortar: traction, accumulated slip and state at the points: tau(xi) = sum_A tau_A R_A(xi),
/// the state of the control point that contributes most of the pressure (largest
/// lambda_A R_A; 0 where the point carries no pressure).
struct MortarFrictionPoints {
  CurveData s;
  SlavePoints sp;
  MortarState ms;
  FrictionData fr;

  KOKKOS_INLINE_FUNCTION void operator()(const int i) const {
    fr.tau(i) = 0;
    fr.slip(i) = 0;
    fr.state(i) = 0;
    if (sp.span(i) < 0 || !sp.valid(i)) return;
    double R[3][kMaxBasis1D], x[2], dx[2], ddx[2];
    const int span = sp.span(i);
    curve_eval_span(span, s.p, s.U.data(), CurrentCP{s.X, s.u}, s.w, sp.xi(i), x, dx, ddx, R);
    double tau = 0, slip = 0, best = -1;
    int st = 0;
    for (int a = 0; a <= s.p; ++a) {
      const int A = span - s.p + a;
      tau += fr.tauA(A) * R[0][a];
      slip += fr.slipA(A) * R[0][a];
      if (ms.lambda(A) * R[0][a] > best) { best = ms.lambda(A) * R[0][a]; st = fr.stateA(A); }
    }
    fr.tau(i) = tau;
    fr.slip(i) = slip;
    fr.state(i) = sp.pressure(i) > 0 ? st : 0;
  }
};

/// Everything the slip variation of one point needs, gathered from the curves.
struct SlipPoint {
  int ps = 1, pm = 1, nds = 0, nd = 0;
  double Ns[kMaxBasis1D];              // slave basis at xi
  double xs[kMaxBasis1D][2];           // current slave control points
  double B[4][kMaxBasis1D];            // master basis and derivatives 1..3 at eta
  double xm[kMaxBasis1D][2];           // current master control points
  double eta = 0, eta_ref = 0, sn = 1; // projection, reference, normal sign (side_normal)
  bool ref = true;                     // eta_n exists (else no slip measure: ds = 0 for all u)
};

/// Gathers point i (slave span sp.span(i) at sp.xi(i), master span sp.mspan(i) at sp.mxi(i))
/// with its element dofs lid[0..nd) in the order [slave a (x, y), master b (x, y)].
KOKKOS_INLINE_FUNCTION void gather_slip_point(const CurveData& s, const CurveData& m, const SlavePoints& sp,
                                              const FrictionData& fr, int i, SlipPoint& d, int* lid) {
  double Rs[3][kMaxBasis1D], x[2], dx[2], ddx[2];
  const int ss = sp.span(i), ms = sp.mspan(i);
  curve_eval_span(ss, s.p, s.U.data(), CurrentCP{s.X, s.u}, s.w, sp.xi(i), x, dx, ddx, Rs);
  curve_basis3_span(ms, m.p, m.U.data(), m.w, sp.mxi(i), d.B);
  d.ps = s.p;
  d.pm = m.p;
  d.nds = kBoundaryDim * (s.p + 1);
  d.nd = d.nds + kBoundaryDim * (m.p + 1);
  for (int a = 0; a <= s.p; ++a) {
    const int k = ss - s.p + a;
    d.Ns[a] = Rs[0][a];
    for (int c = 0; c < 2; ++c) {
      d.xs[a][c] = s.X(k, c) + s.u(k, c);
      lid[dof_of(a, c, kBoundaryDim)] = dof_of(s.lid(k), c, kBoundaryDim);
    }
  }
  for (int b = 0; b <= m.p; ++b) {
    const int k = ms - m.p + b;
    for (int c = 0; c < 2; ++c) {
      d.xm[b][c] = m.X(k, c) + m.u(k, c);
      lid[d.nds + dof_of(b, c, kBoundaryDim)] = dof_of(m.lid(k), c, kBoundaryDim);
    }
  }
  d.eta = sp.mxi(i);
  d.ref = fr.ref_valid(i) != 0;
  d.eta_ref = d.ref ? fr.ref_mxi(i) : sp.mxi(i);
  d.sn = static_cast<double>(side_normal_sign(m.side)) * m.orientation;
}

/// S = d(ds)/du (values and derivatives: dS/du), ds and the gap g, all as Fad over the point's
/// dofs (see the header). N >= d.nd.
template <int N>
KOKKOS_INLINE_FUNCTION void slip_variation(const SlipPoint& d, FadN<N> S[N], FadN<N>& ds, FadN<N>& g) {
  using F = FadN<N>;
  // values at the projection (doubles): D = d eta / du
  double rho0[2] = {0, 0}, t0[2] = {0, 0}, m0[2] = {0, 0}, xs0[2] = {0, 0};
  for (int b = 0; b <= d.pm; ++b)
    for (int c = 0; c < 2; ++c) {
      rho0[c] += d.B[0][b] * d.xm[b][c];
      t0[c] += d.B[1][b] * d.xm[b][c];
      m0[c] += d.B[2][b] * d.xm[b][c];
    }
  for (int a = 0; a <= d.ps; ++a)
    for (int c = 0; c < 2; ++c) xs0[c] += d.Ns[a] * d.xs[a][c];
  const double len0 = kmath::sqrt(t0[0] * t0[0] + t0[1] * t0[1]);
  const double n0[2] = {d.sn * t0[1] / len0, -d.sn * t0[0] / len0};
  const double g0 = (xs0[0] - rho0[0]) * n0[0] + (xs0[1] - rho0[1]) * n0[1];
  const double H0 = t0[0] * t0[0] + t0[1] * t0[1] - g0 * (n0[0] * m0[0] + n0[1] * m0[1]);
  F eta(N, d.eta);
  for (int r = 0; r < N; ++r) eta.fastAccessDx(r) = 0.0;
  for (int a = 0; a <= d.ps; ++a)
    for (int c = 0; c < 2; ++c) eta.fastAccessDx(dof_of(a, c, kBoundaryDim)) = d.Ns[a] * t0[c] / H0;
  for (int b = 0; b <= d.pm; ++b)
    for (int c = 0; c < 2; ++c)
      eta.fastAccessDx(d.nds + dof_of(b, c, kBoundaryDim)) = (-d.B[0][b] * t0[c] + g0 * d.B[1][b] * n0[c]) / H0;
  const F de = eta - d.eta;
  // the element's control points as independent variables
  F xs[2] = {F(0.0), F(0.0)}, rho[2] = {F(0.0), F(0.0)}, t[2] = {F(0.0), F(0.0)}, mm[2] = {F(0.0), F(0.0)};
  F R0[kMaxBasis1D], R1[kMaxBasis1D];
  for (int a = 0; a <= d.ps; ++a)
    for (int c = 0; c < 2; ++c) xs[c] += d.Ns[a] * F(N, dof_of(a, c, kBoundaryDim), d.xs[a][c]);
  for (int b = 0; b <= d.pm; ++b) {
    R0[b] = d.B[0][b] + d.B[1][b] * de;
    R1[b] = d.B[1][b] + d.B[2][b] * de;
    const F R2 = d.B[2][b] + d.B[3][b] * de;
    for (int c = 0; c < 2; ++c) {
      const F x(N, d.nds + dof_of(b, c, kBoundaryDim), d.xm[b][c]);
      rho[c] += R0[b] * x;
      t[c] += R1[b] * x;
      mm[c] += R2 * x;
    }
  }
  using std::sqrt;
  const F len = sqrt(t[0] * t[0] + t[1] * t[1]);
  const F e[2] = {t[0] / len, t[1] / len};
  const F n[2] = {d.sn * e[1], -d.sn * e[0]};
  g = (xs[0] - rho[0]) * n[0] + (xs[1] - rho[1]) * n[1];
  const F H = t[0] * t[0] + t[1] * t[1] - g * (n[0] * mm[0] + n[1] * mm[1]);
  // a point with no reference projection (it had none at the last converged step: it came
  // into reach of the master since) has ds = 0 whatever u (FrictionPointUpdate), so its arm has
  // no derivative either: with eta - eta (a value 0, a derivative D) the tangent held a stick
  // stiffness eps_T S S^T that its residual (tau = lambda_T = 0) does not have, and Newton
  // converged linearly (0.94 per iteration) where a sliding master brought points into reach
  const F arm = d.ref ? F(eta - d.eta_ref) : F(0.0);
  const F em = e[0] * mm[0] + e[1] * mm[1];
  for (int r = 0; r < N; ++r) S[r] = F(0.0);
  for (int a = 0; a <= d.ps; ++a)
    for (int c = 0; c < 2; ++c) {
      const F D = d.Ns[a] * t[c] / H;
      S[dof_of(a, c, kBoundaryDim)] = len * D + arm * em * D;
    }
  for (int b = 0; b <= d.pm; ++b)
    for (int c = 0; c < 2; ++c) {
      const F D = (-R0[b] * t[c] + g * R1[b] * n[c]) / H;
      S[d.nds + dof_of(b, c, kBoundaryDim)] = len * D + arm * (R1[b] * e[c] + em * D);
    }
  ds = len * arm;
}

/// Tangential residual and tangent of the points [p_begin, p_end): KTS, the full law per
/// point (tau a Fad through p and ds); mortar, the -int tau(xi) dS/du part with tau(xi) given.
template <int P, class LocalMatrix, class FView>
struct AssembleFriction {
  static constexpr int N = 4 * (P + 1);
  CurveData s, m;
  SlavePoints sp;
  FrictionData fr;
  double eps = 0;
  int p_begin = 0;
  bool mortar = false;
  LocalMatrix K;
  FView f;
  ForceSum force;   // the slave rows' sum of -f_c (add_slave_force)

  KOKKOS_INLINE_FUNCTION void operator()(const int k) const {
    using F = FadN<N>;
    const int i = p_begin + k;
    if (sp.span(i) < 0 || !sp.valid(i)) return;
    if (mortar ? fr.tau(i) == 0.0 : fr.state(i) == 0) return;
    SlipPoint d;
    int lid[N];
    gather_slip_point(s, m, sp, fr, i, d, lid);
    F S[N], ds, g;
    slip_variation<N>(d, S, ds, g);
    F tau;
    if (mortar) {
      tau = F(fr.tau(i));
    } else {
      // the state (FrictionPointUpdate) says active: p = <-eps g>, 0 when touching
      F p = -eps * g;
      if (!(p.val() > 0)) p = F(0.0);
      const F tr = fr.lamT(i) - fr.epsT * ds;
      if (fr.state(i) == 1) tau = tr;
      else tau = (tr.val() >= 0 ? fr.mu : -fr.mu) * p;
    }
    const double w = sp.weight(i);
    double row[N], fv[N];
    for (int r = 0; r < d.nd; ++r) {
      const F Fr = -w * tau * S[r];
      fv[r] = Fr.val();
      Kokkos::atomic_add(&f(lid[r]), fv[r]);
      for (int c = 0; c < d.nd; ++c) row[c] = Fr.fastAccessDx(c);
      K.sumIntoValues(lid[r], lid, d.nd, row, false, true);
    }
    const double none[2] = {0.0, 0.0}, e[2] = {fr.tangent(i, 0), fr.tangent(i, 1)};
    add_slave_force(force, fv, d.nds, none, e);
  }
};

/// Mortar: the control point part of the tangent, eps_T / w_A V_A (x) V_A (stick) or
/// mu sign eps / w_A V_A (x) delta g_A (slip), V_A = int R_A S dGamma_0.
template <int P, class LocalMatrix>
struct AssembleMortarFriction {
  static constexpr int N = 4 * (P + 1);
  CurveData s, m;
  SlavePoints sp;
  MortarState ms;
  FrictionData fr;
  MortarScratch sc;
  double eps = 0;
  int slots = 1, a_begin = 0;
  LocalMatrix K;

  KOKKOS_INLINE_FUNCTION void operator()(const int k) const {
    using F = FadN<N>;
    const int A = a_begin + k;
    const int st = fr.stateA(A);
    if (st == 0) return;
    const bool slip = st == 2;
    if (slip && !(ms.lambda(A) > 0)) return;
    // V_A in v0, delta g_A in v1, on A's dense dof range (contact_mortar.hpp)
    const SupportRange r = support_range(s, m, sp, slots, A);
    if (!support_scratch(sc, k, r, ms.flags)) return;
    const SlavePoints& p = sp;
    const FrictionData& f = fr;
    const MortarScratch& SC = sc;
    const CurveData &S_ = s, &M_ = m;
    for_each_support_point(s, sp, slots, A, [&](int i, double RA, const double (*)[kMaxBasis1D], int) {
      SlipPoint d;
      int lid[N];
      gather_slip_point(S_, M_, p, f, i, d, lid);
      F S[N], ds, g;
      slip_variation<N>(d, S, ds, g);
      const double w = RA * p.weight(i);
      const int ss = p.span(i), mspan = p.mspan(i);
      for (int q = 0; q < d.nd; ++q) {
        const int e = q < d.nds ? r.slave(ss - S_.p + point_of_dof(q, kBoundaryDim), component_of_dof(q, kBoundaryDim))
                              : r.master(mspan - M_.p + point_of_dof(q - d.nds, kBoundaryDim), component_of_dof(q - d.nds, kBoundaryDim));
        SC.v0(k, e) += w * S[q].val();
        SC.v1(k, e) += w * g.fastAccessDx(q);
      }
    });
    const int n = support_compact(sc, k, r, s, m);
    const double c = slip ? (fr.tauA(A) >= 0 ? 1.0 : -1.0) * fr.mu * mortar_eps(ms, A, eps) / ms.wA(A) : fr.epsT / ms.wA(A);
    support_outer(sc, k, n, c, slip, K);
  }
};

}  // namespace iga
