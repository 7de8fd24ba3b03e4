// Problem file: one side's (or corner's) condition, and what a side or corner name designates.
#include "model/yaml_reader.hpp"

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

namespace detail {

void read_side(const Reader& R, const YAML::Node& n, const std::string& path, SideCondition& sc) {
  R.keys(n, path, {"displacement", "pressure", "traction"});
  const int K = R.stages, D = R.dim;
  sc.value.assign(K, {0.0, 0.0, 0.0});
  sc.p0.assign(K, 0.0);
  sc.p1.assign(K, 0.0);
  sc.traction.assign(K, {0.0, 0.0, 0.0});
  if (n["displacement"]) {
    const YAML::Node d = n["displacement"];
    if (D == 3)
      R.keys(d, path + ".displacement", {"x", "y", "z"});
    else
      R.keys(d, path + ".displacement", {"x", "y"});
    if (d.size() == 0) R.fail(path + ".displacement", d, D == 3 ? "prescribe any of x, y, z" : "prescribe x, y or both");
    for (int c = 0; c < D; ++c) {
      const char* k = c == 0 ? "x" : c == 1 ? "y" : "z";
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
      if (D == 3) R.fail(path + ".pressure", p, "a solid's face takes a constant pressure (pressure.linear is 2-D)");
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
    if (!t.IsSequence() || static_cast<int>(t.size()) != D)
      R.fail(path + ".traction", t, "expected a list of " + std::to_string(D) + " numbers");
    sc.load = LoadKind::Traction;
    for (int c = 0; c < D; ++c) {
      const auto v = R.staged(t[c], path + ".traction[" + std::to_string(c) + "]");
      for (int s = 0; s < K; ++s) sc.traction[s][c] = v[s];
    }
  }
}

// What a boundary or contact name designates on a body: (patch side, -1) or (patch, corner).
// Names: west/east/south/north and the corners south_west, ... (single-patch bodies),
// patch<k>.<side or corner>, or a named boundary of the body's geometry file.
std::vector<std::pair<PatchSide, int>> boundary_places(const Reader& R, const Body& b, const std::string& name,
                                                       const std::string& key, const YAML::Node& at, bool corners) {
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
  const bool solid = b.dim() == 3;
  corners = corners && !solid;   // corner conditions are 2-D (a solid's face holds it)
  const bool is_side = parse_side(part, s, b.dim()), is_corner = corners && parse_corner(part, c);
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
  if (solid && parse_corner(part, c))
    R.fail(key, at, "corner conditions are 2-D; a solid's boundary names faces (" +
                        std::string(np > 1 ? "patch<k>.west|east|south|north|front|back" : "west, east, south, north, front, back") + ")");
  if (!corners && parse_corner(part, c)) {
    std::string names;
    for (const auto& [nm, list] : b.named) names += (names.empty() ? "" : ", ") + nm;
    R.fail(key, at, "a corner is a point, not a contact side (" +
                        std::string(np > 1 ? "patch<k>.west|east|south|north" : "west, east, south, north") +
                        (names.empty() ? "" : ", or a named boundary of the geometry file: " + names) + ")");
  }
  std::string names;
  for (const auto& [nm, list] : b.named) names += (names.empty() ? "" : ", ") + nm;
  std::string allowed = solid ? (np > 1 ? "patch<k>.west|east|south|north|front|back" : "faces west, east, south, north, front, back")
                              : np > 1 ? "patch<k>.west|east|south|north" : "west, east, south, north";
  if (corners) allowed += np > 1 ? ", a corner patch<k>.south_west|south_east|north_west|north_east" : ", or a corner south_west, south_east, north_west, north_east";
  if (!names.empty()) allowed += ", or a named boundary of the geometry file: " + names;
  R.fail(key, at, "unknown side (" + allowed + ")");
}

}  // namespace detail

}  // namespace iga
