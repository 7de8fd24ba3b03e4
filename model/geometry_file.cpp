// Geometry files: G+Smo XML (read through Teuchos' XML parser, and written) and the GeoPDEs
// multipatch text format v2.1 (read). The conventions, checked against both projects' sources,
// are in docs/geometry-files.md; in short:
//   - both number sides 1..4 = west (u = 0), east (u = 1), south (v = 0), north (v = 1);
//   - both list control points with the first parametric index running fastest;
//   - G+Smo's <coefs> are Euclidean (the weights live in the basis); GeoPDEs' coordinate rows
//     are homogeneous (w x, w y), as the NURBS toolbox stores them;
//   - G+Smo's interfaces and boundaries name patches by their Geometry id; GeoPDEs by the
//     1-based patch number.
#include "model/geometry_file.hpp"

#include <Teuchos_StringInputSource.hpp>
#include <Teuchos_XMLObject.hpp>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <sstream>
#include <stdexcept>

namespace iga {
namespace {

// ---------------------------------------------------------------------------------------------
// Shared helpers

// A third coordinate counts as zero below this (nrbexport's own test for a 2-D geometry).
constexpr double kZeroZ = 1e-12;

[[noreturn]] void fail(const std::string& where, const std::string& what) {
  throw InputError(where + ": " + what);
}

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::string trim(const std::string& s) {
  size_t b = 0, e = s.size();
  while (b < e && std::isspace(static_cast<unsigned char>(s[b]))) ++b;
  while (e > b && std::isspace(static_cast<unsigned char>(s[e - 1]))) --e;
  return s.substr(b, e - b);
}

std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> out;
  std::istringstream is(s);
  for (std::string t; is >> t;) out.push_back(t);
  return out;
}

// Quotes a token for a message, cut short and free of control characters.
std::string quote(const std::string& s) {
  std::string t;
  for (char c : s.substr(0, 40)) t += std::isprint(static_cast<unsigned char>(c)) ? c : '?';
  if (s.size() > 40) t += "...";
  return "\"" + t + "\"";
}

bool to_double(const std::string& s, double& v) {
  if (s.empty()) return false;
  char* end = nullptr;
  v = std::strtod(s.c_str(), &end);
  return end == s.c_str() + s.size() && std::isfinite(v);
}

bool to_int(const std::string& s, long& v) {
  if (s.empty()) return false;
  char* end = nullptr;
  errno = 0;
  v = std::strtol(s.c_str(), &end, 10);
  return end == s.c_str() + s.size() && errno != ERANGE && v >= -1000000000L && v <= 1000000000L;
}

// Shortest decimal that reads back to the same double (at most 17 significant digits).
std::string fmt(double v) {
  char buf[64];
  for (int prec = 15; prec <= 17; ++prec) {
    std::snprintf(buf, sizeof buf, "%.*g", prec, v);
    if (std::strtod(buf, nullptr) == v) break;
  }
  return buf;
}

// The writers' pieces: numbers on one line, and whether a side names one of np patches.
std::string number_row(const std::vector<double>& v) {
  std::string r;
  for (size_t j = 0; j < v.size(); ++j) r += (j ? " " : "") + fmt(v[j]);
  return r;
}

std::string side_out_of_range(const PatchSide& s, int np) {
  if (s.patch >= 0 && s.patch < np && static_cast<int>(s.side) >= 0 && static_cast<int>(s.side) <= 3) return "";
  return "names patch " + std::to_string(s.patch) + " side " + std::to_string(static_cast<int>(s.side)) +
         ", not one of the " + std::to_string(np) + " patches' sides";
}

std::string read_file_text(const std::string& path) {
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) fail(path, std::string("cannot open the file (") + std::strerror(errno) + ")");
  std::string text;
  char buf[65536];
  size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, f)) > 0) text.append(buf, n);
  const bool bad = std::ferror(f) != 0;
  const int err = errno;
  std::fclose(f);
  if (bad) fail(path, std::string("cannot read the file (") + std::strerror(err) + ")");
  return text;
}

// The side of a 1-based G+Smo / GeoPDEs side number (both: 1 west, 2 east, 3 south, 4 north).
Side side_of_number(long k) { return static_cast<Side>(k - 1); }
int number_of_side(Side s) { return static_cast<int>(s) + 1; }
int side_direction(Side s) { return static_cast<int>(s) / 2; }   // the fixed parameter: 0 u, 1 v
int side_parameter(Side s) { return static_cast<int>(s) % 2; }   // at its start (0) or end (1)

std::string side_text(const PatchSide& s) {
  return "patch" + std::to_string(s.patch) + "." + side_name(s.side);
}

// Knot vector checks with the format's own words; Patch::validate() runs afterwards as well.
std::string check_knots(const std::vector<double>& U, int p) {
  std::ostringstream os;
  if (static_cast<int>(U.size()) < 2 * (p + 1)) {
    os << U.size() << " knots; an open knot vector of degree " << p << " needs at least " << 2 * (p + 1);
    return os.str();
  }
  for (size_t k = 1; k < U.size(); ++k)
    if (U[k] < U[k - 1]) {
      os << "the knots decrease at knot " << k + 1 << " (" << fmt(U[k - 1]) << " then " << fmt(U[k])
         << ")";
      return os.str();
    }
  for (int k = 1; k <= p; ++k)
    if (U[k] != U[0] || U[U.size() - 1 - k] != U.back()) {
      os << "the knot vector is not open: degree " << p << " needs its first " << p + 1 << " and its last "
         << p + 1 << " knots equal";
      return os.str();
    }
  if (!(U.back() > U.front())) return "the knots span an empty interval";
  return "";
}

// Topology bookkeeping shared by both readers: every interface joins two distinct sides that no
// other interface uses; a listed boundary side is no interface side. `where` locates the entry
// for the message, `label` names it for a later one.
class TopologyCheck {
 public:
  void interface(const Interface& f, const std::string& where, const std::string& label) {
    if (f.a == f.b) fail(where, "the interface joins " + side_text(f.a) + " with itself");
    for (const PatchSide& s : {f.a, f.b}) {
      auto it = used_.find(key(s));
      if (it != used_.end()) fail(where, side_text(s) + " is already in " + it->second);
    }
    used_[key(f.a)] = label;
    used_[key(f.b)] = label;
  }

