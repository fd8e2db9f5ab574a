#pragma once
// cube_root(x): the real cube root that the element models take of det F
// (J^(-2/3) in neo-Hookean, Mooney-Rivlin and Fung), written so that a block
// of tets can take it with vector instructions. std::cbrt runs one value at a
// time (8-10 ns a call on the roofline machine) and was the largest single
// cost of those models' element pass.
//
// Steps, for |x| finite and nonzero:
//  1. scale |x| by an exact power of two into a range where y^3 stays finite
//     and normal (s = |x| 2^(3k), k = 0 or +-200 in double, +-20 in float);
//  2. first guess from the bits: the high 32-bit word divided by 3 plus a
//     constant that re-biases the exponent (about 3% off);
//  3. Halley's iteration as a correction, y -= y (y^3 - s) / (2 y^3 + s):
//     it triples the correct digits each step (3% -> 1e-5 -> 1e-15 -> done),
//     and since the correction is small its rounding stays below an ulp
//     (measured against long double: at most 0.95 ulp in double and in
//     float; glibc's cbrt: 3.2 ulp in double);
//  4. undo the scale (2^-k, exact) and put back the sign.
// Zero, infinities and NaN return x, so a NaN still reaches the checks that
// drive rollbacks.
//
// Lanes (kernels/cpu/lanes.hpp) runs these steps on vectors with the
// constants below; every lane equals this function bit for bit (all steps are
// exact or elementwise IEEE operations). Device code keeps CUDA's cbrt, which
// is already one instruction stream per thread.
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

#include "kernels/host_device.hpp"

namespace descent {

template <class T>
struct CubeRootSteps;

template <>
struct CubeRootSteps<double> {
  using Word = std::uint64_t;            // the bits of one value
  static constexpr int kHighShift = 32;  // the guess works on the high word
  static constexpr std::uint32_t kBias = 0x2A9F7893u;
  static constexpr double kScale = 0x1p600;      // |x| above scaled down, below 1/kScale up
  static constexpr double kRootScale = 0x1p200;  // cube root of kScale
  static constexpr int kHalleySteps = 3;
};

template <>
struct CubeRootSteps<float> {
  using Word = std::uint32_t;
  static constexpr int kHighShift = 0;  // a float is one 32-bit word
  static constexpr std::uint32_t kBias = 0x2A5137A0u;
  static constexpr float kScale = 0x1p60f;
  static constexpr float kRootScale = 0x1p20f;
  static constexpr int kHalleySteps = 2;
};

// Step 3 on any real type (T or Lanes of T): s > 0 normal, y its first guess.
template <class T, class Real>
DESCENT_HOST_DEVICE Real cube_root_halley(Real s, Real y) {
  for (int k = 0; k < CubeRootSteps<T>::kHalleySteps; ++k) {
    const Real y3 = y * y * y;
    y -= y * (y3 - s) / (Real(2) * y3 + s);
  }
  return y;
}

template <class T>
DESCENT_HOST_DEVICE T cube_root_scalar(T x) {
#if defined(__CUDA_ARCH__)
  return ::cbrt(x);
#else
  using Steps = CubeRootSteps<T>;
  using Word = typename Steps::Word;
  const T a = std::fabs(x);
  if (!(a > T(0)) || a == std::numeric_limits<T>::infinity()) return x;  // 0, NaN, inf
  const bool small = a < T(1) / Steps::kScale;
  const bool large = a > Steps::kScale;
  const T s = small ? a * Steps::kScale : large ? a * (T(1) / Steps::kScale) : a;
  Word bits;
  std::memcpy(&bits, &s, sizeof bits);
  const auto high = static_cast<std::uint32_t>(bits >> Steps::kHighShift);
  bits = static_cast<Word>(high / 3 + Steps::kBias) << Steps::kHighShift;
  T y;
  std::memcpy(&y, &bits, sizeof y);
  y = cube_root_halley<T>(s, y);
  y = small ? y * (T(1) / Steps::kRootScale) : large ? y * Steps::kRootScale : y;
  return std::copysign(y, x);
#endif
}

DESCENT_HOST_DEVICE inline double cube_root(double x) { return cube_root_scalar(x); }
DESCENT_HOST_DEVICE inline float cube_root(float x) { return cube_root_scalar(x); }

}  // namespace descent
