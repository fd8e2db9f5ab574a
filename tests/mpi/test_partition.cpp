// The parallel set-up from slices to local meshes (partition/distribute.hpp),
// with METIS, with PT-Scotch and with RCB (no dual graph: surface faces and
// cut from face matching): the dual graph equals a serial reference,
// every tet lands on exactly one rank, every vertex is owned by exactly one
// rank, shared lists are symmetric, surface faces are the body's, the cut
// counted in parallel equals a serial count, and bad meshes are refused on
// every rank with the culprit named.
#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>
#include <array>
#include <map>
#include <string>

#include "common/error.hpp"
#include "meshes/generators.hpp"
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

// The faces of a whole mesh: sorted vertex triple -> the tets that have it.
std::map<std::array<index_t, 3>, std::vector<index_t>> serial_faces(const Mesh& mesh) {
  std::map<std::array<index_t, 3>, std::vector<index_t>> faces;
  for (index_t t = 0; t < mesh.num_tets(); ++t)
    for (const auto& f : kTetFaces) {
      std::array<index_t, 3> key{mesh.tets[4 * t + f[0]], mesh.tets[4 * t + f[1]],
                                 mesh.tets[4 * t + f[2]]};
      std::sort(key.begin(), key.end());
      faces[key].push_back(t);
    }
  return faces;
}

std::array<index_t, 3> face_key(const Mesh& mesh, global_index_t t, int f) {
  std::array<index_t, 3> key;
  for (int k = 0; k < 3; ++k) key[k] = mesh.tets[4 * t + kTetFaces[f][k]];
  std::sort(key.begin(), key.end());
  return key;
}

std::vector<std::string> methods() {
  std::vector<std::string> m{"metis"};
  if (have_ptscotch()) m.push_back("ptscotch");
  m.push_back("rcb");
  return m;
}

class PartitionTest : public ::testing::TestWithParam<std::string> {
 protected:
  PartitionSpec spec() const {
    PartitionSpec s;
    s.method = GetParam();
    return s;
  }
  // The partition's own local order, which the tests of the documented
  // order pin (test_local_order.cpp tests partition.reorder = "rcm").
  PartitionSpec spec_in_id_order() const {
    PartitionSpec s = spec();
    s.reorder = "none";
    return s;
  }
};

TEST(DualGraph, EqualsTheSerialFaceAdjacency) {
  for (const Mesh& mesh : {small_box(), small_helix()}) {
    const MeshSlice slice = slice_of(mesh, world_rank(), world_size());
    const DualGraph graph = build_dual_graph(MPI_COMM_WORLD, slice);
    const auto faces = serial_faces(mesh);
    ASSERT_EQ(graph.num_tets(), slice.num_tets());
    for (index_t t = 0; t < graph.num_tets(); ++t) {
      const global_index_t id = slice.first_tet + t;
      std::vector<global_index_t> want;
      std::uint8_t surface = 0;
      for (int f = 0; f < 4; ++f) {
        const auto& users = faces.at(face_key(mesh, id, f));
        if (users.size() == 1) surface |= static_cast<std::uint8_t>(1u << f);
        for (index_t u : users)
          if (u != id) want.push_back(u);
      }
      std::sort(want.begin(), want.end());
      const std::vector<global_index_t> got(graph.neighbours.begin() + graph.offsets[t],
                                            graph.neighbours.begin() + graph.offsets[t + 1]);
      ASSERT_EQ(got, want) << mesh.source << ", tet " << id;
      ASSERT_EQ(graph.surface_faces[t], surface) << mesh.source << ", tet " << id;
    }
  }
}

