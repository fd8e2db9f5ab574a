// One part's LocalMesh from what arrived: its tets and its vertices with
// the parts sharing each.
#include <algorithm>
#include <array>

#include "common/error.hpp"
#include "common/tet_orientation.hpp"
#include "partition/distribute.hpp"

namespace descent {
namespace {

// Swapping corners 2 and 3 swaps the faces opposite them.
std::uint8_t swap_faces_2_and_3(std::uint8_t faces) {
  const std::uint8_t two = (faces >> 2) & 1u, three = (faces >> 3) & 1u;
  return static_cast<std::uint8_t>((faces & 0b0011u) | (three << 2) | (two << 3));
}

}  // namespace

void build_vertex_corners(LocalMesh& mesh) {
  const index_t nv = mesh.num_vertices();
  mesh.corner_offsets.assign(static_cast<std::size_t>(nv) + 1, 0);
  for (index_t v : mesh.tets) ++mesh.corner_offsets[v + 1];
  for (index_t v = 0; v < nv; ++v) mesh.corner_offsets[v + 1] += mesh.corner_offsets[v];
  mesh.vertex_corners.resize(mesh.tets.size());
  std::vector<index_t> fill(mesh.corner_offsets.begin(), mesh.corner_offsets.end() - 1);
  for (index_t c = 0; c < static_cast<index_t>(mesh.tets.size()); ++c)
    mesh.vertex_corners[fill[mesh.tets[c]]++] = c;
}

LocalMesh build_local_mesh(const PartTets& tets, const PartVertices& vertices, int num_parts,
                           global_index_t num_global_vertices, global_index_t num_global_tets,
                           const std::string& source, index_t* reoriented) {
  const int part = tets.part;
  LocalMesh local;
  local.rank = part;
  local.num_ranks = num_parts;
  local.num_global_vertices = num_global_vertices;
  local.num_global_tets = num_global_tets;

  // Local order of the part's vertices (ids ascending, so each group is
  // ascending too): interior, shared owned (this part is the lowest sharer),
  // shared others.
  const index_t nv = static_cast<index_t>(vertices.ids.size());
  auto num_sharers = [&](index_t k) {
    return vertices.sharer_offsets[k + 1] - vertices.sharer_offsets[k];
  };
  auto owned = [&](index_t k) { return vertices.sharers[vertices.sharer_offsets[k]] == part; };
  std::vector<index_t> local_of(nv);
  index_t next = 0;
  for (index_t k = 0; k < nv; ++k)
    if (num_sharers(k) == 1) local_of[k] = next++;
  local.num_interior = next;
  for (index_t k = 0; k < nv; ++k)
    if (num_sharers(k) > 1 && owned(k)) local_of[k] = next++;
  local.num_owned = next;
  for (index_t k = 0; k < nv; ++k)
    if (num_sharers(k) > 1 && !owned(k)) local_of[k] = next++;

  local.global_vertex.resize(nv);
  local.rest_positions.resize(3 * static_cast<std::size_t>(nv));
  for (index_t k = 0; k < nv; ++k) {
    local.global_vertex[local_of[k]] = vertices.ids[k];
    std::copy_n(&vertices.positions[3 * static_cast<std::size_t>(k)], 3,
                &local.rest_positions[3 * static_cast<std::size_t>(local_of[k])]);
  }

  // Neighbours, and per neighbour the shared vertices in ascending global id.
  for (index_t k = 0; k < nv; ++k)
    for (index_t s = vertices.sharer_offsets[k]; s < vertices.sharer_offsets[k + 1]; ++s)
      if (vertices.sharers[s] != part) local.neighbours.push_back(vertices.sharers[s]);
  std::sort(local.neighbours.begin(), local.neighbours.end());
  local.neighbours.erase(std::unique(local.neighbours.begin(), local.neighbours.end()),
                         local.neighbours.end());
  local.shared_with.resize(local.neighbours.size());
  for (index_t k = 0; k < nv; ++k)
    for (index_t s = vertices.sharer_offsets[k]; s < vertices.sharer_offsets[k + 1]; ++s) {
      if (vertices.sharers[s] == part) continue;
      const auto n =
          std::lower_bound(local.neighbours.begin(), local.neighbours.end(), vertices.sharers[s]) -
          local.neighbours.begin();
      local.shared_with[n].push_back(local_of[k]);
    }

  // Tets: boundary first, then interior, each by ascending global id (the
  // part's order); negatively oriented ones flipped.
  const index_t nt = tets.num_tets();
  std::vector<index_t> boundary_tets, interior_tets;
  for (index_t t = 0; t < nt; ++t) {
    bool boundary = false;
    for (int a = 0; a < 4; ++a)
      boundary = boundary || local_of[vertices.corners[4 * static_cast<std::size_t>(t) + a]] >=
                                 local.num_interior;
    (boundary ? boundary_tets : interior_tets).push_back(t);
  }
  local.num_boundary_tets = static_cast<index_t>(boundary_tets.size());
  std::vector<index_t> order = std::move(boundary_tets);
  order.insert(order.end(), interior_tets.begin(), interior_tets.end());
  local.global_tet.resize(nt);
  local.tets.resize(4 * static_cast<std::size_t>(nt));
  local.surface_faces.resize(nt);
  index_t flipped = 0;
  for (index_t l = 0; l < nt; ++l) {
    const index_t t = order[l];
    local.global_tet[l] = tets.ids[t];
    index_t* corner = &local.tets[4 * static_cast<std::size_t>(l)];
    std::array<const double*, 4> x;
    for (int a = 0; a < 4; ++a) {
      corner[a] = local_of[vertices.corners[4 * static_cast<std::size_t>(t) + a]];
      x[a] = &local.rest_positions[3 * static_cast<std::size_t>(corner[a])];
    }
    local.surface_faces[l] = tets.surface_faces[t];
    const TetOrientation orientation = tet_orientation(x);
    if (orientation == TetOrientation::flat || orientation == TetOrientation::overflows) {
      const global_index_t* v = &tets.vertices[4 * static_cast<std::size_t>(t)];
      throw InputError(detail::concat(
          source, ": tet ", tets.ids[t], " ",
          bad_tet_description(orientation, detail::concat(v[0], " ", v[1], " ", v[2], " ", v[3]))));
    }
    if (orientation == TetOrientation::negative) {
      std::swap(corner[2], corner[3]);
      local.surface_faces[l] = swap_faces_2_and_3(local.surface_faces[l]);
      ++flipped;
    }
  }
  if (reoriented) *reoriented = flipped;

  build_vertex_corners(local);
  return local;
}

}  // namespace descent
