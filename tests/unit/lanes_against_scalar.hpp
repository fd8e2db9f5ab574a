#pragma once
// Test helper: a math function's vector form in Lanes (kernels/cpu/lanes.hpp)
// against its scalar form, bit for bit in every lane, with special values
// scattered among the inputs and one block made of them; shared by the cube
// root and exponential tests.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <iterator>
#include <random>
#include <vector>

#include "kernels/cpu/lanes.hpp"

namespace descent::testing {

template <class T>
bool same_bits(T a, T b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

// `values` (a multiple of the lane width) with each of `specials` put at a
// random place and all of them at the start, then every block of lanes
// through `lanes` against `scalar` value by value (NaN matches NaN).
template <class T, std::size_t N, class LaneFunction, class ScalarFunction>
void expect_lanes_equal_scalar(std::vector<T> values, const T (&specials)[N], LaneFunction lanes,
                               ScalarFunction scalar) {
  constexpr int kW = kLaneWidth<T>;
  std::mt19937_64 rng(3);
  for (const T s : specials) values[rng() % values.size()] = s;
  for (std::size_t i = 0; i < N; ++i) values[i] = specials[i];
  for (std::size_t b = 0; b < values.size(); b += kW) {
    Lanes<T, kW> x;
    for (int l = 0; l < kW; ++l) x.v[l] = values[b + l];
    const Lanes<T, kW> y = lanes(x);
    for (int l = 0; l < kW; ++l) {
      const T expected = scalar(values[b + l]);
      ASSERT_TRUE(same_bits(y.v[l], expected) || (std::isnan(y.v[l]) && std::isnan(expected)))
          << "x = " << values[b + l] << ": lanes " << y.v[l] << ", scalar " << expected;
    }
  }
}

}  // namespace descent::testing
