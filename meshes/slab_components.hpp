#pragma once
// The largest face-connected component of a voxelized body held in slabs
// (slabs.hpp), found without gathering the body: each rank labels the
// components inside its slab, matches them with the slab below across the
// shared face, and every rank unites the small table of all slab components.
#include <mpi.h>

#include <cstdint>
#include <vector>

#include "meshes/double_helix_grid.hpp"
#include "meshes/slabs.hpp"

namespace descent::helix {

struct ComponentCensus {
  std::int64_t num_components = 0;      // of the whole body, before the filter
  std::int64_t body_cells_dropped = 0;  // outside the component kept, all slabs
};

// Collective. `inside` holds this slab's cells (1 in the body, else 0; layout
// (j - slabs.first()) * cells_per_layer + k * nx + i); on return only the
// cells of the body's largest component are 1. Among equals the component
// with the smallest cell index wins, as the serial generator's first found in
// cell order. A body with no cell has no component and stays empty.
ComponentCensus keep_largest_component(MPI_Comm comm, const Grid& grid, const Slabs& slabs,
                                       std::vector<std::uint8_t>& inside);

}  // namespace descent::helix
