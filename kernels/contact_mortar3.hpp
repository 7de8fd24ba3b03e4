#pragma once
// Segment-to-segment mortar contact between faces of solids (3-D, frictionless): the 3-D form
// of contact_mortar.hpp, with the segmentation of contact_clip.hpp. Either side one face or a
// list of patch faces: slave elements are numbered face after face (ContactFaces::eoff), the
// slave control points A once where faces share them (ContactFace::aid, A's occurrences in
// a_ptr / a_occ), and a slot or edge point carries its slave and master face.
//
// Weighted gap of slave control point A (reference measure dGamma_0):
//   g_A = \int R_A g dGamma_0,  w_A = \int R_A dGamma_0,  g = (x_s - rho(xi)) . n(xi) with xi
//   the closest-point projection; lambda_A = <lbar_A - eps g_A / w_A> (penalty: lbar = 0;
//   ALM: lbar <- lambda between Newton solves), active when lbar_A - eps g_A / w_A >= -eps touch.
//   Pressure field p = sum_A lambda_A R_A (uniform lambda: uniform pressure, the patch test).
// Residual and tangent (as in 2-D): f_c = -\int p N dGamma_0 and K_c = -\int p G dGamma_0 per
//   quadrature slot (AssembleKts3 with the slot's mortar pressure), plus
//   sum_{A active} eps / w_A delta g_A (x) delta g_A per slave control point
//   (AssembleMortarGap3), delta g_A = \int R_A N dGamma_0. The segments move with u; where
//   two segments meet the integrand is continuous and their motions cancel, but where the
//   master face ends inside a slave element (a die overhanging a slab) the covered part of
//   that element grows or shrinks with u, and the tangent has the boundary terms
//     - \oint p N (x) V' dl_0  (AssembleMortarEdge3, per edge point)
//     + sum_{A active} eps / w_A delta g_A (x) \oint R_A g V' dl_0   (AssembleMortarGap3)
//   over the image of the master's boundary in the slave parameter plane, dl_0 its reference
//   measure and V' the derivative of its outward normal velocity (edge_velocity: the shots of
//   the boundary cells' corners differentiated). The same terms at master element edges where
//   the integrand jumps (continuity below `smooth`: C^0 edges for the normal, and with friction
//   C^1 edges too, since the slip's variation carries the master's second derivatives): each
//   side's edge points evaluate their own element, and the two sums give the jump term. The residual stays -\int p N: it is then not
//   the gradient of the potential there (the boundary term of delta g_A is not in it), and the
//   tangent is not symmetric.
// Segments (MortarSegments3, one slave element per thread; on one rank not for the elements
//   all of whose control points are certainly out of contact, MortarFar3 / MortarOut3): the master elements whose boxes
//   meet the slave element's box (grown by its own size) are candidates; each candidate's
//   corners (shared with its neighbours) are shot along the master normal onto the slave
//   element's surface, x_s(u, v) = rho + t n (Newton on (u, v, t), the slave element's
//   polynomial extended beyond its edges), giving a quadrilateral in the slave parameter plane
//   whose straight edges approximate the image of the master element's edges (the images of
//   neighbours tile the plane exactly, so the segments partition the slave element); clip_polygons cuts the slave element's parameter
//   rectangle with its hull, and the fan rule of contact_clip.hpp (each fan triangle with a
//   symmetric rule exact to degree 2 n - 2: `tri`, solver/contact3d.cpp's triangle_rule) fills
//   the element's quadrature slots (parameters, weight = rule
//   weight x |X_u x X_v| of the reference face, the master element as the projection's warm
//   start). On a flat master each segment is exactly the slave region that sees that master
//   element, so the slave and master forces are integrated exactly: the patch test holds to
//   round-off for non-matching meshes.
// Layout: slots of SlavePoints3, `slots` per slave element (element-major); an unused slot
//   has face = -1. flags(0): the most slots an element needed when short, flags(1): the most
//   candidate master elements of one slave element when its row was short (the host grows
//   either and segments again); flags(2): a clipping overflow (cannot happen with four-cornered
//   cells); flags(3): the most edge points one element needed when short (MortarEdges3).
//   MortarState::flags(1): the most dofs of one delta g_A when its scratch row was short.
// Cost per slave element: candidates x (sub + 1)^2 shots (each grid point of a candidate's
//   cells once; Newton ~ 5 steps of a first-derivative surface evaluation, ~ (p + 1)^2 40
//   flops) and per cell a clip (~ 16^2 comparisons + exact orientation tests) and n^2 x
//   vertices slot points. On the Hertz ball only ~2 % of the candidates' cell images overlap
//   their slave element (the candidates' box test grows the slave element's box by its size
//   in every direction): `facing` skips the shots of those the master normal cannot carry
//   onto it.
#include "kernels/contact_clip.hpp"
#include "kernels/contact_kts3.hpp"
#include "kernels/contact_mortar.hpp"

