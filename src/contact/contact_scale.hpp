#pragma once
// The two scales every contact term of a run shares, obstacles and pairs
// alike (docs/contact.md): the barrier's activation distance dh and each
// surface vertex's barrier stiffness.
#include <algorithm>
#include <cmath>

#include "comm/reduction.hpp"
#include "io/scene.hpp"
#include "partition/local_mesh.hpp"

namespace descent {

// contact.distance, or 1e-3 of the diagonal of the bodies' bounding box at
// rest (collective: six maxima over ranks).
inline double activation_distance(const LocalMesh& mesh, const Scene& scene,
                                  EnergyReduction& reduction) {
  if (scene.contact.distance > 0) return scene.contact.distance;
  const auto& x = mesh.rest_positions;
  double extent2 = 0;
  for (int i = 0; i < 3; ++i) {
    double lo = 1e300, hi = -1e300;
    for (index_t v = 0; v < mesh.num_vertices(); ++v) {
      lo = std::min(lo, x[3 * static_cast<std::size_t>(v) + i]);
      hi = std::max(hi, x[3 * static_cast<std::size_t>(v) + i]);
    }
    const double span = reduction.max_of(hi) + reduction.max_of(-lo);
    extent2 += span * span;
  }
  return 1e-3 * std::sqrt(extent2);
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
