// The routing plan: each row's destination and send slot from BlockRange,
// the ids sent once through the exchange helper, their arrivals turned into
// block rows and counted to check that the ranks' rows cover each id once.
#include "io/block_routing.hpp"

#include "comm/exchange.hpp"
#include "comm/mpi_check.hpp"

namespace descent {

BlockRouting::BlockRouting(MPI_Comm comm, const BlockRange& blocks,
                           std::span<const global_index_t> ids)
    : comm_(comm) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  const int size = blocks.parts();
  first_row_ = blocks.begin(rank);
  num_rows_ = blocks.size(rank);

  // Send order: rows for rank 0, then rank 1, ..., each in the caller's order.
  std::vector<int> destination(ids.size());
  std::vector<std::size_t> counts(size, 0);
  for (std::size_t k = 0; k < ids.size(); ++k) ++counts[destination[k] = blocks.owner(ids[k])];
  std::vector<std::size_t> next(size, 0);
  for (int r = 1; r < size; ++r) next[r] = next[r - 1] + counts[r - 1];
  send_slot_.resize(ids.size());
  std::vector<global_index_t> ids_in_send_order(ids.size());
  for (std::size_t k = 0; k < ids.size(); ++k) {
    send_slot_[k] = next[destination[k]]++;
    ids_in_send_order[send_slot_[k]] = ids[k];
  }
  // The helper refuses counts past INT_MAX, so the int counts below hold.
  const Inbox<global_index_t> arrivals = exchange(comm, ids_in_send_order, counts);

  send_counts_.resize(size);
  send_offsets_.resize(size);
  receive_counts_.resize(size);
  receive_offsets_.resize(size);
  std::size_t sent = 0;
  for (int r = 0; r < size; ++r) {
    send_counts_[r] = static_cast<int>(counts[r]);
    send_offsets_[r] = static_cast<int>(sent);
    sent += counts[r];
    receive_counts_[r] = static_cast<int>(arrivals.from_offsets[r + 1] - arrivals.from_offsets[r]);
    receive_offsets_[r] = static_cast<int>(arrivals.from_offsets[r]);
  }

  block_row_.resize(arrivals.records.size());
  std::vector<char> seen(num_rows_, 0);
  bool once = arrivals.records.size() == static_cast<std::size_t>(num_rows_);
  for (std::size_t j = 0; j < arrivals.records.size(); ++j) {
    block_row_[j] = static_cast<std::size_t>(arrivals.records[j] - first_row_);
    once = once && seen[block_row_[j]] == 0;
    seen[block_row_[j]] = 1;
  }
  int once_everywhere = once ? 1 : 0;
  DESCENT_MPI_CHECK(MPI_Allreduce(MPI_IN_PLACE, &once_everywhere, 1, MPI_INT, MPI_MIN, comm));
  covers_each_row_once_ = once_everywhere == 1;
}

void BlockRouting::exchange_rows(std::size_t row_bytes) {
  receive_buffer_.resize(block_row_.size() * row_bytes);
  MPI_Datatype row;
  DESCENT_MPI_CHECK(MPI_Type_contiguous(static_cast<int>(row_bytes), MPI_BYTE, &row));
  DESCENT_MPI_CHECK(MPI_Type_commit(&row));
  const int code = MPI_Alltoallv(send_buffer_.data(), send_counts_.data(), send_offsets_.data(),
                                 row, receive_buffer_.data(), receive_counts_.data(),
                                 receive_offsets_.data(), row, comm_);
  MPI_Type_free(&row);
  DESCENT_MPI_CHECK(code);
}

}  // namespace descent
