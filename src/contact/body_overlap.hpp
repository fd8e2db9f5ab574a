#pragma once
// Whether the bodies of a scene ([[body]]) start apart: two bodies overlap
// when a surface edge of one crosses a surface triangle of the other, or a
// surface vertex of one lies inside the other (strictly inside one of its
// tets, or on an inner face, edge or corner and on none of its surface
// triangles: one body wholly inside another crosses no surface). Bodies that touch (a face on a
// face, a vertex on a face) or lie closer than contact.distance do not overlap.
#include <string>
#include <vector>

#include "common/mesh.hpp"

namespace descent {

// Throws InputError naming the first two overlapping bodies (names[b] for
// body b of mesh.body_vertex_offsets) and a point where they overlap. A mesh
// of one body passes. Serial: the set-up calls it where the whole mesh is
// (rank 0), before the mesh is scattered.
void check_bodies_apart(const Mesh& mesh, const std::vector<std::string>& names);

}  // namespace descent
