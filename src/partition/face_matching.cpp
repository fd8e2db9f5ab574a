#include "partition/face_matching.hpp"

#include <algorithm>
#include <array>
#include <tuple>

#include "comm/collective_error.hpp"
#include "comm/exchange.hpp"
#include "comm/mpi_check.hpp"
#include "common/block_range.hpp"
#include "common/error.hpp"

namespace descent {
namespace {

// A face of a part's tet in the part's vertex numbers, filed under its
// smallest vertex: the other two (b < c) and 4 * local tet + the corner the
// face is opposite.
struct LocalFace {
  index_t b, c;
  index_t tet_face;
};

// A face no other tet of its part has, on its way to the rank of its
// smallest vertex: global vertex ids a < b < c, its tet's global id and
// vertices (as input), part and local tet_face.
struct OpenFace {
  global_index_t a, b, c;
  global_index_t tet;
  global_index_t tet_vertices[4];
  int part;
  index_t tet_face;
};

// The answer to an open face: the tet across and its part, or kSurface.
struct FaceMatch {
  int part;
  index_t tet_face;
  global_index_t across;
  int across_part;
};

constexpr global_index_t kSurface = -1;

std::string duplicate_message(const std::string& source, global_index_t later,
                              global_index_t earlier, const global_index_t* later_vertices) {
  const global_index_t* v = later_vertices;
  return detail::concat(source, ": tet ", later, " has the same vertices as tet ", earlier, ": ",
                        v[0], " ", v[1], " ", v[2], " ", v[3]);
}

// What is wrong with a face that `count` tets have: two of them with the
// same vertices (the same vertex opposite the face: opposite(i)), named as
// build_dual_graph names them, or else more than two tets on one face.
// tet(i) is the global id of the i-th, vertices(i) its four vertex ids.
template <class Opposite, class Tet, class Vertices>
std::string crowded_face_error(const std::string& source, global_index_t a, global_index_t b,
                               global_index_t c, std::size_t count, Opposite opposite, Tet tet,
                               Vertices vertices) {
  for (std::size_t i = 0; i < count; ++i)
    for (std::size_t j = i + 1; j < count; ++j)
      if (opposite(i) == opposite(j)) {
        const std::size_t later = tet(i) > tet(j) ? i : j, earlier = i + j - later;
        return duplicate_message(source, tet(later), tet(earlier), vertices(later));
      }
  return detail::concat(source, ": the face of vertices ", a, " ", b, " ", c, " belongs to ", count,
                        " tets (", tet(0), ", ", tet(1), ", ", tet(2), (count > 3 ? ", ..." : ""),
                        "); a face has at most two");
}

// Matches the faces of one part's tets among themselves: across[4 t + f]
// gets the global id of the tet across face f of tet t; the faces left
// alone are appended to `open`. Returns an error message, or "".
std::string match_within_part(const PartTets& tets, const PartVertices& vertices,
                              const std::string& source, std::vector<global_index_t>& across,
                              std::vector<OpenFace>& open) {
  const index_t nt = tets.num_tets();
  const std::size_t nv = vertices.ids.size();
  auto sorted_face = [&](index_t t, int f) {
    std::array<index_t, 3> v;
    for (int k = 0; k < 3; ++k)
      v[k] = vertices.corners[4 * static_cast<std::size_t>(t) + kTetFaces[f][k]];
    std::sort(v.begin(), v.end());
    return v;
  };
  std::vector<std::size_t> bucket(nv + 1, 0);
  for (index_t t = 0; t < nt; ++t)
    for (int f = 0; f < 4; ++f) ++bucket[sorted_face(t, f)[0] + 1];
  for (std::size_t v = 0; v < nv; ++v) bucket[v + 1] += bucket[v];
  std::vector<LocalFace> faces(4 * static_cast<std::size_t>(nt));
  {
    std::vector<std::size_t> next(bucket.begin(), bucket.end() - 1);
    for (index_t t = 0; t < nt; ++t)
      for (int f = 0; f < 4; ++f) {
        const std::array<index_t, 3> v = sorted_face(t, f);
        faces[next[v[0]]++] = {v[1], v[2], 4 * t + f};
      }
  }
  std::string error;
  for (std::size_t a = 0; a < nv; ++a) {
    const auto begin = faces.begin() + bucket[a], end = faces.begin() + bucket[a + 1];
    std::sort(begin, end, [](const LocalFace& x, const LocalFace& y) {
      return std::tie(x.b, x.c, x.tet_face) < std::tie(y.b, y.c, y.tet_face);
    });
    for (auto k = begin; k != end;) {
      auto run = k + 1;
      while (run != end && run->b == k->b && run->c == k->c) ++run;
      if (run - k == 1) {
        const index_t t = k->tet_face / 4;
        OpenFace face{vertices.ids[a], vertices.ids[k->b], vertices.ids[k->c], tets.ids[t], {},
                      tets.part,       k->tet_face};
        std::copy_n(&tets.vertices[4 * static_cast<std::size_t>(t)], 4, face.tet_vertices);
        open.push_back(face);
      } else if (run - k == 2) {
        across[k->tet_face] = tets.ids[(k + 1)->tet_face / 4];
        across[(k + 1)->tet_face] = tets.ids[k->tet_face / 4];
      } else if (error.empty()) {
        error = crowded_face_error(
            source, vertices.ids[a], vertices.ids[k->b], vertices.ids[k->c],
            static_cast<std::size_t>(run - k),
            [&](std::size_t i) { return vertices.corners[k[i].tet_face]; },
            [&](std::size_t i) { return tets.ids[k[i].tet_face / 4]; },
            [&](std::size_t i) {
              return &tets.vertices[4 * static_cast<std::size_t>(k[i].tet_face / 4)];
            });
      }
      k = run;
    }
  }
  return error;
}

// Two tets that share two faces share all four vertices (reported by the
// part of the later tet, as build_dual_graph does).
std::string duplicate_tet_error(const PartTets& tets, const std::vector<global_index_t>& across,
                                const std::string& source) {
  for (index_t t = 0; t < tets.num_tets(); ++t)
    for (int f = 0; f < 4; ++f)
      for (int g = f + 1; g < 4; ++g) {
        const global_index_t other = across[4 * static_cast<std::size_t>(t) + f];
        if (other == kSurface || other != across[4 * static_cast<std::size_t>(t) + g] ||
            other > tets.ids[t])
          continue;
        return duplicate_message(source, tets.ids[t], other,
                                 &tets.vertices[4 * static_cast<std::size_t>(t)]);
      }
  return "";
}

}  // namespace

global_index_t match_part_faces(MPI_Comm comm, std::span<PartTets> parts,
                                std::span<const PartVertices> vertices,
                                global_index_t num_global_vertices, int num_parts,
                                const std::string& source) {
  int size = 1;
  MPI_Comm_size(comm, &size);
  DESCENT_VERIFY(parts.size() == vertices.size(), parts.size(), " parts, ", vertices.size(),
                 " vertex lists");
  const BlockRange vertex_blocks(num_global_vertices, size), part_ranks(num_parts, size);

  std::string error;
  std::vector<std::vector<global_index_t>> across(parts.size());
  std::vector<OpenFace> open;
  for (std::size_t i = 0; i < parts.size(); ++i) {
    across[i].assign(4 * static_cast<std::size_t>(parts[i].num_tets()), kSurface);
    const std::string e = match_within_part(parts[i], vertices[i], source, across[i], open);
    if (error.empty()) error = e;
  }

  Outbox<OpenFace> outbox(size);
  for (const OpenFace& face : open) outbox.count(vertex_blocks.owner(face.a));
  outbox.allocate();
  for (const OpenFace& face : open) outbox.place(vertex_blocks.owner(face.a), face);
  open = {};
  std::vector<OpenFace> arrived = exchange(comm, outbox).records;
  std::sort(arrived.begin(), arrived.end(), [](const OpenFace& x, const OpenFace& y) {
    return std::tie(x.a, x.b, x.c, x.tet) < std::tie(y.a, y.b, y.c, y.tet);
  });

  // Each open face learns the tet across it, if any; a face of two parts is
  // counted once, here.
  global_index_t cut = 0;
  std::vector<FaceMatch> matches;
  matches.reserve(arrived.size());
  for (std::size_t k = 0; k < arrived.size();) {
    std::size_t end = k + 1;
    while (end < arrived.size() && arrived[end].a == arrived[k].a &&
           arrived[end].b == arrived[k].b && arrived[end].c == arrived[k].c)
      ++end;
    const OpenFace& x = arrived[k];
    if (end - k == 1) {
      matches.push_back({x.part, x.tet_face, kSurface, -1});
    } else if (end - k == 2) {
      const OpenFace& y = arrived[k + 1];
      matches.push_back({x.part, x.tet_face, y.tet, y.part});
      matches.push_back({y.part, y.tet_face, x.tet, x.part});
      cut += x.part != y.part ? 1 : 0;
    } else if (error.empty()) {
      const OpenFace* run = &arrived[k];
      error = crowded_face_error(
          source, x.a, x.b, x.c, end - k,
          [&](std::size_t i) { return run[i].tet_vertices[run[i].tet_face % 4]; },
          [&](std::size_t i) { return run[i].tet; },
          [&](std::size_t i) { return run[i].tet_vertices; });
    }
    k = end;
  }
  arrived = {};
  Outbox<FaceMatch> answers(size);
  for (const FaceMatch& m : matches) answers.count(part_ranks.owner(m.part));
  answers.allocate();
  for (const FaceMatch& m : matches) answers.place(part_ranks.owner(m.part), m);
  matches = {};
  const Inbox<FaceMatch> answered = exchange(comm, answers);

  const int first_part = parts.empty() ? 0 : parts.front().part;
  for (std::size_t i = 0; i < parts.size(); ++i)
    parts[i].surface_faces.assign(parts[i].num_tets(), 0);
  for (const FaceMatch& m : answered.records) {
    const std::size_t i = static_cast<std::size_t>(m.part - first_part);
    across[i][m.tet_face] = m.across;
    if (m.across == kSurface)
      parts[i].surface_faces[m.tet_face / 4] |= static_cast<std::uint8_t>(1u << (m.tet_face % 4));
  }
  for (std::size_t i = 0; i < parts.size() && error.empty(); ++i)
    error = duplicate_tet_error(parts[i], across[i], source);
  DESCENT_MPI_CHECK(MPI_Allreduce(MPI_IN_PLACE, &cut, 1, MPI_INT64_T, MPI_SUM, comm));
  throw_if_any_failed(comm, error);
  return cut;
}

}  // namespace descent
