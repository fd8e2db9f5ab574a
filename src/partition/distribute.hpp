#pragma once
// From MeshSlices to LocalMeshes: the tets move to the ranks of their parts,
// each part asks the ranks holding the vertex blocks for its vertices (their
// positions and the parts sharing each), and the local meshes are built from
// what arrived. No rank holds more than its slice and its parts.
//
// A part belongs to rank BlockRange(num_parts, ranks).owner(part): in a run
// there is one part per rank (part = rank); `descent partition` may make
// more parts than it runs ranks.
#include <mpi.h>

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "common/mesh_slice.hpp"
#include "partition/dual_graph.hpp"
#include "partition/graph_partition.hpp"
#include "partition/local_mesh.hpp"
#include "partition/partition_quality.hpp"
#include "partition/partition_spec.hpp"

namespace descent {

// The tets of one part: ascending global ids; 4 global vertex ids per tet in
// the input's order; surface_faces as in DualGraph::boundary_faces.
struct PartTets {
  int part = 0;
  std::vector<global_index_t> ids;
  std::vector<global_index_t> vertices;
  std::vector<std::uint8_t> surface_faces;

  index_t num_tets() const { return static_cast<index_t>(ids.size()); }
};

// The vertices one part's tets use. Layout: ids ascending; corners[4 t + a]
// indexes ids for corner a of the part's tet t; positions xyz per id; the
// parts using ids[k] (this one included) at sharers[sharer_offsets[k] ..
// sharer_offsets[k + 1]), ascending.
struct PartVertices {
  std::vector<global_index_t> ids;
  std::vector<index_t> corners;
  std::vector<double> positions;
  std::vector<index_t> sharer_offsets;
  std::vector<int> sharers;
};

// Vertices of this rank's vertex block that no tet uses (a mesh file may
// hold some): kept, and written at rest.
struct UnusedVertices {
  std::vector<global_index_t> ids;
  std::vector<double> positions;  // xyz per id
};

// The parts this rank holds, ascending.
std::vector<int> parts_of_rank(int rank, int ranks, int num_parts);

// Collective: every tet of the slice goes to the rank of its part (part[t]
// for the slice's tet t); returns this rank's parts in parts_of_rank order.
std::vector<PartTets> migrate_tets(MPI_Comm comm, const MeshSlice& slice,
                                   const std::vector<std::uint8_t>& surface_faces,
                                   std::span<const int> part, int num_parts);

// Collective: the vertices of each part this rank holds, answered by the
// ranks holding the vertex blocks. `block_positions` is this rank's block
// (BlockRange(num_global_vertices, ranks)) of vertex positions; the block's
// vertices that no part asked for go to `unused`.
std::vector<PartVertices> gather_part_vertices(MPI_Comm comm, std::span<const PartTets> parts,
                                               global_index_t num_global_vertices,
                                               global_index_t first_vertex,
                                               std::span<const double> block_positions,
                                               UnusedVertices* unused);

// One part's LocalMesh (rank = part, num_ranks = num_parts). Tets negatively
// oriented in the input are flipped (two corners swapped) and counted in
// *reoriented; a flat tet, or one too large for doubles, is an InputError
// naming `source` and the tet.
LocalMesh build_local_mesh(const PartTets& tets, const PartVertices& vertices, int num_parts,
                           global_index_t num_global_vertices, global_index_t num_global_tets,
                           const std::string& source, index_t* reoriented);

// Wall seconds of each set-up phase on this rank, for the log and the
// benchmarks.
// face_matching: the surface and the cut found after migration
// (partition.method = "rcb", which skips the dual graph).
struct SetupSeconds {
  double dual_graph = 0, partition = 0, migration = 0, vertices = 0, face_matching = 0,
         local_mesh = 0, local_order = 0;
};

// Everything a rank of a run needs of the mesh.
struct DistributedMesh {
  LocalMesh local;
  UnusedVertices unused;  // of this rank's vertex block, for the frame writer
  PartitionQuality quality;
  PartitionMethod method = PartitionMethod::metis;
  global_index_t reoriented_tets = 0;  // over all ranks
  global_index_t unused_vertices = 0;  // over all ranks
  std::string source;
  SetupSeconds seconds;
};

// Collective, one part per rank: the part's vertices asked from the ranks
// holding the vertex blocks (this rank's is `block_positions`, from
// `first_vertex`), its LocalMesh built and validated (an InputError on any
// rank ends every rank) and renumbered as `reorder` (PartitionSpec::reorder)
// says, and the counts of re-oriented tets and unused vertices summed; fills
// those members of `mesh`. With `cut_faces`, the tets' surface faces are
// found first (match_part_faces: a partition made without the dual graph)
// and the faces between parts stored there.
void assemble_local_mesh(MPI_Comm comm, PartTets& tets, global_index_t num_vertices,
                         global_index_t num_tets, global_index_t first_vertex,
                         std::span<const double> block_positions, const std::string& reorder,
                         DistributedMesh& mesh, global_index_t* cut_faces = nullptr);

// Collective: the whole set-up from slices, one part per rank of comm,
// partitioned as `spec` says (choose_partition_method, partition_dual_graph).
// The slice is taken by value: its arrays are freed as soon as their data
// has moved on.
DistributedMesh distribute_mesh(MPI_Comm comm, MeshSlice slice, const PartitionSpec& spec);

// The same from a whole mesh every rank holds (tests, small tools): each
// rank takes its slice of it.
DistributedMesh distribute_mesh(MPI_Comm comm, const Mesh& mesh, const PartitionSpec& spec);

}  // namespace descent
