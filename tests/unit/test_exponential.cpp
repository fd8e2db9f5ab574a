// exponential (kernels/exponential.hpp) against the long double exp: within
// the ulps its header states over [kMinArg, kMaxArg] in double and in float
// (spread evenly, and densely near 0 where Fung's argument c3 (Ibar1 - 3)
// lives); NaN, the overflow and the flush to zero as stated; and its vector
// form in Lanes equals it bit for bit in every lane, specials mixed within
// one vector.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "kernels/cpu/lanes.hpp"
#include "kernels/exponential.hpp"
#include "lanes_against_scalar.hpp"

namespace descent {
namespace {

// Half of them uniform over the whole finite range, half within +-1 (the
// last in log2 down to 1e-12 of it, both signs).
template <class T>
std::vector<T> exponents(int n, std::uint64_t seed) {
  using Steps = ExponentialSteps<T>;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> whole(Steps::kMinArg, Steps::kMaxArg);
  std::uniform_real_distribution<double> small(-40, 0);
  std::vector<T> values(n);
  for (int i = 0; i < n; ++i) {
    const T x = i % 2 ? T(whole(rng)) : T(std::exp2(small(rng)));
    values[i] = i % 4 == 2 ? -x : x;
  }
  return values;
}

template <class T>
double ulps_from_exact(T y, T x) {
  const long double exact = std::exp(static_cast<long double>(x));
  const T nearest = static_cast<T>(exact);
  const long double ulp = std::nextafter(nearest, std::numeric_limits<T>::infinity()) - nearest;
  return double(std::fabs(static_cast<long double>(y) - exact) / ulp);
}

template <class T>
void within_stated_ulps(double stated) {
  double worst = 0;
  for (const T x : exponents<T>(400000, 7))
    worst = std::max(worst, ulps_from_exact(exponential(x), x));
  std::printf("[ exponential ] %s: worst %.3f ulp\n", sizeof(T) == 8 ? "double" : "float", worst);
  EXPECT_LT(worst, stated);
  for (const T x : {T(0), T(1), T(-1), T(0.5), T(1e-7), T(-1e-7), T(10), T(-10)})
    EXPECT_LT(ulps_from_exact(exponential(x), x), stated) << x;
  EXPECT_EQ(exponential(T(0)), T(1));
}

TEST(Exponential, DoubleWithinItsStatedUlps) { within_stated_ulps<double>(1.2); }
TEST(Exponential, FloatWithinItsStatedUlps) { within_stated_ulps<float>(1.2); }

template <class T>
void special_values() {
  using Steps = ExponentialSteps<T>;
  const T inf = std::numeric_limits<T>::infinity();
  EXPECT_TRUE(std::isnan(exponential(std::numeric_limits<T>::quiet_NaN())));
  EXPECT_EQ(exponential(inf), inf);
  EXPECT_EQ(exponential(-inf), T(0));
  EXPECT_EQ(exponential(std::nextafter(Steps::kMaxArg, inf)), inf);
  EXPECT_TRUE(std::isfinite(exponential(Steps::kMaxArg)));
  EXPECT_GT(exponential(Steps::kMaxArg), std::numeric_limits<T>::max() / 2);
  EXPECT_EQ(exponential(std::nextafter(Steps::kMinArg, -inf)), T(0));
  EXPECT_GE(exponential(Steps::kMinArg), std::numeric_limits<T>::min());
}

TEST(Exponential, DoubleSpecialValues) { special_values<double>(); }
TEST(Exponential, FloatSpecialValues) { special_values<float>(); }

template <class T>
void lanes_equal_scalar() {
  using Steps = ExponentialSteps<T>;
  constexpr int kW = kLaneWidth<T>;
  std::vector<T> values = exponents<T>(kW * 4000, 11);
  const T inf = std::numeric_limits<T>::infinity();
  const T specials[] = {T(0),
                        -T(0),
                        inf,
                        -inf,
                        std::numeric_limits<T>::quiet_NaN(),
                        Steps::kMaxArg,
                        std::nextafter(Steps::kMaxArg, inf),
                        Steps::kMinArg,
                        std::nextafter(Steps::kMinArg, -inf)};
  const auto f = [](auto x) { return exponential(x); };
  testing::expect_lanes_equal_scalar(values, specials, f, f);
}

TEST(Exponential, DoubleLanesEqualScalar) { lanes_equal_scalar<double>(); }
TEST(Exponential, FloatLanesEqualScalar) { lanes_equal_scalar<float>(); }

}  // namespace
}  // namespace descent
