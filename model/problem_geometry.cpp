// Problem file: bodies (material, geometry: inline NURBS, generators, geometry files;
// interfaces, refinement, the boundary block) and their geometry after the read.
#include "model/yaml_reader.hpp"
#include "model/geometry_check.hpp"
#include "model/geometry_file.hpp"
#include "kernels/numbering.hpp"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <cmath>
#include <filesystem>
#include <functional>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <sstream>

namespace iga {

std::string Body::side_label(int patch, Side s) const {
  return multipatch() ? patch_side_name({patch, s}) : std::string(side_name(s));
}

bool Body::is_interface(const PatchSide& s) const {
  for (const Interface& f : interfaces)
    if (f.a == s || f.b == s) return true;
  return false;
}

std::string Body::corner_label(int patch, Corner c) const {
  return (multipatch() ? "patch" + std::to_string(patch) + "." : std::string()) + corner_name(c);
}

std::vector<double> Body::patch_values(int patch, const std::vector<double>& u) const {
  const auto& idx = cp_index[patch];
  const int D = dim();
  std::vector<double> v(D * idx.size());
  for (size_t a = 0; a < idx.size(); ++a)
    for (int c = 0; c < D; ++c) v[dof_of(a, c, D)] = u[dof_of(static_cast<size_t>(idx[a]), c, D)];
  return v;
}

MultiPatch body_geometry(const Body& b, const std::vector<double>* u) {
  MultiPatch mp;
  mp.patches = b.patches;
  mp.interfaces = b.interfaces;
  mp.named = b.named;
  for (size_t k = 0; k < b.patches.size(); ++k) {
    for (int s = 0; s < num_sides(b.patches[k].dim()); ++s) {
      const PatchSide ps{static_cast<int>(k), static_cast<Side>(s)};
      if (!b.is_interface(ps)) mp.boundary.push_back(ps);
    }
    if (u) {
      const std::vector<double> uk = b.patch_values(static_cast<int>(k), *u);
      for (size_t a = 0; a < b.patches[k].cp.size(); ++a)
        for (int c = 0; c < b.dim(); ++c) mp.patches[k].cp[a].x[c] += uk[dof_of(a, c, b.dim())];
    }
  }
  return mp;
}


namespace detail {

// Number of distinct values of a knot vector.
int distinct_knots(const std::vector<double>& U) {
  int k = 0;
  for (size_t i = 0; i < U.size(); ++i) k += (i == 0 || U[i] != U[i - 1]) ? 1 : 0;
  return k;
}

Patch read_nurbs(const Reader& R, const YAML::Node& n, const std::string& path) {
  R.keys(n, path, {"degree", "knots", "control_points"});
  const int D = R.dim;
  Patch P;
  P.pdim = D;
  if (!n["degree"]) R.missing(path + ".degree");
  if (!n["knots"]) R.missing(path + ".knots");
  if (!n["control_points"]) R.missing(path + ".control_points");
  const YAML::Node deg = n["degree"];
  if (!deg.IsSequence() || static_cast<int>(deg.size()) != D)
    R.fail(path + ".degree", deg, D == 3 ? "expected [p_xi, p_eta, p_zeta]" : "expected [p_xi, p_eta]");
  for (int d = 0; d < D; ++d) P.degree[d] = R.integer(deg[d], path + ".degree[" + std::to_string(d) + "]");
  const YAML::Node kn = n["knots"];
  if (!kn.IsSequence() || static_cast<int>(kn.size()) != D)
    R.fail(path + ".knots", kn, D == 3 ? "expected three knot vectors [[...], [...], [...]]" : "expected two knot vectors [[...], [...]]");
  for (int d = 0; d < D; ++d) P.knots[d] = R.numbers(kn[d], path + ".knots[" + std::to_string(d) + "]");
  const YAML::Node cps = n["control_points"];
  const char* form = D == 3 ? "[x, y, z, w]" : "[x, y, w]";
  if (!cps.IsSequence()) R.fail(path + ".control_points", cps, std::string("expected a list of ") + form);
  for (size_t a = 0; a < cps.size(); ++a) {
    const std::string key = path + ".control_points[" + std::to_string(a) + "]";
    if (!cps[a].IsSequence() || (static_cast<int>(cps[a].size()) != D + 1 && static_cast<int>(cps[a].size()) != D))
      R.fail(key, cps[a], std::string("expected ") + form);
    const auto v = R.lengths(cps[a], key);
    ControlPoint c;
    for (int d = 0; d < D; ++d) c.x[d] = v[d];
    c.w = static_cast<int>(v.size()) == D + 1 ? v[D] : 1.0;
    P.cp.push_back(c);
  }
  for (int d = 0; d < D; ++d)
    if (P.degree[d] < 1 || P.degree[d] > 5)
      R.fail(path + ".degree[" + std::to_string(d) + "]", deg[d], "degree must be 1..5");
  const std::string err = P.validate();
  if (!err.empty()) {
    // name the most specific key the message is about
    std::string key = path;
    YAML::Node at = n;
    if (err.rfind("knots[", 0) == 0 && err.size() > 7 && err[6] >= '0' && err[6] < '0' + D) {
      const int d = err[6] - '0';
      key += ".knots[" + std::to_string(d) + "]"; at = kn[d];
    }
    else if (err.rfind("control_points[", 0) == 0) {
      const size_t a = std::stoul(err.substr(15));
      key += ".control_points[" + std::to_string(a) + "]"; at = cps[a];
    } else if (err.rfind("control_points", 0) == 0) {
      key += ".control_points"; 
      throw InputError(printable(R.file + ":" + std::to_string(cps.Mark().line + 1) + ": " + key + ": " + err));
    }
    R.fail(key, at, err);
  }
  return P;
}

Patch make_rectangle(const Reader& R, const YAML::Node& n, const std::string& path) {
  R.keys(n, path, {"origin", "size"});
  if (!n["origin"]) R.missing(path + ".origin");
  if (!n["size"]) R.missing(path + ".size");
  const auto o = R.lengths(n["origin"], path + ".origin", 2);
  const auto s = R.lengths(n["size"], path + ".size", 2);
  for (int d = 0; d < 2; ++d)
    if (!(s[d] > 0)) R.fail(path + ".size", n["size"], "both sizes must be > 0");
  Patch P;
  P.degree = {1, 1};
  P.knots = {uniform_open_knots(1, 1), uniform_open_knots(1, 1)};
  P.cp = {ControlPoint{{o[0], o[1]}, 1}, ControlPoint{{o[0] + s[0], o[1]}, 1}, ControlPoint{{o[0], o[1] + s[1]}, 1},
          ControlPoint{{o[0] + s[0], o[1] + s[1]}, 1}};
  return P;
}

// A box [origin, origin + size] as one trilinear patch (3-D).
Patch make_box(const Reader& R, const YAML::Node& n, const std::string& path) {
  R.keys(n, path, {"origin", "size"});
  if (!n["origin"]) R.missing(path + ".origin");
  if (!n["size"]) R.missing(path + ".size");
  const auto o = R.lengths(n["origin"], path + ".origin", 3);
  const auto s = R.lengths(n["size"], path + ".size", 3);
  for (int d = 0; d < 3; ++d)
    if (!(s[d] > 0)) R.fail(path + ".size", n["size"], "all three sizes must be > 0");
  Patch P;
  P.pdim = 3;
  P.degree = {1, 1, 1};
  P.knots = {uniform_open_knots(1, 1), uniform_open_knots(1, 1), uniform_open_knots(1, 1)};
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 2; ++i) P.cp.push_back(ControlPoint{{o[0] + i * s[0], o[1] + j * s[1], o[2] + k * s[2]}, 1});
  return P;
}

Patch make_quarter_annulus(const Reader& R, const YAML::Node& n, const std::string& path) {
  R.keys(n, path, {"center", "inner_radius", "outer_radius", "start_angle"});
  for (const char* k : {"center", "inner_radius", "outer_radius"})
    if (!n[k]) R.missing(path + "." + k);
  const auto c = R.lengths(n["center"], path + ".center", 2);
  const double ri = R.length(n["inner_radius"], path + ".inner_radius");
  const double ro = R.length(n["outer_radius"], path + ".outer_radius");
  if (!(ro > ri)) R.fail(path + ".outer_radius", n["outer_radius"], "must be > inner_radius");
  const double a0 = n["start_angle"] ? R.number(n["start_angle"], path + ".start_angle") : 0.0;
  const double th = a0 * M_PI / 180.0, cs = std::cos(th), sn = std::sin(th);
  Patch P;
  P.degree = {2, 1};
  P.knots = {uniform_open_knots(2, 1), uniform_open_knots(1, 1)};
  const double w = std::sqrt(0.5);
  for (double r : {ri, ro}) {
    const double loc[3][2] = {{r, 0}, {r, r}, {0, r}};
    const double wt[3] = {1, w, 1};
    for (int k = 0; k < 3; ++k)
      P.cp.push_back(ControlPoint{{c[0] + cs * loc[k][0] - sn * loc[k][1], c[1] + sn * loc[k][0] + cs * loc[k][1]}, wt[k]});
  }
  return P;
}

Body read_body(const Reader& R, const YAML::Node& n, const std::string& path) {
  R.keys(n, path, {"name", "material", "geometry", "refine", "boundary"});
  Body b;
  if (!n["name"]) R.missing(path + ".name");
  b.name = R.string(n["name"], path + ".name");
  if (b.name.empty()) R.fail(path + ".name", n["name"], "must not be empty");
  // names become HDF5 groups, XML attributes and file names: keep them plain
  bool plain = b.name.size() <= 64 && (std::isalnum(static_cast<unsigned char>(b.name[0])) || b.name[0] == '_');
  for (const char c : b.name) plain = plain && (std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.');
  if (!plain)
    R.fail(path + ".name", n["name"],
           "a body name is 1..64 letters, digits, '_', '-' or '.', starting with a letter, digit or '_'");
  if (!n["material"]) R.missing(path + ".material");
  const YAML::Node m = n["material"];
  R.keys(m, path + ".material", {"model", "youngs_modulus", "poisson_ratio"});
  if (m["model"]) {
    const std::string t = R.string(m["model"], path + ".material.model");
    if (t == "linear") b.model = MaterialModel::Linear;
    else if (t == "saint_venant_kirchhoff") b.model = MaterialModel::SaintVenantKirchhoff;
    else if (t == "neo_hookean") b.model = MaterialModel::NeoHookean;
    else R.fail(path + ".material.model", m["model"], "expected linear, saint_venant_kirchhoff or neo_hookean");
  }
  if (!m["youngs_modulus"]) R.missing(path + ".material.youngs_modulus");
  if (!m["poisson_ratio"]) R.missing(path + ".material.poisson_ratio");
  b.E = R.number(m["youngs_modulus"], path + ".material.youngs_modulus");
  if (!(b.E > 0)) R.fail(path + ".material.youngs_modulus", m["youngs_modulus"], "must be > 0");
  b.nu = R.number(m["poisson_ratio"], path + ".material.poisson_ratio");
  if (!(b.nu > -1.0 && b.nu < 0.5))
    R.fail(path + ".material.poisson_ratio", m["poisson_ratio"], "must lie in (-1, 0.5)");

  if (!n["geometry"]) R.missing(path + ".geometry");
  const YAML::Node g = n["geometry"];
  R.keys(g, path + ".geometry", {"nurbs", "rectangle", "quarter_annulus", "box", "file", "patches"});
  if (g.size() != 1)
    R.fail(path + ".geometry", g, R.dim == 3 ? "give exactly one of nurbs, patches, box, file"
                                             : "give exactly one of nurbs, patches, rectangle, quarter_annulus, file");
  for (const char* two : {"rectangle", "quarter_annulus"})
    if (g[two] && R.dim == 3)
      R.fail(path + ".geometry." + two, g[two], std::string(two) + " is a 2-D geometry; a solid (analysis.type: solid) takes box, nurbs, patches or file");
  if (g["box"] && R.dim != 3)
    R.fail(path + ".geometry.box", g["box"], "box is a 3-D geometry (analysis.type: solid); in 2-D use rectangle");
  std::vector<Interface> declared;
  if (g["nurbs"]) b.patches = {read_nurbs(R, g["nurbs"], path + ".geometry.nurbs")};
  else if (g["patches"]) {
    // several patches listed inline, each as `nurbs`; interfaces are found by coincidence
    const YAML::Node ps = g["patches"];
    if (!ps.IsSequence() || ps.size() == 0) R.fail(path + ".geometry.patches", ps, "expected a list of patches {degree, knots, control_points}");
    for (size_t k = 0; k < ps.size(); ++k) b.patches.push_back(read_nurbs(R, ps[k], path + ".geometry.patches[" + std::to_string(k) + "]"));
  }
  else if (g["rectangle"]) b.patches = {make_rectangle(R, g["rectangle"], path + ".geometry.rectangle")};
  else if (g["quarter_annulus"]) b.patches = {make_quarter_annulus(R, g["quarter_annulus"], path + ".geometry.quarter_annulus")};
  else if (g["box"]) b.patches = {make_box(R, g["box"], path + ".geometry.box")};
  else {
    // a geometry file, relative to the problem file; its own errors name it and its line
    const std::string name = R.string(g["file"], path + ".geometry.file");
    namespace fs = std::filesystem;
    const fs::path gp = fs::path(name).is_absolute() ? fs::path(name) : fs::path(R.file).parent_path() / name;
    std::error_code ec;
    if (fs::is_directory(gp, ec)) R.fail(path + ".geometry.file", g["file"], gp.string() + " is a directory, not a geometry file");
    if (!fs::is_regular_file(gp, ec)) R.fail(path + ".geometry.file", g["file"], "cannot open the geometry file " + gp.string());
    MultiPatch mp = read_geometry_file(gp.string());
    if (mp.patches.empty()) R.fail(path + ".geometry.file", g["file"], "the geometry file holds no patch");
    for (size_t k = 0; k < mp.patches.size(); ++k) {
      if (mp.patches[k].dim() != R.dim)
        R.fail(path + ".geometry.file", g["file"], "patch " + std::to_string(k) + " is " + std::to_string(mp.patches[k].dim()) +
               "-D, the problem " + std::to_string(R.dim) + "-D (analysis.type: " + (R.dim == 3 ? "solid" : "plane_strain or plane_stress") + ")");
      for (int d = 0; d < R.dim; ++d)
        if (mp.patches[k].degree[d] > 5)
          R.fail(path + ".geometry.file", g["file"], "patch " + std::to_string(k) + " has degree " +
                 std::to_string(mp.patches[k].degree[d]) + " (1..5 are supported)");
    }
    b.patches = std::move(mp.patches);
    declared = std::move(mp.interfaces);
    b.named = std::move(mp.named);
  }
  const int np = static_cast<int>(b.patches.size());
  // interfaces: declared ones and those found on the unrefined patches (refinement keeps
  // conforming sides conforming only when both are refined alike: checked after it)
  b.tolerance = 1e-8 * std::max(patches_diameter(b.patches), 1e-300);
  {
    for (const Interface& f : declared) {
      const std::string err = check_interface(b.patches, f, b.tolerance);
      if (!err.empty()) R.fail(path + ".geometry.file", g["file"], "body '" + b.name + "': " + err);
      // 2-D: a declared direction the geometry contradicts (the geometry decides, so the
      // answer is right, but the file is inconsistent; found by a problem written from the
      // docs: a G+Smo orientation 0 and a GeoPDEs 1 on sides running the same way)
      if (!declared_orientation_holds(b.patches, f, b.tolerance)) {
        const std::string where = R.file + ": " + path + ".geometry.file: body '" + b.name + "': the interface " +
                                  patch_side_name(f.a) + " / " + patch_side_name(f.b) + " is declared ";
        if (b.patches[f.a.patch].dim() == 2) {
          const bool rev = geometric_reversal(b.patches, f);
          R.warnings.push_back(where + (f.reversed ? "reversed" : "in the same direction") + " but its sides run " +
                               (rev ? "opposite ways" : "the same way") + "; the geometry is used (check the file)");
        } else {
          // 3-D: the faces coincide in another of the 8 orientations (check_interface found one)
          R.warnings.push_back(where + "in an orientation in which its faces' control points do not coincide (face "
                               "directions " + std::to_string(f.face_map[0]) + " " + std::to_string(f.face_map[1]) +
                               ", flipped " + std::to_string(f.face_flip[0]) + " " + std::to_string(f.face_flip[1]) +
                               " in face " + patch_side_name(f.b) + "'s terms); the geometry is used (check the file)");
        }
      }
    }
    b.interfaces = declared;
    for (const Interface& f : find_interfaces(b.patches, b.tolerance)) {
      bool known = false;
      for (const Interface& d : declared) known = known || (d.a == f.a && d.b == f.b) || (d.a == f.b && d.b == f.a);
      if (!known) b.interfaces.push_back(f);
    }
    const std::string nc = find_nonconforming(b.patches, b.interfaces, b.tolerance);
    // (blamed on the file where one was given: a --set file was blamed on the problem file's
    // line of the geometry it replaced)
    if (!nc.empty()) {
      if (g["file"]) R.fail(path + ".geometry.file", g["file"], "body '" + b.name + "': " + nc);
      R.fail(path + ".geometry", g, "body '" + b.name + "': " + nc);
    }
  }

  if (n["refine"]) {
    const YAML::Node r = n["refine"];
    R.keys(r, path + ".refine", {"degree_elevate", "insert_knots", "subdivide"});
    // sizes after each refinement, checked before it is done (a refinement too large for
    // the machine is refused at once, not after minutes of knot insertion); every patch of
    // the body is refined alike
    const int D = R.dim;
    using Counts = std::array<double, 3>;
    using CountFn = std::function<Counts(const Patch&)>;
    auto totals = [&](const CountFn& ncp, const CountFn& el) {
      double dofs = 0, sample = 0;
      for (const Patch& q : b.patches) {
        const auto c = ncp(q);
        const auto e = el(q);
        double n = D;
        for (int d = 0; d < D; ++d) n *= c[d];
        dofs += n;
        sample += R.sample_bytes(e[0], e[1]);
      }
      return std::pair<double, double>(dofs, sample);
    };
    auto elements = [&](const Patch& q) {
      Counts e{1, 1, 1};
      for (int d = 0; d < D; ++d) e[d] = static_cast<double>(q.element_spans(d).size());
      return e;
    };
    auto max_degree = [&] {
      int m = 1;
      for (const Patch& q : b.patches)
        for (int d = 0; d < D; ++d) m = std::max(m, q.degree[d]);
      return m;
    };
    if (r["degree_elevate"]) {
      const auto e = D == 2 ? [&] { const auto v = R.int_pair(r["degree_elevate"], path + ".refine.degree_elevate"); return std::array<int, 3>{v[0], v[1], 0}; }()
                            : R.int_per_direction(r["degree_elevate"], path + ".refine.degree_elevate");
      for (const Patch& q : b.patches)
        for (int d = 0; d < D; ++d) {
          if (e[d] < 0) R.fail(path + ".refine.degree_elevate", r["degree_elevate"], "must be >= 0");
          if (q.degree[d] + e[d] > 5)
            R.fail(path + ".refine.degree_elevate", r["degree_elevate"],
                   "would raise degree " + std::to_string(q.degree[d]) + " above the supported 5");
        }
      const auto t = totals([&](const Patch& q) {
        Counts c{1, 1, 1};
        for (int d = 0; d < D; ++d) c[d] = static_cast<double>(q.ncp(d) + static_cast<long long>(e[d]) * (distinct_knots(q.knots[d]) - 1));
        return c;
      }, elements);
      R.fits(path + ".refine.degree_elevate", r["degree_elevate"], t.first, max_degree() + std::max({e[0], e[1], e[2]}), t.second, D);
      for (Patch& q : b.patches)
        for (int d = 0; d < D; ++d) q.elevate(d, e[d]);
    }
    if (r["insert_knots"]) {
      const YAML::Node ik = r["insert_knots"];
      const std::string key = path + ".refine.insert_knots";
      if (!ik.IsSequence() || static_cast<int>(ik.size()) != D)
        R.fail(key, ik, D == 3 ? "expected three lists [[xi knots], [eta knots], [zeta knots]] in [0, 1]"
                               : "expected two lists [[xi knots], [eta knots]] in [0, 1]");
      std::array<long long, 3> added{0, 0, 0};
      for (int d = 0; d < D; ++d) {
        if (ik[d].IsSequence() && ik[d].size() > kMaxInsertedKnots)
          R.fail(key + "[" + std::to_string(d) + "]", ik[d],
                 "at most " + std::to_string(kMaxInsertedKnots) + " knots per direction; use subdivide for uniform refinement");
        added[d] = ik[d].IsSequence() ? static_cast<long long>(ik[d].size()) : 0;
      }
      const auto t = totals([&](const Patch& q) {
                              Counts c{1, 1, 1};
                              for (int d = 0; d < D; ++d) c[d] = static_cast<double>(q.ncp(d) + added[d]);
                              return c;
                            },
                            [&](const Patch& q) {
                              auto e = elements(q);
                              for (int d = 0; d < D; ++d) e[d] += static_cast<double>(added[d]);
                              return e;
                            });
      R.fits(key, ik, t.first, max_degree(), t.second, D);
      for (int d = 0; d < D; ++d) {
        const auto ks = R.numbers(ik[d], key + "[" + std::to_string(d) + "]");
        for (Patch& q : b.patches) {
          const auto U = q.knots[d];
          for (double t : ks) {
            if (!(t > 0 && t < 1)) R.fail(key + "[" + std::to_string(d) + "]", ik[d], "knots must lie strictly inside (0, 1)");
            q.insert_knot(d, U.front() + t * (U.back() - U.front()));
          }
          const std::string err = q.validate();
          if (!err.empty()) R.fail(key + "[" + std::to_string(d) + "]", ik[d], err);
        }
      }
    }
    if (r["subdivide"]) {
      const auto s = D == 2 ? [&] { const auto v = R.int_pair(r["subdivide"], path + ".refine.subdivide"); return std::array<int, 3>{v[0], v[1], 1}; }()
                            : R.int_per_direction(r["subdivide"], path + ".refine.subdivide");
      for (int d = 0; d < D; ++d)
        if (s[d] < 1 || s[d] > 100000) R.fail(path + ".refine.subdivide", r["subdivide"], "must be 1..100000");
      const auto t = totals([&](const Patch& q) {
        Counts c{1, 1, 1};
        for (int d = 0; d < D; ++d) c[d] = static_cast<double>(q.ncp(d) + static_cast<long long>(s[d] - 1) * static_cast<long long>(q.element_spans(d).size()));
        return c;
      }, [&](const Patch& q) {
        auto e = elements(q);
        for (int d = 0; d < D; ++d) e[d] *= s[d];
        return e;
      });
      R.fits(path + ".refine.subdivide", r["subdivide"], t.first, max_degree(), t.second, D);
      for (Patch& q : b.patches)
        for (int d = 0; d < D; ++d) q.subdivide(d, s[d]);
    }
    for (const Interface& f : b.interfaces) {
      const std::string err = check_interface(b.patches, f, b.tolerance);
      if (!err.empty()) R.fail(path + ".refine", r, "body '" + b.name + "': " + err);
    }
  }
  b.cp_index = merge_control_points(b.patches, b.interfaces, b.num_cps, b.tolerance);
  // a folded or flat patch (det J changing sign or vanishing inside) is bad input, blamed on
  // the control points where they were given
  for (int k = 0; k < np; ++k) {
    const std::string bad = check_jacobian(b.patches[k]);
    if (bad.empty()) continue;
    const std::string who = "body '" + b.name + "'" + (np > 1 ? ", patch " + std::to_string(k) : std::string()) + ": ";
    if (g["nurbs"]) R.fail(path + ".geometry.nurbs.control_points", g["nurbs"]["control_points"], who + bad);
    if (g["patches"])
      R.fail(path + ".geometry.patches[" + std::to_string(k) + "].control_points", g["patches"][k]["control_points"], who + bad);
    R.fail(path + (g["file"] ? ".geometry.file" : ".geometry"), g["file"] ? g["file"] : g, who + bad);
  }
  b.sides.assign(np, {});
  b.corners.assign(np, {});
  if (n["boundary"]) {
    const YAML::Node bc = n["boundary"];
    if (!bc.IsMap()) R.fail(path + ".boundary", bc, "expected a mapping");
    std::map<std::string, std::string> given;   // side or corner -> the key that gave its condition
    for (const auto& kv : bc) {
      const std::string name = kv.first.as<std::string>(), key = path + ".boundary." + name;
      const auto where = boundary_places(R, b, name, key, kv.second);
      for (const auto& [ps, corner] : where) {
        SideCondition& sc = corner < 0 ? b.sides[ps.patch][static_cast<int>(ps.side)] : b.corners[ps.patch][corner];
        const std::string what = corner < 0 ? b.side_label(ps.patch, ps.side) : b.corner_label(ps.patch, static_cast<Corner>(corner));
        if (!sc.value.empty())
          R.fail(key, kv.second, what + (what == name ? "" : ", a side of " + name + ",") + " already has a condition (" + given[what] + ")");
        given[what] = key;
        read_side(R, kv.second, key, sc);
        if (corner >= 0 && sc.load != LoadKind::None)
          R.fail(key, kv.second, "a corner takes a displacement only (a point load is not supported)");
        if (corner < 0 && sc.load != LoadKind::None && b.is_interface(ps))
          R.fail(key, kv.second, patch_side_name(ps) + " is an interface between patches, inside the body: no load there");
      }
    }
  }
  auto zero_free = [&](SideCondition& sc) {   // free sides: zero values at every stage end
    if (!sc.value.empty()) return;
    sc.value.assign(R.stages, {0.0, 0.0, 0.0});
    sc.p0.assign(R.stages, 0.0);
    sc.p1.assign(R.stages, 0.0);
    sc.traction.assign(R.stages, {0.0, 0.0, 0.0});
  };
  for (int k = 0; k < np; ++k) {
    for (auto& sc : b.sides[k]) zero_free(sc);
    for (auto& sc : b.corners[k]) zero_free(sc);
  }
  return b;
}

}  // namespace detail

}  // namespace iga
