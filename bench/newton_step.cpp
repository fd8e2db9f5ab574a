// One Newton step, timed: the driver of bench/newton_step.sh.
//
//   mpiexec -n P newton_step_bench SCENE.toml REPEATS [key=value ...]
//
// Loads the scene with the overrides (as `descent run --set`), builds the
// simulation, constructs Newton (solver.method = "newton"; its set-up timed
// apart: the "ldlt" symbolic analysis, the "petsc" pattern) and takes the
// first time step from the scene's initial state REPEATS times, each from
// the same state, to |g| <= solver.newton_tolerance |g0|. Rank 0 prints one
// CSV line (header with --header as the only argument): the median step time
// (slowest rank), Newton iterations, Krylov iterations (CG, or PETSc's; 0 for
// ldlt), and the MPI_Allreduce calls of one step counted at the MPI
// boundary (PMPI: ours and PETSc's alike) plus the other collectives.
#include <mpi.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <vector>

#include "app/scene_mesh.hpp"
#include "app/simulation.hpp"
#include "io/scene.hpp"
#include "pmpi_counters.hpp"
#include "solver/methods/newton.hpp"
#include "solver/petsc/petsc_session.hpp"

namespace {

int run(int argc, char** argv) {
  using namespace descent;
  int rank = 0, ranks = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &ranks);
  if (argc == 2 && std::string(argv[1]) == "--header") {
    std::printf(
        "ranks,solver,tets,vertices,setup_s,step_s,newton_iterations,krylov_iterations,"
        "allreduces,other_collectives,final_gradient_ratio,repeats\n");
    return 0;
  }
  if (argc < 3) {
    if (rank == 0) std::fprintf(stderr, "usage: newton_step_bench SCENE REPEATS [key=value ...]\n");
    return 2;
  }
  const int repeats = std::max(1, std::atoi(argv[2]));
  std::vector<std::string> overrides(argv + 3, argv + argc);
  overrides.push_back("solver.method='newton'");
  const Scene scene = load_scene(argv[1], overrides);
  const Mesh mesh = build_scene_mesh(scene.mesh);
  Simulation<double> sim(MPI_COMM_WORLD, scene, mesh);

  MPI_Barrier(MPI_COMM_WORLD);
  double t0 = MPI_Wtime();
  Newton<double> newton(sim.problem(), scene.solver);
  double setup = MPI_Wtime() - t0;
  MPI_Allreduce(MPI_IN_PLACE, &setup, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);

  std::vector<double> seconds;
  int iterations = 0;
  long krylov = 0, allreduces = 0, others = 0;
  double ratio = 0;
  for (int r = 0; r < repeats; ++r) {
    BodyState<double> state = sim.state();
    MPI_Barrier(MPI_COMM_WORLD);
    const long a0 = testing::pmpi_allreduces(), o0 = testing::pmpi_other_collectives();
    t0 = MPI_Wtime();
    const StepStats stats = newton.step(state);
    double s = MPI_Wtime() - t0;
    allreduces = testing::pmpi_allreduces() - a0;
    others = testing::pmpi_other_collectives() - o0;
    MPI_Allreduce(MPI_IN_PLACE, &s, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
    seconds.push_back(s);
    iterations = stats.iterations;
    krylov = 0;
    for (int k : newton.cg_iterations()) krylov += k;
    const auto& g = newton.gradient_norms();
    ratio = g.back() / g.front();
  }
  std::sort(seconds.begin(), seconds.end());
  long tets = static_cast<long>(mesh.tets.size() / 4), vertices = mesh.num_vertices();
  if (rank == 0)
    std::printf("%d,%s,%ld,%ld,%.3f,%.3f,%d,%ld,%ld,%ld,%.3e,%d\n", ranks,
                scene.solver.newton_solver.c_str(), tets, vertices, setup,
                seconds[seconds.size() / 2], iterations, krylov, allreduces, others, ratio,
                repeats);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  int status = 1;
  try {
    status = run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "newton_step_bench: %s\n", e.what());
    MPI_Abort(MPI_COMM_WORLD, 1);
  }
  descent::finish_petsc();
  MPI_Finalize();
  return status;
}
