#pragma once
// One rank's share of a global mesh as it comes in, before partitioning:
// the block of tets and the block of vertices that BlockRange gives this
// rank (mesh files are read, and generators generate, block by block, so no
// rank ever holds the whole mesh). Ids are the input's, 0-based; tets refer
// to vertices of any block.
//
// Layout: tets holds 4 global vertex ids per tet, for global tets
// [first_tet, first_tet + num_tets()); positions holds xyz (metres) of the
// global vertices [first_vertex, first_vertex + num_vertices()).
#include <string>
#include <vector>

#include "common/block_range.hpp"
#include "common/mesh.hpp"

namespace descent {

struct MeshSlice {
  std::string source;  // file name or generator description, for messages
  global_index_t num_global_vertices = 0;
  global_index_t num_global_tets = 0;
  global_index_t first_tet = 0;
  std::vector<global_index_t> tets;
  global_index_t first_vertex = 0;
  std::vector<double> positions;
  std::vector<global_index_t> body_vertex_offsets;  // as Mesh's, whole on every rank

  index_t num_tets() const { return static_cast<index_t>(tets.size() / 4); }
  index_t num_vertices() const { return static_cast<index_t>(positions.size() / 3); }
};

// Block `rank` of `size` of a whole mesh (tests, and meshes a serial reader
// has read on one rank).
inline MeshSlice slice_of(const Mesh& mesh, int rank, int size) {
  const BlockRange tets(mesh.num_tets(), size), vertices(mesh.num_vertices(), size);
  MeshSlice slice;
  slice.source = mesh.source;
  slice.body_vertex_offsets = mesh.body_vertex_offsets;
  slice.num_global_vertices = mesh.num_vertices();
  slice.num_global_tets = mesh.num_tets();
  slice.first_tet = tets.begin(rank);
  slice.tets.assign(mesh.tets.begin() + 4 * tets.begin(rank),
                    mesh.tets.begin() + 4 * tets.end(rank));
  slice.first_vertex = vertices.begin(rank);
  slice.positions.assign(mesh.positions.begin() + 3 * vertices.begin(rank),
                         mesh.positions.begin() + 3 * vertices.end(rank));
  return slice;
}

}  // namespace descent
