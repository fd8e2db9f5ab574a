// Contact between bodies with contact.method = "projection" on 1 to 4 ranks
// (contact/body_projection.hpp): two boxes thrown at each other, the step
// solved without contact and its result corrected, end every step apart,
// keep their total momentum, and lose the normal velocity of the impact;
// at 20 m/s relative speed and dt = 1/30, where every solve takes them
// through each other, every method's steps end apart. (P ranks giving one
// rank's result, and bodies touching at the start: test_body_contact.cpp,
// for both formulations.)
#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "app/scene_mesh.hpp"
#include "app/simulation.hpp"
#include "common/error.hpp"
#include "contact/body_overlap.hpp"
#include "gather_positions.hpp"
#include "small_scenes.hpp"

namespace descent {
namespace {

using testing::head_on;
using testing::measured;

Scene projected(Scene scene) {
  scene.contact.method = "projection";
  return scene;
}

// Whether the bodies at the simulation's state are apart (rank 0 answers for
// all: the whole mesh's positions are gathered there).
bool apart(Simulation<double>& sim, Mesh mesh) {
  const std::vector<double> q = testing::gather_positions(MPI_COMM_WORLD, sim, mesh.num_vertices());
  int rank = 0, ok = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  if (rank == 0) {
    mesh.positions = q;
    try {
      check_bodies_apart(mesh, {"body.0", "body.1"});
    } catch (const InputError&) {
      ok = 0;
    }
  }
  MPI_Bcast(&ok, 1, MPI_INT, 0, MPI_COMM_WORLD);
  return ok == 1;
}

TEST(BodyProjection, HeadOnImpactEndsEveryStepApartAndKeepsMomentum) {
  const Scene scene = projected(head_on(2.0));
  const Mesh mesh = build_scene_mesh(scene);
  Simulation<double> sim(MPI_COMM_WORLD, scene, mesh);
  const double p0 = measured(sim, "body0_momentum_x");
  const double kinetic0 = measured(sim, "body0_kinetic") + measured(sim, "body1_kinetic");
  ASSERT_GT(p0, 0.0);
  double most_pairs = 0, largest_push = 0;
  for (int frame = 0; frame < 30; ++frame) {
    ASSERT_TRUE(sim.step().finite) << "frame " << frame;
    EXPECT_TRUE(apart(sim, mesh)) << "frame " << frame;
    EXPECT_GT(measured(sim, "body_contact_least_distance"), 0.0) << "frame " << frame;
    for (const char* axis : {"x", "y", "z"}) {
      const std::string a = std::string("body0_momentum_") + axis;
      const std::string b = std::string("body1_momentum_") + axis;
      EXPECT_LT(std::abs(measured(sim, a) + measured(sim, b)), 1e-6 * p0) << "frame " << frame;
    }
    most_pairs = std::max(most_pairs, measured(sim, "body_contact_pairs"));
    // The corrections push the two bodies equally and oppositely.
    const double push = measured(sim, "body1_contact_force_x");
    largest_push = std::max(largest_push, push);
    EXPECT_LE(std::abs(measured(sim, "body0_contact_force_x") + push), 1e-9 * std::abs(push) + 1e-9)
        << "frame " << frame;
  }
  EXPECT_GT(most_pairs, 0.0);    // they did meet
  EXPECT_GT(largest_push, 0.0);  // body 1 pushed back towards +x
  // The impact is inelastic: the approach is stopped, and no energy gained.
  EXPECT_LT(measured(sim, "body0_momentum_x"), 0.5 * p0);
  EXPECT_LT(measured(sim, "body0_kinetic") + measured(sim, "body1_kinetic"), kinetic0);
}

// 20 m/s relative at dt = 1/30: each step moves the boxes 0.67 m against
// each other, so a solve without contact takes them through each other
// (the penetration column says so) and the pass must bring them back, for
// a method with Jacobi's D, with the multilevel preconditioner and
// without Chebyshev.
TEST(BodyProjection, EveryMethodEndsApartAtTwentyMetresPerSecond) {
  struct Case {
    const char* method;
    const char* preconditioner;
  };
  for (const Case c :
       {Case{"chebyshev", "jacobi"}, Case{"chebyshev", "multilevel"}, Case{"lbfgs", "jacobi"}}) {
    Scene scene = projected(head_on(10.0));
    scene.time.dt = 1.0 / 30.0;
    scene.solver.method = c.method;
    scene.solver.preconditioner = c.preconditioner;
    scene.solver.iterations = 96;
    scene.solver.accuracy = 1e-3;
    const Mesh mesh = build_scene_mesh(scene);
    Simulation<double> sim(MPI_COMM_WORLD, scene, mesh);
    const double p0 = measured(sim, "body0_momentum_x");
    double deepest = 0;
    for (int frame = 0; frame < 12; ++frame) {
      ASSERT_TRUE(sim.step().finite) << c.method << " " << c.preconditioner << " frame " << frame;
      EXPECT_TRUE(apart(sim, mesh)) << c.method << " " << c.preconditioner << " frame " << frame;
      deepest = std::max(deepest, measured(sim, "body_contact_penetration"));
      // The islands' cut keeps their common move, the sweeps each pair's
      // momentum: the total stays what it was.
      const double total = measured(sim, "body0_momentum_x") + measured(sim, "body1_momentum_x");
      EXPECT_LT(std::abs(total), 1e-6 * p0)
          << c.method << " " << c.preconditioner << " frame " << frame;
    }
    EXPECT_GT(deepest, 0.05) << c.method << " " << c.preconditioner;
  }
}

}  // namespace
}  // namespace descent
