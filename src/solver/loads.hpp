#pragma once
// Surface loads and prescribed motions of a scene, as per-vertex data.
#include <array>
#include <vector>

#include "common/mesh.hpp"
#include "io/scene.hpp"
#include "partition/local_mesh.hpp"

namespace descent {

// One rank's part of a load region's weights: per local vertex, a third of
// the area of each surface face (LocalMesh::surface_faces) of this rank's
// tets whose three vertices lie in the region; the area they sum to goes to
// *area. Every surface face belongs to one tet, so to one rank: the totals
// over ranks (shared vertices summed through the halo) give each vertex its
// share of the region's force once divided by the region's whole area.
std::vector<double> local_load_areas(const LocalMesh& mesh, const LoadRegion& region, double* area);

// The region's total force at time t (ramped linearly over `ramp` seconds).
std::array<double, 3> load_force(const LoadRegion& region, double t);

// Where a held vertex with rest position x_rest is at time t.
std::array<double, 3> moved_position(const Motion& motion, const double* x_rest, double t);

}  // namespace descent
