// The linear solvers behind solve_linear. The direct solver (MUMPS) must give the solution the
// iterative one (GMRES or CG + BoomerAMG or MueLu, tolerance 1e-13) gives, for elasticity and for every
// contact method, frictionless (L D L^T) and with friction (L U); L D L^T and L U must agree
// where the tangent is symmetric; the analysis and the factors are reused where the pattern
// or the matrix has not changed; a singular matrix is reported in one line, without cuts.
// Runs on 1 rank (test_linear) and on 2 (test_linear_2ranks: each rank passes its own rows).
#include "support.hpp"

using namespace iga;
using namespace iga::test;

namespace {

Solved solve_problem(Problem P) {
  Solved s;
  s.P = std::move(P);
  s.sys = rcp(new System(s.P, Tpetra::getDefaultComm()));
  s.res = solve(*s.sys);
  s.disp = gather_displacements(*s.sys, *s.res.u);
  return s;
}

// max |u_a - u_b| / max |u_b| over all control points (rank 0; 0 elsewhere)
double relative_difference(const Solved& a, const Solved& b) {
  double diff = 0, norm = 0;
  for (size_t k = 0; k < a.disp.size(); ++k)
    for (size_t i = 0; i < a.disp[k].size(); ++i) {
      diff = std::max(diff, std::abs(a.disp[k][i] - b.disp[k][i]));
      norm = std::max(norm, std::abs(b.disp[k][i]));
    }
  return norm > 0 ? diff / norm : diff;
}

struct Case {
  std::string name, yaml;
  std::vector<std::string> sets;
  std::string iterative = "gmres";
};

std::vector<Case> cases() {
  std::vector<Case> cs;
  cs.push_back({"LameCylinder", read(IGACONTACT_SOURCE_DIR "/examples/lame_cylinder.yaml"), {}, "cg"});
  for (const char* m : {"kts_penalty", "mortar_penalty", "mortar_alm"}) {
    RingAndBlock rb;
    rb.method = m;
    cs.push_back({std::string("RingAndBlock_") + m, rb.yaml(), {}});
  }
  // the iterative cases above run with the default preconditioner (BoomerAMG); MueLu here
  {
    RingAndBlock rb;
    cs.push_back({"RingAndBlock_kts_penalty_MueLu", rb.yaml(), {"solver.linear.preconditioner=muelu"}});
  }
  // kts_alm over-constrains the gap where slave points outnumber master dofs (the ring and
  // block, the two blocks): the patch test, whose meshes it fits
  cs.push_back({"PatchTest_kts_alm", read(IGACONTACT_SOURCE_DIR "/examples/patch_test_uniform.yaml"),
                {"contact.0.method=kts_alm"}});
  cs.push_back({"SlidingBlockFriction", read(IGACONTACT_SOURCE_DIR "/examples/sliding_block.yaml"), {}});
  cs.push_back({"WheelMortarFriction", read(IGACONTACT_SOURCE_DIR "/examples/wheel.yaml"),
                {"contact.0.method=mortar_penalty", "contact.0.friction=0.3"}});
  return cs;
}

}  // namespace

class DirectAgainstIterative : public ::testing::TestWithParam<int> {};

TEST_P(DirectAgainstIterative, SameSolution) {
  const Case c = cases()[GetParam()];
  std::vector<std::string> it = c.sets, di = c.sets;
  it.insert(it.end(), {"solver.linear.method=" + c.iterative, "solver.linear.tolerance=1e-13", "solver.linear.forcing=fixed",
                       "solver.linear.max_iterations=5000"});
  di.push_back("solver.linear.method=direct");
  const Solved a = solve_text(c.yaml, Tpetra::getDefaultComm(), {}, it);
  const Solved b = solve_text(c.yaml, Tpetra::getDefaultComm(), {}, di);
  ASSERT_TRUE(a.res.converged) << a.res.message;
  ASSERT_TRUE(b.res.converged) << b.res.message;
  EXPECT_EQ(b.P.linear.symmetric, c.name.find("Friction") == std::string::npos);
  EXPECT_GE(b.res.direct.factorisations, 1);
  const double d = relative_difference(a, b);
  if (Tpetra::getDefaultComm()->getRank() == 0)
    std::printf("  %s: max |u_direct - u_%s| / max |u| = %.2e, Newton %d / %d\n", c.name.c_str(),
                c.iterative.c_str(), d, static_cast<int>(a.res.newton_iterations.size()),
                static_cast<int>(b.res.newton_iterations.size()));
  // Newton stops at relative residual 1e-10 on either path: the solutions agree to about
  // that times the condition of the tangent's contact part, far below 1e-7
  EXPECT_LT(d, 1e-7);
}