namespace iga {

constexpr int kMortar3Candidates = 64;   // candidate master elements per slave element to start with
constexpr int kMaxCells = 8;             // cells per direction of a master element in the segmentation, at most

/// Slave face data of a mortar pair: the reference surface (for measures).
KOKKOS_INLINE_FUNCTION SurfaceData reference_surface(const ContactFace& f) {
  SurfaceData r = f.sd;
  r.cp = f.X;
  return r;
}

/// The slave face of element eg of a list (the faces' elements numbered face after face,
/// ContactFaces::eoff) and, in e, its element within that face.
KOKKOS_INLINE_FUNCTION int slave_face_of(const ContactFaces& s, int eg, int& e) {
  int f = 0;
  while (f + 1 < s.n && eg >= s.eoff[f + 1]) ++f;
  e = eg - s.eoff[f];
  return f;
}

constexpr int kEdgeData = 16;   // doubles per edge point (MortarEdges3::d)

/// Points on the image of the master face's boundary inside slave elements, where the covered
/// part of a slave element ends: the quadrature of the tangent's boundary terms (header). Per
/// slave element `per` entries (element-major), elem = -1 unused. d(i, .): u, v (the slave
/// parameters of the point), s (its place on the edge a -> b), w (Gauss weight x the clipped
/// edge's length in s x |X_u x X_v| of the reference slave face), nu_u, nu_v (the outward
/// normal of the covered region in the slave parameter plane, times |b - a|), then for corner
/// a and corner b: the shot (u, v, t) and the master parameters (xi, eta) of the corner.
struct MortarEdges3 {
  Kokkos::View<int*, MemSpace> elem, sface, melem, mface;   // slave element and face; master element and face of the edge's cell
  Kokkos::View<double* [kEdgeData], MemSpace> d;
  int per = 0;
};

/// The box of slave element es's current control points, grown by the box's largest side (the
/// returned margin): a master element whose box misses it is too far from the slave element
/// to touch it (a global radius would take in many elements of a graded master).
KOKKOS_INLINE_FUNCTION double grown_box(const SurfaceData& ss, const int es[2], double box[6]) {
  for (int c = 0; c < 3; ++c) {
    box[c] = 1e300;
    box[3 + c] = -1e300;
  }
  for (int j = es[1] - ss.p[1]; j <= es[1]; ++j)
    for (int i = es[0] - ss.p[0]; i <= es[0]; ++i)
      for (int c = 0; c < 3; ++c) {
        const double x = ss.cp(i + ss.n[0] * j, c);
        box[c] = x < box[c] ? x : box[c];
        box[3 + c] = x > box[3 + c] ? x : box[3 + c];
      }
  double margin = 0;
  for (int c = 0; c < 3; ++c) margin = box[3 + c] - box[c] > margin ? box[3 + c] - box[c] : margin;
  for (int c = 0; c < 3; ++c) {
    box[c] -= margin;
    box[3 + c] += margin;
  }
  return margin;
}

/// f(E, f) for each master element E of face f whose box meets `box` (the candidates).
template <class F>
KOKKOS_INLINE_FUNCTION void for_each_candidate(const ContactFaces& m, const double box[6], const F& fn) {
  for (int f = 0; f < m.n; ++f) {
    const SurfaceSearch& g = m.search[f];
    g.for_each_in_box(box, box + 3, [&](const int E) {
      bool overlap = true;
      for (int d = 0; d < 3; ++d) overlap = overlap && g.box(E, d) <= box[3 + d] && g.box(E, 3 + d) >= box[d];
      if (overlap) fn(E, f);
    });
  }
}

/// The unit normal nb (S_u x S_v) at the centre of element [mlo, mhi] and the spread, the
/// largest |n - nb| at its corners; false where the surface has no normal there.
KOKKOS_INLINE_FUNCTION bool centre_normal(const SurfaceData& ms, const int mspn[2], const double mlo[2], const double mhi[2],
                                          double nb[3], double& spread) {
  double d[3][3];
  surface_first_derivatives(ms, mspn, 0.5 * (mlo[0] + mhi[0]), 0.5 * (mlo[1] + mhi[1]), d);
  cross3(d[1], d[2], nb);
  const double lb = kmath::sqrt(dot3(nb, nb));
  if (!(lb > 0)) return false;
  for (int c = 0; c < 3; ++c) nb[c] /= lb;
  spread = 0;
  for (int k = 0; k < 4; ++k) {
    surface_first_derivatives(ms, mspn, k % 2 ? mhi[0] : mlo[0], k / 2 ? mhi[1] : mlo[1], d);
    double n[3];
    cross3(d[1], d[2], n);
    const double l = kmath::sqrt(dot3(n, n));
    if (!(l > 0)) return false;
    double dn = 0;
    for (int c = 0; c < 3; ++c) dn += (n[c] / l - nb[c]) * (n[c] / l - nb[c]);
    spread = kmath::sqrt(dn) > spread ? kmath::sqrt(dn) : spread;
  }
  return true;
}

/// centre_normal of every element of master face f, into m.frame[f] (once per update: the
/// segmentation and MortarFar3 read it for each of their candidates).
struct MasterFrames3 {
  SurfaceData ms;
  Kokkos::View<double* [4], MemSpace> frame;
  KOKKOS_INLINE_FUNCTION void operator()(const int E) const {
    int mspn[2];
    surface_element_spans(ms, E, mspn);
    const double mlo[2] = {ms.U[0](mspn[0]), ms.U[1](mspn[1])}, mhi[2] = {ms.U[0](mspn[0] + 1), ms.U[1](mspn[1] + 1)};
    double nb[3], spread;
    const bool ok = centre_normal(ms, mspn, mlo, mhi, nb, spread);
    for (int c = 0; c < 3; ++c) frame(E, c) = ok ? nb[c] : 0.0;
    frame(E, 3) = ok ? spread : -1.0;
  }
};

/// The centre normal and spread of master element E of face f (MasterFrames3); false where it
/// has no normal.
KOKKOS_INLINE_FUNCTION bool master_frame(const ContactFaces& m, int f, int E, double nb[3], double& spread) {
  const auto& fr = m.frame[f];
  for (int c = 0; c < 3; ++c) nb[c] = fr(E, c);
  spread = fr(E, 3);
  return spread >= 0;
}

/// [lo, hi]: the extent along t of element sp's control points (the element lies in their hull).
KOKKOS_INLINE_FUNCTION void hull_extent(const SurfaceData& sd, const int sp[2], const double* t, double& lo, double& hi) {
  lo = 1e300;
  hi = -1e300;
  for (int j = sp[1] - sd.p[1]; j <= sp[1]; ++j)
    for (int i = sp[0] - sd.p[0]; i <= sp[0]; ++i) {
      const int a = i + sd.n[0] * j;
      const double x = sd.cp(a, 0) * t[0] + sd.cp(a, 1) * t[1] + sd.cp(a, 2) * t[2];
      lo = x < lo ? x : lo;
      hi = x > hi ? x : hi;
    }
}

/// The tangential half of MortarSegments3::facing, for a master element's centre normal nb
/// and spread (centre_normal): false where the two elements' hulls along a tangent of nb are
/// farther apart than margin (2 spread + 0.1), so that no point of the master element sees the
/// slave element along its normal within a distance margin.
KOKKOS_INLINE_FUNCTION bool facing_along(const SurfaceData& ss, const int es[2], const SurfaceData& ms, const int mspn[2],
                                         const double nb[3], double spread, double margin) {
  // tangents of nbar: t1 along the axis least aligned with it, t2 = nbar x t1
  int ax = 0;
  for (int c = 1; c < 3; ++c) ax = kmath::fabs(nb[c]) < kmath::fabs(nb[ax]) ? c : ax;
  double t1[3] = {-nb[ax] * nb[0], -nb[ax] * nb[1], -nb[ax] * nb[2]};
  t1[ax] += 1.0;
  const double l1 = kmath::sqrt(dot3(t1, t1));
  for (int c = 0; c < 3; ++c) t1[c] /= l1;
  double t2[3];
  cross3(nb, t1, t2);
  const double delta = margin * (2 * spread + 0.1);
  const double* tangents[2] = {t1, t2};   // a plain array: no std::initializer_list in a kernel
  for (int k = 0; k < 2; ++k) {
    double slo, shi, mlo_, mhi_;
    hull_extent(ss, es, tangents[k], slo, shi);
    hull_extent(ms, mspn, tangents[k], mlo_, mhi_);
    if (mhi_ < slo - delta || mlo_ > shi + delta) return false;
  }
  return true;
}

/// Slave elements certainly out of contact (far(eg) = 1): every candidate master element (its
/// box meets the slave element's grown box, grown_box, by the margin of the element's size)
/// that faces the slave element (facing_along: it could carry a foot within the margin) lies
/// below it along its own outward centre normal nb (the slave hull's lowest point above the
/// master hull's highest by more than the touching tolerance), and its normals turn little
/// (2 spread < 1, spread as in centre_normal, doubled for the interior: n . nb > 1/2 over the
/// element). At a slot's foot
/// rho on such an element x - rho = g n(rho), so g n(rho) . nb = (x - rho) . nb > 0: the gap
/// g is positive. A foot anywhere else is farther than the margin (a slave point that deep in
/// the master is no contact the segmentation would see either: it takes its segments from
/// the same candidates). The test reads control points (a few dot products per control point
/// and candidate) and the normal at 5 points of each candidate; it runs over every slave
/// element before the segmentation.
struct MortarFar3 {
  ContactFaces s, m;
  Kokkos::View<int*, MemSpace> far;
  double touch = 0;   // gaps below this count as touching (SlavePoints3::touch): far means farther

  KOKKOS_INLINE_FUNCTION void operator()(const int eg) const {
    int e;
    const int fs = slave_face_of(s, eg, e);
    const SurfaceData& ss = s.f[fs].sd;
    int es[2];
    surface_element_spans(ss, e, es);
    double box[6];
    const double margin = grown_box(ss, es, box);
    bool out = true;
    for_each_candidate(m, box, [&](const int E, const int f) {
      if (!out) return;
      const SurfaceData& ms = m.f[f].sd;
      int mspn[2];
      surface_element_spans(ms, E, mspn);
      double nb[3], spread;
      if (!master_frame(m, f, E, nb, spread)) {
        out = false;
        return;
      }
      if (!facing_along(ss, es, ms, mspn, nb, spread, margin)) return;
      for (int c = 0; c < 3; ++c) nb[c] *= m.f[f].sign;
      double slo, shi, mlo_, mhi_;
      hull_extent(ss, es, nb, slo, shi);
      hull_extent(ms, mspn, nb, mlo_, mhi_);
      out = slo - mhi_ > touch && 2 * spread < 1;
    });
    far(eg) = out ? 1 : 0;
  }
};

/// Slave control points certainly out of contact: every slave element of A's support far
/// (MortarFar3) and no multiplier carried from the last augmentation (lbar_A = 0). Their
/// weighted gaps are positive; the segmentation skips the elements all of whose control
/// points are out, and MortarGaps3 keeps these inactive.
struct MortarOut3 {
  ContactFaces s;
  MortarState ms;
  Kokkos::View<const int*, MemSpace> far;
  Kokkos::View<int*, MemSpace> out;

  KOKKOS_INLINE_FUNCTION void operator()(const int A) const;
};

struct MortarSegments3 {
  ContactFaces s, m;
  SlavePoints3 sp;
  MortarEdges3 ed;
  GaussRule gauss;      // the edge points' rule (MortarEdges3)
  TriangleRule tri;     // each fan triangle's rule (contact_clip.hpp)
  int slots = 1;
  int smooth = 1;   // edge points also on master element edges of continuity below this
  int sub = 1;   // cells per direction of a master element (its edges' images: straight per cell)
  Kokkos::View<int*, MemSpace> flags;
  Kokkos::View<int**, Kokkos::LayoutRight, MemSpace> cand;   // per slave element: candidate master elements
  Kokkos::View<const int*, MemSpace> skip;   // per slave control point A: certainly out of contact (MortarFar3); empty: none

