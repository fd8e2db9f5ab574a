// The local numbering for locality (partition/local_order.hpp) on 1 to 4
// ranks: reverse Cuthill-McKee keeps each vertex class's vertices, the
// boundary tets first and the shared lists in global id order, brings one
// tet's corners close together on a mesh numbered at random, and a run
// renumbered so equals the run in the partition's order to round-off, its
// results in input order.
#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <random>
#include <string>
#include <vector>

#include "app/scene_mesh.hpp"
#include "app/simulation.hpp"
#include "gather_positions.hpp"
#include "mesh_extent.hpp"
#include "partition/distribute.hpp"
#include "partition/local_order.hpp"
#include "small_scenes.hpp"
#include "world_rank.hpp"

namespace descent {
namespace {

using testing::world_rank;
using testing::world_size;

// `mesh` with its vertices and tets numbered at random (a fixed seed), as a
// file may number them.
Mesh shuffled(const Mesh& mesh) {
  std::mt19937 random(2026);
  std::vector<index_t> new_of_old(mesh.num_vertices()), tet_order(mesh.num_tets());
  std::iota(new_of_old.begin(), new_of_old.end(), index_t{0});
  std::iota(tet_order.begin(), tet_order.end(), index_t{0});
  std::shuffle(new_of_old.begin(), new_of_old.end(), random);
  std::shuffle(tet_order.begin(), tet_order.end(), random);
  Mesh out;
  out.source = mesh.source + ", shuffled";
  out.positions.resize(mesh.positions.size());
  for (index_t v = 0; v < mesh.num_vertices(); ++v)
    for (int i = 0; i < 3; ++i) out.positions[3 * new_of_old[v] + i] = mesh.positions[3 * v + i];
  for (index_t t : tet_order)
    for (int a = 0; a < 4; ++a) out.tets.push_back(new_of_old[mesh.tets[4 * t + a]]);
  return out;
}

Mesh shuffled_helix() { return shuffled(build_scene_mesh(testing::small_helix_scene().mesh)); }

PartitionSpec ordered(const std::string& reorder) {
  PartitionSpec spec;
  spec.method = "metis";
  spec.reorder = reorder;
  return spec;
}

// The global ids of local vertices [first, last), ascending.
std::vector<global_index_t> ids_of(const LocalMesh& l, index_t first, index_t last) {
  std::vector<global_index_t> ids(l.global_vertex.begin() + first, l.global_vertex.begin() + last);
  std::sort(ids.begin(), ids.end());
  return ids;
}

// Global tet id -> its corners as global vertex ids, in corner order.
std::map<global_index_t, std::vector<global_index_t>> tets_by_id(const LocalMesh& l) {
  std::map<global_index_t, std::vector<global_index_t>> tets;
  for (index_t t = 0; t < l.num_tets(); ++t)
    for (int a = 0; a < 4; ++a) tets[l.global_tet[t]].push_back(l.global_vertex[l.tets[4 * t + a]]);
  return tets;
}

TEST(LocalOrder, EachClassKeepsItsVerticesAndTheHaloItsOrder) {
  const Mesh mesh = shuffled_helix();
  const LocalMesh none = distribute_mesh(MPI_COMM_WORLD, mesh, ordered("none")).local;
  const LocalMesh rcm = distribute_mesh(MPI_COMM_WORLD, mesh, ordered("rcm")).local;
  ASSERT_EQ(rcm.num_vertices(), none.num_vertices());
  ASSERT_EQ(rcm.num_interior, none.num_interior);
  ASSERT_EQ(rcm.num_owned, none.num_owned);
  ASSERT_EQ(rcm.num_boundary_tets, none.num_boundary_tets);
  const index_t bounds[4] = {0, none.num_interior, none.num_owned, none.num_vertices()};
  for (int c = 0; c < 3; ++c)
    EXPECT_EQ(ids_of(rcm, bounds[c], bounds[c + 1]), ids_of(none, bounds[c], bounds[c + 1]))
        << "vertex class " << c;
  EXPECT_NE(rcm.global_vertex, none.global_vertex) << "a shuffled mesh is renumbered";
  for (index_t v = 0; v < rcm.num_vertices(); ++v) {
    const auto at =
        std::find(none.global_vertex.begin(), none.global_vertex.end(), rcm.global_vertex[v]);
    for (int i = 0; i < 3; ++i)
      ASSERT_EQ(rcm.rest_positions[3 * v + i],
                none.rest_positions[3 * (at - none.global_vertex.begin()) + i]);
  }

  // The same tets, corners in the same order (orientation kept), surface
  // faces with them, boundary tets first, each group by its lowest corner,
  // then by global id.
  EXPECT_EQ(tets_by_id(rcm), tets_by_id(none));
  std::map<global_index_t, int> surface;
  for (index_t t = 0; t < none.num_tets(); ++t) surface[none.global_tet[t]] = none.surface_faces[t];
  for (index_t t = 0; t < rcm.num_tets(); ++t) {
    ASSERT_EQ(rcm.surface_faces[t], surface.at(rcm.global_tet[t])) << "tet " << rcm.global_tet[t];
    bool touches_shared = false;
    for (int a = 0; a < 4; ++a)
      touches_shared = touches_shared || rcm.tets[4 * t + a] >= rcm.num_interior;
    EXPECT_EQ(touches_shared, t < rcm.num_boundary_tets) << "tet " << t;
  }
  auto lowest = [&](index_t t) {
    return *std::min_element(&rcm.tets[4 * t], &rcm.tets[4 * t] + 4);
  };
  for (index_t t = 1; t < rcm.num_tets(); ++t)
    if (t != rcm.num_boundary_tets) {
      ASSERT_LE(lowest(t - 1), lowest(t)) << "tet " << t;
      if (lowest(t - 1) == lowest(t)) {
        ASSERT_LT(rcm.global_tet[t - 1], rcm.global_tet[t]) << "tets of one lowest corner";
      }
    }
  ASSERT_EQ(rcm.vertex_corners.size(), rcm.tets.size());
  for (index_t v = 0; v < rcm.num_vertices(); ++v)
    for (index_t k = rcm.corner_offsets[v]; k < rcm.corner_offsets[v + 1]; ++k)
      ASSERT_EQ(rcm.tets[rcm.vertex_corners[k]], v);

  // Each neighbour's list names the same vertices in the same (global id)
  // order, so the buffers still line up with the neighbour's.
  ASSERT_EQ(rcm.neighbours, none.neighbours);
  for (std::size_t n = 0; n < rcm.neighbours.size(); ++n) {
    ASSERT_EQ(rcm.shared_with[n].size(), none.shared_with[n].size());
    for (std::size_t k = 0; k < rcm.shared_with[n].size(); ++k)
      EXPECT_EQ(rcm.global_vertex[rcm.shared_with[n][k]],
                none.global_vertex[none.shared_with[n][k]]);
  }
}

// On a mesh numbered at random one tet's corners lie a third of the vertex
// array apart on average; reverse Cuthill-McKee brings them at least as
// close as the generator's own numbering (along the helix, section by
// section) has them.
TEST(LocalOrder, BringsATetsCornersCloseOnAShuffledMesh) {
  const Mesh generated = build_scene_mesh(testing::small_helix_scene().mesh);
  const Mesh mesh = shuffled(generated);
  const LocalMesh none = distribute_mesh(MPI_COMM_WORLD, mesh, ordered("none")).local;
  const LocalMesh rcm = distribute_mesh(MPI_COMM_WORLD, mesh, ordered("rcm")).local;
  const LocalMesh reference = distribute_mesh(MPI_COMM_WORLD, generated, ordered("none")).local;
  const double before = mean_corner_spread(none), after = mean_corner_spread(rcm);
  const double generator = mean_corner_spread(reference);
  EXPECT_GT(before, 0.2 * none.num_vertices()) << "the shuffle should scatter the corners";
  EXPECT_LE(after, generator) << "shuffled " << before << ", reordered " << after;
  std::printf(
      "[ local order ] rank %d, %d vertices: mean corner spread %.1f shuffled -> %.1f reordered "
      "(generator's order %.1f)\n",
      world_rank(), rcm.num_vertices(), before, after, generator);
}

// Reverse Cuthill-McKee of a path numbered out of order numbers it end to end.
TEST(LocalOrder, ReverseCuthillMcKeeNumbersAPathEndToEnd) {
  // The path 3 - 0 - 4 - 1 - 2, as CSR rows of vertices 0..4, and vertex 5
  // alone.
  const std::vector<index_t> offsets{0, 2, 4, 5, 6, 8, 8};
  const std::vector<index_t> adjacent{3, 4, 2, 4, 1, 0, 0, 1};
  const std::vector<index_t> order = reverse_cuthill_mckee(offsets, adjacent, 0, 6);
  ASSERT_EQ(order.size(), 6u);
  EXPECT_EQ(order.front(), 5) << "the lone vertex, numbered last by Cuthill-McKee, comes first";
  const std::vector<index_t> path(order.begin() + 1, order.end());
  const std::vector<index_t> forward{3, 0, 4, 1, 2}, backward{2, 1, 4, 0, 3};
  EXPECT_TRUE(path == forward || path == backward);
}

// The largest |q_rcm - q_none| over all coordinates, in input order (rank 0;
// 0 elsewhere), after `frames` steps of `scene` on `mesh`.
double reordered_difference(Scene scene, const Mesh& mesh, int frames, double* moved) {
  std::vector<double> by_id[2];
  for (int k = 0; k < 2; ++k) {
    scene.partition.reorder = k == 0 ? "none" : "rcm";
    Simulation<double> sim(MPI_COMM_WORLD, scene, mesh);
    for (int frame = 0; frame < frames; ++frame) EXPECT_TRUE(sim.step().finite);
    by_id[k] = testing::gather_positions(MPI_COMM_WORLD, sim, mesh.num_vertices());
  }
  double worst = 0;
  *moved = 0;
  for (std::size_t k = 0; k < by_id[0].size(); ++k) {
    worst = std::max(worst, std::abs(by_id[1][k] - by_id[0][k]));
    *moved = std::max(*moved, std::abs(by_id[0][k] - mesh.positions[k]));
  }
  return worst;
}

TEST(LocalOrder, ARenumberedRunEqualsTheRunInInputOrder) {
  const Mesh mesh = shuffled_helix();
  const double diagonal = testing::bounding_box_diagonal(mesh);
  for (const char* preconditioner : {"jacobi", "multilevel"}) {
    Scene scene = testing::small_helix_scene();
    scene.solver.preconditioner = preconditioner;
    double moved = 0;
    const double worst = reordered_difference(scene, mesh, 10, &moved);
    if (world_rank() == 0) {
      EXPECT_GT(moved, 1e-3 * diagonal) << "the helix should sag visibly";
      EXPECT_LE(worst, 1e-12 * diagonal) << preconditioner << ", " << world_size() << " ranks";
      std::printf("[ local order ] %s, %d ranks: max |q_rcm - q_none| = %.3g (diagonal %.3g)\n",
                  preconditioner, world_size(), worst, diagonal);
    }
  }
}

// Contact pairs between bodies see local vertex ids too.
TEST(LocalOrder, ARenumberedContactRunEqualsTheRunInInputOrder) {
  const Scene scene = testing::head_on(2.0);
  const Mesh mesh = build_scene_mesh(scene);
  const double diagonal = testing::bounding_box_diagonal(mesh);
  double moved = 0;
  const double worst = reordered_difference(scene, mesh, 20, &moved);
  if (world_rank() == 0) {
    EXPECT_GT(moved, 0.05 * diagonal) << "the boxes should meet";
    EXPECT_LE(worst, 1e-12 * diagonal) << world_size() << " ranks";
    std::printf("[ local order ] two boxes, %d ranks: max |q_rcm - q_none| = %.3g\n", world_size(),
                worst);
  }
}

}  // namespace
}  // namespace descent