INSTANTIATE_TEST_SUITE_P(Cases, DirectAgainstIterative, ::testing::Range(0, static_cast<int>(cases().size())),
                         [](const ::testing::TestParamInfo<int>& i) { return cases()[i.param].name; });

// Inexact Newton: with the Eisenstat-Walker forcing (the default for gmres and cg without
// friction) each Krylov solve stops at a tolerance that follows Newton's progress, and Newton
// still converges to its own tolerance: the same solution as with every solve at 1e-12, to
// what Newton's residual allows, with far fewer Krylov iterations. The solutions differ by
// the condition of the tangent times Newton's tolerance (1.5e-10 at the default 1e-10):
// Newton is asked for 1e-11 here, and the gap must be below 1e-7. Frictionless KTS and
// mortar. (With friction, auto keeps the fixed tolerance: see solver/newton.cpp.)
TEST(Forcing, EisenstatWalkerReachesTheSolutionWithFewerIterations) {
  for (const char* m : {"kts_penalty", "mortar_penalty"}) {
    const std::vector<std::string> base = {"solver.linear.method=gmres", "solver.linear.max_iterations=3000",
                                           "solver.newton.tolerance=1e-11", std::string("contact.0.method=") + m};
    std::vector<std::string> ew = base, fixed = base;
    fixed.push_back("solver.linear.forcing=fixed");
    const std::string yaml = read(IGACONTACT_SOURCE_DIR "/examples/wheel.yaml");
    const Solved a = solve_text(yaml, Tpetra::getDefaultComm(), {}, ew);
    const Solved b = solve_text(yaml, Tpetra::getDefaultComm(), {}, fixed);
    ASSERT_TRUE(a.res.converged) << m << ": " << a.res.message;
    ASSERT_TRUE(b.res.converged) << m << ": " << b.res.message;
    EXPECT_EQ(a.P.linear.forcing, Forcing::Auto);
    const double d = relative_difference(a, b);
    if (Tpetra::getDefaultComm()->getRank() == 0)
      std::printf("  %s: max |u_ew - u_fixed| / max |u| = %.2e; linear iterations %d / %d; Newton %d / %d\n", m, d,
                  a.res.linear_iterations, b.res.linear_iterations, newton_total(a), newton_total(b));
    EXPECT_LT(d, 1e-7) << m;
    // fewer: measured with BoomerAMG (the default) 481 -> 140 and 356 -> 110 on 1 rank,
    // 497 -> 130 and 371 -> 110 on 2
    EXPECT_LT(a.res.linear_iterations, b.res.linear_iterations) << m;
  }
}

// The frictionless tangent is symmetric: L D L^T (the upper triangle only) gives what L U gives.
TEST(DirectSolver, LdltMatchesLu) {
  for (const char* m : {"kts_penalty", "kts_alm", "mortar_penalty", "mortar_alm"}) {
    RingAndBlock rb;
    rb.method = m;
    const bool alm = std::string(m) == "kts_alm";
    Problem P = parse_problem(alm ? read(IGACONTACT_SOURCE_DIR "/examples/patch_test_uniform.yaml") : rb.yaml(),
                              "test.yaml", {"solver.linear.method=direct", std::string("contact.0.method=") + m});
    ASSERT_TRUE(P.linear.symmetric);
    const Solved ldlt = solve_problem(P);
    P.linear.symmetric = false;
    const Solved lu = solve_problem(P);
    ASSERT_TRUE(ldlt.res.converged && lu.res.converged);
    EXPECT_EQ(ldlt.res.newton_iterations, lu.res.newton_iterations) << m;
    EXPECT_LT(relative_difference(ldlt, lu), 1e-10) << m;
  }
}

