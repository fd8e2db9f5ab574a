#pragma once
// The CUDA execution (kernels/execution.hpp): the interface on one device,
// two streams (0: main, 1: side) and a few events, with captured graphs
// replayed by key. nvcc only.
//
// Launch shape: one thread per index, 256 per block. Reductions are
// deterministic: a fixed grid of per-block partial sums in double, then one
// block sums those in a fixed order, so a run repeats bit for bit.
#include <cuda_runtime.h>

#include <map>
#include <string>

#include "common/mesh.hpp"
#include "kernels/cuda/cuda_check.hpp"
#include "kernels/execution.hpp"

namespace descent {

namespace cuda_detail {

constexpr int kBlock = 256;
constexpr int kReduceBlocks = 1024;

template <class F>
__global__ void __launch_bounds__(kBlock) for_each_kernel(index_t begin, index_t end, F f) {
  const long long i = begin + static_cast<long long>(blockIdx.x) * blockDim.x + threadIdx.x;
  if (i < end) f(static_cast<index_t>(i));
}

// Block sums of two doubles into out[2 * blockIdx.x], grid-stride over [0, n).
template <class F>
__global__ void __launch_bounds__(kBlock) reduce_kernel(index_t n, F f, double* out) {
  __shared__ double value[kBlock], magnitude[kBlock];
  double v = 0, m = 0;
  for (long long i = static_cast<long long>(blockIdx.x) * blockDim.x + threadIdx.x; i < n;
       i += static_cast<long long>(gridDim.x) * blockDim.x) {
    const Sum2 s = f(static_cast<index_t>(i));
    v += s.value;
    m += s.magnitude;
  }
  value[threadIdx.x] = v;
  magnitude[threadIdx.x] = m;
  __syncthreads();
  for (int width = kBlock / 2; width > 0; width /= 2) {
    if (threadIdx.x < width) {
      value[threadIdx.x] += value[threadIdx.x + width];
      magnitude[threadIdx.x] += magnitude[threadIdx.x + width];
    }
    __syncthreads();
  }
  if (threadIdx.x == 0) {
    out[2 * blockIdx.x] = value[0];
    out[2 * blockIdx.x + 1] = magnitude[0];
  }
}

// The sum of `blocks` pairs, in a fixed tree order, into out[0..1].
__global__ void __launch_bounds__(kReduceBlocks)
    finish_reduce_kernel(int blocks, double* partial, double* out);

}  // namespace cuda_detail

class CudaExec {
 public:
  static constexpr bool kAsync = true;
  static constexpr bool kHostMemory = false;

  explicit CudaExec(int device);
  ~CudaExec();
  CudaExec(const CudaExec&) = delete;
  CudaExec& operator=(const CudaExec&) = delete;

  template <class F>
  void for_each(int stream, index_t begin, index_t end, const F& f) {
    if (end <= begin) return;
    const long long n = static_cast<long long>(end) - begin;
    const unsigned blocks =
        static_cast<unsigned>((n + cuda_detail::kBlock - 1) / cuda_detail::kBlock);
    cuda_detail::for_each_kernel<<<blocks, cuda_detail::kBlock, 0, streams_[stream]>>>(begin, end,
                                                                                       f);
    DESCENT_CUDA_CHECK(cudaGetLastError());
  }

  bool serial() const { return false; }

  template <class F>
  Sum2 reduce(int stream, index_t n, const F& f) {
    long long wanted = (static_cast<long long>(n) + cuda_detail::kBlock - 1) / cuda_detail::kBlock;
    const int blocks = static_cast<int>(
        wanted < 1 ? 1
                   : (wanted > cuda_detail::kReduceBlocks ? cuda_detail::kReduceBlocks : wanted));
    cuda_detail::reduce_kernel<<<blocks, cuda_detail::kBlock, 0, streams_[stream]>>>(n, f,
                                                                                     partial_);
    DESCENT_CUDA_CHECK(cudaGetLastError());
    finish(stream, blocks);
    return {result_[0], result_[1]};
  }

  void* allocate(std::size_t bytes);
  void release(void* p);
  void* allocate_pinned(std::size_t bytes);
  void release_pinned(void* p);
  void copy(int stream, void* dst, const void* src, std::size_t bytes);
  void zero(int stream, void* p, std::size_t bytes);
  void record(int stream, int event);
  void wait(int stream, int event);
  void sync(int stream);

  // The first call with a key captures enqueue() on the main stream (the
  // side stream joins through events) into a graph; every call launches it.
  template <class F>
  void run_graph(const std::string& key, const F& enqueue) {
    auto it = graphs_.find(key);
    if (it == graphs_.end()) {
      if (graphs_.size() >= kMaxGraphs) {  // an unusual schedule: launch directly
        enqueue();
        return;
      }
      begin_capture();
      enqueue();
      it = graphs_.emplace(key, end_capture()).first;
    }
    launch(it->second);
  }
  void clear_graphs();
  long graph_launches() const { return graph_launches_; }
  std::string describe() const;

 private:
  static constexpr std::size_t kMaxGraphs = 64;
  void finish(int stream, int blocks);  // second pass of reduce, result to host
  void begin_capture();
  cudaGraphExec_t end_capture();
  void launch(cudaGraphExec_t graph);

  int device_;
  cudaStream_t streams_[2] = {nullptr, nullptr};
  cudaEvent_t events_[4] = {nullptr, nullptr, nullptr, nullptr};
  double* partial_ = nullptr;  // 2 per reduce block
  double* result_ = nullptr;   // 2, pinned host
  double* result_device_ = nullptr;
  std::map<std::string, cudaGraphExec_t> graphs_;
  long graph_launches_ = 0;
};

}  // namespace descent
