#pragma once
// Every rank's records, concatenated in rank order, on every rank
// (MPI_Allgatherv). For the small tables the slice generators share: per-layer
// counts and per-slab components, never mesh-sized data.
#include <mpi.h>

#include <climits>
#include <cstdint>
#include <type_traits>
#include <vector>

#include "comm/mpi_check.hpp"
#include "common/error.hpp"

namespace descent {

// Records are plain structs of int64 fields (or int64 values), sent as int64s.
template <class Record>
std::vector<Record> all_gather(MPI_Comm comm, const std::vector<Record>& mine) {
  static_assert(std::is_trivially_copyable_v<Record> && sizeof(Record) % sizeof(std::int64_t) == 0);
  constexpr std::size_t kWords = sizeof(Record) / sizeof(std::int64_t);
  int size = 1;
  DESCENT_MPI_CHECK(MPI_Comm_size(comm, &size));
  if (mine.size() > INT_MAX / kWords)
    throw MpiError(detail::concat("all_gather: ", mine.size(), " records on one rank"));
  const int my_words = static_cast<int>(mine.size() * kWords);
  std::vector<int> words(size), offsets(size);
  DESCENT_MPI_CHECK(MPI_Allgather(&my_words, 1, MPI_INT, words.data(), 1, MPI_INT, comm));
  long long total = 0;
  for (int r = 0; r < size; ++r) {
    offsets[r] = static_cast<int>(total);
    total += words[r];
    if (total > INT_MAX)
      throw MpiError(detail::concat("all_gather: more than ", INT_MAX, " words in all"));
  }
  std::vector<Record> all(static_cast<std::size_t>(total) / kWords);
  DESCENT_MPI_CHECK(MPI_Allgatherv(mine.data(), my_words, MPI_INT64_T, all.data(), words.data(),
                                   offsets.data(), MPI_INT64_T, comm));
  return all;
}

}  // namespace descent
