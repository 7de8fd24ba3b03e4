#pragma once
// The YAML reader of model/problem.cpp and its parts (internal to model/problem*.cpp): a
// node tree with the file name and key path at hand for one-line messages, --set overrides,
// and the readers of each part of the problem file.
#include <array>
#include <cmath>
#include <initializer_list>
#include <limits>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <Teuchos_ParameterList.hpp>
#include <Teuchos_RCP.hpp>
#include <yaml-cpp/yaml.h>

#include "model/problem.hpp"

namespace iga::detail {

// One-line messages (control characters escaped) and one-line YAML values.
std::string printable(const std::string& s);
std::string one_line(const YAML::Node& n);

// A value given on the command line with --set KEY=VALUE: messages about it (or anything
// inside it) cite the --set argument, not a line of the file.
struct Override {
  std::string text;   // "KEY=VALUE" as given
  YAML::Node value;
};

bool contains_node(const YAML::Node& tree, const YAML::Node& n);

// Memory per dof of a run at degree p in dim dimensions: about 51.5 bytes per matrix entry of
// its row, dim (2p + 1)^dim entries (the tangent, the preconditioner's copy and hierarchy,
// the solver's vectors). Measured: 2575 bytes per dof at p = 2 in 2-D (50 entries a row,
// docs/performance.md), 18.4 kB at p = 2 in 3-D (375 entries; the 98,304-dof cube with CG +
// BoomerAMG, 1.96 GB peak).
inline double bytes_per_dof_estimate(int degree, int dim) {
  double coupled = 1;
  for (int d = 0; d < dim; ++d) coupled *= 2.0 * degree + 1;
  return 51.5 * dim * coupled;
}

// Reads one YAML node tree with the file name and key path at hand for messages.
struct Reader {
  std::string file;
  std::vector<Override> overrides;
  double memory_bytes = 0;   // what the machine has available (0: unknown, no size check)
  int samples_per_element = 4;   // output.samples_per_element, read before the bodies
  int stages = 1;                // analysis.stages, read before the bodies
  int dim = 2;                   // analysis.type (solid: 3), read before the bodies
  mutable std::vector<std::string> warnings;   // warning lines found while reading (Problem::warnings)

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
    if (dim == 3) return 0;   // 3-D writes no sampled grid (docs/paraview.md, the output layout)
    return (samples_per_element * ne0 + 1) * (samples_per_element * ne1 + 1) * 240.0;
  }

  [[noreturn]] void fail(const std::string& key, const YAML::Node& n, const std::string& why) const {
    std::ostringstream os;
    os << file;
    const Override* from = nullptr;
    for (const auto& o : overrides)
      // the node is the override's value or inside it, or a map the override's path made
      // (no line in the file: a mistyped key of --set, bodies.0.materal.youngs_modulus=5)
      if (n.IsDefined() && (contains_node(o.value, n) || (n.Mark().line < 0 && contains_node(n, o.value)))) from = &o;
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
        // YAML 1.1's merge key (<<) is no part of YAML 1.2, which yaml-cpp reads: a key like any other
        const std::string merge = k == "<<" ? "YAML merge keys (<<) are not supported: write the keys out; " : "";
        fail(path.empty() ? k : path + "." + k, kv.second, merge + "unknown key (allowed here: " + list + ")");
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
  /// Coordinates and lengths of the geometry: numbers up to 1e100 in magnitude, so that their
  /// squares (Jacobians, element sizes, stiffness) stay finite. A size near 1e308 was refused
  /// further on with a misleading reason (an interface "not conforming", det J vanishing).
  std::vector<double> lengths(const YAML::Node& n, const std::string& key, int size = -1) const {
    const std::vector<double> v = numbers(n, key, size);
    for (double x : v)
      if (std::abs(x) > 1e100)
        fail(key, n, "a coordinate or length beyond 1e100 cannot be computed with (its square overflows); rescale the units");
    return v;
  }
  double length(const YAML::Node& n, const std::string& key) const {
    const double v = positive(n, key);
    if (v > 1e100) fail(key, n, "a length beyond 1e100 cannot be computed with (its square overflows); rescale the units");
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
  // An int (the same in every direction) or a list of `dim` integers, one per parametric
  // direction; entries beyond dim are 0.
  std::array<int, 3> int_per_direction(const YAML::Node& n, const std::string& key) const {
    if (n.IsScalar()) { const int a = integer(n, key); return {a, a, dim == 3 ? a : 0}; }
    if (!n.IsSequence() || static_cast<int>(n.size()) != dim)
      fail(key, n, "expected an integer or a list of " + std::to_string(dim) + " integers");
    std::array<int, 3> v{0, 0, 0};
    for (int d = 0; d < dim; ++d) v[d] = integer(n[d], key + "[" + std::to_string(d) + "]");
    return v;
  }
  double positive(const YAML::Node& n, const std::string& key) const {
    const double v = number(n, key);
    if (!(v > 0)) fail(key, n, "must be > 0");
    if (v < std::numeric_limits<double>::min())   // subnormal: products with it vanish
      fail(key, n, "is below the smallest normal number (2.2e-308); rescale the units");
    return v;
  }

  // Refuses a problem that will not fit the machine, before anything is built
  // (bytes_per_dof_estimate).
  void fits(const std::string& key, const YAML::Node& n, double dofs, int degree, double extra_bytes = 0,
            int dim = 2) const {
    const double bytes = dofs * bytes_per_dof_estimate(degree, dim) + extra_bytes;
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
void check_duplicate_keys(const Reader& R, const YAML::Node& n, const std::string& path);
// --set KEY=VALUE applied to the node tree (model/yaml_reader.cpp says how keys are walked).
void apply_override(const std::string& file, YAML::Node root, const std::string& ov, std::vector<Override>& record);
// MemAvailable of /proc/meminfo in bytes, or IGACONTACT_MEMORY_LIMIT (model/problem_checks.cpp).
double available_memory_bytes();

// model/problem_geometry.cpp: patches and bodies
Patch read_nurbs(const Reader& R, const YAML::Node& n, const std::string& path);
Patch make_rectangle(const Reader& R, const YAML::Node& n, const std::string& path);
Patch make_quarter_annulus(const Reader& R, const YAML::Node& n, const std::string& path);
Patch make_box(const Reader& R, const YAML::Node& n, const std::string& path);
Body read_body(const Reader& R, const YAML::Node& n, const std::string& path);

// model/problem_boundary.cpp: boundary conditions and the names of sides and corners
void read_side(const Reader& R, const YAML::Node& n, const std::string& path, SideCondition& sc);
std::vector<std::pair<PatchSide, int>> boundary_places(const Reader& R, const Body& b, const std::string& name,
                                                       const std::string& key, const YAML::Node& at, bool corners = true);

// model/problem_contact.cpp: contact surfaces and pairs (the `contact` list)
ContactSurface read_surface(const Reader& R, const Problem& P, const YAML::Node& n, const std::string& path);
void read_contact_pairs(const Reader& R, const YAML::Node& root, Problem& P);

// model/problem_solver.cpp: the `solver` block, the MueLu file, the automatic linear method
Teuchos::RCP<const Teuchos::ParameterList> muelu_xml(const Reader& R, const YAML::Node& n);
void read_solver(const Reader& R, const YAML::Node& root, Problem& P);
void choose_linear_method(const Reader& R, const YAML::Node& root, Problem& P);

// model/problem_checks.cpp: rigid-body freedom (rigid_rank: model/rigid_modes.hpp), scales,
// the size of the problem
void check_problem(const Reader& R, const YAML::Node& root, Problem& P);

}  // namespace iga::detail
