// The failure catalogue: every file in tests/bad_inputs/ starts with a line
//   # expect: <the exact first line of the message>
// where {file} stands for the file's path. Loading must throw InputError with that line.
// `# expect-prefix: ` instead gives the start of the line (messages that quote this
// machine's memory).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "model/problem.hpp"

using namespace iga;
namespace fs = std::filesystem;

TEST(BadInput, CatalogueGivesTheExpectedOneLineMessages) {
  const fs::path dir = fs::path(IGACONTACT_SOURCE_DIR) / "tests" / "bad_inputs";
  int count = 0;
  for (const auto& entry : fs::directory_iterator(dir)) {
    if (entry.path().extension() != ".yaml") continue;
    std::ifstream in(entry.path());
    std::string first;
    std::getline(in, first);
    const std::string tag = "# expect: ", ptag = "# expect-prefix: ";
    const bool prefix = first.rfind(ptag, 0) == 0;
    ASSERT_TRUE(prefix || first.rfind(tag, 0) == 0) << entry.path() << " has no '# expect: ' first line";
    std::string expect = first.substr(prefix ? ptag.size() : tag.size());
    const std::string file = entry.path().string();
    for (size_t k; (k = expect.find("{file}")) != std::string::npos;) expect.replace(k, 6, file);
    const std::string folder = entry.path().parent_path().string();
    for (size_t k; (k = expect.find("{dir}")) != std::string::npos;) expect.replace(k, 5, folder);
    ++count;
    try {
      load_problem(file);
      ADD_FAILURE() << file << " was accepted";
    } catch (const InputError& e) {
      const std::string msg = e.what();
      EXPECT_EQ(msg.find('\n'), std::string::npos) << "message is not one line: " << msg;
      if (prefix) EXPECT_EQ(msg.substr(0, expect.size()), expect) << entry.path().filename() << ": " << msg;
      else EXPECT_EQ(msg, expect) << entry.path().filename();
    }
  }
  EXPECT_GE(count, 30);
}

TEST(BadInput, MissingFileAndOverrides) {
  try { load_problem("does/not/exist.yaml"); FAIL(); } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "does/not/exist.yaml: cannot open the problem file");
  }
  const fs::path good = fs::path(IGACONTACT_SOURCE_DIR) / "examples" / "lame_cylinder.yaml";
  EXPECT_NO_THROW(load_problem(good.string(), {"bodies.0.refine.subdivide=[4,2]"}));
  const Problem P = load_problem(good.string(), {"bodies.0.material.poisson_ratio=0.25", "analysis.load_steps=3"});
  EXPECT_DOUBLE_EQ(P.bodies[0].nu, 0.25);
  EXPECT_EQ(P.load_steps, 3);
  try { load_problem(good.string(), {"bodies.0.material.poisson_ratio=0.5"}); FAIL(); } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("bodies[0].material.poisson_ratio = 0.5: must lie in (-1, 0.5)"), std::string::npos) << e.what();
  }
  try { load_problem(good.string(), {"bodies.7.name=x"}); FAIL(); } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("'7' is not an index of that list"), std::string::npos) << e.what();
  }
  try { load_problem(good.string(), {"nonsense"}); FAIL(); } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("expected KEY=VALUE"), std::string::npos) << e.what();
  }
}

TEST(BadInput, FuzzedTextNeverCrashesTheLoader) {
  // a bounded mutation run over the example files: any outcome but InputError or success fails
  const fs::path dir = fs::path(IGACONTACT_SOURCE_DIR) / "examples";
  std::vector<std::string> seeds;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().extension() == ".yaml") {
      std::ifstream in(e.path());
      seeds.emplace_back(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    }
  ASSERT_FALSE(seeds.empty());
  unsigned x = 12345;
  auto rnd = [&]() { x = x * 1103515245u + 12345u; return (x >> 8) & 0xffffff; };
  const char alphabet[] = "-0123456789.e[]{}:, \n#abcxyz";
  int accepted = 0;
  for (int it = 0; it < 3000; ++it) {
    std::string s = seeds[rnd() % seeds.size()];
    const int edits = 1 + rnd() % 4;
    for (int k = 0; k < edits && !s.empty(); ++k) {
      const size_t pos = rnd() % s.size();
      switch (rnd() % 3) {
        case 0: s[pos] = alphabet[rnd() % (sizeof(alphabet) - 1)]; break;
        case 1: s.erase(pos, 1 + rnd() % 8); break;
        default: s.insert(pos, 1, alphabet[rnd() % (sizeof(alphabet) - 1)]); break;
      }
    }
    try {
      parse_problem(s, "fuzz.yaml", {"bodies.0.refine.subdivide=1"});
      ++accepted;
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()).rfind("fuzz.yaml", 0), 0u) << e.what();
    }
  }
  std::printf("  %d of 3000 mutated files were still valid\n", accepted);
}

