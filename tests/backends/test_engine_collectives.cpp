// Collectives of the Chebyshev engine with fixed parameters, counted at the
// MPI boundary through PMPI (tests/mpi/pmpi_counters.hpp): exactly one
// MPI_Allreduce per energy check (12 per 96-iteration step) and no other
// collective inside a step, in float, for gather and scatter assembly
// (tests/mpi/test_collectives.cpp counts the automatic parameters' pattern).
#include <gtest/gtest.h>
#include <mpi.h>

#include "app/scene_mesh.hpp"
#include "tests/backends/compare_runs.hpp"
#include "tests/mpi/pmpi_counters.hpp"
#include "tests/mpi/small_scenes.hpp"

namespace descent {
namespace {

TEST(EngineCollectives, OneAllreducePerCheckAndNothingElse) {
  Scene scene = testing::fixed_chebyshev(testing::small_helix_scene());
  scene.solver.iterations = 96;
  scene.solver.check_interval = 8;
  const Mesh mesh = build_scene_mesh(scene.mesh);
  for (Assembly assembly : {Assembly::gather, Assembly::scatter}) {
    Simulation<float> sim(MPI_COMM_WORLD, scene, mesh,
                          testing::backend_of(BackendKind::cpu, assembly));
    for (int frame = 0; frame < 3; ++frame) {
      const long allreduce_before = testing::pmpi_allreduces();
      const long other_before = testing::pmpi_other_collectives();
      const StepStats step = sim.step();
      ASSERT_EQ(step.iterations, 96) << "the step ended early; the count below assumes a full step";
      EXPECT_EQ(testing::pmpi_allreduces() - allreduce_before, 96 / 8)
          << to_string(assembly) << ", frame " << frame;
      EXPECT_EQ(testing::pmpi_other_collectives() - other_before, 0)
          << to_string(assembly) << ", frame " << frame;
    }
  }
}

}  // namespace
}  // namespace descent
