#pragma once
// Test helper: the length scale that position tolerances are stated in.
#include <algorithm>
#include <cmath>

#include "common/mesh.hpp"

namespace descent::testing {

// Diagonal of the axis-aligned bounding box of the mesh's positions.
inline double bounding_box_diagonal(const Mesh& mesh) {
  double lo[3] = {1e300, 1e300, 1e300}, hi[3] = {-1e300, -1e300, -1e300};
  for (std::size_t k = 0; k < mesh.positions.size(); ++k) {
    lo[k % 3] = std::min(lo[k % 3], mesh.positions[k]);
    hi[k % 3] = std::max(hi[k % 3], mesh.positions[k]);
  }
  double d2 = 0;
  for (int i = 0; i < 3; ++i) d2 += (hi[i] - lo[i]) * (hi[i] - lo[i]);
  return std::sqrt(d2);
}

}  // namespace descent::testing
