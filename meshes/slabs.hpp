#pragma once
// The cell layers of a grid split over the ranks of a communicator in slabs:
// rank r holds layers [first(), end()) of BlockRange(num_layers, P). Some
// slabs are empty when P exceeds the layer count; the last rank's never is.
// Per-slab data is stored layer by layer: layer j at (j - first()) * layer size.
#include <mpi.h>

#include <cstdint>
#include <vector>

#include "comm/mpi_check.hpp"
#include "common/block_range.hpp"
#include "common/mesh.hpp"

namespace descent {

class Slabs {
 public:
  Slabs(index_t num_layers, int rank, int num_ranks)
      : layers_(num_layers, num_ranks), rank_(rank) {}

  int rank() const { return rank_; }
  int num_ranks() const { return layers_.parts(); }
  index_t num_layers() const { return index_t(layers_.total()); }
  index_t first() const { return first_of(rank_); }
  index_t end() const { return end_of(rank_); }
  index_t size() const { return end() - first(); }
  bool empty() const { return size() == 0; }
  index_t first_of(int rank) const { return index_t(layers_.begin(rank)); }
  index_t end_of(int rank) const { return index_t(layers_.end(rank)); }
  // The rank whose slab holds `layer`, for 0 <= layer < num_layers().
  int owner(index_t layer) const { return layers_.owner(layer); }

 private:
  BlockRange layers_;
  int rank_;
};

template <class T>
MPI_Datatype mpi_type_of();
template <>
inline MPI_Datatype mpi_type_of<std::uint8_t>() {
  return MPI_UINT8_T;
}
template <>
inline MPI_Datatype mpi_type_of<std::int64_t>() {
  return MPI_INT64_T;
}

// Collective: sends `top_layer` (layer_size values of this slab's last layer)
// to the rank holding the next layer up, and returns the same values of the
// layer just below this slab from the rank holding it; empty when there is no
// layer below (an empty slab, or one starting at layer 0). A shift along the
// slabs, so each rank talks to its two neighbouring non-empty slabs only.
template <class T>
std::vector<T> layer_from_below(MPI_Comm comm, const Slabs& slabs, const T* top_layer,
                                index_t layer_size) {
  const bool has_above = !slabs.empty() && slabs.end() < slabs.num_layers();
  const bool has_below = !slabs.empty() && slabs.first() > 0;
  std::vector<T> below(has_below ? layer_size : 0);
  const int above_rank = has_above ? slabs.owner(slabs.end()) : MPI_PROC_NULL;
  const int below_rank = has_below ? slabs.owner(slabs.first() - 1) : MPI_PROC_NULL;
  constexpr int kTag = 0;
  DESCENT_MPI_CHECK(MPI_Sendrecv(top_layer, has_above ? layer_size : 0, mpi_type_of<T>(),
                                 above_rank, kTag, below.data(), int(below.size()),
                                 mpi_type_of<T>(), below_rank, kTag, comm, MPI_STATUS_IGNORE));
  return below;
}

}  // namespace descent