  void boundary(const PatchSide& s, const std::string& where) {
    auto it = used_.find(key(s));
    if (it != used_.end()) fail(where, side_text(s) + " is listed as boundary but is in " + it->second);
  }

 private:
  static int key(const PatchSide& s) { return s.patch * 4 + static_cast<int>(s.side); }
  std::map<int, std::string> used_;
};

void add_unique(std::vector<PatchSide>& v, const PatchSide& s) {
  if (std::find(v.begin(), v.end(), s) == v.end()) v.push_back(s);
}

void add_named(MultiPatch& mp, const std::string& name, const PatchSide& s) {
  for (auto& [n, sides] : mp.named)
    if (n == name) {
      add_unique(sides, s);
      return;
    }
  mp.named.push_back({name, {s}});
}

// ---------------------------------------------------------------------------------------------
// G+Smo XML

using Teuchos::XMLObject;

std::string content(const XMLObject& x) {
  std::string s;
  for (int i = 0; i < x.numContentLines(); ++i) s += x.getContentLine(i) + "\n";
  return s;
}

std::vector<std::vector<std::string>> content_lines(const XMLObject& x) {
  std::vector<std::vector<std::string>> out;
  for (int i = 0; i < x.numContentLines(); ++i) {
    auto t = split(x.getContentLine(i));
    if (!t.empty()) out.push_back(std::move(t));
  }
  return out;
}

const XMLObject* first_child(const XMLObject& x, const std::string& tag) {
  for (int i = 0; i < x.numChildren(); ++i)
    if (x.getChild(i).getTag() == tag) return &x.getChild(i);
  return nullptr;
}

std::vector<const XMLObject*> children(const XMLObject& x, const std::string& tag) {
  std::vector<const XMLObject*> out;
  for (int i = 0; i < x.numChildren(); ++i)
    if (x.getChild(i).getTag() == tag) out.push_back(&x.getChild(i));
  return out;
}

std::string attr(const XMLObject& x, const std::string& name) {
  return x.hasAttribute(name) ? x.getAttribute(name) : std::string();
}

const XMLObject& need_child(const XMLObject& x, const std::string& tag, const std::string& where) {
  const XMLObject* c = first_child(x, tag);
  if (!c) fail(where, "missing <" + tag + ">");
  return *c;
}

// Only plain-text numbers: G+Smo's binary (base64) formats are not read.
void check_ascii(const XMLObject& x, const std::string& where) {
  if (x.hasAttribute("format") && lower(x.getAttribute("format")) != "ascii")
    fail(where, "format=" + quote(x.getAttribute("format")) +
                    " is not supported (igacontact reads numbers written as text, format=\"ascii\")");
}

std::vector<double> xml_numbers(const XMLObject& x, const std::string& where) {
  std::vector<double> v;
  for (const std::string& t : split(content(x))) {
    double d;
    if (!to_double(t, d)) fail(where, quote(t) + " is not a number (value " + std::to_string(v.size() + 1) + ")");
    v.push_back(d);
  }
  return v;
}

std::string geometry_label(const XMLObject& g, int position) {
  if (g.hasAttribute("id")) return "<Geometry id=\"" + g.getAttribute("id") + "\">";
  return "<Geometry> number " + std::to_string(position + 1);
}

// One direction of a tensor B-spline basis: <Basis type="BSplineBasis"><KnotVector degree=..>.
void read_xml_knots(const XMLObject& b, const std::string& where, int& degree, std::vector<double>& U) {
  if (attr(b, "type") != "BSplineBasis")
    fail(where, "type=" + quote(attr(b, "type")) + ", expected \"BSplineBasis\"");
  const XMLObject& kv = need_child(b, "KnotVector", where);
  const std::string w = where + " <KnotVector>";
  if (!kv.hasAttribute("degree")) fail(w, "missing the degree attribute");
  long p;
  if (!to_int(trim(kv.getAttribute("degree")), p)) fail(w, "degree=" + quote(kv.getAttribute("degree")) + " is not an integer");
  if (p < 1) fail(w, "degree=" + std::to_string(p) + ": the degree must be at least 1");
  if (p > 1000) fail(w, "degree=" + std::to_string(p) + " is too high");
  degree = static_cast<int>(p);   // Patch::validate() checks the supported range
  if (kv.hasAttribute("mode")) {
    if (kv.getAttribute("mode") != "uniform")
      fail(w, "mode=" + quote(kv.getAttribute("mode")) + " is not supported (only mode=\"uniform\")");
    long csize;
    if (!kv.hasAttribute("csize") || !to_int(trim(kv.getAttribute("csize")), csize))
      fail(w, "mode=\"uniform\" needs an integer csize attribute (the number of basis functions)");
    if (csize < p + 1)
      fail(w, "csize=" + std::to_string(csize) + " is less than degree + 1 = " + std::to_string(p + 1));
    if (csize > 1000000) fail(w, "csize=" + std::to_string(csize) + " is too many basis functions");
    U = uniform_open_knots(degree, static_cast<int>(csize - p));
    return;
  }
  check_ascii(kv, w);
  U = xml_numbers(kv, w);
  const std::string bad = check_knots(U, degree);
  if (!bad.empty()) fail(w, bad);
}

