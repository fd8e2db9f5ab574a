#pragma once
// Surface loads and prescribed motions of a scene, as per-vertex data.
#include <array>
#include <vector>

#include "common/mesh.hpp"
#include "io/scene.hpp"

namespace descent {

using Face = std::array<index_t, 3>;

// Faces used by exactly one tet of the whole mesh (its boundary surface).
std::vector<Face> boundary_faces(const Mesh& mesh);

// Share of a load region's total force per global vertex: the boundary faces
// with all three vertices in the region, weighted by area, each face giving
// a third of its share to each of its vertices. Sums to 1. Throws InputError
// naming `key` (e.g. "load.0") when the region holds no boundary face.
std::vector<double> load_weights(const Mesh& mesh, const std::vector<Face>& faces,
                                 const LoadRegion& region, const std::string& key);

// The region's total force at time t (ramped linearly over `ramp` seconds).
std::array<double, 3> load_force(const LoadRegion& region, double t);

// Where a held vertex with rest position x_rest is at time t.
std::array<double, 3> moved_position(const Motion& motion, const double* x_rest, double t);

}  // namespace descent
