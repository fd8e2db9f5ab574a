// A NaN or Inf anywhere, on any rank, is detected through the energy
// reduction the solver already makes: the step reports it on every rank,
// the rank holding the culprit names it, and the body keeps its last good
// state instead of taking the non-finite one.
#include <gtest/gtest.h>
#include <mpi.h>

#include <cmath>
#include <limits>

#include "app/scene_mesh.hpp"
#include "app/simulation.hpp"
#include "io/scene.hpp"

namespace descent {
namespace {

int comm_rank() {
  int r = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &r);
  return r;
}
int comm_size() {
  int s = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &s);
  return s;
}

// A 3x3x3-cell box standing on its held bottom face under gravity.
Scene standing_box() {
  Scene scene;
  scene.mesh.generator = "box";
  scene.mesh.box.cells = {3, 3, 3};
  FixedRegion bottom;
  bottom.box_min = {-0.01, -0.01, -0.01};
  bottom.box_max = {1.01, 0.01, 1.01};
  scene.fixed = {bottom};
  scene.solver.iterations = 32;
  return scene;
}

template <class Real>
void nan_velocity_stops_the_step_and_names_the_vertex() {
  const Scene scene = standing_box();
  const Mesh mesh = build_scene_mesh(scene.mesh);
  Simulation<Real> sim(MPI_COMM_WORLD, scene, mesh);
  ASSERT_TRUE(sim.step().finite);
  // The victim: an interior vertex of the last rank (no other rank holds it).
  const int last = comm_size() - 1;
  const LocalMesh& local = sim.local_mesh();
  int victim = -1;
  if (comm_rank() == last) {
    ASSERT_GT(local.num_interior, 0);
    victim = local.global_vertex[0];
  }
  MPI_Bcast(&victim, 1, MPI_INT, last, MPI_COMM_WORLD);
  Checkpoint state = sim.checkpoint(1);
  bool holds_victim = false;
  for (index_t v = 0; v < local.num_vertices(); ++v) {
    if (local.global_vertex[v] != victim) continue;
    holds_victim = true;
    state.v[3 * v + 1] = std::numeric_limits<double>::quiet_NaN();
  }
  sim.restore(state);
  const std::vector<Real> q_before = sim.state().q;

  const StepStats step = sim.step();
  EXPECT_FALSE(step.finite) << "every rank learns it from the reduction";
  EXPECT_EQ(sim.state().q, q_before) << "the body keeps its last good positions";
  for (Real x : sim.state().q) ASSERT_TRUE(std::isfinite(x));
  if (holds_victim) {
    EXPECT_EQ(step.failed_at.kind, NonFiniteSite::Kind::velocity);
    EXPECT_EQ(step.failed_at.id, victim);
    EXPECT_TRUE(std::isnan(step.failed_at.value));
  } else {
    EXPECT_FALSE(step.failed_at.found()) << "rank " << comm_rank() << " holds nothing non-finite";
  }
}

TEST(NonFinite, NanVelocityOnTheLastRankIsNamedThereDouble) {
  nan_velocity_stops_the_step_and_names_the_vertex<double>();
}

TEST(NonFinite, NanVelocityOnTheLastRankIsNamedThereFloat) {
  nan_velocity_stops_the_step_and_names_the_vertex<float>();
}

// tests/extremes/data/scene_crush_through.toml in code: a one-cell slab whose
// top face is driven through its bottom face; at frame 3 every neo-Hookean
// tet is held inverted (infinite energy) and no finite state exists.
TEST(NonFinite, TetsHeldInvertedFailTheStepAndAreNamed) {
  Scene scene;
  scene.gravity = {0.0, 0.0, 0.0};
  scene.mesh.generator = "box";
  scene.mesh.box.cells = {3, 1, 3};
  FixedRegion bottom, top;
  bottom.box_min = {-0.01, -0.01, -0.01};
  bottom.box_max = {1.01, 0.01, 1.01};
  top.box_min = {-0.01, 0.99, -0.01};
  top.box_max = {1.01, 1.01, 1.01};
  top.motion.kind = "translate";
  top.motion.velocity = {0.0, -4.0, 0.0};
  scene.fixed = {bottom, top};
  scene.time.dt = 0.1;
  scene.solver.iterations = 32;
  const Mesh mesh = build_scene_mesh(scene.mesh);
  Simulation<double> sim(MPI_COMM_WORLD, scene, mesh);
  for (int frame = 1; frame <= 2; ++frame) ASSERT_TRUE(sim.step().finite) << "frame " << frame;
  const std::vector<double> q_before = sim.state().q;
  const StepStats step = sim.step();
  EXPECT_FALSE(step.finite);
  EXPECT_EQ(step.nonfinite_rollbacks, step.rollbacks) << "every trial was infinite";
  EXPECT_EQ(sim.state().q, q_before);
  // Every rank holds inverted tets here, so every rank names one of its own,
  // as inverted (the neo-Hookean barrier), not as a NaN.
  ASSERT_EQ(step.failed_at.kind, NonFiniteSite::Kind::inverted_element);
  const auto& tets = sim.local_mesh().global_tet;
  EXPECT_NE(std::find(tets.begin(), tets.end(), step.failed_at.id), tets.end());
  EXPECT_EQ(step.failed_at.value, std::numeric_limits<double>::infinity());
}

}  // namespace
}  // namespace descent