TEST(DualGraph, RefusesTwoTetsWithTheSameVertices) {
  Mesh mesh = small_box();
  // Tet 7 again, its vertices in another order, at the end.
  mesh.tets.insert(mesh.tets.end(), {mesh.tets[4 * 7 + 2], mesh.tets[4 * 7 + 0],
                                     mesh.tets[4 * 7 + 3], mesh.tets[4 * 7 + 1]});
  mesh.source = "twice.h5";
  const MeshSlice slice = slice_of(mesh, world_rank(), world_size());
  std::string message;
  int failed_here = 0;
  try {
    build_dual_graph(MPI_COMM_WORLD, slice);
  } catch (const InputError& e) {
    message = e.what();
    failed_here = 1;
  } catch (const PeerFailure&) {
  }
  int failed = 0;
  MPI_Allreduce(&failed_here, &failed, 1, MPI_INT, MPI_SUM, MPI_COMM_WORLD);
  EXPECT_EQ(failed, 1) << "reported once, by the rank of the later tet";
  if (failed_here) {
    EXPECT_EQ(message.rfind(detail::concat("twice.h5: tet ", mesh.num_tets() - 1,
                                           " has the same vertices as tet 7"),
                            0),
              0u)
        << message;
  }
}

TEST_P(PartitionTest, EveryTetOnExactlyOneRankAndPartsNonEmpty) {
  for (const Mesh& mesh : {small_box(), small_helix()}) {
    const DistributedMesh d = distribute_mesh(MPI_COMM_WORLD, mesh, spec());
    std::vector<int> count(mesh.num_tets(), 0);
    for (global_index_t t : d.local.global_tet) ++count[t];
    MPI_Allreduce(MPI_IN_PLACE, count.data(), mesh.num_tets(), MPI_INT, MPI_SUM, MPI_COMM_WORLD);
    for (index_t t = 0; t < mesh.num_tets(); ++t) ASSERT_EQ(count[t], 1) << "tet " << t;
    EXPECT_GT(d.local.num_tets(), 0);
    EXPECT_EQ(d.local.rank, world_rank());
    EXPECT_EQ(d.local.num_global_tets, mesh.num_tets());
    EXPECT_EQ(d.quality.tets_per_part[world_rank()], d.local.num_tets());
    EXPECT_LE(d.quality.imbalance, 1.1) << GetParam();
  }
}

TEST_P(PartitionTest, EveryVertexOwnedByExactlyOneRankAndOrderedAsDocumented) {
  const Mesh mesh = small_helix();
  const DistributedMesh d = distribute_mesh(MPI_COMM_WORLD, mesh, spec_in_id_order());
  const LocalMesh& l = d.local;
  std::vector<int> owners(mesh.num_vertices(), 0);
  for (index_t v = 0; v < l.num_owned; ++v) ++owners[l.global_vertex[v]];
  MPI_Allreduce(MPI_IN_PLACE, owners.data(), mesh.num_vertices(), MPI_INT, MPI_SUM, MPI_COMM_WORLD);
  for (index_t v = 0; v < mesh.num_vertices(); ++v) ASSERT_EQ(owners[v], 1) << "vertex " << v;
  const auto& g = l.global_vertex;
  EXPECT_TRUE(std::is_sorted(g.begin(), g.begin() + l.num_interior));
  EXPECT_TRUE(std::is_sorted(g.begin() + l.num_interior, g.begin() + l.num_owned));
  EXPECT_TRUE(std::is_sorted(g.begin() + l.num_owned, g.end()));
  if (world_size() == 1) {
    EXPECT_EQ(l.num_shared(), 0);
  }
  EXPECT_EQ(d.unused_vertices, 0);
}

