// The spectrum estimate of the automatic Chebyshev parameters against a
// dense eigensolver (issue 11), on a small box sagging under gravity (about
// 150 free dofs), in double and float, on 1 to 3 ranks:
//   - the engine's Lanczos run long enough to span the space finds the
//     extreme eigenvalues of D^-1 H (H the exact Hessian of eps, D the
//     iterations' diagonal) to round-off: the engine's Hessian product and
//     its D-inner products are right, and the same on every rank count;
//   - the stepper's own estimate (20 Lanczos steps and the translation
//     quotient) contains the top within the stated margin, lambda_max <= b
//     <= (1 + spectrum_margin) lambda_max, and its bottom a lies within a
//     factor of the true lambda_min.
#include <gtest/gtest.h>
#include <mpi.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstdio>

#include "app/scene_mesh.hpp"
#include "app/simulation.hpp"
#include "deformed_state.hpp"
#include "kernels/vertex.hpp"
#include "solver/iteration_engine.hpp"
#include "solver/methods/hessian_operator.hpp"
#include "solver/spectrum.hpp"
#include "world_rank.hpp"

namespace descent {
namespace {

using testing::deformed_state;
using testing::world_rank;

Scene sagging_box() {
  Scene scene;
  scene.mesh.generator = "box";
  scene.mesh.box.cells = {2, 4, 2};
  scene.mesh.box.size = {0.2, 0.4, 0.2};
  scene.material.young = 2e4;
  scene.material.poisson = 0.35;
  FixedRegion bottom;
  bottom.box_min = {-1.0, -1.0, -1.0};
  bottom.box_max = {1.0, 0.01, 1.0};
  scene.fixed.push_back(bottom);
  scene.gravity = {3.0, -9.81, 0.0};  // sideways too: a bent, not only squashed, box
  scene.time.dt = 1.0 / 30.0;
  scene.solver.preconditioner = "jacobi";  // the spectrum of D^-1 H
  return scene;
}

// The extreme eigenvalues of D^-1 H at the simulation's positions (1 rank),
// by a dense eigensolver of D^-1/2 H D^-1/2 on the free dofs.
RitzExtremes dense_extremes(Simulation<double>& sim) {
  LocalProblem<double>& problem = sim.problem();
  const std::vector<double> q = sim.state().q;
  const std::size_t n = q.size();
  const auto assembled = problem.elastic_gradient(q.data(), true);
  const VertexTerms<double> terms = problem.vertex_terms();
  std::vector<std::size_t> free;
  std::vector<double> d(n);
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t v = k / 3;
    d[k] = dof_diagonal(terms, problem.mass()[v], assembled.values[assembled.width * v + 3 + k % 3],
                        problem.diagonal_floor()[k]);
    if (!(problem.fixed_axes()[v] & (1u << (k % 3)))) free.push_back(k);
  }
  HessianOperator<double> hessian(problem);
  const Eigen::Index m = static_cast<Eigen::Index>(free.size());
  Eigen::MatrixXd s(m, m);
  std::vector<double> unit(n, 0.0), column(n);
  for (Eigen::Index j = 0; j < m; ++j) {
    unit[free[j]] = 1;
    hessian.product(q.data(), unit.data(), column.data());
    unit[free[j]] = 0;
    for (Eigen::Index i = 0; i < m; ++i)
      s(i, j) = column[free[i]] / std::sqrt(d[free[i]] * d[free[j]]);
  }
  const Eigen::MatrixXd symmetric = 0.5 * (s + s.transpose());
  const Eigen::VectorXd values =
      Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(symmetric).eigenvalues();
  return {values.minCoeff(), values.maxCoeff()};
}

// A deterministic vector by global dof (the same on every rank count).
double pseudo_random(std::uint64_t id) {
  std::uint64_t z = id * 0x9E3779B97F4A7C15ull + 7;
  z ^= z >> 29;
  z *= 0xBF58476D1CE4E5B9ull;
  z ^= z >> 32;
  return static_cast<double>(z % 2000001) / 1000000.0 - 1.0;
}

template <class Real>
LanczosRun engine_lanczos(Simulation<Real>& sim, int steps) {
  LocalProblem<Real>& problem = sim.problem();
  auto engine = make_host_engine(problem, problem.halo(), EngineOptions{});
  const auto staging = engine->staging();
  const auto& q = sim.state().q;
  const LocalMesh& mesh = sim.local_mesh();
  for (std::size_t k = 0; k < q.size(); ++k) {
    staging.q[k] = staging.y[k] = staging.qt[k] = q[k];
    staging.force[k] = 0;
    staging.vector[k] = static_cast<Real>(pseudo_random(3 * mesh.global_vertex[k / 3] + k % 3));
  }
  engine->begin_step(true, nullptr);
  engine->refresh_diagonal();
  return lanczos(*engine, problem, steps);
}

template <class Real>
void check_against_dense(double long_run_tolerance) {
  const Scene scene = sagging_box();
  const Mesh mesh = build_scene_mesh(scene.mesh);
  const std::vector<double> state = deformed_state(scene, mesh, 6);

  RitzExtremes dense;
  if (world_rank() == 0) {
    Simulation<double> reference(MPI_COMM_SELF, scene, mesh);
    reference.set_positions(state);
    dense = dense_extremes(reference);
  }
  MPI_Bcast(&dense, 2, MPI_DOUBLE, 0, MPI_COMM_WORLD);
  ASSERT_GT(dense.lowest, 0) << "the box's D^-1 H should be positive definite here";

  Simulation<Real> sim(MPI_COMM_WORLD, scene, mesh);
  sim.set_positions(state);
  // Steps past the dimension: the Krylov space is the whole space.
  const LanczosRun full = engine_lanczos(sim, 400);
  EXPECT_NEAR(full.ritz.highest, dense.highest, long_run_tolerance * dense.highest);
  EXPECT_NEAR(full.ritz.lowest, dense.lowest, long_run_tolerance * dense.highest);

  // The stepper's estimate at the same state (zero velocity: the guess is
  // the state itself), with the defaults.
  const StepStats step = sim.step();
  ASSERT_GT(step.spectrum_steps, 0);
  const double margin = scene.solver.spectrum_margin;
  EXPECT_GE(step.lambda_max, dense.highest) << "the top bound must contain lambda_max";
  EXPECT_LE(step.lambda_max, (1 + margin) * dense.highest * (1 + 10 * long_run_tolerance));
  EXPECT_GT(step.lambda_min, 0.2 * dense.lowest);
  EXPECT_LT(step.lambda_min, 5 * dense.lowest);
  if (world_rank() == 0)
    std::printf(
        "[ spectrum ] %s, %d rank(s): dense [%.6e, %.6f]; Lanczos %d steps [%.6e, %.6f]; "
        "stepper %d steps [%.4e, %.4f]\n",
        sizeof(Real) == 4 ? "float" : "double", testing::world_size(), dense.lowest, dense.highest,
        full.steps, full.ritz.lowest, full.ritz.highest, step.spectrum_steps, step.lambda_min,
        step.lambda_max);

  // Every rank count finds the same extremes: compare with one rank.
  double mine[2] = {full.ritz.lowest, full.ritz.highest};
  double first[2] = {mine[0], mine[1]};
  if (world_rank() == 0) {
    Simulation<Real> alone(MPI_COMM_SELF, scene, mesh);
    alone.set_positions(state);
    const LanczosRun one = engine_lanczos(alone, 400);
    first[0] = one.ritz.lowest;
    first[1] = one.ritz.highest;
  }
  MPI_Bcast(first, 2, MPI_DOUBLE, 0, MPI_COMM_WORLD);
  EXPECT_NEAR(mine[1], first[1], long_run_tolerance * first[1]);
  EXPECT_NEAR(mine[0], first[0], long_run_tolerance * first[1]);
}

TEST(Spectrum, LanczosAgainstADenseEigensolverInDouble) { check_against_dense<double>(1e-9); }

TEST(Spectrum, LanczosAgainstADenseEigensolverInFloat) { check_against_dense<float>(2e-4); }

}  // namespace
}  // namespace descent
