#include "kernels/cuda/exec_cuda.cuh"

namespace descent {

namespace cuda_detail {

__global__ void __launch_bounds__(kReduceBlocks)
    finish_reduce_kernel(int blocks, double* partial, double* out) {
  __shared__ double value[kReduceBlocks], magnitude[kReduceBlocks];
  const int t = threadIdx.x;
  value[t] = t < blocks ? partial[2 * t] : 0.0;
  magnitude[t] = t < blocks ? partial[2 * t + 1] : 0.0;
  __syncthreads();
  for (int width = kReduceBlocks / 2; width > 0; width /= 2) {
    if (t < width) {
      value[t] += value[t + width];
      magnitude[t] += magnitude[t + width];
    }
    __syncthreads();
  }
  if (t == 0) {
    out[0] = value[0];
    out[1] = magnitude[0];
  }
}

}  // namespace cuda_detail

CudaExec::CudaExec(int device) : device_(device) {
  DESCENT_CUDA_CHECK(cudaSetDevice(device));
  for (auto& s : streams_) DESCENT_CUDA_CHECK(cudaStreamCreateWithFlags(&s, cudaStreamNonBlocking));
  for (auto& e : events_) DESCENT_CUDA_CHECK(cudaEventCreateWithFlags(&e, cudaEventDisableTiming));
  DESCENT_CUDA_CHECK(cudaMalloc(&partial_, 2 * cuda_detail::kReduceBlocks * sizeof(double)));
  DESCENT_CUDA_CHECK(cudaMalloc(&result_device_, 2 * sizeof(double)));
  DESCENT_CUDA_CHECK(cudaMallocHost(&result_, 2 * sizeof(double)));
}

// Destructors do not throw: a failure here is reported by the next call.
CudaExec::~CudaExec() {
  for (auto& [key, graph] : graphs_) cudaGraphExecDestroy(graph);
  cudaFree(partial_);
  cudaFree(result_device_);
  cudaFreeHost(result_);
  for (auto& e : events_) cudaEventDestroy(e);
  for (auto& s : streams_) cudaStreamDestroy(s);
}

void* CudaExec::allocate(std::size_t bytes) {
  void* p = nullptr;
  if (bytes) DESCENT_CUDA_CHECK(cudaMalloc(&p, bytes));
  return p;
}
void CudaExec::release(void* p) { cudaFree(p); }
void* CudaExec::allocate_pinned(std::size_t bytes) {
  void* p = nullptr;
  if (bytes) DESCENT_CUDA_CHECK(cudaMallocHost(&p, bytes));
  return p;
}
void CudaExec::release_pinned(void* p) { cudaFreeHost(p); }

void CudaExec::copy(int stream, void* dst, const void* src, std::size_t bytes) {
  if (bytes)
    DESCENT_CUDA_CHECK(cudaMemcpyAsync(dst, src, bytes, cudaMemcpyDefault, streams_[stream]));
}
void CudaExec::zero(int stream, void* p, std::size_t bytes) {
  if (bytes) DESCENT_CUDA_CHECK(cudaMemsetAsync(p, 0, bytes, streams_[stream]));
}
void CudaExec::record(int stream, int event) {
  DESCENT_CUDA_CHECK(cudaEventRecord(events_[event], streams_[stream]));
}
void CudaExec::wait(int stream, int event) {
  DESCENT_CUDA_CHECK(cudaStreamWaitEvent(streams_[stream], events_[event], 0));
}
void CudaExec::sync(int stream) { DESCENT_CUDA_CHECK(cudaStreamSynchronize(streams_[stream])); }

void CudaExec::finish(int stream, int blocks) {
  cuda_detail::finish_reduce_kernel<<<1, cuda_detail::kReduceBlocks, 0, streams_[stream]>>>(
      blocks, partial_, result_device_);
  DESCENT_CUDA_CHECK(cudaGetLastError());
  copy(stream, result_, result_device_, 2 * sizeof(double));
  sync(stream);
}

void CudaExec::begin_capture() {
  DESCENT_CUDA_CHECK(cudaStreamBeginCapture(streams_[0], cudaStreamCaptureModeThreadLocal));
}

cudaGraphExec_t CudaExec::end_capture() {
  cudaGraph_t graph = nullptr;
  DESCENT_CUDA_CHECK(cudaStreamEndCapture(streams_[0], &graph));
  cudaGraphExec_t exec = nullptr;
  DESCENT_CUDA_CHECK(cudaGraphInstantiate(&exec, graph, 0));
  cudaGraphDestroy(graph);
  return exec;
}

void CudaExec::clear_graphs() {
  for (auto& [key, graph] : graphs_) DESCENT_CUDA_CHECK(cudaGraphExecDestroy(graph));
  graphs_.clear();
}

void CudaExec::launch(cudaGraphExec_t graph) {
  DESCENT_CUDA_CHECK(cudaGraphLaunch(graph, streams_[0]));
  ++graph_launches_;
}

std::string CudaExec::describe() const {
  cudaDeviceProp prop{};
  cudaGetDeviceProperties(&prop, device_);
  return std::string("cuda device ") + std::to_string(device_) + " (" + prop.name + ")";
}

}  // namespace descent
