// Issue 33 ("no silent wrong answer"), the contact items, each from a problem file of the kind
// a user writes:
//  - bodies that touch exactly at the start (gap 0 up to round-off) and are held only by the
//    contact (and, sideways, by friction alone) converge at once with every method, to the
//    exact answer where the method has it (tests/problems/block_on_base.yaml);
//  - the reported contact force is the assembled contact residual, so it equals the reactions
//    to round-off, with friction on a curved master, KTS and mortar, on 1 and 2 ranks;
//  - a mortar run's outputs (contact CSV, result.h5, the summary) hold no NaN or inf, and the
//    slave point on the symmetry axis carries the Hertz peak pressure;
//  - the 2-D and 3-D interpenetration checks report a rigid overlap's depth exactly (in 2-D
//    also where the bodies' sides line up) and allow what a declared pair allows.
#include <gtest/gtest.h>
#include <hdf5.h>

#include <unistd.h>

#include <filesystem>
#include <map>

#include "model/configuration_check.hpp"
#include "support.hpp"

using namespace iga;
using namespace iga::test;

namespace {

const std::string kBlockOnBase = IGACONTACT_SOURCE_DIR "/tests/problems/block_on_base.yaml";

/// The block's roller taken out of the problem file (friction then holds it sideways).
std::string without_block_roller(std::string y) {
  const std::string line = "      west:  {displacement: {x: 0.0}}   # the block's roller\n";
  const size_t at = y.find(line);
  EXPECT_NE(at, std::string::npos);
  if (at != std::string::npos) y.erase(at, line.size());
  return y;
}

}  // namespace

class TouchingAtStart : public ::testing::TestWithParam<std::tuple<const char*, double, bool>> {};

// The block on the base: q = 10 over a length of 1. Every method converges in the first load
// step without a cut (before, a touching point had no stiffness when its gap was +1e-16 or
// when friction had to hold it at zero pressure: a singular first solve, 10 cuts, exit 3).
// Mortar passes the contact patch test: p = q at every slave point and lambda_A = q, no
// tangential traction, to round-off (1e-8 q: the Newton tolerance). KTS transmits the
// resultant exactly (its pressure is not uniform, docs/contact-methods.md).
TEST_P(TouchingAtStart, ConvergesToTheUniformPressure) {
  const std::string method = std::get<0>(GetParam());
  const double mu = std::get<1>(GetParam());
  const bool roller = std::get<2>(GetParam());
  const double q = 10.0, L = 1.0;
  std::string yaml = read(kBlockOnBase);
  if (!roller) yaml = without_block_roller(yaml);
  const std::vector<std::string> sets{"contact.0.method=" + method, "contact.0.friction=" + std::to_string(mu),
                                      "solver.newton.tolerance=1e-12"};
  // the initial gaps: zero to round-off, the largest on the open side (the tie the active
  // rule must break towards contact)
  {
    const Problem P = parse_problem(yaml, "block_on_base.yaml", sets);
    System sys(P, Tpetra::getDefaultComm());
    ContactPairData c(sys, 0);
    c.update(Vector(sys.owned_map()));
    double gmax = -1, gabs = 0;
    for (double g : c.state().gap) { gmax = std::max(gmax, g); gabs = std::max(gabs, std::abs(g)); }
    std::printf("  %s, mu = %g, %s: initial gaps in [.., %.2e], max |g| %.2e\n", method.c_str(), mu,
                roller ? "block on a roller" : "block held sideways by friction alone", gmax, gabs);
    ASSERT_GT(gmax, 0.0);
    ASSERT_LT(gabs, 1e-14);
  }
  const Solved s = solve_text(yaml, Tpetra::getDefaultComm(), {}, sets);
  ASSERT_TRUE(s.res.converged) << s.res.message;
  EXPECT_EQ(s.res.cuts, 0);
  const auto& c = s.res.contact[0];
  const ContactSummary cs = c.summary();
  std::printf("  force [%.3e, %.15g], normal %.15g, tangential %.2e, Newton iterations %d\n", cs.fx, cs.fy,
              cs.normal_force, cs.tangential_force, newton_total(s));
  EXPECT_NEAR(cs.fy, q * L, 1e-9 * q * L);
  EXPECT_NEAR(cs.normal_force, q * L, 1e-9 * q * L);
  EXPECT_NEAR(cs.tangential_force, 0.0, (method.rfind("kts", 0) == 0 && mu > 0 ? 1e-5 : 1e-9) * q * L);
  const auto st = c.state();
  if (method.rfind("mortar", 0) == 0) {
    double dev = 0, tau = 0;
    for (size_t i = 0; i < st.x.size(); ++i) {
      ASSERT_TRUE(st.active[i]) << "slave point " << i << " at x = " << st.x[i] << " is not in contact";
      dev = std::max(dev, std::abs(st.pressure[i] - q));
      tau = std::max(tau, std::abs(st.tangential[i]));
    }
    double dev_l = 0;
    for (double l : c.mortar_multipliers()) dev_l = std::max(dev_l, std::abs(l - q));
    std::printf("  %zu slave points: max |p - q| = %.2e, max |lambda_A - q| = %.2e, max |tau| = %.2e\n", st.x.size(), dev,
                dev_l, tau);
    EXPECT_LT(dev, 1e-8 * q);
    EXPECT_LT(dev_l, 1e-8 * q);
    EXPECT_LT(tau, 1e-8 * q);
    EXPECT_NEAR(cs.fx, 0.0, 1e-9 * q * L);
  } else {
    int active = 0;
    for (int a : st.active) active += a;
    EXPECT_EQ(active, static_cast<int>(st.x.size()));
  }
}

