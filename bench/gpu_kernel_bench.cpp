// Element-kernel throughput of the Chebyshev engine on one rank: the double
// helix (a preset or a resolution) after one real step, then the element
// pass alone, gather and scatter, without and with the Hessian diagonal.
// One line per case, key=value, for bench/gpu_table1.py:
//   kernel assembly=gather diag=0 tets=324624 us=... bytes=... gbs=...
//
//   descent_kernel_bench [--preset 316k | --resolution 15.1] [--precision float|double]
//                        [--backend cuda|cpu] [--repeats 50]
#include <mpi.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "app/scene_mesh.hpp"
#include "app/simulation.hpp"
#include "meshes/generators.hpp"
#include "solver/chebyshev_descent.hpp"

namespace {

using namespace descent;

struct Args {
  std::string preset = "316k";
  double resolution = 0;  // overrides the preset when > 0
  std::string precision = "float";
  std::string backend = "cuda";
  int repeats = 50;
};

Scene helix_scene(const Args& args) {
  Scene scene;
  scene.mesh.generator = "double_helix";
  scene.mesh.helix.resolution =
      args.resolution > 0 ? args.resolution : double_helix_preset_resolution(args.preset);
  const double height = double_helix_height(scene.mesh.helix);
  FixedRegion top;
  top.box_min = {-1.0, height - 0.04, -1.0};
  top.box_max = {1.0, height + 1.0, 1.0};
  scene.fixed.push_back(top);
  scene.material.young = 1e6;
  scene.time.dt = 1.0 / 30.0;
  scene.solver.iterations = 96;
  return scene;
}

template <class Real>
void run(const Args& args) {
  const Scene scene = helix_scene(args);
  const Mesh mesh = build_scene_mesh(scene.mesh);
  for (Assembly assembly : {Assembly::gather, Assembly::scatter}) {
    BackendRequest request;
    request.backend = args.backend;
    request.assembly = to_string(assembly);
    Simulation<Real> sim(MPI_COMM_WORLD, scene, mesh,
                         choose_backend(MPI_COMM_WORLD, request, nullptr));
    sim.step();  // a deformed state, as in a run
    auto& chebyshev = dynamic_cast<ChebyshevDescent<Real>&>(sim.stepper());
    for (bool diag : {false, true}) {
      chebyshev.engine().time_element_pass(diag, 3);  // warm-up
      const auto t = chebyshev.engine().time_element_pass(diag, args.repeats);
      std::printf("kernel assembly=%s diag=%d precision=%s tets=%d us=%.3f bytes=%.0f gbs=%.1f\n",
                  to_string(assembly), diag ? 1 : 0, args.precision.c_str(), mesh.num_tets(),
                  1e6 * t.seconds, t.bytes, t.bytes / t.seconds / 1e9);
    }
    std::printf("memory assembly=%s %s\n", to_string(assembly), sim.device_memory_report().c_str());
  }
}

}  // namespace

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  Args args;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string key = argv[i], value = argv[i + 1];
    if (key == "--preset")
      args.preset = value;
    else if (key == "--resolution")
      args.resolution = std::atof(value.c_str());
    else if (key == "--precision")
      args.precision = value;
    else if (key == "--backend")
      args.backend = value;
    else if (key == "--repeats")
      args.repeats = std::atoi(value.c_str());
    else {
      std::fprintf(stderr, "descent_kernel_bench: unknown option %s\n", key.c_str());
      MPI_Finalize();
      return 2;
    }
  }
  int code = 0;
  try {
    if (args.precision == "double")
      run<double>(args);
    else
      run<float>(args);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "descent_kernel_bench: %s\n", e.what());
    code = 1;
  }
  MPI_Finalize();
  return code;
}