// Linear elasticity over several load steps: one analysis, one factorisation, a solve per step.
TEST(DirectSolver, ReusesAnalysisAndFactors) {
  const Solved s = solve_text(read(IGACONTACT_SOURCE_DIR "/examples/lame_cylinder.yaml"), Tpetra::getDefaultComm(),
                              {}, {"solver.linear.method=direct", "analysis.load_steps=3"});
  ASSERT_TRUE(s.res.converged);
  EXPECT_EQ(s.res.direct.analyses, 1);
  EXPECT_EQ(s.res.direct.factorisations, 1);
  int newton = 0;
  for (int n : s.res.newton_iterations) newton += n;
  EXPECT_EQ(s.res.direct.solves, newton);
  // contact: the analysis is redone only where the tangent's pattern changed
  const Solved w = solve_text(read(IGACONTACT_SOURCE_DIR "/examples/wheel.yaml"), Tpetra::getDefaultComm(), {},
                              {"solver.linear.method=direct"});
  ASSERT_TRUE(w.res.converged);
  EXPECT_LE(w.res.direct.analyses, w.res.tangent_rebuilds);
  EXPECT_GT(w.res.direct.factor_bytes, 0);
  EXPECT_GT(w.res.direct.factor_entries, 0);
}

// Kept factors (GMRES on the factors of an earlier tangent) are given up by a count of
// operations, not by a clock: the same run twice in one process takes the same path, to the
// bit (it had differed run to run in its factorisation count and at round-off). The friction
// example keeps factors across Newton iterations and refactorises some of the time.
TEST(DirectSolver, KeptFactorsRepeatExactly) {
  const std::string yaml = read(IGACONTACT_SOURCE_DIR "/examples/cattaneo_mindlin.yaml");
  const std::vector<std::string> sets = {"solver.linear.method=direct", "solver.linear.condense=false"};
  const Solved a = solve_text(yaml, Tpetra::getDefaultComm(), {}, sets);
  const Solved b = solve_text(yaml, Tpetra::getDefaultComm(), {}, sets);
  ASSERT_TRUE(a.res.converged && b.res.converged);
  EXPECT_GT(a.res.direct.factorisations, 1);
  EXPECT_LT(a.res.direct.factorisations, a.res.direct.solves);   // factors were kept for some solves
  EXPECT_EQ(a.res.direct.factorisations, b.res.direct.factorisations);
  EXPECT_EQ(a.res.linear_iterations, b.res.linear_iterations);
  if (Tpetra::getDefaultComm()->getSize() == 1) {
    EXPECT_EQ(a.disp, b.disp);
  } else if (Tpetra::getDefaultComm()->getRank() == 0) {
    // several ranks: the same path, and MUMPS' parallel scheduling adds round-off only
    EXPECT_LT(relative_difference(a, b), 1e-12);
  }
}