INSTANTIATE_TEST_SUITE_P(Methods, TouchingAtStart,
                         ::testing::Values(std::make_tuple("kts_penalty", 0.0, true), std::make_tuple("kts_alm", 0.0, true),
                                           std::make_tuple("mortar_penalty", 0.0, true),
                                           std::make_tuple("mortar_alm", 0.0, true),
                                           std::make_tuple("kts_penalty", 0.3, true),
                                           std::make_tuple("mortar_penalty", 0.3, true),
                                           std::make_tuple("mortar_alm", 0.3, true),
                                           std::make_tuple("kts_penalty", 0.3, false),
                                           std::make_tuple("mortar_penalty", 0.3, false),
                                           std::make_tuple("mortar_alm", 0.3, false)));

class ContactForce : public ::testing::TestWithParam<std::tuple<const char*, bool, int>> {};

// examples/cattaneo_mindlin.yaml (pressed, then sheared with mu = 0.3: stick and slip), as it
// is (master: the block, curved by the indentation) and with the wheel's rim as the master
// (curved, R = 1), the mesh as in the example (k = 1) and refined (k = 2). The force on the
// slave body is balanced by its support alone (no load on it), and the master's support
// carries it: F = -R_slave = R_master to round-off (1e-9 |F|: the free dofs' residuals bound
// the difference; Newton to 1e-12 leaves 1e-13, the default 1e-10 up to 9e-11). Before, with friction the summary's force was the
// quadrature of tau e and missed the weak form's factor, 2.5e-5 .. 1.1e-3 of |F|.
TEST_P(ContactForce, EqualsTheReactionsWithFriction) {
  const std::string method = std::get<0>(GetParam());
  const bool rim_master = std::get<1>(GetParam());
  const int k = std::get<2>(GetParam());
  std::vector<std::string> sets{"contact.0.method=" + method, "bodies.0.refine.subdivide=[" + std::to_string(12 * k) + ", 4]",
                                "bodies.1.refine.subdivide=[" + std::to_string(8 * k) + ", 4]", "solver.newton.tolerance=1e-12"};
  if (rim_master) sets.insert(sets.end(), {"contact.0.master.body=wheel", "contact.0.slave.body=block"});
  const Solved s = solve_text(read(IGACONTACT_SOURCE_DIR "/examples/cattaneo_mindlin.yaml"), Tpetra::getDefaultComm(), {}, sets);
  ASSERT_TRUE(s.res.converged) << s.res.message;
  const ContactSummary c = s.res.contact[0].summary();
  const FrictionCounts fc = s.res.contact[0].friction_counts();
  const auto R = reactions_json(*s.sys, *s.res.residual);
  const std::string slave = rim_master ? "block" : "wheel", master = rim_master ? "wheel" : "block";
  const std::array<double, 2> Rs{R[slave]["south"][0].get<double>(), R[slave]["south"][1].get<double>()};
  const std::array<double, 2> Rm{R[master]["south"][0].get<double>(), R[master]["south"][1].get<double>()};
  const double F = std::hypot(c.fx, c.fy);
  const double es = std::hypot(c.fx + Rs[0], c.fy + Rs[1]), em = std::hypot(c.fx - Rm[0], c.fy - Rm[1]);
  std::printf("  %s, master %s, k = %d (%d stick, %d slip): F = [%.12g, %.12g], |F + R_slave| = %.1e, |F - R_master| = %.1e "
              "of |F|; normal %.10g, tangential %.10g\n",
              method.c_str(), master.c_str(), k, fc.stick, fc.slip, c.fx, c.fy, es / F, em / F, c.normal_force,
              c.tangential_force);
  ASSERT_GT(fc.stick, 0);
  ASSERT_GT(fc.slip, 0);
  EXPECT_LT(es, 1e-9 * F);
  EXPECT_LT(em, 1e-9 * F);
  // the components along the master's normal and tangent: together they make up F up to the
  // turning of the normal over the contact zone (a / R = 0.05: 1e-3 of the force)
  EXPECT_NEAR(std::hypot(c.normal_force, c.tangential_force), F, 2e-3 * F);
}

