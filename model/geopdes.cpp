// GeoPDEs multipatch text geometry files (format v2.1): the reader and the writer.
// Conventions in docs/geometry-files.md and at the top of model/geometry_common.cpp.
#include "model/geometry_file.hpp"
#include "model/geometry_common.hpp"

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
  if (ndim != 2 && ndim != 3)
    fail(in.at(line), "ndim = " + std::to_string(ndim) + ": igacontact reads 2-D and 3-D parametric patches (ndim = 2 or 3)");
  const int dim = static_cast<int>(ndim);
  const long rdim = head.size() > 1 ? head[1] : ndim;
  if (dim == 3 && rdim != 3)
    fail(in.at(line), "rdim = " + std::to_string(rdim) + ": volumes (ndim = 3) need the physical dimension 3");
  if (rdim != 2 && rdim != 3)
    fail(in.at(line), "rdim = " + std::to_string(rdim) + ": the physical dimension must be 2 (or 3 with z = 0)");
  const long np = head.size() > 2 ? head[2] : 1;
  const long ni = head.size() > 3 ? head[3] : 0;
  const long ns = head.size() > 4 ? head[4] : 0;
  if (np < 1 || np > 100000) fail(in.at(line), "npatches = " + std::to_string(np) + " is out of range 1..100000");
  if (ni < 0 || ns < 0) fail(in.at(line), "negative number of interfaces or subdomains");

  MultiPatch mp;
  const char* dir_name[3] = {"u", "v", "w"};
  for (long k = 1; k <= np; ++k) {
    const std::string pk = "patch " + std::to_string(k);
    s = in.need("the degrees of " + pk, line);
    const int start = line;
    if (!numeric_line(s)) {   // the optional name, e.g. "PATCH 1"
      // an INTERFACE or SUBDOMAIN block where a patch should begin: the header counts more
      // patches than the file holds (it read the block's numbers as a patch and blamed them)
      const auto t = split(s);
      if (!t.empty() && (t[0] == "INTERFACE" || t[0] == "SUBDOMAIN"))
        fail(in.at(line), "'" + s + "' where " + pk + " should begin: the header declares npatches = " + std::to_string(np) +
                              " but the file holds " + std::to_string(k - 1));
      s = in.need("the degrees of " + pk, line);
    }
    Patch P;
    P.pdim = dim;
    const auto deg = line_ints(in, s, line, pk + " degrees", dim);
    for (int d = 0; d < dim; ++d) {
      if (deg[d] < 1)
        fail(in.at(line), pk + ": degree " + std::to_string(deg[d]) + " in " + dir_name[d] + ": the degree must be at least 1");
      if (deg[d] > 1000) fail(in.at(line), pk + ": degree " + std::to_string(deg[d]) + " in " + dir_name[d] + " is too high");
      P.degree[d] = static_cast<int>(deg[d]);   // Patch::validate() checks the supported range
    }
    s = in.need("the numbers of control points of " + pk, line);
    const auto ncp = line_ints(in, s, line, pk + " numbers of control points", dim);
    for (int d = 0; d < dim; ++d) {
      if (ncp[d] < deg[d] + 1)
        fail(in.at(line), pk + ": " + std::to_string(ncp[d]) + " control points in " + dir_name[d] + "; degree " +
                              std::to_string(deg[d]) + " needs at least " + std::to_string(deg[d] + 1));
      if (ncp[d] > 1000000) fail(in.at(line), pk + ": " + std::to_string(ncp[d]) + " control points in " + dir_name[d] + " is too many");
    }
    for (int d = 0; d < dim; ++d) {
      const std::string what = pk + " knots in " + dir_name[d];
      s = in.need("the " + what, line);
      P.knots[d] = line_numbers(in, s, line, what, static_cast<size_t>(ncp[d] + deg[d] + 1));
      const std::string bad = check_knots(P.knots[d], P.degree[d]);
      if (!bad.empty()) fail(in.at(line), what + ": " + bad);
    }
    const size_t n = static_cast<size_t>(ncp[0] * ncp[1] * (dim == 3 ? ncp[2] : 1));
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
    if (rdim == 3 && dim == 2)
      for (size_t a = 0; a < n; ++a)
        if (std::abs(coord[2][a]) > kZeroZ)
          fail(in.at(coord_line[2]), pk + ": control point " + std::to_string(a + 1) + " has z = " + fmt(coord[2][a] / w[a]) +
                                         "; igacontact is 2-D, z must be 0");
    // Homogeneous (w x, w y, w) to Euclidean.
    P.cp.resize(n);
    for (size_t a = 0; a < n; ++a)
      P.cp[a] = dim == 3 ? ControlPoint{{coord[0][a] / w[a], coord[1][a] / w[a], coord[2][a] / w[a]}, w[a]}
                         : ControlPoint{{coord[0][a] / w[a], coord[1][a] / w[a]}, w[a]};
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
    if (dim == 2 && (v[1] < 1 || v[1] > 4))
      fail(in.at(line), what + ": side " + std::to_string(v[1]) + " is out of range 1..4 (u = 0, u = 1, v = 0, v = 1)");
    if (v[1] < 1 || v[1] > 6)
      fail(in.at(line), what + ": side " + std::to_string(v[1]) + " is out of range 1..6 (u = 0, u = 1, v = 0, v = 1, w = 0, w = 1)");
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
    if (dim == 3) {
      // flag ornt1 ornt2 (GeoPDEs' mp_interface_3d): flag -1: the face directions swap (the
      // first of side1 runs along the second of side2); ornt k -1: side1's direction k runs
      // against its partner
      s = in.need("the orientation (flag ornt1 ornt2) of " + ik, line);
      const auto o = line_ints(in, s, line, ik + " orientation (flag ornt1 ornt2)", 3);
      const char* name[3] = {"flag", "ornt1", "ornt2"};
      for (int k = 0; k < 3; ++k)
        if (o[k] != 1 && o[k] != -1) fail(in.at(line), ik + ": " + name[k] + " " + std::to_string(o[k]) + " must be 1 or -1");
      f.face_map = o[0] == 1 ? std::array<int, 2>{0, 1} : std::array<int, 2>{1, 0};
      f.face_flip = {o[1] == -1, o[2] == -1};
    } else {
      s = in.need("the orientation of " + ik, line);
      const auto o = line_ints(in, s, line, ik + " orientation", 1);
      if (o[0] != 1 && o[0] != -1)
        fail(in.at(line), ik + ": orientation " + std::to_string(o[0]) + " must be 1 (same direction) or -1 (reversed)");
      f.reversed = o[0] == -1;
    }
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
    if (cnt[0] < 0 || cnt[0] > num_sides(dim) * np)
      fail(in.at(line), bk + ": " + std::to_string(cnt[0]) + " sides is out of range 0.." + std::to_string(num_sides(dim) * np));
    for (long j = 1; j <= cnt[0]; ++j) {
      const PatchSide ps = patch_side(bk + " side " + std::to_string(j));
      topo.boundary(ps, in.at(line) + ": " + bk);
      add_unique(mp.boundary, ps);
      add_named(mp, name, ps);
    }
  }
  // GeoPDEs (mp_geo_read_nurbs) gives a single patch without boundaries its four sides.
  if (nb == 0 && np == 1)
    for (int k = 0; k < num_sides(dim); ++k) {
      const PatchSide ps{0, static_cast<Side>(k)};
      mp.boundary.push_back(ps);
      mp.named.push_back({"boundary" + std::to_string(k + 1), {ps}});
    }
  return mp;
}