Patch read_xml_patch(const XMLObject& g, const std::string& where) {
  const std::string type = attr(g, "type");
  const bool nurbs = type == "TensorNurbs2";
  if (!nurbs && type != "TensorBSpline2")
    fail(where, "unsupported type=" + quote(type) +
                    " (igacontact reads 2-D tensor patches: TensorBSpline2, TensorNurbs2)");

  if (first_child(g, "transform"))
    fail(where, "<transform> is not supported (apply the transformation to the coefs)");

  // Basis: TensorNurbsBasis2 { TensorBSplineBasis2, weights } or TensorBSplineBasis2.
  const std::string wb = where + " <Basis>";
  const XMLObject& basis = need_child(g, "Basis", where);
  const XMLObject* tensor = &basis;
  const XMLObject* weights = nullptr;
  if (nurbs) {
    if (attr(basis, "type") != "TensorNurbsBasis2")
      fail(wb, "type=" + quote(attr(basis, "type")) + ", a TensorNurbs2 needs \"TensorNurbsBasis2\"");
    tensor = &need_child(basis, "Basis", wb);
    weights = &need_child(basis, "weights", wb);
  }
  const std::string wt = nurbs ? wb + " <Basis>" : wb;
  if (attr(*tensor, "type") != "TensorBSplineBasis2")
    fail(wt, "type=" + quote(attr(*tensor, "type")) + ", expected \"TensorBSplineBasis2\"");
  const auto comps = children(*tensor, "Basis");
  if (comps.size() != 2)
    fail(wt, "has " + std::to_string(comps.size()) + " <Basis> children; a 2-D tensor basis has 2");

  Patch P;
  bool seen[2] = {false, false};
  for (int k = 0; k < 2; ++k) {
    int d = k;
    if (comps[k]->hasAttribute("index")) {
      long idx;
      if (!to_int(trim(comps[k]->getAttribute("index")), idx) || idx < 0 || idx > 1)
        fail(wt, "<Basis index=" + quote(comps[k]->getAttribute("index")) + ">: index must be 0 or 1");
      d = static_cast<int>(idx);
    }
    if (seen[d]) fail(wt, "two <Basis> children for direction " + std::to_string(d));
    seen[d] = true;
    read_xml_knots(*comps[k], wt + " <Basis index=\"" + std::to_string(d) + "\">", P.degree[d], P.knots[d]);
  }
  const long n0 = P.ncp(0), n1 = P.ncp(1), n = n0 * n1;
  const std::string dims = std::to_string(n0) + " x " + std::to_string(n1) + " = " + std::to_string(n);

  // coefs: one row per basis function (x y [z]), Euclidean.
  const std::string wc = where + " <coefs>";
  const XMLObject& coefs = need_child(g, "coefs", where);
  if (!coefs.hasAttribute("geoDim")) fail(wc, "missing the geoDim attribute");
  long gd;
  if (!to_int(trim(coefs.getAttribute("geoDim")), gd) || (gd != 2 && gd != 3))
    fail(wc, "geoDim=" + quote(coefs.getAttribute("geoDim")) + ": igacontact reads geoDim 2 (or 3 with z = 0)");
  check_ascii(coefs, wc);
  bool by_coordinate = false;
  if (coefs.hasAttribute("order")) {
    if (coefs.getAttribute("order") != "coordinates")
      fail(wc, "order=" + quote(coefs.getAttribute("order")) + " is not supported (only order=\"coordinates\")");
    by_coordinate = true;
  }
  const std::vector<double> c = xml_numbers(coefs, wc);
  if (static_cast<long>(c.size()) != n * gd)
    fail(wc, "has " + std::to_string(c.size()) + " values; the basis has " + dims + " functions, times geoDim " +
                 std::to_string(gd) + " = " + std::to_string(n * gd));
  auto coef = [&](long a, int comp) { return by_coordinate ? c[comp * n + a] : c[a * gd + comp]; };
  if (gd == 3)
    for (long a = 0; a < n; ++a)
      if (std::abs(coef(a, 2)) > kZeroZ)
        fail(wc, "control point " + std::to_string(a) + " has z = " + fmt(coef(a, 2)) +
                     "; igacontact is 2-D, a geoDim 3 patch must have z = 0");

  std::vector<double> w(n, 1.0);
  if (weights) {
    const std::string ww = wb + " <weights>";
    check_ascii(*weights, ww);
    w = xml_numbers(*weights, ww);
    if (static_cast<long>(w.size()) != n)
      fail(ww, "has " + std::to_string(w.size()) + " weights; the basis has " + dims + " functions");
    for (long a = 0; a < n; ++a)
      if (!(w[a] > 0)) fail(ww, "weight " + std::to_string(a) + " is " + fmt(w[a]) + "; weights must be > 0");
  }
  P.cp.resize(n);
  for (long a = 0; a < n; ++a) P.cp[a] = {coef(a, 0), coef(a, 1), w[a]};
  const std::string bad = P.validate();
  if (!bad.empty()) fail(where, bad);
  return P;
}

// Teuchos reports "XML parse error at line N: what" as the last line of a longer message.
[[noreturn]] void xml_syntax_error(const std::string& path, const std::string& message) {
  std::string last;
  std::istringstream is(message);
  for (std::string l; std::getline(is, l);)
    if (!trim(l).empty()) last = trim(l);
  const std::string tag = "XML parse error at line ";
  if (last.rfind(tag, 0) == 0) {
    size_t k = tag.size();
    while (k < last.size() && std::isdigit(static_cast<unsigned char>(last[k]))) ++k;
    const std::string line = last.substr(tag.size(), k - tag.size());
    std::string what = last.substr(k);
    if (what.rfind(": ", 0) == 0) what = what.substr(2);
    throw InputError(path + ":" + line + ": XML syntax error: " + what);
  }
  if (last.find("empty XML") != std::string::npos) fail(path, "XML syntax error: the file has no root element");
  fail(path, "XML syntax error: " + last);
}

