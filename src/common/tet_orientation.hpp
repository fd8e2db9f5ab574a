#pragma once
// Whether a tet as listed is positively oriented, flat, or too large for
// double precision: the one test every reader and the distributed set-up
// apply before a tet reaches the solver.
#include <algorithm>
#include <array>
#include <cmath>
#include <string>

namespace descent {

enum class TetOrientation { positive, negative, flat, overflows };

// x[k] points at the xyz of corner k.
inline TetOrientation tet_orientation(const std::array<const double*, 4>& x) {
  // |det| below this times L^3 (L the longest edge) is rounding noise of a flat tet.
  constexpr double kFlatRelativeVolume = 1e-14;
  double longest_squared = 0;
  for (int a = 0; a < 4; ++a)
    for (int b = a + 1; b < 4; ++b) {
      const double dx = x[b][0] - x[a][0], dy = x[b][1] - x[a][1], dz = x[b][2] - x[a][2];
      longest_squared = std::max(longest_squared, dx * dx + dy * dy + dz * dz);
    }
  std::array<std::array<double, 3>, 3> e;  // edges from corner 0
  for (int k = 0; k < 3; ++k)
    for (int d = 0; d < 3; ++d) e[k][d] = x[k + 1][d] - x[0][d];
  const double det = e[0][0] * (e[1][1] * e[2][2] - e[1][2] * e[2][1]) -
                     e[0][1] * (e[1][0] * e[2][2] - e[1][2] * e[2][0]) +
                     e[0][2] * (e[1][0] * e[2][1] - e[1][1] * e[2][0]);
  const double longest = std::sqrt(longest_squared);
  // Coordinates near the double range make the volume overflow (inf, or NaN
  // from 0 * inf): no solver can use such a tet.
  if (!std::isfinite(det) || !std::isfinite(longest * longest * longest))
    return TetOrientation::overflows;
  if (std::abs(det) <= kFlatRelativeVolume * longest * longest * longest)
    return TetOrientation::flat;
  return det > 0 ? TetOrientation::positive : TetOrientation::negative;
}

// What is wrong with a flat or overflowing tet, for a message "tet N ...":
// "has zero volume: its vertices 1 2 3 4 are coplanar".
inline std::string bad_tet_description(TetOrientation orientation, const std::string& vertices) {
  return orientation == TetOrientation::flat
             ? "has zero volume: its vertices " + vertices + " are coplanar"
             : "has a volume that overflows double precision: its vertices " + vertices +
                   " are too far apart";
}

}  // namespace descent