  /// Whether every control point of slave element es (face sf) is certainly out of contact.
  KOKKOS_INLINE_FUNCTION bool all_out(const ContactFace& sf, const SurfaceData& ss, const int es[2]) const {
    for (int j = es[1] - ss.p[1]; j <= es[1]; ++j)
      for (int i = es[0] - ss.p[0]; i <= es[0]; ++i)
        if (!skip(sf.aid(i + ss.n[0] * j))) return false;
    return true;
  }

  KOKKOS_INLINE_FUNCTION void operator()(const int eg) const {
    int e;   // slave element eg of the list: element e of face fs
    const int fs = slave_face_of(s, eg, e);
    const ContactFace& sf = s.f[fs];
    const SurfaceData& ss = sf.sd;
    int es[2];
    surface_element_spans(ss, e, es);
    const double lo[2] = {ss.U[0](es[0]), ss.U[1](es[1])}, hi[2] = {ss.U[0](es[0] + 1), ss.U[1](es[1] + 1)};
    for (int k = 0; k < slots; ++k) {
      sp.face(eg * slots + k) = -1;
      sp.valid(eg * slots + k) = 0;
    }
    for (int k = 0; k < ed.per; ++k) ed.elem(eg * ed.per + k) = -1;
    int eused = 0;
    // a slave element whose every control point is certainly out of contact (MortarFar3) is
    // not segmented: its slots would only add positive gaps to inactive control points
    if (skip.extent(0) > 0 && all_out(sf, ss, es)) return;
    double box[6];
    const double margin = grown_box(ss, es, box);
    const SurfaceData ref = reference_surface(sf);
    const ClipPolygon rect = parameter_rectangle(lo[0], hi[0], lo[1], hi[1]);
    const double uc = 0.5 * (lo[0] + hi[0]), vc = 0.5 * (lo[1] + hi[1]);
    const double hsz = (hi[0] - lo[0]) > (hi[1] - lo[1]) ? hi[0] - lo[0] : hi[1] - lo[1];
    int used = 0;
    // candidates (master element E of face f as E kMaxFacesPerSurface + f) in this element's
    // row of the scratch (its capacity grows to what is needed), from every master face's bins
    int nc = 0;
    const int cap = static_cast<int>(cand.extent(1));
    for_each_candidate(m, box, [&](const int E, const int f) {
        const int code = E * kMaxFacesPerSurface + f;
        bool seen = false;
        for (int q = 0; q < nc && q < cap && !seen; ++q) seen = cand(eg, q) == code;
        if (seen) return;
        if (nc < cap) cand(eg, nc) = code;
        ++nc;
    });
    if (nc > cap) {   // the host grows the rows and segments again
      Kokkos::atomic_fetch_max(&flags(1), nc);
      return;
    }
    for (int q = 0; q < nc; ++q) {
      const int E = cand(eg, q) / kMaxFacesPerSurface, fm = cand(eg, q) % kMaxFacesPerSurface;
      const SurfaceData& ms = m.f[fm].sd;
      int mspn[2];
      surface_element_spans(ms, E, mspn);
      double mlo[2] = {ms.U[0](mspn[0]), ms.U[1](mspn[1])}, mhi[2] = {ms.U[0](mspn[0] + 1), ms.U[1](mspn[1] + 1)};
      if (!facing(ss, es, fm, E, mspn, margin)) continue;
      // past an open edge of the master face (a symmetry plane, ContactFace::open) the element
      // goes on by an eighth of its width: its image covers the slave up to the slave's own
      // edge there (the slave element's rectangle clips it) while the master's normal at the
      // edge tilts by less than about h / (8 |g|), and that edge is no boundary of the master.
      // (A whole width would make the cells twice as wide there: another discretisation.)
      const int open = m.f[fm].open;
      for (int k = 0; k < 2; ++k) {
        const double w = 0.125 * (mhi[k] - mlo[k]);
        if (open_past(ms, mspn, k, 0, open)) mlo[k] -= w;
        if (open_past(ms, mspn, k, 1, open)) mhi[k] += w;
      }
      // the element cut into sub x sub cells; each cell's corners, counter-clockwise, shot onto
      // the slave surface. Neighbouring cells (and elements) share their corners, so their
      // straight-edged images tile the slave plane exactly (samples along an edge would make a
      // curved cell's image non-convex, and the hulls of neighbours would overlap); the cells
      // make the straight edges follow the curved images of the element's edges (sub^2 closer).
      // The (sub + 1)^2 grid points are shot once each, a row of cells at a time (two rows of
      // shots kept), instead of four times per cell point.
      Shot rows[2][kMaxCells + 1];
      // each shot's Newton starts from its neighbour's result (a cell away: 2-3 steps instead
      // of ~5 from the slave element's centre), the first from the centre
      for (int i = 0; i <= sub; ++i)
        shoot(ss, es, ms, mspn, mlo, mhi, i, 0, uc, vc, hsz, margin, i > 0 ? &rows[0][i - 1] : nullptr, rows[0][i]);
      for (int cj = 0; cj < sub; ++cj) {
      const Shot* below = rows[cj % 2];
      Shot* above = rows[(cj + 1) % 2];
      for (int i = 0; i <= sub; ++i)
        shoot(ss, es, ms, mspn, mlo, mhi, i, cj + 1, uc, vc, hsz, margin, i > 0 ? &above[i - 1] : &below[0], above[i]);
      for (int ci = 0; ci < sub; ++ci) {
      ClipPolygon poly;
      poly.n = 0;
      double shot[4][5];   // per corner: u, v, t, xi, eta
      bool shot_ok[4] = {false, false, false, false};
      int corner_sign[4] = {0, 0, 0, 0};   // per vertex: the map's orientation there
      for (int k = 0; k < 4; ++k) {
        const Shot& c = k == 0 ? below[ci] : k == 1 ? below[ci + 1] : k == 2 ? above[ci + 1] : above[ci];
        if (!c.ok) continue;
        poly.v[poly.n][0] = c.u;
        poly.v[poly.n][1] = c.v;
        ++poly.n;
        shot_ok[k] = true;
        corner_sign[poly.n - 1] = c.sign;
        shot[k][0] = c.u;
        shot[k][1] = c.v;
        shot[k][2] = c.t;
        shot[k][3] = c.xi;
        shot[k][4] = c.eta;
      }
      if (poly.n < 3 || !cell_image_valid(poly, corner_sign)) continue;
      if (ed.per > 0) add_edge_points(eg, e, fs, fm, E, ci, cj, mspn, lo, hi, hsz, poly, shot, shot_ok, ref, es, eused);
      ClipPolygon P;
      if (clip_polygons(rect, poly, P) & kClipOverflow) Kokkos::atomic_fetch_max(&flags(2), 1);
      const double mc[2] = {mlo[0] + (ci + 0.5) / sub * (mhi[0] - mlo[0]), mlo[1] + (cj + 0.5) / sub * (mhi[1] - mlo[1])};
      for_each_polygon_point(P, tri, [&](const double x[2], double w) {
        if (used < slots) {
          const int i = eg * slots + used;
          double d[3][3], nn[3];
          surface_first_derivatives(ref, es, x[0], x[1], d);
          cross3(d[1], d[2], nn);
          sp.face(i) = fs;
          sp.elem(i) = e;
          sp.uv(i, 0) = x[0];
          sp.uv(i, 1) = x[1];
          sp.weight(i) = w * kmath::sqrt(dot3(nn, nn));
          for (int c = 0; c < 3; ++c) sp.X(i, c) = d[0][c];
          sp.mface(i) = fm;   // the projection's warm start: this master element
          sp.melem(i) = E;
          sp.muv(i, 0) = mc[0];
          sp.muv(i, 1) = mc[1];
        }
        ++used;
      });
      }
      }
    }
    if (used > slots) Kokkos::atomic_fetch_max(&flags(0), used);
    if (eused > ed.per) Kokkos::atomic_fetch_max(&flags(3), eused);
  }

  /// Whether master element [mlo, mhi] can see slave element es along its normals within
  /// |t| <= margin: a shot x_s = x_m + t n_m moves tangentially (in the frame of the master
  /// element's centre normal nbar) by |t| |n_m - (n_m . nbar) nbar| <= margin sin(theta), theta
  /// the normals' spread over the element; the elements lie in the hulls of their control
  /// points (positive weights). So where the two hulls' extents along a tangent of nbar are
  /// farther apart than margin (2 s + 0.1), s the largest |n - nbar| at the element's corners
  /// (doubled for the interior, plus 0.1 for a nearly flat element and the straight-edged
  /// cells), no cell of the element can overlap the slave element: its shots are not made.
  /// The box test that chose the candidates grows the slave element by margin in every
  /// direction; on the Hertz ball ~2 % of its candidates' cells overlapped.
  KOKKOS_INLINE_FUNCTION bool facing(const SurfaceData& ss, const int es[2], int fm, int E, const int mspn[2],
                                     double margin) const {
    double nb[3], spread;
    if (!master_frame(m, fm, E, nb, spread)) return true;
    return facing_along(ss, es, m.f[fm].sd, mspn, nb, spread, margin);
  }

