// Newton with solver.newton_solver = "ldlt" (solver/methods/newton_ldlt.hpp)
// on the small helix stretched (or compressed) far from equilibrium: it
// reaches |g| <= 1e-10 |g0| in no more Newton iterations than with CG, its
// result equals CG's, its collectives are as documented (gathers to rank 0,
// no allreduce of its own), an indefinite exact Hessian is detected and
// replaced by the projected one, the solve itself satisfies H dq = -g, and
// P ranks agree with 1 rank.
#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "app/scene_mesh.hpp"
#include "app/simulation.hpp"
#include "gather_positions.hpp"
#include "mesh_extent.hpp"
#include "small_scenes.hpp"
#include "solver/methods/newton.hpp"
#include "world_rank.hpp"

namespace descent {
namespace {

using testing::world_rank;

using testing::stretched_positions;

struct NewtonRun {
  StepStats stats;
  std::vector<double> gradient_norms;
  std::vector<int> cg_iterations;
  int projected_solves = 0;
  std::vector<double> q;  // local vertices, after the step
  double seconds = 0;     // newton.step, slowest rank
  ReductionCounters before, after;
  ReductionCounters setup;  // counter increments of the constructor
};

NewtonRun run_newton(Simulation<double>& sim, const Scene& scene, const char* solver) {
  SolverSpec spec = scene.solver;
  spec.method = "newton";
  spec.init = "position";
  spec.newton_solver = solver;
  NewtonRun run;
  const ReductionCounters start = sim.reduction_counters();
  Newton<double> newton(sim.problem(), spec);
  run.before = sim.reduction_counters();
  run.setup.root_gathers = run.before.root_gathers - start.root_gathers;
  run.setup.root_scatters = run.before.root_scatters - start.root_scatters;
  run.setup.dot_allreduces = run.before.dot_allreduces - start.dot_allreduces;
  BodyState<double> state = sim.state();
  MPI_Barrier(MPI_COMM_WORLD);
  const double t0 = MPI_Wtime();
  run.stats = newton.step(state);
  double seconds = MPI_Wtime() - t0;
  run.after = sim.reduction_counters();
  MPI_Allreduce(MPI_IN_PLACE, &seconds, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
  run.seconds = seconds;
  run.gradient_norms = newton.gradient_norms();
  run.cg_iterations = newton.cg_iterations();
  run.projected_solves = newton.projected_solves();
  run.q.assign(state.q.begin(), state.q.end());
  return run;
}

void print_run(const char* solver, const NewtonRun& run) {
  if (world_rank() != 0) return;
  std::printf("%s: %d Newton iterations, %d halvings, %d projected, %zu solves, %.3f s", solver,
              run.stats.iterations, run.stats.rollbacks, run.projected_solves,
              run.cg_iterations.size(), run.seconds);
  std::printf(", CG iterations:");
  for (int cg : run.cg_iterations) std::printf(" %d", cg);
  std::printf("\n%s |g|/|g0|:", solver);
  for (double g : run.gradient_norms) std::printf(" %.3e", g / run.gradient_norms.front());
  std::printf("\n");
}

class NewtonLdltTest : public ::testing::Test {
 protected:
  void SetUp() override {
    scene_ = testing::small_helix_scene();
    mesh_ = build_scene_mesh(scene_.mesh);
    diagonal_ = testing::bounding_box_diagonal(mesh_);
  }
  Scene scene_;
  Mesh mesh_;
  double diagonal_ = 0;
};

TEST_F(NewtonLdltTest, ReachesTheGradientCriterionInNoMoreIterationsThanCg) {
  Simulation<double> sim(MPI_COMM_WORLD, scene_, mesh_);
  sim.set_positions(stretched_positions(mesh_));
  const NewtonRun cg = run_newton(sim, scene_, "cg");
  const NewtonRun ldlt = run_newton(sim, scene_, "ldlt");
  print_run("cg", cg);
  print_run("ldlt", ldlt);
  const std::vector<double>& g = ldlt.gradient_norms;
  ASSERT_GE(g.size(), 3u);
  EXPECT_LE(g.back(), 1e-10 * g.front());
  EXPECT_FALSE(ldlt.stats.stalled);
  EXPECT_LE(ldlt.stats.iterations, cg.stats.iterations);
  // One entry per linear solve, 0: no CG iteration behind an ldlt solve.
  EXPECT_EQ(ldlt.cg_iterations.size(),
            static_cast<std::size_t>(ldlt.stats.iterations + ldlt.projected_solves));
  for (int it : ldlt.cg_iterations) EXPECT_EQ(it, 0);
  // Quadratic once |g| < 1e-2 |g0|, down to the round-off of the gradient.
  int checked = 0;
  for (std::size_t k = 0; k + 1 < g.size(); ++k) {
    const double now = g[k] / g[0], next = g[k + 1] / g[0];
    if (now > 1e-2 || next < 1e-12) continue;
    EXPECT_LE(next, 10 * now * now) << "Newton step " << k << " is not quadratic";
    ++checked;
  }
  EXPECT_GE(checked, 1) << "no Newton step in the quadratic regime was seen";
}

// Both solve the same Newton systems to (near) round-off; their results
// differ by the gradient criterion's slack only.
TEST_F(NewtonLdltTest, EqualsCgOnEveryRankCount) {
  Simulation<double> sim(MPI_COMM_WORLD, scene_, mesh_);
  sim.set_positions(stretched_positions(mesh_));
  const NewtonRun cg = run_newton(sim, scene_, "cg");
  const NewtonRun ldlt = run_newton(sim, scene_, "ldlt");
  double worst = 0, moved = 0;
  const std::size_t owned = 3 * static_cast<std::size_t>(sim.local_mesh().num_owned);
  for (std::size_t k = 0; k < owned; ++k) {
    worst = std::max(worst, std::abs(ldlt.q[k] - cg.q[k]));
    moved = std::max(moved, std::abs(ldlt.q[k] - sim.state().q[k]));
  }
  double maxima[2] = {worst, moved};
  MPI_Allreduce(MPI_IN_PLACE, maxima, 2, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
  if (world_rank() == 0)
    std::printf("max |q_ldlt - q_cg| = %.3e, max |q_ldlt - q0| = %.3e (bbox diagonal %.3f)\n",
                maxima[0], maxima[1], diagonal_);
  EXPECT_GT(maxima[1], 1e-3 * diagonal_);  // the step moved: equality is not trivial
  EXPECT_LE(maxima[0], 1e-10 * diagonal_);
}

// Per ldlt solve one gather and one scatter, no allreduce beyond g.dq; the
// set-up gathers three times, scatters and reduces nothing.
TEST_F(NewtonLdltTest, CollectivesAsDocumented) {
  Simulation<double> sim(MPI_COMM_WORLD, scene_, mesh_);
  sim.set_positions(stretched_positions(mesh_));
  const NewtonRun ldlt = run_newton(sim, scene_, "ldlt");
  EXPECT_EQ(ldlt.setup.root_gathers, 3);
  EXPECT_EQ(ldlt.setup.root_scatters, 0);
  EXPECT_EQ(ldlt.setup.dot_allreduces, 0);
  const long solves = static_cast<long>(ldlt.cg_iterations.size());
  EXPECT_EQ(ldlt.after.root_gathers - ldlt.before.root_gathers, solves);
  EXPECT_EQ(ldlt.after.root_scatters - ldlt.before.root_scatters, solves);
  const long dots = ldlt.after.dot_allreduces - ldlt.before.dot_allreduces;
  const long energies = ldlt.after.allreduces - ldlt.before.allreduces;
  EXPECT_EQ(dots, static_cast<long>(ldlt.gradient_norms.size()) + solves);  // |g|^2, g.dq
  EXPECT_EQ(energies, ldlt.stats.iterations + ldlt.stats.rollbacks);        // line search
}

// Three frames of newton with ldlt on all ranks against 1 rank.
TEST_F(NewtonLdltTest, DistributedRunsAgreeWithOneRank) {
  scene_.solver.method = "newton";
  scene_.solver.newton_solver = "ldlt";
  const testing::OneRankComparison c =
      testing::compare_with_one_rank(MPI_COMM_WORLD, scene_, mesh_, 3);
  if (world_rank() != 0) return;
  std::printf("ldlt max |q_P - q_1| = %.3e, max |q_1 - rest| = %.3e (bbox diagonal %.3f)\n",
              c.worst, c.moved, diagonal_);
  EXPECT_GT(c.moved, 1e-4 * diagonal_);
  EXPECT_LE(c.worst, 1e-10 * diagonal_);
}

// Compressed to 70% of its height the exact Hessian is indefinite: a D entry
// <= 0 sends the iteration to the projected Hessian, as CG's p.Hp <= 0 does.
TEST_F(NewtonLdltTest, FallsBackToTheProjectedHessianWhenIndefinite) {
  Simulation<double> sim(MPI_COMM_WORLD, scene_, mesh_);
  sim.set_positions(stretched_positions(mesh_, 0.7));
  const NewtonRun cg = run_newton(sim, scene_, "cg");
  const NewtonRun ldlt = run_newton(sim, scene_, "ldlt");
  print_run("compressed cg", cg);
  print_run("compressed ldlt", ldlt);
  EXPECT_GE(ldlt.projected_solves, 1);
  EXPECT_LE(ldlt.gradient_norms.back(), 1e-10 * ldlt.gradient_norms.front());
  // The exact Newton step of an indefinite system is no good direction:
  // taking it costs iterations and halvings that CG's fallback does not.
  EXPECT_LE(ldlt.stats.iterations, cg.stats.iterations);
  EXPECT_LE(ldlt.stats.rollbacks, cg.stats.rollbacks);
}

// The solver alone at the compressed state: H dq = -g to round-off (checked
// with the distributed product), dq = 0 on held dofs, and the flag: not
// positive definite for the exact Hessian, positive for the projected one.
TEST_F(NewtonLdltTest, SolvesTheAssembledSystem) {
  Simulation<double> sim(MPI_COMM_WORLD, scene_, mesh_);
  sim.set_positions(stretched_positions(mesh_, 0.7));
  LocalProblem<double>& problem = sim.problem();
  HessianOperator<double> hessian(problem);
  NewtonLdlt<double> ldlt(problem, hessian);
  const std::size_t n = 3 * static_cast<std::size_t>(problem.num_vertices());
  const std::size_t owned = 3 * static_cast<std::size_t>(problem.mesh().num_owned);
  const auto& fixed = problem.fixed_axes();
  auto held = [&](std::size_t dof) { return (fixed[dof / 3] >> (dof % 3)) & 1u; };
  // A right-hand side with every free dof in play: g = sin of the global dof.
  std::vector<double> g(n), dq(n), hdq(n);
  for (std::size_t k = 0; k < n; ++k)
    g[k] = held(k) ? 0.0 : std::sin(3.0 * problem.mesh().global_vertex[k / 3] + double(k % 3));
  for (bool project : {false, true}) {
    hessian.assemble(sim.state().q.data(), project);
    const bool positive = ldlt.solve(g.data(), dq.data());
    hessian.apply(dq.data(), hdq.data());
    double sums[3] = {0, 0, 0};  // |H dq + g|^2, |g|^2, |dq on held dofs|^2
    for (std::size_t k = 0; k < owned; ++k) {
      sums[0] += (hdq[k] + g[k]) * (hdq[k] + g[k]);
      sums[1] += g[k] * g[k];
      if (held(k)) sums[2] += dq[k] * dq[k];
    }
    MPI_Allreduce(MPI_IN_PLACE, sums, 3, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
    const double relative = std::sqrt(sums[0] / sums[1]);
    if (world_rank() == 0)
      std::printf("%s Hessian: positive %d, |H dq + g| / |g| = %.3e\n",
                  project ? "projected" : "exact", int(positive), relative);
    EXPECT_EQ(positive, project) << (project ? "projected" : "exact");
    EXPECT_LE(relative, 1e-8);
    EXPECT_EQ(sums[2], 0.0);
  }
}

// The float instantiation: the same option reaches a small gradient too.
TEST_F(NewtonLdltTest, FloatLowersTheGradient) {
  Simulation<float> sim(MPI_COMM_WORLD, scene_, mesh_);
  sim.set_positions(stretched_positions(mesh_));
  SolverSpec spec = scene_.solver;
  spec.method = "newton";
  spec.init = "position";
  spec.newton_solver = "ldlt";
  spec.newton_iterations = 8;  // float's round-off floor is near 1e-6 |g0|
  Newton<float> newton(sim.problem(), spec);
  BodyState<float> state = sim.state();
  const StepStats stats = newton.step(state);
  const std::vector<double>& g = newton.gradient_norms();
  if (world_rank() == 0) {
    std::printf("float ldlt: %d iterations, |g|/|g0|:", stats.iterations);
    for (double n : g) std::printf(" %.3e", n / g.front());
    std::printf("\n");
  }
  EXPECT_GE(stats.iterations, 1);
  EXPECT_LE(g.back(), 1e-3 * g.front());
}

}  // namespace
}  // namespace descent
