#pragma once
// Helpers for the backend tests (tests/backends, tests/gpu): run a scene for
// some frames on a backend and compare the global picture on rank 0.
#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

#include "app/simulation.hpp"
#include "tests/mpi/gather_positions.hpp"
#include "tests/mpi/mesh_extent.hpp"

namespace descent::testing {

// Global positions (xyz by global id, on rank 0 of comm) after `frames`
// steps of `scene` on `backend`; every step must stay finite.
template <class Real>
std::vector<double> run_frames(MPI_Comm comm, const Scene& scene, const Mesh& mesh,
                               const BackendChoice& backend, int frames) {
  Simulation<Real> sim(comm, scene, mesh, backend);
  for (int f = 0; f < frames; ++f) sim.step();
  return gather_positions(comm, sim, mesh.num_vertices());
}

// max_k |a_k - b_k| (infinite when either is not finite).
inline double max_difference(const std::vector<double>& a, const std::vector<double>& b) {
  double worst = 0;
  for (std::size_t k = 0; k < a.size(); ++k) {
    const double d = std::abs(a[k] - b[k]);
    if (!std::isfinite(d)) return INFINITY;
    worst = std::max(worst, d);
  }
  return worst;
}

// Number of shared vertices whose positions differ in any bit from a
// neighbour's copy (every sharer must hold the same bits).
template <class Real>
int shared_mismatches(MPI_Comm comm, const Simulation<Real>& sim) {
  const LocalMesh& l = sim.local_mesh();
  const auto& q = sim.state().q;
  const std::size_t nn = l.neighbours.size();
  std::vector<std::vector<Real>> mine(nn), theirs(nn);
  std::vector<MPI_Request> requests(2 * nn);
  const int bytes_per_vertex = 3 * sizeof(Real);
  for (std::size_t n = 0; n < nn; ++n) {
    for (index_t v : l.shared_with[n])
      for (int i = 0; i < 3; ++i) mine[n].push_back(q[3 * v + i]);
    theirs[n].resize(mine[n].size());
    MPI_Irecv(theirs[n].data(), static_cast<int>(theirs[n].size() * sizeof(Real)), MPI_BYTE,
              l.neighbours[n], 19, comm, &requests[n]);
  }
  for (std::size_t n = 0; n < nn; ++n)
    MPI_Isend(mine[n].data(), static_cast<int>(mine[n].size() * sizeof(Real)), MPI_BYTE,
              l.neighbours[n], 19, comm, &requests[nn + n]);
  MPI_Waitall(static_cast<int>(requests.size()), requests.data(), MPI_STATUSES_IGNORE);
  int mismatches = 0;
  for (std::size_t n = 0; n < nn; ++n)
    for (std::size_t k = 0; k < mine[n].size(); k += 3)
      if (std::memcmp(&mine[n][k], &theirs[n][k], bytes_per_vertex) != 0) ++mismatches;
  int total = 0;
  MPI_Allreduce(&mismatches, &total, 1, MPI_INT, MPI_SUM, comm);
  return total;
}

inline BackendChoice backend_of(BackendKind kind, Assembly assembly = Assembly::gather,
                                int device = 0) {
  BackendChoice b;
  b.kind = kind;
  b.engine.assembly = assembly;
  b.engine.device = device;
  return b;
}

}  // namespace descent::testing
