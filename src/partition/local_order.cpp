#include "partition/local_order.hpp"

#include <algorithm>

#include "common/error.hpp"

namespace descent {
namespace {

// Vertex adjacency of the mesh (CSR, each row ascending, no self loops):
// vertices joined by an edge of some tet.
void vertex_graph(const LocalMesh& mesh, std::vector<index_t>& offsets,
                  std::vector<index_t>& adjacent) {
  const index_t nv = mesh.num_vertices();
  offsets.assign(static_cast<std::size_t>(nv) + 1, 0);
  adjacent.clear();
  std::vector<index_t> row;
  for (index_t v = 0; v < nv; ++v) {
    row.clear();
    for (index_t k = mesh.corner_offsets[v]; k < mesh.corner_offsets[v + 1]; ++k) {
      const index_t* tet = &mesh.tets[4 * static_cast<std::size_t>(mesh.vertex_corners[k] / 4)];
      for (int a = 0; a < 4; ++a)
        if (tet[a] != v) row.push_back(tet[a]);
    }
    std::sort(row.begin(), row.end());
    row.erase(std::unique(row.begin(), row.end()), row.end());
    adjacent.insert(adjacent.end(), row.begin(), row.end());
    offsets[v + 1] = static_cast<index_t>(adjacent.size());
  }
}

// Breadth-first level structures over the vertices of [first, last) not yet
// placed.
class LevelSearch {
 public:
  LevelSearch(const std::vector<index_t>& offsets, const std::vector<index_t>& adjacent,
              index_t first, index_t last)
      : offsets_(offsets),
        adjacent_(adjacent),
        first_(first),
        last_(last),
        seen_(last - first, 0) {}

  // The levels from `root`: `reached` gets the vertices in visiting order;
  // returns the number of levels, and where the last one starts in *far.
  int run(index_t root, const std::vector<char>& placed, std::vector<index_t>& reached,
          std::size_t* far) {
    ++searches_;
    reached.assign(1, root);
    seen_[root - first_] = searches_;
    std::size_t level_start = 0;
    for (int levels = 1;; ++levels) {
      const std::size_t level_end = reached.size();
      for (std::size_t k = level_start; k < level_end; ++k)
        for (index_t s = offsets_[reached[k]]; s < offsets_[reached[k] + 1]; ++s) {
          const index_t u = adjacent_[s];
          if (u < first_ || u >= last_ || placed[u - first_] || seen_[u - first_] == searches_)
            continue;
          seen_[u - first_] = searches_;
          reached.push_back(u);
        }
      if (reached.size() == level_end) {
        *far = level_start;
        return levels;
      }
      level_start = level_end;
    }
  }