INSTANTIATE_TEST_SUITE_P(CattaneoMindlin, ContactForce,
                         ::testing::Values(std::make_tuple("mortar_penalty", false, 1), std::make_tuple("kts_penalty", false, 1),
                                           std::make_tuple("mortar_penalty", true, 1), std::make_tuple("kts_penalty", true, 1),
                                           std::make_tuple("mortar_penalty", true, 2), std::make_tuple("kts_penalty", true, 2)));

namespace {

// every floating-point dataset of an HDF5 file, read as doubles: name -> values
herr_t collect_dataset(hid_t root, const char* name, const H5L_info_t*, void* data) {
  auto& out = *static_cast<std::map<std::string, std::vector<double>>*>(data);
  const hid_t d = H5Oopen(root, name, H5P_DEFAULT);
  if (d < 0) return 0;
  if (H5Iget_type(d) != H5I_DATASET) { H5Oclose(d); return 0; }
  const hid_t t = H5Dget_type(d);
  if (H5Tget_class(t) == H5T_FLOAT) {
    const hid_t sp = H5Dget_space(d);
    const hssize_t n = H5Sget_simple_extent_npoints(sp);
    std::vector<double> v(static_cast<size_t>(n));
    if (n > 0) H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data());
    out[name] = std::move(v);
    H5Sclose(sp);
  }
  H5Tclose(t);
  H5Oclose(d);
  return 0;
}

void expect_finite_json(const nlohmann::json& j, const std::string& path, int& numbers) {
  if (j.is_number_float()) {
    ++numbers;
    EXPECT_TRUE(std::isfinite(j.get<double>())) << path;
  } else if (j.is_null()) {
    ADD_FAILURE() << path << " is null (a NaN or inf written as JSON)";
  } else if (j.is_object()) {
    for (auto it = j.begin(); it != j.end(); ++it) expect_finite_json(it.value(), path + "." + it.key(), numbers);
  } else if (j.is_array()) {
    for (size_t k = 0; k < j.size(); ++k) expect_finite_json(j[k], path + "[" + std::to_string(k) + "]", numbers);
  }
}

}  // namespace

