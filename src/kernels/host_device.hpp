#pragma once
// Marks math that compiles for the host and, under nvcc, for the device too.
#if defined(__CUDACC__)
#define DESCENT_HOST_DEVICE __host__ __device__
#else
#define DESCENT_HOST_DEVICE
#endif
