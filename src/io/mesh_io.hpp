#pragma once
// Reading and writing whole tetrahedral meshes.
//
// Readers: Gmsh .msh (ASCII 2.2 and 4.1; 4-node tets, type 4; other element
// types and unknown sections skipped), MEDIT .mesh (ASCII, `Vertices` and
// `Tetrahedra`), TetGen .node/.ele (either name, or the base name; `#`
// comments; 0- or 1-based as the file's first index says).
// Every reader validates: indices in range, finite coordinates, no duplicate
// tet (same vertex set), no tet with a repeated vertex, no zero-volume tet.
// A negatively oriented tet is re-oriented (two vertices swapped) and counted.
// Anything else is an InputError naming the file, the line and the element.
#include <string>
#include <vector>

#include "common/mesh.hpp"

namespace descent {

struct MeshReadReport {
  index_t reoriented_tets = 0;        // negatively oriented tets that were flipped
  index_t unreferenced_vertices = 0;  // vertices used by no tet (kept, reported)
  std::vector<std::string> warnings;  // one line each, ready to print
};

Mesh read_mesh(const std::string& path, MeshReadReport* report = nullptr);

// Validates a mesh built in memory (generators, tests) by the same rules as
// the readers; `what` names it in messages.
void validate_mesh(Mesh& mesh, const std::string& what, MeshReadReport* report = nullptr);

// Writes by extension: .mesh (MEDIT), .msh (Gmsh 2.2 ASCII), .node (TetGen
// .node + .ele beside it). Coordinates with 17 significant digits, so a round
// trip is exact.
void write_mesh(const Mesh& mesh, const std::string& path);

}  // namespace descent