// examples/wheel.yaml with mortar_penalty, its outputs written as the program writes them:
// no field of contact_0.csv is empty, NaN or inf, nor any float of result.h5 or any number of
// the summary; the slave point on the symmetry axis (x = 0, the end of the rim) is there, and
// its pressure is the Hertz peak p0 of the run's load to 2 % (the example mesh: -0.6 %,
// docs/contact-methods.md) and the largest pressure to 1e-3. Before, the slave points next to
// the axis had no projection (the master's discrete end tangent tilts): gap nan, pressure 0.
TEST(MortarOutputs, NoNanAndThePeakPressureOnTheSymmetryAxis) {
  const auto comm = Tpetra::getDefaultComm();
  const Problem P = parse_problem(read(IGACONTACT_SOURCE_DIR "/examples/wheel.yaml"), "wheel.yaml",
                                  {"contact.0.method=mortar_penalty"});
  System sys(P, comm);
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("igacontact_mortar_outputs_" + std::to_string(::getpid()));
  if (comm->getRank() == 0) fs::create_directories(dir);
  comm->barrier();
  ResultWriter writer(sys, dir.string(), "wheel.yaml", "test");
  const SolveResult res = solve(sys, {}, [&](const StepState& st) { writer.step(st); });
  ASSERT_TRUE(res.converged) << res.message;
  const nlohmann::json summary = writer.finish(res);
  int numbers = 0;
  expect_finite_json(summary, "summary", numbers);
  EXPECT_GT(numbers, 20);
  if (comm->getRank() == 0) {
    // the CSV: every field a finite number
    std::ifstream in(dir / "contact_0.csv");
    std::string line;
    std::getline(in, line);
    ASSERT_EQ(line, "x,y,xi,gap,pressure,active,tangential_traction,slip,state");
    std::vector<std::array<double, 9>> rows;
    while (std::getline(in, line)) {
      std::array<double, 9> r{};
      std::stringstream ls(line);
      std::string field;
      int k = 0;
      while (std::getline(ls, field, ',')) {
        ASSERT_LT(k, 9) << line;
        ASSERT_FALSE(field.empty()) << line;
        size_t used = 0;
        r[k] = std::stod(field, &used);
        ASSERT_EQ(used, field.size()) << line;
        ASSERT_TRUE(std::isfinite(r[k])) << line;
        ++k;
      }
      ASSERT_EQ(k, 9) << line;
      rows.push_back(r);
    }
    ASSERT_GT(rows.size(), 100u);
    // result.h5: every float dataset finite
    std::map<std::string, std::vector<double>> sets;
    const hid_t f = H5Fopen((dir / "result.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    ASSERT_GE(f, 0);
    H5Lvisit(f, H5_INDEX_NAME, H5_ITER_NATIVE, collect_dataset, &sets);
    H5Fclose(f);
    ASSERT_TRUE(sets.count("contact/pair_0/gap") && sets.count("contact/pair_0/pressure"));
    EXPECT_EQ(sets["contact/pair_0/gap"].size(), rows.size());
    size_t values = 0;
    for (const auto& [name, v] : sets)
      for (double x : v) {
        ++values;
        ASSERT_TRUE(std::isfinite(x)) << "result.h5: " << name;
      }
    // the point on the symmetry axis: the end of the slave curve (largest xi)
    const auto axis = *std::max_element(rows.begin(), rows.end(), [](const auto& a, const auto& b) { return a[2] < b[2]; });
    double pmax = 0;
    for (const auto& r : rows) pmax = std::max(pmax, r[4]);
    const double E = 1000.0, nu = 0.3, Es = E / (2 * (1 - nu * nu)), Pw = 2 * summary["contact"][0]["normal_force"].get<double>();
    const double a = std::sqrt(4 * Pw * 1.0 / (M_PI * Es)), p0 = 2 * Pw / (M_PI * a);
    std::printf("  %zu CSV rows, %zu floats in result.h5; axis point x = %.2e, xi = %.12f: gap %.4e, pressure %.6g; "
                "largest %.6g; Hertz p0 %.6g (%+.2f %%)\n",
                rows.size(), values, axis[0], axis[2], axis[3], axis[4], pmax, p0, 100 * (axis[4] / p0 - 1));
    EXPECT_LT(std::abs(axis[0]), 1e-6);
    EXPECT_GT(axis[2], 1 - 1e-6);
    EXPECT_LT(axis[3], 0.0);   // in contact
    EXPECT_NEAR(axis[4], p0, 0.02 * p0);
    EXPECT_NEAR(axis[4], pmax, 1e-3 * pmax);
    fs::remove_all(dir);
  }
}

// The 3-D interpenetration check (model/configuration_check3.cpp) on two blocks, the top one
// moved rigidly down by d into the base: the depth it reports is the overlap d, exactly;
// touching (d = 0) is no finding; with a contact pair declared, 3 x its penetration and 5 % of
// the face element (here 0.035: 2 x 2 face elements of 0.5) are allowed, no more.
TEST(Penetration3, RigidOverlapOfTwoBlocks) {
  const std::string yaml = R"(analysis: {type: solid}
bodies:
  - name: base
    material: {youngs_modulus: 1.0, poisson_ratio: 0.3}
    geometry: {box: {origin: [0, 0, 0], size: [2, 2, 1]}}
    refine: {degree_elevate: 1, subdivide: [4, 4, 2]}
    boundary: {front: {displacement: {x: 0.0, y: 0.0, z: 0.0}}}
  - name: top
    material: {youngs_modulus: 1.0, poisson_ratio: 0.3}
    geometry: {box: {origin: [0.5, 0.5, 1], size: [1, 1, 1]}}
    refine: {degree_elevate: 1, subdivide: 2}
    boundary: {back: {displacement: {x: 0.0, y: 0.0, z: 0.0}}}
)";
  const std::string pair = "contact:\n  - {master: {body: base, side: back}, slave: {body: top, side: front}, penalty: 100.0}\n";
  auto check = [&](bool with_pair, double d, double pen) {
    const Problem P = parse_problem(yaml + (with_pair ? pair : ""), "blocks.yaml");
    std::vector<std::vector<double>> u;
    for (const Body& B : P.bodies) u.emplace_back(3 * static_cast<size_t>(B.num_cps), 0.0);
    for (int a = 0; a < P.bodies[1].num_cps; ++a) u[1][3 * static_cast<size_t>(a) + 2] = -d;
    return find_penetration(P, u, with_pair ? std::vector<double>{pen} : std::vector<double>{});
  };
  EXPECT_EQ(check(false, 0.0, 0.0), "");
  for (const auto& [d, text] : {std::pair<double, const char*>{0.05, "is 0.05 inside"}, {0.3, "is 0.3 inside"}}) {
    const std::string m = check(false, d, 0.0);
    EXPECT_NE(m.find("interpenetration: "), std::string::npos) << m;
    EXPECT_NE(m.find(text), std::string::npos) << m;
    EXPECT_NE(m.find("no contact pair is declared between"), std::string::npos) << m;
  }
  EXPECT_EQ(check(true, 0.03, 0.01), "");   // within 0.035
  EXPECT_EQ(check(true, 0.05, 0.02), "");   // within 3 x 0.02
  const std::string m = check(true, 0.1, 0.01);
  EXPECT_NE(m.find("is 0.1 inside"), std::string::npos) << m;
  EXPECT_NE(m.find("the contact pairs between them allow 0.035"), std::string::npos) << m;
}

// The 2-D check (model/configuration_check.cpp) on a cap moved rigidly down by d into its base,
// no pair declared: the reported depth is d, exactly, whether the cap is narrower than the base
// (its sides cross the base's top), as wide (both sides line up with the base's: the boundaries
// meet only where they touch, with no proper crossing anywhere) or flush on one side. Found by
// a problem written from the docs: a cap as wide as its base pressed 0.05 into it without a
// contact pair exited 0 with check.passed true (only proper crossings were looked at).
TEST(Penetration, RigidOverlapWhereTheSidesLineUp) {
  auto check = [](double x0, double w, double d) {
    const std::string yaml = R"(analysis: {type: plane_strain}
bodies:
  - name: base
    material: {youngs_modulus: 500.0, poisson_ratio: 0.25}
    geometry: {rectangle: {origin: [0.0, 0.0], size: [2.0, 0.4]}}
    refine: {degree_elevate: 2, subdivide: [7, 2]}
    boundary: {south: {displacement: {x: 0.0, y: 0.0}}}
  - name: cap
    material: {youngs_modulus: 500.0, poisson_ratio: 0.25}
    geometry: {rectangle: {origin: [X0, 0.4], size: [W, 0.6]}}
    refine: {degree_elevate: 2, subdivide: [4, 3]}
    boundary: {north: {displacement: {x: 0.0, y: 0.0}}}
)";
    std::string y = yaml;
    y.replace(y.find("X0"), 2, std::to_string(x0));
    y.replace(y.find("W,"), 1, std::to_string(w));
    const Problem P = parse_problem(y, "cap.yaml");
    std::vector<std::vector<double>> u;
    for (const Body& B : P.bodies) u.emplace_back(2 * static_cast<size_t>(B.num_cps), 0.0);
    for (int a = 0; a < P.bodies[1].num_cps; ++a) u[1][2 * static_cast<size_t>(a) + 1] = -d;
    return find_penetration(P, u, {});
  };
  // (0, 1): flush on the west, the east side crossing the base's top at one of its sample points
  for (const auto& [x0, w] : {std::pair<double, double>{0.5, 1.0}, {0.0, 2.0}, {0.0, 1.0}, {0.0, 1.2}, {0.8, 1.2}}) {
    SCOPED_TRACE("cap from x = " + std::to_string(x0) + ", width " + std::to_string(w));
    EXPECT_EQ(check(x0, w, 0.0), "");   // touching
    for (const auto& [d, text] : {std::pair<double, const char*>{0.05, " 0.05 inside"}, {0.2, " 0.2 inside"}}) {
      const std::string m = check(x0, w, d);
      EXPECT_NE(m.find("interpenetration: "), std::string::npos) << m;
      EXPECT_NE(m.find(text), std::string::npos) << m;
      EXPECT_NE(m.find("no contact pair is declared between"), std::string::npos) << m;
    }
  }
}

