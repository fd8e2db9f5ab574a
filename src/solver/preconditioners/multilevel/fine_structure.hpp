#pragma once
// The finest level's operator structure, fixed for a run: its block pattern
// over the rank's local vertices (the vertex pairs of its tets), where each
// tet's 16 blocks lie, and a colouring of the tets that lets the assembly
// run in parallel without two threads adding to one block. Colours cost
// locality (each sweeps the whole operator: on the 82K helix 25 colours
// made the assembly several times slower on one thread), so a run on one
// host thread takes all tets as one colour, in their own order.
#include <vector>

#include "partition/local_mesh.hpp"
#include "solver/preconditioners/multilevel/block_sparse.hpp"

namespace descent {

struct FineStructure {
  BlockPattern pattern;            // 3x3 blocks
  std::vector<index_t> tet_slots;  // 16 per tet: block (corner a, corner b) at [16 t + 4 a + b]
  std::vector<index_t> diagonal_slots;  // per vertex
  // Tets by colour: colour c's tets are colour_order[colour_offsets[c] ..
  // colour_offsets[c + 1]); no two of one colour share a vertex.
  std::vector<index_t> colour_order;
  std::vector<index_t> colour_offsets;
};

FineStructure make_fine_structure(const LocalMesh& mesh, bool coloured);

}  // namespace descent
