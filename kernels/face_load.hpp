#pragma once
// Neumann loads on one face of a trivariate patch (3-D): one Kokkos::parallel_for over the
// face's elements. The 2-D side loads (curves) are kernels/boundary_load.hpp.
//
// Weak form   l(v) = \int_{Gamma_face} v . t dA
//   t = -p n for a normal pressure (positive pushes into the body; n the outward unit normal),
//   t given for a traction.
// On the face the fixed direction's basis is 1 at its end function (open knot vectors), so the
// face is the bivariate NURBS of its own control points: with the free directions (f0, f1) in
// increasing order, a_i = dx/dxi_fi, the area element is |a_0 x a_1| dxi_f0 dxi_f1 and
// n = s (a_0 x a_1) / |a_0 x a_1|, s = side_normal_sign(face) x the patch orientation
// (kernels/sides.hpp: one rule for 2-D and 3-D). So
//   f_a += \sum_q R_a(q) t~(q) w_q,   t~ = -p s (a_0 x a_1)  (pressure)  or  t |a_0 x a_1|  (traction),
// summed atomically into f (overlap dofs, dof_of(lid, c, 3)).
// Data: PatchDataT<3> (knots, spans, control points {x, y, z, w}, lid); a face element k =
// k0 + ne_f0 k1 belongs to the patch element side_tensor_index(face, {k0, k1}, ne, 3) and is
// done by the rank owning that element.
// Cost per quadrature point: ~ 12 (p + 1)^2 flops for the basis and tangents, 3 (p + 1)^2
// atomic additions; reads the (p + 1)^2 face control points of the element.
#include "kernels/numbering.hpp"
#include "kernels/scatter.hpp"
#include "kernels/sides.hpp"
#include "kernels/types.hpp"

namespace iga {

struct FaceLoad {
  int face = 0;          // 0..5: 2 direction + end (kernels/sides.hpp)
  int kind = 0;          // 1 pressure, 3 traction
  double p = 0;          // pressure
  double t[3] = {0, 0, 0};
  double scale = 1.0;    // load factor
  int orientation = 1;   // +1 right-handed patch, -1 left-handed
};

/// The free directions of a face of a trivariate patch, in increasing order.
KOKKOS_INLINE_FUNCTION void face_directions(int face, int fd[2]) {
  for (int e = 0, i = 0; e < 3; ++e)
    if (e != side_direction(face)) fd[i++] = e;
}

/// Face elements of a face of a trivariate patch: ne_f0 x ne_f1.
KOKKOS_INLINE_FUNCTION int num_face_elements(const PatchData3& pd, int face) {
  int fd[2];
  face_directions(face, fd);
  return pd.ne[fd[0]] * pd.ne[fd[1]];
}

/// Face element k = k0 + ne_f0 k1 of a face: its free directions fd, knot spans s, and per free
/// direction the span's start lo and half length h. False where the patch element it belongs
/// to is not in [e_begin, e_end) (another rank's).
struct FaceElement {
  int fd[2], s[2];
  double lo[2], h[2];
  KOKKOS_INLINE_FUNCTION bool set(const PatchData3& pd, int face, int k, int e_begin, int e_end) {
    face_directions(face, fd);
    const int kk[2] = {k % pd.ne[fd[0]], k / pd.ne[fd[0]]};
    const int pe = side_tensor_index(face, kk, pd.ne, 3);
    if (pe < e_begin || pe >= e_end) return false;
    for (int i = 0; i < 2; ++i) {
      s[i] = pd.span[fd[i]](kk[i]);
      const double* U = pd.U[fd[i]].data();
      lo[i] = U[s[i]];
      h[i] = 0.5 * (U[s[i] + 1] - U[s[i]]);
    }
    return true;
  }
};

template <class FView>
struct AssembleFaceLoad {
  PatchData3 pd;
  FaceLoad load;
  GaussRule g[2];         // per free direction
  FView f;
  int e_begin = 0, e_end = 0;

  int num_face_elements() const { return iga::num_face_elements(pd, load.face); }

