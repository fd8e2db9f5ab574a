// The multilevel preconditioner (solver/preconditioners/multilevel/) on a
// sagging box, on 1 to 4 ranks:
//   - the V-cycle is symmetric and positive definite: x^T P^-1 y =
//     y^T P^-1 x and x^T P^-1 x > 0 for vectors drawn by global dof id;
//   - the hierarchy (unknowns per level) and P^-1 r are those of one rank,
//     the latter to round-off, and shared vertices hold bitwise equal values
//     on all sharers, held dofs 0;
//   - on one rank, the spectrum of P^-1 A (A the operator the V-cycle is
//     built on, dense) lies in (0, 1]: with exact Galerkin coarse operators
//     and an exact coarsest solve the V-cycle's error propagator is an
//     A-orthogonal projection between two contractions; and the Chebyshev
//     stepper's estimate [a, b] of the spectrum of P^-1 H (H the exact
//     Hessian) holds its top and finds its bottom;
//   - the Chebyshev stepper's iterates with P^-1 are those of one rank;
//   - on a box refined twice (8x the unknowns each time) the iterations a
//     step needs to a fixed accuracy grow by at most 1.3x.
#include <gtest/gtest.h>
#include <mpi.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstdio>

#include "app/scene_mesh.hpp"
#include "app/simulation.hpp"
#include "deformed_state.hpp"
#include "kernels/cpu/host_exec.hpp"
#include "solver/methods/hessian_operator.hpp"
#include "solver/preconditioners/multilevel/multilevel_impl.hpp"
#include "world_rank.hpp"