TEST_P(PartitionTest, LocalTetsMatchTheMeshAndBoundaryTetsComeFirst) {
  const Mesh mesh = small_helix();
  const DistributedMesh d = distribute_mesh(MPI_COMM_WORLD, mesh, spec_in_id_order());
  const LocalMesh& l = d.local;
  const auto faces = serial_faces(mesh);
  EXPECT_EQ(d.reoriented_tets, 0) << "the generator's tets are positive";
  for (index_t t = 0; t < l.num_tets(); ++t) {
    bool touches_shared = false;
    std::uint8_t surface = 0;
    for (int a = 0; a < 4; ++a) {
      const index_t lv = l.tets[4 * t + a];
      ASSERT_EQ(l.global_vertex[lv], mesh.tets[4 * l.global_tet[t] + a]);
      for (int i = 0; i < 3; ++i)
        ASSERT_EQ(l.rest_positions[3 * lv + i], mesh.positions[3 * l.global_vertex[lv] + i]);
      touches_shared = touches_shared || lv >= l.num_interior;
      if (faces.at(face_key(mesh, l.global_tet[t], a)).size() == 1)
        surface |= static_cast<std::uint8_t>(1u << a);
    }
    EXPECT_EQ(touches_shared, t < l.num_boundary_tets) << "tet " << t;
    EXPECT_EQ(l.surface_faces[t], surface) << "tet " << l.global_tet[t];
  }
  EXPECT_TRUE(std::is_sorted(l.global_tet.begin(), l.global_tet.begin() + l.num_boundary_tets));
  EXPECT_TRUE(std::is_sorted(l.global_tet.begin() + l.num_boundary_tets, l.global_tet.end()));
  ASSERT_EQ(l.vertex_corners.size(), l.tets.size());
  for (index_t v = 0; v < l.num_vertices(); ++v)
    for (index_t k = l.corner_offsets[v]; k < l.corner_offsets[v + 1]; ++k)
      ASSERT_EQ(l.tets[l.vertex_corners[k]], v);
}

