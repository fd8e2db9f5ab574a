// Newton's CG preconditioned by the multilevel V-cycle (solver.preconditioner
// = "multilevel" with solver.method = "newton"; docs/methods.md): P^-1 is
// rebuilt at each Newton iterate, so the CG solves the same systems as with
// Jacobi's diagonal, to the same tolerance, in a fraction of the iterations;
// the step's result equals Jacobi's, and P ranks agree with one rank.
#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>

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

struct NewtonRun {
  StepStats stats;
  std::vector<double> gradient_norms;
  long cg_iterations = 0;  // over the step's solves
  int preconditioner_refreshes = 0;
  std::vector<double> q;  // local vertices, after the step
};

NewtonRun run_newton(Simulation<double>& sim, const Scene& scene, const char* preconditioner) {
  SolverSpec spec = scene.solver;
  spec.method = "newton";
  spec.init = "position";
  spec.preconditioner = preconditioner;
  Newton<double> newton(sim.problem(), spec);
  BodyState<double> state = sim.state();
  NewtonRun run;
  run.stats = newton.step(state);
  run.gradient_norms = newton.gradient_norms();
  const std::vector<int>& cg = newton.cg_iterations();
  run.cg_iterations = std::accumulate(cg.begin(), cg.end(), 0L);
  const Stepper<double>& stepper = newton;  // where preconditioner() is public
  if (stepper.preconditioner())
    run.preconditioner_refreshes = static_cast<int>(stepper.preconditioner()->stats().refreshes);
  run.q.assign(state.q.begin(), state.q.end());
  if (world_rank() == 0)
    std::printf("%s: %d Newton iterations, %ld CG iterations, |g|/|g0| = %.3e\n", preconditioner,
                run.stats.iterations, run.cg_iterations,
                run.gradient_norms.back() / run.gradient_norms.front());
  return run;
}

class NewtonMultilevelTest : public ::testing::Test {
 protected:
  void SetUp() override {
    scene_ = testing::small_helix_scene();
    scene_.material.young = 1e7;  // stiff: where Jacobi's CG is slow
    mesh_ = build_scene_mesh(scene_.mesh);
    diagonal_ = testing::bounding_box_diagonal(mesh_);
  }
  Scene scene_;
  Mesh mesh_;
  double diagonal_ = 0;
};

// The stretched helix released: both reach |g| <= 1e-10 |g0| and end at the
// same positions (up to the gradient criterion's slack), the multilevel CG in
// less than a quarter of Jacobi's iterations, with P^-1 rebuilt at every
// Newton iterate (the step's start and each later one).
TEST_F(NewtonMultilevelTest, SameStepAsJacobiInAFractionOfTheCgIterations) {
  Simulation<double> sim(MPI_COMM_WORLD, scene_, mesh_);
  sim.set_positions(testing::stretched_positions(mesh_));
  const NewtonRun jacobi = run_newton(sim, scene_, "jacobi");
  const NewtonRun multilevel = run_newton(sim, scene_, "multilevel");
  for (const NewtonRun* run : {&jacobi, &multilevel}) {
    EXPECT_LE(run->gradient_norms.back(), 1e-10 * run->gradient_norms.front());
    EXPECT_FALSE(run->stats.stalled);
  }
  EXPECT_EQ(multilevel.preconditioner_refreshes,
            static_cast<int>(multilevel.gradient_norms.size()) - 1);
  EXPECT_LT(4 * multilevel.cg_iterations, jacobi.cg_iterations);
  double worst = 0, moved = 0;
  const std::size_t owned = 3 * static_cast<std::size_t>(sim.local_mesh().num_owned);
  for (std::size_t k = 0; k < owned; ++k) {
    worst = std::max(worst, std::abs(multilevel.q[k] - jacobi.q[k]));
    moved = std::max(moved, std::abs(jacobi.q[k] - sim.state().q[k]));
  }
  double maxima[2] = {worst, moved};
  MPI_Allreduce(MPI_IN_PLACE, maxima, 2, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
  if (world_rank() == 0)
    std::printf("max |q_multilevel - q_jacobi| = %.3e, max |q_jacobi - q0| = %.3e\n", maxima[0],
                maxima[1]);
  EXPECT_GT(maxima[1], 1e-3 * diagonal_);  // the step moved: equality is not trivial
  EXPECT_LE(maxima[0], 1e-10 * diagonal_);
}

// Three frames of newton with the multilevel CG on all ranks against 1 rank.
TEST_F(NewtonMultilevelTest, DistributedRunsAgreeWithOneRank) {
  scene_.solver.method = "newton";
  scene_.solver.preconditioner = "multilevel";
  const testing::OneRankComparison c =
      testing::compare_with_one_rank(MPI_COMM_WORLD, scene_, mesh_, 3);
  if (world_rank() != 0) return;
  std::printf("multilevel max |q_P - q_1| = %.3e, max |q_1 - rest| = %.3e (bbox diagonal %.3f)\n",
              c.worst, c.moved, diagonal_);
  EXPECT_GT(c.moved, 1e-4 * diagonal_);
  EXPECT_LE(c.worst, 1e-10 * diagonal_);
}

// solver.preconditioner = "auto" gives newton's CG the multilevel P^-1 where
// it fits: a body with inertia, or held quasi-statically, and bodies in
// contact (the pairs' diagonal joins it; the Chebyshev descent keeps Jacobi's
// there); not a quasi-static body that nothing holds (its operator is
// singular), nor the direct solver.
TEST_F(NewtonMultilevelTest, AutoTakesTheMultilevelOneWhereItFits) {
  auto has_multilevel = [&](const Scene& scene) {
    Simulation<double> sim(MPI_COMM_WORLD, scene, mesh_);
    SolverSpec spec = scene.solver;
    spec.method = "newton";
    spec.preconditioner = "auto";
    const Newton<double> newton(sim.problem(), spec);
    const Stepper<double>& stepper = newton;
    return stepper.preconditioner() != nullptr;
  };
  EXPECT_TRUE(has_multilevel(scene_));
  Scene quasistatic = scene_;
  quasistatic.time.quasistatic = true;
  EXPECT_TRUE(has_multilevel(quasistatic));  // the top cap is held
  quasistatic.fixed.clear();
  EXPECT_FALSE(has_multilevel(quasistatic));
  Scene ldlt = scene_;
  ldlt.solver.newton_solver = "ldlt";
  EXPECT_FALSE(has_multilevel(ldlt));

  const Scene two = testing::head_on(2.0);
  const Mesh bodies = build_scene_mesh(two);
  Simulation<double> chebyshev(MPI_COMM_WORLD, two, bodies);
  EXPECT_EQ(chebyshev.stepper().preconditioner(), nullptr);
  SolverSpec spec = two.solver;
  spec.method = "newton";
  const Newton<double> newton(chebyshev.problem(), spec);
  const Stepper<double>& stepper = newton;
  EXPECT_NE(stepper.preconditioner(), nullptr);
}

}  // namespace
}  // namespace descent
