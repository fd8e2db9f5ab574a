#pragma once
// The body's surface and the faces between parts, found from the parts'
// own tets after migration, for a partition made without the dual graph
// (partition.method = "rcb").
//
// Each part first matches the faces of its own tets, with its local vertex
// numbers (a counting sort by each face's smallest vertex, then a small sort
// per vertex): most faces are found there. Only the faces left alone, those
// of the body's surface and those between parts, travel to the rank whose
// vertex block holds their smallest vertex, as every face does to build the
// dual graph (partition/dual_graph.hpp), and that rank answers each tet's
// part with the tet across (or none: the surface). So the exchange carries
// a few per cent of the faces instead of all of them.
#include <mpi.h>

#include <span>
#include <string>

#include "partition/distribute.hpp"

namespace descent {

// Collective: sets parts[i].surface_faces (bits as DualGraph::surface_faces)
// from the tets of parts[i] and returns the faces between parts, over all
// ranks. vertices[i] numbers the corners of parts[i] (gather_part_vertices);
// num_parts is the partition's. Validates as build_dual_graph does: two
// tets with the same vertices are an InputError naming `source` and both
// tets; so is a face of more than two tets found together (a tet mesh has
// at most two per face).
global_index_t match_part_faces(MPI_Comm comm, std::span<PartTets> parts,
                                std::span<const PartVertices> vertices,
                                global_index_t num_global_vertices, int num_parts,
                                const std::string& source);

}  // namespace descent