// An initial overlap of a pair's sides (model/configuration_check.cpp, check_pair_facing): bodies
// that start d inside each other get one warning line naming the pair and the depth (the run
// treats it as an interference fit); touching bodies (d = 0) and self-contact pairs get none.
// Found by a slider placed 0.05 into its base that ran as a press fit without a word.
TEST(InitialOverlap, WarnsWithTheDepthWhereTheBodiesStartInsideEachOther) {
  const std::string yaml2 = R"(analysis: {type: plane_strain}
bodies:
  - name: base
    material: {youngs_modulus: 2000.0, poisson_ratio: 0.25}
    geometry: {rectangle: {origin: [0.0, 0.0], size: [3.0, 1.0]}}
    refine: {degree_elevate: 1, subdivide: [12, 4]}
    boundary: {south: {displacement: {x: 0.0, y: 0.0}}}
  - name: slider
    material: {youngs_modulus: 500.0, poisson_ratio: 0.35}
    geometry: {rectangle: {origin: [1.0, Y0], size: [1.0, 0.5]}}
    refine: {degree_elevate: 1, subdivide: [5, 3]}
    boundary: {north: {displacement: {y: -0.01}}}
contact:
  - {master: {body: base, side: north}, slave: {body: slider, side: south}, penalty: 1.0e5}
)";
  const std::string yaml3 = R"(analysis: {type: solid}
