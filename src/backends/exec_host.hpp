#pragma once
// The host execution of the device stepper: the same launches as the CUDA
// execution (src/kernels/cuda/exec_cuda.cuh), run as OpenMP loops on host
// memory. It is always compiled, so the whole GPU algorithm (streams, packed
// exchange, graphs of iterations, device reductions) is exercised and
// compared with the CPU reference on machines without a GPU.
//
// The interface every execution offers (duck-typed, used by
// backends/device_engine_impl.hpp):
//   kAsync                        launches return before the work is done
//   for_each(stream, begin, end, f)   f(i) for i in [begin, end)
//   reduce(stream, n, f)          sum over i of f(i), a Sum2 of doubles
//   allocate/release(bytes)       device memory; allocate_pinned for staging
//   copy(stream, dst, src, bytes) any direction, ordered on the stream
//   zero(stream, p, bytes)
//   record(stream, event), wait(stream, event): event e marks the point of
//   stream s; a later wait makes another stream start after it
//   sync(stream)                  the host waits for the stream
//   run_graph(key, enqueue)       enqueue() once under capture, replayed by key
//   clear_graphs()                forget captured graphs (their buffers moved)
#include <omp.h>

#include <atomic>
#include <cstddef>
#include <cstdlib>
#include <cstring>
#include <new>
#include <string>

#include "common/mesh.hpp"
#include "kernels/host_device.hpp"

namespace descent {

// A pair of sums accumulated in double: an energy and its terms' magnitudes.
struct Sum2 {
  double value = 0;
  double magnitude = 0;
};

// Atomic add usable from launched bodies on both executions.
template <class Real>
DESCENT_HOST_DEVICE inline void atomic_add(Real* target, Real value) {
#if defined(__CUDA_ARCH__)
  atomicAdd(target, value);
#else
  std::atomic_ref<Real>(*target).fetch_add(value, std::memory_order_relaxed);
#endif
}

class HostExec {
 public:
  static constexpr bool kAsync = false;

  HostExec() = default;
  explicit HostExec(int /*device*/) {}

  template <class F>
  void for_each(int /*stream*/, index_t begin, index_t end, const F& f) {
#pragma omp parallel for schedule(static)
    for (index_t i = begin; i < end; ++i) f(i);
  }

  template <class F>
  Sum2 reduce(int /*stream*/, index_t n, const F& f) {
    double value = 0, magnitude = 0;
#pragma omp parallel for schedule(static) reduction(+ : value, magnitude)
    for (index_t i = 0; i < n; ++i) {
      const Sum2 s = f(i);
      value += s.value;
      magnitude += s.magnitude;
    }
    return {value, magnitude};
  }

  void* allocate(std::size_t bytes) { return bytes ? ::operator new(bytes) : nullptr; }
  void release(void* p) { ::operator delete(p); }
  void* allocate_pinned(std::size_t bytes) { return allocate(bytes); }
  void release_pinned(void* p) { release(p); }

  void copy(int /*stream*/, void* dst, const void* src, std::size_t bytes) {
    if (bytes) std::memcpy(dst, src, bytes);
  }
  void zero(int /*stream*/, void* p, std::size_t bytes) {
    if (bytes) std::memset(p, 0, bytes);
  }
  void record(int /*stream*/, int /*event*/) {}
  void wait(int /*stream*/, int /*event*/) {}
  void sync(int /*stream*/) {}

  // Nothing to capture on the host: the sequence simply runs.
  template <class F>
  void run_graph(const std::string& /*key*/, const F& enqueue) {
    enqueue();
  }
  void clear_graphs() {}
  long graph_launches() const { return 0; }
  std::string describe() const {
    return "host (OpenMP, " + std::to_string(omp_get_max_threads()) + " threads)";
  }
};

}  // namespace descent
