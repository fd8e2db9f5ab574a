// Layers fetched from the slabs that hold them; see fetched_layers.hpp.
#include "meshes/fetched_layers.hpp"

#include <algorithm>

#include "comm/mpi_check.hpp"
#include "common/error.hpp"

namespace descent {
namespace {

LayerSpan overlap(const LayerSpan& span, index_t first, index_t end) {
  return {std::max(span.first, first), std::min(span.end, end)};
}

}  // namespace

FetchedLayers::FetchedLayers(MPI_Comm comm, const Slabs& slabs, index_t layer_size,
                             const std::vector<std::uint8_t>& slab,
                             const std::vector<std::vector<LayerSpan>>& needed)
    : num_grid_layers_(slabs.num_layers()), layer_size_(layer_size) {
  const int num_ranks = slabs.num_ranks();
  // Counts and offsets in layers.
  std::vector<int> send_counts(num_ranks, 0), send_offsets(num_ranks, 0);
  std::vector<int> recv_counts(num_ranks, 0), recv_offsets(num_ranks, 0);
  std::vector<std::uint8_t> send;
  for (int r = 0, num_sent = 0; r < num_ranks; ++r) {
    send_offsets[r] = num_sent;
    for (const LayerSpan& span : needed[r]) {
      const LayerSpan mine = overlap(span, slabs.first(), slabs.end());
      for (index_t j = mine.first; j < mine.end; ++j) {
        const auto layer = slab.begin() + std::size_t(j - slabs.first()) * layer_size;
        send.insert(send.end(), layer, layer + layer_size);
        ++send_counts[r];
        ++num_sent;
      }
    }
  }
  // Slabs ascend with the rank, so layers arrive in ascending order.
  for (int r = 0; r < num_ranks; ++r) {
    recv_offsets[r] = int(ids_.size());
    for (const LayerSpan& span : needed[slabs.rank()]) {
      const LayerSpan theirs = overlap(span, slabs.first_of(r), slabs.end_of(r));
      for (index_t j = theirs.first; j < theirs.end; ++j) ids_.push_back(j);
    }
    recv_counts[r] = int(ids_.size()) - recv_offsets[r];
  }
  cells_.resize(ids_.size() * std::size_t(layer_size));

  MPI_Datatype layer;
  DESCENT_MPI_CHECK(MPI_Type_contiguous(layer_size, MPI_UINT8_T, &layer));
  DESCENT_MPI_CHECK(MPI_Type_commit(&layer));
  const int code =
      MPI_Alltoallv(send.data(), send_counts.data(), send_offsets.data(), layer, cells_.data(),
                    recv_counts.data(), recv_offsets.data(), layer, comm);
  MPI_Type_free(&layer);
  DESCENT_MPI_CHECK(code);
}

const std::uint8_t* FetchedLayers::layer(index_t j) const {
  if (j < 0 || j >= num_grid_layers_) return nullptr;
  const auto it = std::lower_bound(ids_.begin(), ids_.end(), j);
  DESCENT_VERIFY(it != ids_.end() && *it == j, "cell layer ", j, " was not fetched");
  return cells_.data() + std::size_t(it - ids_.begin()) * layer_size_;
}

}  // namespace descent
