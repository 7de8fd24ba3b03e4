#include "model/problem.hpp"
#include "model/configuration_check.hpp"

#include <MueLu_MasterList.hpp>
#include <Teuchos_XMLParameterListHelpers.hpp>
#include <yaml-cpp/yaml.h>

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

#include "model/geometry_check.hpp"
#include "model/geometry_file.hpp"

namespace iga {

// auto: not for the direct solver (its factorisations are exact, and its GMRES on kept factors
// solves to the tolerance), and not with friction: the inexact steps of the wheel with mortar
// friction 0.3 sent points through slip on the way, and the step ended in a different stick
// state (tangential force 1.3e-4 apart, whatever Newton's tolerance), where every exact path
// ended in the same one.
bool eisenstat_walker_forcing(const Problem& P) {
  if (P.linear.forcing != Forcing::Auto) return P.linear.forcing == Forcing::EisenstatWalker;
  // a linear problem (small strain, no contact) is solved by one linear solve to the fixed
  // tolerance, after which Newton's residual check passes: inexact steps took 3 (issue 34)
  const bool linear = P.contact.empty() && P.kinematics == Kinematics::Small;
  return P.linear.method != LinearMethod::Direct && !P.has_friction() && !linear;
}

bool Problem::has_friction() const {
  return std::any_of(contact.begin(), contact.end(), [](const ContactPair& c) { return c.friction > 0; });
}

// solver.linear.method: auto takes MUMPS up to this many dofs and GMRES/CG + BoomerAMG above:
// where the two cost the same, measured per degree p (the highest of any patch) by
// benchmarks/auto_crossover.py (docs/performance.md, "auto by degree"). A linear problem (small
// strain, no contact) is one CG solve to the fixed tolerance, and there the factorisation stays
// ahead far longer, the more so at high degree (on the Lame cylinder MUMPS was ahead or even
// up to 6e4-2.4e5 dofs at p = 2, 1.2e5-2.4e5 at p = 3, 4, and past 2.4e5 at p = 5; a plate
// at p = 1: 6e4). A nonlinear one (contact, finite strain) is solved by GMRES with inexact
// Newton, which won on two blocks in contact from 1e4 dofs at p <= 3 and from 1.5e4-3e4 at
// p = 4, 5. With friction the Krylov solves keep the fixed tolerance and MUMPS was 2x faster
// at 55,272 dofs: kAutoDirectMaxDofsFriction.
long long Problem::auto_direct_max_dofs() const {
  if (has_friction()) return kAutoDirectMaxDofsFriction;
  int p = 1;
  for (const Body& b : bodies)
    for (const Patch& pt : b.patches) p = std::max(p, std::max(pt.degree[0], pt.degree[1]));
  const bool linear = contact.empty() && kinematics == Kinematics::Small;
  //                                                 p = 1      2       3       4       5
  static constexpr long long kMaxDofs[2][5] = {/* nonlinear */ {10000, 10000, 20000, 20000, 30000},
                                               /* linear */ {60000, 60000, 150000, 150000, 240000}};
  return kMaxDofs[linear ? 1 : 0][std::min(p, 5) - 1];
}

const char* linear_method_name(LinearMethod m) {
  switch (m) {
    case LinearMethod::CG: return "cg";
    case LinearMethod::GMRES: return "gmres";
    case LinearMethod::Direct: return "direct";
  }
  return "?";
}

const char* preconditioner_name(Preconditioner p) {
  switch (p) {
    case Preconditioner::MueLu: return "muelu";
    case Preconditioner::BoomerAMG: return "boomeramg";
    case Preconditioner::ILUT: return "ilut";
    case Preconditioner::Relaxation: return "relaxation";
    case Preconditioner::None: return "none";
  }
  return "?";
}

const char* contact_method_name(ContactMethod m) {
  switch (m) {
    case ContactMethod::KtsPenalty: return "kts_penalty";
    case ContactMethod::KtsAlm: return "kts_alm";
    case ContactMethod::MortarPenalty: return "mortar_penalty";
    case ContactMethod::MortarAlm: return "mortar_alm";
  }
  return "?";
}

const char* material_model_name(MaterialModel m) {
  switch (m) {
    case MaterialModel::Linear: return "linear";
    case MaterialModel::SaintVenantKirchhoff: return "saint_venant_kirchhoff";
    case MaterialModel::NeoHookean: return "neo_hookean";
  }
  return "?";
}

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
  std::vector<double> v(2 * idx.size());
  for (size_t a = 0; a < idx.size(); ++a) {
    v[2 * a] = u[2 * idx[a]];
    v[2 * a + 1] = u[2 * idx[a] + 1];
  }
  return v;
}

MultiPatch body_geometry(const Body& b, const std::vector<double>* u) {
  MultiPatch mp;
  mp.patches = b.patches;
  mp.interfaces = b.interfaces;
  mp.named = b.named;
  for (size_t k = 0; k < b.patches.size(); ++k) {
    for (int s = 0; s < 4; ++s) {
      const PatchSide ps{static_cast<int>(k), static_cast<Side>(s)};
      if (!b.is_interface(ps)) mp.boundary.push_back(ps);
    }
    if (u) {
      const std::vector<double> uk = b.patch_values(static_cast<int>(k), *u);
      for (size_t a = 0; a < b.patches[k].cp.size(); ++a)
        for (int c = 0; c < 2; ++c) mp.patches[k].cp[a][c] += uk[2 * a + c];
    }
  }
  return mp;
}

SurfaceChain surface_chain(const Problem& P, const ContactSurface& s) {
  const Body& b = P.bodies[s.body];
  return make_chain(b.patches, s.sides, b.tolerance);
}

int Problem::find_body(const std::string& name) const {
  for (size_t b = 0; b < bodies.size(); ++b)
    if (bodies[b].name == name) return static_cast<int>(b);
  return -1;
}

namespace {

// Messages stay one line whatever the input holds: control characters are escaped.
std::string printable(const std::string& s) {
  std::string out;
  for (const char c : s) {
    if (c == '\n') out += "\\n";
    else if (c == '\r') out += "\\r";
    else if (c == '\t') out += "\\t";
    else if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) out += '?';
    else out += c;
  }
  return out;
}

std::string one_line(const YAML::Node& n) {
  if (!n.IsDefined() || n.IsNull()) return "null";
  YAML::Emitter e;
  e.SetMapFormat(YAML::Flow);
  e.SetSeqFormat(YAML::Flow);
  e << n;
  std::string s = e.c_str();
  for (char& c : s)
    if (c == '\n') c = ' ';
  if (s.size() > 80) s = s.substr(0, 77) + "...";
  return s;
}

// A value given on the command line with --set KEY=VALUE: messages about it (or anything
// inside it) cite the --set argument, not a line of the file.
struct Override {
  std::string text;   // "KEY=VALUE" as given
  YAML::Node value;
};

bool contains_node(const YAML::Node& tree, const YAML::Node& n) {
  if (tree.is(n)) return true;
  if (tree.IsSequence() || tree.IsMap())
    for (const auto& it : tree) {
      if (tree.IsMap() ? (contains_node(it.first, n) || contains_node(it.second, n)) : contains_node(it, n)) return true;
    }
  return false;
}

// Reads one YAML node tree with the file name and key path at hand for messages.
struct Reader {
  std::string file;
  std::vector<Override> overrides;
  double memory_bytes = 0;   // what the machine has available (0: unknown, no size check)
  int samples_per_element = 4;   // output.samples_per_element, read before the bodies
  int stages = 1;                // analysis.stages, read before the bodies

  // output.samples_per_element: 1..64, or auto (0)
  int samples(const YAML::Node& n) const {
    if (n.IsScalar() && n.Scalar() == "auto") return 0;
    const int s = integer(n, "output.samples_per_element");
    if (s < 1 || s > 64) fail("output.samples_per_element", n, "must be 1..64 or auto");
    return s;
  }