// Reads a <MultiPatch>'s topology into mp (its patches already read; position: Geometry id -> patch).
void read_xml_topology(const XMLObject& m, const std::string& where,
                       const std::map<long, int>& position, const std::string& id_list, MultiPatch& mp) {
  TopologyCheck topo;
  auto patch_of = [&](const std::string& tok, const std::string& w) {
    long id;
    if (!to_int(tok, id)) fail(w, quote(tok) + " is not an integer patch id");
    auto it = position.find(id);
    if (it == position.end())
      fail(w, "patch id " + std::to_string(id) + " is not a patch of this multipatch (its <patches>: " + id_list + ")");
    return it->second;
  };
  auto side_of = [&](const std::string& tok, const std::string& w) {
    long s;
    if (!to_int(tok, s)) fail(w, quote(tok) + " is not an integer side");
    if (s < 1 || s > 4) fail(w, "side " + std::to_string(s) + " is out of range 1..4 (west, east, south, north)");
    return side_of_number(s);
  };
  auto flag_of = [&](const std::string& tok, const std::string& w, const char* what) {
    long f;
    if (!to_int(tok, f) || (f != 0 && f != 1)) fail(w, std::string(what) + " " + quote(tok) + " is not 0 or 1");
    return static_cast<int>(f);
  };

  int count = 0;
  for (const XMLObject* x : children(m, "interfaces")) {
    const std::string wi = where + " <interfaces>";
    const auto lines = content_lines(*x);
    // G+Smo writes 8 numbers per 2-D interface: patch side patch side, the direction map (2)
    // and the orientation flags (2). Its older files have 5: patch side patch side flag.
    const bool legacy = !lines.empty() && std::all_of(lines.begin(), lines.end(),
                                                      [](const auto& l) { return l.size() == 5; });
    std::vector<std::vector<std::string>> entries;
    if (legacy) {
      entries = lines;
    } else {
      std::vector<std::string> all;
      for (const auto& l : lines) all.insert(all.end(), l.begin(), l.end());
      if (all.size() % 8 != 0)
        fail(wi, "has " + std::to_string(all.size()) +
                     " numbers; each 2-D interface takes 8 (patch side patch side, direction map (2), orientation (2))");
      for (size_t k = 0; k < all.size(); k += 8) entries.emplace_back(all.begin() + k, all.begin() + k + 8);
    }
    for (const auto& e : entries) {
      ++count;
      std::string text;
      for (const auto& t : e) text += (text.empty() ? "" : " ") + t;
      const std::string label = "interface " + std::to_string(count) + " (" + text + ")";
      const std::string w = wi + ": " + label;
      Interface f;
      f.a = {patch_of(e[0], w), side_of(e[1], w)};
      f.b = {patch_of(e[2], w), side_of(e[3], w)};
      const int t1 = 1 - side_direction(f.a.side), t2 = 1 - side_direction(f.b.side);
      if (legacy) {
        long o;
        if (!to_int(e[4], o)) fail(w, "orientation " + quote(e[4]) + " is not an integer");
        f.reversed = !(o > 0);   // G+Smo's old reader: orient = (k > 0)
      } else {
        const int map0 = flag_of(e[4], w, "direction map entry"), map1 = flag_of(e[5], w, "direction map entry");
        const int o[2] = {flag_of(e[6], w, "orientation flag"), flag_of(e[7], w, "orientation flag")};
        const int map[2] = {map0, map1};
        if (map0 == map1) fail(w, "the direction map (" + e[4] + " " + e[5] + ") is not a permutation of 0 1");
        if (map[t1] != t2)
          fail(w, "the direction map (" + e[4] + " " + e[5] + ") does not take the direction along " +
                      side_text(f.a) + " (" + std::to_string(t1) + ") to the one along " + side_text(f.b) + " (" +
                      std::to_string(t2) + ")");
        // The flag of the direction along the first side: 1 = same orientation. (G+Smo sets
        // the flag across the sides itself and ignores the file's.)
        f.reversed = o[t1] == 0;
      }
      bool dup = false;
      for (const Interface& g : mp.interfaces)
        dup = dup || (g.a == f.a && g.b == f.b && g.reversed == f.reversed);
      if (dup) continue;   // G+Smo drops repeated interfaces
      topo.interface(f, w, label);
      mp.interfaces.push_back(f);
    }
  }

  for (const XMLObject* x : children(m, "boundary")) {
    const std::string name = trim(attr(*x, "name"));
    const std::string wb = where + (name.empty() ? " <boundary>" : " <boundary name=\"" + name + "\">");
    const auto t = split(content(*x));
    if (t.size() % 2 != 0) fail(wb, "has " + std::to_string(t.size()) + " numbers; expected pairs: patch side");
    for (size_t k = 0; k < t.size(); k += 2) {
      const std::string w = wb + ": entry " + std::to_string(k / 2 + 1) + " (" + t[k] + " " + t[k + 1] + ")";
      const PatchSide s{patch_of(t[k], w), side_of(t[k + 1], w)};
      topo.boundary(s, w);
      add_unique(mp.boundary, s);
      if (!name.empty()) add_named(mp, name, s);
    }
  }
}

// ---------------------------------------------------------------------------------------------
// GeoPDEs text

class TextLines {
 public:
  TextLines(std::string path, const std::string& text) : path_(std::move(path)) {
    std::istringstream is(text);
    for (std::string l; std::getline(is, l);) {
      if (!l.empty() && l.back() == '\r') l.pop_back();
      lines_.push_back(l);
    }
  }
  // Next data line (not blank, not a '#' comment): its text and 1-based line number.
  bool next(std::string& s, int& line) {
    while (pos_ < lines_.size()) {
      const std::string t = trim(lines_[pos_++]);
      if (t.empty() || t[0] == '#') continue;
      s = t;
      line = static_cast<int>(pos_);
      return true;
    }
    return false;
  }
  std::string need(const std::string& what, int& line) {
    std::string s;
    if (!next(s, line)) fail(last(), "the file ends before " + what + " (truncated?)");
    return s;
  }
  std::string at(int line) const { return path_ + ":" + std::to_string(line); }
  std::string last() const { return at(std::max<int>(1, static_cast<int>(lines_.size()))); }
  const std::vector<std::string>& raw() const { return lines_; }

 private:
  std::string path_;
  std::vector<std::string> lines_;
  size_t pos_ = 0;
};

bool numeric_line(const std::string& s) {
  const auto t = split(s);
  double d;
  return !t.empty() && to_double(t[0], d);
}

// The numbers of a line, each read by `read` (to_double or to_int; `kind` names it in the
// message), count of them when count > 0.
template <class T>
std::vector<T> line_values(const TextLines& in, const std::string& s, int line, const std::string& what, size_t count,
                           bool (*read)(const std::string&, T&), const char* kind) {
  std::vector<T> v;
  for (const std::string& t : split(s)) {
    T x;
    if (!read(t, x)) fail(in.at(line), quote(t) + " is not " + kind + " (" + what + ")");
    v.push_back(x);
  }
  if (count && v.size() != count)
    fail(in.at(line), what + ": " + std::to_string(v.size()) + " values, expected " + std::to_string(count));
  return v;
}

std::vector<double> line_numbers(const TextLines& in, const std::string& s, int line, const std::string& what,
                                 size_t count) {
  return line_values<double>(in, s, line, what, count, to_double, "a number");
}

std::vector<long> line_ints(const TextLines& in, const std::string& s, int line, const std::string& what,
                            size_t count) {
  return line_values<long>(in, s, line, what, count, to_int, "an integer");
}

std::string boundary_name(const std::string& line, int k) {
  const auto t = split(line);
  long dummy;
  if (!t.empty() && lower(t[0]) == "boundary" && (t.size() == 1 || (t.size() == 2 && to_int(t[1], dummy))))
    return "boundary" + std::to_string(k);
  std::string name;
  for (const auto& w : t) name += (name.empty() ? "" : "_") + w;
  return name;
}

}  // namespace

// =============================================================================================