  KOKKOS_INLINE_FUNCTION void operator()(const int k) const {
    FaceElement fe;
    if (!fe.set(pd, load.face, k, e_begin, e_end)) return;
    const int* fd = fe.fd;
    const int* s = fe.s;
    int p[2];
    const double* U[2];
    for (int i = 0; i < 2; ++i) {
      p[i] = pd.p[fd[i]];
      U[i] = pd.U[fd[i]].data();
    }
    const double h0 = fe.h[0], h1 = fe.h[1];
    const double sgn = static_cast<double>(side_normal_sign(load.face)) * load.orientation;
    for (int q1 = 0; q1 < g[1].n; ++q1)
      for (int q0 = 0; q0 < g[0].n; ++q0) {
        const double u0 = fe.lo[0] + h0 * (g[0].x[q0] + 1.0), u1 = fe.lo[1] + h1 * (g[1].x[q1] + 1.0);
        double N0[3][kMaxBasis1D], N1[3][kMaxBasis1D];
        bspline_ders(s[0], u0, p[0], U[0], 1, N0);
        bspline_ders(s[1], u1, p[1], U[1], 1, N1);
        // homogeneous sums: W, W_0, W_1 and (w x), its derivatives
        double W = 0, Wd[2] = {0, 0}, X[3] = {0, 0, 0}, Xd[2][3] = {{0, 0, 0}, {0, 0, 0}};
        for (int j = 0; j <= p[1]; ++j)
          for (int i = 0; i <= p[0]; ++i) {
            const int ij[2] = {s[0] - p[0] + i, s[1] - p[1] + j};
            const int a = side_tensor_index(load.face, ij, pd.n, 3);
            const double w = pd.cp(a, 3);
            const double b = N0[0][i] * N1[0][j] * w, b0 = N0[1][i] * N1[0][j] * w, b1 = N0[0][i] * N1[1][j] * w;
            W += b; Wd[0] += b0; Wd[1] += b1;
            for (int c = 0; c < 3; ++c) {
              const double x = pd.cp(a, c);
              X[c] += b * x; Xd[0][c] += b0 * x; Xd[1][c] += b1 * x;
            }
          }
        double a0[3], a1[3];
        for (int c = 0; c < 3; ++c) {
          const double x = X[c] / W;
          a0[c] = (Xd[0][c] - x * Wd[0]) / W;
          a1[c] = (Xd[1][c] - x * Wd[1]) / W;
        }
        const double n[3] = {a0[1] * a1[2] - a0[2] * a1[1], a0[2] * a1[0] - a0[0] * a1[2], a0[0] * a1[1] - a0[1] * a1[0]};
        double tr[3];
        if (load.kind == 1) {
          for (int c = 0; c < 3; ++c) tr[c] = -load.p * sgn * n[c];
        } else {
          const double area = kmath::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
          for (int c = 0; c < 3; ++c) tr[c] = load.t[c] * area;
        }
        const double wq = g[0].w[q0] * g[1].w[q1] * h0 * h1 * load.scale;
        for (int j = 0; j <= p[1]; ++j)
          for (int i = 0; i <= p[0]; ++i) {
            const int ij[2] = {s[0] - p[0] + i, s[1] - p[1] + j};
            const int a = side_tensor_index(load.face, ij, pd.n, 3);
            const int l = pd.lid(a);
            if (l < 0) continue;
            const double R = N0[0][i] * N1[0][j] * pd.cp(a, 3) / W;
            for (int c = 0; c < 3; ++c) Kokkos::atomic_add(&f(dof_of(l, c, 3)), R * tr[c] * wq);
          }
      }
  }
};

/// Basis of a face element at (u0, u1) on the face's control points (nf = (p0 + 1)(p1 + 1), the
/// first free direction fastest): the patch control points cps, R and its parameter
/// derivatives R0, R1, and the tangents a0, a1 of the configuration X + u (u: overlap
/// displacements, empty: the reference).
template <int MaxNf>
KOKKOS_INLINE_FUNCTION int face_basis(const PatchData3& pd, int face, const int fd[2], const int s[2], double u0, double u1,
                                      const Kokkos::View<const double*, MemSpace>& u, int cps[MaxNf], double R[MaxNf],
                                      double R0[MaxNf], double R1[MaxNf], double a0[3], double a1[3]) {
  const int p0 = pd.p[fd[0]], p1 = pd.p[fd[1]];
  double N0[3][kMaxBasis1D], N1[3][kMaxBasis1D];
  bspline_ders(s[0], u0, p0, pd.U[fd[0]].data(), 1, N0);
  bspline_ders(s[1], u1, p1, pd.U[fd[1]].data(), 1, N1);
  double W = 0, W0 = 0, W1 = 0;
  int n = 0;
  for (int j = 0; j <= p1; ++j)
    for (int i = 0; i <= p0; ++i, ++n) {
      const int ij[2] = {s[0] - p0 + i, s[1] - p1 + j};
      cps[n] = side_tensor_index(face, ij, pd.n, 3);
      const double w = pd.cp(cps[n], 3);
      R[n] = N0[0][i] * N1[0][j] * w;
      R0[n] = N0[1][i] * N1[0][j] * w;
      R1[n] = N0[0][i] * N1[1][j] * w;
      W += R[n]; W0 += R0[n]; W1 += R1[n];
    }
  for (int c = 0; c < 3; ++c) a0[c] = a1[c] = 0;
  const bool have_u = u.extent(0) > 0;
  for (int b = 0; b < n; ++b) {
    R[b] /= W;
    R0[b] = R0[b] / W - R[b] * W0 / W;
    R1[b] = R1[b] / W - R[b] * W1 / W;
    const int l = pd.lid(cps[b]);
    for (int c = 0; c < 3; ++c) {
      const double x = pd.cp(cps[b], c) + (have_u && l >= 0 ? u(dof_of(l, c, 3)) : 0.0);
      a0[c] += R0[b] * x;
      a1[c] += R1[b] * x;
    }
  }
  return n;
}

KOKKOS_INLINE_FUNCTION constexpr double levi_civita(int i, int j, int k) {
  return (i == j || j == k || i == k) ? 0.0 : ((j - i + 3) % 3 == 1 ? 1.0 : -1.0);
}

/// A pressure on the deformed face (finite kinematics, 3-D): a follower load in
/// System::assemble_internal with its (non-symmetric) tangent.
///   -f_ext,ai = \int p s R_a n~_i dxi,   n~ = a_0 x a_1,  a_m = \sum_b R_b,m (X_b + u_b),
///   d(-f_ext,ai)/du_bk = \int p s R_a (eps_ikl a_1l R_b,0 + eps_ijk a_0j R_b,1) dxi
/// (s = side_normal_sign x orientation, as AssembleFaceLoad). One thread per face element,
/// rows written whole (ElementScatter::add_row), the basis recomputed per row: no element
/// matrix on the stack. Cost per face element: 3 nf rows x nq points x (~ 20 nf) flops.
template <int MaxNf, class LocalMatrix>
struct AssembleFollowerFacePressure {
  PatchData3 pd;
  FaceLoad load;    // kind 1; p at the current load point; scale 1
  GaussRule g[2];
  int e_begin = 0, e_end = 0;
  Kokkos::View<const double*, MemSpace> u = {};
  Kokkos::View<double*, MemSpace> f = {};
  ElementScatter<LocalMatrix> scatter = {};
  bool force = false, tangent = false;