  // Memory of the output sampling of ne0 x ne1 elements: a sampled point costs ~30 doubles
  // on rank 0 (fields, the HDF5 image, the VTK cells).
  double sample_bytes(double ne0, double ne1) const {
    return (samples_per_element * ne0 + 1) * (samples_per_element * ne1 + 1) * 240.0;
  }

  [[noreturn]] void fail(const std::string& key, const YAML::Node& n, const std::string& why) const {
    std::ostringstream os;
    os << file;
    const Override* from = nullptr;
    for (const auto& o : overrides)
      if (n.IsDefined() && contains_node(o.value, n)) from = &o;
    if (from) os << ": --set " << from->text;
    else if (n.IsDefined() && n.Mark().line >= 0) os << ":" << n.Mark().line + 1;
    os << ": " << key << " = " << one_line(n) << ": " << why;
    throw InputError(printable(os.str()));
  }
  [[noreturn]] void missing(const std::string& key) const {
    throw InputError(printable(file + ": " + key + ": required key is missing"));
  }

  void keys(const YAML::Node& n, const std::string& path, std::initializer_list<const char*> allowed) const {
    if (!n.IsMap()) fail(path, n, "expected a mapping");
    for (const auto& kv : n) {
      const std::string k = kv.first.as<std::string>();
      bool ok = false;
      for (const char* a : allowed) ok = ok || k == a;
      if (!ok) {
        std::string list;
        for (const char* a : allowed) list += std::string(list.empty() ? "" : ", ") + a;
        fail(path.empty() ? k : path + "." + k, kv.second, "unknown key (allowed here: " + list + ")");
      }
    }
  }

  double number(const YAML::Node& n, const std::string& key) const {
    if (!n.IsScalar()) fail(key, n, "expected a number");
    double v;
    try { v = n.as<double>(); } catch (const YAML::Exception&) { fail(key, n, "expected a number"); }
    if (!std::isfinite(v)) fail(key, n, "expected a finite number");
    return v;
  }
  int integer(const YAML::Node& n, const std::string& key) const {
    if (!n.IsScalar()) fail(key, n, "expected an integer");
    long v;
    try { v = n.as<long>(); } catch (const YAML::Exception&) { fail(key, n, "expected an integer"); }
    if (v < -1000000000L || v > 1000000000L) fail(key, n, "integer out of range");
    return static_cast<int>(v);
  }
  bool boolean(const YAML::Node& n, const std::string& key) const {
    if (!n.IsScalar()) fail(key, n, "expected true or false");
    bool v;
    try { v = n.as<bool>(); } catch (const YAML::Exception&) { fail(key, n, "expected true or false"); }
    return v;
  }
  std::string string(const YAML::Node& n, const std::string& key) const {
    if (!n.IsScalar()) fail(key, n, "expected a string");
    return n.as<std::string>();
  }
  std::vector<double> numbers(const YAML::Node& n, const std::string& key, int size = -1) const {
    if (!n.IsSequence()) fail(key, n, size > 0 ? "expected a list of " + std::to_string(size) + " numbers" : "expected a list of numbers");
    if (size >= 0 && static_cast<int>(n.size()) != size)
      fail(key, n, "expected a list of " + std::to_string(size) + " numbers");
    std::vector<double> v;
    for (size_t k = 0; k < n.size(); ++k) v.push_back(number(n[k], key + "[" + std::to_string(k) + "]"));
    return v;
  }
  // A prescribed value: a number (the same at the end of every stage) or a list with one
  // number per stage (analysis.stages).
  std::vector<double> staged(const YAML::Node& n, const std::string& key) const {
    if (n.IsSequence()) {
      if (static_cast<int>(n.size()) != stages)
        fail(key, n, "expected a number or a list of " + std::to_string(stages) + " numbers (one per stage)");
      std::vector<double> v;
      for (size_t k = 0; k < n.size(); ++k) v.push_back(number(n[k], key + "[" + std::to_string(k) + "]"));
      return v;
    }
    return std::vector<double>(stages, number(n, key));
  }
  // An int or a pair [a, b].
  std::array<int, 2> int_pair(const YAML::Node& n, const std::string& key) const {
    if (n.IsScalar()) { const int a = integer(n, key); return {a, a}; }
    if (!n.IsSequence() || n.size() != 2) fail(key, n, "expected an integer or a list of 2 integers");
    return {integer(n[0], key + "[0]"), integer(n[1], key + "[1]")};
  }
  double positive(const YAML::Node& n, const std::string& key) const {
    const double v = number(n, key);
    if (!(v > 0)) fail(key, n, "must be > 0");
    if (v < std::numeric_limits<double>::min())   // subnormal: products with it vanish
      fail(key, n, "is below the smallest normal number (2.2e-308); rescale the units");
    return v;
  }

  // Refuses a problem that will not fit the machine, before anything is built. The estimate
  // follows the measured 2575 bytes per dof of a degree-2 run (docs/performance.md), scaled
  // with the number of control points each one couples with, (2p + 1)^2.
  void fits(const std::string& key, const YAML::Node& n, double dofs, int degree, double extra_bytes = 0) const {
    const double coupled = (2.0 * degree + 1) * (2.0 * degree + 1);
    const double bytes = dofs * 103.0 * coupled + extra_bytes;
    if (dofs > kMaxDofs || (memory_bytes > 0 && bytes > memory_bytes)) {
      std::ostringstream os;
      os.precision(3);
      os << "the problem would have " << dofs << " dofs and need about " << bytes / 1e9
         << " GB of memory; this machine has " << memory_bytes / 1e9 << " GB available";
      if (dofs > kMaxDofs) os << " (and at most " << kMaxDofs << " dofs are supported)";
      if (extra_bytes > 0.5 * bytes) os << " (the output sampling alone: about " << extra_bytes / 1e9 << " GB)";
      fail(key, n, os.str());
    }
  }
};

// Duplicate keys in a mapping: YAML forbids them, yaml-cpp keeps the first silently.
void check_duplicate_keys(const Reader& R, const YAML::Node& n, const std::string& path) {
  if (n.IsMap()) {
    std::set<std::string> seen;
    for (const auto& kv : n) {
      const std::string k = kv.first.IsScalar() ? kv.first.Scalar() : one_line(kv.first);
      const std::string key = path.empty() ? k : path + "." + k;
      if (!seen.insert(k).second) R.fail(key, kv.second, "duplicate key (given more than once in this mapping)");
      check_duplicate_keys(R, kv.second, key);
    }
  } else if (n.IsSequence()) {
    for (size_t k = 0; k < n.size(); ++k) check_duplicate_keys(R, n[k], path + "[" + std::to_string(k) + "]");
  }
}

// Number of distinct values of a knot vector.
int distinct_knots(const std::vector<double>& U) {
  int k = 0;
  for (size_t i = 0; i < U.size(); ++i) k += (i == 0 || U[i] != U[i - 1]) ? 1 : 0;
  return k;
}

