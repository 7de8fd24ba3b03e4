// Geometry files: G+Smo XML and GeoPDEs v2.1 text (model/geometry_file.*). The same geometry
// read from both formats, exact circles, interfaces checked against the geometry, real G+Smo
// files, the writer's round trip, and the catalogue of malformed inputs with their messages.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "io/files.hpp"
#include "model/geometry_check.hpp"
#include "model/geometry_file.hpp"

using namespace iga;
namespace fs = std::filesystem;

namespace {

const std::string kSrc = IGACONTACT_SOURCE_DIR;
const std::string kFiles = kSrc + "/tests/geometry_files";
const std::string kExamples = kSrc + "/examples/geometry";

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// A G+Smo file as igacontact writes one (a run's geometry_<body>.xml, `igacontact export`).
void write_gismo_xml(const std::string& path, const std::vector<const MultiPatch*>& multipatches) {
  write_file_atomic(path, gismo_xml_text(multipatches));
}

// A fresh folder for files the test writes, removed afterwards.
struct Scratch {
  fs::path path;
  explicit Scratch(const std::string& name) : path(fs::temp_directory_path() / ("igacontact_geometry_file_" + name)) {
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~Scratch() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
  fs::path operator/(const std::string& f) const { return path / f; }
};

// Point at parameter t in [0, 1] along a side, in the side's own parameter direction.
std::array<double, 2> side_point(const Patch& P, Side s, double t) {
  auto at = [&](int d, double x) { return P.knots[d].front() + x * (P.knots[d].back() - P.knots[d].front()); };
  switch (s) {
    case Side::West: return P.eval(at(0, 0), at(1, t));
    case Side::East: return P.eval(at(0, 1), at(1, t));
    case Side::South: return P.eval(at(0, t), at(1, 0));
    case Side::North: return P.eval(at(0, t), at(1, 1));
  }
  return {0, 0};
}

double dist(const std::array<double, 2>& a, const std::array<double, 2>& b) {
  return std::hypot(a[0] - b[0], a[1] - b[1]);
}

std::string side_str(const PatchSide& s) { return std::to_string(s.patch) + "." + side_name(s.side); }

// Every declared interface: the two sides coincide point by point, in the declared direction.
void expect_interfaces_match(const MultiPatch& mp, double tol, const std::string& what) {
  for (const Interface& f : mp.interfaces)
    for (double t : {0.0, 0.1, 0.3, 0.5, 0.77, 1.0}) {
      const auto a = side_point(mp.patches[f.a.patch], f.a.side, t);
      const auto b = side_point(mp.patches[f.b.patch], f.b.side, f.reversed ? 1 - t : t);
      EXPECT_LT(dist(a, b), tol) << what << ": interface " << side_str(f.a) << " / " << side_str(f.b)
                                 << (f.reversed ? " (reversed)" : "") << " at t = " << t;
    }
}

void expect_same_topology(const MultiPatch& a, const MultiPatch& b, const std::string& what) {
  ASSERT_EQ(a.interfaces.size(), b.interfaces.size()) << what;
  for (size_t k = 0; k < a.interfaces.size(); ++k) {
    EXPECT_TRUE(a.interfaces[k].a == b.interfaces[k].a) << what << " interface " << k;
    EXPECT_TRUE(a.interfaces[k].b == b.interfaces[k].b) << what << " interface " << k;
    EXPECT_EQ(a.interfaces[k].reversed, b.interfaces[k].reversed) << what << " interface " << k;
  }
  EXPECT_TRUE(a.boundary == b.boundary) << what;
  ASSERT_EQ(a.named.size(), b.named.size()) << what;
  for (size_t k = 0; k < a.named.size(); ++k) {
    EXPECT_EQ(a.named[k].first, b.named[k].first) << what;
    EXPECT_TRUE(a.named[k].second == b.named[k].second) << what << " " << a.named[k].first;
  }
}

// Same degrees and knots, control points within tol (relative to 1 + |x|; exactly when tol = 0), and the same
// points at a grid of parameters within 1e-14.
void expect_same_patches(const MultiPatch& a, const MultiPatch& b, double tol, const std::string& what) {
  ASSERT_EQ(a.patches.size(), b.patches.size()) << what;
  for (size_t k = 0; k < a.patches.size(); ++k) {
    const Patch& P = a.patches[k];
    const Patch& Q = b.patches[k];
    EXPECT_EQ(P.degree, Q.degree) << what << " patch " << k;
    EXPECT_EQ(P.knots[0], Q.knots[0]) << what << " patch " << k;
    EXPECT_EQ(P.knots[1], Q.knots[1]) << what << " patch " << k;
    ASSERT_EQ(P.cp.size(), Q.cp.size()) << what << " patch " << k;
    for (size_t i = 0; i < P.cp.size(); ++i)
      for (int c = 0; c < 3; ++c) {   // x, y, then the weight
        const double pc = c < 2 ? P.cp[i].x[c] : P.cp[i].w, qc = c < 2 ? Q.cp[i].x[c] : Q.cp[i].w;
        if (tol == 0) EXPECT_EQ(pc, qc) << what << " patch " << k << " cp " << i;
        else EXPECT_NEAR(pc, qc, tol * (1 + std::abs(pc))) << what << " patch " << k << " cp " << i;
      }
    for (double u : {0.0, 0.13, 0.5, 0.61, 1.0})
      for (double v : {0.0, 0.29, 0.5, 0.87, 1.0}) {
        auto at = [&](int d, double x) { return P.knots[d].front() + x * (P.knots[d].back() - P.knots[d].front()); };
        EXPECT_LT(dist(P.eval(at(0, u), at(1, v)), Q.eval(at(0, u), at(1, v))), 1e-14)
            << what << " patch " << k << " at " << u << ", " << v;
      }
  }
}

}  // namespace

// ---------------------------------------------------------------------------------------------

TEST(GeometryFile, ExamplesReadTheSameFromGismoAndGeoPDEs) {
  for (const std::string name : {"ring4", "wheel4", "wheel4_joint", "plate_with_hole"}) {
    const MultiPatch x = read_geometry_file(kExamples + "/" + name + ".xml");
    const MultiPatch t = read_geometry_file(kExamples + "/" + name + ".txt");
    // GeoPDEs stores w x: dividing by w may move the last bit.
    expect_same_patches(x, t, 1e-15, name);
    expect_same_topology(x, t, name);
    expect_interfaces_match(x, 1e-14, name + ".xml");
    expect_interfaces_match(t, 1e-14, name + ".txt");
  }
}

TEST(GeometryFile, SameTwoPatchGeometryInBothFormatsWithAReversedInterface) {
  const MultiPatch x = read_gismo_xml(kFiles + "/two_patches_reversed.xml");
  const MultiPatch t = read_geopdes(kFiles + "/two_patches_reversed.txt");
  ASSERT_EQ(x.patches.size(), 2u);
  // id_index "10 7": patch 0 is Geometry 10 (the rational one), patch 1 Geometry 7.
  EXPECT_EQ(x.patches[0].degree, (std::array<int, 3>{2, 1, 0}));
  EXPECT_EQ(x.patches[1].degree, (std::array<int, 3>{1, 1, 0}));
  EXPECT_EQ(x.patches[0].knots[0], (std::vector<double>{0, 0, 0, 0.5, 1, 1, 1}));
  EXPECT_DOUBLE_EQ(x.patches[0].cp[1].w, 0.8);
  ASSERT_EQ(x.interfaces.size(), 1u);
  EXPECT_TRUE((x.interfaces[0].a == PatchSide{0, Side::East}));
  EXPECT_TRUE((x.interfaces[0].b == PatchSide{1, Side::South}));
  EXPECT_TRUE(x.interfaces[0].reversed);
  ASSERT_EQ(x.named.size(), 4u);
  EXPECT_EQ(x.named[1].first, "boundary2");
  EXPECT_TRUE((x.named[1].second == std::vector<PatchSide>{{0, Side::South}, {1, Side::East}}));
  EXPECT_EQ(x.boundary.size(), 6u);
  expect_same_patches(x, t, 1e-15, "two_patches_reversed");
  expect_same_topology(x, t, "two_patches_reversed");
  expect_interfaces_match(x, 1e-14, "two_patches_reversed");
  // Had the flag been read the other way round, the sides would not meet.
  MultiPatch wrong = x;
  wrong.interfaces[0].reversed = false;
  const auto a = side_point(wrong.patches[0], Side::East, 0), b = side_point(wrong.patches[1], Side::South, 0);
  EXPECT_GT(dist(a, b), 0.5);
}

TEST(GeometryFile, LegacyFiveNumberInterfacesAndFilesWithoutMultiPatch) {
  const MultiPatch x = read_gismo_xml(kFiles + "/two_patches_reversed.xml");
  const MultiPatch legacy = read_gismo_xml(kFiles + "/legacy_interfaces.xml");
  expect_same_topology(x, legacy, "legacy_interfaces");

  const MultiPatch plain = read_gismo_xml(kFiles + "/no_multipatch.xml");
  ASSERT_EQ(plain.patches.size(), 2u);
  EXPECT_TRUE(plain.interfaces.empty());
  EXPECT_TRUE(plain.boundary.empty());
  EXPECT_TRUE(plain.named.empty());
  // order="coordinates": all x then all y.
  const std::vector<ControlPoint> expect{{{1, 0}, 1}, {{2, 0}, 1}, {{1, 1}, 1}, {{2, 1}, 1}};
  EXPECT_EQ(plain.patches[1].cp, expect);
  EXPECT_EQ(plain.patches[0].cp[1], (ControlPoint{{1, 0}, 1}));
}

TEST(GeometryFile, QuarterAnnuliReproduceExactRadii) {
  struct Case {
    std::string file;
    double cx, cy, ri, ro;
  };
  for (const Case& c : {Case{"ring4.xml", 0, 0, 1, 2}, Case{"ring4.txt", 0, 0, 1, 2}, Case{"wheel4.xml", 0, 10, 5, 10},
                        Case{"wheel4_joint.txt", 0, 10, 5, 10}}) {
    const MultiPatch mp = read_geometry_file(kExamples + "/" + c.file);
    ASSERT_EQ(mp.patches.size(), 4u) << c.file;
    for (size_t k = 0; k < 4; ++k) {
      const Patch& P = mp.patches[k];
      EXPECT_EQ(P.degree, (std::array<int, 3>{2, 1, 0})) << c.file;
      EXPECT_EQ(P.orientation(), -1) << c.file << ": xi counter-clockwise, eta outwards";
      for (int i = 0; i <= 40; ++i) {
        const double u = i / 40.0;
        for (auto [v, r] : {std::pair{0.0, c.ri}, std::pair{1.0, c.ro}}) {
          const auto x = P.eval(u, v);
          EXPECT_NEAR(std::hypot(x[0] - c.cx, x[1] - c.cy), r, 1e-14 * r) << c.file << " patch " << k << " u " << u;
        }
      }
    }
    EXPECT_EQ(mp.interfaces.size(), 4u);
    ASSERT_EQ(mp.named.size(), 2u);
    EXPECT_EQ(mp.named[0].first, "inner");
    EXPECT_EQ(mp.named[1].first, "outer");
    for (size_t k = 0; k < 4; ++k) EXPECT_TRUE((mp.named[1].second[k] == PatchSide{int(k), Side::North}));
  }
  // ring4: patch k starts at k * 90 degrees.
  const MultiPatch ring = read_geometry_file(kExamples + "/ring4.xml");
  EXPECT_LT(dist(ring.patches[1].eval(0, 0), {0, 1}), 1e-15);
  EXPECT_LT(dist(ring.patches[3].eval(1, 1), {2, 0}), 1e-15);
  // The wheel touches y = 0 in the middle of patch 0, or at the joint of patches 2 and 3.
  const MultiPatch w = read_geometry_file(kExamples + "/wheel4.xml");
  EXPECT_LT(dist(w.patches[0].eval(0.5, 1), {0, 0}), 1e-14);
  EXPECT_LT(dist(w.patches[0].eval(0, 1), {-10 * std::sqrt(0.5), 10 - 10 * std::sqrt(0.5)}), 1e-14);
  const MultiPatch j = read_geometry_file(kExamples + "/wheel4_joint.xml");
  EXPECT_LT(dist(j.patches[2].eval(1, 1), {0, 0}), 1e-14);
  EXPECT_LT(dist(j.patches[3].eval(0, 1), {0, 0}), 1e-14);
}

TEST(GeometryFile, PlateWithHole) {
  const MultiPatch mp = read_geometry_file(kExamples + "/plate_with_hole.xml");
  ASSERT_EQ(mp.patches.size(), 2u);
  for (const Patch& P : mp.patches) {
    EXPECT_EQ(P.degree, (std::array<int, 3>{2, 2, 0}));
    EXPECT_EQ(P.orientation(), 1);
    for (int i = 0; i <= 40; ++i) {
      const double v = i / 40.0;
      const auto h = P.eval(0, v);   // the hole: west side
      EXPECT_NEAR(std::hypot(h[0], h[1]), 1.0, 1e-14);
    }
  }
  // Patch 0 from the x axis to the diagonal, patch 1 from the diagonal to the y axis.
  for (int i = 0; i <= 20; ++i) {
    const double t = i / 20.0;
    EXPECT_NEAR(mp.patches[0].eval(t, 0)[1], 0.0, 1e-15);   // bottom: y = 0
    EXPECT_NEAR(mp.patches[0].eval(1, t)[0], 4.0, 1e-15);   // right: x = 4
    EXPECT_NEAR(mp.patches[1].eval(1, t)[1], 4.0, 1e-15);   // top: y = 4
    EXPECT_NEAR(mp.patches[1].eval(t, 1)[0], 0.0, 1e-15);   // left: x = 0
    const auto d = mp.patches[0].eval(t, 1);                // the diagonal
    EXPECT_NEAR(d[0], d[1], 1e-14);
  }
  EXPECT_LT(dist(mp.patches[0].eval(0, 0), {1, 0}), 1e-15);
  EXPECT_LT(dist(mp.patches[0].eval(1, 1), {4, 4}), 1e-15);
  ASSERT_EQ(mp.interfaces.size(), 1u);
  EXPECT_TRUE((mp.interfaces[0].a == PatchSide{0, Side::North}));
  EXPECT_TRUE((mp.interfaces[0].b == PatchSide{1, Side::South}));
  expect_interfaces_match(mp, 1e-14, "plate_with_hole");
  std::vector<std::string> names;
  for (const auto& n : mp.named) names.push_back(n.first);
  EXPECT_EQ(names, (std::vector<std::string>{"hole", "bottom", "right", "top", "left"}));
}

TEST(GeometryFile, RealGismoFiles) {
  // G+Smo 0.8.1 output, unmodified (tests/geometry_files/README.md).
  const MultiPatch disk = read_gismo_xml(kFiles + "/gismo/square_with_disk.xml");
  ASSERT_EQ(disk.patches.size(), 5u);
  EXPECT_EQ(disk.interfaces.size(), 8u);
  EXPECT_EQ(disk.boundary.size(), 4u);
  expect_interfaces_match(disk, 1e-13, "square_with_disk");
  // Patch 0 is the unit disc (its four sides are quarter circles), its neighbours fill the
  // square [-2, 2]^2 whose sides are their north sides. The file's weights have 15 digits.
  for (int s = 0; s < 4; ++s)
    for (double t : {0.0, 0.25, 0.5, 0.9})
      EXPECT_NEAR(std::hypot(side_point(disk.patches[0], Side(s), t)[0], side_point(disk.patches[0], Side(s), t)[1]),
                  1.0, 1e-13);
  for (const PatchSide& b : disk.boundary) {
    EXPECT_EQ(b.side, Side::North);
    const auto x = side_point(disk.patches[b.patch], b.side, 0.3);
    EXPECT_NEAR(std::max(std::abs(x[0]), std::abs(x[1])), 2.0, 1e-13);
  }
  // Interface 4 3 0 1 1 0 0 0: patch 4's south runs against patch 0's west.
  bool found = false;
  for (const Interface& f : disk.interfaces)
    if (f.a == PatchSide{4, Side::South} && f.b == PatchSide{0, Side::West}) found = f.reversed;
  EXPECT_TRUE(found);

  const MultiPatch rect = read_gismo_xml(kFiles + "/gismo/rectangle_with_disk_hole.xml");
  ASSERT_EQ(rect.patches.size(), 11u);
  EXPECT_EQ(rect.interfaces.size(), 11u);
  EXPECT_EQ(rect.boundary.size(), 22u);
  expect_interfaces_match(rect, 1e-13, "rectangle_with_disk_hole");
  EXPECT_EQ(rect.patches[0].cp.front().w, 1.0);   // TensorBSpline2
}

TEST(GeometryFile, WriteThenReadGivesIdenticalPatchesAndTopology) {
  const Scratch dir("roundtrip");
  for (const std::string& in : {kExamples + "/ring4.xml", kExamples + "/plate_with_hole.txt",
                                kFiles + "/two_patches_reversed.xml", kFiles + "/gismo/square_with_disk.xml"}) {
    const MultiPatch a = read_geometry_file(in);
    const std::string out = (dir / "out.xml").string();
    write_gismo_xml(out, {&a});
    const MultiPatch b = read_gismo_xml(out);
    expect_same_patches(a, b, 0.0, in);
    expect_same_topology(a, b, in);
    // Written again: the same text.
    write_gismo_xml((dir / "again.xml").string(), {&b});
    EXPECT_EQ(read_text(out), read_text((dir / "again.xml").string())) << in;
  }
  // Rational patches are TensorNurbs2, the others TensorBSpline2.
  const MultiPatch two = read_gismo_xml(kFiles + "/two_patches_reversed.xml");
  write_gismo_xml((dir / "two.xml").string(), {&two});
  const std::string text = read_text((dir / "two.xml").string());
  EXPECT_NE(text.find("<Geometry type=\"TensorNurbs2\" id=\"0\">"), std::string::npos);
  EXPECT_NE(text.find("<Geometry type=\"TensorBSpline2\" id=\"1\">"), std::string::npos);
  // Each boundary side once (G+Smo keeps one label per side): the four named groups only.
  size_t elements = 0;
  for (size_t k = 0; (k = text.find("<boundary", k)) != std::string::npos; ++k) ++elements;
  EXPECT_EQ(elements, 4u);
  EXPECT_EQ(text.find("<boundary>"), std::string::npos);
  // 17 significant digits where needed: 0.1 + 0.2 comes back exactly.
  MultiPatch odd = two;
  odd.patches[1].cp[0].x[0] = 0.1 + 0.2;
  write_gismo_xml((dir / "odd.xml").string(), {&odd});
  EXPECT_EQ(read_gismo_xml((dir / "odd.xml").string()).patches[1].cp[0].x[0], 0.1 + 0.2);
  // No temporary file is left beside the output.
  for (const auto& e : fs::directory_iterator(dir.path))
    EXPECT_EQ(e.path().string().find(".tmp"), std::string::npos) << e.path();
}

TEST(GeometryFile, GeoPdesWriteThenReadGivesIdenticalPatchesAndTopology) {
  const Scratch dir("geopdes");
  for (const std::string& in : {kExamples + "/ring4.xml", kExamples + "/plate_with_hole.xml",
                                kFiles + "/two_patches_reversed.xml", kFiles + "/gismo/square_with_disk.xml"}) {
    const MultiPatch a = read_geometry_file(in);
    const std::string out = (dir / "out.txt").string();
    write_file_atomic(out, geopdes_text(a));
    const MultiPatch b = read_geopdes(out);
    // Homogeneous rows (w x, w y) divided back by w: equal to a rounding of x.
    expect_same_patches(a, b, 1e-15, in);
    // Interfaces as they were; the same boundary sides (GeoPDEs lists them by group); each
    // named group with its sides, and the unnamed rest as one more group "boundary<n>".
    ASSERT_EQ(a.interfaces.size(), b.interfaces.size()) << in;
    for (size_t k = 0; k < a.interfaces.size(); ++k) {
      EXPECT_TRUE(a.interfaces[k].a == b.interfaces[k].a && a.interfaces[k].b == b.interfaces[k].b) << in;
      EXPECT_EQ(a.interfaces[k].reversed, b.interfaces[k].reversed) << in;
    }
    auto key = [](const PatchSide& x) { return 4 * x.patch + static_cast<int>(x.side); };
    std::set<int> sa, sb, named;
    for (const PatchSide& x : a.boundary) sa.insert(key(x));
    for (const PatchSide& x : b.boundary) sb.insert(key(x));
    EXPECT_EQ(sa, sb) << in;
    for (size_t k = 0; k < a.named.size(); ++k) {
      ASSERT_LT(k, b.named.size()) << in;
      EXPECT_EQ(b.named[k].first, a.named[k].first) << in;
      EXPECT_TRUE(b.named[k].second == a.named[k].second) << in << " " << a.named[k].first;
      for (const PatchSide& x : a.named[k].second) named.insert(key(x));
    }
    EXPECT_EQ(b.named.size(), a.named.size() + (named.size() < sa.size() ? 1 : 0)) << in;
    // Written again from what was read and read back: the same patches exactly.
    write_file_atomic((dir / "again.txt").string(), geopdes_text(b));
    expect_same_patches(b, read_geopdes((dir / "again.txt").string()), 1e-15, in);
  }
  // The example files' GeoPDEs text equals the one make_geometry.py wrote, up to its header.
  const MultiPatch ring = read_geometry_file(kExamples + "/ring4.txt");
  EXPECT_EQ(read_geopdes(kExamples + "/ring4.txt").patches.size(), 4u);
  const MultiPatch back = [&] {
    write_file_atomic((dir / "ring.txt").string(), geopdes_text(ring));
    return read_geopdes((dir / "ring.txt").string());
  }();
  expect_same_patches(ring, back, 1e-15, "ring4.txt");
  // Refused: an invalid patch, a side out of range.
  MultiPatch broken = ring;
  broken.patches[2].cp.pop_back();
  EXPECT_THROW(geopdes_text(broken), std::runtime_error);
  MultiPatch odd = ring;
  odd.interfaces.push_back({{7, Side::West}, {0, Side::East}, false});
  EXPECT_THROW(geopdes_text(odd), std::runtime_error);
}

TEST(GeometryFile, WriterKeepsSidesInSeveralGroupsAndNamedSidesOffTheBoundaryList) {
  const Scratch dir("groups");
  MultiPatch mp = read_geometry_file(kExamples + "/ring4.xml");
  mp.boundary = {{0, Side::South}, {0, Side::North}, {1, Side::South}, {1, Side::North}};
  mp.named = {{"inner", {{0, Side::South}, {1, Side::South}}},
              {"contact", {{0, Side::North}, {3, Side::North}}},   // 3.north: not in mp.boundary
              {"load", {{0, Side::North}}}};                       // 0.north: a second group
  const std::string out = (dir / "groups.xml").string();
  write_gismo_xml(out, {&mp});
  const MultiPatch back = read_gismo_xml(out);
  expect_same_patches(mp, back, 0.0, "groups");
  ASSERT_EQ(back.named.size(), 3u);
  for (size_t k = 0; k < 3; ++k) {
    EXPECT_EQ(back.named[k].first, mp.named[k].first);
    EXPECT_TRUE(back.named[k].second == mp.named[k].second) << mp.named[k].first;
  }
  // The listed boundary first, in its order, then the named side that was not in it.
  auto expect = mp.boundary;
  expect.push_back({3, Side::North});
  EXPECT_TRUE(back.boundary == expect);
}

TEST(GeometryFile, SeveralMultiPatchesInOneFile) {
  const Scratch dir("several");
  const MultiPatch ring = read_geometry_file(kExamples + "/ring4.xml");
  const MultiPatch plate = read_geometry_file(kExamples + "/plate_with_hole.xml");
  const std::string out = (dir / "both.xml").string();
  write_gismo_xml(out, {&ring, &plate});
  const std::string text = read_text(out);
  // The first multipatch is read back.
  const MultiPatch first = read_gismo_xml(out);
  expect_same_patches(ring, first, 0.0, "first");
  expect_same_topology(ring, first, "first");
  // The second names its patches by their Geometry ids (4, 5): drop the first <MultiPatch>
  // and it is read back.
  const size_t a = text.find(" <MultiPatch"), b = text.find("</MultiPatch>\n");
  ASSERT_NE(a, std::string::npos);
  ASSERT_NE(b, std::string::npos);
  EXPECT_NE(text.find("<patches type=\"id_range\">4 5</patches>"), std::string::npos);
  std::ofstream((dir / "second.xml").string()) << text.substr(0, a) + text.substr(b + 14);
  const MultiPatch second = read_gismo_xml((dir / "second.xml").string());
  expect_same_patches(plate, second, 0.0, "second");
  expect_same_topology(plate, second, "second");
}

TEST(GeometryFile, WriteFailureNamesTheFileAndLeavesNothing) {
  const MultiPatch ring = read_geometry_file(kExamples + "/ring4.xml");
  const Scratch dir("fail");
  const std::string bad = (dir / "no_such_folder" / "ring.xml").string();
  try {
    write_gismo_xml(bad, {&ring});
    ADD_FAILURE() << "wrote into a missing folder";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(bad), std::string::npos) << e.what();
  }
  EXPECT_TRUE(fs::is_empty(dir.path));
  // A patch that is not valid is refused, and an existing file is left as it was.
  const std::string out = (dir / "keep.xml").string();
  std::ofstream(out) << "old";
  MultiPatch broken = ring;
  broken.patches[2].cp.pop_back();
  EXPECT_THROW(write_gismo_xml(out, {&ring, &broken}), std::runtime_error);
  EXPECT_EQ(read_text(out), "old");
  EXPECT_THROW(write_gismo_xml(out, {nullptr}), std::runtime_error);
  size_t files = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir.path)) ++files;
  EXPECT_EQ(files, 1u);
}