// Solves condensed onto the contact sides (small strain: the tangent changes only in their
// rows and columns, solved by the Schur complement of one factorisation updated per Newton
// iteration) give the ordinary factorisation's answer: the same Newton path and displacements
// to round-off, for every contact method, with friction (L U) too; one analysis and one
// factorisation for the whole run, every solve condensed.
TEST(DirectSolver, CondensedSolvesMatchFactorisedOnes) {
  std::vector<std::pair<std::string, std::vector<std::string>>> runs;
  for (const char* m : {"kts_penalty", "mortar_penalty", "mortar_alm"}) {
    RingAndBlock rb;
    rb.method = m;
    runs.push_back({rb.yaml(), {}});
  }
  runs.push_back({read(IGACONTACT_SOURCE_DIR "/examples/sliding_block.yaml"), {}});
  runs.push_back({read(IGACONTACT_SOURCE_DIR "/examples/wheel.yaml"), {"contact.0.friction=0.3"}});
  for (auto& [yaml, sets] : runs) {
    // (these small problems' sides hold more than the twelfth of the dofs auto condenses at)
    sets.push_back("solver.linear.method=direct");
    sets.push_back("solver.linear.condense=true");
    const Problem P = parse_problem(yaml, "test.yaml", sets);
    ASSERT_TRUE(P.condensed_contact());
    const Solved c = solve_problem(P);
    std::vector<std::string> plain = sets;
    plain.back() = "solver.linear.condense=false";
    const Solved f = solve_problem(parse_problem(yaml, "test.yaml", plain));
    ASSERT_TRUE(c.res.converged && f.res.converged) << c.res.message << f.res.message;
    EXPECT_EQ(c.res.newton_iterations, f.res.newton_iterations) << sets[0];
    EXPECT_EQ(c.res.direct.analyses, 1);
    EXPECT_EQ(c.res.direct.factorisations, 1);
    EXPECT_EQ(c.res.direct.condensed_solves, newton_total(c));
    EXPECT_GT(c.res.direct.condensed_rank, 0);   // the contact tangent did change
    EXPECT_EQ(f.res.direct.condensed_solves, 0);
    if (Tpetra::getDefaultComm()->getRank() == 0) EXPECT_LT(relative_difference(c, f), 1e-9) << sets[0];
  }
}

// The condensed solve on a matrix of its own: a 1-D Laplacian (L D L^T and L U) whose last
// 12 rows and columns change after the factorisation (a dense update, non-symmetric for L U): the
// solution equals a fresh factorisation's; a change in the set's coupling to the other dofs is
// noticed (the other rows are the caller's to keep: the elastic stiffness at small strain).
TEST(DirectSolver, CondensedSolveOfAChangedBlock) {
  const auto comm = Tpetra::getDefaultComm();
  const GO n = 300, m = 12;
  const RCP<const Map> map = rcp(new Map(static_cast<Tpetra::global_size_t>(n), 0, comm));
  auto make = [&](double block, double outside, bool symmetric) {
    RCP<Matrix> A = rcp(new Matrix(map, 3 + m));
    for (LO l = 0; l < static_cast<LO>(map->getNodeNumElements()); ++l) {
      const GO i = map->getGlobalElement(l);
      std::vector<GO> cols;
      std::vector<double> vals;
      cols.push_back(i);
      vals.push_back(2.0);
      // the coupling of the set's first dof with the dof before it: `outside` changes it
      if (i > 0) { cols.push_back(i - 1); vals.push_back(-1.0 + (i == n - m ? outside : 0.0)); }
      if (i + 1 < n) { cols.push_back(i + 1); vals.push_back(-1.0 + (i + 1 == n - m ? outside : 0.0)); }
      if (i >= n - m)
        for (GO j = n - m; j < n; ++j)
          if (std::abs(j - i) > 1 || j == i) {
            const double v = block * (symmetric ? std::sin(1.0 + 0.37 * static_cast<double>(i + j) + 0.11 * static_cast<double>(i * j))
                                                : std::sin(1.0 + 0.37 * static_cast<double>(i) + 0.11 * static_cast<double>(j * j)));
            if (j == i) vals[0] += std::abs(block) * 3;
            else { cols.push_back(j); vals.push_back(v); }
          }
      A->insertGlobalValues(i, Teuchos::ArrayView<const GO>(cols), Teuchos::ArrayView<const double>(vals));
    }
    A->fillComplete();
    return A;
  };
  std::vector<GO> set;
  for (GO j = n - m; j < n; ++j) set.push_back(j);
  Vector b(map);
  b.randomize();
  for (bool symmetric : {true, false}) {
    DirectSolver ds(comm);
    ds.set_condensed(set);
    // (factorised with a block already there: for L U a non-symmetric Schur complement, whose
    // layout a symmetric one would not tell)
    const RCP<Matrix> A0 = make(symmetric ? 0.0 : 0.1, 0.0, symmetric);
    ASSERT_TRUE(ds.factorise(*A0, symmetric).converged);
    ASSERT_TRUE(ds.condensed_ready(*A0, symmetric));
    // the changed block: symmetric for L D L^T (which reads the upper triangle), not for L U
    const RCP<Matrix> A1 = make(0.3, 0.0, symmetric);
    ASSERT_TRUE(ds.condensed_ready(*A1, symmetric));
    Vector x(map), y(map);
    const LinearSolveResult r = ds.solve_condensed(*A1, x, b, symmetric);
    ASSERT_TRUE(r.converged) << r.message;
    DirectSolver fresh(comm);
    ASSERT_TRUE(fresh.solve(*A1, y, b, symmetric).converged);
    y.update(-1.0, x, 1.0);
    EXPECT_LT(y.normInf() / x.normInf(), 1e-12) << symmetric;
    EXPECT_EQ(ds.stats().factorisations, 1);
    EXPECT_EQ(ds.stats().condensed_rank, static_cast<int>(m));
    // a change outside the block (the set's coupling to the other dofs, A_CI): not condensable
    EXPECT_FALSE(ds.condensed_ready(*make(0.3, 0.5, symmetric), symmetric));
  }
}

