#pragma once
// A partition made once (`descent partition`) and read by every later run
// on as many ranks as it has parts (`descent run --partition`).
//
// File layout (PIECES.h5): the mesh, as io/mesh_h5.hpp writes it
// (/mesh/positions, /mesh/tets, and PIECES.xdmf beside it), and
//   /partition/tet_offsets    int64 [P + 1, 1]  part p's tets are rows
//                             tet_offsets[p] .. tet_offsets[p + 1] of:
//   /partition/tet_ids        int64 [T, 1]      global tet ids, ascending in a part
//   /partition/tets           int64 [T, 4]      their vertex ids, as in /mesh/tets
//   /partition/surface_faces  uint8 [T, 1]      bit f: face f lies on the surface
//   /partition/part_stats     int64 [P, 4]      per part: tets, shared vertices,
//                             neighbours, shared (vertex, neighbour) pairs
// and attributes on /partition: num_parts, cut_faces (int64), imbalance
// (float64), method (string). A run reads its part's rows and its block of
// /mesh/positions, so no rank reads more than its share.
#include <mpi.h>

#include <string>
#include <vector>

#include "common/mesh_slice.hpp"
#include "partition/distribute.hpp"

namespace descent {

// Columns of /partition/part_stats (tets, shared vertices, neighbours,
// shared pairs).
constexpr int kPartStatsColumns = 4;

// Collective: writes the mesh (each rank its slice) and the parts each rank
// holds (parts_of_rank order) into PATH.partial/ and moves the file and its
// XDMF index to PATH at the end, so an interrupted write leaves no file
// that looks whole.
void write_partition_file(MPI_Comm comm, const std::string& path, const MeshSlice& slice,
                          const std::vector<PartTets>& held, int num_parts, PartitionMethod method,
                          const PartitionQuality& quality);

// This rank's piece of a partition file, and the rank's block of vertices.
struct PartitionPiece {
  PartTets tets;
  global_index_t num_global_vertices = 0, num_global_tets = 0;
  global_index_t first_vertex = 0;
  std::vector<double> block_positions;  // xyz of BlockRange(V, ranks) block
  PartitionQuality quality;
  std::string method;
};

// Collective, one part per rank of comm. A file made for another number of
// parts is an InputError naming both counts, on every rank.
PartitionPiece read_partition_piece(MPI_Comm comm, const std::string& path);

// Collective: the run's DistributedMesh from its piece (vertices asked from
// the ranks holding their blocks, the local mesh built, validated and
// renumbered as `reorder` says: PartitionSpec::reorder).
DistributedMesh distribute_piece(MPI_Comm comm, PartitionPiece piece, const std::string& source,
                                 const std::string& reorder);

}  // namespace descent
