// solver.accuracy for every method of ours (issue 24) on the small helix,
// each step against Newton's eps* from the same state (the truth, run to
// |g| <= 1e-10 |g0| without a target):
//   - a step with a target TOL stops at e <= TOL, before its cap, and
//     reports an estimate at or below TOL;
//   - a looser target takes fewer iterations;
//   - P ranks take the iterations one rank takes.
// The first-order methods read their error from the energy checks
// (solver/check_history.hpp), Newton from its decrement, linear_cg from the
// energy decrease of its linear solve (whose converged answer lies off
// eps's minimum by linearly implicit Euler's own error: its scene is one
// where that error is far below the targets).
#include <gtest/gtest.h>
#include <mpi.h>

#include <cstdio>
#include <string>
#include <vector>

#include "app/scene_mesh.hpp"
#include "app/simulation.hpp"
#include "app/study_trace.hpp"
#include "small_scenes.hpp"
#include "world_rank.hpp"

namespace descent {
namespace {

using testing::world_rank;

// A state `frames` steps into `scene` (its own method: the automatic
// Chebyshev), or the mesh stretched from its held top (frames = 0) for
// Newton, and eps* there.
struct State {
  Scene scene;
  Mesh mesh;
  Simulation<double> sim;
  double energy_star = 0;
  State(const Scene& s, int frames, MPI_Comm comm = MPI_COMM_WORLD)
      : scene(s), mesh(build_scene_mesh(s.mesh)), sim(comm, s, mesh) {
    if (frames == 0) sim.set_positions(testing::stretched_positions(mesh));
    for (int frame = 0; frame < frames; ++frame) sim.step();
    SolverSpec truth = spec_of("newton");
    truth.accuracy = 0;
    energy_star = trace_step(comm, sim, truth).records.back().energy;
  }
  SolverSpec spec_of(const char* method) const {
    SolverSpec spec = scene.solver;
    spec.method = method;
    // From the stretched mesh the guess is the state itself.
    if (std::string(method) == "newton") spec.init = "position";
    return spec;
  }
};

struct Target {
  double e = 0, estimate = 0;
  int iterations = 0;
};

// One step of `method` to `target` from the state, its e against eps*.
Target run(State& s, const char* method, double target, int cap, MPI_Comm comm = MPI_COMM_WORLD) {
  SolverSpec spec = s.spec_of(method);
  spec.accuracy = target;
  spec.iterations = cap;
  const StepTrace trace = trace_step(comm, s.sim, spec);
  Target t;
  t.e = relative_errors(trace, s.energy_star).back();
  t.estimate = trace.stats.error_estimate;
  t.iterations = trace.stats.iterations;
  return t;
}

// The two claims for one method: each target met before the cap,
// the looser one in fewer iterations.
void expect_targets_met(State& s, const char* method, double loose, double tight, int cap) {
  const int limit = std::string(method) == "newton" ? s.scene.solver.newton_iterations : cap;
  Target previous;
  for (double target : {loose, tight}) {
    const Target t = run(s, method, target, cap);
    if (world_rank() == 0)
      std::printf("[ accuracy ] %-12s TOL %.0e: e = %.3e (estimate %.3e) after %d iterations\n",
                  method, target, t.e, t.estimate, t.iterations);
    EXPECT_LE(t.e, target) << method << " at " << target;
    EXPECT_GE(t.e, -1e-9) << method << ": eps* is the minimum";
    EXPECT_LE(t.estimate, target) << method << " at " << target;
    EXPECT_LT(t.iterations, limit) << method << " at " << target << ": the target, not the cap";
    if (target == tight) {
      EXPECT_LT(previous.iterations, t.iterations) << method << ": the looser target is cheaper";
    }
    previous = t;
  }
}

TEST(MethodAccuracy, FirstOrderMethodsStopAtTheirTarget) {
  State s(testing::small_helix_scene(), 3);
  // Targets a few hundred iterations apart for the slow methods, the fast
  // ones to far below.
  expect_targets_met(s, "gd", 1e-1, 1e-2, 5000);
  expect_targets_met(s, "jacobi_gd", 1e-1, 1e-2, 5000);
  expect_targets_met(s, "nesterov", 1e-2, 1e-5, 5000);
  expect_targets_met(s, "ncg", 1e-2, 1e-7, 2000);
  expect_targets_met(s, "lbfgs", 1e-2, 1e-7, 2000);
}

TEST(MethodAccuracy, ProjectiveDynamicsStopsAtItsTarget) {
  Scene scene = testing::small_helix_scene();
  scene.material.model = "arap";
  State s(scene, 3);
  expect_targets_met(s, "pd_chebyshev", 1e-2, 1e-4, 5000);
}

// From the stretched mesh Newton needs several iterations; its decrement
// tells it when the target is met.
TEST(MethodAccuracy, NewtonStopsFromItsDecrement) {
  State s(testing::small_helix_scene(), 0);
  expect_targets_met(s, "newton", 1e-1, 1e-6, 96);
}

// linear_cg's target is its linear solve's error; at h = 1/120 the solve's
// converged answer lies within 1e-5 of eps* in relative error (2.2e-6), so e
// against eps* follows the solve's.
TEST(MethodAccuracy, LinearCgStopsFromItsResidual) {
  Scene scene = testing::small_helix_scene();
  scene.material.model = "corotated";
  scene.time.dt = 1.0 / 120;
  State s(scene, 3);
  const Target converged = run(s, "linear_cg", 0, 5000);  // to r.r <= 1e-10 b.b
  if (world_rank() == 0)
    std::printf("[ accuracy ] linear_cg converged: e = %.3e after %d iterations\n", converged.e,
                converged.iterations);
  ASSERT_LE(converged.e, 1e-5) << "linearly implicit Euler's own error must lie below the targets";
  expect_targets_met(s, "linear_cg", 1e-1, 1e-4, 5000);
}

// The estimates ride on global sums only: every rank count takes one rank's
// iterations (and so the same stop).
TEST(MethodAccuracy, RanksTakeOneRanksIterations) {
  State distributed(testing::small_helix_scene(), 3);
  std::vector<int> counts;
  const char* const methods[] = {"gd", "jacobi_gd", "nesterov", "ncg", "lbfgs"};
  for (const char* method : methods)
    counts.push_back(run(distributed, method, 1e-2, 5000).iterations);
  if (world_rank() != 0) return;
  State serial(testing::small_helix_scene(), 3, MPI_COMM_SELF);
  for (std::size_t m = 0; m < counts.size(); ++m) {
    EXPECT_EQ(run(serial, methods[m], 1e-2, 5000, MPI_COMM_SELF).iterations, counts[m])
        << methods[m];
    std::printf("[ accuracy ] %-10s to 1e-2: %d iterations on %d ranks and on 1\n", methods[m],
                counts[m], testing::world_size());
  }
}

}  // namespace
}  // namespace descent
