// Collectives inside the iteration loop, counted at the MPI boundary through
// the PMPI profiling interface (pmpi_counters.hpp): exactly one MPI_Allreduce
// per check interval (8 iterations), no other collective, and the comm
// layer's own counter agrees; with the automatic parameters the steps that
// estimate the spectrum add 2 + 2 per Lanczos step, every spectrum_interval
// steps and after a rollback, and the others add nothing. With the
// multilevel preconditioner each application of P^-1 adds one
// MPI_Allgatherv (the coarsest solve) and nothing else, and each refresh
// 1 + 2 x 10 MPI_Allgather (the smoother bounds) and the gather of the
// coarsest operator (an MPI_Allgather and an MPI_Allgatherv).
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

TEST(Collectives, MultilevelAddsOneGatherPerVcycle) {
  Scene scene = testing::small_helix_scene();
  scene.solver.iterations = 32;
  scene.solver.check_interval = 8;
  scene.solver.spectrum_interval = 0;  // the first step and after rollbacks only
  scene.solver.spectrum_steps = 12;
  scene.solver.preconditioner = "multilevel";
  scene.solver.multilevel_coarse_size = 200;
  const Mesh mesh = build_scene_mesh(scene.mesh);
  Simulation<double> sim(MPI_COMM_WORLD, scene, mesh);
  for (int frame = 0; frame < 3; ++frame) {
    const long allreduce_before = testing::pmpi_allreduces();
    const long other_before = testing::pmpi_other_collectives();
    const long gatherv_before = testing::pmpi_allgathervs();
    const StepStats step = sim.step();
    ASSERT_EQ(step.iterations, 32) << "the step ended early; the count below assumes a full step";
    const bool estimated = step.spectrum_steps > 0;
    EXPECT_EQ(estimated, frame == 0 || step.rollbacks > 0) << "frame " << frame;
    const long refreshes = 1 + step.rollbacks;
    // One V-cycle per iteration, per Lanczos step and for the start vector.
    const long vcycles = 32 + (estimated ? 1 + step.spectrum_steps : 0);
    EXPECT_EQ(testing::pmpi_allreduces() - allreduce_before,
              32 / 8 + (estimated ? 2 + 2 * step.spectrum_steps : 0))
        << "frame " << frame;
    EXPECT_EQ(testing::pmpi_allgathervs() - gatherv_before, vcycles + refreshes)
        << "frame " << frame;
    EXPECT_EQ(testing::pmpi_other_collectives() - other_before, refreshes * (1 + 2 * 10 + 1))
        << "frame " << frame;
  }
}

}  // namespace
}  // namespace descent
