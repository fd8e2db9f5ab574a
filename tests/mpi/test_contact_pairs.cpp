// The contact halo and the pair search between bodies (contact/
// contact_halo.hpp, contact/contact_pairs.hpp) on 1 to 4 ranks: every rank
// finds exactly the pairs of the whole mesh that touch its vertices, the
// pairs counted across ranks are the whole mesh's each once, the spatial
// hash misses no pair that a search of every primitive pair finds, ghosts
// follow their holders' positions, and contact.self adds the pairs within
// one body, never two primitives that share a vertex.
#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <set>
#include <vector>

#include "app/scene_mesh.hpp"
#include "comm/halo.hpp"
#include "contact/contact_halo.hpp"
#include "contact/contact_pairs.hpp"
#include "kernels/primitive_distance.hpp"
#include "partition/distribute.hpp"

namespace descent {
namespace {

using Key = std::array<global_index_t, 5>;  // kind (0: vertex-triangle, 1: edge-edge), ids

Body box_body(std::array<int, 3> cells, std::array<double, 3> translate, double degrees) {
  Body body;
  body.mesh.generator = "box";
  body.mesh.box.cells = cells;
  body.mesh.box.size = {0.4, 0.2, 0.4};
  body.translate = translate;
  body.rotate_axis = {1, 0, 1};
  body.rotate_degrees = degrees;
  return body;
}

// Two boxes, the upper one turned a little and 0.02 above the lower at its
// lowest corner, a third far off.
Mesh three_bodies() {
  Scene scene;
  scene.bodies = {box_body({4, 2, 4}, {0, 0, 0}, 0), box_body({3, 2, 3}, {0.05, 0.5, 0.05}, 0),
                  box_body({2, 2, 2}, {3, 0, 0}, 0)};
  scene.bodies[1].rotate_degrees = 4;
  Mesh mesh = build_scene_mesh(scene);
  // Lift the second body so its lowest vertex sits 0.02 above the first.
  double lowest = 1e300;
  for (global_index_t v = mesh.body_vertex_offsets[1]; v < mesh.body_vertex_offsets[2]; ++v)
    lowest = std::min(lowest, mesh.positions[3 * v + 1]);
  for (global_index_t v = mesh.body_vertex_offsets[1]; v < mesh.body_vertex_offsets[2]; ++v)
    mesh.positions[3 * v + 1] += 0.2 + 0.02 - lowest;
  return mesh;
}

struct Found {
  std::vector<Key> all;      // every pair this rank evaluates
  std::vector<Key> counted;  // those whose energy it counts
};

Key key_of(const ContactHalo<double>& halo, int kind, const std::array<index_t, 4>& v) {
  return {kind, halo.global_id()[v[0]], halo.global_id()[v[1]], halo.global_id()[v[2]],
          halo.global_id()[v[3]]};
}

using Move = std::array<double, 3>;

// The pairs found about the rest positions, or, with one move per body,
// along the straight paths from them to the moved positions.
Found pairs_on(MPI_Comm comm, const Mesh& mesh, double reach, bool self,
               const std::vector<Move>& moves = {}) {
  DistributedMesh distributed = distribute_mesh(comm, mesh, PartitionSpec{});
  const LocalMesh& local = distributed.local;
  Halo<double> halo(comm, local);
  ContactHalo<double> contact(local, halo);
  std::vector<double> moved(local.rest_positions);
  for (index_t v = 0; v < local.num_vertices() && !moves.empty(); ++v)
    for (int i = 0; i < 3; ++i)
      moved[3 * v + i] +=
          moves[body_of_vertex(mesh.body_vertex_offsets, local.global_vertex[v])][i];
  std::vector<double> to;
  if (!moves.empty()) {
    contact.rebuild(local.rest_positions.data(), reach, {}, moved.data());
    contact.gather(moved.data(), to);
  } else {
    contact.rebuild(local.rest_positions.data(), reach);
  }
  const ContactPairs pairs =
      find_contact_pairs(contact, reach, self, moves.empty() ? nullptr : &to);
  Found found;
  for (int kind = 0; kind < 2; ++kind)
    for (const auto& v : kind == 0 ? pairs.vertex_triangle : pairs.edge_edge) {
      found.all.push_back(key_of(contact, kind, v));
      if (counted_here(contact, v)) found.counted.push_back(key_of(contact, kind, v));
    }
  std::sort(found.all.begin(), found.all.end());
  std::sort(found.counted.begin(), found.counted.end());
  return found;
}

std::vector<Key> gather_keys(MPI_Comm comm, const std::vector<Key>& mine) {
  int size = 1;
  MPI_Comm_size(comm, &size);
  const int count = static_cast<int>(5 * mine.size());
  std::vector<int> counts(size), offsets(size + 1, 0);
  MPI_Allgather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, comm);
  for (int r = 0; r < size; ++r) offsets[r + 1] = offsets[r] + counts[r];
  std::vector<global_index_t> flat(offsets[size]);
  MPI_Allgatherv(mine.data(), count, MPI_INT64_T, flat.data(), counts.data(), offsets.data(),
                 MPI_INT64_T, comm);
  std::vector<Key> all(flat.size() / 5);
  for (std::size_t k = 0; k < all.size(); ++k)
    for (int i = 0; i < 5; ++i) all[k][i] = flat[5 * k + i];
  std::sort(all.begin(), all.end());
  return all;
}

TEST(ContactPairs, EveryRankFindsThePairsAroundItsVerticesAndEachIsCountedOnce) {
  const Mesh mesh = three_bodies();
  constexpr double reach = 0.05;
  const Found whole = pairs_on(MPI_COMM_SELF, mesh, reach, false);
  ASSERT_GT(whole.all.size(), 10u);  // the two boxes do face each other
  EXPECT_EQ(whole.counted, whole.all);
  for (const Key& k : whole.all) {
    // Only bodies 0 and 1 are near each other.
    for (int i = 1; i < 5; ++i) EXPECT_LT(k[i], mesh.body_vertex_offsets[2]);
  }
  const Found mine = pairs_on(MPI_COMM_WORLD, mesh, reach, false);
  // Counted across ranks: the whole mesh's pairs, each once.
  EXPECT_EQ(gather_keys(MPI_COMM_WORLD, mine.counted), whole.all);
  // Each rank has every pair of the whole that touches one of its vertices.
  DistributedMesh distributed = distribute_mesh(MPI_COMM_WORLD, mesh, PartitionSpec{});
  const std::set<global_index_t> local(distributed.local.global_vertex.begin(),
                                       distributed.local.global_vertex.end());
  std::vector<Key> want;
  for (const Key& k : whole.all)
    if (local.count(k[1]) || local.count(k[2]) || local.count(k[3]) || local.count(k[4]))
      want.push_back(k);
  EXPECT_EQ(mine.all, want);
}

// Every vertex-triangle and edge-edge pair of the halo's surface whose
// primitives share no vertex, tried one by one: those that
// keep(key, distance) accepts, sorted (key: kind, then the ids; kind 0:
// vertex, triangle; 1: edge, edge, each edge lesser id first).
template <class Keep>
std::vector<Key> every_pair(const ContactHalo<double>& contact, const Mesh& mesh, Keep&& keep) {
  const auto& gid = contact.global_id();
  const auto& x = contact.positions();
  std::set<std::array<global_index_t, 2>> edge_set;
  for (const auto& t : contact.triangles())
    for (int k = 0; k < 3; ++k)
      edge_set.insert(
          {std::min(gid[t[k]], gid[t[(k + 1) % 3]]), std::max(gid[t[k]], gid[t[(k + 1) % 3]])});
  std::vector<index_t> by_id(mesh.num_vertices(), -1);
  for (index_t c = 0; c < contact.num_vertices(); ++c) by_id[gid[c]] = c;
  auto point = [&](global_index_t id, double* out) {
    for (int i = 0; i < 3; ++i) out[i] = x[3 * by_id[id] + i];
  };
  std::vector<Key> kept;
  double y[12];
  for (index_t c = 0; c < contact.num_vertices(); ++c)
    for (const auto& t : contact.triangles()) {
      if (c == t[0] || c == t[1] || c == t[2]) continue;
      const Key key{0, gid[c], gid[t[0]], gid[t[1]], gid[t[2]]};
      for (int k = 0; k < 4; ++k) point(key[k + 1], y + 3 * k);
      if (keep(key, std::sqrt(point_triangle_distance(y, false).d2))) kept.push_back(key);
    }
  for (auto a = edge_set.begin(); a != edge_set.end(); ++a)
    for (auto b = std::next(a); b != edge_set.end(); ++b) {
      const auto &e = *a, &f = *b;
      if (e[0] == f[0] || e[0] == f[1] || e[1] == f[0] || e[1] == f[1]) continue;
      const Key key{1, e[0], e[1], f[0], f[1]};
      for (int k = 0; k < 4; ++k) point(key[k + 1], y + 3 * k);
      if (keep(key, std::sqrt(edge_edge_distance(y, false).d2))) kept.push_back(key);
    }
  std::sort(kept.begin(), kept.end());
  return kept;
}

// The hash must find every pair of different bodies within reach.
TEST(ContactPairs, TheHashMissesNoPair) {
  const Mesh mesh = three_bodies();
  constexpr double reach = 0.05;
  DistributedMesh distributed = distribute_mesh(MPI_COMM_SELF, mesh, PartitionSpec{});
  Halo<double> halo(MPI_COMM_SELF, distributed.local);
  ContactHalo<double> contact(distributed.local, halo);
  contact.rebuild(distributed.local.rest_positions.data(), reach);
  auto body = [&](global_index_t id) { return body_of_vertex(mesh.body_vertex_offsets, id); };
  const std::vector<Key> brute = every_pair(contact, mesh, [&](const Key& k, double d) {
    return body(k[1]) != body(k[k[0] == 0 ? 2 : 3]) && d < reach;
  });
  EXPECT_EQ(pairs_on(MPI_COMM_SELF, mesh, reach, false).all, brute);
}

// With a drift cap per vertex (contact.self, contact/body_contact.hpp):
// exactly the pairs, within one body and between bodies, whose distance is
// below reach plus the largest cap of each side; caps that differ from
// vertex to vertex, so a side's largest cap and each box's own growth are
// what decide.
TEST(ContactPairs, WithCapsEachSideReachesByItsLargestCap) {
  const Mesh mesh = three_bodies();
  constexpr double reach = 0.01;
  DistributedMesh distributed = distribute_mesh(MPI_COMM_SELF, mesh, PartitionSpec{});
  Halo<double> halo(MPI_COMM_SELF, distributed.local);
  ContactHalo<double> contact(distributed.local, halo);
  // Caps from 0.0011 to 0.0434 by global id, off the mesh's spacing (a
  // distance equal to reach plus two caps would be decided by round-off);
  // the halo's reach covers the largest.
  auto cap_of_id = [](global_index_t id) {
    return 0.0011 + 0.0047 * static_cast<double>((id * 7) % 10);
  };
  contact.rebuild(distributed.local.rest_positions.data(), reach + 2 * 0.045);
  const auto& gid = contact.global_id();
  std::vector<double> caps(contact.num_vertices());
  for (index_t c = 0; c < contact.num_vertices(); ++c) caps[c] = cap_of_id(gid[c]);
  const ContactPairs pairs = find_contact_pairs<double>(contact, reach, true, nullptr, &caps);
  std::vector<Key> found;
  for (int kind = 0; kind < 2; ++kind)
    for (const auto& v : kind == 0 ? pairs.vertex_triangle : pairs.edge_edge)
      found.push_back(key_of(contact, kind, v));
  std::sort(found.begin(), found.end());

  std::size_t within_reach = 0;  // pairs closer than reach alone
  const std::vector<Key> brute = every_pair(contact, mesh, [&](const Key& k, double d) {
    const int second = k[0] == 0 ? 2 : 3;  // where the second side's ids start in k
    double cap[2] = {0, 0};
    for (int j = 1; j < 5; ++j) cap[j >= second] = std::max(cap[j >= second], cap_of_id(k[j]));
    within_reach += d < reach;
    return d < reach + cap[0] + cap[1];
  });
  ASSERT_GT(brute.size(), within_reach + 10);
  EXPECT_EQ(found, brute);
}

// Along paths (the guess's pull-back, contact/body_contact.hpp): exactly the
// pairs of two bodies whose boxes over both ends of their paths come within
// reach and whose gap, less the longest move of each side, is below reach,
// the same whatever the rank count (the hash's cells, sized from the boxes
// a rank holds, must not decide). The first body slides and the second
// falls past it; the far third body travels a long way alone.
TEST(ContactPairs, ASweptSearchFindsThePairsWhosePathsMayComeWithinReach) {
  const Mesh mesh = three_bodies();
  constexpr double reach = 0.01;
  const std::vector<Move> moves = {{-0.05, 0, 0.03}, {0.12, -0.05, 0}, {-0.6, 0, 0}};
  const Found whole = pairs_on(MPI_COMM_SELF, mesh, reach, false, moves);
  auto body = [&](global_index_t id) { return body_of_vertex(mesh.body_vertex_offsets, id); };
  auto at = [&](global_index_t id, double s, double* out) {
    for (int i = 0; i < 3; ++i) out[i] = mesh.positions[3 * id + i] + s * moves[body(id)][i];
  };
  // Surface triangles and edges: those of the halo on one rank.
  DistributedMesh distributed = distribute_mesh(MPI_COMM_SELF, mesh, PartitionSpec{});
  Halo<double> halo(MPI_COMM_SELF, distributed.local);
  ContactHalo<double> contact(distributed.local, halo);
  contact.rebuild(distributed.local.rest_positions.data(), reach);
  const auto& gid = contact.global_id();
  std::set<std::array<global_index_t, 3>> triangles;
  std::set<std::array<global_index_t, 2>> edges;
  std::set<global_index_t> vertices;
  for (const auto& t : contact.triangles()) {
    triangles.insert({gid[t[0]], gid[t[1]], gid[t[2]]});
    for (int k = 0; k < 3; ++k) {
      vertices.insert(gid[t[k]]);
      edges.insert(
          {std::min(gid[t[k]], gid[t[(k + 1) % 3]]), std::max(gid[t[k]], gid[t[(k + 1) % 3]])});
    }
  }
  auto length = [](const Move& m) { return std::sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]); };
  // Boxes over both ends, the first grown by reach, meet.
  auto boxes_meet = [&](const std::vector<global_index_t>& a,
                        const std::vector<global_index_t>& b) {
    for (int i = 0; i < 3; ++i) {
      double lo[2] = {1e300, 1e300}, hi[2] = {-1e300, -1e300};
      for (int side = 0; side < 2; ++side)
        for (global_index_t id : side == 0 ? a : b)
          for (double s : {0.0, 1.0}) {
            double x[3];
            at(id, s, x);
            lo[side] = std::min(lo[side], x[i]);
            hi[side] = std::max(hi[side], x[i]);
          }
      if (hi[0] + reach < lo[1] || hi[1] < lo[0] - reach) return false;
    }
    return true;
  };
  std::vector<Key> brute;
  double y[12];
  for (global_index_t p : vertices)
    for (const auto& t : triangles) {
      if (body(p) == body(t[0]) || !boxes_meet({p}, {t[0], t[1], t[2]})) continue;
      at(p, 0, y);
      for (int k = 0; k < 3; ++k) at(t[k], 0, y + 3 * (k + 1));
      const double closing = length(moves[body(p)]) + length(moves[body(t[0])]);
      if (std::sqrt(point_triangle_distance(y, false).d2) - closing < reach)
        brute.push_back({0, p, t[0], t[1], t[2]});
    }
  for (auto a = edges.begin(); a != edges.end(); ++a)
    for (auto b = std::next(a); b != edges.end(); ++b) {
      const auto &e = *a, &f = *b;
      if (body(e[0]) == body(f[0])) continue;
      // The search grows the later edge's box (by global ids), as here the
      // first; either way the boxes meet within reach.
      if (!boxes_meet({e[0], e[1]}, {f[0], f[1]})) continue;
      at(e[0], 0, y);
      at(e[1], 0, y + 3);
      at(f[0], 0, y + 6);
      at(f[1], 0, y + 9);
      const double closing = length(moves[body(e[0])]) + length(moves[body(f[0])]);
      if (std::sqrt(edge_edge_distance(y, false).d2) - closing < reach)
        brute.push_back({1, e[0], e[1], f[0], f[1]});
    }
  std::sort(brute.begin(), brute.end());
  ASSERT_GT(brute.size(), 10u);
  EXPECT_EQ(whole.all, brute);
  const Found mine = pairs_on(MPI_COMM_WORLD, mesh, reach, false, moves);
  EXPECT_EQ(gather_keys(MPI_COMM_WORLD, mine.counted), whole.all);
}

