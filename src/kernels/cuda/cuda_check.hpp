#pragma once
// Every CUDA runtime call's status is checked; a failure throws CudaError
// naming the call, its place and the runtime's message (never in device code).
#include <cuda_runtime.h>

#include "common/error.hpp"

namespace descent {

struct CudaError : Error {
  using Error::Error;
};

namespace detail {
inline void check_cuda(cudaError_t code, const char* call, const char* file, int line) {
  if (code == cudaSuccess) return;
  throw CudaError(concat(file, ":", line, ": ", call, " failed: ", cudaGetErrorName(code), ": ",
                         cudaGetErrorString(code)));
}
}  // namespace detail

}  // namespace descent

#define DESCENT_CUDA_CHECK(call) ::descent::detail::check_cuda((call), #call, __FILE__, __LINE__)