TEST(GeometryFile, GeoPDEsSinglePatchGetsItsFourSidesAsBoundaries) {
  const Scratch dir("single");
  const std::string path = (dir / "square.txt").string();
  std::ofstream(path) << "# nurbs mesh v.2.1\n#\n2 2 1\nPATCH 1\n1 1\n2 2\n0 0 1 1\n0 0 1 1\n0 1 0 1\n0 0 1 1\n1 1 1 1\n";
  const MultiPatch mp = read_geometry_file(path);
  ASSERT_EQ(mp.patches.size(), 1u);
  ASSERT_EQ(mp.named.size(), 4u);
  EXPECT_EQ(mp.named[2].first, "boundary3");
  EXPECT_TRUE((mp.named[2].second == std::vector<PatchSide>{{0, Side::South}}));
  EXPECT_EQ(mp.boundary.size(), 4u);
  // Upper-case extensions are the same formats.
  const std::string upper = (dir / "SQUARE.TXT").string();
  fs::copy_file(path, upper);
  EXPECT_EQ(read_geometry_file(upper).patches.size(), 1u);
}

// ---------------------------------------------------------------------------------------------
// Malformed inputs: every file in tests/geometry_files/bad/ has its exact message here
// ({dir} stands for that folder), and every message is one line.

TEST(GeometryFile, BadInputsGiveOneLineMessages) {
  const std::string dir = kFiles + "/bad";
  const std::map<std::string, std::string> expect = {
      // clang-format off
      {"missing.xml", "{dir}/missing.xml: cannot open the file (No such file or directory)"},
      {"directory.xml", "{dir}/directory.xml: cannot read the file (Is a directory)"},
      {"unknown_extension.igs", "{dir}/unknown_extension.igs: unknown extension \".igs\": a geometry file is .xml (G+Smo) or .txt (GeoPDEs)"},
      {"xml_syntax.xml", "{dir}/xml_syntax.xml:20: XML syntax error: document not well-formed: end element tag = 'coef' did not match start element 'coefs' from line 15"},
      {"root_not_xml.xml", "{dir}/root_not_xml.xml: the root element is <gismo>, a G+Smo file has <xml>"},
      {"geometry_3d.xml", "{dir}/geometry_3d.xml: <Geometry id=\"0\"> <Basis>: type=\"TensorNurbsBasis2\", a TensorNurbs3 needs \"TensorNurbsBasis3\""},
      {"pardim_3.xml", "{dir}/pardim_3.xml: <Geometry id=\"0\">: a 2-D patch in <MultiPatch id=\"2\"> of parDim=\"3\""},
      {"geodim_3d.xml", "{dir}/geodim_3d.xml: <Geometry id=\"0\"> <coefs>: geoDim=\"2\": a TensorBSpline3 needs geoDim 3 (x y z)"},
      {"interface_3d_count.xml", "{dir}/interface_3d_count.xml: <MultiPatch id=\"2\"> <interfaces>: has 9 numbers; each 3-D interface takes 10 (patch side patch side, direction map (3), orientation (3))"},
      {"interface_3d_map.xml", "{dir}/interface_3d_map.xml: <MultiPatch id=\"2\"> <interfaces>: interface 1 (0 2 1 1 1 0 2 0 1 1): the direction map (1 0 2) does not take the direction across patch0.east (0) to the one across patch1.west (0)"},
      {"side_3d.xml", "{dir}/side_3d.xml: <MultiPatch id=\"2\"> <boundary>: entry 2 (1 7): side 7 is out of range 1..6 (west, east, south, north, front, back)"},
      {"knots_decreasing.xml", "{dir}/knots_decreasing.xml: <Geometry id=\"0\"> <Basis> <Basis> <Basis index=\"1\"> <KnotVector>: the knots decrease at knot 4 (1 then 0.5)"},
      {"knots_not_open.xml", "{dir}/knots_not_open.xml: <Geometry id=\"1\"> <Basis> <Basis index=\"0\"> <KnotVector>: the knot vector is not open: degree 2 needs its first 3 and its last 3 knots equal"},
      {"degree_missing.xml", "{dir}/degree_missing.xml: <Geometry id=\"1\"> <Basis> <Basis index=\"0\"> <KnotVector>: missing the degree attribute"},
      {"degree_zero.xml", "{dir}/degree_zero.xml: <Geometry id=\"0\"> <Basis> <Basis> <Basis index=\"0\"> <KnotVector>: degree=0: the degree must be at least 1"},
      {"coefs_count.xml", "{dir}/coefs_count.xml: <Geometry id=\"1\"> <coefs>: has 10 values; the basis has 3 x 2 = 6 functions, times geoDim 2 = 12"},
      {"weights_count.xml", "{dir}/weights_count.xml: <Geometry id=\"0\"> <Basis> <weights>: has 3 weights; the basis has 2 x 2 = 4 functions"},
      {"weight_negative.xml", "{dir}/weight_negative.xml: <Geometry id=\"0\"> <Basis> <weights>: weight 1 is -0.5; weights must be > 0"},
      {"not_a_number.xml", "{dir}/not_a_number.xml: <Geometry id=\"1\"> <coefs>: \"O\" is not a number (value 4)"},
      {"z_nonzero.xml", "{dir}/z_nonzero.xml: <Geometry id=\"0\"> <coefs>: control point 2 has z = 0.25; igacontact is 2-D, a geoDim 3 patch must have z = 0"},
      {"interior_knot_repeated.xml", "{dir}/interior_knot_repeated.xml: <Geometry id=\"1\">: knots[0] repeats the interior knot 0.5 3 times; at most 2 keep the patch continuous"},
      {"patches_id_missing.xml", "{dir}/patches_id_missing.xml: <MultiPatch id=\"2\"> <patches>: no <Geometry> with id=\"2\" in the file"},
      {"interface_patch.xml", "{dir}/interface_patch.xml: <MultiPatch id=\"2\"> <interfaces>: interface 1 (0 2 5 1 0 1 0 1): patch id 5 is not a patch of this multipatch (its <patches>: ids 0..1)"},
      {"interface_side.xml", "{dir}/interface_side.xml: <MultiPatch id=\"2\"> <interfaces>: interface 1 (0 2 1 5 0 1 0 1): side 5 is out of range 1..4 (west, east, south, north)"},
      {"interface_count.xml", "{dir}/interface_count.xml: <MultiPatch id=\"2\"> <interfaces>: has 7 numbers; each 2-D interface takes 8 (patch side patch side, direction map (2), orientation (2))"},
      {"interface_direction_map.xml", "{dir}/interface_direction_map.xml: <MultiPatch id=\"2\"> <interfaces>: interface 1 (0 2 1 1 1 0 0 1): the direction map (1 0) does not take the direction along patch0.east (1) to the one along patch1.west (1)"},
      {"side_twice.xml", "{dir}/side_twice.xml: <MultiPatch id=\"2\"> <interfaces>: interface 2 (1 1 0 4 1 0 0 1): patch1.west is already in interface 1 (0 2 1 1 0 1 0 1)"},
      {"geopdes_version.txt", "{dir}/geopdes_version.txt:1: GeoPDEs format version 0.7 is not supported: igacontact reads v.2.1 (nrbexport's default)"},
      {"geopdes_no_header.txt", "{dir}/geopdes_no_header.txt:1: no version header before the first data line; a GeoPDEs v2.1 file starts with '# nurbs mesh v.2.1'"},
      {"geopdes_truncated.txt", "{dir}/geopdes_truncated.txt:17: the file ends before the patch 2 knots in v (truncated?)"},
      {"geopdes_3d.txt", "{dir}/geopdes_3d.txt:7: patch 1 degrees: 2 values, expected 3"},
      {"geopdes_degree.txt", "{dir}/geopdes_degree.txt:15: patch 2: degree 0 in u: the degree must be at least 1"},
      {"geopdes_count.txt", "{dir}/geopdes_count.txt:11: patch 1 x coordinates (w x): 3 values, expected 4"},
      {"geopdes_knots.txt", "{dir}/geopdes_knots.txt:9: patch 1 knots in u: the knots decrease at knot 4 (1 then 0.5)"},
      {"geopdes_weight.txt", "{dir}/geopdes_weight.txt:21: patch 2: weight 3 is 0; weights must be > 0"},
      {"geopdes_not_number.txt", "{dir}/geopdes_not_number.txt:19: \"two\" is not a number (patch 2 x coordinates (w x))"},
      {"geopdes_z.txt", "{dir}/geopdes_z.txt:22: patch 2: control point 3 has z = 0.5; igacontact is 2-D, z must be 0"},
      {"geopdes_interior_knot.txt", "{dir}/geopdes_interior_knot.txt:6: patch 1: knots[0] repeats the interior knot 0.5 2 times; at most 1 keep the patch continuous"},
      {"geopdes_interface_patch.txt", "{dir}/geopdes_interface_patch.txt:24: interface 1 second side: patch 3 does not exist (patches 1..2)"},
      {"geopdes_side.txt", "{dir}/geopdes_side.txt:23: interface 1 first side: side 5 is out of range 1..4 (u = 0, u = 1, v = 0, v = 1)"},
      {"geopdes_orientation.txt", "{dir}/geopdes_orientation.txt:25: interface 1: orientation 0 must be 1 (same direction) or -1 (reversed)"},
      {"geopdes_extra_interface.txt", "{dir}/geopdes_extra_interface.txt:22: \"INTERFACE 1\": more interface blocks than the header declares (ninterfaces = 0 at line 5)"},
      {"geopdes_more_patches.txt", "{dir}/geopdes_more_patches.txt:35: 'INTERFACE 1' where patch 5 should begin: the header declares npatches = 5 but the file holds 4"},
      {"geopdes_boundary_patch.txt", "{dir}/geopdes_boundary_patch.txt:29: boundary 1 side 2: patch 4 does not exist (patches 1..2)"},
      // clang-format on
  };
  std::set<std::string> seen;
  for (const auto& e : fs::directory_iterator(dir)) seen.insert(e.path().filename().string());
  seen.insert("missing.xml");
  for (const auto& name : seen) EXPECT_TRUE(expect.count(name)) << "no expected message for bad/" << name;
  for (const auto& [name, message] : expect) {
    EXPECT_TRUE(seen.count(name)) << "bad/" << name << " is missing";
    std::string want = message;
    for (size_t k; (k = want.find("{dir}")) != std::string::npos;) want.replace(k, 5, dir);
    try {
      read_geometry_file(dir + "/" + name);
      ADD_FAILURE() << name << " was accepted";
    } catch (const InputError& e) {
      const std::string msg = e.what();
      EXPECT_EQ(msg.find('\n'), std::string::npos) << "not one line: " << msg;
      EXPECT_EQ(msg, want) << name;
    }
  }
}