bodies:
  - name: block
    material: {youngs_modulus: 1000.0, poisson_ratio: 0.3}
    geometry: {box: {origin: [0, 0, 0], size: [2, 2, 1]}}
    refine: {subdivide: [3, 3, 1]}
    boundary: {front: {displacement: {x: 0, y: 0, z: 0}}}
  - name: lid
    material: {youngs_modulus: 1000.0, poisson_ratio: 0.3}
    geometry: {box: {origin: [0.5, 0.5, Z0], size: [1, 1, 1]}}
    refine: {subdivide: [2, 2, 1]}
    boundary: {back: {displacement: {x: 0, y: 0, z: -0.01}}}
contact:
  - {master: {body: block, side: back}, slave: {body: lid, side: front}, penalty: 1.0e5}
)";
  auto warnings = [](std::string y, const std::string& key, const std::string& value) {
    y.replace(y.find(key), key.size(), value);
    const Problem P = parse_problem(y, "pair.yaml");
    std::string all;
    for (const std::string& w : P.warnings) all += w + "\n";
    return all;
  };
  EXPECT_EQ(warnings(yaml2, "Y0", "1.0").find("inside"), std::string::npos);   // touching
  EXPECT_EQ(warnings(yaml3, "Z0", "1.0").find("inside"), std::string::npos);
  const std::string w2 = warnings(yaml2, "Y0", "0.95"), w3 = warnings(yaml3, "Z0", "0.9");
  EXPECT_NE(w2.find("pair.yaml: contact[0]: the slave slider.south starts up to 0.05 inside the master base.north"),
            std::string::npos) << w2;
  EXPECT_NE(w3.find("pair.yaml: contact[0]: the slave lid.front starts up to 0.1 inside the master block.back"),
            std::string::npos) << w3;
  // past half the slave's smallest extent the pair is refused, with the overlap named
  try {
    warnings(yaml2, "Y0", "0.6");
    ADD_FAILURE() << "an overlap of 0.4 was accepted";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("the slave side starts up to 0.4 inside the master base.north"), std::string::npos)
        << e.what();
  }
}
