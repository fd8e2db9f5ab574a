#pragma once
// The scales every contact term of a run shares, obstacles and pairs alike
// (docs/contact.md): the barrier's activation distance dh, each surface
// vertex's barrier stiffness, and the mean surface edge at rest.
#include <algorithm>
#include <cmath>
#include <vector>

#include "comm/reduction.hpp"
#include "common/mesh.hpp"
#include "io/scene.hpp"
#include "partition/local_mesh.hpp"

namespace descent {

// contact.distance, or 1e-3 of the diagonal of the bodies' bounding box at
// rest (collective: one allreduce of the box's six maxima).
inline double activation_distance(const LocalMesh& mesh, const Scene& scene,
                                  EnergyReduction& reduction) {
  if (scene.contact.distance > 0) return scene.contact.distance;
  const auto& x = mesh.rest_positions;
  double box[6] = {-1e300, -1e300, -1e300, -1e300, -1e300, -1e300};  // hi xyz, -lo xyz
  for (index_t v = 0; v < mesh.num_vertices(); ++v)
    for (int i = 0; i < 3; ++i) {
      box[i] = std::max(box[i], x[3 * static_cast<std::size_t>(v) + i]);
      box[3 + i] = std::max(box[3 + i], -x[3 * static_cast<std::size_t>(v) + i]);
    }
  reduction.max_in_place(box, 6);
  double extent2 = 0;
  for (int i = 0; i < 3; ++i) extent2 += (box[i] + box[3 + i]) * (box[i] + box[3 + i]);
  return 1e-3 * std::sqrt(extent2);
}

// The mean length of the surface triangles' edges at rest (each edge counted
// once per triangle; the same on every rank). Collective: one allreduce.
inline double mean_surface_edge(const LocalMesh& mesh, EnergyReduction& reduction) {
  std::vector<double> edges(2, 0.0);  // summed length, count
  const auto& x = mesh.rest_positions;
  for (index_t t = 0; t < mesh.num_tets(); ++t)
    for (int f = 0; f < 4; ++f) {
      if (!(mesh.surface_faces[t] & (1u << f))) continue;
      for (int k = 0; k < 3; ++k) {
        const std::size_t a = mesh.tets[4 * static_cast<std::size_t>(t) + kTetFaces[f][k]];
        const std::size_t b =
            mesh.tets[4 * static_cast<std::size_t>(t) + kTetFaces[f][(k + 1) % 3]];
        double d2 = 0;
        for (int i = 0; i < 3; ++i)
          d2 += (x[3 * b + i] - x[3 * a + i]) * (x[3 * b + i] - x[3 * a + i]);
        edges[0] += std::sqrt(d2);
        edges[1] += 1;
      }
    }
  reduction.sum_in_place(edges);
  return edges[1] > 0 ? edges[0] / edges[1] : 0.0;
}

// contact.stiffness, or what holds vertex v already: m / h^2 plus the largest
// of its rest elastic Hessian diagonal (3 per vertex), so the barrier's force
// and the body's are of one scale whatever the units.
template <class Real>
Real vertex_stiffness(const Scene& scene, Real mass, double inv_h2, const Real* rest_diagonal) {
  if (scene.contact.stiffness > 0) return static_cast<Real>(scene.contact.stiffness);
  return static_cast<Real>(mass * inv_h2) +
         std::max({rest_diagonal[0], rest_diagonal[1], rest_diagonal[2]});
}

}  // namespace descent
