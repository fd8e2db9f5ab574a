#pragma once
// A whole tetrahedral mesh as read from a file or made by a generator, before
// partitioning. Layout: positions is xyz-interleaved (3 * num_vertices doubles,
// SI metres); tets holds 4 zero-based vertex indices per tet, each positively
// oriented (det[x1-x0, x2-x0, x3-x0] > 0) once a reader has validated it.
#include <cstdint>
#include <string>
#include <vector>

namespace descent {

// Indices within one rank's data (local vertices, local tets, and the
// whole Mesh a serial reader or test holds): 32-bit keeps the per-tet arrays
// of the hot loops small. Ids of the global mesh, which a cluster run can
// take past 2^31 tets, are global_index_t.
using index_t = std::int32_t;
using global_index_t = std::int64_t;

// The four faces of a tet as corner indices, opposite corners 0..3, each
// ordered counter-clockwise seen from outside a positively oriented tet.
inline constexpr int kTetFaces[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};

struct Mesh {
  std::vector<double> positions;
  std::vector<index_t> tets;
  std::string source;  // file name or generator description, for messages
  // A scene of several bodies ([[body]]): body b's vertices are
  // [body_vertex_offsets[b], body_vertex_offsets[b + 1]) (its tets use only
  // those); empty for a mesh that is one body.
  std::vector<global_index_t> body_vertex_offsets;

  index_t num_vertices() const { return static_cast<index_t>(positions.size() / 3); }
  index_t num_tets() const { return static_cast<index_t>(tets.size() / 4); }
};

}  // namespace descent
