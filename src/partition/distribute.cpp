#include "partition/distribute.hpp"

#include <algorithm>
#include <chrono>
#include <limits>

#include "comm/collective_error.hpp"
#include "comm/exchange.hpp"
#include "comm/mpi_check.hpp"
#include "common/block_range.hpp"
#include "common/error.hpp"
#include "partition/face_matching.hpp"
#include "partition/geometric_partition.hpp"
#include "partition/local_order.hpp"
#include "partition/radix_sort.hpp"

namespace descent {
namespace {

// Seconds since the last lap.
class Stopwatch {
 public:
  double lap() {
    const auto now = std::chrono::steady_clock::now();
    const double seconds = std::chrono::duration<double>(now - last_).count();
    last_ = now;
    return seconds;
  }

 private:
  std::chrono::steady_clock::time_point last_ = std::chrono::steady_clock::now();
};

int comm_size(MPI_Comm comm) {
  int size = 1;
  MPI_Comm_size(comm, &size);
  return size;
}

int comm_rank(MPI_Comm comm) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  return rank;
}

struct TetRecord {
  global_index_t id;
  global_index_t vertices[4];
  int part;
  std::uint8_t surface_faces;
};

// A part asking the holder of a vertex block for one vertex.
struct VertexRequest {
  global_index_t id;
  int part;
};

// The answer: the vertex's position and how many parts use it (their list
// follows in a second exchange).
struct VertexAnswer {
  double position[3];
  int num_sharers;
};

// Ids of the vertices a part's tets use, ascending, and for each corner its
// index among them.
void number_part_vertices(const PartTets& tets, global_index_t num_global_vertices,
                          PartVertices& vertices) {
  std::vector<KeyedIndex> corners(tets.vertices.size());
  for (std::size_t c = 0; c < corners.size(); ++c)
    corners[c] = {tets.vertices[c], static_cast<index_t>(c)};
  radix_sort(corners, num_global_vertices);
  vertices.corners.resize(corners.size());
  for (const KeyedIndex& corner : corners) {
    if (vertices.ids.empty() || vertices.ids.back() != corner.key)
      vertices.ids.push_back(corner.key);
    vertices.corners[corner.value] = static_cast<index_t>(vertices.ids.size() - 1);
  }
}

}  // namespace

std::vector<int> parts_of_rank(int rank, int ranks, int num_parts) {
  const BlockRange blocks(num_parts, ranks);
  std::vector<int> parts;
  for (global_index_t p = blocks.begin(rank); p < blocks.end(rank); ++p)
    parts.push_back(static_cast<int>(p));
  return parts;
}

std::vector<PartTets> migrate_tets(MPI_Comm comm, const MeshSlice& slice,
                                   const std::vector<std::uint8_t>& surface_faces,
                                   std::span<const int> part, int num_parts) {
  const int size = comm_size(comm);
  const BlockRange part_ranks(num_parts, size);
  Outbox<TetRecord> outbox(size);
  for (index_t t = 0; t < slice.num_tets(); ++t) outbox.count(part_ranks.owner(part[t]));
  outbox.allocate();
  for (index_t t = 0; t < slice.num_tets(); ++t) {
    TetRecord record{};
    record.id = slice.first_tet + t;
    std::copy_n(&slice.tets[4 * static_cast<std::size_t>(t)], 4, record.vertices);
    record.part = part[t];
    record.surface_faces = surface_faces[t];
    outbox.place(part_ranks.owner(part[t]), record);
  }
  const Inbox<TetRecord> inbox = exchange(comm, outbox);

  // Slices are blocks in rank order, and each rank sent its tets in order:
  // what arrived is ascending by id already, within every part.
  const std::vector<int> held = parts_of_rank(comm_rank(comm), size, num_parts);
  std::vector<PartTets> parts(held.size());
  std::vector<global_index_t> count(held.size(), 0);
  for (const TetRecord& r : inbox.records) ++count[r.part - held.front()];
  // Local corner indices (4 per tet) are 32-bit, like every per-rank array.
  constexpr global_index_t kMaxPartTets = std::numeric_limits<index_t>::max() / 4;
  std::string error;
  for (std::size_t i = 0; i < held.size() && error.empty(); ++i)
    if (count[i] > kMaxPartTets)
      error = detail::concat("part ", held[i], " has ", count[i], " tets; a rank holds at most ",
                             kMaxPartTets, " (32-bit local indices): use more ranks");
  throw_if_any_failed<PartitionError>(comm, error);
  for (std::size_t i = 0; i < held.size(); ++i) {
    parts[i].part = held[i];
    parts[i].ids.reserve(count[i]);
    parts[i].vertices.reserve(4 * static_cast<std::size_t>(count[i]));
    parts[i].surface_faces.reserve(count[i]);
  }
  for (const TetRecord& r : inbox.records) {
    PartTets& p = parts[r.part - held.front()];
    p.ids.push_back(r.id);
    p.vertices.insert(p.vertices.end(), r.vertices, r.vertices + 4);
    p.surface_faces.push_back(r.surface_faces);
  }
  return parts;
}

