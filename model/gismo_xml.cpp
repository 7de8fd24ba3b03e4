// G+Smo XML geometry files: the reader (through Teuchos' XML parser) and the writer.
// Conventions in docs/geometry-files.md and at the top of model/geometry_common.cpp.
#include "model/geometry_file.hpp"
#include "model/geometry_common.hpp"

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

using namespace geometry_io;

namespace {

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
  const bool nurbs = type == "TensorNurbs2" || type == "TensorNurbs3";
  if (!nurbs && type != "TensorBSpline2" && type != "TensorBSpline3")
    fail(where, "unsupported type=" + quote(type) +
                    " (igacontact reads tensor patches: TensorBSpline2, TensorNurbs2, TensorBSpline3, TensorNurbs3)");
  const int dim = type.back() == '3' ? 3 : 2;
  const std::string D = std::to_string(dim);

  if (first_child(g, "transform"))
    fail(where, "<transform> is not supported (apply the transformation to the coefs)");

  // Basis: TensorNurbsBasis<D> { TensorBSplineBasis<D>, weights } or TensorBSplineBasis<D>.
  const std::string wb = where + " <Basis>";
  const XMLObject& basis = need_child(g, "Basis", where);
  const XMLObject* tensor = &basis;
  const XMLObject* weights = nullptr;
  if (nurbs) {
    if (attr(basis, "type") != "TensorNurbsBasis" + D)
      fail(wb, "type=" + quote(attr(basis, "type")) + ", a TensorNurbs" + D + " needs \"TensorNurbsBasis" + D + "\"");
    tensor = &need_child(basis, "Basis", wb);
    weights = &need_child(basis, "weights", wb);
  }
  const std::string wt = nurbs ? wb + " <Basis>" : wb;
  if (attr(*tensor, "type") != "TensorBSplineBasis" + D)
    fail(wt, "type=" + quote(attr(*tensor, "type")) + ", expected \"TensorBSplineBasis" + D + "\"");
  const auto comps = children(*tensor, "Basis");
  if (static_cast<int>(comps.size()) != dim)
    fail(wt, "has " + std::to_string(comps.size()) + " <Basis> children; a " + D + "-D tensor basis has " + D);

  Patch P;
  P.pdim = dim;
  bool seen[3] = {false, false, false};
  for (int k = 0; k < dim; ++k) {
    int d = k;
    if (comps[k]->hasAttribute("index")) {
      long idx;
      if (!to_int(trim(comps[k]->getAttribute("index")), idx) || idx < 0 || idx >= dim)
        fail(wt, "<Basis index=" + quote(comps[k]->getAttribute("index")) + ">: index must be " + (dim == 2 ? "0 or 1" : "0, 1 or 2"));
      d = static_cast<int>(idx);
    }
    if (seen[d]) fail(wt, "two <Basis> children for direction " + std::to_string(d));
    seen[d] = true;
    read_xml_knots(*comps[k], wt + " <Basis index=\"" + std::to_string(d) + "\">", P.degree[d], P.knots[d]);
  }
  const long n0 = P.ncp(0), n1 = P.ncp(1), n2 = P.ncp(2), n = n0 * n1 * n2;
  const std::string dims = std::to_string(n0) + " x " + std::to_string(n1) + (dim == 3 ? " x " + std::to_string(n2) : std::string()) +
                           " = " + std::to_string(n);

