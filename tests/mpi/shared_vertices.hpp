#pragma once
// Test helper: shared vertices must be bitwise identical on all their sharers.
#include <mpi.h>

#include <cstring>
#include <vector>

#include "app/simulation.hpp"

namespace descent::testing {

// Number of shared vertices whose positions differ in any bit from a
// neighbour's copy (exchanged directly, by global-id order of the lists),
// summed over all ranks of comm.
inline int shared_mismatches(MPI_Comm comm, const Simulation<double>& sim) {
  const LocalMesh& l = sim.local_mesh();
  const auto& q = sim.state().q;
  std::vector<std::vector<double>> mine(l.neighbours.size()), theirs(l.neighbours.size());
  std::vector<MPI_Request> requests(2 * l.neighbours.size());
  for (std::size_t n = 0; n < l.neighbours.size(); ++n) {
    for (index_t v : l.shared_with[n])
      for (int i = 0; i < 3; ++i) mine[n].push_back(q[3 * v + i]);
    theirs[n].resize(mine[n].size());
    MPI_Irecv(theirs[n].data(), static_cast<int>(theirs[n].size()), MPI_DOUBLE, l.neighbours[n], 9,
              comm, &requests[n]);
  }
  for (std::size_t n = 0; n < l.neighbours.size(); ++n)
    MPI_Isend(mine[n].data(), static_cast<int>(mine[n].size()), MPI_DOUBLE, l.neighbours[n], 9,
              comm, &requests[l.neighbours.size() + n]);
  MPI_Waitall(static_cast<int>(requests.size()), requests.data(), MPI_STATUSES_IGNORE);
  int mismatches = 0;
  for (std::size_t n = 0; n < l.neighbours.size(); ++n)
    for (std::size_t k = 0; k < mine[n].size(); k += 3)
      if (std::memcmp(&mine[n][k], &theirs[n][k], 3 * sizeof(double)) != 0) ++mismatches;
  MPI_Allreduce(MPI_IN_PLACE, &mismatches, 1, MPI_INT, MPI_SUM, comm);
  return mismatches;
}

}  // namespace descent::testing