Patch read_nurbs(const Reader& R, const YAML::Node& n, const std::string& path) {
  R.keys(n, path, {"degree", "knots", "control_points"});
  Patch P;
  if (!n["degree"]) R.missing(path + ".degree");
  if (!n["knots"]) R.missing(path + ".knots");
  if (!n["control_points"]) R.missing(path + ".control_points");
  const YAML::Node deg = n["degree"];
  if (!deg.IsSequence() || deg.size() != 2) R.fail(path + ".degree", deg, "expected [p_xi, p_eta]");
  for (int d = 0; d < 2; ++d) P.degree[d] = R.integer(deg[d], path + ".degree[" + std::to_string(d) + "]");
  const YAML::Node kn = n["knots"];
  if (!kn.IsSequence() || kn.size() != 2) R.fail(path + ".knots", kn, "expected two knot vectors [[...], [...]]");
  for (int d = 0; d < 2; ++d) P.knots[d] = R.numbers(kn[d], path + ".knots[" + std::to_string(d) + "]");
  const YAML::Node cps = n["control_points"];
  if (!cps.IsSequence()) R.fail(path + ".control_points", cps, "expected a list of [x, y, w]");
  for (size_t a = 0; a < cps.size(); ++a) {
    const std::string key = path + ".control_points[" + std::to_string(a) + "]";
    if (!cps[a].IsSequence() || (cps[a].size() != 3 && cps[a].size() != 2))
      R.fail(key, cps[a], "expected [x, y, w]");
    const auto v = R.numbers(cps[a], key);
    P.cp.push_back({v[0], v[1], v.size() == 3 ? v[2] : 1.0});
  }
  for (int d = 0; d < 2; ++d)
    if (P.degree[d] < 1 || P.degree[d] > 5)
      R.fail(path + ".degree[" + std::to_string(d) + "]", deg[d], "degree must be 1..5");
  const std::string err = P.validate();
  if (!err.empty()) {
    // name the most specific key the message is about
    std::string key = path;
    YAML::Node at = n;
    if (err.rfind("knots[0]", 0) == 0) { key += ".knots[0]"; at = kn[0]; }
    else if (err.rfind("knots[1]", 0) == 0) { key += ".knots[1]"; at = kn[1]; }
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
  const auto o = R.numbers(n["origin"], path + ".origin", 2);
  const auto s = R.numbers(n["size"], path + ".size", 2);
  for (int d = 0; d < 2; ++d)
    if (!(s[d] > 0)) R.fail(path + ".size", n["size"], "both sizes must be > 0");
  Patch P;
  P.degree = {1, 1};
  P.knots = {uniform_open_knots(1, 1), uniform_open_knots(1, 1)};
  P.cp = {{o[0], o[1], 1}, {o[0] + s[0], o[1], 1}, {o[0], o[1] + s[1], 1}, {o[0] + s[0], o[1] + s[1], 1}};
  return P;
}

Patch make_quarter_annulus(const Reader& R, const YAML::Node& n, const std::string& path) {
  R.keys(n, path, {"center", "inner_radius", "outer_radius", "start_angle"});
  for (const char* k : {"center", "inner_radius", "outer_radius"})
    if (!n[k]) R.missing(path + "." + k);
  const auto c = R.numbers(n["center"], path + ".center", 2);
  const double ri = R.positive(n["inner_radius"], path + ".inner_radius");
  const double ro = R.positive(n["outer_radius"], path + ".outer_radius");
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
      P.cp.push_back({c[0] + cs * loc[k][0] - sn * loc[k][1], c[1] + sn * loc[k][0] + cs * loc[k][1], wt[k]});
  }
  return P;
}

void read_side(const Reader& R, const YAML::Node& n, const std::string& path, SideCondition& sc) {
  R.keys(n, path, {"displacement", "pressure", "traction"});
  const int K = R.stages;
  sc.value.assign(K, {0.0, 0.0});
  sc.p0.assign(K, 0.0);
  sc.p1.assign(K, 0.0);
  sc.traction.assign(K, {0.0, 0.0});
  if (n["displacement"]) {
    const YAML::Node d = n["displacement"];
    R.keys(d, path + ".displacement", {"x", "y"});
    if (d.size() == 0) R.fail(path + ".displacement", d, "prescribe x, y or both");
    for (int c = 0; c < 2; ++c) {
      const char* k = c == 0 ? "x" : "y";
      if (d[k]) {
        sc.fixed[c] = true;
        const auto v = R.staged(d[k], path + ".displacement." + k);
        for (int s = 0; s < K; ++s) sc.value[s][c] = v[s];
      }
    }
  }
  const int nloads = (n["pressure"] ? 1 : 0) + (n["traction"] ? 1 : 0);
  if (nloads > 1) R.fail(path, n, "give either pressure or traction on a side, not both");
  if (n["pressure"]) {
    const YAML::Node p = n["pressure"];
    if (p.IsMap()) {
      R.keys(p, path + ".pressure", {"linear"});
      if (!p["linear"]) R.missing(path + ".pressure.linear");
      const YAML::Node l = p["linear"];
      if (!l.IsSequence() || l.size() != 2) R.fail(path + ".pressure.linear", l, "expected a list of 2 numbers");
      sc.load = LoadKind::LinearPressure;
      sc.p0 = R.staged(l[0], path + ".pressure.linear[0]");
      sc.p1 = R.staged(l[1], path + ".pressure.linear[1]");
    } else {
      sc.load = LoadKind::Pressure;
      sc.p0 = sc.p1 = R.staged(p, path + ".pressure");
    }
  }
  if (n["traction"]) {
    const YAML::Node t = n["traction"];
    if (!t.IsSequence() || t.size() != 2) R.fail(path + ".traction", t, "expected a list of 2 numbers");
    sc.load = LoadKind::Traction;
    for (int c = 0; c < 2; ++c) {
      const auto v = R.staged(t[c], path + ".traction[" + std::to_string(c) + "]");
      for (int s = 0; s < K; ++s) sc.traction[s][c] = v[s];
    }
  }
}

