// Recursive coordinate bisection (partition/geometric_partition.hpp) and the
// face matching that replaces the dual graph for it
// (partition/face_matching.hpp): parts sized exactly as BlockRange, the same
// parts whatever the number of ranks that compute them, each split a plane
// across the longest side, and duplicate tets refused, naming both.
#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>
#include <array>
#include <limits>
#include <string>

#include "comm/collective_error.hpp"
#include "common/error.hpp"
#include "partition/distribute.hpp"
#include "partition/geometric_partition.hpp"
#include "partition_meshes.hpp"
#include "world_rank.hpp"

namespace descent {
namespace {

using testing::small_box;
using testing::small_helix;
using testing::world_rank;
using testing::world_size;

// The part of every tet of the mesh, computed on the world's ranks and
// gathered on each.
std::vector<int> parts_on_world(const Mesh& mesh, int nparts) {
  const MeshSlice slice = slice_of(mesh, world_rank(), world_size());
  const std::vector<int> mine = partition_by_coordinates(MPI_COMM_WORLD, slice, nparts);
  EXPECT_EQ(mine.size(), static_cast<std::size_t>(slice.num_tets()));
  std::vector<int> all(mesh.num_tets(), 0);
  std::copy(mine.begin(), mine.end(), all.begin() + slice.first_tet);
  MPI_Allreduce(MPI_IN_PLACE, all.data(), mesh.num_tets(), MPI_INT, MPI_SUM, MPI_COMM_WORLD);
  return all;
}

TEST(GeometricPartition, PartsAreSizedExactlyAndEveryOneHoldsTets) {
  for (const Mesh& mesh : {small_box(), small_helix()})
    for (const int nparts : {1, 2, 3, 5, 8, 13}) {
      const std::vector<int> part = parts_on_world(mesh, nparts);
      std::vector<global_index_t> count(nparts, 0);
      for (const int p : part) {
        ASSERT_GE(p, 0);
        ASSERT_LT(p, nparts);
        ++count[p];
      }
      const BlockRange want(mesh.num_tets(), nparts);
      for (int p = 0; p < nparts; ++p) {
        EXPECT_EQ(count[p], want.size(p)) << mesh.source << ", part " << p << " of " << nparts;
        EXPECT_GT(count[p], 0);
      }
    }
}

TEST(GeometricPartition, TheSamePartsOnAnyNumberOfRanks) {
  for (const Mesh& mesh : {small_box(), small_helix()})
    for (const int nparts : {2, 7}) {
      const std::vector<int> world = parts_on_world(mesh, nparts);
      const std::vector<int> alone =
          partition_by_coordinates(MPI_COMM_SELF, slice_of(mesh, 0, 1), nparts);
      EXPECT_EQ(world, alone) << mesh.source << ", " << nparts << " parts on " << world_size()
                              << " ranks";
      EXPECT_EQ(parts_on_world(mesh, nparts), world) << "a second run";
    }
}

TEST(GeometricPartition, TwoPartsAreSplitByAPlaneAcrossTheLongestSide) {
  const Mesh mesh = small_helix();
  const std::vector<int> part = parts_on_world(mesh, 2);
  std::vector<double> centroid(3 * static_cast<std::size_t>(mesh.num_tets()), 0.0);
  std::array<double, 3> lo, hi;
  lo.fill(std::numeric_limits<double>::infinity());
  hi.fill(-std::numeric_limits<double>::infinity());
  for (index_t t = 0; t < mesh.num_tets(); ++t)
    for (int k = 0; k < 3; ++k) {
      double& c = centroid[3 * t + k];
      for (int a = 0; a < 4; ++a) c += mesh.positions[3 * mesh.tets[4 * t + a] + k];
      c *= 0.25;
      lo[k] = std::min(lo[k], c);
      hi[k] = std::max(hi[k], c);
    }
  int axis = 0;
  for (int k = 1; k < 3; ++k)
    if (hi[k] - lo[k] > hi[axis] - lo[axis]) axis = k;
  double top_of_first = -std::numeric_limits<double>::infinity();
  double bottom_of_second = std::numeric_limits<double>::infinity();
  for (index_t t = 0; t < mesh.num_tets(); ++t) {
    const double c = centroid[3 * t + axis];
    if (part[t] == 0)
      top_of_first = std::max(top_of_first, c);
    else
      bottom_of_second = std::min(bottom_of_second, c);
  }
  EXPECT_LE(top_of_first, bottom_of_second) << "axis " << axis;
}

TEST(GeometricPartition, RefusesTwoTetsWithTheSameVertices) {
  Mesh mesh = small_box();
  // Tet 7 again, its vertices in another order, at the end: the same
  // centroid, so it may lie in tet 7's part or the next; its faces inside
  // the box then belong to three tets, and the message still names the
  // two copies.
  mesh.tets.insert(mesh.tets.end(), {mesh.tets[4 * 7 + 2], mesh.tets[4 * 7 + 0],
                                     mesh.tets[4 * 7 + 3], mesh.tets[4 * 7 + 1]});
  mesh.source = "twice.h5";
  PartitionSpec spec;
  spec.method = "rcb";
  std::string message;
  int failed_here = 0;
  try {
    distribute_mesh(MPI_COMM_WORLD, mesh, spec);
  } catch (const InputError& e) {
    message = e.what();
    failed_here = 1;
  } catch (const PeerFailure&) {
  }
  int failed = 0;
  MPI_Allreduce(&failed_here, &failed, 1, MPI_INT, MPI_SUM, MPI_COMM_WORLD);
  EXPECT_GE(failed, 1) << "reported by the ranks that see the two copies meet";
  if (failed_here) {
    EXPECT_EQ(message.rfind(detail::concat("twice.h5: tet ", mesh.num_tets() - 1,
                                           " has the same vertices as tet 7"),
                            0),
              0u)
        << message;
  }
}

TEST(GeometricPartition, RcbIsAPartitionMethodName) {
  EXPECT_EQ(choose_partition_method("rcb", 10), PartitionMethod::rcb);
  EXPECT_STREQ(to_string(PartitionMethod::rcb), "RCB");
  try {
    choose_partition_method("bisection", 10);
    FAIL() << "an unknown name is refused";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("not one of: auto, metis, ptscotch, rcb"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace descent
