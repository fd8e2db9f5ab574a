#pragma once
// Partitioning the dual graph: a part for every tet, so that parts hold
// about equal numbers of tets and few faces lie between parts.
//
// Two partitioners: PT-Scotch partitions the distributed graph in parallel
// (no rank sees more than its slice); METIS, the quality reference, is
// serial: the graph is gathered on rank 0 of the communicator, partitioned
// there and the parts scattered back. "auto" takes METIS for meshes below
// kSerialPartitionLimit tets, where rank 0's share of the work and memory is
// small, and PT-Scotch above (METIS where descent was built without it).
#include <mpi.h>

#include <string>
#include <vector>

#include "partition/dual_graph.hpp"
#include "partition/partition_quality.hpp"

namespace descent {

// rcb: recursive coordinate bisection (partition/geometric_partition.hpp),
// which needs no dual graph.
enum class PartitionMethod { metis, ptscotch, rcb };

// The gathered graph at this size takes rank 0 about 10 MB and METIS well
// under a second; beyond it rank 0's memory and time stand out.
inline constexpr global_index_t kSerialPartitionLimit = 500'000;

// Whether this descent was built with PT-Scotch (Debian: libptscotch-dev).
bool have_ptscotch();

// "auto", "metis", "ptscotch" or "rcb" (scene key partition.method);
// "ptscotch" in a build without it is an InputError naming the package.
PartitionMethod choose_partition_method(const std::string& name, global_index_t num_tets);
const char* to_string(PartitionMethod method);

// The part in [0, nparts) of each tet of this rank's slice of the graph,
// and the faces between parts (over all ranks).
struct GraphPartition {
  std::vector<int> part;
  global_index_t cut_faces = 0;
};

// Collective: the best of `tries` partitions (the fewest faces between
// parts; METIS computes its tries itself, METIS_OPTION_NCUTS), the same on
// every run for the same mesh, rank count, nparts and tries. Every part
// gets at least one tet, or a PartitionError says which did not.
GraphPartition partition_dual_graph(MPI_Comm comm, const DualGraph& graph, int nparts,
                                    PartitionMethod method, int tries);

// The two partitioners behind it, for nparts >= 2. `seed` picks PT-Scotch's
// random sequence (its seeds 2k and 2k + 1 agree: pass even ones).
std::vector<int> partition_with_metis(MPI_Comm comm, const DualGraph& graph, int nparts, int tries);
std::vector<int> partition_with_ptscotch(MPI_Comm comm, const DualGraph& graph, int nparts,
                                         int seed);

}  // namespace descent
