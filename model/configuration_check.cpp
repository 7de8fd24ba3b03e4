#include "model/configuration_check.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

#include "model/geometry_check.hpp"

namespace iga {

std::string check_number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", v);
  return buf;
}

// Outer sides of a body (not interfaces, not collapsed to a point).
std::vector<PatchSide> outer_sides(const Body& b) {
  std::vector<PatchSide> out;
  for (size_t k = 0; k < b.patches.size(); ++k)
    for (int s = 0; s < num_sides(b.patches[k].dim()); ++s) {
      const PatchSide ps{static_cast<int>(k), static_cast<Side>(s)};
      if (!b.is_interface(ps) && !side_collapsed(b.patches[k], ps.side, b.tolerance)) out.push_back(ps);
    }
  return out;
}

namespace {

using Vec = std::array<double, 2>;

double dist(const Vec& a, const Vec& b) { return std::hypot(a[0] - b[0], a[1] - b[1]); }

std::string point(const Vec& x) { return "(" + check_number(x[0]) + ", " + check_number(x[1]) + ")"; }

// ------------------------------------------------------------------ curves: points, normals

struct CurveSample {
  Vec x, n;   // point, outward unit normal
};

// Points and outward normals of a chain: `per` interior points per element and the element ends.
std::vector<CurveSample> sample_chain(const SurfaceChain& ch, int per) {
  const Curve& c = ch.curve;
  const double a = c.knots.front(), b = c.knots.back();
  std::vector<CurveSample> out;
  for (const int s : c.element_spans()) {
    const double t0 = c.knots[s], t1 = c.knots[s + 1];
    for (int i = 0; i <= per + 1; ++i) {
      const double t = t0 + (t1 - t0) * i / (per + 1);
      const double h = 1e-7 * (b - a);
      const Vec p = c.eval(std::min(t + h, b)), q = c.eval(std::max(t - h, a));
      const double tx = p[0] - q[0], ty = p[1] - q[1], l = std::hypot(tx, ty);
      if (!(l > 0)) continue;   // a collapsed point: no normal
      out.push_back({c.eval(t), {ch.normal_sign * ty / l, -ch.normal_sign * tx / l}});
    }
  }
  return out;
}

bool faces(const std::vector<CurveSample>& slave, const std::vector<CurveSample>& master, double d) {
  for (const CurveSample& s : slave)
    for (const CurveSample& m : master) {
      const double nn = s.n[0] * m.n[0] + s.n[1] * m.n[1];
      if (nn >= -1e-3) continue;
      const double ms = (m.x[0] - s.x[0]) * s.n[0] + (m.x[1] - s.x[1]) * s.n[1];
      const double sm = (s.x[0] - m.x[0]) * m.n[0] + (s.x[1] - m.x[1]) * m.n[1];
      if (ms >= -d && sm >= -d) return true;
    }
  return false;
}

// Smallest extent of a body's control-point box.
double smallest_extent(const Body& b) {
  double lo[2] = {1e300, 1e300}, hi[2] = {-1e300, -1e300};
  for (const Patch& p : b.patches)
    for (const ControlPoint& q : p.cp)
      for (int d = 0; d < 2; ++d) { lo[d] = std::min(lo[d], q.x[d]); hi[d] = std::max(hi[d], q.x[d]); }
  return std::min(hi[0] - lo[0], hi[1] - lo[1]);
}


// ------------------------------------------------------------------ faces (3-D)

struct FaceSample {
  std::array<double, 3> x, n;   // point, outward unit normal
};

double dot(const std::array<double, 3>& a, const std::array<double, 3>& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

// Points and outward normals of patch faces: `per` + 2 points a direction per element (its
// corners and edges included), normals by central differences of the face's map.
std::vector<FaceSample> sample_faces(const Body& b, const std::vector<PatchSide>& sides, int per) {
  std::vector<FaceSample> out;
  for (const PatchSide& ps : sides) {
    const Patch& Pt = b.patches[ps.patch];
    const Patch F = Pt.face(ps.side);
    const double sign = side_normal_sign(static_cast<int>(ps.side)) * Pt.orientation();
    const double lo[2] = {F.knots[0].front(), F.knots[1].front()}, hi[2] = {F.knots[0].back(), F.knots[1].back()};
    const auto s0 = F.element_spans(0), s1 = F.element_spans(1);
    for (int e1 : s1)
      for (int e0 : s0) {
        const double a[2] = {F.knots[0][e0], F.knots[1][e1]}, z[2] = {F.knots[0][e0 + 1], F.knots[1][e1 + 1]};
        for (int j = 0; j <= per + 1; ++j)
          for (int i = 0; i <= per + 1; ++i) {
            const double t[2] = {a[0] + (z[0] - a[0]) * i / (per + 1), a[1] + (z[1] - a[1]) * j / (per + 1)};
            std::array<double, 3> tg[2];
            for (int d = 0; d < 2; ++d) {
              const double h = 1e-7 * (hi[d] - lo[d]);
              double tp[2] = {t[0], t[1]}, tm[2] = {t[0], t[1]};
              tp[d] = std::min(t[d] + h, hi[d]);
              tm[d] = std::max(t[d] - h, lo[d]);
              const auto xp = F.point(tp), xm = F.point(tm);
              for (int c = 0; c < 3; ++c) tg[d][c] = xp[c] - xm[c];
            }
            std::array<double, 3> n = {tg[0][1] * tg[1][2] - tg[0][2] * tg[1][1], tg[0][2] * tg[1][0] - tg[0][0] * tg[1][2],
                                       tg[0][0] * tg[1][1] - tg[0][1] * tg[1][0]};
            const double l = std::sqrt(dot(n, n));
            if (!(l > 0)) continue;   // a collapsed point: no normal
            const auto x = F.point(t);
            for (int c = 0; c < 3; ++c) n[c] *= sign / l;
            out.push_back({{x[0], x[1], x[2]}, n});
          }
      }
  }
  return out;
}

bool faces(const std::vector<FaceSample>& slave, const std::vector<FaceSample>& master, double d) {
  for (const FaceSample& s : slave)
    for (const FaceSample& m : master) {
      if (dot(s.n, m.n) >= -1e-3) continue;
      std::array<double, 3> ms, sm;
      for (int c = 0; c < 3; ++c) { ms[c] = m.x[c] - s.x[c]; sm[c] = -ms[c]; }
      if (dot(ms, s.n) >= -d && dot(sm, m.n) >= -d) return true;
    }
  return false;
}

// Smallest extent of a solid's control-point box.
double smallest_extent3(const Body& b) {
  double lo[3] = {1e300, 1e300, 1e300}, hi[3] = {-1e300, -1e300, -1e300};
  for (const Patch& p : b.patches)
    for (const ControlPoint& q : p.cp)
      for (int d = 0; d < 3; ++d) { lo[d] = std::min(lo[d], q.x[d]); hi[d] = std::max(hi[d], q.x[d]); }
  return std::min({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
}

// The deepest initial overlap of a pair's sides (curve or face samples): for each slave sample,
// the nearest master sample with an opposed normal (n_s . n_m < -1/2) that lies no farther
// sideways than 1.5 x that master sample's distance to its neighbours in the sampling grid
// (the samples before and after it, and `row` before and after: one element's row of face
// samples); where each lies behind the other's side ((x_m - x_s) . n_s < 0 and
// (x_s - x_m) . n_m < 0), the smaller of the two depths. 0 where nothing overlaps. Read
// time: the slave samples are thinned so that at most 2e7 pairs are compared (about 0.1 s;
// the depth is then that of the samples taken).
template <class S>
double overlap_depth(const std::vector<S>& slave, const std::vector<S>& master, size_t row) {
  auto dotn = [](const auto& a, const auto& b) {
    double r = 0;
    for (size_t c = 0; c < a.size(); ++c) r += a[c] * b[c];
    return r;
  };
  auto distance = [](const auto& a, const auto& b) {
    double r = 0;
    for (size_t c = 0; c < a.size(); ++c) r += (a[c] - b[c]) * (a[c] - b[c]);
    return std::sqrt(r);
  };
  const size_t nm = master.size();
  std::vector<double> spacing(nm, std::numeric_limits<double>::infinity());
  for (size_t i = 0; i < nm; ++i)
    for (const size_t off : {size_t{1}, row})
      for (const size_t j : {i + off, i >= off ? i - off : nm}) {
        if (j >= nm || j == i) continue;
        const double d = distance(master[i].x, master[j].x);
        if (d > 0) spacing[i] = std::min(spacing[i], d);
      }
  const size_t stride = std::max<size_t>(1, (slave.size() * nm) / 20000000 + 1);
  double deepest = 0;
  for (size_t is = 0; is < slave.size(); is += stride) {
    const S& s = slave[is];
    size_t k = nm;
    double dk = std::numeric_limits<double>::infinity();
    for (size_t j = 0; j < nm; ++j) {
      if (dotn(s.n, master[j].n) >= -0.5) continue;
      const double d = distance(s.x, master[j].x);
      if (d < dk) { dk = d; k = j; }
    }
    if (k == nm) continue;
    auto diff = master[k].x;
    for (size_t c = 0; c < diff.size(); ++c) diff[c] -= s.x[c];
    const double along = dotn(diff, s.n);
    const double lateral = std::sqrt(std::max(0.0, dk * dk - along * along));
    if (lateral > 1.5 * spacing[k]) continue;
    const double depth = std::min(-along, dotn(diff, master[k].n));
    deepest = std::max(deepest, depth);
  }
  return deepest;
}

// The facing test of a pair from its sides' samples (curves or faces, `word` "side" or "face"):
// "" when some slave point has the master in front of it (d half the slave body's smallest
// extent), else the refusal: the overlap where the slave side lies inside the master deeper
// than d, or the sides face away (naming the slave body's sides that do face it,
// facing_sides()). Where they face, *warning gets the initial overlap's line (deeper than 1e-8
// of that extent). Two sides of one body have its own material between them: no overlap.
// Where none of the slave body's sides faces the master but some of the master body's sides
// face the slave side (master_facing()), the master side is the one at fault: the line says so,
// names those, and *master_at_fault is set (the caller then names the key contact[k].master).
template <class S, class FacingSides, class MasterFacing>
std::string facing_and_overlap(const Problem& P, const ContactPair& c, const std::vector<S>& slave,
                               const std::vector<S>& master, size_t row, double extent, const char* word,
                               const FacingSides& facing_sides, const MasterFacing& master_facing,
                               std::string* warning, bool* master_at_fault) {
  const Body& sb = P.bodies[c.slave.body];
  const std::string master_side = P.bodies[c.master.body].name + "." + c.master.label;
  const bool self = c.master.body == c.slave.body;
  const double d = 0.5 * extent;
  if (slave.empty() || master.empty() || faces(slave, master, d)) {
    const double overlap = self || slave.empty() || master.empty() || !warning ? 0.0 : overlap_depth(slave, master, row);
    if (overlap > 1e-8 * extent)
      *warning = "the slave " + sb.name + "." + c.slave.label + " starts up to " + check_number(overlap) +
                 " inside the master " + master_side +
                 " (an initial overlap: the first load step pushes the bodies apart, as in an interference fit; if that is "
                 "not meant, check the bodies' positions)";
    return "";
  }
  const double overlap = self ? 0.0 : overlap_depth(slave, master, row);
  if (overlap > 0)
    return std::string("the slave ") + word + " starts up to " + check_number(overlap) + " inside the master " + master_side +
           ": the bodies overlap in the problem file by more than half the slave body's smallest extent (" + check_number(d) +
           "), so no slave point has the master in front of it; check the bodies' positions";
  const std::string facing = facing_sides();
  if (facing.empty()) {
    const std::string other = master_facing();
    if (!other.empty()) {
      if (master_at_fault) *master_at_fault = true;
      return std::string("the master ") + word + " " + master_side + " faces away from the slave " + sb.name + "." +
             c.slave.label + ": no slave point has the master in front of it with opposite outward normals, so they can "
             "never touch (" + word + "s of " + P.bodies[c.master.body].name + " that face the slave: " + other + ")";
    }
  }
  return std::string("the slave ") + word + " faces away from the master " + master_side +
         ": no slave point has the master in front of it with opposite outward normals, so they can never touch" +
         (facing.empty() ? std::string("") : " (" + std::string(word) + "s of " + sb.name + " that face it: " + facing + ")");
}

}  // namespace

std::string check_pair_facing(const Problem& P, const ContactPair& c, std::string* overlap_warning,
                              bool* master_at_fault) {
  if (master_at_fault) *master_at_fault = false;
  const Body& sb = P.bodies[c.slave.body];
  const Body& mb = P.bodies[c.master.body];
  // the other sides of a body (the slave's facing the master, the master's facing the slave)
  // for the refusal's line; on one body (self-contact) not the pair's own sides
  auto other_side = [&](const PatchSide& ps, const std::vector<PatchSide>& own) {
    return std::find(own.begin(), own.end(), ps) == own.end() &&
           !(c.master.body == c.slave.body &&
             std::find(c.master.sides.begin(), c.master.sides.end(), ps) != c.master.sides.end());
  };
  auto add = [](std::string& list, const Body& b, const PatchSide& ps) {
    list += (list.empty() ? "" : ", ") + b.side_label(ps.patch, ps.side);
  };
  // the sides of body b (other than own) for which test(samples of the side) holds
  auto sides_where = [&](const Body& b, const std::vector<PatchSide>& own, const auto& samples, const auto& test) {
    std::string list;
    for (const PatchSide& ps : outer_sides(b)) {
      if (!other_side(ps, own)) continue;
      try {
        if (test(samples(b, ps))) add(list, b, ps);
      } catch (const std::exception&) {
      }
    }
    return list;
  };
  // one pass for curves (2-D: 4 samples per element) and faces (3-D: 3 x 3 per element, a
  // row of 3 in the grid), side_samples(body, side) sampling one side
  auto check = [&](const auto& master, const auto& slave, const auto& side_samples, size_t row, double extent,
                   const char* word) {
    const double d = 0.5 * extent;
    return facing_and_overlap(
        P, c, slave, master, row, extent, word,
        [&] { return sides_where(sb, c.slave.sides, side_samples, [&](const auto& s) { return faces(s, master, d); }); },
        [&] { return sides_where(mb, c.master.sides, side_samples, [&](const auto& m) { return faces(slave, m, d); }); },
        overlap_warning, master_at_fault);
  };
  if (P.dim() == 3)
    return check(sample_faces(mb, c.master.sides, 1), sample_faces(sb, c.slave.sides, 1),
                 [](const Body& b, const PatchSide& ps) { return sample_faces(b, {ps}, 1); }, 3, smallest_extent3(sb),
                 "face");
  return check(sample_chain(surface_chain(P, c.master), 4), sample_chain(surface_chain(P, c.slave), 4),
               [](const Body& b, const PatchSide& ps) { return sample_chain(make_chain(b.patches, {ps}, b.tolerance), 4); },
               1, smallest_extent(sb), "side");
}

double smallest_element_size(const Patch& F) {
  double h = std::numeric_limits<double>::infinity();
  for (int s1 : F.element_spans(1))
    for (int s0 : F.element_spans(0)) {
      const double c[4][2] = {{F.knots[0][s0], F.knots[1][s1]}, {F.knots[0][s0 + 1], F.knots[1][s1]},
                              {F.knots[0][s0], F.knots[1][s1 + 1]}, {F.knots[0][s0 + 1], F.knots[1][s1 + 1]}};
      std::array<double, kMaxDim> x[4];
      for (int k = 0; k < 4; ++k) x[k] = F.point(c[k]);
      auto d = [&](int i, int j) { return std::sqrt(dot({x[i][0] - x[j][0], x[i][1] - x[j][1], x[i][2] - x[j][2]},
                                                        {x[i][0] - x[j][0], x[i][1] - x[j][1], x[i][2] - x[j][2]})); };
      const double size = std::max(std::max(d(0, 1), d(2, 3)), std::max(d(0, 2), d(1, 3)));
      if (size > 0) h = std::min(h, size);
    }
  return h;
}

double penalty_ratio(const Problem& P, const ContactPair& c, double* E_out, double* h_out) {
  const double E = std::min(P.bodies[c.slave.body].E, P.bodies[c.master.body].E);
  if (P.dim() == 3) {
    double h = std::numeric_limits<double>::infinity();
    for (const PatchSide& ps : c.slave.sides)
      h = std::min(h, smallest_element_size(P.bodies[c.slave.body].patches[ps.patch].face(ps.side)));
    if (E_out) *E_out = E;
    if (h_out) *h_out = h;
    return std::isfinite(h) && E > 0 ? c.penalty / (E / h) : 0.0;
  }
  const SurfaceChain ch = surface_chain(P, c.slave);
  double h = std::numeric_limits<double>::infinity();
  for (const int s : ch.curve.element_spans()) {
    double len = 0;
    Vec prev = ch.curve.eval(ch.curve.knots[s]);
    for (int i = 1; i <= 8; ++i) {
      const Vec q = ch.curve.eval(ch.curve.knots[s] + (ch.curve.knots[s + 1] - ch.curve.knots[s]) * i / 8.0);
      len += dist(prev, q);
      prev = q;
    }
    if (len > 0) h = std::min(h, len);
  }
  if (E_out) *E_out = E;
  if (h_out) *h_out = h;
  return std::isfinite(h) && E > 0 ? c.penalty / (E / h) : 0.0;
}

std::string penalty_warning(const Problem& P, int k) {
  const ContactPair& c = P.contact[k];
  double E = 0, h = 0;
  const double ratio = penalty_ratio(P, c, &E, &h);
  if (!(ratio > kPenaltyRatioWarning)) return "";
  return "contact[" + std::to_string(k) + "].penalty = " + check_number(c.penalty) + " is " + check_number(ratio) +
         " x E/h (E = " + check_number(E) + ", the smaller Young's modulus; h = " + check_number(h) +
         ", the smallest slave element): above about " + check_number(kPenaltyRatioWarning) +
         " E/h round-off in the gaps and the tangent's conditioning make the pressure unreliable; take 1-100 E/h, "
         "and an _alm method where the gaps must close further";
}

// ------------------------------------------------------------------ penetration

namespace {


struct Polyline {    // one outer side, deformed, with its reference points
  std::vector<Vec> x, X;
  int body, patch;
  Side side;
  std::vector<double> s, h;   // per point: reference arc length from the start, its element's length
  std::array<std::vector<std::pair<int, int>>, 2> joined;   // per end: (line, end) meeting it
};

// The boundary near a point along the boundary itself (not across a gap): points of the same
// side within arc length r, or of a side joined at an end, within r through that end.
struct Boundary {
  std::vector<Polyline> lines;
  void join(double tol) {
    for (size_t l = 0; l < lines.size(); ++l)
      for (int e = 0; e < 2; ++e) {
        const Vec& p = e ? lines[l].X.back() : lines[l].X.front();
        for (size_t m = 0; m < lines.size(); ++m)
          if (m != l && lines[m].body == lines[l].body)
            for (int f = 0; f < 2; ++f)
              if (dist(p, f ? lines[m].X.back() : lines[m].X.front()) <= tol) lines[l].joined[e].push_back({static_cast<int>(m), f});
      }
  }
  double to_end(int l, double s, int e) const { return e ? lines[l].s.back() - s : s; }
  bool near(int l, double s, int m, double t, double r) const {
    if (l == m) return std::abs(s - t) < r;
    for (int e = 0; e < 2; ++e)
      for (const auto& [k, f] : lines[l].joined[e])
        if (k == m && to_end(l, s, e) + to_end(m, t, f) < r) return true;
    return false;
  }
};

// A deformed patch ready for point inversion: 2 x 2 points per element in bins.
struct Inverter {
  const Patch* ref = nullptr;
  Patch cur;
  double lo[2] = {0, 0}, hi[2] = {0, 0};   // bounding box of the deformed control points (contains the patch)
  struct Pt { Vec x, X; double u, v; };
  std::vector<Pt> pts;
  int nb[2] = {1, 1};
  double cell = 1;
  std::vector<std::vector<int>> bins;

  void build() {
    lo[0] = lo[1] = 1e300; hi[0] = hi[1] = -1e300;
    for (const ControlPoint& q : cur.cp)
      for (int d = 0; d < 2; ++d) { lo[d] = std::min(lo[d], q.x[d]); hi[d] = std::max(hi[d], q.x[d]); }
    const auto s0 = cur.element_spans(0), s1 = cur.element_spans(1);
    for (const int j : s1)
      for (int b = 0; b < 2; ++b)
        for (const int i : s0)
          for (int a = 0; a < 2; ++a) {
            const double u = cur.knots[0][i] + (a + 0.5) / 2 * (cur.knots[0][i + 1] - cur.knots[0][i]);
            const double v = cur.knots[1][j] + (b + 0.5) / 2 * (cur.knots[1][j + 1] - cur.knots[1][j]);
            pts.push_back({cur.eval(u, v), ref->eval(u, v), u, v});
          }
    const double w = std::max(hi[0] - lo[0], 1e-300), h = std::max(hi[1] - lo[1], 1e-300);
    cell = std::sqrt(w * h / std::max<size_t>(pts.size(), 1));
    cell = std::max({cell, w / 2048, h / 2048});
    nb[0] = std::max(1, static_cast<int>(std::ceil(w / cell)));
    nb[1] = std::max(1, static_cast<int>(std::ceil(h / cell)));
    bins.assign(static_cast<size_t>(nb[0]) * nb[1], {});
    for (size_t k = 0; k < pts.size(); ++k) bins[bin(pts[k].x)].push_back(static_cast<int>(k));
  }
  int cell_of(double x, int d) const {
    return std::clamp(static_cast<int>(std::floor((x - lo[d]) / cell)), 0, nb[d] - 1);
  }
  size_t bin(const Vec& x) const { return static_cast<size_t>(cell_of(x[0], 0)) + static_cast<size_t>(nb[0]) * cell_of(x[1], 1); }
  bool in_box(const Vec& x, double tol) const {
    return x[0] >= lo[0] - tol && x[0] <= hi[0] + tol && x[1] >= lo[1] - tol && x[1] <= hi[1] + tol;
  }
  // the k points nearest to x (deformed), nearest first
  std::vector<int> nearest(const Vec& x, size_t k) const {
    const int c0 = cell_of(x[0], 0), c1 = cell_of(x[1], 1);
    std::vector<std::pair<double, int>> best;   // sorted, at most k
    for (int r = 0; r <= std::max(nb[0], nb[1]); ++r) {
      if (best.size() == k && (r - 1) * cell > best.back().first) break;
      for (int j = c1 - r; j <= c1 + r; ++j)
        for (int i = c0 - r; i <= c0 + r; ++i) {
          if (i < 0 || j < 0 || i >= nb[0] || j >= nb[1]) continue;
          if (std::max(std::abs(i - c0), std::abs(j - c1)) != r) continue;
          for (const int q : bins[static_cast<size_t>(i) + static_cast<size_t>(nb[0]) * j]) {
            const double d = dist(pts[q].x, x);
            if (best.size() == k && d >= best.back().first) continue;
            best.insert(std::upper_bound(best.begin(), best.end(), std::make_pair(d, q)), {d, q});
            if (best.size() > k) best.pop_back();
          }
        }
    }
    std::vector<int> out;
    for (const auto& b : best) out.push_back(b.second);
    return out;
  }
  // Newton on cur(u, v) = x from (u, v); true when it converges to within tol
  bool invert(const Vec& x, double& u, double& v, double tol) const {
    const double a0 = cur.knots[0].front(), a1 = cur.knots[0].back();
    const double b0 = cur.knots[1].front(), b1 = cur.knots[1].back();
    for (int it = 0; it < 25; ++it) {
      const Vec p = cur.eval(u, v);
      const double rx = p[0] - x[0], ry = p[1] - x[1];
      if (std::hypot(rx, ry) <= tol) return true;
      const double hu = 1e-7 * (a1 - a0), hv = 1e-7 * (b1 - b0);
      const double up = std::min(u + hu, a1), um = std::max(u - hu, a0);
      const double vp = std::min(v + hv, b1), vm = std::max(v - hv, b0);
      const Vec pu = cur.eval(up, v), mu = cur.eval(um, v), pv = cur.eval(u, vp), mv = cur.eval(u, vm);
      const double J00 = (pu[0] - mu[0]) / (up - um), J10 = (pu[1] - mu[1]) / (up - um);
      const double J01 = (pv[0] - mv[0]) / (vp - vm), J11 = (pv[1] - mv[1]) / (vp - vm);
      const double det = J00 * J11 - J01 * J10;
      if (!(std::abs(det) > 0)) return false;
      double du = -(J11 * rx - J01 * ry) / det, dv = -(-J10 * rx + J00 * ry) / det;
      const double lim = std::max(std::abs(du) / (0.25 * (a1 - a0)), std::abs(dv) / (0.25 * (b1 - b0)));
      if (lim > 1) { du /= lim; dv /= lim; }
      const double un = std::clamp(u + du, a0, a1), vn = std::clamp(v + dv, b0, b1);
      if (un == u && vn == v) return false;   // pushed against the patch boundary: outside
      u = un; v = vn;
    }
    return false;
  }
};

double segment_distance(const Vec& p, const Vec& a, const Vec& b) {
  const double ex = b[0] - a[0], ey = b[1] - a[1], l2 = ex * ex + ey * ey;
  double t = l2 > 0 ? ((p[0] - a[0]) * ex + (p[1] - a[1]) * ey) / l2 : 0.0;
  t = std::clamp(t, 0.0, 1.0);
  return std::hypot(p[0] - a[0] - t * ex, p[1] - a[1] - t * ey);
}

}  // namespace

namespace {

double orient(const Vec& a, const Vec& b, const Vec& c) {
  return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}
// Whether the closed segments ab and cd meet: they cross, or one's end lies on the other
// (collinear segments that overlap too). Two bodies whose sides line up exactly (a cap as wide
// as the block it is pressed into, both held at x = 0) have boundaries that meet only so: no
// proper crossing anywhere, though the cap's bottom lies inside the block.
bool meet(const Vec& a, const Vec& b, const Vec& c, const Vec& d) {
  const double o1 = orient(a, b, c), o2 = orient(a, b, d), o3 = orient(c, d, a), o4 = orient(c, d, b);
  auto opposite = [](double x, double y) { return (x < 0 && y > 0) || (x > 0 && y < 0); };
  if (opposite(o1, o2) && opposite(o3, o4)) return true;
  // r on the segment pq, r collinear with it
  auto on = [](const Vec& p, const Vec& q, const Vec& r) {
    return std::min(p[0], q[0]) <= r[0] && r[0] <= std::max(p[0], q[0]) && std::min(p[1], q[1]) <= r[1] &&
           r[1] <= std::max(p[1], q[1]);
  };
  return (o1 == 0 && on(a, b, c)) || (o2 == 0 && on(a, b, d)) || (o3 == 0 && on(c, d, a)) || (o4 == 0 && on(c, d, b));
}

// Pairs of boundary polylines that meet (their segments cross or touch, `meet`): lines of two
// bodies, or of one body where the segments are not neighbours along the boundary
// (self-penetration; the crossing may lie close to a crease, as where an O-ring's slit closes). A locally injective
// map (no inverted element) whose boundary curves do not meet does not overlap itself, and
// two bodies whose boundaries do not meet do not overlap (unless one lies wholly inside the
// other: find_penetration tests one line of each body for that), so only the lines found here
// need the point-in-body tests.
std::vector<std::pair<int, int>> crossing_lines(const Boundary& bd) {
  const std::vector<Polyline>& lines = bd.lines;
  struct Seg { int line, i; };
  std::vector<Seg> segs;
  double lo[2] = {1e300, 1e300}, hi[2] = {-1e300, -1e300}, len = 0;
  for (size_t l = 0; l < lines.size(); ++l)
    for (size_t i = 0; i + 1 < lines[l].x.size(); ++i) {
      segs.push_back({static_cast<int>(l), static_cast<int>(i)});
      for (const Vec& p : {lines[l].x[i], lines[l].x[i + 1]})
        for (int d = 0; d < 2; ++d) { lo[d] = std::min(lo[d], p[d]); hi[d] = std::max(hi[d], p[d]); }
      len += dist(lines[l].x[i], lines[l].x[i + 1]);
    }
  std::vector<std::pair<int, int>> out;
  if (segs.empty()) return out;
  // about one segment per bin: cells of the mean segment length, or coarser where the
  // segments are few for the box they span
  const double area = (hi[0] - lo[0]) * (hi[1] - lo[1]);
  const double cell = std::max({len / segs.size(), std::sqrt(area / segs.size()), (hi[0] - lo[0]) / 4096,
                                (hi[1] - lo[1]) / 4096, 1e-300});
  const int n0 = static_cast<int>((hi[0] - lo[0]) / cell) + 1, n1 = static_cast<int>((hi[1] - lo[1]) / cell) + 1;
  std::vector<std::vector<int>> bins(static_cast<size_t>(n0) * n1);
  auto c = [&](double x, int d) { return std::clamp(static_cast<int>((x - lo[d]) / cell), 0, (d ? n1 : n0) - 1); };
  for (size_t k = 0; k < segs.size(); ++k) {
    const Vec& a = lines[segs[k].line].x[segs[k].i];
    const Vec& b = lines[segs[k].line].x[segs[k].i + 1];
    for (int j = c(std::min(a[1], b[1]), 1); j <= c(std::max(a[1], b[1]), 1); ++j)
      for (int i = c(std::min(a[0], b[0]), 0); i <= c(std::max(a[0], b[0]), 0); ++i)
        bins[static_cast<size_t>(i) + static_cast<size_t>(n0) * j].push_back(static_cast<int>(k));
  }
  std::vector<char> seen(lines.size() * lines.size(), 0);
  for (const auto& bin : bins)
    for (size_t p = 0; p < bin.size(); ++p)
      for (size_t q = p + 1; q < bin.size(); ++q) {
        const Seg& s = segs[bin[p]];
        const Seg& t = segs[bin[q]];
        const Polyline& A = lines[s.line];
        const Polyline& B = lines[t.line];
        char& mark = seen[static_cast<size_t>(s.line) * lines.size() + t.line];
        if (mark) continue;
        if (!meet(A.x[s.i], A.x[s.i + 1], B.x[t.i], B.x[t.i + 1])) continue;
        // one body: segments next to each other along the boundary (they share a point) do
        // not count; any other meeting means the boundary crosses or touches itself
        if (A.body == B.body &&
            bd.near(s.line, A.s[s.i], t.line, B.s[t.i], 1.01 * (A.s[s.i + 1] - A.s[s.i] + B.s[t.i + 1] - B.s[t.i])))
          continue;
        mark = 1;
        seen[static_cast<size_t>(t.line) * lines.size() + s.line] = 1;
        out.push_back({s.line, t.line});
      }
  return out;
}

}  // namespace

void pair_allowances(const Problem& P, const std::vector<double>& pair_penetration, std::vector<double>& allowed,
                     std::vector<bool>& declared) {
  const size_t nb = P.bodies.size();
  allowed.assign(nb * nb, 0.0);
  declared.assign(nb * nb, false);
  for (size_t k = 0; k < P.contact.size(); ++k) {
    const size_t a = static_cast<size_t>(P.contact[k].slave.body), b = static_cast<size_t>(P.contact[k].master.body);
    const double pen = k < pair_penetration.size() ? std::max(0.0, pair_penetration[k]) : 0.0;
    for (const size_t i : {a * nb + b, b * nb + a}) {
      allowed[i] = std::max(allowed[i], 3.0 * pen);
      declared[i] = true;
    }
  }
}

std::string find_penetration(const Problem& P, const std::vector<std::vector<double>>& u,
                             const std::vector<double>& pair_penetration) {
  // solids: faces instead of curves (configuration_check3.cpp)
  if (P.dim() == 3) return find_penetration3(P, u, pair_penetration);
  const int nb = static_cast<int>(P.bodies.size());
  constexpr int kPer = 4;            // boundary points per element: kPer + 1 with its ends
  constexpr double kNear = 4.0;      // self: the boundary within 4 element sizes (along it) is the point's own
  constexpr size_t kStarts = 6;      // Newton starts in its own body: the nearest points of a patch
  constexpr double kFloor = 0.01;    // allowed depth at least 1 % of the boundary element
  Boundary bd;
  std::vector<std::vector<Inverter>> inv(nb);
  double L = 0;
  for (int b = 0; b < nb; ++b) {
    const Body& B = P.bodies[b];
    L = std::max(L, patches_diameter(B.patches));
    MultiPatch deformed = body_geometry(B, &u[b]);
    for (size_t k = 0; k < B.patches.size(); ++k) {
      Inverter I;
      I.ref = &B.patches[k];
      I.cur = std::move(deformed.patches[k]);
      inv[b].push_back(std::move(I));
    }
    for (const PatchSide& ps : outer_sides(B)) {
      const Curve cr = B.patches[ps.patch].side_curve(ps.side);
      const Curve cc = inv[b][ps.patch].cur.side_curve(ps.side);
      Polyline pl{{}, {}, b, ps.patch, ps.side, {}, {}, {}};
      for (const int sp : cr.element_spans()) {
        const double t0 = cr.knots[sp], t1 = cr.knots[sp + 1];
        for (int i = (pl.x.empty() ? 0 : 1); i <= kPer; ++i) {
          const double t = t0 + (t1 - t0) * i / kPer;
          const Vec X = cr.eval(t);
          pl.s.push_back(pl.X.empty() ? 0.0 : pl.s.back() + dist(pl.X.back(), X));
          pl.x.push_back(cc.eval(t));
          pl.X.push_back(X);
          pl.h.push_back(0);
        }
        // the element's length, for its points
        const size_t n = pl.s.size();
        const double he = pl.s[n - 1] - pl.s[n - 1 - kPer];
        for (size_t q = n - 1 - kPer; q < n; ++q) pl.h[q] = std::max(pl.h[q], he);
      }
      bd.lines.push_back(std::move(pl));
    }
  }
  bd.join(1e-9 * L);
  const std::vector<Polyline>& lines = bd.lines;
  // which lines to test against which bodies
  std::vector<std::vector<char>> test(lines.size(), std::vector<char>(static_cast<size_t>(nb), 0));
  std::vector<std::vector<int>> order(lines.size());   // per line: the lines it crosses first, then the rest
  for (const auto& [a, b] : crossing_lines(bd)) {
    test[a][lines[b].body] = 1;
    test[b][lines[a].body] = 1;
    order[a].push_back(b);
    order[b].push_back(a);
  }
  // a body wholly inside another (no boundary crossing): each body's first line tested
  // against every body none of its lines crosses
  for (int a = 0; a < nb; ++a) {
    int first = -1;
    for (size_t l = 0; l < lines.size() && first < 0; ++l)
      if (lines[l].body == a) first = static_cast<int>(l);
    if (first < 0) continue;
    for (int b = 0; b < nb; ++b) {
      if (b == a) continue;
      bool crosses = false;
      for (size_t l = 0; l < lines.size() && !crosses; ++l) crosses = lines[l].body == a && test[l][b];
      if (!crosses) test[static_cast<size_t>(first)][b] = 1;
    }
  }
  for (size_t l = 0; l < lines.size(); ++l)
    for (size_t m = 0; m < lines.size(); ++m)
      if (std::find(order[l].begin(), order[l].end(), static_cast<int>(m)) == order[l].end()) order[l].push_back(static_cast<int>(m));
  std::vector<char> built(static_cast<size_t>(nb), 0);
  std::vector<double> allowed;
  std::vector<bool> declared;
  pair_allowances(P, pair_penetration, allowed, declared);
  const double tol_x = 1e-10 * L;
  double worst = 0;
  std::string message;
  for (size_t l = 0; l < lines.size(); ++l) {
    const Polyline& S = lines[l];
    for (int b = 0; b < nb; ++b) {
      if (!test[l][b]) continue;
      if (!built[b]) {
        for (Inverter& I : inv[b]) I.build();
        built[b] = 1;
      }
      const bool self = b == S.body;
      for (size_t i = 0; i < S.x.size(); ++i) {
        // below 1 % of the point's boundary element the geometry of the discretisation
        // decides (a KTS slave's corner between its quadrature points)
        const double limit = std::max(kFloor * S.h[i], allowed[static_cast<size_t>(S.body) * nb + b]);
        const Vec& x = S.x[i];
        const Vec& X = S.X[i];
        // inside a patch of body b: a preimage of x there (self: not x's own reference point)
        bool inside = false;
        for (const Inverter& I : inv[b]) {
          if (inside || !I.in_box(x, tol_x)) continue;
          // another body: from the nearest point (a preimage is unique); its own body: from
          // several, since the nearest may lie on the point's own side of the fold
          for (const int k : I.nearest(x, self ? kStarts : 1)) {
            double uu = I.pts[k].u, vv = I.pts[k].v;
            if (!I.invert(x, uu, vv, tol_x)) continue;
            if (self && dist(I.ref->eval(uu, vv), X) <= 1e-6 * L) continue;   // its own place
            inside = true;
            break;
          }
        }
        if (!inside) continue;
        // depth: distance to the body's deformed boundary (self: away from the point, along the
        // boundary); the lines this one crosses first, no further once below what is reported
        double depth = 1e300;
        const Polyline* through = nullptr;
        const double enough = std::max(limit, worst);
        const double r = kNear * S.h[i];
        for (const int m : order[l]) {
          const Polyline& pl = lines[m];
          if (pl.body != b) continue;
          for (size_t j = 0; j + 1 < pl.x.size() && depth > enough; ++j) {
            if (self && bd.near(static_cast<int>(l), S.s[i], m, pl.s[j], r) && bd.near(static_cast<int>(l), S.s[i], m, pl.s[j + 1], r))
              continue;
            const double d = segment_distance(x, pl.x[j], pl.x[j + 1]);
            if (d < depth) { depth = d; through = &pl; }
          }
          if (depth <= enough) break;
        }
        if (!(depth > enough) || !through) continue;
        worst = depth;
        const Body& A = P.bodies[S.body];
        const Body& B = P.bodies[b];
        std::ostringstream os;
        if (self) {
          os << "self-penetration: " << A.name << "." << A.side_label(S.patch, S.side) << " passes " << check_number(depth)
             << " into its own body through " << A.name << "." << B.side_label(through->patch, through->side) << " at "
             << point(x);
          os << (declared[static_cast<size_t>(b) * nb + b]
                     ? "; its self-contact pairs allow " + check_number(limit)
                     : "; declare a contact pair between those two sides of " + A.name + " (self-contact)");
        } else {
          os << "interpenetration: " << A.name << "." << A.side_label(S.patch, S.side) << " is " << check_number(depth)
             << " inside " << B.name << " (below " << B.name << "." << B.side_label(through->patch, through->side)
             << ") at " << point(x);
          os << (declared[static_cast<size_t>(S.body) * nb + b]
                     ? "; the contact pairs between them allow " + check_number(limit) + " (3 x their penalty penetration)"
                     : "; no contact pair is declared between " + A.name + " and " + B.name);
        }
        message = os.str();
      }
    }
  }
  return message;
}

std::string find_inverted(const Problem& P, const std::vector<std::vector<double>>& u) {
  for (size_t b = 0; b < P.bodies.size(); ++b) {
    const Body& B = P.bodies[b];
    const MultiPatch deformed = body_geometry(B, &u[b]);
    for (size_t k = 0; k < B.patches.size(); ++k) {
      const Patch& cur = deformed.patches[k];
      bool finite = true;
      for (const ControlPoint& q : cur.cp) finite = finite && std::isfinite(q.x[0]) && std::isfinite(q.x[1]) && std::isfinite(q.x[2]);
      const std::string where = "body " + B.name + (B.multipatch() ? " patch " + std::to_string(k) : std::string());
      if (!finite) return "inverted elements: " + where + " has a displacement that is not a number";
      // det F = det(dx/dxi) / det(dX/dxi): det(dx/dxi) must keep the reference sign everywhere
      const std::string why = check_jacobian(cur, B.patches[k].orientation());
      if (!why.empty()) return "inverted elements (det F <= 0) in the deformed " + where + ": " + why;
    }
  }
  return "";
}

}  // namespace iga