// A body held by nothing but a contact pair that is open (a gap of 0.1, a traction pulls it
// away): the tangent is singular. The direct solver says so, and no smaller increment is tried.
TEST(DirectSolver, SingularMatrixIsReported) {
  const std::string yaml =
      "bodies:\n"
      "  - name: base\n    material: {youngs_modulus: 1000.0, poisson_ratio: 0.3}\n"
      "    geometry: {rectangle: {origin: [0, 0], size: [2.0, 1.0]}}\n"
      "    refine: {degree_elevate: 1, subdivide: [4, 2]}\n"
      "    boundary: {south: {displacement: {x: 0, y: 0}}}\n"
      "  - name: free\n    material: {youngs_modulus: 1000.0, poisson_ratio: 0.3}\n"
      "    geometry: {rectangle: {origin: [0.5, 1.1], size: [1.0, 0.5]}}\n"
      "    refine: {degree_elevate: 1, subdivide: [2, 2]}\n"
      "    boundary: {north: {traction: [0.0, 1.0]}}\n"
      "contact:\n  - {master: {body: base, side: north}, slave: {body: free, side: south}, method: kts_penalty, penalty: 1.0e4}\n";
  const Solved s = solve_text(yaml, Tpetra::getDefaultComm(), {}, {"solver.linear.method=direct"});
  EXPECT_FALSE(s.res.converged);
  EXPECT_NE(s.res.message.find("singular"), std::string::npos) << s.res.message;
  EXPECT_EQ(s.res.message.find('\n'), std::string::npos) << s.res.message;
  EXPECT_EQ(s.res.cuts, 0);
}