// --set reaches map keys that contain dots: the sides and corners of a multi-patch body
// (`patch2.south`), by the longest existing key or by a quoted component; a path that reaches
// no key of the file is still bad input with one line.
TEST(BadInput, SetReachesDottedKeysOfMultiPatchBodies) {
  const fs::path file = fs::path(IGACONTACT_SOURCE_DIR) / "examples" / "whole_wheel.yaml";
  std::ifstream in(file);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  // the hub by patch sides instead of the named boundary `inner`, plus one corner
  const std::string inner = "      inner: {displacement: {x: [0.0, 0.01], y: -0.04}}";
  const size_t at = text.find(inner);
  ASSERT_NE(at, std::string::npos);
  std::string sides;
  for (int k = 0; k < 4; ++k)
    sides += "      patch" + std::to_string(k) + ".south: {displacement: {x: [0.0, 0.01], y: -0.04}}\n";
  sides += "      patch0.south_west: {displacement: {x: [0.0, 0.01]}}";
  text.replace(at, inner.size(), sides);

  const Problem P0 = parse_problem(text, file.string(), {});
  const auto& s0 = P0.bodies[1].sides;
  ASSERT_EQ(s0.size(), 4u);
  EXPECT_DOUBLE_EQ(s0[2][static_cast<int>(Side::South)].value.back()[1], -0.04);

  const Problem P = parse_problem(text, file.string(),
      {"bodies.1.boundary.patch2.south.displacement.y=-0.05",
       "bodies.1.boundary.\"patch0.south_west\".displacement.x=[0.0, 0.25]"});
  const Body& w = P.bodies[1];
  EXPECT_DOUBLE_EQ(w.sides[2][static_cast<int>(Side::South)].value.back()[1], -0.05);
  EXPECT_DOUBLE_EQ(w.sides[1][static_cast<int>(Side::South)].value.back()[1], -0.04);
  EXPECT_DOUBLE_EQ(w.sides[2][static_cast<int>(Side::South)].value.back()[0], 0.01);
  EXPECT_DOUBLE_EQ(w.corners[0][static_cast<int>(Corner::SouthWest)].value.back()[0], 0.25);

  auto one_line_error = [&](const std::string& ov, const std::string& part) {
    try {
      parse_problem(text, file.string(), {ov});
      ADD_FAILURE() << ov << " was accepted";
    } catch (const InputError& e) {
      const std::string msg = e.what();
      EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
      EXPECT_NE(msg.find(part), std::string::npos) << ov << ": " << msg;
    }
  };
  // patch2.north is no key of the file: the walk makes `patch2: {north: ...}`, an unknown side
  one_line_error("bodies.1.boundary.patch2.north.displacement.y=0", "bodies[1].boundary.patch2 = {north:");
  one_line_error("bodies.1.boundary.patch2.north.displacement.y=0", "unknown side");
  one_line_error("bodies.1.boundary.\"patch2.south.displacement.y=0", "the key path has an unclosed quote");
  one_line_error("bodies.1.boundary.\"\".displacement.y=0", "the key path has an empty part");
  one_line_error("analysis.type.x=0", "--set analysis.type.x: 'x' is below a value, not a map");
  one_line_error("bodies.2.boundary.patch2.south.displacement.y=0", "'2' is not an index of that list");
  // a mistyped key of --set: the line names the --set it came from (it named the file alone)
  one_line_error("bodies.0.materal.youngs_modulus=5", "--set bodies.0.materal.youngs_modulus=5: bodies[0].materal = ");
  one_line_error("bodies.1.boundary.patch2.north.displacement.y=0", "--set bodies.1.boundary.patch2.north.displacement.y=0: ");
}
