#pragma once
// The dual graph of a distributed mesh: tets are its vertices, and two tets
// are joined when they share a face (METIS's ncommon = 3). Built in
// parallel from the ranks' MeshSlices, distributed like them.
#include <mpi.h>

#include <cstdint>
#include <vector>

#include "common/mesh_slice.hpp"

namespace descent {

// Layout: CSR over the slice's tets (local tet t is global tet first_tet + t):
// the neighbours of t are neighbours[offsets[t] .. offsets[t + 1]), global
// tet ids ascending. Offsets are 64-bit: 4 entries per tet pass 2^31 at 537M
// tets. surface_faces[t] has bit f set when face f of t (kTetFaces[f], the
// face opposite corner f) belongs to no other tet: the body's surface.
struct DualGraph {
  global_index_t num_global_tets = 0;
  global_index_t first_tet = 0;
  std::vector<global_index_t> offsets;
  std::vector<global_index_t> neighbours;
  std::vector<std::uint8_t> surface_faces;

  index_t num_tets() const { return static_cast<index_t>(surface_faces.size()); }
};

// Collective. Each face goes to the rank whose vertex block holds its
// smallest vertex, which matches it with the other tets of the same face and
// answers each tet's rank. Validates what needs the whole mesh: every tet id
// in range, no tet repeating a vertex, no two tets with the same vertices
// (InputError naming the slice's source and both tets, thrown on the rank
// that finds it, after the collective calls).
DualGraph build_dual_graph(MPI_Comm comm, const MeshSlice& slice);

}  // namespace descent
