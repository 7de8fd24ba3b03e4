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

namespace iga::detail {

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

bool contains_node(const YAML::Node& tree, const YAML::Node& n) {
  if (tree.is(n)) return true;
  if (tree.IsSequence() || tree.IsMap())
    for (const auto& it : tree) {
      if (tree.IsMap() ? (contains_node(it.first, n) || contains_node(it.second, n)) : contains_node(it, n)) return true;
    }
  return false;
}

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

}  // namespace iga::detail