// ---------------------------------------------------------------------------------------------
// 3-D: trivariate patches (TensorNurbs3 / TensorBSpline3), faces 1..6, interfaces with their
// orientation maps.

namespace {

void expect_same_patches_3d(const MultiPatch& a, const MultiPatch& b, const std::string& what) {
  ASSERT_EQ(a.patches.size(), b.patches.size()) << what;
  for (size_t k = 0; k < a.patches.size(); ++k) {
    const Patch &P = a.patches[k], &Q = b.patches[k];
    EXPECT_EQ(P.dim(), Q.dim()) << what;
    EXPECT_EQ(P.degree, Q.degree) << what << " patch " << k;
    EXPECT_EQ(P.knots, Q.knots) << what << " patch " << k;
    EXPECT_EQ(P.cp, Q.cp) << what << " patch " << k;   // x, y, z and w bit for bit
  }
}

void expect_same_topology_3d(const MultiPatch& a, const MultiPatch& b, const std::string& what) {
  ASSERT_EQ(a.interfaces.size(), b.interfaces.size()) << what;
  for (size_t k = 0; k < a.interfaces.size(); ++k) {
    const Interface &f = a.interfaces[k], &g = b.interfaces[k];
    EXPECT_EQ(f.a, g.a) << what;
    EXPECT_EQ(f.b, g.b) << what;
    EXPECT_EQ(f.face_map, g.face_map) << what << " interface " << k;
    EXPECT_EQ(f.face_flip, g.face_flip) << what << " interface " << k;
  }
  EXPECT_EQ(a.boundary, b.boundary) << what;
  ASSERT_EQ(a.named.size(), b.named.size()) << what;
  for (size_t k = 0; k < a.named.size(); ++k) {
    EXPECT_EQ(a.named[k].first, b.named[k].first) << what;
    EXPECT_EQ(a.named[k].second, b.named[k].second) << what;
  }
}

// Box [o, o + L] of degree 1 x 2 x 1 (one element), then its directions relabelled: direction
// d of the result is direction perm[d] of the box, reversed where rev[d].
Patch box_relabelled(std::array<double, 3> o, std::array<double, 3> L, std::array<int, 3> perm, std::array<bool, 3> rev) {
  const int p[3] = {1, 2, 1};
  Patch B;
  B.pdim = 3;
  for (int d = 0; d < 3; ++d) B.degree[d] = p[d], B.knots[d] = uniform_open_knots(p[d], 1);
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 2; ++i) B.cp.push_back(ControlPoint({o[0] + L[0] * i, o[1] + L[1] * 0.5 * j, o[2] + L[2] * k}, 1.0));
  Patch Q;
  Q.pdim = 3;
  for (int d = 0; d < 3; ++d) Q.degree[d] = B.degree[perm[d]], Q.knots[d] = B.knots[perm[d]];
  Q.cp.resize(B.cp.size());
  for (int k = 0; k < Q.ncp(2); ++k)
    for (int j = 0; j < Q.ncp(1); ++j)
      for (int i = 0; i < Q.ncp(0); ++i) {
        const int q[3] = {i, j, k};
        int src[3];
        for (int d = 0; d < 3; ++d) src[perm[d]] = rev[d] ? Q.ncp(d) - 1 - q[d] : q[d];
        Q.cp[Q.index(i, j, k)] = B.cp[B.index(src[0], src[1], src[2])];
      }
  return Q;
}

}  // namespace

