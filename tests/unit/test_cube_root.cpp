// cube_root (kernels/cube_root.hpp) against the long double cube root: within
// one ulp over the whole range of double and of float, signs and the special
// values kept; and its vector form in Lanes equals it bit for bit in every
// lane, specials and scaled ranges mixed within one vector.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "kernels/cpu/lanes.hpp"
#include "kernels/cube_root.hpp"
#include "lanes_against_scalar.hpp"

namespace descent {
namespace {

// Values spread evenly in log2 over every normal and subnormal exponent,
// both signs.
template <class T>
std::vector<T> spread_values(int n, std::uint64_t seed) {
  const double lowest = std::log2(double(std::numeric_limits<T>::denorm_min()));
  const double highest = std::log2(double(std::numeric_limits<T>::max()));
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> exponent(lowest, highest);
  std::vector<T> values(n);
  for (int i = 0; i < n; ++i) {
    const T x = T(std::exp2(exponent(rng)));
    values[i] = i % 2 ? -x : x;
  }
  return values;
}

template <class T>
double ulps_from_exact(T root, T x) {
  const long double exact = std::cbrt(static_cast<long double>(x));
  const T nearest = static_cast<T>(exact);
  const long double ulp =
      std::nextafter(std::fabs(nearest), std::numeric_limits<T>::infinity()) - std::fabs(nearest);
  return double(std::fabs(static_cast<long double>(root) - exact) / ulp);
}

template <class T>
void within_one_ulp() {
  double worst = 0;
  for (const T x : spread_values<T>(400000, 7))
    worst = std::max(worst, ulps_from_exact(cube_root(x), x));
  EXPECT_LT(worst, 1.0);
  for (const T x : {T(1), T(8), T(0.125), T(27), T(1e-3)})
    EXPECT_LT(ulps_from_exact(cube_root(x), x), 1.0) << x;
}

TEST(CubeRoot, DoubleWithinOneUlp) { within_one_ulp<double>(); }
TEST(CubeRoot, FloatWithinOneUlp) { within_one_ulp<float>(); }

template <class T>
void special_values() {
  const T inf = std::numeric_limits<T>::infinity();
  EXPECT_EQ(cube_root(T(0)), T(0));
  EXPECT_FALSE(std::signbit(cube_root(T(0))));
  EXPECT_TRUE(std::signbit(cube_root(-T(0))));
  EXPECT_EQ(cube_root(inf), inf);
  EXPECT_EQ(cube_root(-inf), -inf);
  EXPECT_TRUE(std::isnan(cube_root(std::numeric_limits<T>::quiet_NaN())));
  EXPECT_EQ(cube_root(-T(8)), -T(2));
}

TEST(CubeRoot, DoubleSpecialValues) { special_values<double>(); }
TEST(CubeRoot, FloatSpecialValues) { special_values<float>(); }

template <class T>
void lanes_equal_scalar() {
  constexpr int kW = kLaneWidth<T>;
  std::vector<T> values = spread_values<T>(kW * 4000, 11);
  const T specials[] = {T(0),
                        -T(0),
                        std::numeric_limits<T>::infinity(),
                        -std::numeric_limits<T>::infinity(),
                        std::numeric_limits<T>::quiet_NaN(),
                        std::numeric_limits<T>::denorm_min(),
                        std::numeric_limits<T>::max(),
                        std::numeric_limits<T>::min(),
                        T(1)};
  const auto f = [](auto x) { return cube_root(x); };
  testing::expect_lanes_equal_scalar(values, specials, f, f);
}

TEST(CubeRoot, DoubleLanesEqualScalar) { lanes_equal_scalar<double>(); }
TEST(CubeRoot, FloatLanesEqualScalar) { lanes_equal_scalar<float>(); }

}  // namespace
}  // namespace descent
