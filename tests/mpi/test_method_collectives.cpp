// Collectives per step of each method (docs/methods.md), counted at the MPI
// boundary through PMPI (pmpi_counters.hpp), against the documented formulas;
// the comm layer's counters (energy + dot allreduces) agree with PMPI and
// nothing else is called.
#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>

#include "app/scene_mesh.hpp"
#include "app/simulation.hpp"
#include "pmpi_counters.hpp"
#include "small_scenes.hpp"
#include "solver/methods/newton.hpp"

namespace descent {
namespace {

struct Counted {
  StepStats stats;
  long allreduce = 0, other = 0, layer = 0;
};

Counted count_step(Simulation<double>& sim) {
  const long a = testing::pmpi_allreduces(), o = testing::pmpi_other_collectives();
  const ReductionCounters before = sim.reduction_counters();
  Counted c;
  c.stats = sim.step();
  c.allreduce = testing::pmpi_allreduces() - a;
  c.other = testing::pmpi_other_collectives() - o;
  const ReductionCounters& after = sim.reduction_counters();
  c.layer = after.allreduces - before.allreduces + after.dot_allreduces - before.dot_allreduces;
  return c;
}

// Steps of 96 iterations, energy check every 8, diagonal every 32.
constexpr int kIterations = 96, kChecks = 96 / 8, kDiagonals = 96 / 32;

long expected_count(const std::string& method, int history) {
  if (method == "chebyshev" || method == "jacobi_gd" || method == "nesterov" ||
      method == "pd_chebyshev")
    return kChecks;
  if (method == "gd") return kChecks + kDiagonals;        // + the max of the diagonal
  if (method == "ncg") return kChecks + 2 * kIterations;  // [z, g.dq_prev], dq.H dq
  // lbfgs: iteration k holds min(k, m) pairs (no rollback, every pair kept):
  // 1 fused [s.y, y.P^-1 y] from k = 1 on, 2 per pair in the two loops.
  long n = kChecks;
  for (int k = 0; k < kIterations; ++k) n += (k > 0 ? 1 : 0) + 2 * std::min(k, history);
  return n;
}

TEST(MethodCollectives, AsDocumentedPerMethod) {
  for (const char* method :
       {"chebyshev", "gd", "jacobi_gd", "nesterov", "ncg", "lbfgs", "pd_chebyshev"}) {
    // Chebyshev with fixed parameters: the count of the iterations alone
    // (tests/mpi/test_collectives.cpp adds the automatic parameters' estimates).
    Scene scene = testing::fixed_chebyshev(testing::small_helix_scene());
    scene.solver.method = method;
    if (std::string(method) == "pd_chebyshev") scene.material.model = "arap";
    scene.solver.iterations = kIterations;
    const Mesh mesh = build_scene_mesh(scene.mesh);
    Simulation<double> sim(MPI_COMM_WORLD, scene, mesh);
    for (int frame = 0; frame < 2; ++frame) {
      const Counted c = count_step(sim);
      ASSERT_EQ(c.stats.iterations, kIterations) << method << ": the count assumes a full step";
      if (std::string(method) == "lbfgs") {
        ASSERT_EQ(c.stats.rollbacks, 0) << "the lbfgs count assumes no rollback";
      }
      EXPECT_EQ(c.allreduce, expected_count(method, scene.solver.history))
          << method << " frame " << frame;
      EXPECT_EQ(c.layer, c.allreduce) << method;
      EXPECT_EQ(c.other, 0) << method;
    }
  }
}

// Eq. 10's initialisation adds one allreduce (two inner products fused).
TEST(MethodCollectives, OptimizedInitialisationAddsOne) {
  Scene scene = testing::fixed_chebyshev(testing::small_helix_scene());
  scene.solver.init = "optimized";
  const Mesh mesh = build_scene_mesh(scene.mesh);
  Simulation<double> sim(MPI_COMM_WORLD, scene, mesh);
  const Counted c = count_step(sim);
  ASSERT_EQ(c.stats.iterations, kIterations);
  EXPECT_EQ(c.allreduce, kChecks + 1);
  EXPECT_EQ(c.layer, c.allreduce);
}

// Newton: per Newton iteration 1 (|g|^2) + 1 + 2 per CG iteration + 1 (g.dq)
// + one per line-search trial; one more |g|^2 at the converged iterate.
TEST(MethodCollectives, NewtonAsDocumented) {
  Scene scene = testing::small_helix_scene();
  scene.solver.method = "newton";
  scene.solver.init = "position";
  const Mesh mesh = build_scene_mesh(scene.mesh);
  Simulation<double> sim(MPI_COMM_WORLD, scene, mesh);
  Newton<double> newton(sim.problem(), scene.solver);
  BodyState<double> state = sim.state();
  const long a = testing::pmpi_allreduces(), o = testing::pmpi_other_collectives();
  const StepStats stats = newton.step(state);
  const long counted = testing::pmpi_allreduces() - a;
  long expected = static_cast<long>(newton.gradient_norms().size());
  for (int cg : newton.cg_iterations()) expected += 1 + 2 * cg + 1;
  expected += stats.iterations + stats.rollbacks;  // line-search trials
  EXPECT_EQ(counted, expected);
  EXPECT_EQ(testing::pmpi_other_collectives() - o, 0);
}

}  // namespace
}  // namespace descent
