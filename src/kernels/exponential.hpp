#pragma once
// exponential(x): the exp that Fung's model takes of its isochoric
// invariant (kernels/fung.hpp), written so that a block of tets can take it
// with vector instructions. std::exp runs one value at a time, and glibc's
// vector forms need -ffast-math, which the NaN checks that drive rollbacks
// forbid.
//
// Steps, for x in [kMinArg, kMaxArg]:
//  1. n = x log2(e) rounded to the nearest integer (adding and subtracting
//     1.5 2^mantissa rounds exactly in the current rounding mode);
//  2. r = x - n ln2 in two parts (Cody and Waite: n ln2_hi is exact, so r
//     keeps its low bits), |r| <= ln2 / 2;
//  3. exp(r) by its Taylor series to degree 13 in double (truncation 4e-18
//     relative at |r| = ln2 / 2) and 7 in float (5e-9), by Horner's rule;
//  4. times 2^n, as 2 exp(r) times 2^(n - 1) built from the exponent bits
//     (n - 1 stays a normal exponent over the whole range).
// Measured against long double over [kMinArg, kMaxArg] and densely near 0:
// at most 1.13 ulp in double and 1.15 in float (tests/unit/
// test_exponential.cpp holds both below 1.2); glibc's exp is within 1. NaN returns NaN (so a NaN
// still reaches the checks), above kMaxArg +inf, below kMinArg 0 (results under 3e-308 in double,
// 4e-38 in float, which flush to zero).
//
// Lanes (kernels/cpu/lanes.hpp) runs these steps on vectors with the
// constants below; every lane equals this function bit for bit (all steps are
// exact or elementwise IEEE operations, none contracted: -ffp-contract=off).
// Device code keeps CUDA's exp, already one instruction stream per thread.
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

#include "kernels/host_device.hpp"

namespace descent {

template <class T>
struct ExponentialSteps;

template <>
struct ExponentialSteps<double> {
  using Word = std::int64_t;  // the bits of one value
  static constexpr int kMantissaBits = 52;
  static constexpr int kExponentBias = 1023;
  static constexpr double kRound = 0x1.8p52;
  static constexpr double kLog2e = 0x1.71547652b82fep0;
  static constexpr double kLn2Hi = 0x1.62e42feep-1;  // 32 bits: n kLn2Hi is exact
  static constexpr double kLn2Lo = 0x1.a39ef35793c76p-33;
  static constexpr double kMaxArg = 709.782712893384;  // ln of the largest double
  static constexpr double kMinArg = -708.0;            // n - 1 >= -1022
  static constexpr int kDegree = 13;
};

template <>
struct ExponentialSteps<float> {
  using Word = std::int32_t;
  static constexpr int kMantissaBits = 23;
  static constexpr int kExponentBias = 127;
  static constexpr float kRound = 0x1.8p23f;
  static constexpr float kLog2e = 0x1.715476p0f;
  static constexpr float kLn2Hi = 0x1.62e4p-1f;  // 15 bits: n kLn2Hi is exact
  static constexpr float kLn2Lo = 0x1.7f7d1cp-20f;
  static constexpr float kMaxArg = 88.72283f;  // ln of the largest float
  static constexpr float kMinArg = -86.0f;     // n - 1 >= -126
  static constexpr int kDegree = 7;
};

// 1/k! for k = 0 .. kDegree, each rounded once (k! is exact in T for every
// k used: 13! < 2^53, 7! < 2^24), made at compile time.
template <class T>
struct InverseFactorials {
  T value[ExponentialSteps<T>::kDegree + 1] = {};
  constexpr InverseFactorials() {
    T factorial = T(1);
    for (int k = 0; k <= ExponentialSteps<T>::kDegree; ++k) {
      if (k > 1) factorial *= T(k);
      value[k] = T(1) / factorial;
    }
  }
};
template <class T>
inline constexpr InverseFactorials<T> kInverseFactorials{};

// Steps 1-3 on any real type (T or Lanes of T), x within [kMinArg,
// kMaxArg]: returns 2 exp(r) and sets n (an integer-valued real).
template <class T, class Real>
DESCENT_HOST_DEVICE Real exponential_reduced(Real x, Real& n) {
  using Steps = ExponentialSteps<T>;
  n = (x * Steps::kLog2e + Steps::kRound) - Steps::kRound;
  const Real r = (x - n * Steps::kLn2Hi) - n * Steps::kLn2Lo;
  const T* c = kInverseFactorials<T>.value;
  Real p = c[Steps::kDegree];
  for (int k = Steps::kDegree - 1; k >= 0; --k) p = p * r + c[k];
  return p * T(2);
}

// The bits of 2^(n - 1) for an integer n - 1 within the normal exponents.
template <class T, class Word>
DESCENT_HOST_DEVICE Word exponential_scale_bits(Word n) {
  using Steps = ExponentialSteps<T>;
  return (n + (Steps::kExponentBias - 1)) << Steps::kMantissaBits;
}

template <class T>
DESCENT_HOST_DEVICE T exponential_scalar(T x) {
#if defined(__CUDA_ARCH__)
  return ::exp(x);
#else
  using Steps = ExponentialSteps<T>;
  using Word = typename Steps::Word;
  if (x != x) return x;
  if (x > Steps::kMaxArg) return std::numeric_limits<T>::infinity();
  if (x < Steps::kMinArg) return T(0);
  T n;
  const T twice = exponential_reduced<T>(x, n);
  const Word bits = exponential_scale_bits<T>(static_cast<Word>(n));
  T scale;
  std::memcpy(&scale, &bits, sizeof scale);
  return twice * scale;
#endif
}

DESCENT_HOST_DEVICE inline double exponential(double x) { return exponential_scalar(x); }
DESCENT_HOST_DEVICE inline float exponential(float x) { return exponential_scalar(x); }

}  // namespace descent
