#pragma once
// Rank 0's string on every rank: its length, then its characters (none are
// sent for an empty string).
#include <mpi.h>

#include <string>

#include "comm/mpi_check.hpp"

namespace descent {

inline std::string broadcast_string(MPI_Comm comm, std::string value_on_rank0) {
  int length = static_cast<int>(value_on_rank0.size());
  DESCENT_MPI_CHECK(MPI_Bcast(&length, 1, MPI_INT, 0, comm));
  value_on_rank0.resize(length);
  if (length > 0) DESCENT_MPI_CHECK(MPI_Bcast(value_on_rank0.data(), length, MPI_CHAR, 0, comm));
  return value_on_rank0;
}

}  // namespace descent
