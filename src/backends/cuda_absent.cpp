// A build without CUDA (no CUDA compiler, or DESCENT_ENABLE_CUDA=OFF): the
// CUDA entry points exist and say so, so callers need no #ifdef.
#include "backends/backend.hpp"
#include "common/error.hpp"

namespace descent {

CudaStatus cuda_status() {
  CudaStatus s;
  s.why_none = "this build has no CUDA backend (configured without a CUDA compiler)";
  return s;
}

template <class Real>
std::unique_ptr<IterationEngine<Real>> make_cuda_engine(LocalProblem<Real>&, Halo<Real>&,
                                                        const EngineOptions&) {
  throw InputError(
      "this build of descent has no CUDA backend: reconfigure with a CUDA compiler "
      "(CUDACXX or PATH) and -DDESCENT_ENABLE_CUDA=ON");
}

template std::unique_ptr<IterationEngine<double>> make_cuda_engine(LocalProblem<double>&,
                                                                   Halo<double>&,
                                                                   const EngineOptions&);
template std::unique_ptr<IterationEngine<float>> make_cuda_engine(LocalProblem<float>&,
                                                                  Halo<float>&,
                                                                  const EngineOptions&);

}  // namespace descent