// What a boundary or contact name designates on a body: (patch side, -1) or (patch, corner).
// Names: west/east/south/north and the corners south_west, ... (single-patch bodies),
// patch<k>.<side or corner>, or a named boundary of the body's geometry file.
std::vector<std::pair<PatchSide, int>> boundary_places(const Reader& R, const Body& b, const std::string& name,
                                                       const std::string& key, const YAML::Node& at, bool corners = true) {
  const int np = static_cast<int>(b.patches.size());
  std::string part = name;
  int patch = 0;
  bool prefixed = false;
  if (name.rfind("patch", 0) == 0 && name.find('.') != std::string::npos) {
    const std::string num = name.substr(5, name.find('.') - 5);
    const bool digits = !num.empty() && num.size() < 9 && std::all_of(num.begin(), num.end(), [](char c) { return std::isdigit(static_cast<unsigned char>(c)); });
    if (!digits) R.fail(key, at, "expected patch<k>.<side> with k a patch number");
    patch = std::stoi(num);
    if (patch >= np)
      R.fail(key, at, "body '" + b.name + "' has " + std::to_string(np) + " patch" + (np > 1 ? "es" : "") + " (patch0 .. patch" +
                          std::to_string(np - 1) + ")");
    part = name.substr(name.find('.') + 1);
    prefixed = true;
  }
  Side s;
  Corner c;
  const bool is_side = parse_side(part, s), is_corner = corners && parse_corner(part, c);
  if ((is_side || is_corner) && !prefixed && np > 1)
    R.fail(key, at, "body '" + b.name + "' has " + std::to_string(np) + " patches: name the side as patch<k>." + part);
  if (is_side) return {{PatchSide{patch, s}, -1}};
  if (is_corner) return {{PatchSide{patch, Side::West}, static_cast<int>(c)}};
  if (!prefixed)
    for (const auto& [nm, list] : b.named)
      if (nm == name) {
        std::vector<std::pair<PatchSide, int>> out;
        for (const PatchSide& ps : list) out.push_back({ps, -1});
        return out;
      }
  if (!corners && parse_corner(part, c)) {
    std::string names;
    for (const auto& [nm, list] : b.named) names += (names.empty() ? "" : ", ") + nm;
    R.fail(key, at, "a corner is a point, not a contact side (" +
                        std::string(np > 1 ? "patch<k>.west|east|south|north" : "west, east, south, north") +
                        (names.empty() ? "" : ", or a named boundary of the geometry file: " + names) + ")");
  }
  std::string names;
  for (const auto& [nm, list] : b.named) names += (names.empty() ? "" : ", ") + nm;
  std::string allowed = np > 1 ? "patch<k>.west|east|south|north" : "west, east, south, north";
  if (corners) allowed += np > 1 ? ", a corner patch<k>.south_west|south_east|north_west|north_east" : ", or a corner south_west, south_east, north_west, north_east";
  if (!names.empty()) allowed += ", or a named boundary of the geometry file: " + names;
  R.fail(key, at, "unknown side (" + allowed + ")");
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
  R.keys(g, path + ".geometry", {"nurbs", "rectangle", "quarter_annulus", "file", "patches"});
  if (g.size() != 1) R.fail(path + ".geometry", g, "give exactly one of nurbs, patches, rectangle, quarter_annulus, file");
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
    for (size_t k = 0; k < mp.patches.size(); ++k)
      for (int d = 0; d < 2; ++d)
        if (mp.patches[k].degree[d] > 5)
          R.fail(path + ".geometry.file", g["file"], "patch " + std::to_string(k) + " has degree " +
                 std::to_string(mp.patches[k].degree[d]) + " (1..5 are supported)");
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
    }
    b.interfaces = declared;
    for (const Interface& f : find_interfaces(b.patches, b.tolerance)) {
      bool known = false;
      for (const Interface& d : declared) known = known || (d.a == f.a && d.b == f.b) || (d.a == f.b && d.b == f.a);
      if (!known) b.interfaces.push_back(f);
    }
    const std::string nc = find_nonconforming(b.patches, b.interfaces, b.tolerance);
    if (!nc.empty()) R.fail(path + ".geometry", g, "body '" + b.name + "': " + nc);
  }

  if (n["refine"]) {
    const YAML::Node r = n["refine"];
    R.keys(r, path + ".refine", {"degree_elevate", "insert_knots", "subdivide"});
    // sizes after each refinement, checked before it is done (a refinement too large for
    // the machine is refused at once, not after minutes of knot insertion); every patch of
    // the body is refined alike
    using NcpFn = std::function<std::array<long long, 2>(const Patch&)>;
    using ElFn = std::function<std::array<double, 2>(const Patch&)>;
    auto totals = [&](const NcpFn& ncp, const ElFn& el) {
      double dofs = 0, sample = 0;
      for (const Patch& q : b.patches) {
        const auto c = ncp(q);
        const auto e = el(q);
        dofs += 2.0 * static_cast<double>(c[0]) * static_cast<double>(c[1]);
        sample += R.sample_bytes(e[0], e[1]);
      }
      return std::pair<double, double>(dofs, sample);
    };
    auto elements = [](const Patch& q) {
      return std::array<double, 2>{static_cast<double>(q.element_spans(0).size()), static_cast<double>(q.element_spans(1).size())};
    };
    auto max_degree = [&] {
      int m = 1;
      for (const Patch& q : b.patches) m = std::max({m, q.degree[0], q.degree[1]});
      return m;
    };
    if (r["degree_elevate"]) {
      const auto e = R.int_pair(r["degree_elevate"], path + ".refine.degree_elevate");
      for (const Patch& q : b.patches)
        for (int d = 0; d < 2; ++d) {
          if (e[d] < 0) R.fail(path + ".refine.degree_elevate", r["degree_elevate"], "must be >= 0");
          if (q.degree[d] + e[d] > 5)
            R.fail(path + ".refine.degree_elevate", r["degree_elevate"],
                   "would raise degree " + std::to_string(q.degree[d]) + " above the supported 5");
        }
      const auto t = totals([&](const Patch& q) {
        std::array<long long, 2> c{};
        for (int d = 0; d < 2; ++d) c[d] = q.ncp(d) + static_cast<long long>(e[d]) * (distinct_knots(q.knots[d]) - 1);
        return c;
      }, elements);
      R.fits(path + ".refine.degree_elevate", r["degree_elevate"], t.first, max_degree() + std::max(e[0], e[1]), t.second);
      for (Patch& q : b.patches)
        for (int d = 0; d < 2; ++d) q.elevate(d, e[d]);
    }
    if (r["insert_knots"]) {
      const YAML::Node ik = r["insert_knots"];
      const std::string key = path + ".refine.insert_knots";
      if (!ik.IsSequence() || ik.size() != 2) R.fail(key, ik, "expected two lists [[xi knots], [eta knots]] in [0, 1]");
      std::array<long long, 2> added{};
      for (int d = 0; d < 2; ++d) {
        if (ik[d].IsSequence() && ik[d].size() > kMaxInsertedKnots)
          R.fail(key + "[" + std::to_string(d) + "]", ik[d],
                 "at most " + std::to_string(kMaxInsertedKnots) + " knots per direction; use subdivide for uniform refinement");
        added[d] = ik[d].IsSequence() ? static_cast<long long>(ik[d].size()) : 0;
      }
      const auto t = totals([&](const Patch& q) { return std::array<long long, 2>{q.ncp(0) + added[0], q.ncp(1) + added[1]}; },
                            [&](const Patch& q) {
                              auto e = elements(q);
                              return std::array<double, 2>{e[0] + added[0], e[1] + added[1]};
                            });
      R.fits(key, ik, t.first, max_degree(), t.second);
      for (int d = 0; d < 2; ++d) {
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
      const auto s = R.int_pair(r["subdivide"], path + ".refine.subdivide");
      for (int d = 0; d < 2; ++d)
        if (s[d] < 1 || s[d] > 100000) R.fail(path + ".refine.subdivide", r["subdivide"], "must be 1..100000");
      const auto t = totals([&](const Patch& q) {
        std::array<long long, 2> c{};
        for (int d = 0; d < 2; ++d) c[d] = q.ncp(d) + static_cast<long long>(s[d] - 1) * static_cast<long long>(q.element_spans(d).size());
        return c;
      }, [&](const Patch& q) {
        auto e = elements(q);
        return std::array<double, 2>{e[0] * s[0], e[1] * s[1]};
      });
      R.fits(path + ".refine.subdivide", r["subdivide"], t.first, max_degree(), t.second);
      for (Patch& q : b.patches)
        for (int d = 0; d < 2; ++d) q.subdivide(d, s[d]);
    }
    for (const Interface& f : b.interfaces) {
      const std::string err = check_interface(b.patches, f, b.tolerance);
      if (!err.empty()) R.fail(path + ".refine", r, "body '" + b.name + "': " + err);
    }
  }
  b.cp_index = merge_control_points(b.patches, b.interfaces, b.num_cps);
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
  for (int k = 0; k < np; ++k)
    for (auto* arr : {&b.sides[k], &b.corners[k]})
      for (auto& sc : *arr)   // free sides: zero values at every stage end
        if (sc.value.empty()) {
          sc.value.assign(R.stages, {0.0, 0.0});
          sc.p0.assign(R.stages, 0.0);
          sc.p1.assign(R.stages, 0.0);
          sc.traction.assign(R.stages, {0.0, 0.0});
        }
  return b;
}

ContactSurface read_surface(const Reader& R, const Problem& P, const YAML::Node& n, const std::string& path) {
  R.keys(n, path, {"body", "side"});
  if (!n["body"]) R.missing(path + ".body");
  if (!n["side"]) R.missing(path + ".side");
  ContactSurface s;
  s.body = P.find_body(R.string(n["body"], path + ".body"));
  if (s.body < 0) R.fail(path + ".body", n["body"], "no body of that name");
  const Body& b = P.bodies[s.body];
  const YAML::Node sd = n["side"];
  std::vector<std::pair<std::string, YAML::Node>> names;
  if (sd.IsSequence()) {
    if (sd.size() == 0) R.fail(path + ".side", sd, "expected a side or a list of patch sides");
    for (size_t k = 0; k < sd.size(); ++k) names.push_back({R.string(sd[k], path + ".side[" + std::to_string(k) + "]"), sd[k]});
  } else {
    names.push_back({R.string(sd, path + ".side"), sd});
  }
  for (const auto& [name, node] : names) {
    for (const auto& pl : boundary_places(R, b, name, path + ".side", node, false)) {
      if (b.is_interface(pl.first))
        R.fail(path + ".side", node, patch_side_name(pl.first) + " is an interface between patches, inside the body: no contact there");
      s.sides.push_back(pl.first);
    }
    s.label += (s.label.empty() ? "" : "+") + name;
  }
  try {
    const SurfaceChain ch = make_chain(b.patches, s.sides, b.tolerance);
    // the joints must be shared control points (one dof), not two that merely touch
    const size_t np = ch.pieces.size(), joints = np > 1 ? np - 1 + (ch.closed ? 1 : 0) : 0;
    for (size_t k = 0; k < joints; ++k) {
      const auto& A = ch.pieces[k];
      const auto& B = ch.pieces[(k + 1) % np];
      const auto ia = b.patches[A.side.patch].side_indices(A.side.side), ib = b.patches[B.side.patch].side_indices(B.side.side);
      const int ea = A.reversed ? ia.front() : ia.back(), sb = B.reversed ? ib.back() : ib.front();
      if (b.cp_index[A.side.patch][ea] != b.cp_index[B.side.patch][sb])
        throw std::invalid_argument(patch_side_name(A.side) + " and " + patch_side_name(B.side) +
                                    " touch at a point that is not shared by an interface of their patches");
    }
  } catch (const std::invalid_argument& e) {
    R.fail(path + ".side", sd, e.what());
  }
  return s;
}

