// Invertible model conversion (paper 1, Eqs. 17-19): with it on, a fully
// inverted tet and a box whose vertices start at random positions recover
// their rest shape (up to a rigid motion), with no NaN, for every model.
#include <gtest/gtest.h>
#include <mpi.h>

#include <cmath>
#include <random>

#include "app/scene_mesh.hpp"
#include "app/simulation.hpp"
#include "gather_positions.hpp"
#include "kernels/svd3.hpp"
#include "kernels/tet.hpp"
#include "small_scenes.hpp"

namespace descent {
namespace {

const char* const kModels[] = {"stvk", "neo_hookean", "mooney_rivlin", "fung", "corotated", "arap"};

Scene recovery_scene(const std::string& model) {
  Scene scene;
  scene.gravity = {0.0, 0.0, 0.0};
  scene.material.model = model;
  if (model == "mooney_rivlin" || model == "fung") scene.material.c2 = 5e3;
  if (model == "fung") scene.material.c3 = 2.0;
  scene.material.conversion.enabled = true;
  scene.time.quasistatic = true;
  scene.solver.iterations = 200;
  scene.solver.init = "position";
  return scene;
}

// F of global tet t of `rest` at positions x (global, xyz by vertex id).
Mat3<double> deformation_of(const Mesh& rest, const std::vector<double>& x, index_t t) {
  Vec3<double> r[4], d[4];
  for (int a = 0; a < 4; ++a) {
    const index_t v = rest.tets[4 * t + a];
    r[a] = {rest.positions[3 * v], rest.positions[3 * v + 1], rest.positions[3 * v + 2]};
    d[a] = {x[3 * v], x[3 * v + 1], x[3 * v + 2]};
  }
  const TetRest<double> tr = tet_rest(r[0], r[1], r[2], r[3]);
  return deformation_gradient(d[0], d[1], d[2], d[3], tr.dm_inv);
}

// Largest |sigma - 1| over the tets of the mesh at positions x (global).
double worst_stretch(const Mesh& rest, const std::vector<double>& x) {
  double worst = 0;
  for (index_t t = 0; t < rest.num_tets(); ++t) {
    const Svd3<double> s = svd3(deformation_of(rest, x, t));
    for (double sigma : s.sigma) worst = std::max(worst, std::abs(sigma - 1.0));
  }
  return worst;
}

// Runs `frames` quasi-static frames from `start` and returns the worst
// |sigma - 1| on rank 0 (-1 elsewhere); NaN if anything went non-finite.
double recover(MPI_Comm comm, const Scene& scene, const Mesh& mesh,
               const std::vector<double>& start, int frames) {
  Simulation<double> sim(comm, scene, mesh);
  sim.set_positions(start);
  for (int f = 0; f < frames; ++f) sim.step();
  const std::vector<double> x = testing::gather_positions(comm, sim, mesh.num_vertices());
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  if (rank != 0) return -1;
  for (double c : x)
    if (!std::isfinite(c)) return NAN;
  return worst_stretch(mesh, x);
}

TEST(Recovery, FullyInvertedTetRecoversForEveryModel) {
  Mesh tet;
  tet.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
  tet.tets = {0, 1, 2, 3};
  tet.source = "one tet";
  // Vertex 3 pushed through the opposite face: det F = -1.
  std::vector<double> start = tet.positions;
  start[11] = -1.0;
  // One tet cannot be split: it runs on rank 0 alone.
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  if (rank != 0) return;
  for (const char* model : kModels) {
    const double worst = recover(MPI_COMM_SELF, recovery_scene(model), tet, start, 40);
    if (worst >= 0 || std::isnan(worst)) {
      EXPECT_LE(worst, 1e-3) << model << ": worst |sigma - 1| after recovery";
    }
  }
}

// Every vertex uniformly in the unit box; the same draw on every rank.
std::vector<double> random_positions(const Mesh& mesh) {
  std::mt19937_64 rng(2024);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<double> start(mesh.positions.size());
  for (double& c : start) c = u(rng);
  return start;
}

Mesh recovery_box() {
  MeshSpec spec;
  spec.generator = "box";
  spec.box.cells = {2, 2, 2};
  return build_scene_mesh(spec);
}

TEST(Recovery, BoxFromRandomPositionsRecovers) {
  const Mesh box = recovery_box();
  const std::vector<double> start = random_positions(box);
  for (const char* model : {"stvk", "neo_hookean", "mooney_rivlin", "corotated", "arap"}) {
    const double worst = recover(MPI_COMM_WORLD, recovery_scene(model), box, start, 100);
    if (worst >= 0 || std::isnan(worst)) {
      EXPECT_LE(worst, 1e-2) << model << ": worst |sigma - 1| after recovery";
    }
  }
}

// Fung's exponential stiffening outruns a stale preconditioner: from random
// positions, with the default M = 32 (and M = 8) the step strands at
// alpha_min with elements stretched ~3x; a diagonal every iteration (M = 1)
// recovers. A rollback-triggered refresh alone did not.
TEST(Recovery, FungBoxFromRandomPositionsRecoversWithAFreshDiagonal) {
  const Mesh box = recovery_box();
  Scene scene = recovery_scene("fung");
  scene.solver.hessian_interval = 1;
  const double worst = recover(MPI_COMM_WORLD, scene, box, random_positions(box), 100);
  if (worst >= 0 || std::isnan(worst)) {
    EXPECT_LE(worst, 1e-2);
  }
}

// A predicted initial guess that inverts every tet of a neo-Hookean body
// (infinite energy: no shorter step gets out of the barrier) fails the step;
// Simulation::step lets the stepper abandon it at the first rollback and
// retakes the step from the step start, which is finite.
TEST(Recovery, AnInvertingPredictionIsRetriedFromTheStepStart) {
  Scene scene = testing::small_helix_scene();
  scene.solver.init = "velocity";
  const Mesh mesh = build_scene_mesh(scene.mesh);
  Simulation<double> sim(MPI_COMM_WORLD, scene, mesh);
  sim.step();
  // Velocities that carry every vertex through the centroid of the local
  // vertices' bounding box in one step: q_t + h v = c - 1.5 (q_t - c).
  Checkpoint c = sim.checkpoint(1);
  double centre[3];
  for (int a = 0; a < 3; ++a) {
    double lo = 1e300, hi = -1e300;
    for (std::size_t k = a; k < c.q.size(); k += 3) {
      lo = std::min(lo, c.q[k]);
      hi = std::max(hi, c.q[k]);
    }
    MPI_Allreduce(MPI_IN_PLACE, &lo, 1, MPI_DOUBLE, MPI_MIN, MPI_COMM_WORLD);
    MPI_Allreduce(MPI_IN_PLACE, &hi, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
    centre[a] = 0.5 * (lo + hi);
  }
  for (std::size_t k = 0; k < c.q.size(); ++k)
    c.v[k] = -2.5 * (c.q[k] - centre[k % 3]) / scene.time.dt;

  // The stepper alone: the step fails and leaves the body where it was.
  sim.restore(c);
  BodyState<double> state = sim.state();
  const StepStats alone = sim.stepper().step(state);
  EXPECT_FALSE(alone.finite);
  EXPECT_FALSE(alone.abandoned_guess);  // it shrank the step to the end
  EXPECT_EQ(state.q, sim.state().q);

  // Allowed to abandon the guess, the stepper ends at the first rollback.
  sim.restore(c);
  BodyState<double> again = sim.state();
  sim.stepper().abandon_non_finite_guess_next_step();
  const StepStats abandoned = sim.stepper().step(again);
  EXPECT_FALSE(abandoned.finite);
  EXPECT_TRUE(abandoned.abandoned_guess);
  EXPECT_EQ(abandoned.rollbacks, 1);
  EXPECT_EQ(again.q, sim.state().q);

  // Through Simulation::step: retaken from q_t, finite, no tet inverted.
  sim.restore(c);
  const StepStats step = sim.step();
  EXPECT_TRUE(step.finite);
  EXPECT_TRUE(step.retried_from_start);
  EXPECT_GT(step.nonfinite_rollbacks, 0);
  EXPECT_LT(step.rollbacks, alone.rollbacks);  // the guess abandoned at once
  const std::vector<double> x = testing::gather_positions(MPI_COMM_WORLD, sim, mesh.num_vertices());
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  if (rank != 0) return;
  for (double coordinate : x) ASSERT_TRUE(std::isfinite(coordinate));
  int inverted = 0;
  for (index_t t = 0; t < mesh.num_tets(); ++t) inverted += det(deformation_of(mesh, x, t)) <= 0;
  std::printf("retried step: %d rollbacks (%d non-finite), %d inverted tets after it\n",
              step.rollbacks, step.nonfinite_rollbacks, inverted);
  EXPECT_EQ(inverted, 0);
}

}  // namespace
}  // namespace descent
