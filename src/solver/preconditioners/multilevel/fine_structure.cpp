#include "solver/preconditioners/multilevel/fine_structure.hpp"

#include <algorithm>

namespace descent {

FineStructure make_fine_structure(const LocalMesh& mesh, bool coloured) {
  FineStructure f;
  const index_t nv = mesh.num_vertices(), nt = mesh.num_tets();
  std::vector<std::vector<index_t>> rows(nv);
  for (index_t v = 0; v < nv; ++v)
    for (index_t k = mesh.corner_offsets[v]; k < mesh.corner_offsets[v + 1]; ++k) {
      const index_t t = mesh.vertex_corners[k] / 4;
      rows[v].insert(rows[v].end(), &mesh.tets[4 * t], &mesh.tets[4 * t] + 4);
    }
  f.pattern = pattern_from_rows(nv, rows);
  f.tet_slots.resize(16 * static_cast<std::size_t>(nt));
  for (index_t t = 0; t < nt; ++t)
    for (int a = 0; a < 4; ++a)
      for (int b = 0; b < 4; ++b)
        f.tet_slots[16 * static_cast<std::size_t>(t) + 4 * a + b] =
            f.pattern.find(mesh.tets[4 * t + a], mesh.tets[4 * t + b]);
  f.diagonal_slots.resize(nv);
  for (index_t v = 0; v < nv; ++v) f.diagonal_slots[v] = f.pattern.find(v, v);

  if (!coloured) {
    f.colour_order.resize(nt);
    for (index_t t = 0; t < nt; ++t) f.colour_order[t] = t;
    f.colour_offsets = {0, nt};
    return f;
  }
  // Greedy colouring in tet order: each tet takes the smallest colour none
  // of its vertices' tets has taken yet.
  std::vector<std::vector<index_t>> used(nv);  // colours taken at each vertex, ascending
  std::vector<index_t> colour(nt);
  index_t colours = 0;
  std::vector<index_t> taken;
  for (index_t t = 0; t < nt; ++t) {
    taken.clear();
    for (int a = 0; a < 4; ++a) {
      const auto& u = used[mesh.tets[4 * t + a]];
      taken.insert(taken.end(), u.begin(), u.end());
    }
    std::sort(taken.begin(), taken.end());
    index_t c = 0;
    for (index_t x : taken) {
      if (x > c) break;
      if (x == c) ++c;
    }
    colour[t] = c;
    colours = std::max(colours, c + 1);
    for (int a = 0; a < 4; ++a) {
      auto& u = used[mesh.tets[4 * t + a]];
      u.insert(std::lower_bound(u.begin(), u.end(), c), c);
    }
  }
  f.colour_offsets.assign(static_cast<std::size_t>(colours) + 1, 0);
  for (index_t t = 0; t < nt; ++t) ++f.colour_offsets[colour[t] + 1];
  for (index_t c = 0; c < colours; ++c) f.colour_offsets[c + 1] += f.colour_offsets[c];
  f.colour_order.resize(nt);
  std::vector<index_t> next(f.colour_offsets.begin(), f.colour_offsets.end() - 1);
  for (index_t t = 0; t < nt; ++t) f.colour_order[next[colour[t]]++] = t;
  return f;
}

}  // namespace descent
