#pragma once
// Lanes<T, W>: W reals side by side, one per tet of a block, so that the
// element math of src/kernels, instantiated on it, computes W tets with each
// instruction of the host's vector unit (GCC vector extensions: the compiler
// lowers each operation to the widest registers the build's -march has).
//
// Each lane gets bitwise the result the math gives on T alone: +, -, *, /
// and sqrt are elementwise IEEE operations (and the build contracts none
// into a fused multiply-add, -ffp-contract=off); abs and copysign move sign
// bits as std's do; cube_root and exponential run the steps of
// kernels/cube_root.hpp and kernels/exponential.hpp on whole vectors; frexp
// and ldexp go lane by lane through std's. A comparison gives a mask, which
// only select() and any_lane() (kernels/real_math.hpp's, for T) read: `if`
// and `?:` on a mask do not compile, so a model that branches on a real
// cannot be instantiated on Lanes and keeps the tet-by-tet loop; one that
// chooses with select() computes both sides and keeps the chosen one's bits
// (kernels/cpu/lane_models.hpp lists the models that run in lanes), and may
// skip a side no lane of the block takes (any_lane).
//
// Host only: nvcc's device code has its own parallelism (one tet per thread).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <type_traits>
#if defined(__SSE2__)
#include <immintrin.h>
#endif

