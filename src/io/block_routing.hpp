#pragma once
// Rows of a global array that ranks hold in any order and number by global id,
// moved to the rank whose BlockRange block holds each id and placed there in
// id order, so that every rank can write its block as one contiguous
// hyperslab. The plan (where each row goes, where each arrival lands) is made
// once; each later move is one MPI_Alltoallv with the planned counts.
#include <mpi.h>

#include <cstddef>
#include <cstring>
#include <span>
#include <type_traits>
#include <vector>

#include "common/block_range.hpp"

namespace descent {

class BlockRouting {
 public:
  // Collective over `comm`, which must outlive the routing. `ids` are the
  // global ids of this rank's rows, each in [0, blocks.total()) (the caller
  // checks: an id out of range has no block).
  BlockRouting(MPI_Comm comm, const BlockRange& blocks, std::span<const global_index_t> ids);

  // The same on every rank: whether the ranks' ids name each row of
  // [0, blocks.total()) exactly once.
  bool covers_each_row_once() const { return covers_each_row_once_; }

  // This rank's block: rows [first_row(), first_row() + num_rows()).
  global_index_t first_row() const { return first_row_; }
  global_index_t num_rows() const { return num_rows_; }

  // Collective: `rows` holds `width` values per row of this rank, in the order
  // of the ids given at construction; `block` receives `width` values per row
  // of this rank's block, in id order. Rows nobody sent are left as they were.
  template <class T>
  void route(std::span<const T> rows, int width, std::span<T> block) {
    static_assert(std::is_trivially_copyable_v<T>, "rows travel as bytes");
    const std::size_t row_bytes = width * sizeof(T);
    send_buffer_.resize(send_slot_.size() * row_bytes);
    for (std::size_t k = 0; k < send_slot_.size(); ++k)
      std::memcpy(&send_buffer_[send_slot_[k] * row_bytes], &rows[k * width], row_bytes);
    exchange_rows(row_bytes);
    for (std::size_t j = 0; j < block_row_.size(); ++j)
      std::memcpy(&block[block_row_[j] * width], &receive_buffer_[j * row_bytes], row_bytes);
  }

  // The same move, for callers that pack and unpack themselves (two arrays
  // in one message): row k of this rank goes to send_slot(k) of the send
  // buffer; arrival j of the receive buffer is row block_row(j) of the block.
  std::size_t num_sent() const { return send_slot_.size(); }
  std::size_t send_slot(std::size_t k) const { return send_slot_[k]; }
  std::size_t num_received() const { return block_row_.size(); }
  std::size_t block_row(std::size_t j) const { return block_row_[j]; }
  // Collective: sends send_buffer (num_sent() rows of row_bytes each) and
  // fills receive_buffer (num_received() rows).
  std::vector<std::byte>& send_buffer() { return send_buffer_; }
  const std::vector<std::byte>& receive_buffer() const { return receive_buffer_; }
  void exchange_rows(std::size_t row_bytes);

 private:
  MPI_Comm comm_;
  global_index_t first_row_ = 0;
  global_index_t num_rows_ = 0;
  bool covers_each_row_once_ = false;
  std::vector<std::size_t> send_slot_;  // per row of this rank: its place in the send buffer
  std::vector<std::size_t> block_row_;  // per arrival: its row in this rank's block
  // Rows per peer rank and where each peer's rows start, as MPI_Alltoallv takes them.
  std::vector<int> send_counts_, send_offsets_, receive_counts_, receive_offsets_;
  std::vector<std::byte> send_buffer_, receive_buffer_;
};

}  // namespace descent