MultiPatch read_gismo_xml(const std::string& path) {
  const std::string text = read_file_text(path);
  XMLObject root;
  try {
    Teuchos::StringInputSource src(text);
    root = src.getObject();
  } catch (const std::exception& e) {
    xml_syntax_error(path, e.what());
  }
  if (root.getTag() != "xml") fail(path, "the root element is <" + root.getTag() + ">, a G+Smo file has <xml>");

  const auto geoms = children(root, "Geometry");
  const XMLObject* m = first_child(root, "MultiPatch");
  MultiPatch mp;
  if (!m) {
    // No topology: every Geometry, in file order, is a patch.
    if (geoms.empty()) fail(path, "no <Geometry> and no <MultiPatch> in <xml>: nothing to read");
    for (size_t k = 0; k < geoms.size(); ++k)
      mp.patches.push_back(read_xml_patch(*geoms[k], path + ": " + geometry_label(*geoms[k], static_cast<int>(k))));
    return mp;
  }

  const std::string where =
      path + ": " + (m->hasAttribute("id") ? "<MultiPatch id=\"" + m->getAttribute("id") + "\">" : "<MultiPatch>");
  if (!m->hasAttribute("parDim")) fail(where, "missing the parDim attribute");
  if (trim(m->getAttribute("parDim")) != "2")
    fail(where, "parDim=" + quote(m->getAttribute("parDim")) + ": igacontact reads 2-D multipatches (parDim=\"2\")");

  // Geometry ids (siblings of the MultiPatch, as G+Smo looks them up).
  std::map<long, const XMLObject*> by_id;
  for (size_t k = 0; k < geoms.size(); ++k) {
    if (!geoms[k]->hasAttribute("id")) continue;
    long id;
    const std::string label = path + ": " + geometry_label(*geoms[k], static_cast<int>(k));
    if (!to_int(trim(geoms[k]->getAttribute("id")), id)) fail(label, "the id is not an integer");
    if (by_id.count(id)) fail(label, "a second <Geometry> with this id");
    by_id[id] = geoms[k];
  }

  const std::string wp = where + " <patches>";
  const XMLObject& pl = need_child(*m, "patches", where);
  const std::string type = attr(pl, "type");
  std::vector<long> ids;
  const auto tok = split(content(pl));
  for (const auto& t : tok) {
    long id;
    if (!to_int(t, id)) fail(wp, quote(t) + " is not an integer Geometry id");
    ids.push_back(id);
  }
  std::string id_list;
  if (type == "id_range") {
    if (ids.size() != 2) fail(wp, "type=\"id_range\" takes two ids, first and last; found " + std::to_string(ids.size()));
    if (ids[0] > ids[1]) fail(wp, "the range " + tok[0] + " " + tok[1] + " is empty (first > last)");
    if (ids[1] - ids[0] >= 100000) fail(wp, "the range " + tok[0] + " " + tok[1] + " is too long");
    id_list = "ids " + tok[0] + ".." + tok[1];
    const long a = ids[0], b = ids[1];
    ids.clear();
    for (long id = a; id <= b; ++id) ids.push_back(id);
  } else if (type == "id_index") {
    if (ids.empty()) fail(wp, "type=\"id_index\" lists no Geometry id");
    id_list = "ids";
    for (size_t k = 0; k < ids.size() && k < 12; ++k) id_list += " " + tok[k];
    if (ids.size() > 12) id_list += " ...";
  } else {
    fail(wp, "type=" + quote(type) + ": expected \"id_range\" or \"id_index\"");
  }

  std::map<long, int> position;
  for (long id : ids) {
    if (position.count(id)) fail(wp, "Geometry id " + std::to_string(id) + " is listed twice");
    auto it = by_id.find(id);
    if (it == by_id.end()) fail(wp, "no <Geometry> with id=\"" + std::to_string(id) + "\" in the file");
    position[id] = static_cast<int>(mp.patches.size());
    mp.patches.push_back(read_xml_patch(*it->second, path + ": <Geometry id=\"" + std::to_string(id) + "\">"));
  }
  read_xml_topology(*m, where, position, id_list, mp);
  return mp;
}

