#pragma once
// The double helix's geometry, grid and voxelization, shared by the serial
// generator (double_helix.cpp) and the per-rank slice generator
// (double_helix_slice.cpp): both decide every cell and place every node with
// the same compiled arithmetic, so their meshes agree bit for bit.
//
// Layout: the grid has nx x ny x nz cells over [-outer, outer] x [0, height] x
// [-outer, outer]. A layer is one j (y) of cells or of nodes; within a layer
// cells are numbered k * nx + i and nodes k * (nx + 1) + i (x fastest), and
// the whole grid stacks layers: cell (i, j, k) is (j * nz + k) * nx + i.
#include <cstdint>
#include <string>
#include <vector>

#include "common/mesh.hpp"
#include "meshes/generators.hpp"

namespace descent::helix {

// Strand 0 has the centreline (R cos t, cap + b t, -R sin t) for every real t
// (a right-handed helix about +y, clipped by the body's y-range), with
// R = helix_radius, b = pitch / 2pi and cap = cap_thickness; strand 1 is strand
// 0 turned by pi about the axis.
struct Geometry {
  double helix_radius;
  double tube_radius;
  double rise_per_radian;  // b
  double cap_thickness;
  double height;
  double outer_radius;  // of the caps and of the grid: helix_radius + tube_radius
};

Geometry geometry_of(const DoubleHelixParams& params);

// Throws InputError for non-positive or non-finite parameters and for tubes
// that would overlap (see DoubleHelixParams).
void validate(const DoubleHelixParams& params);

struct Grid {
  index_t nx, ny, nz;  // cells per axis
  double outer_radius, height;

  index_t cells_per_layer() const { return nx * nz; }
  index_t nodes_per_layer() const { return (nx + 1) * (nz + 1); }
  std::int64_t num_cells() const { return std::int64_t(nx) * ny * nz; }
  std::int64_t num_nodes() const { return std::int64_t(nx + 1) * (ny + 1) * (nz + 1); }
  // Whole-grid numbers in index_t: only for grids made with kWholeGrid.
  index_t cell(index_t i, index_t j, index_t k) const { return (j * nz + k) * nx + i; }
  index_t node(index_t i, index_t j, index_t k) const { return (j * (nz + 1) + k) * (nx + 1) + i; }
  // Coordinates of node i along x (or z), j along y; exact and symmetric at the ends.
  double node_x(index_t i) const { return outer_radius * (double(2 * i - nx) / nx); }
  double node_y(index_t j) const { return height * (double(j) / ny); }
  double centre_x(index_t i) const { return outer_radius * (double(2 * i + 1 - nx) / nx); }
  double centre_y(index_t j) const { return height * ((j + 0.5) / ny); }
};

// What one index_t has to number: every node of the grid (the serial
// generator), or the nodes of one layer (the slice generator, which numbers
// across layers in 64 bits).
enum class NodeIndexing { kWholeGrid, kOneLayer };

// Near-cubic cells of edge about tube_radius / resolution. Throws InputError
// naming mesh.helix.resolution when the nodes `indexing` asks for would not
// fit an index_t.
Grid make_grid(const DoubleHelixParams& params, const Geometry& g, NodeIndexing indexing);

// A column of cells (fixed i, k) in polar form: its centre is
// (rho cos angle, y, -rho sin angle), as on the strands. Layout k * nx + i.
struct Column {
  double rho;
  double angle;
};
std::vector<Column> columns_of(const Grid& grid);

// Writes 1 for each cell of layer j whose centre lies in the body, else 0,
// to layer[k * nx + i].
void voxelize_layer(const Grid& grid, const Geometry& g, const std::vector<Column>& columns,
                    index_t j, std::uint8_t* layer);

// The InputError both generators throw when no cell has its centre in the body.
[[noreturn]] void throw_no_cell_in_body(const DoubleHelixParams& params);

// The mesh's `source`: the generator and its parameters.
std::string source_of(const DoubleHelixParams& params);

}  // namespace descent::helix