std::vector<PartVertices> gather_part_vertices(MPI_Comm comm, std::span<const PartTets> parts,
                                               global_index_t num_global_vertices,
                                               global_index_t first_vertex,
                                               std::span<const double> block_positions,
                                               UnusedVertices* unused) {
  const int size = comm_size(comm);
  const BlockRange vertex_blocks(num_global_vertices, size);
  std::vector<PartVertices> vertices(parts.size());
  for (std::size_t i = 0; i < parts.size(); ++i)
    number_part_vertices(parts[i], num_global_vertices, vertices[i]);

  // Requests, part by part in ascending id; the answers come back from each
  // block's rank in the order it was asked.
  Outbox<VertexRequest> requests(size);
  for (const PartVertices& v : vertices)
    for (const global_index_t id : v.ids) requests.count(vertex_blocks.owner(id));
  requests.allocate();
  for (std::size_t i = 0; i < parts.size(); ++i)
    for (const global_index_t id : vertices[i].ids)
      requests.place(vertex_blocks.owner(id), {id, parts[i].part});
  const Inbox<VertexRequest> asked = exchange(comm, requests);

  // The parts that asked for each vertex of this block, ascending.
  const index_t block_size = static_cast<index_t>(block_positions.size() / 3);
  std::vector<index_t> asked_offsets(static_cast<std::size_t>(block_size) + 1, 0);
  for (const VertexRequest& r : asked.records) ++asked_offsets[r.id - first_vertex + 1];
  for (index_t v = 0; v < block_size; ++v) asked_offsets[v + 1] += asked_offsets[v];
  std::vector<int> askers(asked.records.size());
  {
    std::vector<index_t> next(asked_offsets.begin(), asked_offsets.end() - 1);
    for (const VertexRequest& r : asked.records) askers[next[r.id - first_vertex]++] = r.part;
  }
  for (index_t v = 0; v < block_size; ++v)
    std::sort(askers.begin() + asked_offsets[v], askers.begin() + asked_offsets[v + 1]);
  if (unused) {
    *unused = {};
    for (index_t v = 0; v < block_size; ++v)
      if (asked_offsets[v] == asked_offsets[v + 1]) {
        unused->ids.push_back(first_vertex + v);
        unused->positions.insert(unused->positions.end(), &block_positions[3 * v],
                                 &block_positions[3 * v] + 3);
      }
  }

  // Answers, to each asking rank in the order it asked.
  Outbox<VertexAnswer> answers(size);
  Outbox<int> sharer_lists(size);
  for (int source = 0; source < size; ++source)
    for (std::size_t k = asked.from_offsets[source]; k < asked.from_offsets[source + 1]; ++k) {
      const index_t v = static_cast<index_t>(asked.records[k].id - first_vertex);
      answers.count(source);
      for (index_t s = asked_offsets[v]; s < asked_offsets[v + 1]; ++s) sharer_lists.count(source);
    }
  answers.allocate();
  sharer_lists.allocate();
  for (int source = 0; source < size; ++source)
    for (std::size_t k = asked.from_offsets[source]; k < asked.from_offsets[source + 1]; ++k) {
      const index_t v = static_cast<index_t>(asked.records[k].id - first_vertex);
      VertexAnswer a{};
      std::copy_n(&block_positions[3 * static_cast<std::size_t>(v)], 3, a.position);
      a.num_sharers = asked_offsets[v + 1] - asked_offsets[v];
      answers.place(source, a);
      for (index_t s = asked_offsets[v]; s < asked_offsets[v + 1]; ++s)
        sharer_lists.place(source, askers[s]);
    }
  const Inbox<VertexAnswer> answered = exchange(comm, answers);
  const Inbox<int> sharers = exchange(comm, sharer_lists);

  std::vector<std::size_t> answer_at(answered.from_offsets.begin(),
                                     answered.from_offsets.end() - 1);
  std::vector<std::size_t> sharer_at(sharers.from_offsets.begin(), sharers.from_offsets.end() - 1);
  for (PartVertices& v : vertices) {
    v.positions.resize(3 * v.ids.size());
    v.sharer_offsets.assign(v.ids.size() + 1, 0);
    for (std::size_t k = 0; k < v.ids.size(); ++k) {
      const int owner = vertex_blocks.owner(v.ids[k]);
      const VertexAnswer& a = answered.records[answer_at[owner]++];
      std::copy_n(a.position, 3, &v.positions[3 * k]);
      v.sharer_offsets[k + 1] = v.sharer_offsets[k] + a.num_sharers;
      v.sharers.insert(v.sharers.end(), sharers.records.begin() + sharer_at[owner],
                       sharers.records.begin() + sharer_at[owner] + a.num_sharers);
      sharer_at[owner] += a.num_sharers;
    }
  }
  return vertices;
}