TEST_P(PartitionTest, SharedListsAreSymmetricBetweenNeighbours) {
  const DistributedMesh d = distribute_mesh(MPI_COMM_WORLD, small_box(), spec());
  const LocalMesh& l = d.local;
  std::vector<std::vector<global_index_t>> mine(l.neighbours.size()), theirs(l.neighbours.size());
  std::vector<MPI_Request> requests;
  for (std::size_t n = 0; n < l.neighbours.size(); ++n) {
    for (index_t v : l.shared_with[n]) mine[n].push_back(l.global_vertex[v]);
    theirs[n].resize(mine[n].size() + 1, -1);  // one spare slot detects a longer list
    requests.emplace_back();
    MPI_Irecv(theirs[n].data(), static_cast<int>(theirs[n].size()), MPI_INT64_T, l.neighbours[n], 5,
              MPI_COMM_WORLD, &requests.back());
  }
  for (std::size_t n = 0; n < l.neighbours.size(); ++n) {
    requests.emplace_back();
    MPI_Isend(mine[n].data(), static_cast<int>(mine[n].size()), MPI_INT64_T, l.neighbours[n], 5,
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
  EXPECT_EQ(std::count(l.neighbours.begin(), l.neighbours.end(), world_rank()), 0);
  EXPECT_EQ(d.quality.neighbours_per_part[world_rank()], static_cast<int>(l.neighbours.size()));
}

TEST_P(PartitionTest, CutFacesEqualASerialCount) {
  const Mesh mesh = small_helix();
  const DistributedMesh d = distribute_mesh(MPI_COMM_WORLD, mesh, spec());
  std::vector<int> part(mesh.num_tets(), 0);
  for (global_index_t t : d.local.global_tet) part[t] = world_rank();
  MPI_Allreduce(MPI_IN_PLACE, part.data(), mesh.num_tets(), MPI_INT, MPI_SUM, MPI_COMM_WORLD);
  global_index_t cut = 0;
  for (const auto& [key, users] : serial_faces(mesh))
    if (users.size() == 2 && part[users[0]] != part[users[1]]) ++cut;
  EXPECT_EQ(d.quality.cut_faces, cut);
  if (world_size() > 1) {
    EXPECT_GT(cut, 0);
  }
}

TEST_P(PartitionTest, TheSamePartitionEveryTime) {
  const Mesh mesh = small_helix();
  const DistributedMesh first = distribute_mesh(MPI_COMM_WORLD, mesh, spec());
  const DistributedMesh again = distribute_mesh(MPI_COMM_WORLD, mesh, spec());
  EXPECT_EQ(first.local.global_tet, again.local.global_tet);
}

TEST_P(PartitionTest, FlipsNegativeTetsAndKeepsUnusedVertices) {
  Mesh mesh = small_box();
  for (index_t t = 0; t < mesh.num_tets(); t += 3)
    std::swap(mesh.tets[4 * t], mesh.tets[4 * t + 1]);
  mesh.positions.insert(mesh.positions.end(), {9.0, 9.0, 9.0});  // used by no tet
  const DistributedMesh d = distribute_mesh(MPI_COMM_WORLD, mesh, spec());
  EXPECT_EQ(d.reoriented_tets, (mesh.num_tets() + 2) / 3);
  EXPECT_EQ(d.unused_vertices, 1);
  const bool holds_last =
      BlockRange(mesh.num_vertices(), world_size()).owner(mesh.num_vertices() - 1) == world_rank();
  ASSERT_EQ(d.unused.ids.size(), holds_last ? 1u : 0u);
  if (holds_last) {
    EXPECT_EQ(d.unused.ids[0], mesh.num_vertices() - 1);
    EXPECT_EQ(d.unused.positions, (std::vector<double>{9.0, 9.0, 9.0}));
  }
  const LocalMesh& l = d.local;
  for (index_t t = 0; t < l.num_tets(); ++t) {
    std::array<const double*, 4> x;
    for (int a = 0; a < 4; ++a) x[a] = &l.rest_positions[3 * l.tets[4 * t + a]];
    const double e[3][3] = {{x[1][0] - x[0][0], x[1][1] - x[0][1], x[1][2] - x[0][2]},
                            {x[2][0] - x[0][0], x[2][1] - x[0][1], x[2][2] - x[0][2]},
                            {x[3][0] - x[0][0], x[3][1] - x[0][1], x[3][2] - x[0][2]}};
    const double det = e[0][0] * (e[1][1] * e[2][2] - e[1][2] * e[2][1]) -
                       e[0][1] * (e[1][0] * e[2][2] - e[1][2] * e[2][0]) +
                       e[0][2] * (e[1][0] * e[2][1] - e[1][1] * e[2][0]);
    ASSERT_GT(det, 0) << "tet " << l.global_tet[t];
  }
}

TEST_P(PartitionTest, RefusesAFlatTetOnEveryRank) {
  Mesh mesh = small_box();
  // Tet 3's last corner moved onto the plane of its first three.
  const index_t moved = static_cast<index_t>(mesh.positions.size() / 3);
  std::array<double, 3> p{};
  for (int i = 0; i < 3; ++i)
    p[i] = (mesh.positions[3 * mesh.tets[12] + i] + mesh.positions[3 * mesh.tets[13] + i]) / 2;
  mesh.positions.insert(mesh.positions.end(), p.begin(), p.end());
  mesh.tets[4 * 3 + 2] = moved;
  mesh.source = "flat.msh";
  std::string message;
  bool peer = false;
  try {
    distribute_mesh(MPI_COMM_WORLD, mesh, spec());
  } catch (const InputError& e) {
    message = e.what();
  } catch (const PeerFailure&) {
    peer = true;
  }
  EXPECT_TRUE(peer || message.rfind("flat.msh: tet 3 has zero volume: its vertices", 0) == 0)
      << message;
}

TEST_P(PartitionTest, RefusesMorePartsThanTets) {
  BoxParams box;
  box.cells = {1, 1, 1};
  box.tets_per_cell = 5;
  const Mesh mesh = make_box(box);
  const MeshSlice slice = slice_of(mesh, world_rank(), world_size());
  const PartitionMethod method = choose_partition_method(GetParam(), mesh.num_tets());
  if (method == PartitionMethod::rcb) {
    EXPECT_THROW(partition_by_coordinates(MPI_COMM_WORLD, slice, 8), PartitionError);
    return;
  }
  const DualGraph graph = build_dual_graph(MPI_COMM_WORLD, slice);
  EXPECT_THROW(partition_dual_graph(MPI_COMM_WORLD, graph, 8, method, 1), PartitionError);
}

INSTANTIATE_TEST_SUITE_P(Methods, PartitionTest, ::testing::ValuesIn(methods()),
                         [](const ::testing::TestParamInfo<std::string>& method) {
                           return method.param;
                         });

}  // namespace
}  // namespace descent
