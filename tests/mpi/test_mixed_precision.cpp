// A float run whose energy checks are evaluated in double (issue 22, mixed
// precision; kernels/in_double.hpp): on the small helix, against Newton's
// eps* in double from the same state (the float iterate measured in the
// double twin's problem, with its held positions: app/study_trace.hpp),
//   - given solver.accuracy a float step stops at an error below the target
//     (within 3x) well before the cap, as a double step does (evaluated in
//     float, the checks' round-off hid the step's whole decrease: every step
//     ran to the cap and read an error of ~0.1);
//   - a float step at its minimum stops on the round-off reading too;
//   - run past its floor, a float step rolls back no more than double;
//   - given a target below its floor, a float step ends at its resolution;
//   - every rank count stops within a check of one rank's count.
#include <gtest/gtest.h>
#include <mpi.h>

#include <cstdio>
#include <cstdlib>
#include <vector>

#include "app/scene_mesh.hpp"
#include "app/simulation.hpp"
#include "app/study_trace.hpp"
#include "gather_positions.hpp"
#include "small_scenes.hpp"
#include "world_rank.hpp"

namespace descent {
namespace {

using testing::world_rank;

// The small helix after 3 float frames, with a double twin holding the same
// state: the truth and every measured eps are the twin's.
struct MovingInFloat {
  Scene scene;
  Mesh mesh;
  Simulation<float> sim;
  Simulation<double> twin;
  double energy_star = 0;
  explicit MovingInFloat(Scene s)
      : scene(std::move(s)),
        mesh(build_scene_mesh(scene.mesh)),
        sim(MPI_COMM_WORLD, scene, mesh),
        twin(MPI_COMM_WORLD, scene, mesh) {
    for (int frame = 0; frame < 3; ++frame) sim.step();
    twin.restore(sim.checkpoint(3));
    SolverSpec truth = scene.solver;
    truth.method = "newton";
    truth.accuracy = 0;
    energy_star = trace_step(MPI_COMM_WORLD, twin, truth).records.back().energy;
  }
  StepTrace trace(const SolverSpec& spec) { return trace_step(MPI_COMM_WORLD, sim, spec, &twin); }
};

void expect_target_met(const char* preconditioner) {
  Scene scene = testing::small_helix_scene();
  scene.solver.preconditioner = preconditioner;
  MovingInFloat m(scene);
  for (double target : {1e-2, 1e-3}) {
    SolverSpec spec = m.scene.solver;
    spec.accuracy = target;
    spec.iterations = 3000;
    const StepTrace trace = m.trace(spec);
    const double e = relative_errors(trace, m.energy_star).back();
    if (world_rank() == 0)
      std::printf("[ float %s ] target %.0e: e = %.3e after %d iterations (estimated %.3e)\n",
                  preconditioner, target, e, trace.stats.iterations, trace.stats.error_estimate);
    EXPECT_LE(e, 3 * target) << target;
    EXPECT_LT(trace.stats.iterations, spec.iterations) << "the target, not the cap, ended it";
    EXPECT_LE(trace.stats.error_estimate, target);
    // Not below half the error float reached: the estimate extrapolated past
    // the floor to 4e-13 with the multilevel preconditioner before it was
    // held at the energies' round-off.
    EXPECT_GE(trace.stats.error_estimate, 0.5 * e);
  }
}

TEST(MixedPrecision, FloatReachesTheAccuracyItIsGivenWithJacobi) { expect_target_met("jacobi"); }

TEST(MixedPrecision, FloatReachesTheAccuracyItIsGivenWithMultilevel) {
  expect_target_met("multilevel");
}

// Run far past its floor with a fixed count (no target), a float step
// moves between float states whose eps differ by float's resolution, not
// the descent's: its checks roll back no more often than its double twin's
// (without the resolution in the checks' magnitude, loops::local_energy,
// they rolled back at the floor and widened the spectrum for nothing).
void expect_no_rollback_at_the_floor(const char* preconditioner) {
  Scene scene = testing::small_helix_scene();
  scene.solver.preconditioner = preconditioner;
  MovingInFloat m(scene);
  SolverSpec spec = m.scene.solver;
  spec.accuracy = 0;
  spec.iterations = 400;
  const StepTrace in_float = m.trace(spec);
  const StepTrace in_double = trace_step(MPI_COMM_WORLD, m.twin, spec);
  const double e = relative_errors(in_float, m.energy_star).back();
  if (world_rank() == 0)
    std::printf("[ float %s ] %d fixed iterations: e = %.3e, rollbacks %d (double: %d)\n",
                preconditioner, spec.iterations, e, in_float.stats.rollbacks,
                in_double.stats.rollbacks);
  EXPECT_LT(e, 1e-3) << "the step reached its floor";
  EXPECT_LE(in_float.stats.rollbacks, in_double.stats.rollbacks);
}

TEST(MixedPrecision, AFloatStepPastItsFloorRollsBackNoMoreThanDouble) {
  expect_no_rollback_at_the_floor("jacobi");
  expect_no_rollback_at_the_floor("multilevel");
}

// A target below float's floor (its floor here: 2e-9 with the multilevel
// preconditioner, 3e-8 with Jacobi's; the resolution R of
// loops::local_energy 9e-8 of the step's decrease): the float step ends once its energies
// resolve no more progress, long before the cap, says so (at_resolution)
// and reads an error above the target; the double step reaches the target.
// With Chebyshev's bound the reading is not below the error float left.
// Nesterov's energies oscillate within the round-off while its error is
// still above it and its decrease ratio still rises, so its reading, the
// tail at the last ratio resolved, can fall short: it is held to the
// studies' criterion, within 3x (measured: 1.2e-7 for 1.8e-7).
void expect_end_at_resolution(const char* method) {
  Scene scene = testing::small_helix_scene();
  scene.solver.preconditioner = "jacobi";
  MovingInFloat m(scene);
  SolverSpec spec = m.scene.solver;
  spec.method = method;
  spec.accuracy = 1e-9;
  spec.iterations = 3000;
  const StepTrace in_float = m.trace(spec);
  const StepTrace in_double = trace_step(MPI_COMM_WORLD, m.twin, spec);
  const double e = relative_errors(in_float, m.energy_star).back();
  if (world_rank() == 0)
    std::printf(
        "[ float %s ] target 1e-9: e = %.3e after %d iterations (estimated %.3e); "
        "double: %d iterations\n",
        method, e, in_float.stats.iterations, in_float.stats.error_estimate,
        in_double.stats.iterations);
  EXPECT_TRUE(in_float.stats.at_resolution);
  EXPECT_LT(in_float.stats.iterations, spec.iterations / 4);
  EXPECT_GT(in_float.stats.error_estimate, spec.accuracy);
  const bool bounded = spec.method == "chebyshev";
  EXPECT_GE((bounded ? 1 : 3) * in_float.stats.error_estimate, e)
      << "the estimate does not claim much more than float did";
  EXPECT_FALSE(in_double.stats.at_resolution);
  EXPECT_LT(in_double.stats.iterations, spec.iterations);
}

TEST(MixedPrecision, ATargetBelowFloatsFloorEndsTheStepAtItsResolution) {
  expect_end_at_resolution("chebyshev");
  expect_end_at_resolution("nesterov");
}

// Gravity off, at rest: the step starts at its minimum and every change is
// round-off; the target is met at once in float too.
TEST(MixedPrecision, AFloatStepAtItsMinimumStopsLongBeforeTheCap) {
  Scene scene = testing::small_helix_scene();
  scene.gravity = {0, 0, 0};
  scene.solver.accuracy = 1e-3;
  scene.solver.iterations = 1000;
  const Mesh mesh = build_scene_mesh(scene.mesh);
  Simulation<float> sim{MPI_COMM_WORLD, scene, mesh};
  for (int frame = 0; frame < 2; ++frame) {
    const StepStats stats = sim.step();
    EXPECT_LE(stats.iterations, 100) << "frame " << frame;
    EXPECT_LE(stats.error_estimate, scene.solver.accuracy) << "frame " << frame;
  }
}

// A float run with a target stops before the cap on every rank count, and
// within one check of one rank's count: the halo sums its float forces in
// another order, so the iterates, unlike double's, differ by round-off.
TEST(MixedPrecision, RanksStopWithinACheckOfOneRank) {
  Scene scene = testing::small_helix_scene();
  scene.solver.accuracy = 1e-3;
  scene.solver.iterations = 3000;
  const Mesh mesh = build_scene_mesh(scene.mesh);
  const testing::OneRankComparison c =
      testing::compare_with_one_rank<float>(MPI_COMM_WORLD, scene, mesh, 3);
  if (world_rank() != 0) return;
  for (std::size_t f = 0; f < c.iterations.size(); ++f) {
    EXPECT_LT(c.iterations[f], scene.solver.iterations) << "frame " << f + 1;
    EXPECT_LE(std::abs(c.iterations[f] - c.one_rank_iterations[f]), scene.solver.check_interval)
        << "frame " << f + 1;
  }
}

}  // namespace
}  // namespace descent