// Rank of the rigid-body modes restricted to the constrained dofs of a body: 3 means no
// rigid motion is left free.
int rigid_rank(const Body& b) {
  double G[3][3] = {};
  auto add = [&](const Point3& cp, int c) {
    const double x = cp[0], y = cp[1];
    const double row[3] = {c == 0 ? 1.0 : 0.0, c == 1 ? 1.0 : 0.0, c == 0 ? -y : x};
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) G[i][j] += row[i] * row[j];
  };
  for (size_t k = 0; k < b.patches.size(); ++k)
    for (int s = 0; s < 4; ++s) {
      for (int c = 0; c < 2; ++c) {
        if (b.sides[k][s].fixed[c])
          for (int a : b.patches[k].side_indices(static_cast<Side>(s))) add(b.patches[k].cp[a], c);
        if (b.corners[k][s].fixed[c]) add(b.patches[k].cp[corner_index(b.patches[k], static_cast<Corner>(s))], c);
      }
    }
  // rank by Gaussian elimination with full pivoting on the 3x3 Gram matrix
  double scale = 0;
  for (int i = 0; i < 3; ++i) scale = std::max(scale, G[i][i]);
  if (scale == 0) return 0;
  int rank = 0;
  bool used_r[3] = {}, used_c[3] = {};
  for (int k = 0; k < 3; ++k) {
    int pr = -1, pc = -1;
    double best = 0;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        if (!used_r[i] && !used_c[j] && std::abs(G[i][j]) > best) { best = std::abs(G[i][j]); pr = i; pc = j; }
    if (pr < 0 || best < 1e-10 * scale) break;
    used_r[pr] = used_c[pc] = true;
    ++rank;
    for (int i = 0; i < 3; ++i)
      if (!used_r[i]) {
        const double f = G[i][pc] / G[pr][pc];
        for (int j = 0; j < 3; ++j) G[i][j] -= f * G[pr][j];
      }
  }
  return rank;
}

// --set KEY=VALUE. KEY is a dotted path: map keys and list indices. A map key may itself
// contain dots (a multi-patch side `patch0.south`, a corner `patch1.south_west`): at each map
// the walk takes the longest run of the remaining components that, joined with '.', is a key
// the map already has, and otherwise one component (created when missing, as a new key). A
// component in double quotes is taken whole: bodies.0.boundary."patch0.south".displacement.
void apply_override(const std::string& file, YAML::Node root, const std::string& ov, std::vector<Override>& record) {
  size_t eq = std::string::npos;
  bool open_quote = false;
  for (size_t i = 0; i < ov.size() && eq == std::string::npos; ++i) {
    if (ov[i] == '"') open_quote = !open_quote;
    else if (ov[i] == '=' && !open_quote) eq = i;
  }
  if (open_quote) throw InputError(file + ": --set " + ov + ": the key path has an unclosed quote");
  if (eq == std::string::npos || eq == 0)
    throw InputError(file + ": --set " + ov + ": expected KEY=VALUE with a dotted key path");
  const std::string path = ov.substr(0, eq), text = ov.substr(eq + 1);
  YAML::Node value;
  try { value = YAML::Load(text); } catch (const YAML::Exception& e) {
    throw InputError(file + ": --set " + path + " = " + text + ": value is not valid YAML");
  }
  // split on the dots outside double quotes; a quoted component keeps its dots
  std::vector<std::string> parts;
  std::vector<bool> quoted;
  {
    std::string p;
    bool in_quotes = false, was_quoted = false;
    for (const char c : path) {
      if (c == '"') { in_quotes = !in_quotes; was_quoted = true; }
      else if (c == '.' && !in_quotes) { parts.push_back(p); quoted.push_back(was_quoted); p.clear(); was_quoted = false; }
      else p += c;
    }
    parts.push_back(p);
    quoted.push_back(was_quoted);
  }
  for (const auto& p : parts)
    if (p.empty()) throw InputError(file + ": --set " + ov + ": the key path has an empty part");
  record.push_back({ov, value});
  auto has_key = [](const YAML::Node& map, const std::string& key) {
    if (!map.IsMap()) return false;
    for (const auto& it : map)
      if (it.first.IsScalar() && it.first.Scalar() == key) return true;
    return false;
  };
  auto index = [&](const YAML::Node& list, const std::string& p) {
    char* end = nullptr;
    const long i = std::strtol(p.c_str(), &end, 10);
    if (*end || i < 0 || i >= static_cast<long>(list.size()))
      throw InputError(file + ": --set " + path + ": '" + p + "' is not an index of that list");
    return static_cast<size_t>(i);
  };
  // walk with node copies (yaml-cpp nodes are references into the tree)
  std::vector<YAML::Node> chain{root};
  for (size_t k = 0; k < parts.size();) {
    YAML::Node cur = chain.back();
    if (cur.IsSequence()) {
      const size_t i = index(cur, parts[k]);
      if (k + 1 == parts.size()) { cur[i] = value; return; }
      chain.push_back(cur[i]);
      ++k;
      continue;
    }
    if (!cur.IsMap() && !cur.IsNull())
      throw InputError(file + ": --set " + path + ": '" + parts[k] + "' is below a value, not a map");
    // the longest run parts[k..j] of unquoted components that is an existing key
    size_t j = k;
    std::string key = parts[k];
    if (!quoted[k])
      for (size_t m = parts.size() - 1; m > k; --m) {
        std::string joined = parts[k];
        bool plain = true;
        for (size_t q = k + 1; q <= m; ++q) { plain = plain && !quoted[q]; joined += "." + parts[q]; }
        if (plain && has_key(cur, joined)) { j = m; key = joined; break; }
      }
    if (j + 1 == parts.size()) { cur[key] = value; return; }
    if (!cur[key]) cur[key] = YAML::Node(YAML::NodeType::Map);
    chain.push_back(cur[key]);
    k = j + 1;
  }
}

// solver.linear.muelu_xml: a MueLu XML parameter list (MueLu's own format), relative to the
// problem file's folder. Read and checked here, once, so that a bad file stops the run before
// anything is solved or written: it must parse, and every top-level name must be a MueLu
// parameter (MueLu's master list) or a "level N" sublist.
Teuchos::RCP<const Teuchos::ParameterList> muelu_xml(const Reader& R, const YAML::Node& n) {
  const std::string key = "solver.linear.muelu_xml";
  const std::string given = R.string(n, key);
  if (given.empty()) R.fail(key, n, "must not be empty");
  const std::string path = (std::filesystem::path(R.file).parent_path() / given).string();
  std::error_code ec;   // a regular file only: Teuchos' XML reader loops on a folder or a device
  if (!std::filesystem::is_regular_file(path, ec) || !std::ifstream(path)) R.fail(key, n, "cannot read " + path);
  Teuchos::RCP<Teuchos::ParameterList> list;
  try {
    list = Teuchos::getParametersFromXmlFile(path);
  } catch (const std::exception& e) {
    // Teuchos' message ends with the reason, after the throwing source line and test
    std::string why = e.what();
    while (!why.empty() && std::isspace(static_cast<unsigned char>(why.back()))) why.pop_back();
    why = why.substr(why.find_last_of('\n') + 1);
    R.fail(key, n, "not a Teuchos XML parameter list: " + why);
  }
  const Teuchos::RCP<const Teuchos::ParameterList> master = MueLu::MasterList::List();
  for (auto it = list->begin(); it != list->end(); ++it) {
    const std::string& name = list->name(it);
    if (master->isParameter(name) || name.rfind("level ", 0) == 0) continue;
    R.fail(key, n, "'" + name + "' is not a MueLu parameter");
  }
  return list;
}

