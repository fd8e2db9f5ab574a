// The device engine on the host execution: always built, so the GPU
// algorithm runs (and is tested against the CPU stepper) without a GPU.
#include "backends/device_engine_impl.hpp"
#include "backends/exec_host.hpp"

namespace descent {

const char* to_string(Assembly assembly) {
  return assembly == Assembly::gather ? "gather" : "scatter";
}

template <class Real>
std::unique_ptr<DeviceEngine<Real>> make_host_engine(LocalProblem<Real>& problem, Halo<Real>& halo,
                                                     const EngineOptions& options) {
  return std::make_unique<EngineImpl<HostExec, Real>>(problem, halo, options);
}

template std::unique_ptr<DeviceEngine<double>> make_host_engine(LocalProblem<double>&,
                                                                Halo<double>&,
                                                                const EngineOptions&);
template std::unique_ptr<DeviceEngine<float>> make_host_engine(LocalProblem<float>&, Halo<float>&,
                                                               const EngineOptions&);

}  // namespace descent
