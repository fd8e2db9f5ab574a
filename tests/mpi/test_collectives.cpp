// Collectives inside the iteration loop, counted at the MPI boundary through
// the PMPI profiling interface (pmpi_counters.hpp): exactly one MPI_Allreduce
// per check interval (8 iterations), no other collective, and the comm
// layer's own counter agrees; with the automatic parameters the steps that
// estimate the spectrum add 2 + 2 per Lanczos step, every spectrum_interval
// steps and after a rollback, and the others add nothing.
#include <gtest/gtest.h>
#include <mpi.h>

#include "app/scene_mesh.hpp"
#include "app/simulation.hpp"
#include "pmpi_counters.hpp"
#include "small_scenes.hpp"

namespace descent {
namespace {

TEST(Collectives, OneAllreducePerEightIterationsAndNothingElse) {
  Scene scene = testing::fixed_chebyshev(testing::small_helix_scene());
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

TEST(Collectives, AutomaticParametersEstimateEveryIntervalSteps) {
  Scene scene = testing::small_helix_scene();
  scene.solver.iterations = 96;
  scene.solver.check_interval = 8;
  scene.solver.spectrum_interval = 4;
  scene.solver.spectrum_steps = 12;
  const Mesh mesh = build_scene_mesh(scene.mesh);
  Simulation<double> sim(MPI_COMM_WORLD, scene, mesh);
  int estimates = 0, since = 0;  // steps since the last estimate (0: none yet)
  bool rolled_back = false;      // the previous step did
  for (int frame = 0; frame < 9; ++frame) {
    const long allreduce_before = testing::pmpi_allreduces();
    const long other_before = testing::pmpi_other_collectives();
    const long checks_before = sim.reduction_counters().allreduces;
    const StepStats step = sim.step();
    const long checks = sim.reduction_counters().allreduces - checks_before;
    // Every check is one allreduce; a step may end early only at a check.
    EXPECT_EQ(checks, (step.iterations + 7) / 8) << "frame " << frame;
    const bool estimated = step.spectrum_steps > 0;
    // Estimates at the first step, then every 4 steps, and after a step
    // that rolled back.
    EXPECT_EQ(estimated, since == 0 || since >= 4 || rolled_back) << "frame " << frame;
    since = estimated ? 1 : since + 1;
    rolled_back = step.rollbacks > 0;
    estimates += estimated ? 1 : 0;
    const long expected = checks + (estimated ? 2 + 2 * step.spectrum_steps : 0);
    EXPECT_EQ(testing::pmpi_allreduces() - allreduce_before, expected)
        << "frame " << frame << ": " << step.spectrum_steps << " Lanczos steps";
    EXPECT_EQ(testing::pmpi_other_collectives() - other_before, 0) << "frame " << frame;
  }
  EXPECT_GE(estimates, 3);
}

}  // namespace
}  // namespace descent