  /// One point of a master element's cell grid, shot along the master normal onto the slave
  /// element's surface (MortarSegments3::operator()).
  struct Shot {
    double u = 0, v = 0, t = 0, xi = 0, eta = 0;
    int sign = 0;   // sign(S_u x S_v . n) there: the map's orientation
    bool ok = false;
  };

  /// Grid point (i, j) of the sub x sub cells of master element [mlo, mhi]: x_s(u, v) = rho +
  /// t n by Newton on (u, v, t) from a neighbouring grid point's shot where that converged
  /// (start), else from the slave element's centre; ok where it converged with |t| <= margin.
  KOKKOS_INLINE_FUNCTION void shoot(const SurfaceData& ss, const int es[2], const SurfaceData& ms, const int mspn[2],
                                    const double mlo[2], const double mhi[2], int i, int j, double uc, double vc,
                                    double hsz, double margin, const Shot* start, Shot& out) const {
    out.ok = false;
    const double a = static_cast<double>(i) / sub, b = static_cast<double>(j) / sub;
    const double xi[2] = {mlo[0] + a * (mhi[0] - mlo[0]), mlo[1] + b * (mhi[1] - mlo[1])};
    double d[3][3];
    surface_first_derivatives(ms, mspn, xi[0], xi[1], d);
    double n[3];
    cross3(d[1], d[2], n);
    const double l = kmath::sqrt(dot3(n, n));
    if (!(l > 0)) return;
    for (int c = 0; c < 3; ++c) n[c] /= l;
    // x_s(u, v) = rho + t n: Newton on (u, v, t)
    const bool warm = start && start->ok;
    double u = warm ? start->u : uc, v = warm ? start->v : vc, tt = warm ? start->t : 0, oc = 0;
    bool ok = false;
    for (int it = 0; it < 30; ++it) {
      double ds[3][3];
      surface_first_derivatives(ss, es, u, v, ds);
      double cs[3];
      cross3(ds[1], ds[2], cs);
      oc = dot3(cs, n);
      double F[3];
      for (int c = 0; c < 3; ++c) F[c] = ds[0][c] - d[0][c] - tt * n[c];
      // J = [S_u, S_v, -n]; J delta = -F by Cramer's rule
      const double* J0 = ds[1];
      const double* J1 = ds[2];
      const double J2[3] = {-n[0], -n[1], -n[2]};
      double c12[3], c20[3], c01[3];
      cross3(J1, J2, c12);
      cross3(J2, J0, c20);
      cross3(J0, J1, c01);
      const double det = dot3(J0, c12);
      if (!(kmath::fabs(det) > 0)) break;
      const double du = -dot3(F, c12) / det, dv = -dot3(F, c20) / det, dt = -dot3(F, c01) / det;
      u += du;
      v += dv;
      tt += dt;
      // converged: a step below 1e-11 of the element's size plus the distance from its
      // centre (the slave polynomial evaluated far beyond its element carries round-off of
      // ~1e-13 of that distance: a master element five slave elements wide left corners
      // unconverged at 1e-14 and lost their segments)
      const double reach = hsz + kmath::fabs(u - uc) + kmath::fabs(v - vc);
      if (kmath::fabs(du) + kmath::fabs(dv) < 1e-11 * reach) { ok = true; break; }
      if (kmath::fabs(u - uc) > 100 * hsz || kmath::fabs(v - vc) > 100 * hsz) break;   // running away
    }
    if (!ok || kmath::fabs(tt) > margin) return;
    out.ok = true;
    out.u = u;
    out.v = v;
    out.t = tt;
    out.xi = xi[0];
    out.eta = xi[1];
    out.sign = oc > 0 ? 1 : oc < 0 ? -1 : 0;
  }

  /// Whether a cell's image is a simple polygon with the orientation of the map from the
  /// master to the slave parameters, sign(S_u x S_v . n) at each corner, the same at every
  /// corner. A corner shot onto the slave element's polynomial far beyond its element can land
  /// on a spurious intersection (the polynomial extended several elements carries the
  /// displacements' wiggles amplified): its image is then folded or inverted, and its hull would
  /// cover slave area that this cell does not see (measured: a box overhanging a curved master,
  /// its covered area 0.715 counted as 1.06 .. 1.37 with 2 .. 8 cells per master element).
  KOKKOS_INLINE_FUNCTION static bool cell_image_valid(const ClipPolygon& poly, const int* corner_sign) {
    const int sigma = corner_sign[0];
    if (sigma == 0) return false;
    for (int k = 1; k < poly.n; ++k)
      if (corner_sign[k] != sigma) return false;
    double area = 0;
    for (int k = 0; k < poly.n; ++k) {
      const int k1 = (k + 1) % poly.n;
      area += poly.v[k][0] * poly.v[k1][1] - poly.v[k1][0] * poly.v[k][1];
    }
    if (!(area * sigma > 0)) return false;
    if (poly.n == 4)   // opposite edges must not cross (a bow tie)
      for (int k = 0; k < 2; ++k) {
        const double* a = poly.v[k];
        const double* b = poly.v[k + 1];
        const double* c = poly.v[k + 2];
        const double* d = poly.v[(k + 3) % 4];
        const double o1 = orient2d(a, b, c), o2 = orient2d(a, b, d), o3 = orient2d(c, d, a), o4 = orient2d(c, d, b);
        if (o1 * o2 < 0 && o3 * o4 < 0) return false;
      }
    return true;
  }

