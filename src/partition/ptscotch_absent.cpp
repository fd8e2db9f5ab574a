// A build without PT-Scotch: METIS partitions every run.
#include "common/error.hpp"
#include "partition/graph_partition.hpp"

namespace descent {

bool have_ptscotch() { return false; }

std::vector<int> partition_with_ptscotch(MPI_Comm, const DualGraph&, int, int) {
  throw PartitionError(
      "this descent was built without PT-Scotch (Debian: libptscotch-dev); use "
      "partition.method = \"metis\"");
}

}  // namespace descent
