#pragma once
// The local vertices on the surface of the whole mesh: corners of the faces
// no other tet shares, on every sharer (a vertex of another rank's surface
// face may lie on no surface face of this rank's tets: one halo sum tells).
#include <vector>

#include "comm/halo.hpp"
#include "common/mesh.hpp"
#include "partition/local_mesh.hpp"

namespace descent {

// Collective over the halo's ranks; ascending local ids.
template <class Real>
std::vector<index_t> surface_vertices(const LocalMesh& mesh, Halo<Real>& halo) {
  const index_t nv = mesh.num_vertices();
  std::vector<Real> on_surface(nv, Real(0));
  for (index_t t = 0; t < mesh.num_tets(); ++t)
    for (int f = 0; f < 4; ++f)
      if (mesh.surface_faces[t] & (1u << f))
        for (int a : kTetFaces[f]) on_surface[mesh.tets[4 * static_cast<std::size_t>(t) + a]] = 1;
  halo.sum(on_surface.data(), 1);
  std::vector<index_t> vertices;
  for (index_t v = 0; v < nv; ++v)
    if (on_surface[v] > Real(0)) vertices.push_back(v);
  return vertices;
}

}  // namespace descent