Problem build(Reader& R, const YAML::Node& root) {
  R.stages = 1;
  Problem P;
  P.file = R.file;
  if (!root.IsMap()) R.fail("(top level)", root, "expected a mapping with analysis, bodies, ...");
  R.keys(root, "", {"analysis", "bodies", "contact", "solver", "output"});

  if (root["analysis"]) {
    const YAML::Node a = root["analysis"];
    R.keys(a, "analysis", {"type", "kinematics", "thickness", "load_steps", "stages"});
    if (a["kinematics"]) {
      const std::string t = R.string(a["kinematics"], "analysis.kinematics");
      if (t == "small") P.kinematics = Kinematics::Small;
      else if (t == "finite") P.kinematics = Kinematics::Finite;
      else R.fail("analysis.kinematics", a["kinematics"], "expected small or finite");
    }
    if (a["type"]) {
      const std::string t = R.string(a["type"], "analysis.type");
      if (t == "plane_strain") P.analysis = Analysis::PlaneStrain;
      else if (t == "plane_stress") P.analysis = Analysis::PlaneStress;
      else R.fail("analysis.type", a["type"], "expected plane_strain or plane_stress");
    }
    if (P.kinematics == Kinematics::Finite && P.analysis == Analysis::PlaneStress)
      R.fail("analysis.type", a["type"], "finite kinematics is plane strain only (plane_stress is not supported with analysis.kinematics: finite)");
    if (a["thickness"]) P.thickness = R.positive(a["thickness"], "analysis.thickness");
    if (a["load_steps"] && a["stages"])
      R.fail("analysis.stages", a["stages"], "give either load_steps or stages (load steps per stage), not both");
    if (a["load_steps"]) {
      P.load_steps = R.integer(a["load_steps"], "analysis.load_steps");
      if (P.load_steps < 1 || P.load_steps > kMaxLoadSteps)
        R.fail("analysis.load_steps", a["load_steps"], "must be 1.." + std::to_string(kMaxLoadSteps));
    }
    P.stages = {P.load_steps};
    if (a["stages"]) {
      const YAML::Node st = a["stages"];
      if (!st.IsSequence() || st.size() == 0) R.fail("analysis.stages", st, "expected a list of load steps per stage, e.g. [4, 10, 10]");
      P.stages.clear();
      long total = 0;
      for (size_t k = 0; k < st.size(); ++k) {
        const int n = R.integer(st[k], "analysis.stages[" + std::to_string(k) + "]");
        if (n < 1) R.fail("analysis.stages[" + std::to_string(k) + "]", st[k], "must be >= 1");
        total += n;
        P.stages.push_back(n);
      }
      if (total > kMaxLoadSteps)
        R.fail("analysis.stages", st, "more than " + std::to_string(kMaxLoadSteps) + " load steps in all");
      P.load_steps = static_cast<int>(total);
    }
    R.stages = P.num_stages();
  }

  // the output sampling counts in the size checks made while the bodies are refined
  if (root["output"] && root["output"].IsMap() && root["output"]["samples_per_element"]) {
    const YAML::Node n = root["output"]["samples_per_element"];
    const int s = R.samples(n);
    if (s > 0) R.samples_per_element = s;   // auto: at most 4, the bound used
  }

  if (!root["bodies"]) R.missing("bodies");
  const YAML::Node bodies = root["bodies"];
  if (!bodies.IsSequence() || bodies.size() == 0) R.fail("bodies", bodies, "expected a non-empty list of bodies");
  for (size_t k = 0; k < bodies.size(); ++k) {
    const std::string path = "bodies[" + std::to_string(k) + "]";
    Body b = read_body(R, bodies[k], path);
    if (P.find_body(b.name) >= 0) R.fail(path + ".name", bodies[k]["name"], "duplicate body name");
    if (b.model != MaterialModel::Linear && P.kinematics == Kinematics::Small)
      R.fail(path + ".material.model", bodies[k]["material"]["model"],
             std::string(material_model_name(b.model)) + " is a finite-strain model; set analysis.kinematics: finite");
    P.bodies.push_back(std::move(b));
  }

  if (root["contact"]) {
    const YAML::Node c = root["contact"];
    if (!c.IsSequence()) R.fail("contact", c, "expected a list of contact pairs");
    for (size_t k = 0; k < c.size(); ++k) {
      const std::string path = "contact[" + std::to_string(k) + "]";
      const YAML::Node n = c[k];
      R.keys(n, path, {"master", "slave", "method", "penalty", "quadrature_points", "augmentations", "alm_tolerance",
                       "friction", "tangential_penalty"});
      ContactPair cp;
      if (!n["master"]) R.missing(path + ".master");
      if (!n["slave"]) R.missing(path + ".slave");
      cp.master = read_surface(R, P, n["master"], path + ".master");
      cp.slave = read_surface(R, P, n["slave"], path + ".slave");
      // self-contact: two different sides (or chains of patch sides) of one body
      if (cp.master.body == cp.slave.body)
        for (const PatchSide& ps : cp.slave.sides)
          if (std::find(cp.master.sides.begin(), cp.master.sides.end(), ps) != cp.master.sides.end())
            R.fail(path + ".slave", n["slave"],
                   cp.master.sides == cp.slave.sides
                       ? std::string("master and slave are the same side of the same body")
                       : "master and slave share the side " + P.bodies[cp.slave.body].side_label(ps.patch, ps.side) +
                             " of body '" + P.bodies[cp.slave.body].name + "'");
      if (n["method"]) {
        const std::string m = R.string(n["method"], path + ".method");
        if (m == "kts_penalty") cp.method = ContactMethod::KtsPenalty;
        else if (m == "kts_alm") cp.method = ContactMethod::KtsAlm;
        else if (m == "mortar_penalty") cp.method = ContactMethod::MortarPenalty;
        else if (m == "mortar_alm") cp.method = ContactMethod::MortarAlm;
        else R.fail(path + ".method", n["method"], "expected kts_penalty, kts_alm, mortar_penalty or mortar_alm");
      }
      if (!n["penalty"]) R.missing(path + ".penalty");
      cp.penalty = R.positive(n["penalty"], path + ".penalty");
      if (n["quadrature_points"]) {
        cp.quadrature_points = R.integer(n["quadrature_points"], path + ".quadrature_points");
        if (cp.quadrature_points < 1 || cp.quadrature_points > kMaxContactQuadrature)
          R.fail(path + ".quadrature_points", n["quadrature_points"],
                 "must be 1.." + std::to_string(kMaxContactQuadrature));
      }
      if (n["augmentations"]) {
        cp.augmentations = R.integer(n["augmentations"], path + ".augmentations");
        if (cp.augmentations < 1) R.fail(path + ".augmentations", n["augmentations"], "must be >= 1");
      }
      if (n["alm_tolerance"]) cp.alm_tolerance = R.positive(n["alm_tolerance"], path + ".alm_tolerance");
      if (n["friction"]) {
        cp.friction = R.number(n["friction"], path + ".friction");
        if (!(cp.friction >= 0) || !std::isfinite(cp.friction))
          R.fail(path + ".friction", n["friction"], "the Coulomb coefficient must be a number >= 0");
      }
      // KTS ALM with friction: the stick constraints of the quadrature points outnumber the
      // slave dofs, and where stick meets slip Uzawa drifts along them for a few hundred
      // updates (docs/friction.md): a larger default
      if (!n["augmentations"] && cp.friction > 0 && cp.method == ContactMethod::KtsAlm) cp.augmentations = 500;
      cp.tangential_penalty = n["tangential_penalty"] ? R.positive(n["tangential_penalty"], path + ".tangential_penalty")
                                                      : cp.penalty;
      if (!(cp.tangential_penalty * P.thickness >= std::numeric_limits<double>::min()) ||
          !std::isfinite(cp.tangential_penalty * P.thickness))
        R.fail(path + ".tangential_penalty", n["tangential_penalty"] ? n["tangential_penalty"] : n["penalty"],
               "tangential_penalty x thickness is not a normal floating-point number; rescale the units");
      // a slave side that faces away from its master never touches it: the run would end
      // with no contact and exit 0
      const std::string facing = check_pair_facing(P, cp);
      if (!facing.empty()) R.fail(path + ".slave", n["slave"], facing);
      P.contact.push_back(cp);
      const std::string warn = penalty_warning(P, static_cast<int>(P.contact.size()) - 1);
      if (!warn.empty()) P.warnings.push_back(R.file + ": " + warn);
    }
  }

  if (root["solver"]) {
    const YAML::Node s = root["solver"];
    R.keys(s, "solver", {"newton", "linear", "quadrature", "formation"});
    if (s["formation"]) {
      const std::string f = R.string(s["formation"], "solver.formation");
      if (f == "sum_factorized") P.formation = Formation::SumFactorized;
      else if (f == "elements") P.formation = Formation::Elements;
      else R.fail("solver.formation", s["formation"], "expected sum_factorized or elements");
    }
    if (s["quadrature"]) {
      const std::string q = R.string(s["quadrature"], "solver.quadrature");
      if (q == "gauss") P.quadrature = Quadrature::Gauss;
      else if (q == "spline") P.quadrature = Quadrature::Spline;
      else R.fail("solver.quadrature", s["quadrature"], "expected gauss or spline");
    }
    if (s["newton"]) {
      const YAML::Node n = s["newton"];
      R.keys(n, "solver.newton", {"max_iterations", "tolerance", "line_search", "max_cuts"});
      if (n["line_search"]) P.newton.line_search = R.boolean(n["line_search"], "solver.newton.line_search");
      if (n["max_cuts"]) {
        P.newton.max_cuts = R.integer(n["max_cuts"], "solver.newton.max_cuts");
        if (P.newton.max_cuts < 0 || P.newton.max_cuts > 30) R.fail("solver.newton.max_cuts", n["max_cuts"], "must be 0..30");
      }
      if (n["max_iterations"]) {
        P.newton.max_iterations = R.integer(n["max_iterations"], "solver.newton.max_iterations");
        if (P.newton.max_iterations < 1) R.fail("solver.newton.max_iterations", n["max_iterations"], "must be >= 1");
      }
      if (n["tolerance"]) P.newton.tolerance = R.positive(n["tolerance"], "solver.newton.tolerance");
    }
    if (s["linear"]) {
      const YAML::Node l = s["linear"];
      R.keys(l, "solver.linear", {"method", "preconditioner", "tolerance", "max_iterations", "muelu_xml",
                                   "reuse_preconditioner", "forcing"});
      if (l["method"]) {
        const std::string m = R.string(l["method"], "solver.linear.method");
        if (m == "cg") P.linear.method = LinearMethod::CG;
        else if (m == "gmres") P.linear.method = LinearMethod::GMRES;
        else if (m == "direct") P.linear.method = LinearMethod::Direct;
        else if (m != "auto") R.fail("solver.linear.method", l["method"], "expected auto, direct, gmres or cg");
        P.linear.method_given = m != "auto";
      }
      if (l["preconditioner"]) {
        const std::string m = R.string(l["preconditioner"], "solver.linear.preconditioner");
        if (m == "muelu") P.linear.preconditioner = Preconditioner::MueLu;
        else if (m == "boomeramg") P.linear.preconditioner = Preconditioner::BoomerAMG;
        else if (m == "ilut") P.linear.preconditioner = Preconditioner::ILUT;
        else if (m == "relaxation") P.linear.preconditioner = Preconditioner::Relaxation;
        else if (m == "none") P.linear.preconditioner = Preconditioner::None;
        else R.fail("solver.linear.preconditioner", l["preconditioner"], "expected boomeramg, muelu, ilut, relaxation or none");
      }
      if (l["tolerance"]) P.linear.tolerance = R.positive(l["tolerance"], "solver.linear.tolerance");
      if (l["max_iterations"]) {
        P.linear.max_iterations = R.integer(l["max_iterations"], "solver.linear.max_iterations");
        if (P.linear.max_iterations < 1) R.fail("solver.linear.max_iterations", l["max_iterations"], "must be >= 1");
      }
      if (l["muelu_xml"]) {
        // MueLu's parameters choose MueLu where no preconditioner is named (the default is
        // BoomerAMG); beside another named one they would be ignored: bad input
        if (!l["preconditioner"]) P.linear.preconditioner = Preconditioner::MueLu;
        else if (P.linear.preconditioner != Preconditioner::MueLu)
          R.fail("solver.linear.muelu_xml", l["muelu_xml"],
                 std::string("MueLu parameters, but solver.linear.preconditioner is ") +
                     preconditioner_name(P.linear.preconditioner) + " (name muelu, or drop muelu_xml)");
        P.linear.muelu_parameters = muelu_xml(R, l["muelu_xml"]);
      }
      if (l["reuse_preconditioner"])
        P.linear.reuse_preconditioner = R.boolean(l["reuse_preconditioner"], "solver.linear.reuse_preconditioner");
      if (l["forcing"]) {
        const std::string m = R.string(l["forcing"], "solver.linear.forcing");
        if (m == "eisenstat_walker") P.linear.forcing = Forcing::EisenstatWalker;
        else if (m == "fixed") P.linear.forcing = Forcing::Fixed;
        else if (m != "auto") R.fail("solver.linear.forcing", l["forcing"], "expected auto, eisenstat_walker or fixed");
      }
    }
  }

  if (root["output"]) {
    const YAML::Node o = root["output"];
    R.keys(o, "output", {"directory", "samples_per_element", "probes", "steps"});
    if (o["steps"]) {
      const std::string st = R.string(o["steps"], "output.steps");
      if (st == "all") P.output.all_steps = true;
      else if (st == "last") P.output.all_steps = false;
      else R.fail("output.steps", o["steps"], "expected all or last");
    }
    if (o["directory"]) {
      P.output.directory = R.string(o["directory"], "output.directory");
      if (P.output.directory.empty()) R.fail("output.directory", o["directory"], "must not be empty");
    }
    if (o["samples_per_element"]) {
      P.output.samples_per_element = R.samples(o["samples_per_element"]);
    }
    if (o["probes"]) {
      const YAML::Node pr = o["probes"];
      if (!pr.IsSequence()) R.fail("output.probes", pr, "expected a list of {body, at}");
      for (size_t k = 0; k < pr.size(); ++k) {
        const std::string path = "output.probes[" + std::to_string(k) + "]";
        R.keys(pr[k], path, {"body", "patch", "at"});
        if (!pr[k]["body"]) R.missing(path + ".body");
        if (!pr[k]["at"]) R.missing(path + ".at");
        Probe p;
        p.body = P.find_body(R.string(pr[k]["body"], path + ".body"));
        if (p.body < 0) R.fail(path + ".body", pr[k]["body"], "no body of that name");
        if (pr[k]["patch"]) {
          p.patch = R.integer(pr[k]["patch"], path + ".patch");
          const int np = static_cast<int>(P.bodies[p.body].patches.size());
          if (p.patch < 0 || p.patch >= np)
            R.fail(path + ".patch", pr[k]["patch"], "body '" + P.bodies[p.body].name + "' has patches 0.." + std::to_string(np - 1));
        }
        const auto at = R.numbers(pr[k]["at"], path + ".at", 2);
        for (int d = 0; d < 2; ++d)
          if (at[d] < 0 || at[d] > 1) R.fail(path + ".at", pr[k]["at"], "parametric coordinates must lie in [0, 1]");
        p.at = {at[0], at[1]};
        P.output.probes.push_back(p);
      }
    }
  }

  // Default linear method (auto): the direct solver up to auto_direct_max_dofs() dofs; above, CG for
  // elasticity (SPD), GMRES with contact, whose consistent tangent (the -p G term of the
  // moving projection) is not positive definite far from the solution.
  if (!P.linear.method_given) {
    long long dofs = 0;
    for (const Body& b : P.bodies) dofs += 2LL * b.num_cps;
    P.linear.automatic = true;
    // finite strain: the tangent may be indefinite (buckling) and, with follower pressure,
    // non-symmetric: GMRES
    P.linear.method = dofs <= P.auto_direct_max_dofs()                         ? LinearMethod::Direct
                      : P.contact.empty() && P.kinematics == Kinematics::Small ? LinearMethod::CG
                                                                               : LinearMethod::GMRES;
  }
  for (const ContactPair& c : P.contact)
    if (c.friction > 0) P.linear.symmetric = false;
  // a pressure following the deformed surface has a non-symmetric tangent
  bool follower = false;
  if (P.kinematics == Kinematics::Finite)
    for (const Body& b : P.bodies)
      for (const auto& sides : b.sides)
        for (const SideCondition& sc : sides)
        if (sc.load == LoadKind::Pressure || sc.load == LoadKind::LinearPressure) follower = true;
  if (follower) {
    P.linear.symmetric = false;
    if (P.linear.method == LinearMethod::CG)
      R.fail("solver.linear.method", root["solver"]["linear"]["method"],
             "cg needs a symmetric tangent, and a pressure with analysis.kinematics: finite follows the deformed "
             "surface, whose tangent is non-symmetric; use gmres or direct");
  }
  // friction in slip makes the tangent non-symmetric: CG does not apply
  for (size_t k = 0; k < P.contact.size(); ++k)
    if (P.contact[k].friction > 0 && P.linear.method == LinearMethod::CG)
      R.fail("solver.linear.method", root["solver"]["linear"]["method"],
             "cg needs a symmetric tangent, and friction (contact[" + std::to_string(k) +
                 "].friction > 0) makes it non-symmetric in slip; use gmres or direct");

  // Scales: stiffness and penalty times thickness must stay normal floating-point numbers
  // (a thickness of 1e-320 made every stiffness vanish and "converged" at zero displacement).
  for (size_t b = 0; b < P.bodies.size(); ++b) {
    const double et = P.bodies[b].E * P.thickness;
    if (!(std::isfinite(et) && et >= std::numeric_limits<double>::min()))
      R.fail(root["analysis"] && root["analysis"]["thickness"] ? "analysis.thickness" : "bodies[" + std::to_string(b) + "].material.youngs_modulus",
             root["analysis"] && root["analysis"]["thickness"] ? root["analysis"]["thickness"] : bodies[b]["material"]["youngs_modulus"],
             "youngs_modulus x thickness of body '" + P.bodies[b].name + "' is not a normal floating-point number; rescale the units");
  }
  for (size_t k = 0; k < P.contact.size(); ++k) {
    const double pt = P.contact[k].penalty * P.thickness;
    if (!(std::isfinite(pt) && pt >= std::numeric_limits<double>::min()))
      R.fail("contact[" + std::to_string(k) + "].penalty", root["contact"][k]["penalty"],
             "penalty x thickness is not a normal floating-point number; rescale the units");
  }

  // The whole problem, output samples included, must fit the machine.
  {
    double dofs = 0, out_bytes = 0;
    int degree = 1;
    for (const auto& b : P.bodies) {
      dofs += 2.0 * b.num_cps;
      for (const Patch& q : b.patches) {
        degree = std::max({degree, q.degree[0], q.degree[1]});
        out_bytes += R.sample_bytes(static_cast<double>(q.element_spans(0).size()), static_cast<double>(q.element_spans(1).size()));
      }
    }
    const bool output_dominates = out_bytes > 0.5 * dofs * 103.0 * (2 * degree + 1) * (2 * degree + 1);
    if (output_dominates && root["output"] && root["output"]["samples_per_element"])
      R.fits("output.samples_per_element", root["output"]["samples_per_element"], dofs, degree, out_bytes);
    else
      R.fits("bodies", bodies, dofs, degree, out_bytes);
  }

  // Rigid-body motion: a body that no contact pair touches must be held by its supports.
  for (size_t b = 0; b < P.bodies.size(); ++b) {
    bool in_contact = false;
    for (const auto& c : P.contact) in_contact = in_contact || c.master.body == (int)b || c.slave.body == (int)b;
    if (!in_contact && rigid_rank(P.bodies[b]) < 3)
      R.fail("bodies[" + std::to_string(b) + "].boundary", bodies[b]["boundary"],
             "body '" + P.bodies[b].name +
                 "' is free to move as a rigid body (singular system): prescribe x and y displacements "
                 "that fix translation and rotation");
  }
  return P;
}

