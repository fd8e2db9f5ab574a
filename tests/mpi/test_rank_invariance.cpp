// P ranks equal 1 rank: the small helix for 10 frames agrees with a 1-rank
// run to 1e-9 of its bounding-box diagonal, and every shared vertex is
// bitwise identical on all its sharers after every frame.
#include <gtest/gtest.h>
#include <mpi.h>

#include <cmath>
#include <cstring>

#include "app/scene_mesh.hpp"
#include "app/simulation.hpp"
#include "gather_positions.hpp"
#include "mesh_extent.hpp"
#include "small_scenes.hpp"

namespace descent {
namespace {

// Number of shared vertices whose positions differ in any bit from a
// neighbour's copy (exchanged directly, by global-id order of the lists).
int shared_mismatches(const Simulation<double>& sim) {
  const LocalMesh& l = sim.local_mesh();
  const auto& q = sim.state().q;
  std::vector<std::vector<double>> mine(l.neighbours.size()), theirs(l.neighbours.size());
  std::vector<MPI_Request> requests(2 * l.neighbours.size());
  for (std::size_t n = 0; n < l.neighbours.size(); ++n) {
    for (index_t v : l.shared_with[n])
      for (int i = 0; i < 3; ++i) mine[n].push_back(q[3 * v + i]);
    theirs[n].resize(mine[n].size());
    MPI_Irecv(theirs[n].data(), static_cast<int>(theirs[n].size()), MPI_DOUBLE, l.neighbours[n], 9,
              MPI_COMM_WORLD, &requests[n]);
  }
  for (std::size_t n = 0; n < l.neighbours.size(); ++n)
    MPI_Isend(mine[n].data(), static_cast<int>(mine[n].size()), MPI_DOUBLE, l.neighbours[n], 9,
              MPI_COMM_WORLD, &requests[l.neighbours.size() + n]);
  MPI_Waitall(static_cast<int>(requests.size()), requests.data(), MPI_STATUSES_IGNORE);
  int mismatches = 0;
  for (std::size_t n = 0; n < l.neighbours.size(); ++n)
    for (std::size_t k = 0; k < mine[n].size(); k += 3)
      if (std::memcmp(&mine[n][k], &theirs[n][k], 3 * sizeof(double)) != 0) ++mismatches;
  return mismatches;
}

TEST(RankInvariance, SmallHelixTenFramesMatchesOneRank) {
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  const Scene scene = testing::small_helix_scene();
  const Mesh mesh = build_scene_mesh(scene.mesh);
  constexpr int kFrames = 10;

  Simulation<double> distributed(MPI_COMM_WORLD, scene, mesh);
  for (int frame = 1; frame <= kFrames; ++frame) {
    distributed.step();
    int mismatches = shared_mismatches(distributed);
    MPI_Allreduce(MPI_IN_PLACE, &mismatches, 1, MPI_INT, MPI_SUM, MPI_COMM_WORLD);
    ASSERT_EQ(mismatches, 0) << "shared vertices differ between sharers after frame " << frame;
  }
  const std::vector<double> got =
      testing::gather_positions(MPI_COMM_WORLD, distributed, mesh.num_vertices());

  if (rank == 0) {
    Simulation<double> serial(MPI_COMM_SELF, scene, mesh);
    for (int frame = 1; frame <= kFrames; ++frame) serial.step();
    const std::vector<double> want =
        testing::gather_positions(MPI_COMM_SELF, serial, mesh.num_vertices());
    double worst = 0, moved = 0;
    for (std::size_t k = 0; k < want.size(); ++k) {
      worst = std::max(worst, std::abs(got[k] - want[k]));
      moved = std::max(moved, std::abs(want[k] - mesh.positions[k]));
    }
    const double diagonal = testing::bounding_box_diagonal(mesh);
    EXPECT_GT(moved, 1e-3 * diagonal) << "the helix should sag visibly under gravity";
    EXPECT_LE(worst, 1e-9 * diagonal) << size << " ranks vs 1 rank after " << kFrames << " frames";
    std::printf(
        "[ rank invariance ] %d ranks: max |q_P - q_1| = %.3g (diagonal %.3g, max motion %.3g)\n",
        size, worst, diagonal, moved);
  }
}

}  // namespace
}  // namespace descent
