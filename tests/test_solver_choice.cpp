// solver.linear.method: auto by degree and problem (issue 34): which solver the loader picks,
// and that the pick solves the Lame cylinder of the deal.II comparison
// (benchmarks/peers/compare_lame.sh) to its discretisation's accuracy in one Newton iteration.
#include "support.hpp"

#include <iostream>

using namespace iga;
using namespace iga::test;

namespace {

std::string lame_text() { return read(IGACONTACT_SOURCE_DIR "/examples/lame_cylinder.yaml"); }

// the Lame cylinder at degree p (its geometry is degree (2, 1)) on [2 n, n] elements
Problem lame(int p, int n, std::vector<std::string> sets = {}) {
  sets.push_back("bodies.0.refine.degree_elevate=[" + std::to_string(p - 2) + "," + std::to_string(p - 1) + "]");
  sets.push_back("bodies.0.refine.subdivide=[" + std::to_string(2 * n) + "," + std::to_string(n) + "]");
  return parse_problem(lame_text(), "test.yaml", sets);
}

long long dofs(const Problem& P) {
  long long n = 0;
  for (const Body& b : P.bodies) n += 2LL * b.num_cps;
  return n;
}

}  // namespace

// The threshold grows with the degree (a higher degree fills the factors less per dof than it
// slows BoomerAMG), and the loader follows it on either side.
TEST(AutoByDegree, ThresholdGrowsWithTheDegreeAndTheLoaderFollowsIt) {
  long long previous = 0;
  for (int p = 2; p <= 5; ++p) {
    const Problem P = lame(p, 8);
    EXPECT_GE(P.auto_direct_max_dofs(), previous) << "p = " << p;
    previous = P.auto_direct_max_dofs();
  }
  // p = 4 at about 3e4 dofs: the direct solver (above the old degree-blind 2e4)
  const Problem p4 = lame(4, 80);
  EXPECT_GT(dofs(p4), 20000);
  EXPECT_LE(dofs(p4), p4.auto_direct_max_dofs());
  EXPECT_EQ(p4.linear.method, LinearMethod::Direct);
  // p = 2 above its threshold: CG (no contact, small strain)
  const Problem p2 = lame(2, 160);
  EXPECT_GT(dofs(p2), p2.auto_direct_max_dofs());
  EXPECT_EQ(p2.linear.method, LinearMethod::CG);
}

// The configurations of the deal.II comparison (benchmarks/peers/compare_lame.sh): p = 4 on
// [192, 64] elements (26,656 dofs, the filing's) and on [NU, NV] the fewest elements of aspect
// 3 that still reach the bound; p = 5 on the fewest elements of any aspect: the solution
// u = u_r(r) e_r lies in the exact geometry's rational basis along the circumference but for
// the quadrature of rational functions, so 6 elements there and 22 through the wall reach the
// bound with 594 dofs (21 through the wall: 7e-11, 5 around: 2.6e-10 with 21). The solver
// auto picks, one Newton iteration (the problem is linear), relative L2 displacement error
// below 5e-11 (p + 1th order, docs/verification.md). The script reads the printed errors.
void lame_at_comparison_size(int p, int nu, int nv, long long dofs) {
  const std::string text = lame_text();
  const std::vector<std::string> sets = {"bodies.0.refine.degree_elevate=[" + std::to_string(p - 2) + "," +
                                             std::to_string(p - 1) + "]",
                                         "bodies.0.refine.subdivide=[" + std::to_string(nu) + "," + std::to_string(nv) + "]"};
  const Solved s = solve_text(text, Tpetra::getDefaultComm(), {}, sets);
  ASSERT_TRUE(s.res.converged) << s.res.message;
  EXPECT_EQ(s.res.newton_iterations, std::vector<int>{1});
  EXPECT_EQ(s.sys->num_dofs(), dofs);
  if (Tpetra::getDefaultComm()->getRank() != 0) return;
  const Errors e = l2_errors(s, 0, lame_cylinder(1.0, 2.0, 10.0, 2.0e5, 0.3));
  std::cout << "lame_p" << p << "_" << nu << "x" << nv << " dofs " << s.sys->num_dofs() << " l2_error " << e.u_rel
            << " solver " << linear_method_name(s.P.linear.method) << "\n";
  EXPECT_LT(e.u_rel, 5e-11);
}

TEST(AutoByDegree, LameAtTheComparisonSizeReachesItsAccuracyInOneIteration) { lame_at_comparison_size(4, 192, 64, 26656); }

TEST(AutoByDegree, LameAtTheFewestElementsReachesItsAccuracyInOneIteration) { lame_at_comparison_size(4, 126, 42, 11960); }

TEST(AutoByDegree, LameAtDegreeFiveOnTheFewestElementsOfAnyAspect) { lame_at_comparison_size(5, 6, 22, 594); }
