// Collectives inside the iteration loop, counted at the MPI boundary through
// the PMPI profiling interface (pmpi_counters.hpp): exactly one MPI_Allreduce
// per check interval (8 iterations), no other collective, and the comm
// layer's own counter agrees.
#include <gtest/gtest.h>
#include <mpi.h>

#include "app/scene_mesh.hpp"
#include "app/simulation.hpp"
#include "pmpi_counters.hpp"
#include "small_scenes.hpp"

namespace descent {
namespace {

TEST(Collectives, OneAllreducePerEightIterationsAndNothingElse) {
  Scene scene = testing::small_helix_scene();
  scene.solver.iterations = 96;
  scene.solver.check_interval = 8;
  const Mesh mesh = build_scene_mesh(scene.mesh);
  Simulation<double> sim(MPI_COMM_WORLD, scene, mesh);
  for (int frame = 0; frame < 3; ++frame) {
    const long allreduce_before = testing::pmpi_allreduces();
    const long other_before = testing::pmpi_other_collectives();
    const long counted_before = sim.reduction_counters().allreduces;
    const StepStats step = sim.step();
    ASSERT_EQ(step.iterations, 96) << "the step ended early; the count below assumes a full step";
    EXPECT_EQ(testing::pmpi_allreduces() - allreduce_before, 96 / 8) << "frame " << frame;
    EXPECT_EQ(sim.reduction_counters().allreduces - counted_before, 96 / 8);
    EXPECT_EQ(testing::pmpi_other_collectives() - other_before, 0) << "frame " << frame;
  }
}

}  // namespace
}  // namespace descent
