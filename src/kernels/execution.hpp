#pragma once
// What an execution is: the one interface over which the element and vertex
// loops of kernels/loops.hpp are written, implemented by the host (OpenMP,
// kernels/cpu/host_exec.hpp) and by CUDA (kernels/cuda/exec_cuda.cuh). It is
// duck-typed (a template parameter), so a launch costs no virtual call:
//   kAsync                        launches return before the work is done
//   kHostMemory                   its memory is the host's (no copies needed)
//   for_each(stream, begin, end, f)   f(i) for i in [begin, end)
//   serial()                      for_each runs i = begin, begin + 1, ... one
//                                 after another (a host with one thread)
//   reduce(stream, n, f)          sum over i of f(i), a Sum2 of doubles, in an
//                                 order that does not change from run to run
//   allocate/release(bytes)       device memory; allocate_pinned for staging
//   copy(stream, dst, src, bytes) any direction, ordered on the stream
//   zero(stream, p, bytes)
//   record(stream, event), wait(stream, event): event e marks the point of
//   stream s; a later wait makes another stream start after it
//   sync(stream)                  the host waits for the stream
//   run_graph(key, enqueue)       enqueue() once under capture, replayed by key
//   clear_graphs()                forget captured graphs (their buffers moved)
#include <atomic>

#include "kernels/host_device.hpp"

namespace descent {

// A pair of sums accumulated in double: an energy and its terms' magnitudes,
// or two inner products.
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

}  // namespace descent
