#include "backends/backend.hpp"

#if __has_include(<mpi-ext.h>)
#include <mpi-ext.h>  // Open MPI's MPIX_CUDA_AWARE_SUPPORT
#endif

#include <cstdio>

#include "backends/device_chebyshev.hpp"
#include "comm/mpi_check.hpp"
#include "common/error.hpp"

namespace descent {

const char* to_string(BackendKind kind) {
  switch (kind) {
    case BackendKind::cpu:
      return "cpu";
    case BackendKind::emulated:
      return "emulated";
    case BackendKind::cuda:
      return "cuda";
  }
  return "?";
}

bool mpi_cuda_aware() {
#if defined(MPIX_CUDA_AWARE_SUPPORT) && MPIX_CUDA_AWARE_SUPPORT
  return MPIX_Query_cuda_support() == 1;
#else
  return false;
#endif
}

std::string backend_report() {
  const CudaStatus s = cuda_status();
  std::string out = "backends: cpu, emulated";
  if (s.compiled) {
    out +=
        detail::concat(", cuda (runtime ", s.runtime_version / 1000, ".",
                       (s.runtime_version % 1000) / 10, ", architectures ", s.architectures, ")");
  } else {
    out += " (cuda not compiled in this build)";
  }
  if (s.compiled) {
    if (s.driver_version > 0)
      out += detail::concat("\ndriver: CUDA ", s.driver_version / 1000, ".",
                            (s.driver_version % 1000) / 10);
    if (s.devices.empty()) out += "\ndevices: none usable: " + s.why_none;
    for (std::size_t d = 0; d < s.devices.size(); ++d) {
      const CudaDeviceInfo& i = s.devices[d];
      out += detail::concat("\ndevice ", d, ": ", i.name, " (sm_", i.major, i.minor, ", ",
                            i.memory_bytes >> 20, " MiB)");
    }
  }
  out += std::string("\nMPI: ") + (mpi_cuda_aware() ? "CUDA-aware" : "not CUDA-aware") +
         " (the exchange is staged through host memory either way)";
  return out;
}

namespace {

// This rank's index among the ranks of its node, and their count.
void node_rank(MPI_Comm comm, int* local_rank, int* local_size) {
  MPI_Comm node;
  DESCENT_MPI_CHECK(MPI_Comm_split_type(comm, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &node));
  MPI_Comm_rank(node, local_rank);
  MPI_Comm_size(node, local_size);
  MPI_Comm_free(&node);
}

Assembly parse_assembly(const std::string& text) {
  if (text == "gather") return Assembly::gather;
  if (text == "scatter") return Assembly::scatter;
  throw InputError("--assembly must be gather or scatter, not '" + text + "'");
}

}  // namespace

BackendChoice choose_backend(MPI_Comm comm, const BackendRequest& request, std::string* note) {
  BackendChoice choice;
  choice.engine.assembly = parse_assembly(request.assembly);
  choice.engine.graphs = request.graphs;
  const std::string& want = request.backend;
  if (want == "cpu") return choice;
  if (want == "emulated") {
    choice.kind = BackendKind::emulated;
    return choice;
  }
  if (want != "auto" && want != "cuda")
    throw InputError("--backend must be auto, cpu, cuda or emulated, not '" + want + "'");

  int local_rank = 0, local_size = 1;
  node_rank(comm, &local_rank, &local_size);
  const CudaStatus status = cuda_status();
  const int count = static_cast<int>(status.devices.size());
  // Every rank must take the same path (and so the same default precision):
  // cuda only where all ranks can.
  int usable = status.usable() ? 1 : 0;
  DESCENT_MPI_CHECK(MPI_Allreduce(MPI_IN_PLACE, &usable, 1, MPI_INT, MPI_MIN, comm));
  std::string why = status.usable() ? std::string("another rank sees no device") : status.why_none;
  if (!usable) {
    if (want == "cuda") throw InputError("--backend cuda: no usable CUDA device: " + why);
    if (note) *note = "no usable CUDA device (" + why + "); running on the CPU";
    return choice;
  }
  int crowded = local_size > count && !request.share_device ? 1 : 0;
  DESCENT_MPI_CHECK(MPI_Allreduce(MPI_IN_PLACE, &crowded, 1, MPI_INT, MPI_MAX, comm));
  if (crowded)
    throw InputError(detail::concat(
        "more ranks on a node than visible CUDA devices (this node: ", local_size, " ranks, ",
        count, " device(s)); run fewer ranks per node, or pass --share-device to let ranks share"));
  choice.kind = BackendKind::cuda;
  choice.engine.device = local_rank % count;
  if (note)
    *note = detail::concat("cuda: local rank ", local_rank, " on device ", choice.engine.device,
                           " (", status.devices[choice.engine.device].name, ")",
                           local_size > count ? ", shared with other ranks" : "");
  return choice;
}

template <class Real>
std::unique_ptr<Stepper<Real>> make_backend_stepper(LocalProblem<Real>& problem, Halo<Real>& halo,
                                                    const SolverSpec& spec,
                                                    const BackendChoice& backend) {
  if (backend.kind == BackendKind::cpu) return make_stepper(problem, spec);
  if (spec.method != "chebyshev")
    throw InputError(detail::concat("solver.method = ", spec.method,
                                    " runs on the cpu backend only; ", "use --backend cpu (the ",
                                    to_string(backend.kind), " backend runs chebyshev)"));
  // The device stepper forms these initial guesses itself; others (e.g. the
  // optimized step of Eq. 10) are computed by the CPU stepper only.
  if (spec.init != "position" && spec.init != "velocity" && spec.init != "constant_acceleration")
    throw InputError(detail::concat("solver.init = ", spec.init, " runs on the cpu backend only; ",
                                    "use --backend cpu, or init = constant_acceleration, velocity "
                                    "or position"));
  auto engine = backend.kind == BackendKind::cuda ? make_cuda_engine(problem, halo, backend.engine)
                                                  : make_host_engine(problem, halo, backend.engine);
  return std::make_unique<DeviceChebyshev<Real>>(problem, spec, std::move(engine));
}

template <class Real>
std::string device_memory_report(const Stepper<Real>& stepper, long long tets, long long vertices) {
  const auto* device = dynamic_cast<const DeviceChebyshev<Real>*>(&stepper);
  if (!device) return {};
  const DeviceMemory m = device->engine().memory();
  return detail::concat(device->engine().describe(), ": ", m.total() >> 20,
                        " MiB on device: ", tets > 0 ? m.tet_bytes / tets : 0, " bytes per tet, ",
                        vertices > 0 ? m.vertex_bytes / vertices : 0, " per vertex");
}

template <class Real>
std::string device_timing_report(const Stepper<Real>& stepper) {
  const auto* device = dynamic_cast<const DeviceChebyshev<Real>*>(&stepper);
  if (!device) return {};
  const double iterate = device->iterate_seconds(), check = device->check_seconds();
  const double total = iterate + check;
  char text[160];
  std::snprintf(text, sizeof text,
                "energy checks and rollbacks %.1f%% of iteration time (%.1f of %.1f ms); %ld "
                "graph launches",
                total > 0 ? 100 * check / total : 0.0, 1e3 * check, 1e3 * total,
                device->engine().graph_launches());
  return text;
}

template std::unique_ptr<Stepper<double>> make_backend_stepper(LocalProblem<double>&, Halo<double>&,
                                                               const SolverSpec&,
                                                               const BackendChoice&);
template std::unique_ptr<Stepper<float>> make_backend_stepper(LocalProblem<float>&, Halo<float>&,
                                                              const SolverSpec&,
                                                              const BackendChoice&);
template std::string device_memory_report(const Stepper<double>&, long long, long long);
template std::string device_memory_report(const Stepper<float>&, long long, long long);
template std::string device_timing_report(const Stepper<double>&);
template std::string device_timing_report(const Stepper<float>&);

}  // namespace descent
