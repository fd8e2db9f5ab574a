// Contact between bodies on 1 to 4 ranks (contact/body_contact.hpp): two
// boxes thrown at each other conserve their total momentum through the
// impact, push each other equally and oppositely, gain no energy and bounce
// apart; at 20 m/s relative speed and dt = 1/30 no iterate of any step has
// them overlap (with chebyshev, jacobi_gd and lbfgs); P ranks give one rank's result with the
// contact pairs spanning ranks and bodies that touch at the start are an error, with the barrier
// and with the projection; each contact island keeps its own share of the step's guess; each ball
// of a settled snowman carries the weight of those above it; the Hessian product with the
// contact terms (ncg's step length) matches central differences of the gradient.
#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>

#include "app/scene_mesh.hpp"
#include "app/simulation.hpp"
#include "common/error.hpp"
#include "contact/body_overlap.hpp"
#include "gather_positions.hpp"
#include "kernels/vertex.hpp"
#include "small_scenes.hpp"
#include "solver/methods/hessian_operator.hpp"

namespace descent {
namespace {

using testing::box;
using testing::head_on;
using testing::measured;

TEST(BodyContact, HeadOnImpactConservesMomentumAndBouncesApart) {
  const Scene scene = head_on(2.0);
  const Mesh mesh = build_scene_mesh(scene);
  Simulation<double> sim(MPI_COMM_WORLD, scene, mesh);
  const double p0 = measured(sim, "body0_momentum_x");
  ASSERT_GT(p0, 0.0);
  double most_pairs = 0, largest_push = 0;
  for (int frame = 0; frame < 30; ++frame) {
    ASSERT_TRUE(sim.step().finite) << "frame " << frame;
    const double total = measured(sim, "body0_momentum_x") + measured(sim, "body1_momentum_x");
    EXPECT_LT(std::abs(total), 1e-6 * p0) << "frame " << frame;
    for (const char* axis : {"y", "z"}) {
      const std::string a = std::string("body0_momentum_") + axis;
      const std::string b = std::string("body1_momentum_") + axis;
      EXPECT_LT(std::abs(measured(sim, a) + measured(sim, b)), 1e-6 * p0) << "frame " << frame;
    }
    EXPECT_GT(measured(sim, "body_contact_least_distance"), 0.0) << "frame " << frame;
    most_pairs = std::max(most_pairs, measured(sim, "body_contact_pairs"));
    // The pairs push the two bodies equally and oppositely.
    const double push = measured(sim, "body1_contact_force_x");
    largest_push = std::max(largest_push, push);
    EXPECT_LE(std::abs(measured(sim, "body0_contact_force_x") + push),
              1e-9 * std::abs(push) + 1e-12)
        << "frame " << frame;
  }
  EXPECT_GT(most_pairs, 0.0);                         // they did meet
  EXPECT_GT(largest_push, 0.0);                       // body 1 pushed back towards +x
  EXPECT_LT(measured(sim, "body0_momentum_x"), 0.0);  // and bounced back
  EXPECT_LT(measured(sim, "body0_kinetic") + measured(sim, "body1_kinetic"),
            0.5 * 2 * 0.2 * 0.2 * 0.2 * 1000 * 4.0);  // losing energy, gaining none
}

// The total energy at the state after a step: kinetic, elastic and the
// pairs' barrier (eps with the inertial target at q is the potential).
double total_energy(Simulation<double>& sim) {
  const std::vector<double>& q = sim.state().q;
  double potential = sim.problem().local_energy(q.data(), q.data(), q.data()).value +
                     sim.problem().body_contact()->local_energy(q.data());
  MPI_Allreduce(MPI_IN_PLACE, &potential, 1, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
  return potential + measured(sim, "body0_kinetic") + measured(sim, "body1_kinetic");
}

// descent study measures eps between iterations with the pairs' energy
// (BodyContact::measured_energy): the same sum the iteration's own energy
// check makes, without touching the iteration's state.
TEST(BodyContact, MeasuredEnergyIsTheIterationsOwn) {
  const Scene scene = head_on(2.0);
  const Mesh mesh = build_scene_mesh(scene);
  Simulation<double> sim(MPI_COMM_WORLD, scene, mesh);
  double in_contact = 0;
  for (int frame = 0; frame < 12; ++frame) {
    ASSERT_TRUE(sim.step().finite);
    const double* q = sim.state().q.data();
    double sums[2] = {sim.problem().body_contact()->measured_energy(q),
                      sim.problem().body_contact()->local_energy(q)};
    MPI_Allreduce(MPI_IN_PLACE, sums, 2, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
    EXPECT_NEAR(sums[0], sums[1], 1e-12 * std::abs(sums[1])) << "frame " << frame;
    in_contact = std::max(in_contact, sums[0]);
  }
  EXPECT_GT(in_contact, 0.0);  // the barrier was measured, not only zeros
}

// 30 steps of the head-on impact `scene` solved tightly: the largest rise
// of the total energy in a step (relative to the initial), the largest
// total momentum along x (relative to body 0's initial), the most pairs
// within reach and body 0's final momentum along x.
struct TightImpact {
  double largest_rise = -1e300, largest_momentum = 0, most_pairs = 0, final_momentum_x = 0;
};

TightImpact run_tight_impact(const Scene& scene) {
  const Mesh mesh = build_scene_mesh(scene);
  Simulation<double> sim(MPI_COMM_WORLD, scene, mesh);
  const double p0 = measured(sim, "body0_momentum_x");
  const double initial = total_energy(sim);
  double before = initial;
  TightImpact seen;
  for (int frame = 0; frame < 30; ++frame) {
    EXPECT_TRUE(sim.step().finite) << "frame " << frame;
    const double total = measured(sim, "body0_momentum_x") + measured(sim, "body1_momentum_x");
    seen.largest_momentum = std::max(seen.largest_momentum, std::abs(total) / p0);
    const double after = total_energy(sim);
    seen.largest_rise = std::max(seen.largest_rise, (after - before) / initial);
    before = after;
    seen.most_pairs = std::max(seen.most_pairs, measured(sim, "body_contact_pairs"));
  }
  seen.final_momentum_x = measured(sim, "body0_momentum_x");
  return seen;
}

// Implicit Euler dissipates: with each step solved tightly, no step may
// raise the total energy through the impact.
TEST(BodyContact, HeadOnImpactSolvedTightlyGainsNoEnergy) {
  Scene scene = head_on(2.0);
  scene.solver.accuracy = 1e-9;
  scene.solver.iterations = 4000;
  const TightImpact seen = run_tight_impact(scene);
  EXPECT_GT(seen.most_pairs, 0.0);
  EXPECT_LE(seen.largest_rise, 1e-7);
  EXPECT_LT(seen.largest_momentum, 1e-6);
}

// What 20 steps of `scene` (two bodies) showed on one rank with every
// iterate observed: overlaps (contact/body_overlap.hpp's test on the whole
// mesh at the iterate), coordinates not finite, and the most pairs within
// reach at a step's end. Each step must end finite.
struct ObservedIterates {
  long iterates = 0, overlaps = 0, non_finite = 0;
  double most_pairs = 0, final_momentum_x = 0;  // body 0's
};

ObservedIterates observe_every_iterate(const Scene& scene) {
  ObservedIterates seen;
  Mesh mesh = build_scene_mesh(scene);
  Simulation<double> sim(MPI_COMM_SELF, scene, mesh);
  const LocalMesh& local = sim.local_mesh();
  const std::vector<std::string> names = {"body.0", "body.1"};
  sim.stepper().set_observer([&](int, const double* q, const double*, const double*) {
    ++seen.iterates;
    for (index_t v = 0; v < local.num_vertices(); ++v)
      for (int i = 0; i < 3; ++i) {
        const double x = q[3 * v + i];
        seen.non_finite += !std::isfinite(x);
        mesh.positions[3 * local.global_vertex[v] + i] = x;
      }
    try {
      check_bodies_apart(mesh, names);
    } catch (const InputError&) {
      ++seen.overlaps;
    }
  });
  for (int frame = 0; frame < 20; ++frame) {
    EXPECT_TRUE(sim.step().finite) << "frame " << frame;
    seen.most_pairs = std::max(seen.most_pairs, measured(sim, "body_contact_pairs"));
    EXPECT_GT(measured(sim, "body_contact_least_distance"), 0.0) << "frame " << frame;
  }
  seen.final_momentum_x = measured(sim, "body0_momentum_x");
  return seen;
}

// The boxes at 20 m/s relative speed, dt = 1/30 (each would cross 0.33 m
// into the other in a step), on one rank.
Scene fast_head_on(const char* method, double young, int iterations) {
  Scene scene = head_on(10.0);
  scene.solver.method = method;
  scene.material.young = young;
  scene.time.dt = 1.0 / 30.0;
  scene.solver.iterations = iterations;
  scene.solver.accuracy = 1e-3;
  return scene;
}

// Every iterate of every step, observed: the bodies never overlap and every
// coordinate is finite; soft and stiff.
TEST(BodyContact, NoIterateOverlapsAtTwentyMetresPerSecond) {
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  if (rank != 0) return;
  for (double young : {1e5, 1e7}) {
    const ObservedIterates seen = observe_every_iterate(fast_head_on("chebyshev", young, 96));
    EXPECT_GT(seen.iterates, 20);
    EXPECT_EQ(seen.overlaps, 0) << "E " << young;
    EXPECT_EQ(seen.non_finite, 0) << "E " << young;
  }
}

// The barrier in the first-order methods that evaluate it (jacobi_gd,
// nesterov, ncg, lbfgs): at 20 m/s relative speed and dt = 1/30 no observed
// iterate has the bodies overlap or a coordinate not finite, on one rank;
// the boxes meet and stop each other. jacobi_gd's and lbfgs's bounce back;
// nesterov's glance off sideways (apart in y from frame 4, measured) and
// pass each other with a tenth of their momentum along x, and so do ncg's
// (0.098 p0 left along x, 0.17 p0 gained along y, measured). With lbfgs, which
// reaches 1e-9 within the cap (jacobi_gd does not: its momentum drifts 8e-5
// of p0), the total momentum is kept to 1e-6 through the impact on every
// rank count.
TEST(BodyContact, TheFirstOrderMethodsKeepEveryIterateApart) {
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  for (const char* method : {"jacobi_gd", "nesterov", "ncg", "lbfgs"}) {
    if (rank == 0) {
      const Scene scene = fast_head_on(method, 1e5, 200);
      const ObservedIterates seen = observe_every_iterate(scene);
      EXPECT_GT(seen.iterates, 20) << method;
      EXPECT_EQ(seen.overlaps, 0) << method;
      EXPECT_EQ(seen.non_finite, 0) << method;
      EXPECT_GT(seen.most_pairs, 0.0) << method;
      const double p0 = 10.0 * scene.material.density * 0.2 * 0.2 * 0.2;  // each box at 10 m/s
      if (std::string(method) == "nesterov")
        EXPECT_LT(std::abs(seen.final_momentum_x), 0.1 * p0) << method;  // stopped along x
      else if (std::string(method) == "ncg")
        EXPECT_LT(std::abs(seen.final_momentum_x), 0.2 * p0) << method;  // most of it stopped
      else
        EXPECT_LT(seen.final_momentum_x, 0.0) << method;  // bounced back
    }
    if (std::string(method) != "lbfgs") continue;
    Scene scene = head_on(2.0);
    scene.solver.method = method;
    scene.solver.accuracy = 1e-9;
    scene.solver.iterations = 4000;
    const Mesh mesh = build_scene_mesh(scene);
    Simulation<double> sim(MPI_COMM_WORLD, scene, mesh);
    const double p0 = measured(sim, "body0_momentum_x");
    double most_pairs = 0;
    for (int frame = 0; frame < 30; ++frame) {
      ASSERT_TRUE(sim.step().finite) << method << " frame " << frame;
      const double total = measured(sim, "body0_momentum_x") + measured(sim, "body1_momentum_x");
      EXPECT_LT(std::abs(total), 1e-6 * p0) << method << " frame " << frame;
      most_pairs = std::max(most_pairs, measured(sim, "body_contact_pairs"));
    }
    EXPECT_GT(most_pairs, 0.0) << method;
  }
}

// Newton with the pairs' barrier (their Hessian in H, the line search from
// the longest step that keeps every pair's gap and the pairs' drift cap):
// at 20 m/s relative speed and dt = 1/30 no Newton iterate has the bodies
// overlap or a coordinate not finite, and they meet (the impact's step
// ends at the 50-iteration cap, each iteration's move held to what the
// pairs' paths and the drift cap allow; the boxes then glance off, as
// nesterov's do); the
// head-on impact, solved to Newton's tolerance on every rank count, keeps
// the total momentum to 1e-6 and raises the total energy in no step by more
// than 1e-7 of it (the "or Newton"). Its CG preconditioned by
// "auto"'s multilevel V-cycle (the pairs' diagonal in its finest operator at
// each Newton iterate, their couplings in the CG's products) and by
// Jacobi's diagonal.
TEST(BodyContact, NewtonKeepsEveryIterateApartAndConservesMomentum) {
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  for (const char* preconditioner : {"auto", "jacobi"}) {
    if (rank == 0) {
      Scene fast = fast_head_on("newton", 1e5, 200);
      fast.solver.preconditioner = preconditioner;
      const ObservedIterates seen = observe_every_iterate(fast);
      EXPECT_GT(seen.iterates, 20) << preconditioner;
      EXPECT_EQ(seen.overlaps, 0) << preconditioner;
      EXPECT_EQ(seen.non_finite, 0) << preconditioner;
      EXPECT_GT(seen.most_pairs, 0.0) << preconditioner;
    }
    Scene scene = head_on(2.0);
    scene.solver.method = "newton";
    scene.solver.preconditioner = preconditioner;
    scene.solver.accuracy = 0;  // to newton_tolerance
    const TightImpact seen = run_tight_impact(scene);
    EXPECT_GT(seen.most_pairs, 0.0) << preconditioner;
    EXPECT_LE(seen.largest_rise, 1e-7) << preconditioner;
    EXPECT_LT(seen.largest_momentum, 1e-6) << preconditioner;
    EXPECT_LT(seen.final_momentum_x, 0.0) << preconditioner;  // bounced back
  }
}

// Both formulations: the barrier, and the projection pass after the solve
// (contact/body_projection.hpp, tests/mpi/test_body_projection.cpp).
// And the barrier in lbfgs, whose inner products sum in another order on
// each rank count: chebyshev's runs agree to 3e-16 m through frame 10,
// lbfgs's to 1e-31 m before the impact (frame 6), 1e-14 at frame 8,
// 2e-11 at frame 10 and 3e-7 to 1.3e-6 at frame 12 on 2-4 ranks (its
// curvature pairs and step directions carry the round-off of each sum
// into the next iterate, and the impact amplifies it): compared at frame
// 10, through the start of the impact. Nesterov's momentum, which takes no
// inner product, is compared through frame 12 as chebyshev's is.
TEST(BodyContact, PRanksGiveOneRanksResult) {
  struct Run {
    const char* formulation;
    const char* method;
    int frames;
    bool self;  // contact.self: each vertex's drift cap, ghosts' from their holders
  };
  for (const Run& run :
       {Run{"energy", "chebyshev", 12, false}, Run{"projection", "chebyshev", 12, false},
        Run{"energy", "lbfgs", 10, false}, Run{"energy", "nesterov", 12, false},
        Run{"energy", "ncg", 12, false}, Run{"energy", "chebyshev", 12, true}}) {
    const auto& [formulation, method, frames, self] = run;
    Scene scene = head_on(2.0);
    scene.contact.method = formulation;
    scene.contact.self = self;
    scene.solver.method = method;
    scene.solver.iterations = 48;
    const Mesh mesh = build_scene_mesh(scene);
    const testing::OneRankComparison c =
        testing::compare_with_one_rank(MPI_COMM_WORLD, scene, mesh, frames);
    int rank = 0;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    if (rank == 0) {
      EXPECT_GT(c.moved, 0.05) << formulation << " " << method << " self " << self;
      EXPECT_LT(c.worst, 1e-9 * c.moved) << formulation << " " << method << " self " << self;
    }
  }
}

// The Hessian product ncg's step length takes (HessianOperator::product
// given the step start): with the barriers and lagged friction of pressed
// pairs and of a floor it equals central differences of the gradient the
// methods descend, along a random direction, on every rank; and those
// terms are a large part of it, so leaving them out fails.
TEST(BodyContact, TheHessianProductWithContactMatchesFiniteDifferences) {
  Scene scene = head_on(0.0);
  scene.bodies[1].translate = {-0.05 + 1.5e-4, 0.03, 0.02};  // within dh of box 0's face
  scene.contact.friction = 0.3;
  Obstacle floor;
  floor.kind = "plane";
  floor.normal = {0.0, 1.0, 0.0};
  floor.friction = 0.3;
  Mesh mesh = build_scene_mesh(scene);
  double lowest = 1e300;
  for (std::size_t k = 1; k < mesh.positions.size(); k += 3)
    lowest = std::min(lowest, mesh.positions[k]);
  floor.point = {0.0, lowest - 1.5e-4, 0.0};  // within dh below both boxes
  scene.obstacles.push_back(floor);
  mesh = build_scene_mesh(scene);
  Simulation<double> sim(MPI_COMM_WORLD, scene, mesh);
  ASSERT_GT(measured(sim, "body_contact_pairs"), 0.0);
  ASSERT_GT(measured(sim, "obstacle0_contacts"), 0.0);
  LocalProblem<double>& problem = sim.problem();
  const std::vector<double> qt = sim.state().q;
  const std::size_t n = qt.size();
  // A step's start: the friction lags from qt, the pairs found about q;
  // box 1 slid along y, box 0 along z, so that no friction lies at zero
  // slip, where the mollifier's third derivative jumps and central
  // differences converge only linearly (measured: 3e-4 of H p at 1e-8).
  std::vector<double> q = qt;
  const std::vector<int> body = vertex_bodies(sim.local_mesh());
  for (std::size_t k = 0; k < n; k += 3) {
    if (body[k / 3] == 1) q[k + 1] += 2e-6;
    if (body[k / 3] == 0) q[k + 2] += 2e-6;
  }
  problem.begin_contact_step(0.0, qt.data(), q.data());

  const VertexTerms<double> terms = problem.vertex_terms();
  auto gradient = [&](const std::vector<double>& x) {
    const auto a = problem.elastic_gradient(x.data(), false);
    problem.add_contact_gradient(x.data(), qt.data(), a.width, nullptr);
    std::vector<double> g(n);
    for (std::size_t dof = 0; dof < n; ++dof)
      g[dof] = dof_gradient(terms, problem.mass()[dof / 3], a.values[a.width * (dof / 3) + dof % 3],
                            x[dof], qt[dof], qt[dof], 0.0, static_cast<int>(dof % 3));
    return g;
  };
  // The same direction on every rank: drawn per global vertex.
  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  std::vector<double> global(3 * mesh.num_vertices());
  for (double& x : global) x = uniform(random);
  std::vector<double> p(n);
  for (std::size_t dof = 0; dof < n; ++dof)
    p[dof] = global[3 * sim.local_mesh().global_vertex[dof / 3] + dof % 3];
  const double eps = 1e-9;  // moves of 1e-9 m against gaps of 1.5e-4 m
  std::vector<double> plus = q, minus = q;
  for (std::size_t dof = 0; dof < n; ++dof) {
    plus[dof] += eps * p[dof];
    minus[dof] -= eps * p[dof];
  }
  const std::vector<double> gp = gradient(plus), gm = gradient(minus);
  HessianOperator<double> hessian(problem);
  std::vector<double> with(n), without(n);
  hessian.product(q.data(), p.data(), with.data(), qt.data());
  hessian.product(q.data(), p.data(), without.data());
  // Over owned dofs: |H p - differences|^2, |H p|^2, |contact part|^2.
  double sums[3] = {0, 0, 0};
  for (std::size_t dof = 0; dof < 3 * static_cast<std::size_t>(sim.local_mesh().num_owned); ++dof) {
    const double difference = (gp[dof] - gm[dof]) / (2 * eps);
    sums[0] += (with[dof] - difference) * (with[dof] - difference);
    sums[1] += with[dof] * with[dof];
    sums[2] += (with[dof] - without[dof]) * (with[dof] - without[dof]);
  }
  MPI_Allreduce(MPI_IN_PLACE, sums, 3, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
  EXPECT_LT(std::sqrt(sums[0]), 1e-6 * std::sqrt(sums[1]));
  EXPECT_GT(std::sqrt(sums[2]), 0.1 * std::sqrt(sums[1]));
}

TEST(BodyContact, BodiesThatTouchAtTheStartAreAnError) {
  for (const char* method : {"energy", "projection"}) {
    Scene scene = head_on(0.0);
    scene.contact.method = method;
    scene.bodies[1].translate = {-0.05, 0.0, 0.0};  // face on face at x = -0.05
    const Mesh mesh = build_scene_mesh(scene);      // touching is no overlap
    try {
      Simulation<double> sim(MPI_COMM_WORLD, scene, mesh);
      ADD_FAILURE() << "no error with " << method;
    } catch (const InputError& error) {
      EXPECT_NE(std::string(error.what()).find("bodies touch at the start"), std::string::npos)
          << error.what();
    }
  }
}

// A block on a held slab, gravity tilted by theta = 20 degrees (an incline):
// with friction 0.5 > tan(theta) it sticks (its creep stays below the
// smoothing velocity times the time), with 0.2 it slides with acceleration
// g (sin - mu cos) within 5%.
// A box dropped onto a held slab comes to rest on the barrier: it neither
// hangs above it nor is pressed through it, and no pair of the landing is
// squeezed towards round-off (momentum carrying guarded vertices on into a
// pair once drove gaps to 1e-16, where the pairs pinned their bodies).
TEST(BodyContact, ADroppedBoxComesToRestOnTheBarrier) {
  Scene scene;
  Body slab;
  slab.mesh.generator = "box";
  slab.mesh.box.cells = {5, 1, 5};
  slab.mesh.box.size = {0.6, 0.1, 0.6};
  slab.mesh.box.origin = {-0.3, -0.1, -0.3};
  Body block = box({0.03, 0.11, 0.02}, 0.0);  // its bottom 0.11 above the slab, at 3 m/s
  block.velocity = {0, -3.0, 0};
  scene.bodies = {slab, block};
  FixedRegion held;
  held.box_min = {-1, -1, -1};
  held.box_max = {1, 1e-9, 1};
  scene.fixed.push_back(held);
  scene.material.young = 1e6;
  scene.time.dt = 0.01;
  scene.solver.accuracy = 1e-4;
  scene.solver.iterations = 400;
  const Mesh mesh = build_scene_mesh(scene);
  Simulation<double> sim(MPI_COMM_WORLD, scene, mesh);
  double dh = 0;
  double least = 1e300;
  for (int frame = 0; frame < 40; ++frame) {
    ASSERT_TRUE(sim.step().finite) << "frame " << frame;
    least = std::min(least, measured(sim, "body_contact_least_distance"));
    dh = sim.problem().body_contact()->activation_distance();
  }
  // The barrier stops it at ~0.7 dh (measured, 1 and 2 ranks); 1e-6 dh,
  // the least gap a guarded move keeps from an obstacle, is far below that
  // and far above round-off.
  EXPECT_GT(least, 1e-6 * dh);
  EXPECT_LT(std::abs(measured(sim, "body1_velocity_y")), 0.02);
  const double bottom = measured(sim, "body1_com_y") - 0.1;  // half its height
  EXPECT_GT(bottom, 0.0);
  EXPECT_LT(bottom, dh);
}

// The guess's pull-back scales each contact island's move by its own
// fraction: a box thrown down onto another is held back to keep half their
// gap, while a box falling beside them keeps its whole move (one fraction
// for the scene once held every body of a pile back whenever two touched).
TEST(BodyContact, EachContactIslandKeepsItsOwnShareOfTheGuess) {
  const double dh = 1e-3, drop = 0.01;
  Scene scene;
  // Box 1 lies 0.5 dh above box 0; box 2 is far from both.
  scene.bodies = {box({-0.4, 0, 0}, 0.0), box({-0.38, 0.2 + 0.5 * dh, 0.01}, 0.0),
                  box({0.4, 0, 0}, 0.0)};
  scene.gravity = {0, 0, 0};
  scene.contact.distance = dh;
  const Mesh mesh = build_scene_mesh(scene);
  Simulation<double> sim(MPI_COMM_WORLD, scene, mesh);
  LocalProblem<double>& problem = sim.problem();
  const LocalMesh& local = problem.mesh();
  const std::vector<int> body = vertex_bodies(local);
  const std::vector<double>& qt = local.rest_positions;
  // Boxes 1 and 2 move down by `drop`, box 1 through box 0.
  std::vector<double> q = qt;
  for (std::size_t v = 0; v < body.size(); ++v)
    if (body[v] > 0) q[3 * v + 1] -= drop;
  problem.body_contact()->pull_back(qt.data(), q.data());
  double kept[3] = {-1, -1, -1};  // each body's share of its move, the same for all its vertices
  for (std::size_t v = 0; v < body.size(); ++v) {
    const double share = body[v] == 0 ? 0.0 : (qt[3 * v + 1] - q[3 * v + 1]) / drop;
    if (kept[body[v]] < 0) kept[body[v]] = share;
    EXPECT_NEAR(share, kept[body[v]], 1e-12) << "vertex " << v;
  }
  double shares[2] = {kept[1], kept[2]};
  MPI_Allreduce(MPI_IN_PLACE, shares, 2, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
  EXPECT_NEAR(shares[1], 1.0, 1e-12);
  // Box 1 stops before half its gap of 0.5 dh to box 0 is gone, and not
  // much before: conservative advancement approaches the floor closely.
  EXPECT_GT(shares[0], 0.0);
  EXPECT_LE(shares[0] * drop, 0.25 * dh * (1 + 1e-9));
  EXPECT_GT(shares[0] * drop, 0.2 * dh);
}

TEST(BodyContact, ABlockOnAnInclinedBodySticksOrSlidesAsCoulombSays) {
  const double theta = 20 * M_PI / 180, g = 9.81;
  for (double mu : {0.5, 0.2}) {
    Scene scene;
    Body slab;
    slab.mesh.generator = "box";
    slab.mesh.box.cells = {6, 1, 6};
    slab.mesh.box.size = {1.0, 0.1, 1.0};
    slab.mesh.box.origin = {-0.5, -0.1, -0.5};
    Body block;
    block.mesh.generator = "box";
    block.mesh.box.cells = {4, 2, 4};
    block.mesh.box.size = {0.2, 0.1, 0.2};
    block.mesh.box.origin = {-0.1, 1.5e-4, -0.1};
    scene.bodies = {slab, block};
    FixedRegion held;  // the whole slab, its top face included
    held.box_min = {-1, -1, -1};
    held.box_max = {1, 1e-9, 1};
    scene.fixed.push_back(held);
    scene.gravity = {g * std::sin(theta), -g * std::cos(theta), 0};
    scene.material.young = 1e6;
    scene.contact.friction = mu;
    scene.time.dt = 0.01;
    scene.solver.accuracy = 1e-4;
    scene.solver.iterations = 400;
    const Mesh mesh = build_scene_mesh(scene);
    Simulation<double> sim(MPI_COMM_WORLD, scene, mesh);
    // Settle onto the barrier, then measure over 0.2 s.
    for (int frame = 0; frame < 10; ++frame) ASSERT_TRUE(sim.step().finite);
    const double x0 = measured(sim, "body1_com_x");
    std::vector<double> velocity;
    for (int frame = 0; frame < 20; ++frame) {
      ASSERT_TRUE(sim.step().finite) << "mu " << mu << " frame " << frame;
      velocity.push_back(measured(sim, "body1_velocity_x"));
    }
    const double t = 20 * scene.time.dt;
    if (mu > std::tan(theta)) {
      EXPECT_LT(std::abs(measured(sim, "body1_com_x") - x0), scene.contact.smoothing_velocity * t)
          << "mu " << mu;
    } else {
      const double a = (velocity[19] - velocity[9]) / (10 * scene.time.dt);
      const double want = g * (std::sin(theta) - mu * std::cos(theta));
      EXPECT_NEAR(a, want, 0.05 * want) << "mu " << mu;
    }
  }
}

// Paper 2's snowman, coarse: three balls stacked with 5-10 mm gaps on a
// frictional floor, settling under air damping. At rest (every body slower
// than 1 cm/s) each ball carries the weight of those above it within 1%:
// the head's pair force is its weight, the middle's net pair force its own
// (the head's on it cancels), the base's the weight of the two above, the
// floor's all three. Measured at 1 to 4 ranks: within 0.1% at frame 20.
TEST(BodyContact, EachBallOfASnowmanCarriesTheWeightOfThoseAbove) {
  Scene scene;
  const double radius[3] = {0.3, 0.2, 0.13}, centre_y[3] = {0.305, 0.81, 1.145};
  for (int b = 0; b < 3; ++b) {
    Body ball;
    ball.mesh.generator = "ball";
    ball.mesh.ball.cells = 4;
    ball.mesh.ball.radius = radius[b];
    ball.mesh.ball.centre = {0.0, centre_y[b], 0.0};
    scene.bodies.push_back(ball);
  }
  Obstacle floor;
  floor.kind = "plane";
  floor.normal = {0.0, 1.0, 0.0};
  floor.friction = 0.5;
  scene.obstacles.push_back(floor);
  scene.contact.friction = 0.5;
  scene.material.model = "neo_hookean";
  scene.material.young = 5e5;
  scene.material.density = 500;
  scene.time.dt = 1.0 / 30;
  scene.solver.damping = 20;
  scene.solver.accuracy = 1e-4;
  scene.solver.iterations = 2000;
  const Mesh mesh = build_scene_mesh(scene);
  Simulation<double> sim(MPI_COMM_WORLD, scene, mesh);
  for (int frame = 0; frame < 20; ++frame) ASSERT_TRUE(sim.step().finite) << "frame " << frame;

  // Each ball's lumped mass, summed by the vertices' owners.
  const std::vector<int> body = vertex_bodies(sim.local_mesh());
  double mass[3] = {0, 0, 0};
  for (index_t v = 0; v < sim.local_mesh().num_owned; ++v) mass[body[v]] += sim.problem().mass()[v];
  MPI_Allreduce(MPI_IN_PLACE, mass, 3, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
  const double g = 9.81, weight[3] = {mass[0] * g, mass[1] * g, mass[2] * g};
  for (int b = 0; b < 3; ++b) {
    double speed2 = 0;
    for (const char* a : {"x", "y", "z"}) {
      const double v = measured(sim, "body" + std::to_string(b) + "_velocity_" + a);
      speed2 += v * v;
    }
    ASSERT_LT(std::sqrt(speed2), 0.01) << "ball " << b << " not at rest";
  }
  const double tolerance = 0.01;
  EXPECT_NEAR(measured(sim, "body2_contact_force_y"), weight[2], tolerance * weight[2]);
  EXPECT_NEAR(measured(sim, "body1_contact_force_y"), weight[1], tolerance * weight[1]);
  EXPECT_NEAR(-measured(sim, "body0_contact_force_y"), weight[1] + weight[2],
              tolerance * (weight[1] + weight[2]));
  const double total = weight[0] + weight[1] + weight[2];
  EXPECT_NEAR(-measured(sim, "obstacle0_force_y"), total, tolerance * total);
}

}  // namespace
}  // namespace descent
