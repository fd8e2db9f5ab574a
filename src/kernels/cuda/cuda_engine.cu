// The iteration engine on CUDA: the one template of
// solver/iteration_engine_impl.hpp over CudaExec, for float and double. The
// element, gather, vertex and energy bodies are the shared ones of
// kernels/loops.hpp.
#include "kernels/cuda/exec_cuda.cuh"
#include "solver/iteration_engine_impl.hpp"

namespace descent {

template <class Real>
std::unique_ptr<IterationEngine<Real>> make_cuda_engine(LocalProblem<Real>& problem,
                                                        Halo<Real>& halo,
                                                        const EngineOptions& options) {
  return std::make_unique<EngineImpl<CudaExec, Real>>(problem, halo, options);
}

template std::unique_ptr<IterationEngine<double>> make_cuda_engine(LocalProblem<double>&,
                                                                   Halo<double>&,
                                                                   const EngineOptions&);
template std::unique_ptr<IterationEngine<float>> make_cuda_engine(LocalProblem<float>&,
                                                                  Halo<float>&,
                                                                  const EngineOptions&);

}  // namespace descent
