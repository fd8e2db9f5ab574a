#pragma once
// Test helpers: the global picture of a distributed run, on rank 0.
#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "app/simulation.hpp"

namespace descent::testing {

// The value of stats column `name` after the last step (collective: every
// rank calls it); a test failure when the run has no such column.
inline double measured(Simulation<double>& sim, const std::string& name) {
  const std::vector<double> values = sim.measure();
  const auto& names = sim.measurement_names();
  const auto at = std::find(names.begin(), names.end(), name);
  EXPECT_NE(at, names.end()) << "no column " << name;
  return at == names.end() ? 0.0 : values[at - names.begin()];
}

// Positions of all global vertices (xyz by global id) on rank 0, from the
// owned vertices of every rank; empty on other ranks.
template <class Real>
std::vector<double> gather_positions(MPI_Comm comm, const Simulation<Real>& sim,
                                     global_index_t num_global_vertices) {
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  const LocalMesh& local = sim.local_mesh();
  const int owned = local.num_owned;
  const std::vector<global_index_t> ids(local.global_vertex.begin(),
                                        local.global_vertex.begin() + owned);
  const std::vector<double> xyz = sim.owned_positions();
  std::vector<int> counts(size), offsets(size + 1, 0);
  MPI_Gather(&owned, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, comm);
  for (int r = 0; r < size; ++r) offsets[r + 1] = offsets[r] + counts[r];
  std::vector<global_index_t> all_ids(rank == 0 ? offsets[size] : 0);
  MPI_Gatherv(ids.data(), owned, MPI_INT64_T, all_ids.data(), counts.data(), offsets.data(),
              MPI_INT64_T, 0, comm);
  std::vector<int> counts3(size), offsets3(size);
  for (int r = 0; r < size; ++r) {
    counts3[r] = 3 * counts[r];
    offsets3[r] = 3 * offsets[r];
  }
  std::vector<double> all_xyz(rank == 0 ? 3 * offsets[size] : 0);
  MPI_Gatherv(xyz.data(), 3 * owned, MPI_DOUBLE, all_xyz.data(), counts3.data(), offsets3.data(),
              MPI_DOUBLE, 0, comm);
  std::vector<double> by_id;
  if (rank == 0) {
    by_id.assign(3 * static_cast<std::size_t>(num_global_vertices), 0.0);
    for (std::size_t k = 0; k < all_ids.size(); ++k)
      for (int i = 0; i < 3; ++i) by_id[3 * all_ids[k] + i] = all_xyz[3 * k + i];
  }
  return by_id;
}

// Sum m |v|^2 / 2 over all vertices (each counted by its owner), all ranks.
inline double kinetic_energy(MPI_Comm comm, const Simulation<double>& sim) {
  const auto& mass = sim.problem().mass();
  const auto& v = sim.state().v;
  double sum = 0;
  for (index_t i = 0; i < sim.local_mesh().num_owned; ++i)
    for (int a = 0; a < 3; ++a) sum += 0.5 * mass[i] * v[3 * i + a] * v[3 * i + a];
  MPI_Allreduce(MPI_IN_PLACE, &sum, 1, MPI_DOUBLE, MPI_SUM, comm);
  return sum;
}

// `frames` steps of `scene` on `comm` and, on rank 0, the same on one rank.
// On rank 0: the largest |q_P - q_1| and the largest |q_1 - rest| over all
// coordinates, and each step's iterations on `comm` and on one rank; zeros
// and empty counts on the other ranks.
struct OneRankComparison {
  double worst = 0;
  double moved = 0;
  std::vector<int> iterations, one_rank_iterations;
};

template <class Real = double>
OneRankComparison compare_with_one_rank(MPI_Comm comm, const Scene& scene, const Mesh& mesh,
                                        int frames) {
  OneRankComparison c;
  Simulation<Real> distributed(comm, scene, mesh);
  for (int frame = 0; frame < frames; ++frame)
    c.iterations.push_back(distributed.step().iterations);
  const std::vector<double> got = gather_positions(comm, distributed, mesh.num_vertices());
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  if (rank != 0) return {};
  Simulation<Real> serial(MPI_COMM_SELF, scene, mesh);
  for (int frame = 0; frame < frames; ++frame)
    c.one_rank_iterations.push_back(serial.step().iterations);
  const std::vector<double> want = gather_positions(MPI_COMM_SELF, serial, mesh.num_vertices());
  for (std::size_t k = 0; k < want.size(); ++k) {
    c.worst = std::max(c.worst, std::abs(got[k] - want[k]));
    c.moved = std::max(c.moved, std::abs(want[k] - mesh.positions[k]));
  }
  return c;
}

}  // namespace descent::testing
