#pragma once
// One rank's piece of the mesh, with everything its halo needs.
//
// Local vertex order: [interior | shared owned | shared not owned], where
// shared means used by tets of more than one rank and the owner of a vertex
// is the lowest rank that uses it. So owned vertices are [0, num_owned) and
// shared vertices are [num_interior, num_vertices). Within each group,
// ascending global id as built; partition.reorder may renumber each group
// within itself for locality (partition/local_order.hpp).
// Local tet order: boundary tets (touching a shared vertex) first, then
// interior tets, so the boundary can be computed first and its exchange
// overlapped with the interior; each group by ascending global id as built,
// or by lowest local corner once reordered.
#include <algorithm>
#include <cstdint>
#include <vector>

#include "common/mesh.hpp"

namespace descent {

struct LocalMesh {
  int rank = 0;
  int num_ranks = 1;
  global_index_t num_global_vertices = 0;  // of the whole mesh, unused vertices included
  global_index_t num_global_tets = 0;

  std::vector<global_index_t> global_vertex;  // local -> global vertex id
  index_t num_interior = 0;
  index_t num_owned = 0;
  std::vector<double> rest_positions;  // xyz per local vertex
  // Global vertex ids of each body (Mesh::body_vertex_offsets): body b holds
  // [body_vertex_offsets[b], body_vertex_offsets[b + 1]); empty: one body.
  std::vector<global_index_t> body_vertex_offsets;

  std::vector<index_t> tets;  // 4 local vertex ids per local tet, positively oriented
  std::vector<global_index_t> global_tet;
  index_t num_boundary_tets = 0;
  // Per local tet, bit f set: face f (kTetFaces[f], opposite corner f) lies
  // on the body's surface (no other tet of the whole mesh has it).
  std::vector<std::uint8_t> surface_faces;

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
  int num_bodies() const {
    return body_vertex_offsets.empty() ? 1 : static_cast<int>(body_vertex_offsets.size()) - 1;
  }
};

// Fills mesh.corner_offsets and mesh.vertex_corners from mesh.tets.
void build_vertex_corners(LocalMesh& mesh);

// The body of global vertex `id` of a mesh with these body offsets
// (LocalMesh::body_vertex_offsets; 0 when empty).
inline int body_of_vertex(const std::vector<global_index_t>& offsets, global_index_t id) {
  if (offsets.empty()) return 0;
  return static_cast<int>(std::upper_bound(offsets.begin(), offsets.end(), id) - offsets.begin()) -
         1;
}

// The body of each local vertex (all 0 for a mesh that is one body).
inline std::vector<int> vertex_bodies(const LocalMesh& mesh) {
  std::vector<int> body(mesh.num_vertices(), 0);
  for (index_t v = 0; v < mesh.num_vertices(); ++v)
    body[v] = body_of_vertex(mesh.body_vertex_offsets, mesh.global_vertex[v]);
  return body;
}

}  // namespace descent
