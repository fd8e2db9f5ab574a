// Physics sanity on 1 and 2 ranks: discrete free fall of implicit Euler, a
// hanging helix that comes to rest under air damping, and energies at
// accepted checks that never rise within a step.
#include <gtest/gtest.h>
#include <mpi.h>

#include <cmath>

#include "app/scene_mesh.hpp"
#include "app/simulation.hpp"
#include "gather_positions.hpp"
#include "small_scenes.hpp"

namespace descent {
namespace {

// With no fixed vertex and nothing but gravity, implicit Euler gives
// v_n = n h g and q_n = q_0 + g h^2 n (n + 1) / 2 exactly; the solver must
// reach it to 1e-9 relative every frame.
TEST(Physics, FreeFallFollowsDiscreteImplicitEuler) {
  Scene scene;
  scene.mesh.generator = "box";
  scene.mesh.box.cells = {4, 3, 2};
  scene.mesh.box.size = {0.4, 0.3, 0.2};
  scene.gravity = {0.0, -9.81, 0.0};
  scene.time.dt = 1.0 / 30.0;
  scene.material.young = 1e4;
  scene.solver.iterations = 400;
  const Mesh mesh = build_scene_mesh(scene.mesh);
  Simulation<double> sim(MPI_COMM_WORLD, scene, mesh);
  const double h = scene.time.dt;
  const LocalMesh& l = sim.local_mesh();
  for (int n = 1; n <= 20; ++n) {
    sim.step();
    const double drop = 9.81 * h * h * n * (n + 1) / 2.0;
    double worst = 0;
    for (index_t v = 0; v < l.num_vertices(); ++v) {
      for (int i = 0; i < 3; ++i) {
        const double want = l.rest_positions[3 * v + i] - (i == 1 ? drop : 0.0);
        worst = std::max(worst, std::abs(sim.state().q[3 * v + i] - want));
      }
    }
    MPI_Allreduce(MPI_IN_PLACE, &worst, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
    ASSERT_LE(worst, 1e-9 * drop) << "frame " << n << ": drop " << drop;
  }
}

TEST(Physics, HangingHelixComesToRestAndEnergyNeverRisesWithinAStep) {
  Scene scene = testing::small_helix_scene();
  scene.solver.damping = 4.0;
  const Mesh mesh = build_scene_mesh(scene.mesh);
  Simulation<double> sim(MPI_COMM_WORLD, scene, mesh);
  double peak = 0, last = 0;
  double late_peak = 0;
  for (int frame = 1; frame <= 150; ++frame) {
    const StepStats step = sim.step();
    EXPECT_LE(step.energy, step.initial_energy + step.energy_tolerance) << "frame " << frame;
    last = testing::kinetic_energy(MPI_COMM_WORLD, sim);
    peak = std::max(peak, last);
    if (frame > 120) late_peak = std::max(late_peak, last);
    printf("frame %d KE %g alpha %g rollbacks %d it %d E %.10g\n", frame, last, step.alpha,
           step.rollbacks, step.iterations, step.energy);
  }
  EXPECT_GT(peak, 0.0);
  EXPECT_LT(late_peak, 1e-2 * peak)
      << "kinetic energy in the last second " << late_peak << ", peak " << peak;
}

}  // namespace
}  // namespace descent
