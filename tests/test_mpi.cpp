// Run on 2 ranks: each problem is solved on all ranks and on rank 0 alone (MPI_COMM_SELF);
// the control point displacements must agree to 1e-10 (relative).
#include <gtest/gtest.h>
#include <Teuchos_DefaultMpiComm.hpp>
#include <mpi.h>

#include <fstream>
#include <sstream>

#include "support.hpp"

using namespace iga;
using namespace iga::test;

namespace {
void compare_one_and_many(const std::string& yaml, const std::vector<std::string>& sets, double tol) {
  auto world = Tpetra::getDefaultComm();
  ASSERT_GE(world->getSize(), 2) << "run this test with mpiexec -n 2";
  const Solved many = solve_text(yaml, world, {}, sets);
  ASSERT_TRUE(many.res.converged);
  if (world->getRank() != 0) return;
  auto self = rcp(new Teuchos::MpiComm<int>(MPI_COMM_SELF));
  const Solved one = solve_text(yaml, self, {}, sets);
  ASSERT_TRUE(one.res.converged);
  double diff = 0, norm = 0;
  for (size_t b = 0; b < one.disp.size(); ++b)
    for (size_t k = 0; k < one.disp[b].size(); ++k) {
      diff = std::max(diff, std::abs(one.disp[b][k] - many.disp[b][k]));
      norm = std::max(norm, std::abs(one.disp[b][k]));
    }
  std::printf("  max |u_1 - u_%d| / max |u| = %.2e\n", world->getSize(), diff / norm);
  EXPECT_LT(diff / norm, tol);
}
}  // namespace

TEST(OneVersusTwoRanks, LameCylinder) {
  compare_one_and_many(read(IGACONTACT_SOURCE_DIR "/examples/lame_cylinder.yaml"),
                       {"solver.linear.tolerance=1e-15", "solver.linear.max_iterations=5000"}, 1e-10);
}

TEST(OneVersusTwoRanks, TwoBlocksContact) {
  compare_one_and_many(read(IGACONTACT_SOURCE_DIR "/examples/two_blocks_middle.yaml"),
                       {"solver.linear.tolerance=1e-13"}, 1e-10);
}

TEST(OneVersusTwoRanks, TwoBlocksMortarAlm) {
  compare_one_and_many(read(IGACONTACT_SOURCE_DIR "/examples/two_blocks_middle.yaml"),
                       {"solver.linear.tolerance=1e-13", "contact.0.method=mortar_alm"}, 1e-10);
}

TEST(OneVersusTwoRanks, WheelMortarPenalty) {
  compare_one_and_many(read(IGACONTACT_SOURCE_DIR "/examples/wheel.yaml"),
                       {"solver.linear.tolerance=1e-13", "solver.linear.max_iterations=5000", "contact.0.method=mortar_penalty"},
                       1e-9);
}

TEST(OneVersusTwoRanks, SlidingBlockFriction) {
  for (const char* m : {"kts_penalty", "mortar_penalty"})
    compare_one_and_many(read(IGACONTACT_SOURCE_DIR "/examples/sliding_block.yaml"),
                         {"solver.linear.tolerance=1e-13", std::string("contact.0.method=") + m}, 1e-10);
}

TEST(OneVersusTwoRanks, CattaneoMindlinFriction) {
  compare_one_and_many(read(IGACONTACT_SOURCE_DIR "/examples/cattaneo_mindlin.yaml"),
                       {"solver.linear.tolerance=1e-13", "solver.linear.max_iterations=5000"}, 1e-10);
}

// 3-D: a neo-Hookean block (degree 2, 3 x 2 x 2 elements split over the ranks) clamped on its
// west face, a follower pressure on its top and a dead shear traction on its east face, by
// GMRES + BoomerAMG and by MUMPS.
TEST(OneVersusTwoRanks, SolidFiniteStrain) {
  const std::string yaml =
      "analysis: {type: solid, kinematics: finite, load_steps: 2}\n"
      "bodies:\n  - name: block\n    material: {model: neo_hookean, youngs_modulus: 1000.0, poisson_ratio: 0.3}\n"
      "    geometry: {box: {origin: [0, 0, 0], size: [3, 1, 1]}}\n"
      "    refine: {degree_elevate: 1, subdivide: [6, 2, 2]}\n"
      "    boundary:\n      west: {displacement: {x: 0, y: 0, z: 0}}\n      back: {pressure: 20.0}\n"
      "      east: {traction: [0, 15.0, 0]}\n";
  compare_one_and_many(yaml, {"solver.linear.method=gmres", "solver.linear.tolerance=1e-13", "solver.linear.forcing=fixed"}, 1e-10);
  compare_one_and_many(yaml, {"solver.linear.method=direct"}, 1e-10);
}
