#pragma once
// Personalised all-to-all of plain records (MPI_Alltoallv), the one way the
// set-up moves mesh data between ranks: faces to the rank that matches
// them, tets to their part, vertex requests to the rank holding the vertex.
// Header-only, so the partition library can use it without linking the
// solver's communication library (which itself depends on LocalMesh).
#include <mpi.h>

#include <climits>
#include <cstddef>
#include <type_traits>
#include <vector>

#include "comm/mpi_check.hpp"
#include "common/error.hpp"

namespace descent {

// Records bound for each rank, then sent in one exchange. Layout after
// pack(): records for rank 0, then rank 1, ...
template <class T>
class Outbox {
  static_assert(std::is_trivially_copyable_v<T>, "records travel as bytes");

 public:
  explicit Outbox(int num_ranks) : counts_(num_ranks, 0) {}

  // Two passes: count every record's destination, then place it.
  void count(int rank) { ++counts_[rank]; }
  void allocate() {
    offsets_.assign(counts_.size() + 1, 0);
    for (std::size_t r = 0; r < counts_.size(); ++r) offsets_[r + 1] = offsets_[r] + counts_[r];
    records_.resize(offsets_.back());
    next_.assign(offsets_.begin(), offsets_.end() - 1);
  }
  void place(int rank, const T& record) { records_[next_[rank]++] = record; }

  const std::vector<T>& records() const { return records_; }
  const std::vector<std::size_t>& counts() const { return counts_; }

 private:
  std::vector<std::size_t> counts_, offsets_, next_;
  std::vector<T> records_;
};

// What one exchange delivered: records from rank 0, then rank 1, ...;
// from_offsets[r] .. from_offsets[r + 1] came from rank r.
template <class T>
struct Inbox {
  std::vector<T> records;
  std::vector<std::size_t> from_offsets;
};

// Collective: every rank sends its outbox and receives what the others
// addressed to it. Counts and offsets travel as ints (MPI 3): more than
// INT_MAX records on one rank is refused by name rather than truncated.
template <class T>
Inbox<T> exchange(MPI_Comm comm, const std::vector<T>& records,
                  const std::vector<std::size_t>& counts) {
  const int size = static_cast<int>(counts.size());
  std::vector<int> send_counts(size), send_offsets(size), recv_counts(size), recv_offsets(size);
  std::size_t total = 0;
  for (int r = 0; r < size; ++r) {
    if (total > INT_MAX || counts[r] > INT_MAX - total)
      throw MpiError(detail::concat("exchange: more than ", INT_MAX,
                                    " records leave one rank in one MPI_Alltoallv"));
    send_counts[r] = static_cast<int>(counts[r]);
    send_offsets[r] = static_cast<int>(total);
    total += counts[r];
  }
  DESCENT_MPI_CHECK(
      MPI_Alltoall(send_counts.data(), 1, MPI_INT, recv_counts.data(), 1, MPI_INT, comm));
  Inbox<T> inbox;
  inbox.from_offsets.assign(size + 1, 0);
  for (int r = 0; r < size; ++r) {
    inbox.from_offsets[r + 1] = inbox.from_offsets[r] + static_cast<std::size_t>(recv_counts[r]);
    if (inbox.from_offsets[r] > INT_MAX)
      throw MpiError(detail::concat("exchange: more than ", INT_MAX,
                                    " records reach one rank in one MPI_Alltoallv"));
    recv_offsets[r] = static_cast<int>(inbox.from_offsets[r]);
  }
  inbox.records.resize(inbox.from_offsets.back());
  MPI_Datatype record;
  DESCENT_MPI_CHECK(MPI_Type_contiguous(static_cast<int>(sizeof(T)), MPI_BYTE, &record));
  DESCENT_MPI_CHECK(MPI_Type_commit(&record));
  const int code =
      MPI_Alltoallv(records.data(), send_counts.data(), send_offsets.data(), record,
                    inbox.records.data(), recv_counts.data(), recv_offsets.data(), record, comm);
  MPI_Type_free(&record);
  DESCENT_MPI_CHECK(code);
  return inbox;
}

template <class T>
Inbox<T> exchange(MPI_Comm comm, const Outbox<T>& outbox) {
  return exchange(comm, outbox.records(), outbox.counts());
}

}  // namespace descent
