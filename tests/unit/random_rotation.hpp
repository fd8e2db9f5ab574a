#pragma once
// Test helper: rotations drawn uniformly over SO(3), shared by the model and
// SVD tests.
#include <cmath>
#include <random>

#include "kernels/mat3.hpp"

namespace descent::testing {

// From a normalised Gaussian quaternion.
inline Mat3<double> random_rotation(std::mt19937_64& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  double w = n(rng), x = n(rng), y = n(rng), z = n(rng);
  const double len = std::sqrt(w * w + x * x + y * y + z * z);
  w /= len, x /= len, y /= len, z /= len;
  return {{1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y), 2 * (x * y + w * z),
           1 - 2 * (x * x + z * z), 2 * (y * z - w * x), 2 * (x * z - w * y), 2 * (y * z + w * x),
           1 - 2 * (x * x + y * y)}};
}

}  // namespace descent::testing
