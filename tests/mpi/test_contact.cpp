// Contact with rigid obstacles on 1 to 4 ranks (docs/contact.md): a body
// resting on a plane carries its weight, a block on an incline sticks or
// slides as Coulomb says, a body thrown hard at a plane never crosses it in
// any iterate (with chebyshev, the first-order methods and newton), P ranks
// give one rank's result, the projection pass keeps
// bodies out, and an obstacle that cuts the body at its start is an error
// naming it.
#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "app/scene_mesh.hpp"
#include "app/simulation.hpp"
#include "common/error.hpp"
#include "gather_positions.hpp"

namespace descent {
namespace {

using testing::measured;

constexpr double kG = 9.81;

// A box of `size` whose bottom face lies `gap` above the plane y = 0, with
// friction mu; 4x2x4 cells.
Scene box_on_floor(double gap, double mu) {
  Scene scene;
  scene.mesh.generator = "box";
  scene.mesh.box.cells = {4, 2, 4};
  scene.mesh.box.size = {0.2, 0.1, 0.2};
  scene.mesh.box.origin = {0.0, gap, 0.0};
  scene.material.young = 1e6;
  scene.material.density = 1000;
  Obstacle floor;
  floor.kind = "plane";
  floor.normal = {0.0, 1.0, 0.0};
  floor.friction = mu;
  scene.obstacles.push_back(floor);
  scene.time.dt = 0.01;
  scene.solver.accuracy = 1e-4;
  scene.solver.iterations = 400;
  return scene;
}

double box_mass(const Scene& scene) {
  const auto& s = scene.mesh.box.size;
  return scene.material.density * s[0] * s[1] * s[2];
}

// The mean x of all vertices (each counted by its owner), on every rank.
double mean_x(const Simulation<double>& sim) {
  double s[2] = {0, 0};
  for (index_t v = 0; v < sim.local_mesh().num_owned; ++v) {
    s[0] += sim.state().q[3 * v];
    s[1] += 1;
  }
  MPI_Allreduce(MPI_IN_PLACE, s, 2, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
  return s[0] / s[1];
}

TEST(Contact, QuasiStaticBodyOnAPlaneCarriesItsWeight) {
  Scene scene = box_on_floor(1.5e-4, 0.5);
  scene.time.quasistatic = true;
  const Mesh mesh = build_scene_mesh(scene.mesh);
  Simulation<double> sim(MPI_COMM_WORLD, scene, mesh);
  for (int frame = 0; frame < 10; ++frame) ASSERT_TRUE(sim.step().finite);
  const double weight = box_mass(scene) * kG;
  EXPECT_NEAR(-measured(sim, "obstacle0_force_y"), weight, 5e-3 * weight);
  EXPECT_NEAR(measured(sim, "obstacle0_force_x"), 0.0, 5e-3 * weight);
  EXPECT_EQ(measured(sim, "obstacle0_contacts"), 25.0);  // the bottom face's 5 x 5 vertices
  EXPECT_EQ(measured(sim, "contact_penetration"), 0.0);
}

// Gravity tilted by theta (tan theta = 0.364) against a level floor: the
// block sticks for mu = 0.5 (creep below eps_v t) and slides with
// a = g (sin theta - mu cos theta) for mu = 0.2.
TEST(Contact, BlockOnAnInclineSticksOrSlidesAsCoulombSays) {
  const double theta = 20.0 * M_PI / 180.0;
  for (double mu : {0.5, 0.2}) {
    Scene scene = box_on_floor(1.5e-4, mu);
    scene.gravity = {kG * std::sin(theta), -kG * std::cos(theta), 0.0};
    const Mesh mesh = build_scene_mesh(scene.mesh);
    Simulation<double> sim(MPI_COMM_WORLD, scene, mesh);
    // Settle onto the barrier, then measure over 0.2 s.
    for (int frame = 0; frame < 10; ++frame) ASSERT_TRUE(sim.step().finite);
    const double x0 = mean_x(sim);
    for (int frame = 0; frame < 10; ++frame) ASSERT_TRUE(sim.step().finite);
    const double x1 = mean_x(sim);
    for (int frame = 0; frame < 10; ++frame) ASSERT_TRUE(sim.step().finite);
    const double x2 = mean_x(sim);
    const double span = 10 * scene.time.dt;
    if (mu > std::tan(theta)) {
      EXPECT_LT(std::abs(x2 - x0), scene.contact.smoothing_velocity * 2 * span) << "creep";
      EXPECT_NEAR(measured(sim, "obstacle0_force_x"), box_mass(scene) * kG * std::sin(theta),
                  1e-3 * box_mass(scene) * kG);
    } else {
      // Constant acceleration: the second difference over equal spans.
      const double a = (x2 - 2 * x1 + x0) / (span * span);
      const double want = kG * (std::sin(theta) - mu * std::cos(theta));
      EXPECT_NEAR(a, want, 0.05 * want);
    }
  }
}

// A box that falls 1 m under 200 m/s^2 of gravity and meets the floor at
// 20 m/s with dt = 1/30 (it would cross 0.67 m in one step), with `method`.
Scene hard_impact(const char* method, double young, int iterations) {
  Scene scene = box_on_floor(1.0, 0.0);
  scene.gravity = {0.0, -200.0, 0.0};
  scene.material.young = young;
  scene.solver.method = method;
  scene.time.dt = 1.0 / 30.0;
  scene.solver.accuracy = 1e-3;
  scene.solver.iterations = iterations;
  return scene;
}

// Runs 30 steps of `sim` with every iterate observed (each step must end
// finite); returns the lowest y any surface vertex had in any iterate (-1
// for a coordinate not finite), over all ranks, and counts the iterates.
double lowest_surface_y_of_every_iterate(Simulation<double>& sim, long& iterates) {
  const std::vector<index_t>& surface = sim.problem().contact()->vertices();
  double lowest = 1e300;
  sim.stepper().set_observer([&](int, const double* q, const double*, const double*) {
    ++iterates;
    for (index_t v : surface) {
      const double y = q[3 * v + 1];
      lowest = std::min(lowest, std::isfinite(q[3 * v]) && std::isfinite(q[3 * v + 2]) ? y : -1.0);
    }
  });
  for (int frame = 0; frame < 30; ++frame) EXPECT_TRUE(sim.step().finite) << "frame " << frame;
  sim.stepper().set_observer(nullptr);  // it refers to this frame's `lowest`
  MPI_Allreduce(MPI_IN_PLACE, &lowest, 1, MPI_DOUBLE, MPI_MIN, MPI_COMM_WORLD);
  return lowest;
}

// The hard impact, soft (it is supersonic: the box crushes) and stiff (it
// bounces): no iterate of any step, observed after every iteration, has a
// surface vertex on or below the floor or not finite (a diverging trial
// moves nothing the guard cannot bound, and its check rolls it back), every
// step ends finite, and the body ends on the floor carrying its weight.
TEST(Contact, NoIterateOfAHardImpactCrossesTheFloor) {
  for (double young : {1e5, 1e7}) {
    const Scene scene = hard_impact("chebyshev", young, 96);
    const Mesh mesh = build_scene_mesh(scene.mesh);
    Simulation<double> sim(MPI_COMM_WORLD, scene, mesh);
    long iterates = 0;
    const double lowest = lowest_surface_y_of_every_iterate(sim, iterates);
    EXPECT_GT(lowest, 0.0) << "E " << young << ": a surface vertex reached y = " << lowest;
    EXPECT_GT(iterates, 30);
    const double weight = box_mass(scene) * 200.0;
    EXPECT_GT(measured(sim, "obstacle0_contacts"), 0.0) << "E " << young;
    EXPECT_NEAR(-measured(sim, "obstacle0_force_y"), weight, 0.05 * weight) << "E " << young;
  }
}

// The barrier in the first-order methods (gd, jacobi_gd, nesterov, ncg,
// lbfgs evaluate it and guard each update as chebyshev does, nesterov its
// extrapolation too; ncg's step length takes the barrier's curvature): at
// the hard impact no observed iterate of any of them has a surface vertex
// on or below the floor or not finite; the box lands, and with lbfgs
// settles carrying its weight.
TEST(Contact, TheFirstOrderMethodsKeepEveryIterateOutside) {
  for (const char* method : {"gd", "jacobi_gd", "nesterov", "ncg", "lbfgs"}) {
    const Scene scene = hard_impact(method, 1e6, 200);
    const Mesh mesh = build_scene_mesh(scene.mesh);
    Simulation<double> sim(MPI_COMM_WORLD, scene, mesh);
    long iterates = 0;
    const double lowest = lowest_surface_y_of_every_iterate(sim, iterates);
    EXPECT_GT(lowest, 0.0) << method << ": a surface vertex reached y = " << lowest;
    EXPECT_GT(iterates, 30) << method;
    EXPECT_GT(measured(sim, "obstacle0_contacts"), 0.0) << method;  // it landed
    if (std::string(method) == "lbfgs") {
      const double weight = box_mass(scene) * 200.0;
      EXPECT_NEAR(-measured(sim, "obstacle0_force_y"), weight, 0.05 * weight);
    }
  }
}

// Newton with the obstacles' barrier (its contact blocks in H, its line
// search from the longest step that keeps every gap): at the hard impact on
// a slab 1 cm thick, which a trial ending below it would pass with a finite
// energy, no Newton iterate has a surface vertex on or below the slab's top
// or not finite, soft or stiff; the box lands and settles carrying its
// weight; the quasi-static box on a plane carries its weight as with
// chebyshev. Its CG is preconditioned by "auto"'s multilevel V-cycle at
// the impact (and, stiff, by Jacobi's too), by Jacobi's for the
// quasi-static box, which nothing holds.
TEST(Contact, NewtonKeepsEveryIterateOutsideAndCarriesTheWeight) {
  struct Case {
    double young;
    const char* preconditioner;
  };
  for (const auto& [young, preconditioner] :
       {Case{1e5, "auto"}, Case{1e7, "auto"}, Case{1e7, "jacobi"}}) {
    Scene scene = hard_impact("newton", young, 200);
    scene.solver.accuracy = 1e-6;
    scene.solver.preconditioner = preconditioner;
    scene.obstacles[0].kind = "box";
    scene.obstacles[0].box_min = {-1.0, -0.01, -1.0};
    scene.obstacles[0].box_max = {1.0, 0.0, 1.0};
    const Mesh mesh = build_scene_mesh(scene.mesh);
    Simulation<double> sim(MPI_COMM_WORLD, scene, mesh);
    long iterates = 0;
    const double lowest = lowest_surface_y_of_every_iterate(sim, iterates);
    EXPECT_GT(lowest, 0.0) << "E " << young << " " << preconditioner
                           << ": a surface vertex reached y = " << lowest;
    EXPECT_GT(iterates, 30) << "E " << young << " " << preconditioner;
    EXPECT_GT(measured(sim, "obstacle0_contacts"), 0.0) << "E " << young << " " << preconditioner;
    const double weight = box_mass(scene) * 200.0;
    EXPECT_NEAR(-measured(sim, "obstacle0_force_y"), weight, 0.05 * weight)
        << "E " << young << " " << preconditioner;
  }
  Scene scene = box_on_floor(1.5e-4, 0.5);
  scene.time.quasistatic = true;
  scene.solver.method = "newton";
  scene.solver.accuracy = 1e-8;
  const Mesh mesh = build_scene_mesh(scene.mesh);
  Simulation<double> sim(MPI_COMM_WORLD, scene, mesh);
  for (int frame = 0; frame < 3; ++frame) ASSERT_TRUE(sim.step().finite);
  const double weight = box_mass(scene) * kG;
  EXPECT_NEAR(-measured(sim, "obstacle0_force_y"), weight, 5e-3 * weight);
  EXPECT_EQ(measured(sim, "obstacle0_contacts"), 25.0);
  EXPECT_EQ(measured(sim, "contact_penetration"), 0.0);
}

// Newton's CG with either preconditioner, the multilevel V-cycle's finest
// operator taking the obstacles' contact blocks at each Newton iterate: the
// quasi-static box comes to the same positions with both.
TEST(Contact, NewtonsCgGivesTheSameStepsWithEitherPreconditioner) {
  Scene scene = box_on_floor(1.5e-4, 0.5);
  scene.time.quasistatic = true;
  scene.solver.method = "newton";
  scene.solver.accuracy = 0;  // to newton_tolerance: both solve to round-off
  const Mesh mesh = build_scene_mesh(scene.mesh);
  scene.solver.preconditioner = "jacobi";
  Simulation<double> jacobi(MPI_COMM_WORLD, scene, mesh);
  // Explicitly: "auto" leaves a quasi-static body that nothing holds to
  // Jacobi (without the floor its operator is singular).
  scene.solver.preconditioner = "multilevel";
  Simulation<double> multilevel(MPI_COMM_WORLD, scene, mesh);
  for (int frame = 0; frame < 3; ++frame) {
    ASSERT_TRUE(jacobi.step().finite);
    ASSERT_TRUE(multilevel.step().finite);
  }
  const double weight = box_mass(scene) * kG;
  EXPECT_NEAR(-measured(multilevel, "obstacle0_force_y"), weight, 5e-3 * weight);
  EXPECT_EQ(measured(multilevel, "obstacle0_contacts"), 25.0);
  EXPECT_EQ(measured(multilevel, "contact_penetration"), 0.0);
  double worst = 0;
  for (std::size_t k = 0; k < multilevel.state().q.size(); ++k)
    worst = std::max(worst, std::abs(multilevel.state().q[k] - jacobi.state().q[k]));
  MPI_Allreduce(MPI_IN_PLACE, &worst, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
  EXPECT_LE(worst, 1e-9 * scene.mesh.box.size[0]);
}

// A fixed iteration count on P ranks gives the one-rank positions to
// round-off, with the contact vertices spread over every rank.
TEST(Contact, PRanksGiveOneRanksResult) {
  Scene scene = box_on_floor(0.02, 0.3);
  scene.solver.accuracy = 0;
  scene.solver.iterations = 48;
  scene.time.dt = 1.0 / 60.0;
  scene.gravity = {5.0, -kG, 1.0};  // tan > mu: it lands and slides
  const Mesh mesh = build_scene_mesh(scene.mesh);
  const testing::OneRankComparison c =
      testing::compare_with_one_rank(MPI_COMM_WORLD, scene, mesh, 24);
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  if (rank == 0) {
    EXPECT_GT(c.moved, 0.03);  // it fell 0.02 onto the floor and slid
    EXPECT_LT(c.worst, 1e-9 * c.moved);
  }
}

// contact.method = "projection" with a method that knows nothing of the
// barrier: no vertex ends a step below the floor and the body stays on it.
// (The pass moves surface vertices only: a solve that sinks a body deeper
// than a layer of its elements in one step inverts them, as paper 2's
// collision pass would; the drop here sinks it 0.007 per step into layers of
// 0.05.)
TEST(Contact, ProjectionKeepsEveryStepsResultOutside) {
  Scene scene = box_on_floor(0.01, 0.3);
  scene.contact.method = "projection";
  scene.solver.method = "lbfgs";
  scene.solver.accuracy = 0;
  scene.solver.iterations = 100;
  scene.time.dt = 1.0 / 60.0;
  const Mesh mesh = build_scene_mesh(scene.mesh);
  Simulation<double> sim(MPI_COMM_WORLD, scene, mesh);
  double deepest = 0;
  for (int frame = 0; frame < 40; ++frame) {
    ASSERT_TRUE(sim.step().finite);
    double lowest = 1e300;
    for (index_t v = 0; v < sim.local_mesh().num_vertices(); ++v)
      lowest = std::min(lowest, sim.state().q[3 * v + 1]);
    MPI_Allreduce(MPI_IN_PLACE, &lowest, 1, MPI_DOUBLE, MPI_MIN, MPI_COMM_WORLD);
    EXPECT_GE(lowest, -1e-12) << "frame " << frame;
    deepest = std::max(deepest, measured(sim, "contact_penetration"));
  }
  EXPECT_GT(deepest, 0.0);  // the solves did go through; the pass put them back
  // At rest: the corrections carry the weight (m g per step, as impulses).
  const double weight = box_mass(scene) * kG;
  EXPECT_NEAR(-measured(sim, "obstacle0_force_y"), weight, 0.05 * weight);
}

// The message of the InputError that setting up `scene` throws.
std::string set_up_error(const Scene& scene, const Mesh& mesh) {
  try {
    Simulation<double> sim(MPI_COMM_WORLD, scene, mesh);
  } catch (const InputError& error) {
    return error.what();
  }
  ADD_FAILURE() << "no error";
  return "";
}

TEST(Contact, AnObstacleThatCutsTheBodyIsAnErrorNamingIt) {
  Scene scene = box_on_floor(0.01, 0.0);
  Obstacle ball;
  ball.kind = "sphere";
  ball.centre = {0.1, 0.05, 0.1};
  ball.radius = 0.03;
  scene.obstacles.push_back(ball);
  const Mesh mesh = build_scene_mesh(scene.mesh);
  std::string message = set_up_error(scene, mesh);
  EXPECT_NE(message.find("obstacle.1 (sphere) cuts the body at its start"), std::string::npos)
      << message;
  // Touching is cutting for the barrier, which is infinite at a zero gap.
  scene.obstacles.pop_back();
  scene.obstacles[0].point = {0.0, 0.01, 0.0};
  message = set_up_error(scene, mesh);
  EXPECT_NE(message.find("obstacle.0 (plane) touches the body at its start"), std::string::npos)
      << message;
}

}  // namespace
}  // namespace descent
