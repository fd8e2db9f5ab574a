#pragma once
// How good a partition is, computed in parallel: tets, shared vertices,
// neighbours and halo size per part, and the faces between parts.
#include <mpi.h>

#include <span>
#include <string>
#include <vector>

#include "partition/dual_graph.hpp"
#include "partition/local_mesh.hpp"

namespace descent {

struct PartitionQuality {
  std::vector<global_index_t> tets_per_part;
  std::vector<global_index_t> shared_vertices_per_part;
  std::vector<int> neighbours_per_part;
  // Per part, the (vertex, neighbour) pairs it shares: the values one halo
  // exchange sends per vertex component (and receives).
  std::vector<global_index_t> shared_pairs_per_part;
  global_index_t cut_faces = 0;  // faces whose two tets lie in different parts
  double imbalance = 1.0;        // most tets in a part / mean
};

// Collective: faces of the dual graph between parts (part[t] for the
// graph's local tet t); each rank looks up the parts of the tets across its
// slice's edge from the ranks holding them.
global_index_t count_cut_faces(MPI_Comm comm, const DualGraph& graph, std::span<const int> part);

// Collective: the quality of the parts the ranks hold (each part on one
// rank, `held` this rank's), with the cut counted beforehand.
PartitionQuality partition_quality(MPI_Comm comm, std::span<const LocalMesh> held, int num_parts,
                                   global_index_t cut_faces);

// One line for the log; per-part figures listed for up to 16 parts, else
// their range.
std::string describe(const PartitionQuality& quality);

}  // namespace descent