TEST(GeometryFile3D, SphereOctantInTwoPatches) {
  const MultiPatch mp = read_geometry_file(kExamples + "/sphere_octant2.xml");
  ASSERT_EQ(mp.patches.size(), 2u);
  const int radial[2] = {2, 0};   // the radius direction of each patch
  for (int k = 0; k < 2; ++k) {
    const Patch& P = mp.patches[k];
    ASSERT_EQ(P.dim(), 3);
    EXPECT_EQ(P.orientation(), 1);
    EXPECT_EQ(check_jacobian(P), "") << "patch " << k;
    // exact spheres: |x| = 1 + t along the radius, the octant x, y, z >= 0, patch 0 at
    // angles 0..45 about z, patch 1 at 45..90
    for (int a = 0; a <= 6; ++a)
      for (int b = 0; b <= 6; ++b)
        for (int c = 0; c <= 6; ++c) {
          const double t[3] = {a / 6.0, b / 6.0, c / 6.0};
          const auto x = P.point(t);
          EXPECT_NEAR(std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]), 1.0 + t[radial[k]], 1e-14);
          for (int d = 0; d < 3; ++d) EXPECT_GE(x[d], -1e-15);
          EXPECT_TRUE(k == 0 ? x[1] <= x[0] + 1e-14 : x[0] <= x[1] + 1e-14);
        }
  }
  EXPECT_EQ(mp.patches[0].degree, (std::array<int, 3>{2, 2, 1}));
  EXPECT_EQ(mp.patches[1].degree, (std::array<int, 3>{1, 2, 2}));
  // the interface as the file declares it (G+Smo's 0 2 1 3 1 2 0 0 1 1): patch 0's eta along
  // patch 1's zeta, zeta along xi; the geometry finds the same
  ASSERT_EQ(mp.interfaces.size(), 1u);
  const Interface& f = mp.interfaces[0];
  EXPECT_EQ(f.a, (PatchSide{0, Side::East}));
  EXPECT_EQ(f.b, (PatchSide{1, Side::South}));
  EXPECT_EQ(f.face_map, (std::array<int, 2>{1, 0}));
  EXPECT_EQ(f.face_flip, (std::array<bool, 2>{false, false}));
  const double tol = 1e-8 * patches_diameter(mp.patches);
  const auto found = find_interfaces(mp.patches, tol);
  ASSERT_EQ(found.size(), 1u);   // the pole faces (on the z axis) are no interface
  EXPECT_EQ(found[0].a, f.a);
  EXPECT_EQ(found[0].b, f.b);
  EXPECT_EQ(found[0].face_map, f.face_map);
  EXPECT_EQ(found[0].face_flip, f.face_flip);
  EXPECT_EQ(check_interface(mp.patches, f, tol), "");
  EXPECT_EQ(find_nonconforming(mp.patches, mp.interfaces, tol), "");
  int n = 0;
  merge_control_points(mp.patches, mp.interfaces, n);
  EXPECT_EQ(n, 18 + 18 - 6);
  EXPECT_TRUE(side_collapsed(mp.patches[0], Side::North, tol));
  EXPECT_TRUE(side_collapsed(mp.patches[1], Side::Back, tol));
  // boundaries: sides 5 and 6 are front and back
  EXPECT_EQ(mp.boundary.size(), 8u);
  ASSERT_EQ(mp.named.size(), 5u);
  EXPECT_EQ(mp.named[0].first, "inner");
  EXPECT_TRUE((mp.named[0].second == std::vector<PatchSide>{{0, Side::Front}, {1, Side::West}}));
  EXPECT_EQ(mp.named[4].first, "z0");
  EXPECT_TRUE((mp.named[4].second == std::vector<PatchSide>{{0, Side::South}, {1, Side::Front}}));
}