  /// The edge points of cell (ci, cj) of master element E of face fm in slave element eg (element
  /// e of slave face fs) where its edges are the
  /// master face's boundary: each such edge a -> b (both corners shot) clipped to the slave
  /// element's rectangle (Liang-Barsky), with the Gauss rule on the clipped part. An edge along
  /// the rectangle's side counts for the element on its covered side only. Where two faces of a
  /// master list meet, each face writes its side of the edge: their sum is the jump term, as at
  /// a rough edge inside one face (below).
  KOKKOS_INLINE_FUNCTION void add_edge_points(int eg, int e, int fs, int fm, int E, int ci, int cj, const int mspn[2], const double lo[2],
                                              const double hi[2], double hsz, const ClipPolygon& poly,
                                              const double (*shot)[5], const bool* shot_ok, const SurfaceData& ref,
                                              const int es[2], int& eused) const {
    const SurfaceData& ms = m.f[fm].sd;
    // the master face's boundary, and master element edges across which the residual's
    // integrand jumps: the master's continuity there below `smooth` (1: the normal, 2: its
    // derivatives, which friction's slip variation carries). Both elements at such an edge
    // write its points, each with its own side's integrand and outward normal: their sum is the
    // jump term
    auto rough = [&](int d, int span) {   // the knot U_d[span] of continuity below smooth
      const double x = ms.U[d](span);
      int mult = 0;
      for (int k = span; k >= 0 && ms.U[d](k) == x; --k) ++mult;
      for (int k = span + 1; k < ms.n[d] + ms.p[d] + 1 && ms.U[d](k) == x; ++k) ++mult;
      return ms.p[d] - mult < smooth;
    };
    // (an open edge, ContactFace::open, is none: the master goes on past it)
    const int open = m.f[fm].open;
    const bool boundary[4] = {cj == 0 && ((mspn[1] == ms.p[1] && !open_past(ms, mspn, 1, 0, open)) || rough(1, mspn[1])),
                              ci == sub - 1 && ((mspn[0] == ms.n[0] - 1 && !open_past(ms, mspn, 0, 1, open)) || rough(0, mspn[0] + 1)),
                              cj == sub - 1 && ((mspn[1] == ms.n[1] - 1 && !open_past(ms, mspn, 1, 1, open)) || rough(1, mspn[1] + 1)),
                              ci == 0 && ((mspn[0] == ms.p[0] && !open_past(ms, mspn, 0, 0, open)) || rough(0, mspn[0]))};
    double area = 0;   // the orientation of the cell's image
    for (int k = 0; k < poly.n; ++k) {
      const int k1 = (k + 1) % poly.n;
      area += poly.v[k][0] * poly.v[k1][1] - poly.v[k1][0] * poly.v[k][1];
    }
    const double sigma = area > 0 ? 1.0 : -1.0;
    for (int k = 0; k < 4; ++k) {
      const int k1 = (k + 1) % 4;
      if (!boundary[k] || !shot_ok[k] || !shot_ok[k1]) continue;
      const double A[2] = {shot[k][0], shot[k][1]}, D[2] = {shot[k1][0] - A[0], shot[k1][1] - A[1]};
      double s0 = 0, s1 = 1;
      bool empty = false;
      for (int d = 0; d < 2 && !empty; ++d) {
        if (D[d] == 0) {
          empty = A[d] < lo[d] || A[d] > hi[d];
          continue;
        }
        double t0 = (lo[d] - A[d]) / D[d], t1 = (hi[d] - A[d]) / D[d];
        if (t0 > t1) {
          const double t = t0;
          t0 = t1;
          t1 = t;
        }
        s0 = t0 > s0 ? t0 : s0;
        s1 = t1 < s1 ? t1 : s1;
        empty = !(s1 - s0 > 1e-14);
      }
      if (empty) continue;
      const double nu[2] = {sigma * D[1], -sigma * D[0]};
      // the covered side (against nu) of the clipped edge's middle must be inside the rectangle
      const double sm = 0.5 * (s0 + s1), ln = kmath::sqrt(nu[0] * nu[0] + nu[1] * nu[1]);
      if (!(ln > 0)) continue;
      bool inside = true;
      for (int d = 0; d < 2; ++d) {
        const double x = A[d] + sm * D[d] - 1e-9 * hsz * nu[d] / ln;
        inside = inside && x > lo[d] && x < hi[d];
      }
      if (!inside) continue;
      for (int q = 0; q < gauss.n; ++q) {
        if (eused < ed.per) {
          const int i = eg * ed.per + eused;
          const double sq = s0 + 0.5 * (s1 - s0) * (gauss.x[q] + 1);
          const double u = A[0] + sq * D[0], v = A[1] + sq * D[1];
          double d[6][3], nn[3];
          surface_first_derivatives(ref, es, u, v, d);
          cross3(d[1], d[2], nn);
          ed.elem(i) = e;
          ed.sface(i) = fs;
          ed.mface(i) = fm;
          ed.melem(i) = E;
          ed.d(i, 0) = u;
          ed.d(i, 1) = v;
          ed.d(i, 2) = sq;
          ed.d(i, 3) = gauss.w[q] * 0.5 * (s1 - s0) * kmath::sqrt(dot3(nn, nn));
          ed.d(i, 4) = nu[0];
          ed.d(i, 5) = nu[1];
          for (int c = 0; c < 5; ++c) {
            ed.d(i, 6 + c) = shot[k][c];
            ed.d(i, 11 + c) = shot[k1][c];
          }
        }
        ++eused;
      }
    }
  }
};

/// The closest point to x of a surface's polynomial pieces, not clamped to an element or to
/// the face: Newton from (xi, eta) on the piece with spans ms (follow: the piece of each
/// iterate instead, its parameters clamped into the face to pick it, and returned in ms).
/// dm: S and its first derivatives at the foot (dm[0..2]).
KOKKOS_INLINE_FUNCTION void closest_point_unclamped(const SurfaceData& md, const double x[3], double& xi, double& eta, int ms[2],
                                                    bool follow, double dm[6][3]) {
  const double hsz = md.U[0](md.n[0]) - md.U[0](md.p[0]) + md.U[1](md.n[1]) - md.U[1](md.p[1]);
  for (int it = 0; it < 30; ++it) {
    if (follow) {
      ms[0] = find_span(md.n[0], md.p[0], xi, md.U[0].data());
      ms[1] = find_span(md.n[1], md.p[1], eta, md.U[1].data());
    }
    surface_derivatives(md, ms, xi, eta, dm);
    double r[3];
    for (int c = 0; c < 3; ++c) r[c] = x[c] - dm[0][c];
    const double F0 = dot3(r, dm[1]), F1 = dot3(r, dm[2]);
    const double J00 = -dot3(dm[1], dm[1]) + dot3(r, dm[3]), J01 = -dot3(dm[1], dm[2]) + dot3(r, dm[4]),
                 J11 = -dot3(dm[2], dm[2]) + dot3(r, dm[5]);
    const double det = J00 * J11 - J01 * J01;
    if (!(kmath::fabs(det) > 0)) break;
    const double d0 = -(J11 * F0 - J01 * F1) / det, d1 = -(-J01 * F0 + J00 * F1) / det;
    xi += d0;
    eta += d1;
    if (kmath::fabs(d0) + kmath::fabs(d1) < 1e-15 * hsz) break;
  }
  if (follow) {
    ms[0] = find_span(md.n[0], md.p[0], xi, md.U[0].data());
    ms[1] = find_span(md.n[1], md.p[1], eta, md.U[1].data());
  }
  surface_first_derivatives(md, ms, xi, eta, dm);
}

/// Edge point i of a mortar pair: the slave basis at it (Rs, cps; element spans es), the
/// closest point of the master element's polynomial to its slave point (basis Rm, cpm; spans
/// ms; Newton from the boundary point between its corners, (1 - s) xi_a + s xi_b, not clamped
/// to the element: the limit of the slots' projections as they approach the edge, which may
/// lie a little beyond the master's boundary where that is curved), the master's outward
/// normal n there and the gap g (foot: the master parameters, x: the slave point, when given).
/// Returns false where the master normal is not defined.
KOKKOS_INLINE_FUNCTION bool edge_point(const ContactFace& sf, const ContactFace& mf, const MortarEdges3& ed, int i, int es[2],
                                       int ms[2], double* Rs, int* cps, int& ns, double* Rm, int* cpm, int& nm, double n[3],
                                       double& g, double* foot = nullptr, double* x = nullptr) {
  surface_element_spans(sf.sd, ed.elem(i), es);
  surface_element_spans(mf.sd, ed.melem(i), ms);
  const double s = ed.d(i, 2);
  double xi = (1 - s) * ed.d(i, 9) + s * ed.d(i, 14), eta = (1 - s) * ed.d(i, 10) + s * ed.d(i, 15);
  double Ru[kMaxSurfaceBasis], Rv[kMaxSurfaceBasis], ds[6][3], dm[6][3];
  ns = surface_basis(sf.sd, es, ed.d(i, 0), ed.d(i, 1), Rs, Ru, Rv, cps);
  surface_derivatives_to<0>(sf.sd, es, ed.d(i, 0), ed.d(i, 1), ds);
  closest_point_unclamped(mf.sd, ds[0], xi, eta, ms, false, dm);
  nm = surface_basis(mf.sd, ms, xi, eta, Rm, Ru, Rv, cpm);
  cross3(dm[1], dm[2], n);
  const double l = kmath::sqrt(dot3(n, n));
  if (!(l > 0)) return false;
  g = 0;
  for (int c = 0; c < 3; ++c) {
    n[c] *= mf.sign / l;
    g += (ds[0][c] - dm[0][c]) * n[c];
  }
  if (foot) {
    foot[0] = xi;
    foot[1] = eta;
  }
  if (x)
    for (int c = 0; c < 3; ++c) x[c] = ds[0][c];
  return true;
}

/// The edge points as slave points (friction: their slip vectors and variations come from the
/// slots' functions): the slave parameters and reference measure, the foot of edge_point.
struct MortarEdgePoints3 {
  ContactFaces s, m;
  MortarEdges3 ed;
  SlavePoints3 esp;

