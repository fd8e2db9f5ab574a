#pragma once
// This process's rank in MPI_COMM_WORLD and their count, for tests that print
// or check on rank 0.
#include <mpi.h>

namespace descent::testing {

inline int world_rank() {
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  return rank;
}

inline int world_size() {
  int size = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  return size;
}

}  // namespace descent::testing