void assemble_local_mesh(MPI_Comm comm, PartTets& tets, global_index_t num_vertices,
                         global_index_t num_tets, global_index_t first_vertex,
                         std::span<const double> block_positions, const std::string& reorder,
                         DistributedMesh& mesh, global_index_t* cut_faces) {
  Stopwatch clock;
  const std::vector<PartVertices> vertices = gather_part_vertices(
      comm, std::span(&tets, 1), num_vertices, first_vertex, block_positions, &mesh.unused);
  mesh.seconds.vertices = clock.lap();
  if (cut_faces) {
    *cut_faces = match_part_faces(comm, std::span(&tets, 1), vertices, num_vertices,
                                  comm_size(comm), mesh.source);
    mesh.seconds.face_matching = clock.lap();
  }
  index_t reoriented = 0;
  std::string error;
  try {
    mesh.local = build_local_mesh(tets, vertices.front(), comm_size(comm), num_vertices, num_tets,
                                  mesh.source, &reoriented);
  } catch (const InputError& e) {
    error = e.what();
  }
  throw_if_any_failed(comm, error);
  mesh.seconds.local_mesh = clock.lap();
  reorder_local_mesh(mesh.local, reorder);
  mesh.seconds.local_order = clock.lap();
  global_index_t counts[2] = {reoriented, static_cast<global_index_t>(mesh.unused.ids.size())};
  DESCENT_MPI_CHECK(MPI_Allreduce(MPI_IN_PLACE, counts, 2, MPI_INT64_T, MPI_SUM, comm));
  mesh.reoriented_tets = counts[0];
  mesh.unused_vertices = counts[1];
}

DistributedMesh distribute_mesh(MPI_Comm comm, MeshSlice slice, const PartitionSpec& spec) {
  const int size = comm_size(comm);
  DistributedMesh mesh;
  mesh.source = slice.source;
  mesh.method = choose_partition_method(spec.method, slice.num_global_tets);
  const global_index_t num_vertices = slice.num_global_vertices, num_tets = slice.num_global_tets;

  Stopwatch clock;
  // RCB needs no dual graph: the surface faces and the cut are found after
  // migration, from each part's own tets (face_matching.hpp).
  const bool graph_free = mesh.method == PartitionMethod::rcb;
  GraphPartition partition;
  std::vector<std::uint8_t> surface_faces;
  if (graph_free) {
    partition.part = partition_by_coordinates(comm, slice, size);
    surface_faces.assign(slice.num_tets(), 0);
  } else {
    DualGraph graph = build_dual_graph(comm, slice);
    mesh.seconds.dual_graph = clock.lap();
    partition = partition_dual_graph(comm, graph, size, mesh.method, spec.tries);
    surface_faces = std::move(graph.surface_faces);
  }
  mesh.seconds.partition = clock.lap();
  std::vector<PartTets> tets = migrate_tets(comm, slice, surface_faces, partition.part, size);
  slice.tets = {};
  mesh.seconds.migration = clock.lap();
  assemble_local_mesh(comm, tets.front(), num_vertices, num_tets, slice.first_vertex,
                      slice.positions, spec.reorder, mesh,
                      graph_free ? &partition.cut_faces : nullptr);
  slice.positions = {};
  tets = {};
  mesh.local.body_vertex_offsets = std::move(slice.body_vertex_offsets);
  mesh.quality = partition_quality(comm, std::span(&mesh.local, 1), size, partition.cut_faces);
  return mesh;
}

DistributedMesh distribute_mesh(MPI_Comm comm, const Mesh& mesh, const PartitionSpec& spec) {
  return distribute_mesh(comm, slice_of(mesh, comm_rank(comm), comm_size(comm)), spec);
}

}  // namespace descent