TEST(GeometryFile3D, WriteThenReadGivesIdenticalPatchesAndTopology) {
  const Scratch dir("roundtrip3d");
  const MultiPatch a = read_geometry_file(kExamples + "/sphere_octant2.xml");
  const std::string out = (dir / "out.xml").string();
  write_gismo_xml(out, {&a});
  const MultiPatch b = read_gismo_xml(out);
  expect_same_patches_3d(a, b, "sphere_octant2");
  expect_same_topology_3d(a, b, "sphere_octant2");
  write_gismo_xml((dir / "again.xml").string(), {&b});
  const std::string text = read_text(out);
  EXPECT_EQ(text, read_text((dir / "again.xml").string()));
  EXPECT_NE(text.find("<Geometry type=\"TensorNurbs3\" id=\"0\">"), std::string::npos);
  EXPECT_NE(text.find("<Basis type=\"TensorNurbsBasis3\">"), std::string::npos);
  EXPECT_NE(text.find("<coefs geoDim=\"3\">"), std::string::npos);
  EXPECT_NE(text.find("<MultiPatch parDim=\"3\" id=\"2\">"), std::string::npos);
  EXPECT_NE(text.find("\n0 2 1 3 1 2 0 0 1 1\n"), std::string::npos);   // as G+Smo writes it
  // a 3-D and a 2-D multipatch in one file: each its parDim
  const MultiPatch ring = read_geometry_file(kExamples + "/ring4.xml");
  const std::string both = gismo_xml_text({&ring, &a});
  EXPECT_NE(both.find("<MultiPatch parDim=\"2\" id=\"6\">"), std::string::npos);
  EXPECT_NE(both.find("<MultiPatch parDim=\"3\" id=\"7\">"), std::string::npos);
  // mixed dimensions in one multipatch cannot be written
  MultiPatch mixed = a;
  mixed.patches.push_back(ring.patches[0]);
  EXPECT_THROW(gismo_xml_text({&mixed}), std::runtime_error);
}

