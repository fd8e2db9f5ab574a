// `linear_cg` (paper 2; solver/methods/linear_cg.hpp) on the small corotated
// helix: the converged linearly implicit step is close to Newton's implicit
// step (it is one Newton step on the same eps with dR dropped); every guess
// and preconditioner reaches the same solution, Jacobi in the fewest
// iterations; a few iterations already lower eps from the guess; Rayleigh
// stiffness damping takes kinetic energy out; P ranks agree with 1 rank;
// collectives per step are 2 + 2 x CG iterations (PMPI).
#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "app/scene_mesh.hpp"
#include "app/simulation.hpp"
#include "app/study_trace.hpp"
#include "gather_positions.hpp"
#include "mesh_extent.hpp"
#include "pmpi_counters.hpp"
#include "small_scenes.hpp"
#include "solver/methods/linear_cg.hpp"
#include "world_rank.hpp"

namespace descent {
namespace {

using testing::world_rank;

Scene corotated_helix() {
  Scene scene = testing::small_helix_scene();
  scene.material.model = "corotated";
  scene.solver.method = "linear_cg";
  return scene;
}

SolverSpec converging(SolverSpec spec) {
  spec.iterations = 2000;
  spec.linear_cg_tolerance = 1e-10;
  return spec;
}

// max over free local dofs of |a - b|, over all ranks.
double max_difference(const std::vector<double>& a, const std::vector<double>& b) {
  double worst = 0;
  for (std::size_t k = 0; k < a.size(); ++k) worst = std::max(worst, std::abs(a[k] - b[k]));
  MPI_Allreduce(MPI_IN_PLACE, &worst, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
  return worst;
}

// One step of `spec` from the simulation's state, the state left untouched.
struct Solved {
  BodyState<double> state;
  StepStats stats;
  int cg_iterations = 0;
  double residual2 = 0;
};

Solved solve(Simulation<double>& sim, const SolverSpec& spec) {
  LinearCg<double> method(sim.problem(), spec);
  Solved s{sim.state(), {}, 0, 0};
  s.stats = method.step(s.state);
  s.cg_iterations = method.cg_iterations();
  s.residual2 = method.relative_residual2();
  return s;
}

// Converged linear_cg vs Newton's implicit step, as a fraction of the step.
struct Linearisation {
  double relative_error = 0;  // max |q - q_newton| / max |q_newton - q_t|
  double e = 0;               // relative energy error against Newton's eps*
};

Linearisation compare_with_newton(double dt) {
  Scene scene = corotated_helix();
  scene.time.dt = dt;
  const Mesh mesh = build_scene_mesh(scene.mesh);
  Simulation<double> sim(MPI_COMM_WORLD, scene, mesh);
  for (int frame = 0; frame < 3; ++frame) sim.step();  // moving, stretched by gravity

  const Solved linear = solve(sim, converging(scene.solver));
  EXPECT_LE(linear.residual2, 1e-10);
  EXPECT_LT(linear.cg_iterations, 2000);
  SolverSpec newton_spec = scene.solver;
  newton_spec.method = "newton";
  std::unique_ptr<Stepper<double>> newton = make_stepper(sim.problem(), newton_spec);
  BodyState<double> exact = sim.state();
  const StepStats truth = newton->step(exact);

  const double step = max_difference(exact.q, sim.state().q);
  const double error = max_difference(linear.state.q, exact.q);
  Linearisation l;
  l.relative_error = error / step;
  l.e = (linear.stats.energy - truth.energy) / (linear.stats.initial_energy - truth.energy);
  if (world_rank() == 0)
    std::printf(
        "h = 1/%.0f: linear_cg converged in %d iterations (r.r/b.b %.1e): "
        "max |q - q_newton| = %.3e of a step of %.3e; e = %.2e\n",
        1 / dt, linear.cg_iterations, linear.residual2, error, step, l.e);
  return l;
}

// Linearly implicit Euler is one Newton step (without dR) on implicit
// Euler's eps: its distance from Newton's solution is second order in the
// step, so relative to the step it shrinks with h. A wrong right-hand side or
// operator would leave an O(1) fraction.
TEST(LinearCg, ConvergedStepApproachesNewtonsImplicitStepAsHShrinks) {
  const Linearisation coarse = compare_with_newton(1.0 / 30);
  const Linearisation fine = compare_with_newton(1.0 / 120);
  EXPECT_LE(coarse.relative_error, 0.05);
  EXPECT_LE(fine.relative_error, 0.5 * coarse.relative_error);
  for (const Linearisation& l : {coarse, fine}) {
    EXPECT_GE(l.e, -1e-12);  // Newton's eps* is the minimum
    EXPECT_LE(l.e, 1e-2);
  }
}

TEST(LinearCg, EveryGuessAndPreconditionerReachesTheSameSolution) {
  const Scene scene = corotated_helix();
  const Mesh mesh = build_scene_mesh(scene.mesh);
  Simulation<double> sim(MPI_COMM_WORLD, scene, mesh);
  for (int frame = 0; frame < 3; ++frame) sim.step();

  SolverSpec reference_spec = converging(scene.solver);
  reference_spec.linear_cg_tolerance = 1e-20;  // to round-off
  const Solved reference = solve(sim, reference_spec);
  const double step = max_difference(reference.state.q, sim.state().q);
  const char* const preconditioners[3] = {"identity", "mass", "jacobi"};
  int fewest[3] = {1 << 30, 1 << 30, 1 << 30}, most[3] = {0, 0, 0};
  for (int p = 0; p < 3; ++p) {
    for (const char* guess : {"zero", "velocity", "euler"}) {
      SolverSpec spec = converging(scene.solver);
      spec.linear_cg_preconditioner = preconditioners[p];
      spec.linear_cg_guess = guess;
      const Solved s = solve(sim, spec);
      const double difference = max_difference(s.state.q, reference.state.q);
      if (world_rank() == 0)
        std::printf("%-8s guess %-8s: %4d iterations, max |q - q_ref| = %.2e of a step of %.2e\n",
                    preconditioners[p], guess, s.cg_iterations, difference, step);
      EXPECT_LE(s.residual2, 1e-10) << preconditioners[p] << " " << guess;
      // r.r <= 1e-10 b.b bounds the error by sqrt(1e-10 cond(A)) |v|.
      EXPECT_LE(difference, 1e-3 * step) << preconditioners[p] << " " << guess;
      fewest[p] = std::min(fewest[p], s.cg_iterations);
      most[p] = std::max(most[p], s.cg_iterations);
    }
  }
  // Paper 2, §4: Jacobi converges in far fewer iterations than I or M.
  EXPECT_LT(most[2], std::min(fewest[0], fewest[1]));
}

TEST(LinearCg, AFewIterationsLowerTheEnergyFromEveryGuess) {
  const Scene scene = corotated_helix();
  const Mesh mesh = build_scene_mesh(scene.mesh);
  Simulation<double> sim(MPI_COMM_WORLD, scene, mesh);
  for (int frame = 0; frame < 3; ++frame) sim.step();
  for (const char* guess : {"zero", "velocity", "euler"}) {
    SolverSpec spec = scene.solver;
    spec.linear_cg_guess = guess;
    spec.iterations = 10;
    const StepTrace trace = trace_step(MPI_COMM_WORLD, sim, spec);
    ASSERT_EQ(trace.records.size(), 11u) << guess;
    const double e0 = trace.records.front().energy, e10 = trace.records.back().energy;
    if (world_rank() == 0) std::printf("guess %-8s eps0 %.9e  eps10 %.9e\n", guess, e0, e10);
    EXPECT_LT(e10, e0 - 1e-8 * std::abs(e0)) << guess;
  }
}

TEST(LinearCg, RayleighStiffnessDampingTakesKineticEnergyOut) {
  Scene scene = corotated_helix();
  scene.solver.iterations = 10;
  const Mesh mesh = build_scene_mesh(scene.mesh);
  double kinetic[2] = {0, 0};
  for (int damped = 0; damped < 2; ++damped) {
    scene.solver.rayleigh_stiffness = damped ? 0.01 : 0.0;
    Simulation<double> sim(MPI_COMM_WORLD, scene, mesh);
    for (int frame = 0; frame < 10; ++frame) sim.step();
    kinetic[damped] = testing::kinetic_energy(MPI_COMM_WORLD, sim);
  }
  if (world_rank() == 0)
    std::printf("kinetic energy after 10 frames: %.4e undamped, %.4e with beta = 0.01 s\n",
                kinetic[0], kinetic[1]);
  EXPECT_GT(kinetic[0], 0);
  EXPECT_LT(kinetic[1], 0.9 * kinetic[0]);
}

TEST(LinearCg, DistributedRunsAgreeWithOneRank) {
  Scene scene = corotated_helix();
  const Mesh mesh = build_scene_mesh(scene.mesh);
  const double diagonal = testing::bounding_box_diagonal(mesh);
  for (int iterations : {5, 2000}) {
    scene.solver.iterations = iterations;
    const testing::OneRankComparison c =
        testing::compare_with_one_rank(MPI_COMM_WORLD, scene, mesh, 3);
    if (world_rank() != 0) continue;
    std::printf(
        "linear_cg, %d iterations: max |q_P - q_1| = %.3e, max |q_1 - rest| = %.3e "
        "(bbox diagonal %.3f)\n",
        iterations, c.worst, c.moved, diagonal);
    EXPECT_GT(c.moved, 1e-3 * diagonal);
    EXPECT_LE(c.worst, 1e-9 * diagonal) << iterations;
  }
}

TEST(LinearCg, CollectivesPerStepAreTwoPlusTwoPerIteration) {
  Scene scene = corotated_helix();
  scene.solver.linear_cg_tolerance = 0;  // the fixed count only
  const Mesh mesh = build_scene_mesh(scene.mesh);
  for (int iterations : {1, 2, 5, 10}) {
    scene.solver.iterations = iterations;
    Simulation<double> sim(MPI_COMM_WORLD, scene, mesh);
    sim.step();
    const long allreduce = testing::pmpi_allreduces(), other = testing::pmpi_other_collectives();
    const StepStats stats = sim.step();
    EXPECT_EQ(stats.iterations, iterations);
    EXPECT_EQ(testing::pmpi_allreduces() - allreduce, 2 + 2 * iterations) << iterations;
    EXPECT_EQ(testing::pmpi_other_collectives() - other, 0) << iterations;
  }
}

TEST(LinearCg, FloatAgreesWithDouble) {
  Scene scene = corotated_helix();
  scene.solver.iterations = 10;
  const Mesh mesh = build_scene_mesh(scene.mesh);
  const double diagonal = testing::bounding_box_diagonal(mesh);
  Simulation<double> in_double(MPI_COMM_WORLD, scene, mesh);
  Simulation<float> in_float(MPI_COMM_WORLD, scene, mesh);
  for (int frame = 0; frame < 5; ++frame) {
    in_double.step();
    in_float.step();
  }
  const std::vector<double> want = in_double.owned_positions();
  const std::vector<double> got = in_float.owned_positions();
  const double worst = max_difference(got, want);
  if (world_rank() == 0)
    std::printf("linear_cg float vs double after 5 frames: %.3e (bbox diagonal %.3f)\n", worst,
                diagonal);
  EXPECT_LE(worst, 1e-4 * diagonal);
}

}  // namespace
}  // namespace descent