// MemAvailable of /proc/meminfo in bytes (0 where unknown), or less where the environment's
// IGACONTACT_MEMORY_LIMIT (bytes) says so: a shared machine, or the fuzzer, which must not
// spend its time refining a valid 2e7-dof mesh.
double available_memory_bytes() {
  std::ifstream in("/proc/meminfo");
  std::string key;
  double kib = 0, bytes = 0;
  std::string unit;
  while (in >> key >> kib >> unit)
    if (key == "MemAvailable:") { bytes = kib * 1024.0; break; }
  if (const char* lim = std::getenv("IGACONTACT_MEMORY_LIMIT")) {
    char* end = nullptr;
    const double l = std::strtod(lim, &end);
    if (end != lim && l > 0 && std::isfinite(l)) bytes = bytes > 0 ? std::min(bytes, l) : l;
  }
  return bytes;
}

}  // namespace

Problem parse_problem(const std::string& text, const std::string& file, const std::vector<std::string>& overrides) {
  Reader R;
  R.file = file;
  R.memory_bytes = available_memory_bytes();
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    std::ostringstream os;
    os << file << ":" << e.mark.line + 1 << ":" << e.mark.column + 1 << ": YAML syntax error: " << e.msg;
    throw InputError(printable(os.str()));
  }
  try {
    check_duplicate_keys(R, root, "");
    for (const auto& ov : overrides) apply_override(file, root, ov, R.overrides);
    return build(R, root);
  } catch (const InputError& e) {
    throw InputError(printable(e.what()));
  } catch (const YAML::Exception& e) {
    std::ostringstream os;
    os << file << ":" << e.mark.line + 1 << ": " << e.msg;
    throw InputError(printable(os.str()));
  }
}

