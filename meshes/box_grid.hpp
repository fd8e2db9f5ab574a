#pragma once
// The box's parameter checks, coordinates and cell splits, shared by the
// serial generator (box.cpp) and the per-rank slice generator (box_slice.cpp)
// so that both give the same mesh bit for bit.
//
// Layout: cell (i, j, k) is numbered (k * ny + j) * nx + i and node (i, j, k)
// (k * (ny + 1) + j) * (nx + 1) + i (x fastest, z slowest); the tets of a
// cell are consecutive, in cell order.
#include <span>
#include <string>

#include "common/mesh.hpp"
#include "meshes/generators.hpp"
#include "meshes/hex_split.hpp"

namespace descent::box {

// Throws InputError naming the key of a bad cell count, size, origin or
// tets_per_cell. The index width limits are each generator's own.
void validate_values(const BoxParams& params);

// The mesh's `source`: the generator and its cell counts.
std::string source_of(const BoxParams& params);

// Coordinate of node `node` along `axis`. node / cells is exact at both ends,
// so the faces lie exactly on origin and origin + size.
inline double coordinate(const BoxParams& params, int axis, global_index_t node) {
  return params.origin[axis] + params.size[axis] * (double(node) / params.cells[axis]);
}

// The tets of cell (i, j, k) as cell corners (hex_split.hpp): with 5 per cell
// the split alternates with the cell's parity, so neighbours conform.
inline std::span<const hex_split::TetCorners> split_of(const BoxParams& params, global_index_t i,
                                                       global_index_t j, global_index_t k) {
  if (params.tets_per_cell == 6) return hex_split::kKuhnTets;
  return (i + j + k) % 2 == 0 ? std::span<const hex_split::TetCorners>(hex_split::kFiveTetsEven)
                              : std::span<const hex_split::TetCorners>(hex_split::kFiveTetsOdd);
}

}  // namespace descent::box
