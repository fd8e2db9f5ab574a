// Scenes of several bodies ([[body]]) on 1 to 4 ranks: bodies fly with the
// velocities they are given (their stats columns say so), a body's own
// density and Young's modulus act as the scene's material would, a body
// that restates [mesh] runs the same run bit for bit, and P ranks give one
// rank's result with bodies spread over the ranks.
#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "app/scene_mesh.hpp"
#include "app/simulation.hpp"
#include "gather_positions.hpp"

namespace descent {
namespace {

using testing::measured;

Body box_body(std::array<double, 3> translate) {
  Body body;
  body.mesh.generator = "box";
  body.mesh.box.cells = {3, 2, 2};
  body.mesh.box.size = {0.3, 0.2, 0.2};
  body.translate = translate;
  return body;
}

// Two boxes 0.5 apart along x, no gravity, each step solved tightly.
Scene two_bodies() {
  Scene scene;
  scene.bodies = {box_body({-0.4, 0, 0}), box_body({0.4, 0, 0})};
  scene.gravity = {0, 0, 0};
  scene.material.young = 1e5;
  scene.time.dt = 0.01;
  scene.solver.accuracy = 1e-7;
  scene.solver.iterations = 1000;
  return scene;
}

TEST(Bodies, EachStartsWithItsRigidVelocityAndKeepsItsMomentum) {
  Scene scene = two_bodies();
  scene.bodies[0].velocity = {1.0, 0.5, 0.0};
  scene.bodies[1].angular_velocity = {0.0, 3.0, 0.0};
  scene.bodies[1].density = 2500;
  const Mesh mesh = build_scene_mesh(scene);
  Simulation<double> sim(MPI_COMM_WORLD, scene, mesh);

  const double volume = 0.3 * 0.2 * 0.2;
  const double m0 = 1000 * volume, m1 = 2500 * volume;
  // At the start: body 0 translates, body 1 spins about its centre of mass
  // (no momentum); its kinetic energy is that of the spin, 1/2 w^2 sum m r^2
  // over the lumped masses, r the distance from the y axis through the centre.
  EXPECT_NEAR(measured(sim, "body0_momentum_x"), m0 * 1.0, 1e-12 * m0);
  EXPECT_NEAR(measured(sim, "body0_velocity_y"), 0.5, 1e-12);
  EXPECT_NEAR(measured(sim, "body0_kinetic"), 0.5 * m0 * 1.25, 1e-12 * m0);
  EXPECT_NEAR(measured(sim, "body1_momentum_x"), 0.0, 1e-12 * m1);
  EXPECT_NEAR(measured(sim, "body1_momentum_z"), 0.0, 1e-12 * m1);
  const double cx = measured(sim, "body1_com_x"), cz = measured(sim, "body1_com_z");
  EXPECT_NEAR(cx, 0.4 + 0.15, 1e-12);
  EXPECT_NEAR(cz, 0.1, 1e-12);
  double spin[2] = {0, 0};  // sum m r^2 and the mass, body 1's owned vertices
  const std::vector<int> body = vertex_bodies(sim.local_mesh());
  for (index_t v = 0; v < sim.local_mesh().num_owned; ++v) {
    if (body[v] != 1) continue;
    const double* x = &sim.local_mesh().rest_positions[3 * v];
    const double m = sim.problem().mass()[v];
    spin[0] += m * ((x[0] - cx) * (x[0] - cx) + (x[2] - cz) * (x[2] - cz));
    spin[1] += m;
  }
  MPI_Allreduce(MPI_IN_PLACE, spin, 2, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
  EXPECT_NEAR(spin[1], m1, 1e-12 * m1);  // the body's own density
  EXPECT_NEAR(measured(sim, "body1_kinetic"), 0.5 * 9.0 * spin[0], 1e-12 * spin[0]);

  constexpr int kFrames = 20;
  for (int frame = 0; frame < kFrames; ++frame) ASSERT_TRUE(sim.step().finite);
  const double t = kFrames * scene.time.dt;
  // Body 0 flies on at its velocity; body 1 turns in place. Each step is
  // solved to e <= 1e-7, which bounds the momentum the iteration may lose.
  EXPECT_NEAR(measured(sim, "body0_com_x"), -0.4 + 0.15 + 1.0 * t, 1e-6);
  EXPECT_NEAR(measured(sim, "body0_com_y"), 0.1 + 0.5 * t, 1e-6);
  EXPECT_NEAR(measured(sim, "body0_momentum_x"), m0, 1e-5 * m0);
  EXPECT_NEAR(measured(sim, "body1_com_x"), cx, 1e-6);
  EXPECT_NEAR(measured(sim, "body1_com_z"), cz, 1e-6);
  EXPECT_NEAR(measured(sim, "body1_momentum_x"), 0.0, 1e-5 * m1);
}

// Positions of a run of `scene` after `frames` steps, on rank 0.
std::vector<double> run(const Scene& scene, int frames) {
  const Mesh mesh = build_scene_mesh(scene);
  Simulation<double> sim(MPI_COMM_WORLD, scene, mesh);
  for (int frame = 0; frame < frames; ++frame) EXPECT_TRUE(sim.step().finite);
  return testing::gather_positions(MPI_COMM_WORLD, sim, mesh.num_vertices());
}

// A cantilever box held at x = 0 sagging under gravity, fixed iterations.
Scene cantilever() {
  Scene scene;
  scene.mesh.generator = "box";
  scene.mesh.box.cells = {6, 2, 2};
  scene.mesh.box.size = {0.6, 0.1, 0.1};
  FixedRegion wall;
  wall.box_min = {-1, -1, -1};
  wall.box_max = {1e-9, 1, 1};
  scene.fixed.push_back(wall);
  scene.material.young = 1e5;
  scene.time.dt = 0.02;
  scene.solver.iterations = 64;
  return scene;
}

TEST(Bodies, ABodyThatRestatesTheMeshRunsTheSameRunBitForBit) {
  const Scene plain = cantilever();
  Scene as_body = plain;
  Body body;
  body.mesh = plain.mesh;
  as_body.mesh = MeshSpec{};
  as_body.bodies.push_back(body);
  const std::vector<double> want = run(plain, 6), got = run(as_body, 6);
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  if (rank == 0) {
    ASSERT_EQ(got.size(), want.size());
    for (std::size_t k = 0; k < want.size(); ++k) ASSERT_EQ(got[k], want[k]) << "coordinate " << k;
  }
}

TEST(Bodies, ABodysYoungAndDensityActAsTheScenesMaterialWould) {
  Scene scene_material = cantilever();
  scene_material.material.young = 4e5;
  scene_material.material.density = 600;
  Scene body_material = cantilever();
  Body body;
  body.mesh = body_material.mesh;
  body.young = 4e5;  // over the scene's 1e5
  body.density = 600;
  body_material.mesh = MeshSpec{};
  body_material.bodies.push_back(body);
  const std::vector<double> want = run(scene_material, 6), got = run(body_material, 6);
  const std::vector<double> soft = run(cantilever(), 6);
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  if (rank == 0) {
    const Mesh rest = build_scene_mesh(cantilever());
    double worst = 0, sag = 0, difference = 0;
    for (std::size_t k = 0; k < want.size(); ++k) {
      worst = std::max(worst, std::abs(got[k] - want[k]));
      sag = std::max(sag, std::abs(want[k] - rest.positions[k]));
      difference = std::max(difference, std::abs(soft[k] - want[k]));
    }
    EXPECT_GT(sag, 1e-3);
    EXPECT_GT(difference, 0.1 * sag);  // the overrides do change the run
    EXPECT_LT(worst, 1e-10 * sag);     // and change it as [material] does
  }
}

// Two bodies falling side by side onto a floor, one spinning, a fixed
// iteration count: P ranks give one rank's positions to round-off.
TEST(Bodies, PRanksGiveOneRanksResult) {
  Scene scene = two_bodies();
  scene.gravity = {0, -9.81, 0};
  scene.bodies[0].translate = {-0.4, 0.05, 0};
  scene.bodies[1].angular_velocity = {0, 2, 0};
  scene.bodies[1].rotate_axis = {1, 1, 0};
  scene.bodies[1].rotate_degrees = 20;
  scene.bodies[1].translate = {0.4, 0.12, 0};
  Obstacle floor;
  floor.kind = "plane";
  floor.friction = 0.3;
  scene.obstacles.push_back(floor);
  scene.solver.accuracy = 0;
  scene.solver.iterations = 48;
  const Mesh mesh = build_scene_mesh(scene);
  const testing::OneRankComparison c =
      testing::compare_with_one_rank(MPI_COMM_WORLD, scene, mesh, 16);
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  if (rank == 0) {
    EXPECT_GT(c.moved, 0.01);
    EXPECT_LT(c.worst, 1e-9 * c.moved);
  }
}

}  // namespace
}  // namespace descent
