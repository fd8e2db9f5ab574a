#pragma once
// Lanes<T, W>: W reals side by side, one per tet of a block, so that the
// element math of src/kernels, instantiated on it, computes W tets with each
// instruction of the host's vector unit (GCC vector extensions: the compiler
// lowers each operation to the widest registers the build's -march has).
//
// Each lane gets bitwise the result the math gives on T alone: +, -, *, /
// are elementwise IEEE operations (and the build contracts none into a fused
// multiply-add, -ffp-contract=off), and the math calls (cbrt, sqrt, exp) go
// lane by lane through std's. Comparisons are deliberately absent: a model
// that branches on a real cannot be instantiated on Lanes and keeps the
// tet-by-tet loop (kernels/cpu/lane_models.hpp lists the models that can).
//
// Host only: nvcc's device code has its own parallelism (one tet per thread).
#include <cmath>
#include <cstddef>

namespace descent {

// The vector registers of the build: 64 bytes with AVX-512, 32 with AVX,
// 16 otherwise (SSE2, NEON).
#if defined(__AVX512F__)
inline constexpr int kVectorBytes = 64;
#elif defined(__AVX__)
inline constexpr int kVectorBytes = 32;
#else
inline constexpr int kVectorBytes = 16;
#endif

template <class T>
inline constexpr int kLaneWidth = kVectorBytes / static_cast<int>(sizeof(T));

template <class T, int W>
struct Lanes {
  typedef T Vector
      __attribute__((vector_size(W * sizeof(T))));  // NOLINT: GCC takes a dependent size only here
  Vector v;

  Lanes() = default;
  // Broadcast (literals, Real(2), model parameters): lane by lane, so that
  // -0.0 stays -0.0.
  Lanes(T x) {  // NOLINT: converts implicitly, as a literal converts to T
    for (int l = 0; l < W; ++l) v[l] = x;
  }
  static Lanes of(Vector x) {
    Lanes r;
    r.v = x;
    return r;
  }

  friend Lanes operator+(Lanes a, Lanes b) { return of(a.v + b.v); }
  friend Lanes operator-(Lanes a, Lanes b) { return of(a.v - b.v); }
  friend Lanes operator*(Lanes a, Lanes b) { return of(a.v * b.v); }
  friend Lanes operator/(Lanes a, Lanes b) { return of(a.v / b.v); }
  friend Lanes operator-(Lanes a) { return of(-a.v); }
  Lanes& operator+=(Lanes b) { return *this = *this + b; }
  Lanes& operator-=(Lanes b) { return *this = *this - b; }
  Lanes& operator*=(Lanes b) { return *this = *this * b; }
  Lanes& operator/=(Lanes b) { return *this = *this / b; }

  friend Lanes cbrt(Lanes a) {
    for (int l = 0; l < W; ++l) a.v[l] = std::cbrt(a.v[l]);
    return a;
  }
  friend Lanes sqrt(Lanes a) {
    for (int l = 0; l < W; ++l) a.v[l] = std::sqrt(a.v[l]);
    return a;
  }
  friend Lanes exp(Lanes a) {
    for (int l = 0; l < W; ++l) a.v[l] = std::exp(a.v[l]);
    return a;
  }
};

}  // namespace descent
