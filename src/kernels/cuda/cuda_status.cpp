// What this process sees of CUDA, asked of the runtime (linked statically,
// so the binary starts without any CUDA library; with no driver, or one older
// than the runtime, the runtime's own message says why no device is usable).
#include <cuda_runtime.h>

#include "backends/backend.hpp"

namespace descent {

CudaStatus cuda_status() {
  CudaStatus s;
  s.compiled = true;
  s.architectures = DESCENT_CUDA_ARCHITECTURES;
  cudaRuntimeGetVersion(&s.runtime_version);
  if (cudaDriverGetVersion(&s.driver_version) != cudaSuccess) s.driver_version = 0;
  int count = 0;
  const cudaError_t code = cudaGetDeviceCount(&count);
  if (code != cudaSuccess) {
    s.why_none = std::string(cudaGetErrorName(code)) + ": " + cudaGetErrorString(code);
    if (s.driver_version == 0) s.why_none += " (no CUDA driver found)";
    return s;
  }
  if (count == 0) {
    s.why_none = "the driver reports no CUDA device (CUDA_VISIBLE_DEVICES?)";
    return s;
  }
  for (int d = 0; d < count; ++d) {
    cudaDeviceProp prop{};
    if (cudaGetDeviceProperties(&prop, d) != cudaSuccess) continue;
    s.devices.push_back({prop.name, prop.major, prop.minor, prop.totalGlobalMem});
  }
  return s;
}

}  // namespace descent
