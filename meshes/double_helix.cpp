// The double helix generator. The body is voxelized on a regular grid
// (double_helix_grid.hpp). Each body cell becomes six Kuhn tets
// (hex_split.hpp), so the mesh is conforming by construction and exactly
// reproducible.
#include <algorithm>
#include <cstdint>
#include <limits>
#include <vector>

#include "common/error.hpp"
#include "meshes/double_helix_grid.hpp"
#include "meshes/generators.hpp"
#include "meshes/hex_split.hpp"

namespace descent {
namespace {

using helix::Column;
using helix::Geometry;
using helix::Grid;

// 1 for cells whose centre lies in the body, else 0; indexed by Grid::cell.
std::vector<std::uint8_t> voxelize(const Grid& grid, const Geometry& g) {
  const std::vector<Column> columns = helix::columns_of(grid);
  std::vector<std::uint8_t> inside(grid.num_cells());
  for (index_t j = 0; j < grid.ny; ++j)
    helix::voxelize_layer(grid, g, columns, j,
                          inside.data() + std::size_t(j) * grid.cells_per_layer());
  return inside;
}

// Clears every body cell outside the largest face-connected component (the
// first found, in cell order, among equals). Voxelizing thin parts could
// leave islands; the presets have none.
void keep_largest_component(const Grid& grid, std::vector<std::uint8_t>& inside) {
  constexpr index_t kUnvisited = -1;
  std::vector<index_t> component(inside.size(), kUnvisited);
  std::vector<index_t> stack;
  index_t num_components = 0, largest = kUnvisited;
  std::int64_t largest_size = 0;
  for (index_t j = 0; j < grid.ny; ++j)
    for (index_t k = 0; k < grid.nz; ++k)
      for (index_t i = 0; i < grid.nx; ++i) {
        const index_t seed = grid.cell(i, j, k);
        if (!inside[seed] || component[seed] != kUnvisited) continue;
        const index_t id = num_components++;
        std::int64_t size = 0;
        component[seed] = id;
        stack.push_back(seed);
        while (!stack.empty()) {
          const index_t cell = stack.back();
          stack.pop_back();
          ++size;
          const index_t ci = cell % grid.nx, ck = (cell / grid.nx) % grid.nz,
                        cj = cell / (grid.nx * grid.nz);
          auto visit = [&](index_t ni, index_t nj, index_t nk) {
            const index_t neighbour = grid.cell(ni, nj, nk);
            if (inside[neighbour] && component[neighbour] == kUnvisited) {
              component[neighbour] = id;
              stack.push_back(neighbour);
            }
          };
          if (ci > 0) visit(ci - 1, cj, ck);
          if (ci + 1 < grid.nx) visit(ci + 1, cj, ck);
          if (cj > 0) visit(ci, cj - 1, ck);
          if (cj + 1 < grid.ny) visit(ci, cj + 1, ck);
          if (ck > 0) visit(ci, cj, ck - 1);
          if (ck + 1 < grid.nz) visit(ci, cj, ck + 1);
        }
        if (size > largest_size) {
          largest_size = size;
          largest = id;
        }
      }
  if (num_components <= 1) return;
  for (std::size_t cell = 0; cell < inside.size(); ++cell)
    if (component[cell] != largest) inside[cell] = 0;
}

// Corner c (numbered as in hex_split.hpp) of cell (i, j, k), as a grid node.
index_t corner_node(const Grid& grid, index_t i, index_t j, index_t k, int corner) {
  return grid.node(i + (corner & 1), j + ((corner >> 1) & 1), k + ((corner >> 2) & 1));
}

// Six Kuhn tets per body cell, on the grid nodes they use, numbered densely in
// grid node order; tets come in grid cell order.
Mesh tetrahedralize(const Grid& grid, const std::vector<std::uint8_t>& inside) {
  const std::int64_t num_body_cells = std::count(inside.begin(), inside.end(), 1);
  if (num_body_cells * 6 > std::numeric_limits<index_t>::max())
    throw InputError("mesh.helix.resolution is too high: more tets than a 32-bit index holds");

  constexpr index_t kUnused = -1;
  std::vector<index_t> vertex_of_node(grid.num_nodes(), kUnused);
  for (index_t j = 0; j < grid.ny; ++j)
    for (index_t k = 0; k < grid.nz; ++k)
      for (index_t i = 0; i < grid.nx; ++i)
        if (inside[grid.cell(i, j, k)])
          for (int corner = 0; corner < 8; ++corner)
            vertex_of_node[corner_node(grid, i, j, k, corner)] = 0;

  Mesh mesh;
  index_t num_vertices = 0;
  for (index_t j = 0; j <= grid.ny; ++j)
    for (index_t k = 0; k <= grid.nz; ++k)
      for (index_t i = 0; i <= grid.nx; ++i) {
        index_t& vertex = vertex_of_node[grid.node(i, j, k)];
        if (vertex == kUnused) continue;
        vertex = num_vertices++;
        mesh.positions.insert(mesh.positions.end(),
                              {grid.node_x(i), grid.node_y(j), grid.node_x(k)});
      }

  mesh.tets.reserve(std::size_t(num_body_cells) * 6 * 4);
  for (index_t j = 0; j < grid.ny; ++j)
    for (index_t k = 0; k < grid.nz; ++k)
      for (index_t i = 0; i < grid.nx; ++i) {
        if (!inside[grid.cell(i, j, k)]) continue;
        index_t corner_vertex[8];
        for (int corner = 0; corner < 8; ++corner)
          corner_vertex[corner] = vertex_of_node[corner_node(grid, i, j, k, corner)];
        for (const hex_split::TetCorners& tet : hex_split::kKuhnTets)
          for (int corner : tet) mesh.tets.push_back(corner_vertex[corner]);
      }
  return mesh;
}

}  // namespace

double double_helix_height(const DoubleHelixParams& params) {
  return params.turns * params.pitch + 4 * params.tube_radius;
}

double double_helix_preset_resolution(const std::string& name) {
  // Found by experiment with the default geometry. The grid size changes in
  // steps, so each value sits mid-way along its step; the comments give the
  // grid (cells across x and z, cells along y) and the tet count.
  if (name == "41k") return 2.42;   // 20 x 40: 40,872 tets (-0.3%)
  if (name == "82k") return 3.075;  // 25 x 51: 79,680 tets (-2.8%)
  if (name == "158k") return 3.8;   // 31 x 63: 154,656 tets (-2.1%)
  if (name == "316k") return 4.8;   // 40 x 79: 324,624 tets (+2.7%)
  throw InputError(detail::concat("unknown double helix preset '", name,
                                  "'; valid presets: 41k, 82k, 158k, 316k"));
}

Mesh make_double_helix(const DoubleHelixParams& params) {
  helix::validate(params);
  const Geometry g = helix::geometry_of(params);
  const Grid grid = helix::make_grid(params, g, helix::NodeIndexing::kWholeGrid);
  std::vector<std::uint8_t> inside = voxelize(grid, g);
  if (std::find(inside.begin(), inside.end(), 1) == inside.end())
    helix::throw_no_cell_in_body(params);
  keep_largest_component(grid, inside);
  Mesh mesh = tetrahedralize(grid, inside);
  mesh.source = helix::source_of(params);
  return mesh;
}

}  // namespace descent
