// The methods of solver.method (docs/methods.md) on the small helix: each
// lowers eps; Newton reaches |g| <= 1e-10 |g0| and converges quadratically
// near the solution; Chebyshev after 96 iterations is >= 10x below plain
// gradient descent in relative error against Newton's eps*; P ranks agree
// with 1 rank.
#include <gtest/gtest.h>
#include <mpi.h>

#include <cmath>
#include <cstdio>

#include "app/scene_mesh.hpp"
#include "app/simulation.hpp"
#include "app/study_trace.hpp"
#include "gather_positions.hpp"
#include "mesh_extent.hpp"
#include "small_scenes.hpp"
#include "solver/methods/newton.hpp"
#include "world_rank.hpp"

namespace descent {
namespace {

const char* const kMethods[] = {"chebyshev", "gd",    "jacobi_gd", "nesterov",
                                "ncg",       "lbfgs", "newton"};

using testing::world_rank;

// Two Chebyshev frames: the small helix moving, stretched by gravity.
void start_moving(Simulation<double>& sim) {
  for (int frame = 0; frame < 2; ++frame) sim.step();
}

TEST(Methods, EachMethodLowersTheEnergy) {
  Scene scene = testing::small_helix_scene();
  const Mesh mesh = build_scene_mesh(scene.mesh);
  Simulation<double> sim(MPI_COMM_WORLD, scene, mesh);
  start_moving(sim);
  for (const char* method : kMethods) {
    SolverSpec spec = scene.solver;
    spec.method = method;
    spec.iterations = 32;
    const StepTrace trace = trace_step(MPI_COMM_WORLD, sim, spec);
    ASSERT_GE(trace.records.size(), 2u) << method;
    const double e0 = trace.records.front().energy, e1 = trace.records.back().energy;
    if (world_rank() == 0) std::printf("%-10s eps0 %.9e  eps_end %.9e\n", method, e0, e1);
    // A real decrease: far above the round-off of eps.
    EXPECT_LT(e1, e0 - 1e-8 * std::abs(e0)) << method;
  }
}

// pd_chebyshev is defined on the arap energy only: the same check there,
// against chebyshev on the same energy.
TEST(Methods, PdChebyshevLowersTheArapEnergy) {
  Scene scene = testing::small_helix_scene();
  scene.material.model = "arap";
  const Mesh mesh = build_scene_mesh(scene.mesh);
  Simulation<double> sim(MPI_COMM_WORLD, scene, mesh);
  start_moving(sim);
  for (const char* method : {"pd_chebyshev", "chebyshev"}) {
    SolverSpec spec = scene.solver;
    spec.method = method;
    spec.iterations = 32;
    const StepTrace trace = trace_step(MPI_COMM_WORLD, sim, spec);
    const double e0 = trace.records.front().energy, e1 = trace.records.back().energy;
    if (world_rank() == 0) std::printf("arap %-12s eps0 %.9e  eps_end %.9e\n", method, e0, e1);
    EXPECT_LT(e1, e0 - 1e-8 * std::abs(e0)) << method;
  }
}

// Eq. 10 minimises the quadratic model of eps along h v: its initial guess
// is no worse than constant velocity (d = 1) on the moving helix.
TEST(Methods, OptimizedInitialisationBeatsConstantVelocity) {
  Scene scene = testing::small_helix_scene();
  const Mesh mesh = build_scene_mesh(scene.mesh);
  Simulation<double> sim(MPI_COMM_WORLD, scene, mesh);
  start_moving(sim);
  SolverSpec spec = scene.solver;
  spec.iterations = 8;
  spec.init = "velocity";
  const double velocity = trace_step(MPI_COMM_WORLD, sim, spec).records.front().energy;
  spec.init = "optimized";
  const double optimized = trace_step(MPI_COMM_WORLD, sim, spec).records.front().energy;
  if (world_rank() == 0)
    std::printf("eps(q0): constant velocity %.9e, optimized step %.9e\n", velocity, optimized);
  EXPECT_LE(optimized, velocity);
  EXPECT_NE(optimized, velocity);  // d = 1 exactly would mean Eq. 10 was not applied
}

TEST(Methods, NewtonReachesTheGradientCriterionQuadratically) {
  Scene scene = testing::small_helix_scene();
  const Mesh mesh = build_scene_mesh(scene.mesh);
  Simulation<double> sim(MPI_COMM_WORLD, scene, mesh);
  // Far from equilibrium, so Newton needs several iterations and shows its rate.
  sim.set_positions(testing::stretched_positions(mesh));
  SolverSpec spec = scene.solver;
  spec.method = "newton";
  spec.init = "position";
  Newton<double> newton(sim.problem(), spec);
  BodyState<double> state = sim.state();
  const StepStats stats = newton.step(state);
  const std::vector<double>& g = newton.gradient_norms();
  if (world_rank() == 0) {
    std::printf("newton: %d iterations, %d line-search halvings, CG iterations:", stats.iterations,
                stats.rollbacks);
    for (int cg : newton.cg_iterations()) std::printf(" %d", cg);
    std::printf("\n");
  }
  ASSERT_GE(g.size(), 3u);
  if (world_rank() == 0) {
    for (std::size_t k = 0; k < g.size(); ++k)
      std::printf("newton %zu |g|/|g0| = %.3e\n", k, g[k] / g[0]);
  }
  EXPECT_LE(g.back(), 1e-10 * g.front());
  // Quadratic: once |g| is small (below 1e-2 |g0|), the next Newton step
  // at least squares the relative gradient (up to a factor 10), unless that
  // is below the CG solve's own floor (1e-10 of the current gradient) or the
  // round-off of evaluating the gradient (~1e-13 |g0| here).
  int checked = 0;
  for (std::size_t k = 0; k + 1 < g.size(); ++k) {
    const double now = g[k] / g[0], next = g[k + 1] / g[0];
    if (now > 1e-2 || next < 1e-9 * now || next < 1e-12) continue;
    EXPECT_LE(next, 10 * now * now) << "Newton step " << k << " is not quadratic";
    ++checked;
  }
  EXPECT_GE(checked, 1) << "no Newton step in the quadratic regime was seen";
}

TEST(Methods, ChebyshevIsTenTimesBelowGradientDescentAfter96Iterations) {
  Scene scene = testing::small_helix_scene();
  const Mesh mesh = build_scene_mesh(scene.mesh);
  Simulation<double> sim(MPI_COMM_WORLD, scene, mesh);
  start_moving(sim);
  SolverSpec spec = scene.solver;
  spec.iterations = 96;
  spec.method = "newton";
  const StepTrace truth = trace_step(MPI_COMM_WORLD, sim, spec);
  const double energy_star = truth.records.back().energy;
  spec.method = "chebyshev";
  const double chebyshev =
      relative_errors(trace_step(MPI_COMM_WORLD, sim, spec), energy_star).back();
  spec.method = "gd";
  const double gd = relative_errors(trace_step(MPI_COMM_WORLD, sim, spec), energy_star).back();
  if (world_rank() == 0)
    std::printf("relative error after 96 iterations: chebyshev %.3e, gd %.3e\n", chebyshev, gd);
  EXPECT_GT(chebyshev, -1e-9);  // eps* is the minimum: no method goes below it
  EXPECT_LE(chebyshev * 10, gd);
}

// 3 frames of each method on all ranks against 1 rank. Methods without inner
// products differ only by the energy sums' order; those with them also by
// the order of each inner product's terms, amplified by their recurrences.
TEST(Methods, DistributedRunsAgreeWithOneRank) {
  Scene scene = testing::small_helix_scene();
  const Mesh mesh = build_scene_mesh(scene.mesh);
  const double diagonal = testing::bounding_box_diagonal(mesh);
  std::vector<const char*> methods(std::begin(kMethods), std::end(kMethods));
  methods.push_back("pd_chebyshev");
  for (const char* method : methods) {
    scene.solver.method = method;
    scene.solver.iterations = 48;
    scene.material.model = std::string(method) == "pd_chebyshev" ? "arap" : "neo_hookean";
    const testing::OneRankComparison c =
        testing::compare_with_one_rank(MPI_COMM_WORLD, scene, mesh, 3);
    if (world_rank() != 0) continue;
    std::printf("%-10s max |q_P - q_1| = %.3e (bbox diagonal %.3f)\n", method, c.worst, diagonal);
    EXPECT_GT(c.moved, 1e-3 * diagonal) << method;
    EXPECT_LE(c.worst, 1e-9 * diagonal) << method;
  }
}

}  // namespace
}  // namespace descent
