// The partition and each rank's local mesh: every tet on exactly one rank,
// every vertex owned by exactly one rank, shared lists symmetric between
// neighbours, local <-> global maps consistent with the global mesh.
#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>

#include "app/simulation.hpp"
#include "meshes/generators.hpp"
#include "partition/partition.hpp"

namespace descent {
namespace {

struct PartitionedBox {
  int rank = 0, size = 1;
  Mesh mesh;
  std::vector<int> part;
  LocalMesh local;
};

PartitionedBox make_setup() {
  PartitionedBox s;
  MPI_Comm_rank(MPI_COMM_WORLD, &s.rank);
  MPI_Comm_size(MPI_COMM_WORLD, &s.size);
  BoxParams box;
  box.cells = {6, 5, 4};
  box.tets_per_cell = 5;
  s.mesh = make_box(box);
  s.part = partition_on_root(MPI_COMM_WORLD, s.mesh);
  s.local = build_local_mesh(s.mesh, s.part, s.rank, s.size);
  return s;
}

TEST(Partition, EveryTetOnExactlyOneRank) {
  const PartitionedBox s = make_setup();
  std::vector<int> count(s.mesh.num_tets(), 0);
  for (index_t t : s.local.global_tet) ++count[t];
  MPI_Allreduce(MPI_IN_PLACE, count.data(), s.mesh.num_tets(), MPI_INT, MPI_SUM, MPI_COMM_WORLD);
  for (index_t t = 0; t < s.mesh.num_tets(); ++t) ASSERT_EQ(count[t], 1) << "tet " << t;
  for (index_t t : s.local.global_tet) EXPECT_EQ(s.part[t], s.rank);
}

TEST(Partition, EveryVertexOwnedByExactlyOneRankAndOrderedAsDocumented) {
  const PartitionedBox s = make_setup();
  std::vector<int> owners(s.mesh.num_vertices(), 0);
  for (index_t v = 0; v < s.local.num_owned; ++v) ++owners[s.local.global_vertex[v]];
  MPI_Allreduce(MPI_IN_PLACE, owners.data(), s.mesh.num_vertices(), MPI_INT, MPI_SUM,
                MPI_COMM_WORLD);
  for (index_t v = 0; v < s.mesh.num_vertices(); ++v) ASSERT_EQ(owners[v], 1) << "vertex " << v;
  // Interior, shared owned and shared other are each ascending by global id.
  const auto& g = s.local.global_vertex;
  EXPECT_TRUE(std::is_sorted(g.begin(), g.begin() + s.local.num_interior));
  EXPECT_TRUE(std::is_sorted(g.begin() + s.local.num_interior, g.begin() + s.local.num_owned));
  EXPECT_TRUE(std::is_sorted(g.begin() + s.local.num_owned, g.end()));
  if (s.size == 1) {
    EXPECT_EQ(s.local.num_shared(), 0);
  }
}

TEST(Partition, LocalTetsMatchGlobalMeshAndBoundaryTetsComeFirst) {
  const PartitionedBox s = make_setup();
  const LocalMesh& l = s.local;
  for (index_t t = 0; t < l.num_tets(); ++t) {
    bool touches_shared = false;
    for (int a = 0; a < 4; ++a) {
      const index_t lv = l.tets[4 * t + a];
      ASSERT_EQ(l.global_vertex[lv], s.mesh.tets[4 * l.global_tet[t] + a]);
      for (int i = 0; i < 3; ++i)
        ASSERT_EQ(l.rest_positions[3 * lv + i], s.mesh.positions[3 * l.global_vertex[lv] + i]);
      touches_shared = touches_shared || lv >= l.num_interior;
    }
    EXPECT_EQ(touches_shared, t < l.num_boundary_tets) << "tet " << t;
  }
  // The corner table lists each corner once, under its own vertex.
  ASSERT_EQ(l.vertex_corners.size(), l.tets.size());
  for (index_t v = 0; v < l.num_vertices(); ++v)
    for (index_t k = l.corner_offsets[v]; k < l.corner_offsets[v + 1]; ++k)
      ASSERT_EQ(l.tets[l.vertex_corners[k]], v);
}

TEST(Partition, SharedListsAreSymmetricBetweenNeighbours) {
  const PartitionedBox s = make_setup();
  const LocalMesh& l = s.local;
  // Send my list of shared global ids to each neighbour; theirs must be equal.
  std::vector<std::vector<int>> mine(l.neighbours.size()), theirs(l.neighbours.size());
  std::vector<MPI_Request> requests;
  for (std::size_t n = 0; n < l.neighbours.size(); ++n) {
    for (index_t v : l.shared_with[n]) mine[n].push_back(l.global_vertex[v]);
    theirs[n].resize(mine[n].size() + 1, -1);  // one spare slot detects a longer list
    requests.emplace_back();
    MPI_Irecv(theirs[n].data(), static_cast<int>(theirs[n].size()), MPI_INT, l.neighbours[n], 5,
              MPI_COMM_WORLD, &requests.back());
  }
  for (std::size_t n = 0; n < l.neighbours.size(); ++n) {
    requests.emplace_back();
    MPI_Isend(mine[n].data(), static_cast<int>(mine[n].size()), MPI_INT, l.neighbours[n], 5,
              MPI_COMM_WORLD, &requests.back());
  }
  MPI_Waitall(static_cast<int>(requests.size()), requests.data(), MPI_STATUSES_IGNORE);
  for (std::size_t n = 0; n < l.neighbours.size(); ++n) {
    EXPECT_TRUE(std::is_sorted(mine[n].begin(), mine[n].end()));
    EXPECT_FALSE(mine[n].empty());
    EXPECT_EQ(theirs[n].back(), -1) << "rank " << l.neighbours[n] << " shares more vertices";
    theirs[n].pop_back();
    EXPECT_EQ(mine[n], theirs[n]) << "with rank " << l.neighbours[n];
  }
  EXPECT_EQ(std::count(l.neighbours.begin(), l.neighbours.end(), s.rank), 0);
}

}  // namespace
}  // namespace descent
