// Newton with solver.newton_solver = "petsc" (solver/petsc/newton_petsc.hpp)
// on the small helix stretched far from equilibrium: the assembled PETSc
// matrix is our Hessian (its product equals HessianOperator::apply), PETSc
// Newton (CG + GAMG, and CG + hypre BoomerAMG) takes the same Newton
// iterations as our CG Newton to the same result, an indefinite exact
// Hessian falls back to the projected one, the collectives are ours as
// documented plus PETSc's own, and float runs.
#include <gtest/gtest.h>
#include <mpi.h>
#include <petscsys.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "app/scene_mesh.hpp"
#include "app/simulation.hpp"
#include "mesh_extent.hpp"
#include "pmpi_counters.hpp"
#include "small_scenes.hpp"
#include "solver/methods/newton.hpp"
#include "solver/petsc/newton_petsc.hpp"
#include "world_rank.hpp"

namespace descent {
namespace {

using testing::world_rank;

using testing::stretched_positions;

struct NewtonRun {
  StepStats stats;
  std::vector<double> gradient_norms;
  std::vector<int> cg_iterations;
  std::vector<long> petsc_reductions;
  int projected_solves = 0;
  std::vector<double> q;
  double seconds = 0;
  ReductionCounters before, after;
  long pmpi_allreduces = 0;  // MPI_Allreduce calls of the step, ours and PETSc's
};

NewtonRun run_newton(Simulation<double>& sim, const Scene& scene, const char* solver,
                     const std::string& options = "") {
  SolverSpec spec = scene.solver;
  spec.method = "newton";
  spec.init = "position";
  spec.newton_solver = solver;
  spec.cg_tolerance = 1e-12;  // both linear solvers near round-off
  spec.petsc_options = options;
  NewtonRun run;
  Newton<double> newton(sim.problem(), spec);
  run.before = sim.reduction_counters();
  BodyState<double> state = sim.state();
  MPI_Barrier(MPI_COMM_WORLD);
  const long allreduces = testing::pmpi_allreduces();
  const double t0 = MPI_Wtime();
  run.stats = newton.step(state);
  double seconds = MPI_Wtime() - t0;
  run.pmpi_allreduces = testing::pmpi_allreduces() - allreduces;
  run.after = sim.reduction_counters();
  MPI_Allreduce(MPI_IN_PLACE, &seconds, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
  run.seconds = seconds;
  run.gradient_norms = newton.gradient_norms();
  run.cg_iterations = newton.cg_iterations();
  run.petsc_reductions = newton.petsc_reductions();
  run.projected_solves = newton.projected_solves();
  run.q.assign(state.q.begin(), state.q.end());
  return run;
}

void print_run(const char* solver, const NewtonRun& run) {
  if (world_rank() != 0) return;
  std::printf("%s: %d Newton iterations, %d halvings, %d projected, %.3f s, Krylov iterations:",
              solver, run.stats.iterations, run.stats.rollbacks, run.projected_solves, run.seconds);
  for (int it : run.cg_iterations) std::printf(" %d", it);
  std::printf("\n%s |g|/|g0|:", solver);
  for (double g : run.gradient_norms) std::printf(" %.3e", g / run.gradient_norms.front());
  std::printf("\n");
}

// Max over owned dofs of |a - b|, over all ranks.
double max_difference(const std::vector<double>& a, const std::vector<double>& b,
                      std::size_t owned) {
  double worst = 0;
  for (std::size_t k = 0; k < owned; ++k) worst = std::max(worst, std::abs(a[k] - b[k]));
  MPI_Allreduce(MPI_IN_PLACE, &worst, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
  return worst;
}

class NewtonPetscTest : public ::testing::Test {
 protected:
  void SetUp() override {
    scene_ = testing::small_helix_scene();
    mesh_ = build_scene_mesh(scene_.mesh);
    diagonal_ = testing::bounding_box_diagonal(mesh_);
  }
  // Same Newton iterations as CG and the same q to 1e-10 of the bounding box.
  void expect_equals_cg(const char* name, const std::string& options) {
    Simulation<double> sim(MPI_COMM_WORLD, scene_, mesh_);
    sim.set_positions(stretched_positions(mesh_));
    const NewtonRun cg = run_newton(sim, scene_, "cg");
    const NewtonRun petsc = run_newton(sim, scene_, "petsc", options);
    print_run("cg", cg);
    print_run(name, petsc);
    const std::size_t owned = 3 * static_cast<std::size_t>(sim.local_mesh().num_owned);
    const double worst = max_difference(petsc.q, cg.q, owned);
    const double moved = max_difference(petsc.q, sim.state().q, owned);
    if (world_rank() == 0)
      std::printf("%s: max |q_petsc - q_cg| = %.3e, moved %.3e (bbox diagonal %.3f)\n", name, worst,
                  moved, diagonal_);
    EXPECT_EQ(petsc.stats.iterations, cg.stats.iterations);
    EXPECT_EQ(petsc.projected_solves, cg.projected_solves);
    EXPECT_FALSE(petsc.stats.stalled);
    EXPECT_LE(petsc.gradient_norms.back(), 1e-10 * petsc.gradient_norms.front());
    EXPECT_GT(moved, 1e-3 * diagonal_);  // the step moved: equality is not trivial
    EXPECT_LE(worst, 1e-10 * diagonal_);
    // AMG: far fewer Krylov iterations than Jacobi CG.
    long cg_total = 0, petsc_total = 0;
    for (int it : cg.cg_iterations) cg_total += it;
    for (int it : petsc.cg_iterations) petsc_total += it;
    EXPECT_LT(petsc_total, cg_total);
  }
  Scene scene_;
  Mesh mesh_;
  double diagonal_ = 0;
};

// (a) The assembled matrix times x equals the distributed Hessian product,
// for the exact and the projected element Hessians, on every local vertex.
TEST_F(NewtonPetscTest, MatrixEqualsTheHessianProduct) {
  Simulation<double> sim(MPI_COMM_WORLD, scene_, mesh_);
  sim.set_positions(stretched_positions(mesh_));
  LocalProblem<double>& problem = sim.problem();
  HessianOperator<double> hessian(problem);
  NewtonPetsc<double> petsc(problem, hessian, scene_.solver);
  const std::size_t n = 3 * static_cast<std::size_t>(problem.num_vertices());
  const auto& fixed = problem.fixed_axes();
  auto held = [&](std::size_t dof) { return (fixed[dof / 3] >> (dof % 3)) & 1u; };
  // A pseudo-random direction, a function of the global dof (equal on every
  // sharer), 0 on held dofs (where apply() gives 0 and PETSc's identity row x).
  std::vector<double> x(n), ours(n), theirs(n);
  for (std::size_t k = 0; k < n; ++k) {
    const double id = 3.0 * problem.mesh().global_vertex[k / 3] + double(k % 3);
    x[k] = held(k) ? 0.0 : std::sin(12.9898 * id + 78.233) * 43758.5453;
    x[k] -= std::floor(x[k]) + 0.5;
  }
  for (std::size_t k = 0; k < n; ++k)
    if (held(k)) x[k] = 0.0;
  for (bool project : {false, true}) {
    hessian.assemble(sim.state().q.data(), project);
    hessian.apply(x.data(), ours.data());
    petsc.multiply(x.data(), theirs.data());
    double worst[2] = {0, 0};  // max |difference|, max |H x|
    for (std::size_t k = 0; k < n; ++k) {
      worst[0] = std::max(worst[0], std::abs(ours[k] - theirs[k]));
      worst[1] = std::max(worst[1], std::abs(ours[k]));
    }
    MPI_Allreduce(MPI_IN_PLACE, worst, 2, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
    if (world_rank() == 0)
      std::printf("%s Hessian: max |A x - H x| = %.3e, max |H x| = %.3e\n",
                  project ? "projected" : "exact", worst[0], worst[1]);
    EXPECT_GT(worst[1], 0.0);
    EXPECT_LE(worst[0], 1e-12 * worst[1]) << (project ? "projected" : "exact");
  }
}

// (b) CG + GAMG (the default) against our Jacobi CG.
TEST_F(NewtonPetscTest, GamgEqualsCgNewton) { expect_equals_cg("petsc gamg", ""); }

// Our collectives as documented (|g|^2 per iterate, g.dq per solve, one
// energy per line-search trial), PETSc's own on top: every MPI_Allreduce the
// step made beyond ours is PETSc's, and its own count is near that number.
TEST_F(NewtonPetscTest, CollectivesAreOursPlusPetscs) {
  Simulation<double> sim(MPI_COMM_WORLD, scene_, mesh_);
  sim.set_positions(stretched_positions(mesh_));
  const NewtonRun run = run_newton(sim, scene_, "petsc");
  const long solves = static_cast<long>(run.cg_iterations.size());
  ASSERT_EQ(run.petsc_reductions.size(), run.cg_iterations.size());
  const long dots = run.after.dot_allreduces - run.before.dot_allreduces;
  const long energies = run.after.allreduces - run.before.allreduces;
  EXPECT_EQ(dots, static_cast<long>(run.gradient_norms.size()) + solves);
  EXPECT_EQ(energies, run.stats.iterations + run.stats.rollbacks);
  EXPECT_EQ(run.after.root_gathers, run.before.root_gathers);
  long petsc = 0;
  for (long r : run.petsc_reductions) petsc += r;
  const long petsc_allreduces = run.pmpi_allreduces - dots - energies;
  if (world_rank() == 0)
    std::printf("%ld solves: MPI_Allreduce %ld = %ld ours + %ld PETSc's; PETSc counted %ld\n",
                solves, run.pmpi_allreduces, dots + energies, petsc_allreduces, petsc);
  int size = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  if (size == 1) {
    // PETSc still calls MPI_Allreduce on its one-rank communicator (no
    // communication), and counts none of them.
    EXPECT_EQ(petsc, 0);
  } else {
    // PETSc's own count (its log's "MPI Reductions") misses some of its
    // MPI_Allreduce calls and has some other collectives: near, not equal.
    EXPECT_GT(petsc_allreduces, 0);
    EXPECT_GT(petsc, petsc_allreduces / 2);
    EXPECT_LT(petsc, 2 * petsc_allreduces);
  }
}

// Compressed to 70% of its height the exact Hessian is indefinite: PETSc's
// CG reports it (or fails) and the iteration takes the projected Hessian.
TEST_F(NewtonPetscTest, FallsBackToTheProjectedHessianWhenIndefinite) {
  Simulation<double> sim(MPI_COMM_WORLD, scene_, mesh_);
  sim.set_positions(stretched_positions(mesh_, 0.7));
  const NewtonRun petsc = run_newton(sim, scene_, "petsc");
  print_run("compressed petsc", petsc);
  EXPECT_GE(petsc.projected_solves, 1);
  EXPECT_FALSE(petsc.stats.stalled);
  EXPECT_LE(petsc.gradient_norms.back(), 1e-10 * petsc.gradient_norms.front());
}

// The float instantiation converts to PETSc's doubles and lowers the gradient.
TEST_F(NewtonPetscTest, FloatLowersTheGradient) {
  Simulation<float> sim(MPI_COMM_WORLD, scene_, mesh_);
  sim.set_positions(stretched_positions(mesh_));
  SolverSpec spec = scene_.solver;
  spec.method = "newton";
  spec.init = "position";
  spec.newton_solver = "petsc";
  spec.cg_tolerance = 1e-6;
  spec.newton_iterations = 8;  // float's round-off floor is near 1e-6 |g0|
  Newton<float> newton(sim.problem(), spec);
  BodyState<float> state = sim.state();
  const StepStats stats = newton.step(state);
  const std::vector<double>& g = newton.gradient_norms();
  if (world_rank() == 0) {
    std::printf("float petsc: %d iterations, |g|/|g0|:", stats.iterations);
    for (double n : g) std::printf(" %.3e", n / g.front());
    std::printf("\n");
  }
  EXPECT_GE(stats.iterations, 1);
  EXPECT_LE(g.back(), 1e-3 * g.front());
}

// (c) CG + hypre BoomerAMG through the options database; last, as the option
// stays in PETSc's database until cleared.
#ifdef PETSC_HAVE_HYPRE
TEST_F(NewtonPetscTest, HypreEqualsCgNewton) {
  expect_equals_cg("petsc hypre", "-pc_type hypre");
  PetscOptionsClearValue(nullptr, "-pc_type");
}
#endif

}  // namespace
}  // namespace descent
