#pragma once
// A rank's local numbering chosen for memory locality (scene key
// partition.reorder). A mesh read from a file may number its vertices in any
// order; the element loops then gather corners from all over the vertex
// arrays and scatter into them. Reverse Cuthill-McKee renumbers each vertex
// class of the LocalMesh so that vertices joined by a tet get nearby
// numbers, and the tets follow their lowest-numbered vertex.
//
// What stays as the halo and the overlap need it: the classes [interior |
// shared owned | shared not owned] keep their ranges (each class is reordered
// within itself, on the graph of edges inside it), boundary tets stay before
// interior tets, and each neighbour's shared list stays in ascending global
// id. Only the order of sums changes, so a reordered run equals an
// unreordered one to round-off; output is written by global id, in input
// order either way.
#include <string>
#include <vector>

#include "partition/local_mesh.hpp"

namespace descent {

// The reverse Cuthill-McKee order of the vertices [first, last) of a graph
// (CSR adjacency of all vertices; edges leaving the range are ignored):
// order[k] is the vertex placed k-th. Each connected piece starts from a
// pseudo-peripheral vertex (George and Liu); ties go to the lower index.
std::vector<index_t> reverse_cuthill_mckee(const std::vector<index_t>& offsets,
                                           const std::vector<index_t>& adjacent, index_t first,
                                           index_t last);

// Renumbers `mesh` in place as `method` says: "rcm" as above, "none" keeps
// the partition's order (ascending global id within each class).
void reorder_local_mesh(LocalMesh& mesh, const std::string& method);

// The mean over tets of the spread of their corners' local ids (largest
// minus smallest): how far apart in memory one tet's gathers land.
double mean_corner_spread(const LocalMesh& mesh);

}  // namespace descent
