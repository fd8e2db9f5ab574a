// Face matching in parallel: every face travels to the rank whose vertex
// block holds its smallest vertex, so the tets sharing a face meet there
// whatever ranks their slices are on; that rank answers each tet's rank with
// the tet across the face (or none: a boundary face).
#include "partition/dual_graph.hpp"

#include <algorithm>
#include <array>
#include <tuple>

#include "comm/collective_error.hpp"
#include "comm/exchange.hpp"
#include "common/error.hpp"

namespace descent {
namespace {

// A face as its sorted vertex ids (a < b < c), with the tet and corner it
// came from packed as 4 * tet + f (f: the corner the face is opposite).
struct FaceRecord {
  global_index_t a, b, c;
  global_index_t tet_face;
};

// The tet across face f of tet_face / 4, or kBoundary.
struct FaceAnswer {
  global_index_t tet_face;
  global_index_t across;
};
constexpr global_index_t kBoundary = -1;

Inbox<FaceRecord> send_faces_to_matchers(MPI_Comm comm, const MeshSlice& slice,
                                         const BlockRange& vertex_blocks) {
  auto face_of = [&](index_t t, int f) {
    std::array<global_index_t, 3> v;
    for (int k = 0; k < 3; ++k)
      v[k] = slice.tets[4 * static_cast<std::size_t>(t) + kTetFaces[f][k]];
    std::sort(v.begin(), v.end());
    return FaceRecord{v[0], v[1], v[2], 4 * (slice.first_tet + t) + f};
  };
  // Counting needs only each face's smallest vertex.
  auto smallest = [&](index_t t, int f) {
    const global_index_t* v = &slice.tets[4 * static_cast<std::size_t>(t)];
    return std::min({v[kTetFaces[f][0]], v[kTetFaces[f][1]], v[kTetFaces[f][2]]});
  };
  Outbox<FaceRecord> outbox(vertex_blocks.parts());
  for (index_t t = 0; t < slice.num_tets(); ++t)
    for (int f = 0; f < 4; ++f) outbox.count(vertex_blocks.owner(smallest(t, f)));
  outbox.allocate();
  for (index_t t = 0; t < slice.num_tets(); ++t)
    for (int f = 0; f < 4; ++f) {
      const FaceRecord face = face_of(t, f);
      outbox.place(vertex_blocks.owner(face.a), face);
    }
  return exchange(comm, outbox);
}

// The faces that arrived, grouped: equal faces next to each other. A
// counting sort by the smallest vertex (which lies in this rank's block)
// reads memory almost in order; each bucket, a few dozen faces, is then
// sorted by the other two vertices.
std::vector<FaceRecord> group_equal_faces(std::vector<FaceRecord> faces,
                                          global_index_t first_vertex,
                                          global_index_t num_vertices) {
  std::vector<std::size_t> bucket(static_cast<std::size_t>(num_vertices) + 1, 0);
  for (const FaceRecord& face : faces) ++bucket[face.a - first_vertex + 1];
  for (std::size_t v = 0; v < static_cast<std::size_t>(num_vertices); ++v)
    bucket[v + 1] += bucket[v];
  std::vector<FaceRecord> grouped(faces.size());
  {
    std::vector<std::size_t> next(bucket.begin(), bucket.end() - 1);
    for (const FaceRecord& face : faces) grouped[next[face.a - first_vertex]++] = face;
  }
  faces = {};
  for (std::size_t v = 0; v < static_cast<std::size_t>(num_vertices); ++v)
    std::sort(grouped.begin() + bucket[v], grouped.begin() + bucket[v + 1],
              [](const FaceRecord& x, const FaceRecord& y) {
                return std::tie(x.b, x.c, x.tet_face) < std::tie(y.b, y.c, y.tet_face);
              });
  return grouped;
}

// Calls visit(begin, end) for every run of equal faces.
template <class Visit>
void for_each_face_group(const std::vector<FaceRecord>& grouped, Visit&& visit) {
  for (std::size_t k = 0; k < grouped.size();) {
    std::size_t end = k + 1;
    while (end < grouped.size() && grouped[end].a == grouped[k].a &&
           grouped[end].b == grouped[k].b && grouped[end].c == grouped[k].c)
      ++end;
    visit(k, end);
    k = end;
  }
}

// Each face of a group learns every other tet of the group (two, on a
// manifold mesh); a face alone is on the boundary.
Inbox<FaceAnswer> answer_tets(MPI_Comm comm, const std::vector<FaceRecord>& grouped,
                              const BlockRange& tet_blocks) {
  Outbox<FaceAnswer> outbox(tet_blocks.parts());
  auto answer = [&](auto&& send) {
    for_each_face_group(grouped, [&](std::size_t begin, std::size_t end) {
      for (std::size_t i = begin; i < end; ++i) {
        const int rank = tet_blocks.owner(grouped[i].tet_face / 4);
        if (end - begin == 1) send(rank, FaceAnswer{grouped[i].tet_face, kBoundary});
        for (std::size_t j = begin; j < end; ++j)
          if (j != i) send(rank, FaceAnswer{grouped[i].tet_face, grouped[j].tet_face / 4});
      }
    });
  };
  answer([&](int rank, const FaceAnswer&) { outbox.count(rank); });
  outbox.allocate();
  answer([&](int rank, const FaceAnswer& a) { outbox.place(rank, a); });
  return exchange(comm, outbox);
}

// Two tets that share two faces share all four vertices.
std::string duplicate_tet_error(const MeshSlice& slice, const DualGraph& graph) {
  for (index_t t = 0; t < graph.num_tets(); ++t) {
    const global_index_t id = graph.first_tet + t;
    for (global_index_t k = graph.offsets[t]; k + 1 < graph.offsets[t + 1]; ++k) {
      const global_index_t other = graph.neighbours[k];
      // Reported once, by the rank of the later tet, as the serial check does.
      if (other != graph.neighbours[k + 1] || other > id) continue;
      const global_index_t* v = &slice.tets[4 * static_cast<std::size_t>(t)];
      return detail::concat(slice.source, ": tet ", id, " has the same vertices as tet ", other,
                            ": ", v[0], " ", v[1], " ", v[2], " ", v[3]);
    }
  }
  return "";
}

}  // namespace

DualGraph build_dual_graph(MPI_Comm comm, const MeshSlice& slice) {
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  const BlockRange vertex_blocks(slice.num_global_vertices, size);
  const BlockRange tet_blocks(slice.num_global_tets, size);
  DESCENT_VERIFY(
      slice.first_tet == tet_blocks.begin(rank) && slice.num_tets() == tet_blocks.size(rank),
      "rank ", rank, " holds tets from ", slice.first_tet, ", ", slice.num_tets(),
      " of them, not its block");
  for (const global_index_t v : slice.tets)
    DESCENT_VERIFY(v >= 0 && v < slice.num_global_vertices, "vertex id ", v,
                   " out of range: slices are validated when read");

  std::vector<FaceRecord> grouped =
      group_equal_faces(send_faces_to_matchers(comm, slice, vertex_blocks).records,
                        vertex_blocks.begin(rank), vertex_blocks.size(rank));
  const Inbox<FaceAnswer> answers = answer_tets(comm, grouped, tet_blocks);
  grouped = {};

  DualGraph graph;
  graph.num_global_tets = slice.num_global_tets;
  graph.first_tet = slice.first_tet;
  const index_t nt = slice.num_tets();
  graph.surface_faces.assign(nt, 0);
  graph.offsets.assign(static_cast<std::size_t>(nt) + 1, 0);
  for (const FaceAnswer& a : answers.records)
    if (a.across != kBoundary) ++graph.offsets[a.tet_face / 4 - slice.first_tet + 1];
  for (index_t t = 0; t < nt; ++t) graph.offsets[t + 1] += graph.offsets[t];
  graph.neighbours.resize(graph.offsets.back());
  std::vector<global_index_t> next(graph.offsets.begin(), graph.offsets.end() - 1);
  for (const FaceAnswer& a : answers.records) {
    const global_index_t t = a.tet_face / 4 - slice.first_tet;
    if (a.across == kBoundary)
      graph.surface_faces[t] |= static_cast<std::uint8_t>(1u << (a.tet_face % 4));
    else
      graph.neighbours[next[t]++] = a.across;
  }
  for (index_t t = 0; t < nt; ++t)
    std::sort(graph.neighbours.begin() + graph.offsets[t],
              graph.neighbours.begin() + graph.offsets[t + 1]);
  throw_if_any_failed(comm, duplicate_tet_error(slice, graph));
  return graph;
}

}  // namespace descent