MultiPatch read_geopdes(const std::string& path) {
  TextLines in(path, read_file_text(path));

  // Header: comment lines, one of them "# nurbs mesh v.2.1" (nrbexport) or "# nurbs geometry
  // v.2.1" (GeoPDEs' specification); then "ndim rdim npatches ninterfaces nsubdomains".
  std::string version;
  int version_line = 0;
  for (size_t k = 0; k < in.raw().size(); ++k) {
    const std::string t = trim(in.raw()[k]);
    if (t.empty()) continue;
    if (t[0] != '#') break;
    const std::string c = lower(trim(t.substr(1)));
    const size_t v = c.find(" v.");
    if (version.empty() && c.rfind("nurbs", 0) == 0 && v != std::string::npos) {
      version = split(c.substr(v + 3)).empty() ? "" : split(c.substr(v + 3))[0];
      version_line = static_cast<int>(k + 1);
    }
  }
  std::string s;
  int line = 0;
  if (!in.next(s, line)) fail(in.last(), "no data: a GeoPDEs file starts with '# nurbs mesh v.2.1' and a line 'ndim rdim npatches ninterfaces nsubdomains'");
  if (version.empty())
    fail(in.at(line), "no version header before the first data line; a GeoPDEs v2.1 file starts with '# nurbs mesh v.2.1'");
  if (version != "2.1")
    fail(in.at(version_line), "GeoPDEs format version " + version + " is not supported: igacontact reads v.2.1 (nrbexport's default)");

  const int head_line = line;
  const auto head = line_ints(in, s, line, "ndim rdim npatches ninterfaces nsubdomains", 0);
  if (head.empty() || head.size() > 5)
    fail(in.at(line), "expected 'ndim rdim npatches ninterfaces nsubdomains' (1 to 5 integers), found " +
                          std::to_string(head.size()));
  const long ndim = head[0];
  if (ndim != 2)
    fail(in.at(line), "ndim = " + std::to_string(ndim) + ": igacontact reads 2-D parametric patches (ndim = 2)" +
                          (ndim == 3 ? ", not volumes" : ""));
  const long rdim = head.size() > 1 ? head[1] : ndim;
  if (rdim != 2 && rdim != 3)
    fail(in.at(line), "rdim = " + std::to_string(rdim) + ": the physical dimension must be 2 (or 3 with z = 0)");
  const long np = head.size() > 2 ? head[2] : 1;
  const long ni = head.size() > 3 ? head[3] : 0;
  const long ns = head.size() > 4 ? head[4] : 0;
  if (np < 1 || np > 100000) fail(in.at(line), "npatches = " + std::to_string(np) + " is out of range 1..100000");
  if (ni < 0 || ns < 0) fail(in.at(line), "negative number of interfaces or subdomains");

  MultiPatch mp;
  const char* dir_name[2] = {"u", "v"};
  for (long k = 1; k <= np; ++k) {
    const std::string pk = "patch " + std::to_string(k);
    s = in.need("the degrees of " + pk, line);
    const int start = line;
    if (!numeric_line(s)) s = in.need("the degrees of " + pk, line);   // the optional name, e.g. "PATCH 1"
    Patch P;
    const auto deg = line_ints(in, s, line, pk + " degrees", 2);
    for (int d = 0; d < 2; ++d) {
      if (deg[d] < 1)
        fail(in.at(line), pk + ": degree " + std::to_string(deg[d]) + " in " + dir_name[d] + ": the degree must be at least 1");
      if (deg[d] > 1000) fail(in.at(line), pk + ": degree " + std::to_string(deg[d]) + " in " + dir_name[d] + " is too high");
      P.degree[d] = static_cast<int>(deg[d]);   // Patch::validate() checks the supported range
    }
    s = in.need("the numbers of control points of " + pk, line);
    const auto ncp = line_ints(in, s, line, pk + " numbers of control points", 2);
    for (int d = 0; d < 2; ++d) {
      if (ncp[d] < deg[d] + 1)
        fail(in.at(line), pk + ": " + std::to_string(ncp[d]) + " control points in " + dir_name[d] + "; degree " +
                              std::to_string(deg[d]) + " needs at least " + std::to_string(deg[d] + 1));
      if (ncp[d] > 1000000) fail(in.at(line), pk + ": " + std::to_string(ncp[d]) + " control points in " + dir_name[d] + " is too many");
    }
    for (int d = 0; d < 2; ++d) {
      const std::string what = pk + " knots in " + dir_name[d];
      s = in.need("the " + what, line);
      P.knots[d] = line_numbers(in, s, line, what, static_cast<size_t>(ncp[d] + deg[d] + 1));
      const std::string bad = check_knots(P.knots[d], P.degree[d]);
      if (!bad.empty()) fail(in.at(line), what + ": " + bad);
    }
    const size_t n = static_cast<size_t>(ncp[0] * ncp[1]);
    std::vector<double> coord[3];
    int coord_line[3] = {0, 0, 0};
    const char* cname[3] = {"x", "y", "z"};
    for (int c = 0; c < rdim; ++c) {
      const std::string what = pk + " " + cname[c] + " coordinates (w " + cname[c] + ")";
      s = in.need("the " + what, line);
      coord[c] = line_numbers(in, s, line, what, n);
      coord_line[c] = line;
    }
    s = in.need("the weights of " + pk, line);
    const auto w = line_numbers(in, s, line, pk + " weights", n);
    for (size_t a = 0; a < n; ++a)
      if (!(w[a] > 0)) fail(in.at(line), pk + ": weight " + std::to_string(a + 1) + " is " + fmt(w[a]) + "; weights must be > 0");
    if (rdim == 3)
      for (size_t a = 0; a < n; ++a)
        if (std::abs(coord[2][a]) > kZeroZ)
          fail(in.at(coord_line[2]), pk + ": control point " + std::to_string(a + 1) + " has z = " + fmt(coord[2][a] / w[a]) +
                                         "; igacontact is 2-D, z must be 0");
    // Homogeneous (w x, w y, w) to Euclidean.
    P.cp.resize(n);
    for (size_t a = 0; a < n; ++a) P.cp[a] = {coord[0][a] / w[a], coord[1][a] / w[a], w[a]};
    const std::string bad = P.validate();
    if (!bad.empty()) fail(in.at(start), pk + ": " + bad);
    mp.patches.push_back(std::move(P));
  }

  // A PATCH, INTERFACE or SUBDOMAIN block where the header's counts say none is left.
  const std::string header_line = "line " + std::to_string(head_line);
  auto unexpected_block = [&](const std::string& text, int at, std::initializer_list<const char*> kinds) {
    const std::string first = lower(split(text)[0]);
    const long declared[3] = {np, ni, ns};
    const char* count[3] = {"npatches", "ninterfaces", "nsubdomains"};
    const char* all[3] = {"patch", "interface", "subdomain"};
    for (const char* k : kinds)
      for (int j = 0; j < 3; ++j)
        if (first == k && first == all[j])
          fail(in.at(at), quote(text) + ": more " + all[j] + " blocks than the header declares (" + count[j] + " = " +
                              std::to_string(declared[j]) + " at " + header_line + ")");
  };
  TopologyCheck topo;
  auto patch_side = [&](const std::string& what) {
    s = in.need("the " + what, line);
    const auto v = line_ints(in, s, line, what + " (patch side)", 2);
    if (v[0] < 1 || v[0] > np)
      fail(in.at(line), what + ": patch " + std::to_string(v[0]) + " does not exist (patches 1.." + std::to_string(np) + ")");
    if (v[1] < 1 || v[1] > 4)
      fail(in.at(line), what + ": side " + std::to_string(v[1]) + " is out of range 1..4 (u = 0, u = 1, v = 0, v = 1)");
    return PatchSide{static_cast<int>(v[0] - 1), side_of_number(v[1])};
  };
  for (long i = 1; i <= ni; ++i) {
    const std::string ik = "interface " + std::to_string(i);
    s = in.need("the name line of " + ik + " (e.g. 'INTERFACE " + std::to_string(i) + "')", line);
    if (numeric_line(s)) fail(in.at(line), "expected the name line of " + ik + " (e.g. 'INTERFACE " + std::to_string(i) + "'), found numbers");
    unexpected_block(s, line, {"patch"});
    const int start = line;
    Interface f;
    f.a = patch_side(ik + " first side");
    f.b = patch_side(ik + " second side");
    s = in.need("the orientation of " + ik, line);
    const auto o = line_ints(in, s, line, ik + " orientation", 1);
    if (o[0] != 1 && o[0] != -1)
      fail(in.at(line), ik + ": orientation " + std::to_string(o[0]) + " must be 1 (same direction) or -1 (reversed)");
    f.reversed = o[0] == -1;
    topo.interface(f, in.at(start) + ": " + ik, ik + " (line " + std::to_string(start) + ")");
    mp.interfaces.push_back(f);
  }
  for (long k = 1; k <= ns; ++k) {
    const std::string sk = "subdomain " + std::to_string(k);
    s = in.need("the name line of " + sk + " (e.g. 'SUBDOMAIN " + std::to_string(k) + "')", line);
    if (numeric_line(s)) fail(in.at(line), "expected the name line of " + sk + ", found numbers");
    unexpected_block(s, line, {"patch", "interface"});
    s = in.need("the patches of " + sk, line);
    for (long p : line_ints(in, s, line, sk + " patches", 0))
      if (p < 1 || p > np)
        fail(in.at(line), sk + ": patch " + std::to_string(p) + " does not exist (patches 1.." + std::to_string(np) + ")");
  }
  int nb = 0;
  while (in.next(s, line)) {
    ++nb;
    const std::string bk = "boundary " + std::to_string(nb);
    if (numeric_line(s))
      fail(in.at(line), "expected the name line of " + bk + " (e.g. 'BOUNDARY " + std::to_string(nb) + "'), found numbers");
    unexpected_block(s, line, {"patch", "interface", "subdomain"});
    const std::string name = boundary_name(s, nb);
    s = in.need("the number of sides of " + bk, line);
    const auto cnt = line_ints(in, s, line, bk + " number of sides", 1);
    if (cnt[0] < 0 || cnt[0] > 4 * np)
      fail(in.at(line), bk + ": " + std::to_string(cnt[0]) + " sides is out of range 0.." + std::to_string(4 * np));
    for (long j = 1; j <= cnt[0]; ++j) {
      const PatchSide ps = patch_side(bk + " side " + std::to_string(j));
      topo.boundary(ps, in.at(line) + ": " + bk);
      add_unique(mp.boundary, ps);
      add_named(mp, name, ps);
    }
  }
  // GeoPDEs (mp_geo_read_nurbs) gives a single patch without boundaries its four sides.
  if (nb == 0 && np == 1)
    for (int k = 0; k < 4; ++k) {
      const PatchSide ps{0, static_cast<Side>(k)};
      mp.boundary.push_back(ps);
      mp.named.push_back({"boundary" + std::to_string(k + 1), {ps}});
    }
  return mp;
}

