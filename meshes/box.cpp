// The box generator: a structured grid of hexahedral cells, each split into
// 5 or 6 tets (see hex_split.hpp and box_grid.hpp).
#include <cmath>
#include <cstdint>
#include <limits>

#include "common/error.hpp"
#include "meshes/box_grid.hpp"
#include "meshes/generators.hpp"
#include "meshes/hex_split.hpp"

namespace descent {
namespace {

constexpr const char* kAxisNames[3] = {"x", "y", "z"};

// The whole mesh is numbered in index_t.
void require_index_fits(const BoxParams& params) {
  const std::int64_t nx = params.cells[0], ny = params.cells[1], nz = params.cells[2];
  const double num_nodes = double(nx + 1) * double(ny + 1) * double(nz + 1);
  const double num_tets = double(nx) * double(ny) * double(nz) * params.tets_per_cell;
  if (num_nodes > std::numeric_limits<index_t>::max() ||
      num_tets > std::numeric_limits<index_t>::max())
    throw InputError(detail::concat("mesh.box.cells ", nx, " x ", ny, " x ", nz,
                                    " gives more tets or vertices than a 32-bit index holds"));
}

}  // namespace

namespace box {

void validate_values(const BoxParams& params) {
  for (int axis = 0; axis < 3; ++axis) {
    if (params.cells[axis] < 1)
      throw InputError(detail::concat("mesh.box.cells[", axis, "] (", kAxisNames[axis],
                                      ") must be >= 1, got ", params.cells[axis]));
    if (!std::isfinite(params.size[axis]) || !(params.size[axis] > 0))
      throw InputError(detail::concat("mesh.box.size[", axis, "] (", kAxisNames[axis],
                                      ") must be a finite number > 0, got ", params.size[axis]));
    if (!std::isfinite(params.origin[axis]))
      throw InputError(detail::concat("mesh.box.origin[", axis, "] (", kAxisNames[axis],
                                      ") must be finite, got ", params.origin[axis]));
  }
  if (params.tets_per_cell != 5 && params.tets_per_cell != 6)
    throw InputError(
        detail::concat("mesh.box.tets_per_cell must be 5 or 6, got ", params.tets_per_cell));
}

std::string source_of(const BoxParams& params) {
  return detail::concat("box ", params.cells[0], "x", params.cells[1], "x", params.cells[2],
                        " cells, ", params.tets_per_cell, " tets per cell");
}

}  // namespace box

Mesh make_box(const BoxParams& params) {
  box::validate_values(params);
  require_index_fits(params);
  const index_t nx = params.cells[0], ny = params.cells[1], nz = params.cells[2];
  auto node_index = [&](index_t i, index_t j, index_t k) {
    return (k * (ny + 1) + j) * (nx + 1) + i;
  };

  Mesh mesh;
  mesh.positions.reserve(3 * std::size_t(nx + 1) * (ny + 1) * (nz + 1));
  for (index_t k = 0; k <= nz; ++k)
    for (index_t j = 0; j <= ny; ++j)
      for (index_t i = 0; i <= nx; ++i)
        mesh.positions.insert(mesh.positions.end(),
                              {box::coordinate(params, 0, i), box::coordinate(params, 1, j),
                               box::coordinate(params, 2, k)});

  mesh.tets.reserve(4 * std::size_t(nx) * ny * nz * params.tets_per_cell);
  for (index_t k = 0; k < nz; ++k)
    for (index_t j = 0; j < ny; ++j)
      for (index_t i = 0; i < nx; ++i) {
        index_t corner_node[8];
        for (int corner = 0; corner < 8; ++corner)
          corner_node[corner] =
              node_index(i + (corner & 1), j + ((corner >> 1) & 1), k + ((corner >> 2) & 1));
        for (const hex_split::TetCorners& tet : box::split_of(params, i, j, k))
          for (int corner : tet) mesh.tets.push_back(corner_node[corner]);
      }

  mesh.source = box::source_of(params);
  return mesh;
}

}  // namespace descent
