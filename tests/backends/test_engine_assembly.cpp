// The Chebyshev engine's two assemblies (solver/iteration_engine_impl.hpp:
// two streams, the packed shared-vertex exchange, blocks of iterations
// between checks, reductions in the execution) on the host: scatter
// (atomics) against gather on the same ranks, positions after 1 frame
// within 1e-9 of the bounding-box diagonal in double and 1e-4 in float,
// with and without model conversion, with moving fixed regions and loads;
// P ranks against 1 rank over 10 frames, shared vertices bitwise equal on
// all sharers; exactly one allreduce per energy check with fixed
// parameters; the memory report only for an engine on a device; other
// methods refused by the cuda backend. One thread's assembly in tet order
// against threads' gather: positions, gradients and Hessian products
// bitwise equal.
#include <gtest/gtest.h>
#include <mpi.h>
#include <omp.h>

#include <cmath>
#include <cstdio>
#include <cstring>

#include "app/scene_mesh.hpp"
#include "common/error.hpp"
#include "kernels/cpu/host_exec.hpp"
#include "solver/methods/hessian_operator.hpp"
#include "tests/backends/compare_runs.hpp"
#include "tests/mpi/small_scenes.hpp"
#include "tests/mpi/world_rank.hpp"

namespace descent {
namespace {

using testing::backend_of;
using testing::world_rank;
using testing::world_size;

// Scatter against gather assembly on the same ranks.
template <class Real>
void expect_scatter_matches_gather(const Scene& scene, int frames, double tolerance,
                                   const char* what) {
  const Mesh mesh = build_scene_mesh(scene.mesh);
  const auto cpu = testing::run_frames<Real>(
      MPI_COMM_WORLD, scene, mesh, backend_of(BackendKind::cpu, Assembly::gather), frames);
  const auto dev = testing::run_frames<Real>(
      MPI_COMM_WORLD, scene, mesh, backend_of(BackendKind::cpu, Assembly::scatter), frames);
  if (world_rank() != 0) return;
  const double diagonal = testing::bounding_box_diagonal(mesh);
  const double gap = testing::max_difference(cpu, dev);
  const double moved = testing::max_difference(cpu, mesh.positions);
  EXPECT_GT(moved, 1e-4 * diagonal) << "the scene should move in " << frames << " frame(s)";
  EXPECT_LE(gap, tolerance * diagonal) << what;
  std::printf(
      "[ scatter vs gather ] %s, %d rank(s): max |q_s - q_g| = %.3g (%.3g of diagonal %.3g)\n",
      what, world_size(), gap, gap / diagonal, diagonal);
}

TEST(EngineAssembly, ScatterDoubleOneFrameMatchesGather) {
  expect_scatter_matches_gather<double>(testing::small_helix_scene(), 1, 1e-9, "double, 1 frame");
  expect_scatter_matches_gather<double>(testing::fixed_chebyshev(testing::small_helix_scene()), 1,
                                        1e-9, "double, fixed parameters, 1 frame");
}

TEST(EngineAssembly, FloatOneFrameMatchesGather) {
  expect_scatter_matches_gather<float>(testing::small_helix_scene(), 1, 1e-4, "float, 1 frame");
}

// Conversion moves the energy within a step (both states re-evaluated at
// each check) and keeps per-tet state on the device.
TEST(EngineAssembly, ConversionFiveFramesMatchesGather) {
  Scene scene = testing::small_helix_scene();
  scene.material.conversion.enabled = true;
  scene.material.model = "stvk";
  expect_scatter_matches_gather<double>(scene, 5, 1e-9, "conversion, stvk, 5 frames");
}

// Blocks longer than the engine's first parameter buffer (checks every 96
// iterations) and phases of Chebyshev with their own rho.
TEST(EngineAssembly, LongBlocksAndPhasesMatchGather) {
  Scene scene = testing::fixed_chebyshev(testing::small_helix_scene());
  scene.solver.iterations = 192;
  scene.solver.check_interval = 96;
  scene.solver.phase_rho = {0.9, 0.96};
  scene.solver.phase_lengths = {40};
  expect_scatter_matches_gather<double>(scene, 1, 1e-9, "checks every 96, two phases");
}

// A box held at the bottom, twisted at the top and pulled sideways by a
// ramped surface load: moving fixed dofs and loads travel each step.
TEST(EngineAssembly, TwistedLoadedBoxMatchesGather) {
  Scene scene;
  scene.mesh.generator = "box";
  scene.mesh.box.cells = {3, 6, 3};
  scene.mesh.box.size = {0.3, 0.6, 0.3};
  scene.gravity = {0.0, -9.81, 0.0};
  scene.material.young = 2e5;
  FixedRegion bottom;
  bottom.box_min = {-1.0, -1.0, -1.0};
  bottom.box_max = {1.0, 0.01, 1.0};
  FixedRegion top = bottom;
  top.box_min[1] = 0.59;
  top.box_max[1] = 1.0;
  top.axes = "xz";
  top.motion.kind = "rotate";
  top.motion.centre = {0.15, 0.0, 0.15};
  top.motion.angular_velocity = 3.0;
  scene.fixed = {bottom, top};
  LoadRegion side;
  side.box_min = {0.29, 0.2, -1.0};
  side.box_max = {1.0, 0.4, 1.0};
  side.force = {5.0, 0.0, 2.0};
  side.ramp = 0.1;
  scene.loads = {side};
  scene.solver.iterations = 64;
  expect_scatter_matches_gather<double>(scene, 4, 1e-9, "twisted, loaded box, 4 frames");
}

// OpenMP threads for the rest of a scope.
struct Threads {
  int before = omp_get_max_threads();
  explicit Threads(int n) { omp_set_num_threads(n); }
  ~Threads() { omp_set_num_threads(before); }
};

// With one thread the host adds the element results to the vertex partials
// in tet order, with two it gathers them through the corner arrays
// (kernels/element_out.hpp): the same sums bit for bit. So are the engine's
// positions after 3 frames (fixed parameters and iterations: no reduction,
// whose order the threads change, decides anything) and the other methods'
// gradient, diagonal and Hessian products (LocalProblem, HessianOperator).
TEST(EngineAssembly, OneThreadInOrderEqualsThreadsGatherBitwise) {
  Scene scene = testing::fixed_chebyshev(testing::small_helix_scene());
  scene.solver.accuracy = 0;
  const Mesh mesh = build_scene_mesh(scene.mesh);
  std::vector<double> positions[2];
  for (int threads : {1, 2}) {
    Threads use(threads);
    ASSERT_EQ(HostExec().serial(), threads == 1);
    positions[threads - 1] = testing::run_frames<double>(
        MPI_COMM_WORLD, scene, mesh, backend_of(BackendKind::cpu, Assembly::gather), 3);
  }
  if (world_rank() == 0) {
    EXPECT_GT(testing::max_difference(positions[0], mesh.positions), 0.0);
    EXPECT_EQ(testing::max_difference(positions[0], positions[1]), 0.0);
  }

  Simulation<double> sim(MPI_COMM_WORLD, scene, mesh);
  sim.step();
  LocalProblem<double>& problem = sim.problem();
  const std::vector<double> q = sim.state().q;
  std::vector<double> p(q.size());
  for (std::size_t k = 0; k < p.size(); ++k)
    p[k] = std::sin(2.0 * problem.mesh().global_vertex[k / 3] + double(k % 3));
  std::vector<double> gradient[2], product[2], stored_product[2];
  for (int threads : {1, 2}) {
    Threads use(threads);
    const auto g = problem.elastic_gradient(q.data(), true);
    gradient[threads - 1].assign(g.values, g.values + 6 * problem.num_vertices());
    HessianOperator<double> hessian(problem);
    product[threads - 1].resize(q.size());
    hessian.product(q.data(), p.data(), product[threads - 1].data(), nullptr);
    hessian.assemble(q.data(), true);
    stored_product[threads - 1].resize(q.size());
    hessian.apply(p.data(), stored_product[threads - 1].data());
  }
  auto bitwise = [](const std::vector<double>& a, const std::vector<double>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
  };
  EXPECT_TRUE(bitwise(gradient[0], gradient[1])) << "gradient and diagonal";
  EXPECT_TRUE(bitwise(product[0], product[1])) << "matrix-free Hessian product";
  EXPECT_TRUE(bitwise(stored_product[0], stored_product[1])) << "stored Hessians' product";
}

TEST(EngineAssembly, RanksMatchOneRankAndSharersAgreeBitwise) {
  const Scene scene = testing::small_helix_scene();
  const Mesh mesh = build_scene_mesh(scene.mesh);
  constexpr int kFrames = 10;
  for (Assembly assembly : {Assembly::gather, Assembly::scatter}) {
    Simulation<double> sim(MPI_COMM_WORLD, scene, mesh, backend_of(BackendKind::cpu, assembly));
    for (int f = 1; f <= kFrames; ++f) {
      sim.step();
      ASSERT_EQ(testing::shared_mismatches(MPI_COMM_WORLD, sim), 0)
          << to_string(assembly) << ": shared vertices differ between sharers after frame " << f;
    }
    const auto got = testing::gather_positions(MPI_COMM_WORLD, sim, mesh.num_vertices());
    if (world_rank() != 0) continue;
    const auto want = testing::run_frames<double>(MPI_COMM_SELF, scene, mesh,
                                                  backend_of(BackendKind::cpu, assembly), kFrames);
    const double diagonal = testing::bounding_box_diagonal(mesh);
    const double gap = testing::max_difference(got, want);
    EXPECT_LE(gap, 1e-9 * diagonal) << to_string(assembly);
    std::printf("[ engine rank invariance ] %s, %d ranks vs 1, %d frames: max gap %.3g\n",
                to_string(assembly), world_size(), kFrames, gap);
  }
}

TEST(EngineAssembly, OneAllreducePerCheckAndNoDeviceMemoryReport) {
  Scene scene = testing::fixed_chebyshev(testing::small_helix_scene());
  scene.solver.check_interval = 8;
  const Mesh mesh = build_scene_mesh(scene.mesh);
  Simulation<double> sim(MPI_COMM_WORLD, scene, mesh, backend_of(BackendKind::cpu));
  for (int frame = 0; frame < 3; ++frame) {
    const long before = sim.reduction_counters().allreduces;
    const StepStats step = sim.step();
    ASSERT_EQ(step.iterations, scene.solver.iterations);
    EXPECT_EQ(sim.reduction_counters().allreduces - before,
              scene.solver.iterations / scene.solver.check_interval);
  }
  // The host engine uses the problem's memory; only a device's is reported.
  EXPECT_TRUE(sim.device_memory_report().empty()) << sim.device_memory_report();
  EXPECT_NE(sim.stepper_timing_report().find("energy checks"), std::string::npos);
}

TEST(EngineAssembly, OtherMethodsAskForTheCpuBackend) {
  Scene scene = testing::small_helix_scene();
  scene.solver.method = "gd";
  const Mesh mesh = build_scene_mesh(scene.mesh);
  try {
    Simulation<double> sim(MPI_COMM_WORLD, scene, mesh, backend_of(BackendKind::cuda));
    FAIL() << "a method other than chebyshev was accepted by the cuda backend";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--backend cpu"), std::string::npos) << e.what();
  }
  // The optimized initial guess runs on the host: refused on a device, not replaced.
  scene.solver.method = "chebyshev";
  scene.solver.init = "optimized";
  EXPECT_THROW(Simulation<double>(MPI_COMM_WORLD, scene, mesh, backend_of(BackendKind::cuda)),
               InputError);
}

// Backend selection: explicit choices are taken; `cuda` without a usable
// device is a clear error; `auto` follows what this process sees.
TEST(BackendChoice, FollowsRequestAndDevices) {
  std::string note;
  BackendRequest request;
  request.backend = "cpu";
  EXPECT_EQ(choose_backend(MPI_COMM_WORLD, request, &note).kind, BackendKind::cpu);
  request.assembly = "scatter";
  const BackendChoice scatter = choose_backend(MPI_COMM_WORLD, request, &note);
  EXPECT_EQ(scatter.kind, BackendKind::cpu);
  EXPECT_EQ(scatter.engine.assembly, Assembly::scatter);
  request.backend = "emulated";
  EXPECT_THROW(choose_backend(MPI_COMM_WORLD, request, &note), InputError);
  request.assembly = "sideways";
  EXPECT_THROW(choose_backend(MPI_COMM_WORLD, request, &note), InputError);

  request.assembly = "gather";
  request.backend = "auto";
  request.share_device = true;
  const CudaStatus status = cuda_status();
  const BackendChoice automatic = choose_backend(MPI_COMM_WORLD, request, &note);
  if (status.usable()) {
    EXPECT_EQ(automatic.kind, BackendKind::cuda);
  } else {
    EXPECT_EQ(automatic.kind, BackendKind::cpu);
    EXPECT_NE(note.find(status.why_none), std::string::npos) << note;
    request.backend = "cuda";
    try {
      choose_backend(MPI_COMM_WORLD, request, &note);
      FAIL() << "--backend cuda without a device was accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("no usable CUDA device"), std::string::npos) << e.what();
    }
  }
  EXPECT_NE(backend_report().find("backends: cpu"), std::string::npos);
}

}  // namespace
}  // namespace descent