  KOKKOS_INLINE_FUNCTION void operator()(const int i) const {
    esp.valid(i) = 0;
    esp.pressure(i) = 0;
    esp.face(i) = -1;
    if (ed.elem(i) < 0) return;
    double Rs[kMaxSurfaceBasis], Rm[kMaxSurfaceBasis], n[3], g, foot[2], x[3];
    int cps[kMaxSurfaceBasis], cpm[kMaxSurfaceBasis], es[2], ms[2], ns, nm;
    esp.face(i) = ed.sface(i);
    esp.elem(i) = ed.elem(i);
    esp.uv(i, 0) = ed.d(i, 0);
    esp.uv(i, 1) = ed.d(i, 1);
    esp.weight(i) = ed.d(i, 3);
    if (!edge_point(s.f[ed.sface(i)], m.f[ed.mface(i)], ed, i, es, ms, Rs, cps, ns, Rm, cpm, nm, n, g, foot, x)) return;
    esp.valid(i) = 1;
    esp.mface(i) = ed.mface(i);
    esp.melem(i) = ed.melem(i);
    esp.muv(i, 0) = foot[0];
    esp.muv(i, 1) = foot[1];
    esp.gap(i) = g;
    for (int c = 0; c < 3; ++c) {
      esp.x(i, c) = x[c];
      esp.normal(i, c) = n[c];
    }
  }
};

/// The derivative V' of edge point i's outward normal velocity V = nu . ((1 - s) da + s db)
/// (da, db: the motions of its corners' shots in the slave parameter plane): add(master, a, cp,
/// c, value) for component c of the element's slave (master = false) or master control point
/// a (local index, as surface_basis orders them; cp its surface index). A corner solves F = x_s(u, v) - rho(xi_c) - t n(xi_c) = 0 at fixed xi_c, so
/// [x_s,u x_s,v -n] (du, dv, dt) = -(sum_a R_a dx_a - sum_b R_b dx_b - t dn), with
/// dn = (I - n n) (drho_xi x rho_eta + rho_xi x drho_eta) / |rho_xi x rho_eta| (n unsigned, as
/// the shot's); the rows of the inverse by Cramer's rule, contracted with nu first.
template <class Add>
KOKKOS_INLINE_FUNCTION void edge_velocity(const SurfaceData& ss, const int es[2], const SurfaceData& md, const int ms[2],
                                          const MortarEdges3& ed, int i, const Add& add) {
  const double s = ed.d(i, 2), nu[2] = {ed.d(i, 4), ed.d(i, 5)};
  for (int k = 0; k < 2; ++k) {
    const int o = 6 + 5 * k;
    const double wt = k == 0 ? 1 - s : s;
    const double uc = ed.d(i, o), vc = ed.d(i, o + 1), t = ed.d(i, o + 2), xi = ed.d(i, o + 3), eta = ed.d(i, o + 4);
    double R[kMaxSurfaceBasis], Ru[kMaxSurfaceBasis], Rv[kMaxSurfaceBasis];
    double Rm[kMaxSurfaceBasis], Rm1[kMaxSurfaceBasis], Rm2[kMaxSurfaceBasis];
    int cp[kMaxSurfaceBasis], cpm[kMaxSurfaceBasis];
    const int ns = surface_basis(ss, es, uc, vc, R, Ru, Rv, cp);
    const int nm = surface_basis(md, ms, xi, eta, Rm, Rm1, Rm2, cpm);
    double ds[6][3], dm[6][3];
    surface_first_derivatives(ss, es, uc, vc, ds);
    surface_first_derivatives(md, ms, xi, eta, dm);
    double n[3];
    cross3(dm[1], dm[2], n);
    const double l = kmath::sqrt(dot3(n, n));
    if (!(l > 0)) continue;
    for (int c = 0; c < 3; ++c) n[c] /= l;
    const double mn[3] = {-n[0], -n[1], -n[2]};
    double c12[3], c20[3];
    cross3(ds[2], mn, c12);
    cross3(mn, ds[1], c20);
    const double det = dot3(ds[1], c12);
    if (!(kmath::fabs(det) > 0)) continue;
    double q[3];
    for (int c = 0; c < 3; ++c) q[c] = (nu[0] * c12[c] + nu[1] * c20[c]) / det;
    const double qn = dot3(q, n);
    const double qp[3] = {q[0] - qn * n[0], q[1] - qn * n[1], q[2] - qn * n[2]};
    double a1[3], a2[3];   // rho_eta x q_perp, q_perp x rho_xi
    cross3(dm[2], qp, a1);
    cross3(qp, dm[1], a2);
    for (int a = 0; a < ns; ++a)
      for (int c = 0; c < 3; ++c) add(false, a, cp[a], c, -wt * R[a] * q[c]);
    for (int b = 0; b < nm; ++b)
      for (int c = 0; c < 3; ++c) add(true, b, cpm[b], c, wt * (Rm[b] * q[c] + t / l * (Rm1[b] * a1[c] + Rm2[b] * a2[c])));
  }
}

/// f(i, R_A(edge point i), its slave face) for the edge points of the slave elements in A's
/// support.
template <class F>
KOKKOS_INLINE_FUNCTION void for_each_support_edge3(const ContactFaces& s, const MortarEdges3& ed, int A, const F& f) {
  if (ed.per == 0) return;
  for_each_support_element3(s, A, [&](int eg, int fa, int la, const int es[2]) {
    for (int i = eg * ed.per; i < (eg + 1) * ed.per; ++i) {
      if (ed.elem(i) < 0) break;   // filled from the element's first entry on
      double R[kMaxSurfaceBasis], Ru[kMaxSurfaceBasis], Rv[kMaxSurfaceBasis];
      int cp[kMaxSurfaceBasis];
      surface_basis(s.f[fa].sd, es, ed.d(i, 0), ed.d(i, 1), R, Ru, Rv, cp);
      f(i, R[la], fa);
    }
  });
}

/// K += -w row (x) vel on an element pair's entries (3 per slave cp, then 3 per master cp, nb
/// control points in all): row(r) the row's value, vel the columns', lid(q) the contact
/// matrix's dof of entry q (-1: none). The boundary terms' outer products.
template <class LocalMatrix, class Row, class Lid>
KOKKOS_INLINE_FUNCTION void add_edge_outer(const LocalMatrix& K, int nb, double w, const Row& row, const double* vel,
                                           const Lid& lid) {
  for (int r = 0; r < 3 * nb; ++r) {
    const double v = row(r);
    const int lr = lid(r);
    if (v == 0 || lr < 0) continue;
    for (int b = 0; b < nb; ++b) {
      int cols[3];
      double vals[3];
      int nc = 0;
      for (int cc = 0; cc < 3; ++cc) {
        const int q = 3 * b + cc, lq = lid(q);
        if (vel[q] == 0 || lq < 0) continue;
        cols[nc] = lq;
        vals[nc++] = -w * v * vel[q];
      }
      if (nc > 0) K.sumIntoValues(lr, cols, nc, vals, true, true);
    }
  }
}

/// The boundary term of the pressure part, K_c -= \oint p N (x) V' dl_0, at this rank's edge
/// points [e_begin, ...) where the pressure field is positive.
template <class LocalMatrix>
struct AssembleMortarEdge3 {
  ContactFaces s, m;
  MortarEdges3 ed;
  MortarState ms;
  int e_begin = 0;
  LocalMatrix K;