TEST(GeometryFile3D, InterfacesInEveryOrientationSurviveTheRoundTrip) {
  // box A = [0, 1]^3, box B = [1, 2] x [0, 1]^2 in all 48 parametrisations: the interface the
  // geometry finds is written as G+Smo's 10 numbers and read back the same; TensorBSpline3
  const Scratch dir("orient3d");
  const std::array<std::array<int, 3>, 6> perms{{{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}}};
  int cases = 0;
  for (const auto& perm : perms)
    for (int r = 0; r < 8; ++r) {
      MultiPatch mp;
      mp.patches = {box_relabelled({0, 0, 0}, {1, 1, 1}, {0, 1, 2}, {false, false, false}),
                    box_relabelled({1, 0, 0}, {1, 1, 1}, perm, {(r & 1) != 0, (r & 2) != 0, (r & 4) != 0})};
      mp.interfaces = find_interfaces(mp.patches, 1e-12);
      ASSERT_EQ(mp.interfaces.size(), 1u);
      const Side far = side_of(side_direction(mp.interfaces[0].b.side), 1 - side_end(mp.interfaces[0].b.side));
      mp.boundary = {{0, Side::West}, {1, far}};   // the faces opposite the interface
      mp.named = {{"ends", mp.boundary}};
      const std::string out = (dir / "o.xml").string();
      write_gismo_xml(out, {&mp});
      const MultiPatch b = read_gismo_xml(out);
      expect_same_patches_3d(mp, b, "orientation");
      expect_same_topology_3d(mp, b, "perm " + std::to_string(perm[0]) + std::to_string(perm[1]) + std::to_string(perm[2]) +
                                         " rev " + std::to_string(r));
      EXPECT_NE(read_text(out).find("TensorBSpline3"), std::string::npos);
      int n = 0;
      merge_control_points(b.patches, b.interfaces, n);
      EXPECT_EQ(n, 12 + 12 - 6);
      // the same through GeoPDEs text
      const MultiPatch g = read_geopdes((write_file_atomic((dir / "o.txt").string(), geopdes_text(mp)), (dir / "o.txt").string()));
      expect_same_topology_3d(mp, g, "geopdes");
      ++cases;
    }
  EXPECT_EQ(cases, 48);
}