std::string geopdes_text(const MultiPatch& mp) {
  auto error = [&](const std::string& what) { throw std::runtime_error("GeoPDEs text: " + what); };
  if (mp.patches.empty()) error("the multipatch has no patches");
  const int dim = mp.patches.front().dim();
  for (size_t k = 0; k < mp.patches.size(); ++k)
    if (mp.patches[k].dim() != dim)
      error("patch " + std::to_string(k) + " is " + std::to_string(mp.patches[k].dim()) + "-D, patch 0 " + std::to_string(dim) + "-D");
  const int np = static_cast<int>(mp.patches.size());
  auto check = [&](const PatchSide& s, const std::string& what) {
    const std::string bad = side_out_of_range(s, np, dim);
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
     << "# Written by igacontact: GeoPDEs multipatch text; coordinate rows are homogeneous ("
     << (dim == 3 ? "w x, w y, w z" : "w x, w y") << ")\n"
     << dim << " " << dim << " " << np << " " << mp.interfaces.size() << " 0\n";
  for (int k = 0; k < np; ++k) {
    const Patch& P = mp.patches[k];
    const std::string bad = P.validate();
    if (!bad.empty()) error("patch " + std::to_string(k) + ": " + bad);
    os << "PATCH " << k + 1 << "\n";
    for (int d = 0; d < dim; ++d) os << (d ? " " : "") << P.degree[d];
    os << "\n";
    for (int d = 0; d < dim; ++d) os << (d ? " " : "") << P.knots[d].size() - P.degree[d] - 1;
    os << "\n";
    for (int d = 0; d < dim; ++d) os << number_row(P.knots[d]) << "\n";
    for (int c = 0; c <= dim; ++c) {   // w x, w y [, w z], then w
      for (size_t a = 0; a < P.cp.size(); ++a) os << (a ? " " : "") << fmt(c < dim ? P.cp[a].x[c] * P.cp[a].w : P.cp[a].w);
      os << "\n";
    }
  }
  for (size_t i = 0; i < mp.interfaces.size(); ++i) {
    const Interface& f = mp.interfaces[i];
    check(f.a, "an interface");
    check(f.b, "an interface");
    os << "INTERFACE " << i + 1 << "\n" << ps(f.a) << "\n" << ps(f.b) << "\n";
    if (dim == 3)
      os << (f.face_map[0] == 0 ? 1 : -1) << " " << (f.face_flip[0] ? -1 : 1) << " " << (f.face_flip[1] ? -1 : 1) << "\n";
    else
      os << (f.reversed ? -1 : 1) << "\n";
  }
  for (const auto& [name, sides] : blocks) {
    os << name << "\n" << sides.size() << "\n";
    for (const PatchSide& s : sides) os << ps(s) << "\n";
  }
  return os.str();
}

}  // namespace iga
