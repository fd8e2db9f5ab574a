#pragma once
// Splits of one hexahedral grid cell into tets, shared by the generators.
// A cell corner is numbered a + 2b + 4c for its offset (a, b, c) in {0,1}^3
// along (x, y, z). Every tet listed is positively oriented on an axis-aligned
// cell with positive edge lengths (the orientation is fixed at compile time).
#include <array>
#include <cstddef>
#include <utility>

namespace descent::hex_split {

using TetCorners = std::array<int, 4>;

namespace detail {

constexpr int corner_offset(int corner, int axis) { return (corner >> axis) & 1; }

// Sign of det[c1 - c0, c2 - c0, c3 - c0] on the unit cube.
constexpr int orientation(const TetCorners& tet) {
  int e[3][3] = {};
  for (int row = 0; row < 3; ++row)
    for (int axis = 0; axis < 3; ++axis)
      e[row][axis] = corner_offset(tet[row + 1], axis) - corner_offset(tet[0], axis);
  const int det = e[0][0] * (e[1][1] * e[2][2] - e[1][2] * e[2][1]) -
                  e[0][1] * (e[1][0] * e[2][2] - e[1][2] * e[2][0]) +
                  e[0][2] * (e[1][0] * e[2][1] - e[1][1] * e[2][0]);
  return det > 0 ? 1 : (det < 0 ? -1 : 0);
}

template <std::size_t N>
constexpr std::array<TetCorners, N> oriented(std::array<TetCorners, N> tets) {
  for (TetCorners& tet : tets)
    if (orientation(tet) < 0) std::swap(tet[2], tet[3]);
  return tets;
}

// The same tets reflected through the plane x = 1/2 (corner a <-> 1 - a).
template <std::size_t N>
constexpr std::array<TetCorners, N> mirrored_in_x(std::array<TetCorners, N> tets) {
  for (TetCorners& tet : tets)
    for (int& corner : tet) corner ^= 1;
  return tets;
}

}  // namespace detail

// Kuhn (Freudenthal) split: six tets around the diagonal from corner 0 to
// corner 7, one per monotone path 0 -> e_a -> e_a + e_b -> 7. The same split
// in every cell of a grid is conforming.
inline constexpr std::array<TetCorners, 6> kKuhnTets = detail::oriented<6>({{
    {0, 1, 3, 7},  // x, then y, then z
    {0, 1, 5, 7},  // x, z, y
    {0, 2, 3, 7},  // y, x, z
    {0, 2, 6, 7},  // y, z, x
    {0, 4, 5, 7},  // z, x, y
    {0, 4, 6, 7},  // z, y, x
}});

// Five-tet split: a central tet on the corners of even a + b + c and one tet
// cutting off each odd corner. It draws each face diagonal between the face's
// even corners, so neighbouring cells conform only if they alternate: use
// kFiveTetsEven in cells with even i + j + k and kFiveTetsOdd (the mirror
// image) in the others; both then join the corners of even global parity.
inline constexpr std::array<TetCorners, 5> kFiveTetsEven = detail::oriented<5>({{
    {0, 3, 5, 6},  // central
    {1, 0, 3, 5},
    {2, 0, 3, 6},
    {4, 0, 5, 6},
    {7, 3, 5, 6},
}});
inline constexpr std::array<TetCorners, 5> kFiveTetsOdd =
    detail::oriented<5>(detail::mirrored_in_x<5>(kFiveTetsEven));

}  // namespace descent::hex_split