TEST(GeometryFile3D, GeoPdesWriteThenReadAndItsInterfaceFlags) {
  const Scratch dir("geopdes3d");
  // the example through GeoPDEs text: homogeneous rows (w x may move the last bit)
  const MultiPatch a = read_geometry_file(kExamples + "/sphere_octant2.xml");
  const std::string out = (dir / "octant.txt").string();
  write_file_atomic(out, geopdes_text(a));
  const MultiPatch b = read_geopdes(out);
  ASSERT_EQ(b.patches.size(), 2u);
  for (size_t k = 0; k < 2; ++k) {
    EXPECT_EQ(b.patches[k].dim(), 3);
    EXPECT_EQ(b.patches[k].degree, a.patches[k].degree);
    EXPECT_EQ(b.patches[k].knots, a.patches[k].knots);
    ASSERT_EQ(b.patches[k].cp.size(), a.patches[k].cp.size());
    for (size_t i = 0; i < a.patches[k].cp.size(); ++i) {
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(b.patches[k].cp[i].x[c], a.patches[k].cp[i].x[c], 1e-15 * 2);
      EXPECT_EQ(b.patches[k].cp[i].w, a.patches[k].cp[i].w);
    }
  }
  expect_same_topology_3d(a, b, "octant.txt");
  EXPECT_NE(read_text(out).find("\n3 3 2 1 0\n"), std::string::npos);
  EXPECT_NE(read_text(out).find("INTERFACE 1\n1 2\n2 3\n-1 1 1\n"), std::string::npos);   // swapped face directions

  // GeoPDEs' flag ornt1 ornt2 (mp_interface_3d: flag -1 swaps the face directions, ornt k -1
  // reverses side1's direction k) against the geometry: box 1 = [0, 1]^3 (x = u, y = v,
  // z = w); box 2 = [1, 2] x [0, 1]^2 with x = 1 + w, y = 1 - v, z = u. Box 1's east face
  // (y, z) meets box 2's front face (w = 0; its u = z, v = 1 - y): y runs along v reversed,
  // z along u: flag -1, ornt1 -1, ornt2 1.
  std::ofstream(dir / "boxes.txt") << "# nurbs mesh v.2.1\n3 3 2 1 0\nPATCH 1\n1 1 1\n2 2 2\n0 0 1 1\n0 0 1 1\n0 0 1 1\n"
                                    << "0 1 0 1 0 1 0 1\n0 0 1 1 0 0 1 1\n0 0 0 0 1 1 1 1\n1 1 1 1 1 1 1 1\n"
                                    << "PATCH 2\n1 1 1\n2 2 2\n0 0 1 1\n0 0 1 1\n0 0 1 1\n"
                                    // (u, v, w) in the order u fastest: x = 1 + w, y = 1 - v, z = u
                                    << "1 1 1 1 2 2 2 2\n1 1 0 0 1 1 0 0\n0 1 0 1 0 1 0 1\n1 1 1 1 1 1 1 1\n"
                                    << "INTERFACE 1\n1 2\n2 5\n-1 -1 1\nBOUNDARY 1\n2\n1 1\n2 6\n";
  const MultiPatch c = read_geopdes((dir / "boxes.txt").string());
  ASSERT_EQ(c.interfaces.size(), 1u);
  const auto found = find_interfaces(c.patches, 1e-12);
  ASSERT_EQ(found.size(), 1u);
  EXPECT_EQ(found[0].a, (PatchSide{0, Side::East}));
  EXPECT_EQ(found[0].b, (PatchSide{1, Side::Front}));
  EXPECT_EQ(c.interfaces[0].face_map, found[0].face_map);
  EXPECT_EQ(c.interfaces[0].face_flip, found[0].face_flip);
  EXPECT_EQ(found[0].face_map, (std::array<int, 2>{1, 0}));
  EXPECT_EQ(found[0].face_flip, (std::array<bool, 2>{true, false}));
  EXPECT_EQ(c.boundary, (std::vector<PatchSide>{{0, Side::West}, {1, Side::Back}}));
  // and G+Smo's 10 numbers for the same interface, read back the same
  const MultiPatch d = read_gismo_xml((write_gismo_xml((dir / "boxes.xml").string(), {&c}), (dir / "boxes.xml").string()));
  expect_same_topology_3d(c, d, "boxes.xml");
}

TEST(GeometryFile3D, ExampleReadsTheSameFromGismoAndGeoPDEs) {
  // examples/geometry/make_geometry_3d.py writes both files on its own (not through our writers)
  const MultiPatch x = read_geometry_file(kExamples + "/sphere_octant2.xml");
  const MultiPatch t = read_geometry_file(kExamples + "/sphere_octant2.txt");
  ASSERT_EQ(x.patches.size(), t.patches.size());
  for (size_t k = 0; k < x.patches.size(); ++k) {
    const Patch &P = x.patches[k], &Q = t.patches[k];
    EXPECT_EQ(Q.dim(), 3);
    EXPECT_EQ(P.degree, Q.degree);
    EXPECT_EQ(P.knots, Q.knots);
    ASSERT_EQ(P.cp.size(), Q.cp.size());
    for (size_t a = 0; a < P.cp.size(); ++a) {
      EXPECT_EQ(P.cp[a].w, Q.cp[a].w);
      // GeoPDEs stores w x: dividing by w may move the last bit
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(P.cp[a].x[c], Q.cp[a].x[c], 1e-15 * (1 + std::abs(P.cp[a].x[c])));
    }
  }
  expect_same_topology_3d(x, t, "sphere_octant2");
}
