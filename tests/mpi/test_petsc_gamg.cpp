// The petsc_gamg preconditioner (solver/preconditioners/petsc_gamg.hpp) on the
// small helix stretched far from equilibrium: P^-1 is symmetric and positive
// definite, its result is bitwise equal on all sharers of a shared vertex and
// 0 on held dofs, PCG on the projected Hessian converges with it in a few
// iterations where Jacobi PCG needs many, a refresh refills the same matrix
// as a fresh set-up would, the "gamg_" options reach it, its collectives are
// counted, and float runs.
#include <gtest/gtest.h>
#include <mpi.h>
#include <petscsys.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>

#include "app/scene_mesh.hpp"
#include "app/simulation.hpp"
#include "pmpi_counters.hpp"
#include "small_scenes.hpp"
#include "solver/methods/hessian_operator.hpp"
#include "solver/preconditioners/petsc_gamg.hpp"
#include "world_rank.hpp"

namespace descent {
namespace {

using testing::world_rank;

template <class Real>
bool held(const LocalProblem<Real>& problem, std::size_t dof) {
  return (problem.fixed_axes()[dof / 3] >> (dof % 3)) & 1u;
}

// A pseudo-random vector in [-0.5, 0.5), a function of the global dof (the
// same on every sharer and every rank count), 0 on held dofs.
template <class Real>
std::vector<Real> random_vector(const LocalProblem<Real>& problem, double seed) {
  std::vector<Real> x(3 * static_cast<std::size_t>(problem.num_vertices()));
  for (std::size_t k = 0; k < x.size(); ++k) {
    const double id = 3.0 * problem.mesh().global_vertex[k / 3] + double(k % 3);
    double value = std::sin(12.9898 * id + seed) * 43758.5453;
    value -= std::floor(value) + 0.5;
    x[k] = held(problem, k) ? Real(0) : Real(value);
  }
  return x;
}

// a.b over all ranks' owned dofs, in double.
template <class Real>
double dot(const std::vector<Real>& a, const std::vector<Real>& b, const LocalMesh& mesh) {
  double sum = 0;
  for (std::size_t k = 0; k < 3 * static_cast<std::size_t>(mesh.num_owned); ++k)
    sum += double(a[k]) * double(b[k]);
  MPI_Allreduce(MPI_IN_PLACE, &sum, 1, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
  return sum;
}

// Shared vertices whose 3 values in z differ in any bit from a neighbour's
// copy (exchanged directly, in the order of the shared lists), summed over
// all ranks.
template <class Real>
int sharer_mismatches(const LocalMesh& mesh, const std::vector<Real>& z) {
  const std::size_t neighbours = mesh.neighbours.size();
  std::vector<std::vector<Real>> mine(neighbours), theirs(neighbours);
  std::vector<MPI_Request> requests(2 * neighbours);
  const int bytes = 3 * sizeof(Real);
  for (std::size_t n = 0; n < neighbours; ++n) {
    for (index_t v : mesh.shared_with[n])
      for (int i = 0; i < 3; ++i) mine[n].push_back(z[3 * v + i]);
    theirs[n].resize(mine[n].size());
    MPI_Irecv(theirs[n].data(), static_cast<int>(theirs[n].size()) * int(sizeof(Real)), MPI_BYTE,
              mesh.neighbours[n], 11, MPI_COMM_WORLD, &requests[n]);
  }
  for (std::size_t n = 0; n < neighbours; ++n)
    MPI_Isend(mine[n].data(), static_cast<int>(mine[n].size()) * int(sizeof(Real)), MPI_BYTE,
              mesh.neighbours[n], 11, MPI_COMM_WORLD, &requests[neighbours + n]);
  MPI_Waitall(static_cast<int>(requests.size()), requests.data(), MPI_STATUSES_IGNORE);
  int mismatches = 0;
  for (std::size_t n = 0; n < neighbours; ++n)
    for (std::size_t k = 0; k < mine[n].size(); k += 3)
      if (std::memcmp(&mine[n][k], &theirs[n][k], bytes) != 0) ++mismatches;
  MPI_Allreduce(MPI_IN_PLACE, &mismatches, 1, MPI_INT, MPI_SUM, MPI_COMM_WORLD);
  return mismatches;
}

// Iterations of PCG on H u = b from u = 0 (H the stored Hessian of
// `hessian`, dots over owned dofs) until |r| <= tolerance |b|, limit + 1 when
// `limit` do not reach it. Only the residual is tracked, not u.
template <class Real>
int pcg_iterations(HessianOperator<Real>& hessian, const LocalMesh& mesh,
                   const std::function<void(const Real*, Real*)>& precondition,
                   const std::vector<Real>& b, double tolerance, int limit) {
  const std::size_t n = b.size();
  std::vector<Real> r = b, z(n), p(n), hp(n);
  precondition(r.data(), z.data());
  p = z;
  double rz = dot(r, z, mesh);
  const double stop = tolerance * std::sqrt(dot(b, b, mesh));
  for (int it = 1; it <= limit; ++it) {
    hessian.apply(p.data(), hp.data());
    const double alpha = rz / dot(p, hp, mesh);
    for (std::size_t k = 0; k < n; ++k) r[k] -= Real(alpha) * hp[k];
    if (std::sqrt(dot(r, r, mesh)) <= stop) return it;
    precondition(r.data(), z.data());
    const double rz_next = dot(r, z, mesh);
    for (std::size_t k = 0; k < n; ++k) p[k] = z[k] + Real(rz_next / rz) * p[k];
    rz = rz_next;
  }
  return limit + 1;
}

class PetscGamgTest : public ::testing::Test {
 protected:
  void SetUp() override {
    scene_ = testing::small_helix_scene();
    mesh_ = build_scene_mesh(scene_.mesh);
  }
  Scene scene_;
  Mesh mesh_;
};

// (a) x.P^-1 y = y.P^-1 x, (b) x.P^-1 x > 0, (c) z bitwise equal on all
// sharers and 0 on held dofs; the stats and the one-line description.
template <class Real>
void expect_symmetric_positive_consistent(const Scene& scene, const Mesh& mesh,
                                          double symmetry_tolerance) {
  Simulation<Real> sim(MPI_COMM_WORLD, scene, mesh);
  sim.set_positions(testing::stretched_positions(mesh));
  LocalProblem<Real>& problem = sim.problem();
  std::unique_ptr<Preconditioner<Real>> gamg =
      make_petsc_gamg_preconditioner(problem, scene.solver);
  gamg->refresh(sim.state().q.data());
  const std::vector<Real> x = random_vector(problem, 78.233), y = random_vector(problem, 11.1);
  std::vector<Real> px(x.size()), py(y.size());
  gamg->apply(x.data(), px.data());
  gamg->apply(y.data(), py.data());
  const LocalMesh& local = sim.local_mesh();
  const double xpy = dot(x, py, local), ypx = dot(y, px, local);
  const double xpx = dot(x, px, local), ypy = dot(y, py, local);
  const double asymmetry = std::abs(xpy - ypx) / std::sqrt(xpx * ypy);
  int held_nonzero = 0;
  for (std::size_t k = 0; k < px.size(); ++k)
    if (held(problem, k) && (px[k] != Real(0) || py[k] != Real(0))) ++held_nonzero;
  MPI_Allreduce(MPI_IN_PLACE, &held_nonzero, 1, MPI_INT, MPI_SUM, MPI_COMM_WORLD);
  const PreconditionerStats stats = gamg->stats();
  if (world_rank() == 0)
    std::printf(
        "%s\nx.Py %.17g y.Px %.17g |x.Py - y.Px|/sqrt(x.Px y.Py) %.3e, x.Px %.6e, "
        "y.Py %.6e; refresh %.3f s, apply %.4f s, %zu bytes, %ld PETSc allreduces\n",
        gamg->describe().c_str(), xpy, ypx, asymmetry, xpx, ypy, stats.refresh_seconds,
        stats.apply_seconds / 2, stats.memory_bytes, stats.allreduces);
  EXPECT_LE(asymmetry, symmetry_tolerance);
  EXPECT_GT(xpx, 0.0);
  EXPECT_GT(ypy, 0.0);
  EXPECT_EQ(sharer_mismatches(local, px), 0);
  EXPECT_EQ(sharer_mismatches(local, py), 0);
  EXPECT_EQ(held_nonzero, 0);

  EXPECT_EQ(stats.refreshes, 1);
  EXPECT_EQ(stats.applications, 2);
  EXPECT_GT(stats.memory_bytes, 0u);
  ASSERT_GE(stats.level_dofs.size(), 2u);
  EXPECT_EQ(stats.level_dofs.front(), 3 * static_cast<long long>(mesh.num_vertices()));
  for (std::size_t l = 1; l < stats.level_dofs.size(); ++l)
    EXPECT_LT(stats.level_dofs[l], stats.level_dofs[l - 1]);
  EXPECT_NE(gamg->describe().find("gamg, " + std::to_string(stats.level_dofs.size()) + " levels"),
            std::string::npos)
      << gamg->describe();
}

TEST_F(PetscGamgTest, SymmetricPositiveAndEqualOnSharers) {
  expect_symmetric_positive_consistent<double>(scene_, mesh_, 1e-10);
}

// Float converts on the way in and out of PETSc's doubles: symmetric to
// float's round-off.
TEST_F(PetscGamgTest, FloatSymmetricPositiveAndEqualOnSharers) {
  expect_symmetric_positive_consistent<float>(scene_, mesh_, 1e-6);
}

// (d) PCG on the projected Hessian at the stretched state to 1e-6: a few
// V-cycles against many Jacobi iterations.
TEST_F(PetscGamgTest, PcgConvergesInFewIterations) {
  Simulation<double> sim(MPI_COMM_WORLD, scene_, mesh_);
  sim.set_positions(testing::stretched_positions(mesh_));
  LocalProblem<double>& problem = sim.problem();
  const double* q = sim.state().q.data();
  PetscGamgPreconditioner<double> gamg(problem, scene_.solver);
  gamg.refresh(q);
  HessianOperator<double> hessian(problem);
  hessian.assemble(q, true);
  const std::vector<double> b = random_vector(problem, 5.5);
  const std::vector<double>& diagonal = hessian.diagonal();
  const int with_gamg = pcg_iterations<double>(
      hessian, sim.local_mesh(), [&](const double* r, double* z) { gamg.apply(r, z); }, b, 1e-6,
      1000);
  const int with_jacobi = pcg_iterations<double>(
      hessian, sim.local_mesh(),
      [&](const double* r, double* z) {
        for (std::size_t k = 0; k < b.size(); ++k) z[k] = r[k] / diagonal[k];
      },
      b, 1e-6, 1000);
  if (world_rank() == 0)
    std::printf("PCG to 1e-6: %d iterations with petsc_gamg, %d with Jacobi\n", with_gamg,
                with_jacobi);
  EXPECT_LT(with_gamg, 30);
  EXPECT_LT(4 * with_gamg, with_jacobi);
}

// A second refresh refills the matrix built for the first: P^-1 at the
// stretched state after a refresh at rest equals P^-1 of a fresh set-up there.
TEST_F(PetscGamgTest, RefreshEqualsAFreshSetUp) {
  Simulation<double> sim(MPI_COMM_WORLD, scene_, mesh_);
  LocalProblem<double>& problem = sim.problem();
  const std::vector<double> rest = sim.state().q;
  sim.set_positions(testing::stretched_positions(mesh_));
  const double* q = sim.state().q.data();
  PetscGamgPreconditioner<double> refreshed(problem, scene_.solver), fresh(problem, scene_.solver);
  refreshed.refresh(rest.data());
  refreshed.refresh(q);
  fresh.refresh(q);
  const std::vector<double> x = random_vector(problem, 3.3);
  std::vector<double> a(x.size()), b(x.size());
  refreshed.apply(x.data(), a.data());
  fresh.apply(x.data(), b.data());
  double worst[2] = {0, 0};  // max |a - b|, max |b|
  for (std::size_t k = 0; k < x.size(); ++k) {
    worst[0] = std::max(worst[0], std::abs(a[k] - b[k]));
    worst[1] = std::max(worst[1], std::abs(b[k]));
  }
  MPI_Allreduce(MPI_IN_PLACE, worst, 2, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
  if (world_rank() == 0)
    std::printf("refreshed twice vs fresh: max |difference| %.3e of max %.3e\n", worst[0],
                worst[1]);
  EXPECT_EQ(refreshed.stats().refreshes, 2);
  EXPECT_GT(worst[1], 0.0);
  EXPECT_LE(worst[0], 1e-12 * worst[1]);
}

// PETSc's MPI_Allreduce calls per refresh and per apply, at the MPI boundary
// (PMPI), against the count stats() takes from PETSc's log.
TEST_F(PetscGamgTest, CollectivesArePetscsOwn) {
  Simulation<double> sim(MPI_COMM_WORLD, scene_, mesh_);
  sim.set_positions(testing::stretched_positions(mesh_));
  LocalProblem<double>& problem = sim.problem();
  PetscGamgPreconditioner<double> gamg(problem, scene_.solver);
  const std::vector<double> x = random_vector(problem, 9.9);
  std::vector<double> z(x.size());
  const long before = testing::pmpi_allreduces();
  gamg.refresh(sim.state().q.data());
  const long refresh = testing::pmpi_allreduces() - before;
  const long counted = gamg.stats().allreduces;
  const int applications = 10;
  for (int i = 0; i < applications; ++i) gamg.apply(x.data(), z.data());
  const long apply = testing::pmpi_allreduces() - before - refresh;
  const long apply_counted = gamg.stats().allreduces - counted;
  if (world_rank() == 0)
    std::printf("MPI_Allreduce: refresh %ld (PETSc counted %ld), %d applies %ld (counted %ld)\n",
                refresh, counted, applications, apply, apply_counted);
  if (testing::world_size() == 1) {
    EXPECT_EQ(counted, 0);  // PETSc counts none on one rank
  } else {
    // PETSc's own count misses some of its MPI_Allreduce calls and counts
    // its MPI_Bcast calls too: near, not equal.
    EXPECT_GT(counted, refresh / 2);
    EXPECT_LT(counted, 2 * refresh);
  }
  // refresh() did the set-up PETSc leaves to the first application.
  EXPECT_EQ(apply, 0);
  EXPECT_EQ(apply_counted, 0);
}

// The options database with the prefix "gamg_" reaches the preconditioner
// (last: the option stays in PETSc's database until cleared).
TEST_F(PetscGamgTest, GamgPrefixedOptionsReachIt) {
  Simulation<double> sim(MPI_COMM_WORLD, scene_, mesh_);
  SolverSpec spec = scene_.solver;
  spec.petsc_options = "-gamg_pc_mg_levels 2";
  PetscGamgPreconditioner<double> gamg(sim.problem(), spec);
  gamg.refresh(sim.state().q.data());
  PetscOptionsClearValue(nullptr, "-gamg_pc_mg_levels");
  if (world_rank() == 0) std::printf("%s\n", gamg.describe().c_str());
  EXPECT_EQ(gamg.stats().level_dofs.size(), 2u);
}

}  // namespace
}  // namespace descent
