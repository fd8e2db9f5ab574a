// The device stepper's algorithm (backends/device_engine_impl.hpp: two
// streams, the packed shared-vertex exchange, blocks of iterations between
// checks, device reductions) run on the host execution, against the CPU
// stepper on the same ranks: positions after 1 frame within 1e-9 of the
// bounding-box diagonal in double and 1e-4 in float, for gather and scatter
// assembly, with and without model conversion, with moving fixed regions and
// loads; P ranks against 1 rank over
// 10 frames, shared vertices bitwise equal on all sharers; and still exactly
// one allreduce per energy check.
#include <gtest/gtest.h>
#include <mpi.h>

#include <cstdio>

#include "app/scene_mesh.hpp"
#include "common/error.hpp"
#include "tests/backends/compare_runs.hpp"
#include "tests/mpi/small_scenes.hpp"

namespace descent {
namespace {

using testing::backend_of;

int world_rank() {
  int r = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &r);
  return r;
}
int world_size() {
  int s = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &s);
  return s;
}

// The emulated device stepper against the CPU stepper on the same ranks.
template <class Real>
void expect_matches_cpu(const Scene& scene, Assembly assembly, int frames, double tolerance,
                        const char* what) {
  const Mesh mesh = build_scene_mesh(scene.mesh);
  const auto cpu =
      testing::run_frames<Real>(MPI_COMM_WORLD, scene, mesh, backend_of(BackendKind::cpu), frames);
  const auto dev = testing::run_frames<Real>(MPI_COMM_WORLD, scene, mesh,
                                             backend_of(BackendKind::emulated, assembly), frames);
  if (world_rank() != 0) return;
  const double diagonal = testing::bounding_box_diagonal(mesh);
  const double gap = testing::max_difference(cpu, dev);
  const double moved = testing::max_difference(cpu, mesh.positions);
  EXPECT_GT(moved, 1e-4 * diagonal) << "the scene should move in " << frames << " frame(s)";
  EXPECT_LE(gap, tolerance * diagonal) << what;
  std::printf(
      "[ device vs cpu ] %s, %d rank(s): max |q_dev - q_cpu| = %.3g (%.3g of diagonal %.3g)\n",
      what, world_size(), gap, gap / diagonal, diagonal);
}

TEST(DeviceStepper, GatherDoubleOneFrameMatchesCpu) {
  expect_matches_cpu<double>(testing::small_helix_scene(), Assembly::gather, 1, 1e-9,
                             "gather, double, 1 frame");
}

TEST(DeviceStepper, ScatterDoubleOneFrameMatchesCpu) {
  expect_matches_cpu<double>(testing::small_helix_scene(), Assembly::scatter, 1, 1e-9,
                             "scatter, double, 1 frame");
}

TEST(DeviceStepper, FloatOneFrameMatchesCpu) {
  expect_matches_cpu<float>(testing::small_helix_scene(), Assembly::gather, 1, 1e-4,
                            "gather, float, 1 frame");
  expect_matches_cpu<float>(testing::small_helix_scene(), Assembly::scatter, 1, 1e-4,
                            "scatter, float, 1 frame");
}

// Conversion moves the energy within a step (both states re-evaluated at
// each check) and keeps per-tet state on the device.
TEST(DeviceStepper, ConversionFiveFramesMatchesCpu) {
  Scene scene = testing::small_helix_scene();
  scene.material.conversion.enabled = true;
  scene.material.model = "stvk";
  expect_matches_cpu<double>(scene, Assembly::gather, 5, 1e-9, "conversion, stvk, 5 frames");
}

// Blocks longer than the engine's first parameter buffer (checks every 96
// iterations) and phases of Chebyshev with their own rho.
TEST(DeviceStepper, LongBlocksAndPhasesMatchCpu) {
  Scene scene = testing::small_helix_scene();
  scene.solver.iterations = 192;
  scene.solver.check_interval = 96;
  scene.solver.phase_rho = {0.9, 0.96};
  scene.solver.phase_lengths = {40};
  expect_matches_cpu<double>(scene, Assembly::gather, 1, 1e-9, "checks every 96, two phases");
}