MultiPatch read_geometry_file(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  const size_t dot = path.find_last_of('.');
  const std::string ext = (dot == std::string::npos || (slash != std::string::npos && dot < slash)) ? "" : lower(path.substr(dot));
  if (ext == ".xml") return read_gismo_xml(path);
  if (ext == ".txt") return read_geopdes(path);
  fail(path, (ext.empty() ? std::string("no file extension") : "unknown extension " + quote(path.substr(dot))) +
                 ": a geometry file is .xml (G+Smo) or .txt (GeoPDEs)");
}

// =============================================================================================

std::string gismo_xml_text(const std::vector<const MultiPatch*>& multipatches) {
  auto error = [&](const std::string& what) { throw std::runtime_error("G+Smo XML: " + what); };
  auto escape = [](const std::string& s) {
    std::string o;
    for (char c : s) {
      if (c == '&') o += "&amp;";
      else if (c == '<') o += "&lt;";
      else if (c == '>') o += "&gt;";
      else if (c == '"') o += "&quot;";
      else o += c;
    }
    return o;
  };

  std::ostringstream os;
  os << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
     << "<!--Written by igacontact: G+Smo geometry (TensorBSpline2 / TensorNurbs2, Euclidean coefs)-->\n"
     << "<xml>\n";
  std::vector<int> first(multipatches.size(), 0);
  int id = 0;
  for (size_t m = 0; m < multipatches.size(); ++m) {
    const MultiPatch* mp = multipatches[m];
    if (!mp) error("multipatch " + std::to_string(m) + " is null");
    if (mp->patches.empty()) error("multipatch " + std::to_string(m) + " has no patches");
    first[m] = id;
    for (size_t k = 0; k < mp->patches.size(); ++k, ++id) {
      const Patch& P = mp->patches[k];
      const std::string bad = P.validate();
      if (!bad.empty()) error("multipatch " + std::to_string(m) + ", patch " + std::to_string(k) + ": " + bad);
      const bool rational = std::any_of(P.cp.begin(), P.cp.end(), [](const Point3& c) { return c[2] != 1.0; });
      const std::string in = rational ? "   " : "  ";
      os << " <Geometry type=\"" << (rational ? "TensorNurbs2" : "TensorBSpline2") << "\" id=\"" << id << "\">\n";
      if (rational) os << "  <Basis type=\"TensorNurbsBasis2\">\n";
      os << in << "<Basis type=\"TensorBSplineBasis2\">\n";
      for (int d = 0; d < 2; ++d) {
        os << in << " <Basis type=\"BSplineBasis\" index=\"" << d << "\">\n"
           << in << "  <KnotVector degree=\"" << P.degree[d] << "\">";
        os << number_row(P.knots[d]) << "</KnotVector>\n" << in << " </Basis>\n";
      }
      os << in << "</Basis>\n";
      if (rational) {
        os << "   <weights>\n";
        for (const Point3& c : P.cp) os << fmt(c[2]) << "\n";
        os << "</weights>\n  </Basis>\n";
      }
      os << "  <coefs geoDim=\"2\">\n";
      for (const Point3& c : P.cp) os << fmt(c[0]) << " " << fmt(c[1]) << "\n";
      os << "</coefs>\n </Geometry>\n";
    }
  }
  for (size_t m = 0; m < multipatches.size(); ++m) {
    const MultiPatch& mp = *multipatches[m];
    const int np = static_cast<int>(mp.patches.size());
    auto check = [&](const PatchSide& s, const std::string& what) {
      const std::string bad = side_out_of_range(s, np);
      if (!bad.empty()) error("multipatch " + std::to_string(m) + ": " + what + " " + bad);
    };
    auto ps = [&](const PatchSide& s) { return std::to_string(first[m] + s.patch) + " " + std::to_string(number_of_side(s.side)); };
    os << " <MultiPatch parDim=\"2\" id=\"" << id++ << "\">\n"
       << "  <patches type=\"id_range\">" << first[m] << " " << first[m] + np - 1 << "</patches>\n";
    if (!mp.interfaces.empty()) {
      os << "  <interfaces>\n";
      for (const Interface& f : mp.interfaces) {
        check(f.a, "an interface");
        check(f.b, "an interface");
        // G+Smo's 2-D boundaryInterface: the direction across the first side maps to the one
        // across the second (flag: same parameter value), the one along it to the one along
        // the second (flag: same orientation).
        const int d1 = side_direction(f.a.side), d2 = side_direction(f.b.side);
        int map[2], orient[2];
        map[d1] = d2;
        map[1 - d1] = 1 - d2;
        orient[d1] = side_parameter(f.a.side) == side_parameter(f.b.side);
        orient[1 - d1] = !f.reversed;
        os << ps(f.a) << " " << ps(f.b) << " " << map[0] << " " << map[1] << " " << orient[0] << " " << orient[1] << "\n";
      }
      os << "</interfaces>\n";
    }
    // Boundary sides in their order, each once (G+Smo keeps one label per side): runs of
    // sides with the same name (a side's first named group, or none) as one <boundary>
    // element each; then what a group holds beyond that (sides of a second group, or not
    // in mp.boundary). Reading the file back gives mp.boundary and mp.named again, the sides
    // of a group in mp.boundary's order.
    for (const auto& [name, sides] : mp.named) {
      if (trim(name).empty()) error("multipatch " + std::to_string(m) + " has a named boundary without a name");
      for (const PatchSide& s : sides) check(s, "boundary \"" + name + "\"");
    }
    auto name_of = [&](const PatchSide& s) -> const std::string* {
      for (const auto& g : mp.named)
        if (std::find(g.second.begin(), g.second.end(), s) != g.second.end()) return &g.first;
      return nullptr;
    };
    auto open_element = [&](const std::string* name) {
      os << (name ? "  <boundary name=\"" + escape(*name) + "\">\n" : std::string("  <boundary>\n"));
    };
    std::vector<std::pair<const std::string*, PatchSide>> written;
    const std::string* run = nullptr;
    for (size_t k = 0; k < mp.boundary.size(); ++k) {
      const PatchSide& s = mp.boundary[k];
      check(s, "the boundary");
      const std::string* name = name_of(s);
      if (k == 0 || name != run) {
        if (k > 0) os << "</boundary>\n";
        open_element(name);
        run = name;
      }
      os << ps(s) << "\n";
      if (name) written.push_back({name, s});
    }
    if (!mp.boundary.empty()) os << "</boundary>\n";
    for (const auto& g : mp.named) {
      bool open = false;
      for (const PatchSide& s : g.second) {
        bool done = false;
        for (const auto& w : written) done = done || (*w.first == g.first && w.second == s);
        if (done) continue;
        if (!open) open_element(&g.first);
        open = true;
        os << ps(s) << "\n";
      }
      if (open) os << "</boundary>\n";
    }
    os << " </MultiPatch>\n";
  }
  os << "</xml>\n";
  return os.str();
}

