#pragma once
// Test helper: the positions (global, xyz by vertex id) after `frames` steps
// of a 1-rank run of `scene`: the same state for every rank count, for tests
// that compare P ranks with one at a deformed state.
#include <mpi.h>

#include <vector>

#include "app/simulation.hpp"

namespace descent::testing {

inline std::vector<double> deformed_state(const Scene& scene, const Mesh& mesh, int frames) {
  Simulation<double> sim(MPI_COMM_SELF, scene, mesh);
  for (int f = 0; f < frames; ++f) sim.step();
  std::vector<double> q(3 * static_cast<std::size_t>(mesh.num_vertices()));
  const LocalMesh& local = sim.local_mesh();
  for (index_t v = 0; v < local.num_vertices(); ++v)
    for (int i = 0; i < 3; ++i) q[3 * local.global_vertex[v] + i] = sim.state().q[3 * v + i];
  return q;
}

}  // namespace descent::testing
