#pragma once
// Splitting a mesh across ranks: METIS_PartMeshDual on the tets (neighbours
// share a face: ncommon = 3), then each rank's local piece.
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "common/mesh.hpp"

namespace descent {

// Part (rank) of every tet, in [0, nparts). nparts == 1 needs no METIS.
// METIS failures throw MetisError naming the return code.
std::vector<int> partition_tets(const Mesh& mesh, int nparts);

// One rank's piece of the mesh.
//
// Local vertex order: [interior | shared owned | shared not owned], where
// shared means used by tets of more than one rank and the owner of a vertex
// is the lowest rank that uses it. So owned vertices are [0, num_owned) and
// shared vertices are [num_interior, num_vertices). Within each group,
// ascending global id.
// Local tet order: boundary tets (touching a shared vertex) first, then
// interior tets, each group by ascending global id, so the boundary can be
// computed first and its exchange overlapped with the interior.
struct LocalMesh {
  int rank = 0;
  int num_ranks = 1;

  std::vector<index_t> global_vertex;  // local -> global vertex id
  index_t num_interior = 0;
  index_t num_owned = 0;
  std::vector<double> rest_positions;  // xyz per local vertex

  std::vector<index_t> tets;  // 4 local vertex ids per local tet
  std::vector<index_t> global_tet;
  index_t num_boundary_tets = 0;

  // Neighbour ranks (ascending) and, per neighbour, the local ids of the
  // vertices shared with it in ascending global id (the same order on both
  // sides, so buffers line up without sending ids).
  std::vector<int> neighbours;
  std::vector<std::vector<index_t>> shared_with;

  // Vertex -> corner table (CSR): corners (4 t + a) of local vertex v at
  // vertex_corners[corner_offsets[v] .. corner_offsets[v + 1]), ascending.
  std::vector<index_t> corner_offsets;
  std::vector<index_t> vertex_corners;

  index_t num_vertices() const { return static_cast<index_t>(global_vertex.size()); }
  index_t num_tets() const { return static_cast<index_t>(global_tet.size()); }
  index_t num_shared() const { return num_vertices() - num_interior; }
};

// Distinct (vertex, rank) pairs of a partition, sorted: the ranks that use
// each vertex, ascending.
std::vector<std::pair<index_t, int>> vertex_users(const Mesh& mesh, std::span<const int> tet_part);

LocalMesh build_local_mesh(const Mesh& mesh, std::span<const int> tet_part, int rank,
                           int num_ranks);

// How good a partition is, for the log.
struct PartitionQuality {
  std::vector<index_t> tets_per_rank;
  std::vector<index_t> shared_vertices_per_rank;
  index_t cut_faces = 0;   // interior faces whose two tets lie on different ranks
  double imbalance = 1.0;  // max tets per rank / mean
};

PartitionQuality partition_quality(const Mesh& mesh, std::span<const int> tet_part, int nparts);
std::string describe(const PartitionQuality& quality);

}  // namespace descent