namespace descent {
namespace {

using testing::deformed_state;
using testing::world_rank;

Scene sagging_box(int cells) {
  Scene scene;
  scene.mesh.generator = "box";
  scene.mesh.box.cells = {cells, 2 * cells, cells};
  scene.mesh.box.size = {0.2, 0.4, 0.2};
  scene.material.young = 2e5;
  scene.material.poisson = 0.35;
  FixedRegion bottom;
  bottom.box_min = {-1.0, -1.0, -1.0};
  bottom.box_max = {1.0, 0.01, 1.0};
  scene.fixed.push_back(bottom);
  scene.gravity = {3.0, -9.81, 0.0};
  scene.time.dt = 1.0 / 30.0;
  scene.solver.preconditioner = "multilevel";
  scene.solver.multilevel_cell = 2.0;
  scene.solver.multilevel_coarse_size = 60;
  return scene;
}

double pseudo_random(std::uint64_t id) {
  std::uint64_t z = id * 0x9E3779B97F4A7C15ull + 7;
  z ^= z >> 29;
  z *= 0xBF58476D1CE4E5B9ull;
  z ^= z >> 32;
  return static_cast<double>(z % 2000001) / 1000000.0 - 1.0;
}

// A vector drawn by global dof id (seed), 0 on held dofs.
std::vector<double> draw(const LocalProblem<double>& problem, std::uint64_t seed) {
  const LocalMesh& mesh = problem.mesh();
  std::vector<double> x(3 * static_cast<std::size_t>(mesh.num_vertices()));
  for (std::size_t k = 0; k < x.size(); ++k) {
    const bool held = problem.fixed_axes()[k / 3] >> (k % 3) & 1u;
    x[k] = held ? 0.0 : pseudo_random(seed + 3 * mesh.global_vertex[k / 3] + k % 3);
  }
  return x;
}

double dot(const LocalProblem<double>& problem, const std::vector<double>& a,
           const std::vector<double>& b) {
  double sum = 0;
  for (index_t k = 0; k < 3 * problem.mesh().num_owned; ++k) sum += a[k] * b[k];
  MPI_Allreduce(MPI_IN_PLACE, &sum, 1, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
  return sum;
}

// z by global dof, from every rank's owned vertices.
std::vector<double> by_global_id(const LocalMesh& mesh, const std::vector<double>& z) {
  std::vector<double> out(3 * static_cast<std::size_t>(mesh.num_global_vertices), 0.0);
  for (index_t v = 0; v < mesh.num_owned; ++v)
    for (int i = 0; i < 3; ++i) out[3 * mesh.global_vertex[v] + i] = z[3 * v + i];
  MPI_Allreduce(MPI_IN_PLACE, out.data(), static_cast<int>(out.size()), MPI_DOUBLE, MPI_SUM,
                MPI_COMM_WORLD);
  return out;
}

TEST(Multilevel, VcycleIsSymmetricPositiveDefiniteAndTheSameOnEveryRankCount) {
  const Scene scene = sagging_box(4);
  const Mesh mesh = build_scene_mesh(scene.mesh);
  const std::vector<double> state = deformed_state(scene, mesh, 4);

  Simulation<double> sim(MPI_COMM_WORLD, scene, mesh);
  sim.set_positions(state);
  LocalProblem<double>& problem = sim.problem();
  HostExec exec;
  MultilevelPreconditioner<HostExec, double> p(exec, problem, scene.solver);
  p.refresh(sim.state().q.data());
  const auto& unknowns = p.hierarchy().global_unknowns;
  ASSERT_GE(unknowns.size(), 3u) << "the test wants a V-cycle of three levels or more";

  const std::vector<double> x = draw(problem, 11), y = draw(problem, 977);
  std::vector<double> px(x.size()), py(y.size());
  p.apply(x.data(), px.data());
  p.apply(y.data(), py.data());
  const double xpy = dot(problem, x, py), ypx = dot(problem, y, px), xpx = dot(problem, x, px);
  EXPECT_NEAR(xpy, ypx, 1e-11 * std::sqrt(xpx * dot(problem, y, py)));
  EXPECT_GT(xpx, 0);
  for (std::size_t k = 0; k < px.size(); ++k)
    if (problem.fixed_axes()[k / 3] >> (k % 3) & 1u) {
      EXPECT_EQ(px[k], 0.0) << "held dof " << k;
    }

  // Shared vertices: every sharer holds the same bits (owners' values
  // broadcast by global id against each rank's own).
  const LocalMesh& local = problem.mesh();
  const std::vector<double> global = by_global_id(local, px);
  for (index_t v = local.num_interior; v < local.num_vertices(); ++v)
    for (int i = 0; i < 3; ++i)
      EXPECT_EQ(px[3 * v + i], global[3 * local.global_vertex[v] + i]) << "shared vertex " << v;

  // One rank's hierarchy and result.
  std::vector<long long> one_unknowns(unknowns.size() + 1, 0);
  std::vector<double> one(global.size(), 0.0);
  if (world_rank() == 0) {
    Simulation<double> alone(MPI_COMM_SELF, scene, mesh);
    alone.set_positions(state);
    HostExec exec1;
    MultilevelPreconditioner<HostExec, double> p1(exec1, alone.problem(), scene.solver);
    p1.refresh(alone.state().q.data());
    const auto& u1 = p1.hierarchy().global_unknowns;
    one_unknowns[0] = static_cast<long long>(u1.size());
    std::copy(u1.begin(), u1.begin() + std::min(u1.size(), unknowns.size()),
              one_unknowns.begin() + 1);
    const std::vector<double> x1 = draw(alone.problem(), 11);
    std::vector<double> z1(x1.size());
    p1.apply(x1.data(), z1.data());
    const LocalMesh& m1 = alone.local_mesh();
    for (index_t v = 0; v < m1.num_vertices(); ++v)
      for (int i = 0; i < 3; ++i) one[3 * m1.global_vertex[v] + i] = z1[3 * v + i];
    std::printf("[ multilevel ] %d rank(s): unknowns per level", testing::world_size());
    for (long long u : u1) std::printf(" %lld", u);
    std::printf("\n");
  }
  MPI_Bcast(one_unknowns.data(), static_cast<int>(one_unknowns.size()), MPI_LONG_LONG, 0,
            MPI_COMM_WORLD);
  MPI_Bcast(one.data(), static_cast<int>(one.size()), MPI_DOUBLE, 0, MPI_COMM_WORLD);
  ASSERT_EQ(one_unknowns[0], static_cast<long long>(unknowns.size()));
  for (std::size_t l = 0; l < unknowns.size(); ++l) EXPECT_EQ(unknowns[l], one_unknowns[l + 1]);
  double scale = 0, worst = 0;
  for (std::size_t k = 0; k < one.size(); ++k) {
    scale = std::max(scale, std::abs(one[k]));
    worst = std::max(worst, std::abs(global[k] - one[k]));
  }
  EXPECT_LE(worst, 1e-10 * scale) << "P^-1 r differs from one rank's";
}

// The columns of op applied to the unit vectors of the free dofs, on the
// free dofs: a dense matrix.
template <class Op>
Eigen::MatrixXd dense(const LocalProblem<double>& problem, const std::vector<std::size_t>& free,
                      Op&& op) {
  const std::size_t n = 3 * static_cast<std::size_t>(problem.mesh().num_vertices());
  const Eigen::Index m = static_cast<Eigen::Index>(free.size());
  Eigen::MatrixXd a(m, m);
  std::vector<double> unit(n, 0.0), column(n);
  for (Eigen::Index j = 0; j < m; ++j) {
    unit[free[j]] = 1;
    op(unit.data(), column.data());
    unit[free[j]] = 0;
    for (Eigen::Index i = 0; i < m; ++i) a(i, j) = column[free[i]];
  }
  return 0.5 * (a + a.transpose());
}

// The eigenvalues of B A for SPD B and symmetric A: those of L^T A L, B = L L^T.
Eigen::VectorXd product_spectrum(const Eigen::MatrixXd& b, const Eigen::MatrixXd& a) {
  const Eigen::MatrixXd l = Eigen::LLT<Eigen::MatrixXd>(b).matrixL();
  return Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(l.transpose() * a * l).eigenvalues();
}

TEST(Multilevel, DenseSpectrumLiesInTheTheoryAndInTheEstimate) {
  if (world_rank() != 0) return;  // one rank: dense matrices
  Scene scene = sagging_box(3);
  scene.solver.multilevel_coarse_size = 30;
  const Mesh mesh = build_scene_mesh(scene.mesh);
  const std::vector<double> state = deformed_state(scene, mesh, 6);
  Simulation<double> sim(MPI_COMM_SELF, scene, mesh);
  sim.set_positions(state);
  LocalProblem<double>& problem = sim.problem();
  const std::vector<double> q = sim.state().q;
  std::vector<std::size_t> free;
  for (std::size_t k = 0; k < q.size(); ++k)
    if (!(problem.fixed_axes()[k / 3] >> (k % 3) & 1u)) free.push_back(k);

  HostExec exec;
  MultilevelPreconditioner<HostExec, double> p(exec, problem, scene.solver);
  p.refresh(q.data());
  ASSERT_GE(p.hierarchy().levels.size(), 2u);
  const Eigen::MatrixXd b =
      dense(problem, free, [&](const double* x, double* y) { p.apply(x, y); });
  HessianOperator<double> hessian(problem);
  hessian.assemble(q.data(), true);
  const Eigen::MatrixXd projected =
      dense(problem, free, [&](const double* x, double* y) { hessian.apply(x, y); });
  const Eigen::MatrixXd exact =
      dense(problem, free, [&](const double* x, double* y) { hessian.product(q.data(), x, y); });
  const Eigen::VectorXd theory = product_spectrum(b, projected);
  const Eigen::VectorXd spectrum = product_spectrum(b, exact);
  EXPECT_GT(theory.minCoeff(), 0);
  EXPECT_LE(theory.maxCoeff(), 1 + 1e-9) << "the V-cycle is no contraction in the A norm";

  // The stepper's estimate at the same state (zero velocity: the guess is
  // the state, where it refreshes P^-1 as above).
  const StepStats step = sim.step();
  ASSERT_GT(step.spectrum_steps, 0);
  const double margin = scene.solver.spectrum_margin;
  EXPECT_GE(step.lambda_max, spectrum.maxCoeff()) << "the top bound must contain lambda_max";
  EXPECT_LE(step.lambda_max, (1 + margin) * spectrum.maxCoeff() * (1 + 1e-6));
  EXPECT_GE(step.lambda_min, 0.999 * spectrum.minCoeff()) << "Lanczos approaches from above";
  EXPECT_LT(step.lambda_min, 2 * spectrum.minCoeff());
  std::printf(
      "[ multilevel ] P^-1 A (projected) in [%.4f, %.6f]; P^-1 H (exact) in [%.4f, %.4f], "
      "kappa %.1f; the stepper's estimate [%.4f, %.4f] (%d Lanczos steps)\n",
      theory.minCoeff(), theory.maxCoeff(), spectrum.minCoeff(), spectrum.maxCoeff(),
      spectrum.maxCoeff() / spectrum.minCoeff(), step.lambda_min, step.lambda_max,
      step.spectrum_steps);
}

TEST(Multilevel, ChebyshevIteratesAreThoseOfOneRank) {
  Scene scene = sagging_box(4);
  scene.solver.accuracy = 0;
  scene.solver.iterations = 24;
  const Mesh mesh = build_scene_mesh(scene.mesh);
  Simulation<double> sim(MPI_COMM_WORLD, scene, mesh);
  for (int f = 0; f < 3; ++f) sim.step();
  std::vector<double> one(3 * static_cast<std::size_t>(mesh.num_vertices()), 0.0);
  if (world_rank() == 0) {
    Simulation<double> alone(MPI_COMM_SELF, scene, mesh);
    for (int f = 0; f < 3; ++f) alone.step();
    const LocalMesh& m1 = alone.local_mesh();
    for (index_t v = 0; v < m1.num_vertices(); ++v)
      for (int i = 0; i < 3; ++i) one[3 * m1.global_vertex[v] + i] = alone.state().q[3 * v + i];
  }
  MPI_Bcast(one.data(), static_cast<int>(one.size()), MPI_DOUBLE, 0, MPI_COMM_WORLD);
  const LocalMesh& local = sim.local_mesh();
  double worst = 0;
  for (index_t v = 0; v < local.num_vertices(); ++v)
    for (int i = 0; i < 3; ++i)
      worst =
          std::max(worst, std::abs(sim.state().q[3 * v + i] - one[3 * local.global_vertex[v] + i]));
  MPI_Allreduce(MPI_IN_PLACE, &worst, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
  if (world_rank() == 0)
    std::printf("[ multilevel ] %d rank(s): positions after 3 steps within %.2e m of one rank's\n",
                testing::world_size(), worst);
  EXPECT_LE(worst, 1e-12) << "the box is 0.4 m tall";
}

// Iterations of one step from rest to a relative error of 1e-5 (checked
// every iteration), the box refined `refinement` times from 2 x 4 x 2 cells.
int iterations_to_accuracy(int refinement) {
  Scene scene = sagging_box(2 << refinement);
  scene.material.young = 2e6;  // stiff enough that Jacobi would need many
  scene.solver.accuracy = 1e-5;
  scene.solver.iterations = 500;
  scene.solver.check_interval = 1;
  scene.solver.multilevel_coarse_size = 24;
  const Mesh mesh = build_scene_mesh(scene.mesh);
  Simulation<double> sim(MPI_COMM_WORLD, scene, mesh);
  return sim.step().iterations;
}

TEST(Multilevel, IterationsHardlyGrowUnderRefinement) {
  const int coarse = iterations_to_accuracy(0), middle = iterations_to_accuracy(1),
            fine = iterations_to_accuracy(2);
  if (world_rank() == 0)
    std::printf("[ multilevel ] iterations to e <= 1e-5 on 2x4x2, 4x8x4, 8x16x8 cells: %d %d %d\n",
                coarse, middle, fine);
  EXPECT_LE(fine, 1.3 * coarse);
  EXPECT_LE(middle, 1.3 * coarse);
}

}  // namespace
}  // namespace descent
