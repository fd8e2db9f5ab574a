#pragma once
// The host execution (kernels/execution.hpp): every launch an OpenMP loop on
// host memory. It runs the Chebyshev engine of every CPU run and the loops of
// LocalProblem and the other methods, so the CPU and the CUDA backends share
// one set of element and vertex loops (kernels/loops.hpp).
#include <omp.h>

#include <cstddef>
#include <cstring>
#include <new>
#include <string>

#include "common/mesh.hpp"
#include "kernels/execution.hpp"

namespace descent {

class HostExec {
 public:
  static constexpr bool kAsync = false;
  static constexpr bool kHostMemory = true;

  HostExec() = default;
  explicit HostExec(int /*device*/) {}

  template <class F>
  void for_each(int /*stream*/, index_t begin, index_t end, const F& f) {
#pragma omp parallel for schedule(static)
    for (index_t i = begin; i < end; ++i) f(i);
  }

  bool serial() const { return omp_get_max_threads() == 1; }

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
