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
#include "model/geometry_common.hpp"

#include <charconv>

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
namespace geometry_io {

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

// Shortest decimal that reads back to the same double (at most 17 significant digits), in
// printf's %g style (std::to_chars: a tenth of the three snprintf and strtod it replaced, which
// were most of writing a geometry file at p = 4).
std::string fmt(double v) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::general);
  return std::string(buf, r.ptr);
}

// The writers' pieces: numbers on one line, and whether a side names one of np patches.
std::string number_row(const std::vector<double>& v) {
  std::string r;
  for (size_t j = 0; j < v.size(); ++j) r += (j ? " " : "") + fmt(v[j]);
  return r;
}

std::string side_out_of_range(const PatchSide& s, int np, int dim) {
  if (s.patch >= 0 && s.patch < np && static_cast<int>(s.side) >= 0 && static_cast<int>(s.side) < num_sides(dim)) return "";
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

}  // namespace geometry_io

using namespace geometry_io;

MultiPatch read_geometry_file(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  const size_t dot = path.find_last_of('.');
  const std::string ext = (dot == std::string::npos || (slash != std::string::npos && dot < slash)) ? "" : lower(path.substr(dot));
  if (ext == ".xml") return read_gismo_xml(path);
  if (ext == ".txt") return read_geopdes(path);
  fail(path, (ext.empty() ? std::string("no file extension") : "unknown extension " + quote(path.substr(dot))) +
                 ": a geometry file is .xml (G+Smo) or .txt (GeoPDEs)");
}

}  // namespace iga