  // coefs: one row per basis function (x y [z]), Euclidean.
  const std::string wc = where + " <coefs>";
  const XMLObject& coefs = need_child(g, "coefs", where);
  if (!coefs.hasAttribute("geoDim")) fail(wc, "missing the geoDim attribute");
  long gd;
  if (dim == 3) {
    if (!to_int(trim(coefs.getAttribute("geoDim")), gd) || gd != 3)
      fail(wc, "geoDim=" + quote(coefs.getAttribute("geoDim")) + ": a " + type + " needs geoDim 3 (x y z)");
  } else if (!to_int(trim(coefs.getAttribute("geoDim")), gd) || (gd != 2 && gd != 3)) {
    fail(wc, "geoDim=" + quote(coefs.getAttribute("geoDim")) + ": igacontact reads geoDim 2 (or 3 with z = 0)");
  }
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
  if (gd == 3 && dim == 2)
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
  for (long a = 0; a < n; ++a)
    P.cp[a] = dim == 3 ? ControlPoint{{coef(a, 0), coef(a, 1), coef(a, 2)}, w[a]} : ControlPoint{{coef(a, 0), coef(a, 1)}, w[a]};
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
void read_xml_topology(const XMLObject& m, const std::string& where, int dim,
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
    if (dim == 2 && (s < 1 || s > 4)) fail(w, "side " + std::to_string(s) + " is out of range 1..4 (west, east, south, north)");
    if (s < 1 || s > 6) fail(w, "side " + std::to_string(s) + " is out of range 1..6 (west, east, south, north, front, back)");
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
    // 3-D: 10 numbers (direction map (3), orientation flags (3)).
    const bool legacy = dim == 2 && !lines.empty() && std::all_of(lines.begin(), lines.end(),
                                                                  [](const auto& l) { return l.size() == 5; });
    const size_t per = 4 + 2 * static_cast<size_t>(dim);
    std::vector<std::vector<std::string>> entries;
    if (legacy) {
      entries = lines;
    } else {
      std::vector<std::string> all;
      for (const auto& l : lines) all.insert(all.end(), l.begin(), l.end());
      if (all.size() % per != 0)
        fail(wi, "has " + std::to_string(all.size()) + " numbers; each " + std::to_string(dim) + "-D interface takes " +
                     std::to_string(per) + " (patch side patch side, direction map (" + std::to_string(dim) +
                     "), orientation (" + std::to_string(dim) + "))");
      for (size_t k = 0; k < all.size(); k += per) entries.emplace_back(all.begin() + k, all.begin() + k + per);
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
      const int t1 = side_tangent_direction(f.a.side), t2 = side_tangent_direction(f.b.side);
      if (dim == 3) {
        // G+Smo's boundaryInterface: direction d of the first patch runs along direction map[d]
        // of the second, in the same sense where the flag is 1. The entries of the direction
        // across the faces G+Smo sets itself (the flag from the sides); the map must take it
        // to the direction across the second face.
        int map[3], o[3];
        std::string mtext;
        for (int d = 0; d < 3; ++d) {
          long v;
          if (!to_int(e[4 + d], v) || v < 0 || v > 2) fail(w, "direction map entry " + quote(e[4 + d]) + " is not 0, 1 or 2");
          map[d] = static_cast<int>(v);
          o[d] = flag_of(e[7 + d], w, "orientation flag");
          mtext += (d ? " " : "") + e[4 + d];
        }
        if (map[0] == map[1] || map[0] == map[2] || map[1] == map[2])
          fail(w, "the direction map (" + mtext + ") is not a permutation of 0 1 2");
        const int da = side_direction(f.a.side), db = side_direction(f.b.side);
        if (map[da] != db)
          fail(w, "the direction map (" + mtext + ") does not take the direction across " + side_text(f.a) + " (" +
                      std::to_string(da) + ") to the one across " + side_text(f.b) + " (" + std::to_string(db) + ")");
        const auto fa = face_directions(f.a.side), fb = face_directions(f.b.side);
        for (int k = 0; k < 2; ++k) {
          f.face_map[k] = map[fa[k]] == fb[0] ? 0 : 1;
          f.face_flip[k] = o[fa[k]] == 0;
        }
      } else if (legacy) {
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
        dup = dup || (g.a == f.a && g.b == f.b && g.reversed == f.reversed && g.face_map == f.face_map && g.face_flip == f.face_flip);
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

}  // namespace

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
    for (size_t k = 0; k < geoms.size(); ++k) {
      const std::string label = path + ": " + geometry_label(*geoms[k], static_cast<int>(k));
      mp.patches.push_back(read_xml_patch(*geoms[k], label));
      if (mp.patches.back().dim() != mp.patches.front().dim())
        fail(label, "a " + std::to_string(mp.patches.back().dim()) + "-D patch after " + std::to_string(mp.patches.front().dim()) +
                        "-D ones: the patches of one file have one parametric dimension");
    }
    return mp;
  }

  const std::string where =
      path + ": " + (m->hasAttribute("id") ? "<MultiPatch id=\"" + m->getAttribute("id") + "\">" : "<MultiPatch>");
  if (!m->hasAttribute("parDim")) fail(where, "missing the parDim attribute");
  const std::string pd = trim(m->getAttribute("parDim"));
  if (pd != "2" && pd != "3")
    fail(where, "parDim=" + quote(m->getAttribute("parDim")) + ": igacontact reads 2-D and 3-D multipatches (parDim=\"2\" or \"3\")");
  const int dim = pd == "3" ? 3 : 2;

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
    const std::string label = path + ": <Geometry id=\"" + std::to_string(id) + "\">";
    mp.patches.push_back(read_xml_patch(*it->second, label));
    if (mp.patches.back().dim() != dim)
      fail(label, "a " + std::to_string(mp.patches.back().dim()) + "-D patch in " + where.substr(path.size() + 2) + " of parDim=\"" + pd + "\"");
  }
  read_xml_topology(*m, where, dim, position, id_list, mp);
  return mp;
}

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

  // the parametric dimension of each multipatch (one per multipatch)
  std::vector<int> pdim(multipatches.size(), 2);
  bool any2 = false, any3 = false;
  for (size_t m = 0; m < multipatches.size(); ++m) {
    const MultiPatch* mp = multipatches[m];
    if (!mp || mp->patches.empty()) continue;   // said below
    pdim[m] = mp->patches.front().dim();
    for (size_t k = 0; k < mp->patches.size(); ++k)
      if (mp->patches[k].dim() != pdim[m])
        error("multipatch " + std::to_string(m) + ", patch " + std::to_string(k) + " is " + std::to_string(mp->patches[k].dim()) +
              "-D, its patch 0 " + std::to_string(pdim[m]) + "-D");
    (pdim[m] == 3 ? any3 : any2) = true;
  }

  std::ostringstream os;
  os << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
     << "<!--Written by igacontact: G+Smo geometry ("
     << (any3 ? (any2 ? "TensorBSpline2 / TensorNurbs2 / TensorBSpline3 / TensorNurbs3" : "TensorBSpline3 / TensorNurbs3")
              : "TensorBSpline2 / TensorNurbs2")
     << ", Euclidean coefs)-->\n"
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
      const bool rational = std::any_of(P.cp.begin(), P.cp.end(), [](const ControlPoint& c) { return c.w != 1.0; });
      const std::string in = rational ? "   " : "  ";
      const int dim = P.dim();
      const std::string D = std::to_string(dim);
      os << " <Geometry type=\"" << (rational ? "TensorNurbs" : "TensorBSpline") << D << "\" id=\"" << id << "\">\n";
      if (rational) os << "  <Basis type=\"TensorNurbsBasis" << D << "\">\n";
      os << in << "<Basis type=\"TensorBSplineBasis" << D << "\">\n";
      for (int d = 0; d < dim; ++d) {
        os << in << " <Basis type=\"BSplineBasis\" index=\"" << d << "\">\n"
           << in << "  <KnotVector degree=\"" << P.degree[d] << "\">";
        os << number_row(P.knots[d]) << "</KnotVector>\n" << in << " </Basis>\n";
      }
      os << in << "</Basis>\n";
      if (rational) {
        os << "   <weights>\n";
        for (const ControlPoint& c : P.cp) os << fmt(c.w) << "\n";
        os << "</weights>\n  </Basis>\n";
      }
      os << "  <coefs geoDim=\"" << D << "\">\n";
      for (const ControlPoint& c : P.cp) {
        os << fmt(c.x[0]) << " " << fmt(c.x[1]);
        if (dim == 3) os << " " << fmt(c.x[2]);
        os << "\n";
      }
      os << "</coefs>\n </Geometry>\n";
    }
  }
  for (size_t m = 0; m < multipatches.size(); ++m) {
    const MultiPatch& mp = *multipatches[m];
    const int np = static_cast<int>(mp.patches.size());
    auto check = [&](const PatchSide& s, const std::string& what) {
      const std::string bad = side_out_of_range(s, np, pdim[m]);
      if (!bad.empty()) error("multipatch " + std::to_string(m) + ": " + what + " " + bad);
    };
    auto ps = [&](const PatchSide& s) { return std::to_string(first[m] + s.patch) + " " + std::to_string(number_of_side(s.side)); };
    os << " <MultiPatch parDim=\"" << pdim[m] << "\" id=\"" << id++ << "\">\n"
       << "  <patches type=\"id_range\">" << first[m] << " " << first[m] + np - 1 << "</patches>\n";
    if (!mp.interfaces.empty()) {
      os << "  <interfaces>\n";
      for (const Interface& f : mp.interfaces) {
        check(f.a, "an interface");
        check(f.b, "an interface");
        if (pdim[m] == 3) {
          // G+Smo's boundaryInterface over the 3 directions: across the faces the direction
          // across the second (flag: the same parameter value, as G+Smo sets it), along them
          // as face_map / face_flip say
          const int d1 = side_direction(f.a.side), d2 = side_direction(f.b.side);
          const auto fa = face_directions(f.a.side), fb = face_directions(f.b.side);
          int map[3], orient[3];
          map[d1] = d2;
          orient[d1] = side_end(f.a.side) == side_end(f.b.side);
          for (int k = 0; k < 2; ++k) {
            map[fa[k]] = fb[f.face_map[k]];
            orient[fa[k]] = !f.face_flip[k];
          }
          os << ps(f.a) << " " << ps(f.b) << " " << map[0] << " " << map[1] << " " << map[2] << " " << orient[0] << " "
             << orient[1] << " " << orient[2] << "\n";
          continue;
        }
        // G+Smo's 2-D boundaryInterface: the direction across the first side maps to the one
        // across the second (flag: same parameter value), the one along it to the one along
        // the second (flag: same orientation).
        const int d1 = side_direction(f.a.side), d2 = side_direction(f.b.side);
        int map[2], orient[2];
        map[d1] = d2;
        map[1 - d1] = 1 - d2;
        orient[d1] = side_end(f.a.side) == side_end(f.b.side);
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

}  // namespace iga