 private:
  const std::vector<index_t>& offsets_;
  const std::vector<index_t>& adjacent_;
  index_t first_, last_;
  std::vector<int> seen_;  // per vertex of the range: the last search that reached it
  int searches_ = 0;
};

}  // namespace

std::vector<index_t> reverse_cuthill_mckee(const std::vector<index_t>& offsets,
                                           const std::vector<index_t>& adjacent, index_t first,
                                           index_t last) {
  const index_t n = last - first;
  std::vector<index_t> degree(n, 0);
  for (index_t v = first; v < last; ++v)
    for (index_t s = offsets[v]; s < offsets[v + 1]; ++s)
      if (adjacent[s] >= first && adjacent[s] < last) ++degree[v - first];
  auto before = [&](index_t a, index_t b) {
    return degree[a - first] != degree[b - first] ? degree[a - first] < degree[b - first] : a < b;
  };

  LevelSearch search(offsets, adjacent, first, last);
  std::vector<char> placed(n, 0);
  std::vector<index_t> order, reached, trial, candidates;
  order.reserve(n);
  for (index_t start = first; start < last; ++start) {
    if (placed[start - first]) continue;
    // A pseudo-peripheral root: a vertex of least degree in the last level,
    // again from there while the level structure keeps getting deeper.
    index_t root = start;
    std::size_t far = 0;
    int levels = search.run(root, placed, reached, &far);
    while (true) {
      const index_t candidate = *std::min_element(reached.begin() + far, reached.end(), before);
      std::size_t trial_far = 0;
      const int trial_levels = search.run(candidate, placed, trial, &trial_far);
      if (trial_levels <= levels) break;
      root = candidate;
      levels = trial_levels;
      reached.swap(trial);
      far = trial_far;
    }
    // Cuthill-McKee from the root: each vertex's unplaced neighbours in
    // ascending degree.
    const std::size_t piece_start = order.size();
    order.push_back(root);
    placed[root - first] = 1;
    for (std::size_t k = piece_start; k < order.size(); ++k) {
      candidates.clear();
      for (index_t s = offsets[order[k]]; s < offsets[order[k] + 1]; ++s) {
        const index_t u = adjacent[s];
        if (u >= first && u < last && !placed[u - first]) candidates.push_back(u);
      }
      std::sort(candidates.begin(), candidates.end(), before);
      for (index_t u : candidates) {
        placed[u - first] = 1;
        order.push_back(u);
      }
    }
  }
  std::reverse(order.begin(), order.end());
  return order;
}

void reorder_local_mesh(LocalMesh& mesh, const std::string& method) {
  if (method == "none") return;
  DESCENT_VERIFY(method == "rcm", "partition.reorder '", method, "'");
  const index_t nv = mesh.num_vertices(), nt = mesh.num_tets();

  // Vertices: each class reordered within its range.
  std::vector<index_t> offsets, adjacent;
  vertex_graph(mesh, offsets, adjacent);
  std::vector<index_t> new_of_old(nv);
  const index_t bounds[4] = {0, mesh.num_interior, mesh.num_owned, nv};
  for (int c = 0; c < 3; ++c) {
    const std::vector<index_t> order =
        reverse_cuthill_mckee(offsets, adjacent, bounds[c], bounds[c + 1]);
    for (std::size_t k = 0; k < order.size(); ++k)
      new_of_old[order[k]] = bounds[c] + static_cast<index_t>(k);
  }
  std::vector<global_index_t> global_vertex(nv);
  std::vector<double> rest_positions(mesh.rest_positions.size());
  for (index_t v = 0; v < nv; ++v) {
    global_vertex[new_of_old[v]] = mesh.global_vertex[v];
    std::copy_n(&mesh.rest_positions[3 * static_cast<std::size_t>(v)], 3,
                &rest_positions[3 * static_cast<std::size_t>(new_of_old[v])]);
  }
  mesh.global_vertex.swap(global_vertex);
  mesh.rest_positions.swap(rest_positions);
  for (index_t& v : mesh.tets) v = new_of_old[v];
  for (std::vector<index_t>& shared : mesh.shared_with)
    for (index_t& v : shared) v = new_of_old[v];  // the list's order (global id) stays

  // Tets: each class by its lowest corner, then global id. Each class comes
  // in ascending global id (local_mesh.hpp), so a stable counting sort by
  // the lowest corner gives that order in linear time (a comparison sort of
  // millions of tets took a good part of this step).
  std::vector<index_t> lowest(nt);
  for (index_t t = 0; t < nt; ++t)
    lowest[t] = *std::min_element(&mesh.tets[4 * static_cast<std::size_t>(t)],
                                  &mesh.tets[4 * static_cast<std::size_t>(t)] + 4);
  std::vector<index_t> tet_order(nt);
  std::vector<index_t> start(static_cast<std::size_t>(nv) + 1);
  auto sort_class = [&](index_t begin, index_t end) {
    DESCENT_ASSERT(std::is_sorted(mesh.global_tet.begin() + begin, mesh.global_tet.begin() + end),
                   "tets of a class in ascending global id");
    std::fill(start.begin(), start.end(), 0);
    for (index_t t = begin; t < end; ++t) ++start[lowest[t] + 1];
    for (index_t v = 0; v < nv; ++v) start[v + 1] += start[v];
    for (index_t t = begin; t < end; ++t) tet_order[begin + start[lowest[t]]++] = t;
  };
  sort_class(0, mesh.num_boundary_tets);
  sort_class(mesh.num_boundary_tets, nt);
  std::vector<global_index_t> global_tet(nt);
  std::vector<index_t> tets(mesh.tets.size());
  std::vector<std::uint8_t> surface_faces(nt);
  for (index_t l = 0; l < nt; ++l) {
    const index_t t = tet_order[l];
    global_tet[l] = mesh.global_tet[t];
    std::copy_n(&mesh.tets[4 * static_cast<std::size_t>(t)], 4,
                &tets[4 * static_cast<std::size_t>(l)]);
    surface_faces[l] = mesh.surface_faces[t];
  }
  mesh.global_tet.swap(global_tet);
  mesh.tets.swap(tets);
  mesh.surface_faces.swap(surface_faces);
  build_vertex_corners(mesh);
}

double mean_corner_spread(const LocalMesh& mesh) {
  if (mesh.num_tets() == 0) return 0;
  double total = 0;
  for (index_t t = 0; t < mesh.num_tets(); ++t) {
    const index_t* c = &mesh.tets[4 * static_cast<std::size_t>(t)];
    total += *std::max_element(c, c + 4) - *std::min_element(c, c + 4);
  }
  return total / mesh.num_tets();
}

}  // namespace descent
