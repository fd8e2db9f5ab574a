// P ranks equal 1 rank: the small helix for 10 frames agrees with a 1-rank
// run to 1e-9 of its bounding-box diagonal, and every shared vertex is
// bitwise identical on all its sharers after every frame; with the default
// partitioner and with recursive coordinate bisection (partition.method =
// "rcb", whose surface faces come from face matching, not the dual graph).
#include <gtest/gtest.h>
#include <mpi.h>

#include <cmath>

#include "app/scene_mesh.hpp"
#include "app/simulation.hpp"
#include "gather_positions.hpp"
#include "mesh_extent.hpp"
#include "shared_vertices.hpp"
#include "small_scenes.hpp"

namespace descent {
namespace {

void expect_ten_frames_match_one_rank(const Scene& scene) {
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  const Mesh mesh = build_scene_mesh(scene.mesh);
  constexpr int kFrames = 10;

  Simulation<double> distributed(MPI_COMM_WORLD, scene, mesh);
  for (int frame = 1; frame <= kFrames; ++frame) {
    distributed.step();
    ASSERT_EQ(testing::shared_mismatches(MPI_COMM_WORLD, distributed), 0)
        << "shared vertices differ between sharers after frame " << frame;
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

TEST(RankInvariance, SmallHelixTenFramesMatchesOneRank) {
  expect_ten_frames_match_one_rank(testing::small_helix_scene());
}

TEST(RankInvariance, SmallHelixPartitionedByRcbMatchesOneRank) {
  Scene scene = testing::small_helix_scene();
  scene.partition.method = "rcb";
  expect_ten_frames_match_one_rank(scene);
}

}  // namespace
}  // namespace descent
