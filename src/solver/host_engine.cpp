// The iteration engine on the host execution: the Chebyshev iteration of
// every CPU run, the same template the CUDA engine instantiates.
#include "kernels/cpu/host_exec.hpp"
#include "solver/iteration_engine_impl.hpp"

namespace descent {

const char* to_string(Assembly assembly) {
  return assembly == Assembly::gather ? "gather" : "scatter";
}

template <class Real>
std::unique_ptr<IterationEngine<Real>> make_host_engine(LocalProblem<Real>& problem,
                                                        Halo<Real>& halo,
                                                        const EngineOptions& options) {
  return std::make_unique<EngineImpl<HostExec, Real>>(problem, halo, options);
}

template std::unique_ptr<IterationEngine<double>> make_host_engine(LocalProblem<double>&,
                                                                   Halo<double>&,
                                                                   const EngineOptions&);
template std::unique_ptr<IterationEngine<float>> make_host_engine(LocalProblem<float>&,
                                                                  Halo<float>&,
                                                                  const EngineOptions&);

}  // namespace descent