std::string geopdes_text(const MultiPatch& mp) {
  auto error = [&](const std::string& what) { throw std::runtime_error("GeoPDEs text: " + what); };
  if (mp.patches.empty()) error("the multipatch has no patches");
  const int np = static_cast<int>(mp.patches.size());
  auto check = [&](const PatchSide& s, const std::string& what) {
    const std::string bad = side_out_of_range(s, np);
    if (!bad.empty()) error(what + " " + bad);
  };
  auto ps = [](const PatchSide& s) { return std::to_string(s.patch + 1) + " " + std::to_string(number_of_side(s.side)); };
  // Boundary blocks: each named group with the sides not already written (GeoPDEs gives a side
  // one boundary), then the remaining outer sides as one unnamed block.
  std::vector<std::pair<std::string, std::vector<PatchSide>>> blocks;
  std::vector<PatchSide> done;
  for (const auto& [name, sides] : mp.named) {
    if (trim(name).empty() || name.find_first_of("\n\r") != std::string::npos) error("a named boundary has no usable name");
    std::vector<PatchSide> left;
    for (const PatchSide& s : sides) {
      check(s, "boundary \"" + name + "\"");
      if (std::find(done.begin(), done.end(), s) == done.end()) { left.push_back(s); done.push_back(s); }
    }
    if (!left.empty()) blocks.push_back({name, left});
  }
  std::vector<PatchSide> rest;
  for (const PatchSide& s : mp.boundary) {
    check(s, "the boundary");
    if (std::find(done.begin(), done.end(), s) == done.end()) { rest.push_back(s); done.push_back(s); }
  }
  if (!rest.empty()) blocks.push_back({"BOUNDARY " + std::to_string(blocks.size() + 1), rest});

  std::ostringstream os;
  os << "# nurbs mesh v.2.1\n"
     << "# Written by igacontact: GeoPDEs multipatch text; coordinate rows are homogeneous (w x, w y)\n"
     << "2 2 " << np << " " << mp.interfaces.size() << " 0\n";
  for (int k = 0; k < np; ++k) {
    const Patch& P = mp.patches[k];
    const std::string bad = P.validate();
    if (!bad.empty()) error("patch " + std::to_string(k) + ": " + bad);
    os << "PATCH " << k + 1 << "\n" << P.degree[0] << " " << P.degree[1] << "\n"
       << P.knots[0].size() - P.degree[0] - 1 << " " << P.knots[1].size() - P.degree[1] - 1 << "\n";
    for (int d = 0; d < 2; ++d) os << number_row(P.knots[d]) << "\n";
    for (int c = 0; c < 3; ++c) {   // w x, w y, then w
      for (size_t a = 0; a < P.cp.size(); ++a) os << (a ? " " : "") << fmt(c < 2 ? P.cp[a][c] * P.cp[a][2] : P.cp[a][2]);
      os << "\n";
    }
  }
  for (size_t i = 0; i < mp.interfaces.size(); ++i) {
    const Interface& f = mp.interfaces[i];
    check(f.a, "an interface");
    check(f.b, "an interface");
    os << "INTERFACE " << i + 1 << "\n" << ps(f.a) << "\n" << ps(f.b) << "\n" << (f.reversed ? -1 : 1) << "\n";
  }
  for (const auto& [name, sides] : blocks) {
    os << name << "\n" << sides.size() << "\n";
    for (const PatchSide& s : sides) os << ps(s) << "\n";
  }
  return os.str();
}

}  // namespace iga