#include "kernels/cube_root.hpp"
#include "kernels/exponential.hpp"
#include "kernels/real_math.hpp"

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
  // Per lane an integer of T's size: a comparison's result, or T's bits.
  typedef decltype(Vector{} < Vector{}) Bits;
  // A comparison's result: per lane all ones where true, 0 where false (NaN
  // compares false, as for T). any_lane() reads it for a whole block.
  struct Mask {
    Bits bits;
    friend Mask operator&(Mask a, Mask b) { return {a.bits & b.bits}; }
    friend Mask operator|(Mask a, Mask b) { return {a.bits | b.bits}; }
    friend Mask operator!(Mask a) { return {~a.bits}; }
    friend bool any_lane(Mask m) {
      for (int l = 0; l < W; ++l)
        if (m.bits[l]) return true;
      return false;
    }
    friend bool all_lanes(Mask m) {
      for (int l = 0; l < W; ++l)
        if (!m.bits[l]) return false;
      return true;
    }
  };

  Lanes() = default;
  // Broadcast (literals, Real(2), model parameters). x - (+0) is x for
  // every x (-0.0 stays -0.0, NaN stays NaN), and GCC broadcasts a scalar
  // operand in one instruction; the lane-by-lane loop this replaces became 8
  // masked broadcasts for a value loaded in a loop (exponential's
  // coefficients).
  Lanes(T x) : v(x - Vector{}) {}  // NOLINT: converts implicitly, as a literal converts to T
  static Lanes of(Vector x) {
    Lanes r;
    r.v = x;
    return r;
  }
  // The sign bit of every lane.
  static Bits sign_bits() { return (Bits)Lanes(T(-0.0)).v; }

  friend Lanes operator+(Lanes a, Lanes b) { return of(a.v + b.v); }
  friend Lanes operator-(Lanes a, Lanes b) { return of(a.v - b.v); }
  friend Lanes operator*(Lanes a, Lanes b) { return of(a.v * b.v); }
  friend Lanes operator/(Lanes a, Lanes b) { return of(a.v / b.v); }
  friend Lanes operator-(Lanes a) { return of(-a.v); }
  Lanes& operator+=(Lanes b) { return *this = *this + b; }
  Lanes& operator-=(Lanes b) { return *this = *this - b; }
  Lanes& operator*=(Lanes b) { return *this = *this * b; }
  Lanes& operator/=(Lanes b) { return *this = *this / b; }

  // The steps of cube_root_scalar with masks for its branches. A cast
  // between vector types of one size reinterprets the bits (GCC's rule).
  friend Lanes cube_root(Lanes x) {
    using Steps = CubeRootSteps<T>;
    using Word = typename Steps::Word;
    typedef Word Words __attribute__((vector_size(W * sizeof(T))));  // NOLINT: as Vector
    typedef std::uint64_t Wide __attribute__((vector_size(W * 8)));  // NOLINT: as Vector
    const Words sign = (Words)x.v & (Word(1) << (8 * sizeof(Word) - 1));
    const Vector a = (Vector)((Words)x.v ^ sign);
    const auto small = a < T(1) / Steps::kScale;
    const auto large = a > Steps::kScale;
    const Vector s = small ? a * Steps::kScale : large ? a * (T(1) / Steps::kScale) : a;
    // high / 3 for high < 2^32 as a multiply and a shift in 64 bits (vector
    // units divide no integers): 0xAAAAAAAB = (2^33 + 1) / 3 makes it exact.
    const Wide high = __builtin_convertvector((Words)s >> Steps::kHighShift, Wide);
    const Words third = __builtin_convertvector((high * 0xAAAAAAABull) >> 33, Words);
    const Words guess = (third + Steps::kBias) << Steps::kHighShift;
    Vector y = cube_root_halley<T>(of(s), of((Vector)guess)).v;
    y = small ? y * (T(1) / Steps::kRootScale) : large ? y * Steps::kRootScale : y;
    const auto special = (a == T(0)) | (a != a) | (a == std::numeric_limits<T>::infinity());
    return of(special ? x.v : (Vector)((Words)y | sign));
  }
  friend Mask operator<(Lanes a, Lanes b) { return {a.v < b.v}; }
  friend Mask operator>(Lanes a, Lanes b) { return {a.v > b.v}; }
  friend Mask operator<=(Lanes a, Lanes b) { return {a.v <= b.v}; }
  friend Mask operator>=(Lanes a, Lanes b) { return {a.v >= b.v}; }
  friend Mask operator==(Lanes a, Lanes b) { return {a.v == b.v}; }
  friend Mask operator!=(Lanes a, Lanes b) { return {a.v != b.v}; }
  friend Lanes select(Mask m, Lanes a, Lanes b) { return of(m.bits ? a.v : b.v); }

  friend Lanes abs(Lanes a) { return of((Vector)((Bits)a.v & ~sign_bits())); }
  friend Lanes copysign(Lanes magnitude, Lanes sign) {
    return of((Vector)(((Bits)magnitude.v & ~sign_bits()) | ((Bits)sign.v & sign_bits())));
  }

  // The instruction where the build has one, else lane by lane (the
  // portable build's SSE2 has the 16-byte ones).
  friend Lanes sqrt(Lanes a) {
#if defined(__AVX512F__)
    if constexpr (sizeof(Vector) == 64 && std::is_same_v<T, double>)
      return of((Vector)_mm512_sqrt_pd((__m512d)a.v));
    if constexpr (sizeof(Vector) == 64 && std::is_same_v<T, float>)
      return of((Vector)_mm512_sqrt_ps((__m512)a.v));
#endif
#if defined(__AVX__)
    if constexpr (sizeof(Vector) == 32 && std::is_same_v<T, double>)
      return of((Vector)_mm256_sqrt_pd((__m256d)a.v));
    if constexpr (sizeof(Vector) == 32 && std::is_same_v<T, float>)
      return of((Vector)_mm256_sqrt_ps((__m256)a.v));
#endif
#if defined(__SSE2__)
    if constexpr (sizeof(Vector) == 16 && std::is_same_v<T, double>)
      return of((Vector)_mm_sqrt_pd((__m128d)a.v));
    if constexpr (sizeof(Vector) == 16 && std::is_same_v<T, float>)
      return of((Vector)_mm_sqrt_ps((__m128)a.v));
#endif
    for (int l = 0; l < W; ++l) a.v[l] = std::sqrt(a.v[l]);
    return a;
  }

  // Binary exponents, one per lane: frexp's, and ldexp by them.
  struct Exponents {
    int e[W];
    Exponents operator-() const {
      Exponents r;
      for (int l = 0; l < W; ++l) r.e[l] = -e[l];
      return r;
    }
  };
  friend Exponents frexp_exponent(Lanes a) {
    Exponents r;
    for (int l = 0; l < W; ++l) std::frexp(a.v[l], &r.e[l]);
    return r;
  }
  friend Lanes ldexp(Lanes a, const Exponents& n) {
    for (int l = 0; l < W; ++l) a.v[l] = std::ldexp(a.v[l], n.e[l]);
    return a;
  }
  // The steps of exponential_scalar with masks for its branches: lanes
  // outside [kMinArg, kMaxArg] (and NaN) run the steps on 0 and take their
  // own result after.
  friend Lanes exponential(Lanes x) {
    using Steps = ExponentialSteps<T>;
    using Word = typename Steps::Word;
    typedef Word Words __attribute__((vector_size(W * sizeof(T))));  // NOLINT: as Vector
    const auto not_a_number = x.v != x.v;
    const auto over = x.v > Steps::kMaxArg;
    const auto under = x.v < Steps::kMinArg;
    const Vector zero = Lanes(T(0)).v;
    Lanes n;
    const Vector twice =
        exponential_reduced<T>(of((not_a_number | over | under) ? zero : x.v), n).v;
    const Vector y = twice * (Vector)exponential_scale_bits<T>(__builtin_convertvector(n.v, Words));
    const Vector infinity = Lanes(std::numeric_limits<T>::infinity()).v;
    return of(not_a_number ? x.v : over ? infinity : under ? zero : y);
  }
};

template <class T, int W>
struct ScalarOf<Lanes<T, W>> {
  using type = T;
};

}  // namespace descent
