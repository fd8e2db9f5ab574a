#include "backends/backend.hpp"

#if __has_include(<mpi-ext.h>)
#include <mpi-ext.h>  // Open MPI's MPIX_CUDA_AWARE_SUPPORT
#endif

#include <cstdio>

#include "comm/mpi_check.hpp"
#include "common/error.hpp"
#include "solver/chebyshev_descent.hpp"

namespace descent {

namespace {

std::string format_percent(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f%%", value);
  return text;
}

std::string format_milliseconds(double seconds) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f ms", 1e3 * seconds);
  return text;
}

}  // namespace

const char* to_string(BackendKind kind) {
  switch (kind) {
    case BackendKind::cpu:
      return "cpu";
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
  std::string out = "backends: cpu";
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
  if (want != "auto" && want != "cuda")
    throw InputError("--backend must be auto, cpu or cuda, not '" + want + "'");

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
  const bool cuda = backend.kind == BackendKind::cuda;
  if (spec.method != "chebyshev") {
    if (!cuda) return make_stepper(problem, spec);
    throw InputError(detail::concat("solver.method = ", spec.method,
                                    " runs on the cpu backend only; use --backend cpu (the cuda "
                                    "backend runs chebyshev)"));
  }
  // The optimized step of Eq. 10 is formed on the host from the problem's
  // gradient: on a device it would cost the whole mesh on the CPU per step.
  if (cuda && spec.init == "optimized")
    throw InputError(
        "solver.init = optimized runs on the cpu backend only; use --backend cpu, or init = "
        "constant_acceleration, velocity or position");
  auto engine = cuda ? make_cuda_engine(problem, halo, backend.engine)
                     : make_host_engine(problem, halo, backend.engine);
  return std::make_unique<ChebyshevDescent<Real>>(problem, spec, std::move(engine));
}

template <class Real>
std::string device_memory_report(const Stepper<Real>& stepper, long long tets, long long vertices) {
  const auto* chebyshev = dynamic_cast<const ChebyshevDescent<Real>*>(&stepper);
  if (!chebyshev || !chebyshev->engine().on_device()) return {};
  const EngineMemory m = chebyshev->engine().memory();
  return detail::concat(chebyshev->engine().describe(), ": ", m.total() >> 20,
                        " MiB on device: ", tets > 0 ? m.tet_bytes / tets : 0, " bytes per tet, ",
                        vertices > 0 ? m.vertex_bytes / vertices : 0, " per vertex");
}

template <class Real>
std::string stepper_timing_report(const Stepper<Real>& stepper) {
  const auto* chebyshev = dynamic_cast<const ChebyshevDescent<Real>*>(&stepper);
  if (!chebyshev) return {};
  const double iterate = chebyshev->iterate_seconds(), check = chebyshev->check_seconds();
  const double estimate = chebyshev->estimate_seconds();
  const double total = iterate + check + estimate + chebyshev->refresh_seconds();
  auto share = [total](double part) { return total > 0 ? 100 * part / total : 0.0; };
  std::string text = detail::concat("energy checks and rollbacks ", format_percent(share(check)),
                                    " of step time (", format_milliseconds(check), " of ",
                                    format_milliseconds(total), ")");
  if (chebyshev->estimates() > 0)
    text +=
        detail::concat("; ", chebyshev->estimates(), " spectrum estimate(s) ",
                       format_percent(share(estimate)), " (", format_milliseconds(estimate), ")");
  if (chebyshev->engine().on_device())
    text += detail::concat("; ", chebyshev->engine().graph_launches(), " graph launches");
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
template <class Real>
std::string preconditioner_report(const Stepper<Real>& stepper, long long tets, bool used) {
  const Preconditioner<Real>* p = stepper.preconditioner();
  if (!p) return {};
  const PreconditionerStats s = p->stats();
  if (!used)
    return detail::concat(p->describe(), "; ", s.memory_bytes >> 20, " MiB on rank 0 (",
                          tets > 0 ? static_cast<long long>(s.memory_bytes) / tets : 0,
                          " bytes per tet)");
  auto mean_ms = [](double seconds, long count) {
    char text[32];
    std::snprintf(text, sizeof text, "%.1f", count > 0 ? 1e3 * seconds / count : 0.0);
    return std::string(text);
  };
  return detail::concat(
      "preconditioner: ", s.refreshes, " refreshes, ", format_milliseconds(s.refresh_seconds), " (",
      mean_ms(s.refresh_seconds, s.refreshes), " ms each); ", s.applications, " applications, ",
      format_milliseconds(s.apply_seconds), " (", mean_ms(s.apply_seconds, s.applications),
      " ms each); ", s.allreduces, " allreduces, ", s.gathers, " gathers and ", s.messages,
      " halo messages of its own");
}

template std::string stepper_timing_report(const Stepper<double>&);
template std::string stepper_timing_report(const Stepper<float>&);
template std::string preconditioner_report(const Stepper<double>&, long long, bool);
template std::string preconditioner_report(const Stepper<float>&, long long, bool);

}  // namespace descent
