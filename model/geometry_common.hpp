#pragma once
// Helpers shared by the geometry-file readers and writers (model/geometry_common.cpp,
// model/gismo_xml.cpp, model/geopdes.cpp): messages, number parsing and printing, side
// numbers of both formats, knot checks, the topology bookkeeping. Internal to those files.
#include <map>
#include <string>
#include <vector>

#include "model/input_error.hpp"
#include "model/multipatch.hpp"

namespace iga::geometry_io {


// A third coordinate counts as zero below this (nrbexport's own test for a 2-D geometry).
constexpr double kZeroZ = 1e-12;

[[noreturn]] void fail(const std::string& where, const std::string& what);
std::string lower(std::string s);
std::string trim(const std::string& s);
std::vector<std::string> split(const std::string& s);
// Quotes a token for a message, cut short and free of control characters.
std::string quote(const std::string& s);
bool to_double(const std::string& s, double& v);
bool to_int(const std::string& s, long& v);
// Shortest decimal that reads back to the same double (at most 17 significant digits).
std::string fmt(double v);
// The writers' pieces: numbers on one line, and whether a side names one of np patches.
std::string number_row(const std::vector<double>& v);
std::string side_out_of_range(const PatchSide& s, int np, int dim = 2);   // sides 0 .. 2 dim - 1
std::string read_file_text(const std::string& path);

// The side of a 1-based G+Smo / GeoPDEs side number (both: 1 west, 2 east, 3 south, 4 north).
inline Side side_of_number(long k) { return static_cast<Side>(k - 1); }
inline int number_of_side(Side s) { return static_cast<int>(s) + 1; }

std::string side_text(const PatchSide& s);
// Knot vector checks with the format's own words; Patch::validate() runs afterwards as well.
std::string check_knots(const std::vector<double>& U, int p);

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
  static int key(const PatchSide& s) { return s.patch * 6 + static_cast<int>(s.side); }   // 6 sides in 3-D
  std::map<int, std::string> used_;
};

void add_unique(std::vector<PatchSide>& v, const PatchSide& s);
void add_named(MultiPatch& mp, const std::string& name, const PatchSide& s);

}  // namespace iga::geometry_io
