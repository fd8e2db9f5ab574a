// The checks every mesh passes before use: layout, index ranges, repeated
// vertices, finite coordinates, orientation and volume, duplicate tets, and
// unreferenced vertices.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <tuple>
#include <vector>

#include "common/tet_orientation.hpp"
#include "io/mesh_io_detail.hpp"

namespace descent::mesh_io_detail {

std::int64_t MeshOrigin::vertex_number(index_t v) const {
  return vertex_numbers.empty() ? first_vertex_number + v : vertex_numbers[v];
}

std::int64_t MeshOrigin::tet_number(index_t t) const {
  return tet_numbers.empty() ? first_tet_number + t : tet_numbers[t];
}

std::string MeshOrigin::tet_location(index_t t) const {
  return tet_lines.empty() ? name : detail::concat(name, ":", tet_lines[t]);
}

namespace {

[[noreturn]] void fail_tet(const MeshOrigin& origin, index_t t, const std::string& message) {
  throw InputError(
      detail::concat(origin.tet_location(t), ": tet ", origin.tet_number(t), " ", message));
}

std::string vertex_list(const Mesh& mesh, const MeshOrigin& origin, index_t t) {
  const index_t* v = &mesh.tets[4 * static_cast<std::size_t>(t)];
  return detail::concat(origin.vertex_number(v[0]), " ", origin.vertex_number(v[1]), " ",
                        origin.vertex_number(v[2]), " ", origin.vertex_number(v[3]));
}

void check_layout(const Mesh& mesh, const MeshOrigin& origin) {
  if (mesh.positions.size() % 3 != 0)
    throw InputError(detail::concat(origin.name, ": ", mesh.positions.size(),
                                    " position values is not a multiple of 3 (x y z)"));
  if (mesh.tets.size() % 4 != 0)
    throw InputError(
        detail::concat(origin.name, ": ", mesh.tets.size(), " tet indices is not a multiple of 4"));
  if (mesh.positions.size() / 3 > kMaxIndexCount || mesh.tets.size() / 4 > kMaxIndexCount)
    throw InputError(detail::concat(origin.name, ": more than ", kMaxIndexCount,
                                    " vertices or tets; indices are 32-bit"));
  if (mesh.tets.empty()) throw InputError(detail::concat(origin.name, ": the mesh has no tets"));
}

void check_indices(const Mesh& mesh, const MeshOrigin& origin) {
  const index_t num_vertices = mesh.num_vertices();
  for (index_t t = 0; t < mesh.num_tets(); ++t) {
    const index_t* v = &mesh.tets[4 * static_cast<std::size_t>(t)];
    for (int k = 0; k < 4; ++k) {
      if (v[k] < 0 || v[k] >= num_vertices)
        fail_tet(origin, t,
                 detail::concat("refers to vertex ", v[k], ", but the mesh has ", num_vertices,
                                " vertices"));
    }
    for (int a = 0; a < 4; ++a)
      for (int b = a + 1; b < 4; ++b)
        if (v[a] == v[b])
          fail_tet(origin, t,
                   detail::concat("uses vertex ", origin.vertex_number(v[a]), " twice (vertices ",
                                  vertex_list(mesh, origin, t), ")"));
  }
}

void check_coordinates(const Mesh& mesh, const MeshOrigin& origin) {
  for (index_t v = 0; v < mesh.num_vertices(); ++v) {
    const double* x = &mesh.positions[3 * static_cast<std::size_t>(v)];
    if (!std::isfinite(x[0]) || !std::isfinite(x[1]) || !std::isfinite(x[2]))
      throw InputError(detail::concat(origin.name, ": vertex ", origin.vertex_number(v),
                                      " has a non-finite coordinate (", x[0], " ", x[1], " ", x[2],
                                      ")"));
  }
}

// Flips negatively oriented tets (swapping their last two vertices) and
// returns how many; a flat tet, or one too large for doubles, is an error.
index_t orient_tets(Mesh& mesh, const MeshOrigin& origin) {
  index_t flipped = 0;
  for (index_t t = 0; t < mesh.num_tets(); ++t) {
    index_t* v = &mesh.tets[4 * static_cast<std::size_t>(t)];
    std::array<const double*, 4> x;
    for (int k = 0; k < 4; ++k) x[k] = &mesh.positions[3 * static_cast<std::size_t>(v[k])];
    const TetOrientation orientation = tet_orientation(x);
    if (orientation == TetOrientation::flat || orientation == TetOrientation::overflows)
      fail_tet(origin, t, bad_tet_description(orientation, vertex_list(mesh, origin, t)));
    if (orientation == TetOrientation::negative) {
      std::swap(v[2], v[3]);
      ++flipped;
    }
  }
  return flipped;
}

std::array<index_t, 4> sorted_vertices(const Mesh& mesh, index_t t) {
  const index_t* v = &mesh.tets[4 * static_cast<std::size_t>(t)];
  std::array<index_t, 4> sorted{v[0], v[1], v[2], v[3]};
  std::sort(sorted.begin(), sorted.end());
  return sorted;
}

// Two tets with the same vertex set, in any order, are an error. Tets are
// bucketed by their smallest vertex (a counting sort), and each bucket sorted
// by the other three: duplicates end up next to each other. Unlike a hash
// table this reads memory almost in order, which matters at 10M tets.
void check_duplicates(const Mesh& mesh, const MeshOrigin& origin) {
  struct Entry {
    std::array<index_t, 3> others;  // the three larger vertices, ascending
    index_t tet;
    bool operator<(const Entry& e) const {
      return std::tie(others, tet) < std::tie(e.others, e.tet);
    }
  };
  const index_t num_tets = mesh.num_tets();
  std::vector<std::size_t> bucket_start(mesh.num_vertices() + 1, 0);
  for (index_t t = 0; t < num_tets; ++t) ++bucket_start[sorted_vertices(mesh, t)[0] + 1];
  for (index_t v = 0; v < mesh.num_vertices(); ++v) bucket_start[v + 1] += bucket_start[v];
  std::vector<Entry> entries(num_tets);
  std::vector<std::size_t> next = bucket_start;
  for (index_t t = 0; t < num_tets; ++t) {
    const std::array<index_t, 4> s = sorted_vertices(mesh, t);
    entries[next[s[0]]++] = {{s[1], s[2], s[3]}, t};
  }
  // Report the first tet that repeats an earlier one, paired with that one.
  index_t first = -1, later = num_tets;
  for (index_t v = 0; v < mesh.num_vertices(); ++v) {
    const auto begin = entries.begin() + bucket_start[v],
               end = entries.begin() + bucket_start[v + 1];
    std::sort(begin, end);
    for (auto e = begin; e + 1 < end; ++e)
      if (e->others == (e + 1)->others && (e + 1)->tet < later) {
        first = e->tet;
        later = (e + 1)->tet;
      }
  }
  if (first < 0) return;
  std::string where = detail::concat("tet ", origin.tet_number(first));
  if (!origin.tet_lines.empty()) where += detail::concat(" (line ", origin.tet_lines[first], ")");
  fail_tet(
      origin, later,
      detail::concat("has the same vertices as ", where, ": ", vertex_list(mesh, origin, later)));
}

index_t count_unreferenced(const Mesh& mesh) {
  std::vector<char> used(mesh.num_vertices(), 0);
  for (const index_t v : mesh.tets) used[v] = 1;
  return static_cast<index_t>(std::count(used.begin(), used.end(), 0));
}

}  // namespace

void validate(Mesh& mesh, const MeshOrigin& origin, MeshReadReport* report) {
  check_layout(mesh, origin);
  check_indices(mesh, origin);
  check_coordinates(mesh, origin);
  check_duplicates(mesh, origin);  // before orienting, so messages show the file's vertex order
  const index_t flipped = orient_tets(mesh, origin);
  const index_t unreferenced = count_unreferenced(mesh);
  if (!report) return;
  report->reoriented_tets = flipped;
  report->unreferenced_vertices = unreferenced;
  if (flipped > 0)
    report->warnings.push_back(detail::concat(origin.name, ": re-oriented ", flipped, " of ",
                                              mesh.num_tets(),
                                              " tets that were negatively oriented"));
  if (unreferenced > 0)
    report->warnings.push_back(detail::concat(origin.name, ": ", unreferenced, " of ",
                                              mesh.num_vertices(),
                                              " vertices belong to no tet (kept)"));
}

}  // namespace descent::mesh_io_detail