  KOKKOS_INLINE_FUNCTION void operator()(const int k) const {
    const int i = e_begin + k;
    if (ed.elem(i) < 0) return;
    const ContactFace& sf = s.f[ed.sface(i)];
    const ContactFace& mf = m.f[ed.mface(i)];
    double Rs[kMaxSurfaceBasis], Rm[kMaxSurfaceBasis], n[3], g;
    int cps[kMaxSurfaceBasis], cpm[kMaxSurfaceBasis], es[2], mspn[2], ns, nm;
    if (!edge_point(sf, mf, ed, i, es, mspn, Rs, cps, ns, Rm, cpm, nm, n, g)) return;
    double p = 0;
    for (int a = 0; a < ns; ++a) p += ms.lambda(sf.aid(cps[a])) * Rs[a];
    if (!(p > 0)) return;
    // V' on the element pair's entries: 3 per slave cp (the element's order), then 3 per master cp
    double vel[3 * 2 * kMaxSurfaceBasis];
    for (int q = 0; q < 3 * (ns + nm); ++q) vel[q] = 0;
    edge_velocity(sf.sd, es, mf.sd, mspn, ed, i,
                  [&](bool master, int a, int, int c, double v) { vel[3 * (a + (master ? ns : 0)) + c] += v; });
    const double w = ed.d(i, 3);
    auto lid = [&](int r) {
      const int cp = r / 3;
      const int l = cp < ns ? sf.lid(cps[cp]) : mf.lid(cpm[cp - ns]);
      return l < 0 ? -1 : dof_of(l, r % 3, 3);
    };
    add_edge_outer(
        K, ns + nm, w * p,
        [&](int r) {   // N
          const int cp = r / 3, c = r % 3;
          return cp < ns ? Rs[cp] * n[c] : -Rm[cp - ns] * n[c];
        },
        vel, lid);
  }
};

/// f(eg, fa, la, es) for the slave elements eg in the support of slave control point A, on each
/// slave face fa that holds A: la the local index of A in the element (element e of face fa,
/// eg = eoff[fa] + e), es the element's spans.
template <class F>
KOKKOS_INLINE_FUNCTION void for_each_support_element3(const ContactFaces& s, int A, const F& f) {
  for (int k = s.a_ptr(A); k < s.a_ptr(A + 1); ++k) {
    const int fa = s.a_occ(k, 0), a = s.a_occ(k, 1);
    const SurfaceData& sd = s.f[fa].sd;
    const int ia = a % sd.n[0], ja = a / sd.n[0];
    for (int e1 = 0; e1 < sd.ne[1]; ++e1) {
      const int s1 = sd.span[1](e1);
      if (s1 < ja || s1 > ja + sd.p[1]) continue;
      for (int e0 = 0; e0 < sd.ne[0]; ++e0) {
        const int s0 = sd.span[0](e0);
        if (s0 < ia || s0 > ia + sd.p[0]) continue;
        const int es[2] = {s0, s1};
        f(s.eoff[fa] + e0 + sd.ne[0] * e1, fa, (ia - (s0 - sd.p[0])) + (sd.p[0] + 1) * (ja - (s1 - sd.p[1])), es);
      }
    }
  }
}

/// The slave basis at every slot of [first, last) into sp.R: surface_basis once per slot, where
/// the sums per slave control point read it (each slot is in the support of (p + 1)^2 of them).
struct SlotBasis3 {
  ContactFaces s;
  SlavePoints3 sp;
  KOKKOS_INLINE_FUNCTION void operator()(const int i) const {
    if (sp.face(i) < 0) return;
    const SurfaceData& sd = s.f[sp.face(i)].sd;
    int es[2];
    surface_element_spans(sd, sp.elem(i), es);
    double R[kMaxSurfaceBasis], Ru[kMaxSurfaceBasis], Rv[kMaxSurfaceBasis];
    int cp[kMaxSurfaceBasis];
    const int n = surface_basis(sd, es, sp.uv(i, 0), sp.uv(i, 1), R, Ru, Rv, cp);
    for (int a = 0; a < n; ++a) sp.R(i, a) = R[a];
  }
};

/// The slave basis at slot i (as surface_basis: R and the control points cp of the element with
/// spans es of the slot's face sd) from sp.R.
KOKKOS_INLINE_FUNCTION int slot_basis_cached(const SurfaceData& sd, const SlavePoints3& sp, int i, const int es[2], double* R,
                                             int* cp) {
  int k = 0;
  for (int j = 0; j <= sd.p[1]; ++j)
    for (int a = 0; a <= sd.p[0]; ++a, ++k) {
      cp[k] = surface_cp(sd, es, a, j);
      R[k] = sp.R(i, k);
    }
  return k;
}

/// f(i, R_A(slot i), the slot's face, its element's spans) for the valid slots of the slave
/// elements in A's support (R_A from sp.R).
template <class F>
KOKKOS_INLINE_FUNCTION void for_each_support_slot3(const ContactFaces& s, const SlavePoints3& sp, int slots, int A,
                                                   const F& f) {
  for_each_support_element3(s, A, [&](int eg, int fa, int la, const int es[2]) {
    for (int i = eg * slots; i < (eg + 1) * slots; ++i) {
      if (sp.face(i) < 0 || !sp.valid(i)) continue;
      f(i, sp.R(i, la), fa, es);
    }
  });
}

/// f(i) for the valid slots of the slave elements in A's support.
template <class F>
KOKKOS_INLINE_FUNCTION void for_each_support_slot_index3(const ContactFaces& s, const SlavePoints3& sp, int slots, int A,
                                                         const F& f) {
  for_each_support_element3(s, A, [&](int eg, int, int, const int*) {
    for (int i = eg * slots; i < (eg + 1) * slots; ++i)
      if (sp.face(i) >= 0 && sp.valid(i)) f(i);
  });
}

/// Weighted gaps, multipliers and the active set of every slave control point A.
struct MortarGaps3 {
  ContactFaces s;
  SlavePoints3 sp;
  MortarState ms;
  double eps = 0, touch = 0;
  int slots = 1;
  Kokkos::View<const int*, MemSpace> out;   // MortarOut3's; empty: none

  KOKKOS_INLINE_FUNCTION void operator()(const int A) const {
    double g = 0, cw = 0;
    int cov = 0;
    const SlavePoints3& p = sp;
    for_each_support_slot3(s, sp, slots, A, [&](int i, double RA, int, const int*) {
      g += RA * p.weight(i) * p.gap(i);
      cw += RA * p.weight(i);
      cov = 1;
    });
    if (A < static_cast<int>(ms.cwA.extent(0))) ms.cwA(A) = cw;
    mortar_multiplier(ms, A, g, cov, eps, touch);
    if (out.extent(0) > 0 && out(A)) {   // certainly out of contact (MortarOut3): its support partly unsegmented
      ms.active(A) = 0;
      ms.lambda(A) = 0;
    }
  }
};

KOKKOS_INLINE_FUNCTION void MortarOut3::operator()(const int A) const {
  bool all = ms.lbar(A) == 0;
  for_each_support_element3(s, A, [&](int eg, int, int, const int*) { all = all && far(eg); });
  out(A) = all ? 1 : 0;
}

/// The pressure field at the slots, p = sum_A lambda_A R_A (the slot's `pressure`).
struct MortarPointPressure3 {
  ContactFaces s;
  SlavePoints3 sp;
  MortarState ms;

