#include <algorithm>

#include "common/error.hpp"
#include "partition/partition.hpp"

namespace descent {

LocalMesh build_local_mesh(const Mesh& mesh, std::span<const int> tet_part, int rank,
                           int num_ranks) {
  DESCENT_VERIFY(static_cast<index_t>(tet_part.size()) == mesh.num_tets(), "tet_part size ",
                 tet_part.size(), " vs ", mesh.num_tets(), " tets");
  LocalMesh local;
  local.rank = rank;
  local.num_ranks = num_ranks;

  // Sharers of each global vertex this rank uses, ascending rank.
  const std::vector<std::pair<index_t, int>> users = vertex_users(mesh, tet_part);
  std::vector<index_t> interior, shared_owned, shared_other, shared_by_gid;
  std::vector<std::vector<int>> sharers_of;  // parallel to shared_by_gid
  for (std::size_t k = 0; k < users.size();) {
    std::size_t end = k;
    bool mine = false;
    while (end < users.size() && users[end].first == users[k].first) {
      mine = mine || users[end].second == rank;
      ++end;
    }
    const index_t v = users[k].first;
    if (mine) {
      if (end - k == 1) {
        interior.push_back(v);
      } else {
        (users[k].second == rank ? shared_owned : shared_other).push_back(v);
        shared_by_gid.push_back(v);
        std::vector<int> sharers;
        for (std::size_t u = k; u < end; ++u)
          if (users[u].second != rank) sharers.push_back(users[u].second);
        sharers_of.push_back(std::move(sharers));
      }
    }
    k = end;
  }

  local.num_interior = static_cast<index_t>(interior.size());
  local.num_owned = local.num_interior + static_cast<index_t>(shared_owned.size());
  local.global_vertex = interior;
  local.global_vertex.insert(local.global_vertex.end(), shared_owned.begin(), shared_owned.end());
  local.global_vertex.insert(local.global_vertex.end(), shared_other.begin(), shared_other.end());

  // Global -> local for the vertices of this rank (sorted lookup, no map of
  // the whole mesh's size per rank).
  std::vector<std::pair<index_t, index_t>> to_local;
  to_local.reserve(local.global_vertex.size());
  for (index_t l = 0; l < local.num_vertices(); ++l)
    to_local.emplace_back(local.global_vertex[l], l);
  std::sort(to_local.begin(), to_local.end());
  auto local_of = [&](index_t g) {
    auto it = std::lower_bound(to_local.begin(), to_local.end(), std::pair<index_t, index_t>{g, 0});
    DESCENT_ASSERT(it != to_local.end() && it->first == g, "vertex ", g, " not on rank ", rank);
    return it->second;
  };

  local.rest_positions.resize(3 * local.global_vertex.size());
  for (index_t l = 0; l < local.num_vertices(); ++l)
    for (int i = 0; i < 3; ++i)
      local.rest_positions[3 * l + i] = mesh.positions[3 * local.global_vertex[l] + i];

  // Neighbours and the shared lists, each in ascending global id.
  for (const auto& sharers : sharers_of)
    for (int r : sharers) local.neighbours.push_back(r);
  std::sort(local.neighbours.begin(), local.neighbours.end());
  local.neighbours.erase(std::unique(local.neighbours.begin(), local.neighbours.end()),
                         local.neighbours.end());
  local.shared_with.resize(local.neighbours.size());
  for (std::size_t s = 0; s < shared_by_gid.size(); ++s) {
    for (int r : sharers_of[s]) {
      const auto n = std::lower_bound(local.neighbours.begin(), local.neighbours.end(), r) -
                     local.neighbours.begin();
      local.shared_with[n].push_back(local_of(shared_by_gid[s]));
    }
  }

  // Tets: boundary first, then interior, each by ascending global id.
  std::vector<index_t> boundary_tets, interior_tets;
  for (index_t t = 0; t < mesh.num_tets(); ++t) {
    if (tet_part[t] != rank) continue;
    bool boundary = false;
    for (int a = 0; a < 4; ++a)
      boundary = boundary || local_of(mesh.tets[4 * t + a]) >= local.num_interior;
    (boundary ? boundary_tets : interior_tets).push_back(t);
  }
  local.num_boundary_tets = static_cast<index_t>(boundary_tets.size());
  local.global_tet = boundary_tets;
  local.global_tet.insert(local.global_tet.end(), interior_tets.begin(), interior_tets.end());
  local.tets.resize(4 * local.global_tet.size());
  for (index_t t = 0; t < local.num_tets(); ++t)
    for (int a = 0; a < 4; ++a)
      local.tets[4 * t + a] = local_of(mesh.tets[4 * local.global_tet[t] + a]);

  // Vertex -> corner table.
  local.corner_offsets.assign(local.num_vertices() + 1, 0);
  for (index_t v : local.tets) ++local.corner_offsets[v + 1];
  for (index_t v = 0; v < local.num_vertices(); ++v)
    local.corner_offsets[v + 1] += local.corner_offsets[v];
  local.vertex_corners.resize(local.tets.size());
  std::vector<index_t> fill(local.corner_offsets.begin(), local.corner_offsets.end() - 1);
  for (index_t c = 0; c < static_cast<index_t>(local.tets.size()); ++c)
    local.vertex_corners[fill[local.tets[c]]++] = c;
  return local;
}

}  // namespace descent