TEST(ContactPairs, GhostsFollowTheirHoldersPositions) {
  const Mesh mesh = three_bodies();
  DistributedMesh distributed = distribute_mesh(MPI_COMM_WORLD, mesh, PartitionSpec{});
  const LocalMesh& local = distributed.local;
  Halo<double> halo(MPI_COMM_WORLD, local);
  ContactHalo<double> contact(local, halo);
  contact.rebuild(local.rest_positions.data(), 0.05);
  // Every rank moves its vertices by the same function of the global id.
  auto shift = [](global_index_t id, int i) { return 1e-3 * std::sin(0.7 * id + i); };
  std::vector<double> q(local.rest_positions);
  for (index_t v = 0; v < local.num_vertices(); ++v)
    for (int i = 0; i < 3; ++i) q[3 * v + i] += shift(local.global_vertex[v], i);
  contact.update_ghosts(q.data());
  for (index_t c = 0; c < contact.num_vertices(); ++c) {
    const global_index_t id = contact.global_id()[c];
    for (int i = 0; i < 3; ++i)
      ASSERT_EQ(contact.positions()[3 * c + i], mesh.positions[3 * id + i] + shift(id, i))
          << "contact vertex " << c << " (global " << id << ")";
  }
  int ghosts = contact.num_vertices() - contact.num_local(), any = 0;
  MPI_Allreduce(&ghosts, &any, 1, MPI_INT, MPI_SUM, MPI_COMM_WORLD);
  int size = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  if (size > 1) {
    EXPECT_GT(any, 0);  // the boxes span ranks: some ghosts travel
  }
}

TEST(ContactPairs, SelfContactAddsPairsWithinABodyButNoneSharingAVertex) {
  const Mesh mesh = three_bodies();
  constexpr double reach = 0.12;  // more than an element: pairs within one body
  const Found between = pairs_on(MPI_COMM_WORLD, mesh, reach, false);
  const Found self = pairs_on(MPI_COMM_WORLD, mesh, reach, true);
  EXPECT_TRUE(
      std::includes(self.all.begin(), self.all.end(), between.all.begin(), between.all.end()));
  EXPECT_GT(self.all.size(), between.all.size());
  for (const Key& k : self.all) {
    const std::set<global_index_t> ids(k.begin() + 1, k.end());
    EXPECT_EQ(ids.size(), 4u) << "a pair shares a vertex";
  }
}

}  // namespace
}  // namespace descent