  KOKKOS_INLINE_FUNCTION void operator()(const int i) const {
    if (sp.face(i) < 0 || !sp.valid(i)) {
      sp.pressure(i) = 0;
      return;
    }
    double R[kMaxSurfaceBasis];
    int cp[kMaxSurfaceBasis];
    const int n = slave_point_basis(s, sp, i, R, cp);
    const ContactFace& sf = s.f[sp.face(i)];
    double pr = 0;
    for (int a = 0; a < n; ++a) pr += ms.lambda(sf.aid(cp[a])) * R[a];
    sp.pressure(i) = pr;
  }
};

/// The dense dof range of slave control point A's mortar vectors (delta g_A, and with friction
/// V_A): per slave face that holds A the box of its control points within p of A, then per
/// master face the box of its control points that the slots' and edge points' master elements
/// use; 3 entries (x, y, z) per control point. A control point shared by two faces has an entry
/// in each box: the compaction to the contact matrix's dofs merges them (merge_sorted_dof).
/// Boxes 0 .. ns - 1 are the slave faces', ns .. ns + nm - 1 the master faces'.
struct MortarRange3 {
  static constexpr int kBoxes = 2 * kMaxFacesPerSurface;
  int ns = 0, nb = 0;
  int lo[kBoxes][2], n[kBoxes][2], dn0[kBoxes];
  int off[kBoxes + 1];   // the first control point of box b
  /// Returns the range's size, 0 when no slot of A's support has a projection.
  KOKKOS_INLINE_FUNCTION int init(const ContactFaces& s, const ContactFaces& m, const SlavePoints3& sp, int slots,
                                  const MortarEdges3& ed, int A) {
    ns = s.n;
    nb = s.n + m.n;
    int hi[kBoxes][2];
    for (int b = 0; b < nb; ++b) {
      const SurfaceData& sd = b < ns ? s.f[b].sd : m.f[b - ns].sd;
      dn0[b] = sd.n[0];
      lo[b][0] = sd.n[0];
      lo[b][1] = sd.n[1];
      hi[b][0] = hi[b][1] = -1;
    }
    // the slave control points within p of A on each face that holds it (widened over A's
    // occurrences: a face may hold A twice, where a patch's interface is with itself)
    for (int k = s.a_ptr(A); k < s.a_ptr(A + 1); ++k) {
      const int fa = s.a_occ(k, 0), a = s.a_occ(k, 1);
      const SurfaceData& sd = s.f[fa].sd;
      const int ij[2] = {a % sd.n[0], a / sd.n[0]};
      for (int d = 0; d < 2; ++d) {
        lo[fa][d] = ij[d] - sd.p[d] < lo[fa][d] ? ij[d] - sd.p[d] : lo[fa][d];
        hi[fa][d] = ij[d] + sd.p[d] > hi[fa][d] ? ij[d] + sd.p[d] : hi[fa][d];
      }
    }
    bool any = false;
    auto widen = [&](int f, int E) {
      const SurfaceData& md = m.f[f].sd;
      int ms_[2];
      surface_element_spans(md, E, ms_);
      for (int d = 0; d < 2; ++d) {
        lo[ns + f][d] = ms_[d] - md.p[d] < lo[ns + f][d] ? ms_[d] - md.p[d] : lo[ns + f][d];
        hi[ns + f][d] = ms_[d] > hi[ns + f][d] ? ms_[d] : hi[ns + f][d];
      }
    };
    for_each_support_slot_index3(s, sp, slots, A, [&](int i) {
      widen(sp.mface(i), sp.melem(i));
      any = true;
    });
    if (!any) return 0;
    for_each_support_edge3(s, ed, A, [&](int i, double, int) { widen(ed.mface(i), ed.melem(i)); });
    off[0] = 0;
    for (int b = 0; b < nb; ++b) {
      for (int d = 0; d < 2; ++d) n[b][d] = hi[b][d] >= 0 ? hi[b][d] - lo[b][d] + 1 : 0;
      off[b + 1] = off[b] + n[b][0] * n[b][1];
    }
    return 3 * off[nb];
  }
  /// The first entry of control point cp (its surface index) of box b.
  KOKKOS_INLINE_FUNCTION int box(int b, int cp) const {
    return 3 * (off[b] + (cp % dn0[b] - lo[b][0]) + n[b][0] * (cp / dn0[b] - lo[b][1]));
  }
  KOKKOS_INLINE_FUNCTION int slave(int f, int cp) const { return box(f, cp); }
  KOKKOS_INLINE_FUNCTION int master(int f, int cp) const { return box(ns + f, cp); }
  /// The contact matrix's dof of entry q (-1: a control point without an overlap dof).
  KOKKOS_INLINE_FUNCTION int dof(int q, const ContactFaces& s, const ContactFaces& m) const {
    const int cpq = q / 3, c = q % 3;
    int b = 0;
    while (cpq >= off[b + 1]) ++b;
    const int r = cpq - off[b], ci = lo[b][0] + r % n[b][0], cj = lo[b][1] + r / n[b][0];
    const ContactFace& f = b < ns ? s.f[b] : m.f[b - ns];
    const int lid = f.lid(ci + dn0[b] * cj);
    return lid < 0 ? -1 : dof_of(lid, c, 3);
  }
};

/// Compaction of a dense range: entry `dof` with its nv values val inserted into the sorted
/// list dofs[0, nnz) with values vals (nv per entry: vals(pos, b)), or added to the entry of
/// the same dof (a control point shared by two master faces). The list's storage may be the
/// dense range itself as long as nnz <= the entry read.
template <class Dofs, class Vals>
KOKKOS_INLINE_FUNCTION void merge_sorted_dof(int dof, const double* val, int nv, int& nnz, const Dofs& dofs, const Vals& vals) {
  int pos = nnz;
  while (pos > 0 && dofs(pos - 1) > dof) --pos;
  if (pos > 0 && dofs(pos - 1) == dof) {
    for (int b = 0; b < nv; ++b) vals(pos - 1, b) += val[b];
    return;
  }
  for (int r = nnz; r > pos; --r) {
    dofs(r) = dofs(r - 1);
    for (int b = 0; b < nv; ++b) vals(r, b) = vals(r - 1, b);
  }
  dofs(pos) = dof;
  for (int b = 0; b < nv; ++b) vals(pos, b) = val[b];
  ++nnz;
}

/// A slot's part of delta g_A = int R_A N dGamma_0 on A's dense range: add(entry, value) for
/// the slave control points (w R_a n) and the master ones (-w R_b n) of the slot's elements
/// (w: R_A times the slot's weight; Rs, Rm the bases at the slot on slave face sf and at its
/// foot on master face mf).
template <class Add>
KOKKOS_INLINE_FUNCTION void add_gap_variation(const MortarRange3& rg, int sf, const double* Rs, const int* cps, int ns, int mf,
                                              const double* Rm, const int* cpm, int nm, const double n[3], double w,
                                              const Add& add) {
  for (int a = 0; a < ns; ++a)
    for (int c = 0; c < 3; ++c) add(rg.slave(sf, cps[a]) + c, w * Rs[a] * n[c]);
  for (int b = 0; b < nm; ++b)
    for (int c = 0; c < 3; ++c) add(rg.master(mf, cpm[b]) + c, -w * Rm[b] * n[c]);
}

/// K_c += eps / w_A delta g_A (x) delta g_A for the active slave control points [a_begin, ...):
/// delta g_A accumulated on a dense range (the slave control points within p of A, then the
/// box of master control points its slots' master elements use) in scratch row k, compacted
/// to the touched overlap dofs, sorted, and summed as an outer product.
template <class LocalMatrix>
struct AssembleMortarGap3 {
  ContactFaces s, m;
  SlavePoints3 sp;
  MortarEdges3 ed;
  MortarState ms;
  MortarScratch sc;
  double eps = 0;
  int slots = 1, a_begin = 0;
  LocalMatrix K;

  KOKKOS_INLINE_FUNCTION void operator()(const int k) const {
    const int A = a_begin + k;
    if (!ms.active(A)) return;
    MortarRange3 rg;
    const int size = rg.init(s, m, sp, slots, ed, A);
    if (size == 0) return;
    if (size > sc.cap()) {
      Kokkos::atomic_fetch_max(&ms.flags(1), size);
      return;
    }
    const SlavePoints3& p = sp;
    for (int q = 0; q < size; ++q) sc.v0(k, q) = 0;
    const MortarScratch& S = sc;
    for_each_support_slot3(s, sp, slots, A, [&](int i, double RA, int fa, const int es[2]) {
      const double w = RA * p.weight(i);
      const double n[3] = {p.normal(i, 0), p.normal(i, 1), p.normal(i, 2)};
      double R[kMaxSurfaceBasis], Rm[kMaxSurfaceBasis], Ru[kMaxSurfaceBasis], Rv[kMaxSurfaceBasis];
      int cp[kMaxSurfaceBasis], cpm[kMaxSurfaceBasis];
      int mspn[2];
      const int nsb = slot_basis_cached(s.f[fa].sd, p, i, es, R, cp);
      const int mf = p.mface(i);
      const SurfaceData& md = m.f[mf].sd;
      surface_element_spans(md, p.melem(i), mspn);
      const int nmb = surface_basis(md, mspn, p.muv(i, 0), p.muv(i, 1), Rm, Ru, Rv, cpm);
      add_gap_variation(rg, fa, R, cp, nsb, mf, Rm, cpm, nmb, n, w, [&](int q, double v) { S.v0(k, q) += v; });
    });
    // the boundary part b_A = \oint R_A g V' dl_0 (where the master ends inside A's elements)
    // in the row scratch; the columns are delta g_A + b_A
    for (int q = 0; q < size; ++q) sc.row(k, q) = 0;
    for_each_support_edge3(s, ed, A, [&](int i, double RA, int fa) {
      double Rs[kMaxSurfaceBasis], Rm[kMaxSurfaceBasis], n[3], g;
      int cps[kMaxSurfaceBasis], cpm[kMaxSurfaceBasis], es[2], mspn[2], nsb, nmb;
      const int mf = ed.mface(i);
      if (RA == 0 || !edge_point(s.f[fa], m.f[mf], ed, i, es, mspn, Rs, cps, nsb, Rm, cpm, nmb, n, g)) return;
      const double w = RA * g * ed.d(i, 3);
      edge_velocity(s.f[fa].sd, es, m.f[mf].sd, mspn, ed, i, [&](bool master, int, int cp, int c, double v) {
        S.row(k, (master ? rg.master(mf, cp) : rg.slave(fa, cp)) + c) += w * v;
      });
    });
    // compact to the touched entries with an overlap dof, sorted by dof (insertion sort; a
    // dof in two faces' boxes merged): v1 the rows' delta g_A, v0 the columns'
    // delta g_A + b_A (the list's end stays at or before the entry read)
    int nnz = 0;
    for (int q = 0; q < size; ++q) {
      const double val[2] = {sc.v0(k, q), sc.v0(k, q) + sc.row(k, q)};
      if (val[0] == 0 && val[1] == 0) continue;
      const int dof = rg.dof(q, s, m);
      if (dof < 0) continue;
      merge_sorted_dof(dof, val, 2, nnz, [&](int r) -> int& { return sc.dof(k, r); },
                       [&](int r, int b) -> double& { return b == 0 ? sc.v1(k, r) : sc.v0(k, r); });
    }
    const double c = mortar_eps(ms, A, eps) / ms.wA(A);
    int* dof = &sc.dof(k, 0);
    double* row = &sc.row(k, 0);
    for (int r = 0; r < nnz; ++r) {
      if (sc.v1(k, r) == 0) continue;
      for (int q = 0; q < nnz; ++q) row[q] = c * sc.v1(k, r) * sc.v0(k, q);
      K.sumIntoValues(dof[r], dof, nnz, row, true, true);
    }
  }
};

}  // namespace iga
