#pragma once
// Layers of per-cell bytes that one rank needs from the slabs (slabs.hpp) of
// other ranks, fetched in one MPI_Alltoallv with a whole layer as the unit.
#include <mpi.h>

#include <cstdint>
#include <vector>

#include "common/mesh.hpp"
#include "meshes/slabs.hpp"

namespace descent {

// Cell layers [first, end).
struct LayerSpan {
  index_t first = 0, end = 0;
};

class FetchedLayers {
 public:
  // Collective. `slab` holds this rank's layers (layout as in slabs.hpp);
  // needed[r] lists the layers rank r needs as disjoint ascending spans.
  FetchedLayers(MPI_Comm comm, const Slabs& slabs, index_t layer_size,
                const std::vector<std::uint8_t>& slab,
                const std::vector<std::vector<LayerSpan>>& needed);

  // Layer j, or nullptr when j lies outside the grid (no cells there).
  // Throws LogicError for a layer inside the grid that was not fetched.
  const std::uint8_t* layer(index_t j) const;
  std::size_t num_layers() const { return ids_.size(); }

 private:
  index_t num_grid_layers_, layer_size_;
  std::vector<index_t> ids_;         // ascending
  std::vector<std::uint8_t> cells_;  // layer ids_[n] at n * layer_size_
};

}  // namespace descent