Problem load_problem(const std::string& file, const std::vector<std::string>& overrides) {
  // Only a regular file of a sane size: a folder, a device (/dev/zero) or a fifo is refused
  // before anything is read.
  std::error_code ec;
  const auto st = std::filesystem::status(file, ec);
  if (ec || !std::filesystem::exists(st)) throw InputError(printable(file + ": cannot open the problem file"));
  if (std::filesystem::is_directory(st)) throw InputError(printable(file + ": the problem file is a directory"));
  if (!std::filesystem::is_regular_file(st)) throw InputError(printable(file + ": the problem file is not a regular file"));
  const auto size = std::filesystem::file_size(file, ec);
  if (!ec && size > kMaxProblemFileBytes)
    throw InputError(printable(file + ": the problem file has " + std::to_string(size) + " bytes, more than the " +
                               std::to_string(kMaxProblemFileBytes) + " a problem file may have"));
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(printable(file + ": cannot open the problem file"));
  // read what is there, up to one byte past the limit (a file that grew after the size check),
  // in blocks: a buffer of the limit's size up front made the kernel zero 64 MiB of fresh pages
  // for a 1 kB file (0.015-0.2 s of "0) Read problem")
  std::string text;
  char block[1 << 16];
  while (text.size() <= kMaxProblemFileBytes && in.read(block, sizeof block).gcount() > 0)
    text.append(block, static_cast<size_t>(in.gcount()));
  if (text.size() > kMaxProblemFileBytes) throw InputError(printable(file + ": the problem file is larger than " +
                                                                     std::to_string(kMaxProblemFileBytes) + " bytes"));
  return parse_problem(text, file, overrides);
}

}  // namespace iga
