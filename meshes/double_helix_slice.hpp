#pragma once
// The per-rank double helix generator (make_double_helix_slice) with an
// account of what it did on this rank, for the tests of its scalability and
// of its component filter.
#include <mpi.h>

#include <cstdint>

#include "common/mesh_slice.hpp"
#include "meshes/generators.hpp"

namespace descent::helix {

struct SliceWork {
  index_t nx = 0, ny = 0, nz = 0;        // the grid's cells per axis
  std::int64_t cells_voxelized = 0;      // by this rank: its slab of cell layers
  std::int64_t cell_layers_fetched = 0;  // of kept cells, to emit this rank's blocks
  std::int64_t num_components = 0;       // of the voxelized body, before the filter
  std::int64_t body_cells_dropped = 0;   // by the component filter, on all ranks
};

struct SliceAndWork {
  MeshSlice slice;
  SliceWork work;
};

// make_double_helix_slice and its account; collective over comm.
SliceAndWork make_slice_and_work(MPI_Comm comm, const DoubleHelixParams& params);

}  // namespace descent::helix
