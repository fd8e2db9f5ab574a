#pragma once
// The runtime backend of a run (STYLE "a runtime backend, no #ifdef in the
// solver"): which stepper drives the iteration, chosen once per run from
// --backend, the CUDA devices visible and the rank's place on its node.
#include <mpi.h>

#include <memory>
#include <string>
#include <vector>

#include "comm/halo.hpp"
#include "io/scene.hpp"
#include "solver/iteration_engine.hpp"
#include "solver/local_problem.hpp"
#include "solver/stepper.hpp"

namespace descent {

enum class BackendKind {
  cpu,   // every method on OpenMP loops; chebyshev's engine on the host
  cuda,  // chebyshev's engine on a CUDA device
};
const char* to_string(BackendKind kind);

struct BackendChoice {
  BackendKind kind = BackendKind::cpu;
  EngineOptions engine;  // the Chebyshev engine's (graphs and device: CUDA only)
};

// What this process can see of CUDA (kernels/cuda/cuda_status.cpp, or
// backends/cuda_absent.cpp in a build without CUDA).
struct CudaDeviceInfo {
  std::string name;
  int major = 0, minor = 0;
  std::size_t memory_bytes = 0;
};
struct CudaStatus {
  bool compiled = false;
  std::string architectures;  // the build's CMAKE_CUDA_ARCHITECTURES
  int runtime_version = 0;    // CUDART_VERSION, e.g. 13000
  int driver_version = 0;     // 0: no driver
  std::vector<CudaDeviceInfo> devices;
  std::string why_none;  // why no device is usable (empty when one is)
  bool usable() const { return compiled && !devices.empty(); }
};
CudaStatus cuda_status();

// Whether the MPI library says it passes device pointers (CUDA-aware).
bool mpi_cuda_aware();

// The backends this build has and the devices this process sees, for
// `descent --version`.
std::string backend_report();

// What the user asked for (command line).
struct BackendRequest {
  std::string backend = "auto";     // auto | cpu | cuda
  std::string assembly = "gather";  // gather | scatter
  bool share_device = false;        // let several ranks of a node use one device
  bool graphs = true;
};

// The backend of this rank, agreed by every rank of comm (collective; set-up
// only): `auto` is cuda when every rank sees a device, else cpu. Ranks of a
// node take devices local rank mod count; more ranks than devices is an
// InputError unless share_device. `note` receives a line for the log (why no
// device is used, which device).
BackendChoice choose_backend(MPI_Comm comm, const BackendRequest& request, std::string* note);

// The stepper of spec.method on the chosen backend; the cuda backend runs
// only the chebyshev method (InputError otherwise).
template <class Real>
std::unique_ptr<Stepper<Real>> make_backend_stepper(LocalProblem<Real>& problem, Halo<Real>& halo,
                                                    const SolverSpec& spec,
                                                    const BackendChoice& backend);

// "N MiB on device: B bytes per tet, B per vertex" for a stepper whose engine
// is on a device; empty otherwise.
template <class Real>
std::string device_memory_report(const Stepper<Real>& stepper, long long tets, long long vertices);

// For the Chebyshev stepper: "energy checks ... X% of iteration time" and the
// share of the spectrum estimates; empty for other methods.
template <class Real>
std::string stepper_timing_report(const Stepper<Real>& stepper);

// The stepper's preconditioner other than Jacobi's: at set-up its levels and
// memory per tet; after steps (`used`) also its refreshes and applications
// with their mean cost and its collectives. Empty without one.
template <class Real>
std::string preconditioner_report(const Stepper<Real>& stepper, long long tets, bool used);

}  // namespace descent