// A box held at the bottom, twisted at the top and pulled sideways by a
// ramped surface load: moving fixed dofs and loads travel each step.
TEST(DeviceStepper, TwistedLoadedBoxMatchesCpu) {
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
  expect_matches_cpu<double>(scene, Assembly::gather, 4, 1e-9, "twisted, loaded box, 4 frames");
  expect_matches_cpu<double>(scene, Assembly::scatter, 4, 1e-9, "twisted, loaded box, 4 frames");
}

TEST(DeviceStepper, RanksMatchOneRankAndSharersAgreeBitwise) {
  const Scene scene = testing::small_helix_scene();
  const Mesh mesh = build_scene_mesh(scene.mesh);
  constexpr int kFrames = 10;
  for (Assembly assembly : {Assembly::gather, Assembly::scatter}) {
    Simulation<double> sim(MPI_COMM_WORLD, scene, mesh,
                           backend_of(BackendKind::emulated, assembly));
    for (int f = 1; f <= kFrames; ++f) {
      sim.step();
      ASSERT_EQ(testing::shared_mismatches(MPI_COMM_WORLD, sim), 0)
          << to_string(assembly) << ": shared vertices differ between sharers after frame " << f;
    }
    const auto got = testing::gather_positions(MPI_COMM_WORLD, sim, mesh.num_vertices());
    if (world_rank() != 0) continue;
    const auto want = testing::run_frames<double>(
        MPI_COMM_SELF, scene, mesh, backend_of(BackendKind::emulated, assembly), kFrames);
    const double diagonal = testing::bounding_box_diagonal(mesh);
    const double gap = testing::max_difference(got, want);
    EXPECT_LE(gap, 1e-9 * diagonal) << to_string(assembly);
    std::printf("[ device rank invariance ] %s, %d ranks vs 1, %d frames: max gap %.3g\n",
                to_string(assembly), world_size(), kFrames, gap);
  }
}

TEST(DeviceStepper, OneAllreducePerCheckAndMemoryReported) {
  Scene scene = testing::small_helix_scene();
  scene.solver.check_interval = 8;
  const Mesh mesh = build_scene_mesh(scene.mesh);
  Simulation<double> sim(MPI_COMM_WORLD, scene, mesh, backend_of(BackendKind::emulated));
  for (int frame = 0; frame < 3; ++frame) {
    const long before = sim.reduction_counters().allreduces;
    const StepStats step = sim.step();
    ASSERT_EQ(step.iterations, scene.solver.iterations);
    EXPECT_EQ(sim.reduction_counters().allreduces - before,
              scene.solver.iterations / scene.solver.check_interval);
  }
  const std::string report = sim.device_memory_report();
  EXPECT_NE(report.find("bytes per tet"), std::string::npos) << report;
  Simulation<double> cpu(MPI_COMM_WORLD, scene, mesh);
  EXPECT_TRUE(cpu.device_memory_report().empty());
  if (world_rank() == 0) std::printf("[ device memory ] %s\n", report.c_str());
}

TEST(DeviceStepper, OtherMethodsAskForTheCpuBackend) {
  Scene scene = testing::small_helix_scene();
  scene.solver.method = "gd";
  const Mesh mesh = build_scene_mesh(scene.mesh);
  try {
    Simulation<double> sim(MPI_COMM_WORLD, scene, mesh, backend_of(BackendKind::emulated));
    FAIL() << "a method other than chebyshev was accepted by the device stepper";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--backend cpu"), std::string::npos) << e.what();
  }
  // An initial guess the device stepper does not form is refused, not replaced.
  scene.solver.method = "chebyshev";
  scene.solver.init = "optimized";
  EXPECT_THROW(Simulation<double>(MPI_COMM_WORLD, scene, mesh, backend_of(BackendKind::emulated)),
               InputError);
}

// Backend selection: explicit choices are taken; `cuda` without a usable
// device is a clear error; `auto` follows what this process sees.
TEST(BackendChoice, FollowsRequestAndDevices) {
  std::string note;
  BackendRequest request;
  request.backend = "cpu";
  EXPECT_EQ(choose_backend(MPI_COMM_WORLD, request, &note).kind, BackendKind::cpu);
  request.backend = "emulated";
  request.assembly = "scatter";
  const BackendChoice emulated = choose_backend(MPI_COMM_WORLD, request, &note);
  EXPECT_EQ(emulated.kind, BackendKind::emulated);
  EXPECT_EQ(emulated.engine.assembly, Assembly::scatter);
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