// auto: the direct solver for a small problem, the iterative one above the crossover.
TEST(LinearMethod, AutoChoosesBySize) {
  const std::string lame = read(IGACONTACT_SOURCE_DIR "/examples/lame_cylinder.yaml");
  Problem small = parse_problem(lame, "test.yaml", {});
  EXPECT_TRUE(small.linear.automatic);
  EXPECT_EQ(small.linear.method, LinearMethod::Direct);
  Problem big = parse_problem(lame, "test.yaml", {"bodies.0.refine.subdivide=[400,300]"});
  EXPECT_TRUE(big.linear.automatic);
  EXPECT_EQ(big.linear.method, LinearMethod::CG);
  Problem given = parse_problem(lame, "test.yaml", {"solver.linear.method=gmres"});
  EXPECT_FALSE(given.linear.automatic);
  EXPECT_EQ(given.linear.method, LinearMethod::GMRES);
  // contact at small strain: direct, condensed onto the contact sides, up to 2e5 dofs in 2-D
  // (the 77,380-dof wheel: 1,546 side dofs); without condensation, or at finite strain, GMRES
  const std::string wheel = read(IGACONTACT_SOURCE_DIR "/examples/wheel_scaling.yaml");
  Problem w = parse_problem(wheel, "test.yaml", {});
  EXPECT_TRUE(w.condensed_contact());
  EXPECT_EQ(w.contact_side_dofs(), 2 * (515 + 258));
  EXPECT_EQ(w.linear.method, LinearMethod::Direct);
  EXPECT_EQ(parse_problem(wheel, "test.yaml", {"solver.linear.condense=false"}).linear.method, LinearMethod::GMRES);
  EXPECT_EQ(parse_problem(wheel, "test.yaml", {"analysis.kinematics=finite"}).linear.method, LinearMethod::GMRES);
  EXPECT_EQ(parse_problem(wheel, "test.yaml", {"bodies.0.refine.subdivide=[512,256]"}).linear.method,
            LinearMethod::GMRES);
  // sides holding more than a twelfth of the dofs (the wheel's block coarsened: 1,546 of
  // 15,460): not condensed by auto (a long strip was 21x slower so), by `true` they are
  const std::vector<std::string> coarse = {"bodies.0.refine.subdivide=[256,8]"};
  EXPECT_FALSE(parse_problem(wheel, "test.yaml", coarse).condensed_contact());
  EXPECT_NE(parse_problem(wheel, "test.yaml", coarse).not_condensed_reason().find("more than 1/12"), std::string::npos);
  std::vector<std::string> forced = coarse;
  forced.push_back("solver.linear.condense=true");
  EXPECT_TRUE(parse_problem(wheel, "test.yaml", forced).condensed_contact());
}

// A linear problem (small strain, no contact) is solved once: auto forcing keeps the fixed
// Krylov tolerance there, so one Newton iteration (one CG solve) meets Newton's tolerance,
// and the answer is the Lame solution to the discretisation's accuracy. Eisenstat-Walker,
// asked for by name, takes more Newton iterations to the same answer.
TEST(LinearMethod, LinearProblemTakesOneNewtonIteration) {
  const std::string lame = read(IGACONTACT_SOURCE_DIR "/examples/lame_cylinder.yaml");
  const std::vector<std::string> sets = {"solver.linear.method=cg", "bodies.0.refine.subdivide=[32,16]"};
  EXPECT_FALSE(eisenstat_walker_forcing(parse_problem(lame, "test.yaml", sets)));
  const Solved once = solve_text(lame, Tpetra::getDefaultComm(), {}, sets);
  ASSERT_TRUE(once.res.converged) << once.res.message;
  EXPECT_EQ(once.res.newton_iterations, std::vector<int>{1});
  std::vector<std::string> ew = sets;
  ew.push_back("solver.linear.forcing=eisenstat_walker");
  const Solved inexact = solve_text(lame, Tpetra::getDefaultComm(), {}, ew);
  ASSERT_TRUE(inexact.res.converged) << inexact.res.message;
  EXPECT_GT(newton_total(inexact), 1);
  if (Tpetra::getDefaultComm()->getRank() != 0) return;
  // quarter annulus a = 1, b = 2, p = 10, E = 2e5, nu = 0.3 (examples/lame_cylinder.yaml),
  // degree (3, 3), 16 elements across the wall: the discretisation's displacement error is
  // 1.03e-7 (docs/verification.md, p = 3, n = 16); the one solve must not add to it (1 %),
  // and both solves agree far below it
  const Errors e = l2_errors(once, 0, lame_cylinder(1.0, 2.0, 10.0, 2.0e5, 0.3));
  EXPECT_NEAR(e.u_rel, 1.032e-7, 0.01 * 1.032e-7);
  EXPECT_LT(relative_difference(once, inexact), 1e-8);
}