  int num_face_elements() const { return iga::num_face_elements(pd, load.face); }

  KOKKOS_INLINE_FUNCTION void operator()(const int k) const {
    FaceElement el;
    if (!el.set(pd, load.face, k, e_begin, e_end)) return;
    const int* fd = el.fd;
    const int* s = el.s;
    const double* lo = el.lo;
    const double* h = el.h;
    const double sp = static_cast<double>(side_normal_sign(load.face)) * load.orientation * load.p * load.scale;
    int cps[MaxNf];
    double R[MaxNf], R0[MaxNf], R1[MaxNf], a0[3], a1[3];
    const int nf = (pd.p[fd[0]] + 1) * (pd.p[fd[1]] + 1);
    // rows: a (face function) and i (component); row r = 3 a + i
    for (int r = 0; r < (force || tangent ? 3 * nf : 0); ++r) {
      const int a = r / 3, i = r % 3;
      double v[3 * MaxNf];
      for (int c = 0; c < 3 * nf; ++c) v[c] = 0;
      double fe = 0;
      for (int q1 = 0; q1 < g[1].n; ++q1)
        for (int q0 = 0; q0 < g[0].n; ++q0) {
          face_basis<MaxNf>(pd, load.face, fd, s, lo[0] + h[0] * (g[0].x[q0] + 1.0), lo[1] + h[1] * (g[1].x[q1] + 1.0), u, cps, R, R0,
                            R1, a0, a1);
          const double wq = g[0].w[q0] * g[1].w[q1] * h[0] * h[1] * sp * R[a];
          const double n[3] = {a0[1] * a1[2] - a0[2] * a1[1], a0[2] * a1[0] - a0[0] * a1[2], a0[0] * a1[1] - a0[1] * a1[0]};
          fe += wq * n[i];
          if (tangent)
            for (int kc = 0; kc < 3; ++kc) {
              double t1 = 0, t2 = 0;
              for (int l = 0; l < 3; ++l) {
                t1 += levi_civita(i, kc, l) * a1[l];
                t2 += levi_civita(i, l, kc) * a0[l];
              }
              for (int b = 0; b < nf; ++b) v[dof_of(b, kc, 3)] += wq * (t1 * R0[b] + t2 * R1[b]);
            }
        }
      const int l = pd.lid(cps[a]);
      if (force && l >= 0) Kokkos::atomic_add(&f(dof_of(l, i, 3)), fe);
      if (tangent) scatter.template add_row<MaxNf, 3>(pd.lid, cps[a], i, cps, nf, v);
    }
  }
};

}  // namespace iga
