#include "partition/partition_quality.hpp"

#include <algorithm>
#include <sstream>

#include "comm/exchange.hpp"
#include "comm/mpi_check.hpp"
#include "common/block_range.hpp"
#include "common/error.hpp"

namespace descent {

global_index_t count_cut_faces(MPI_Comm comm, const DualGraph& graph, std::span<const int> part) {
  int size = 1;
  MPI_Comm_size(comm, &size);
  const BlockRange tet_blocks(graph.num_global_tets, size);
  const global_index_t first = graph.first_tet, last = graph.first_tet + graph.num_tets();
  // The tets across this slice's edge, each asked once from its rank.
  std::vector<global_index_t> across;
  for (const global_index_t n : graph.neighbours)
    if (n < first || n >= last) across.push_back(n);
  std::sort(across.begin(), across.end());
  across.erase(std::unique(across.begin(), across.end()), across.end());
  Outbox<global_index_t> asks(size);
  for (const global_index_t n : across) asks.count(tet_blocks.owner(n));
  asks.allocate();
  for (const global_index_t n : across) asks.place(tet_blocks.owner(n), n);
  const Inbox<global_index_t> asked = exchange(comm, asks);
  Outbox<int> answers(size);
  for (int source = 0; source < size; ++source)
    for (std::size_t k = asked.from_offsets[source]; k < asked.from_offsets[source + 1]; ++k)
      answers.count(source);
  answers.allocate();
  for (int source = 0; source < size; ++source)
    for (std::size_t k = asked.from_offsets[source]; k < asked.from_offsets[source + 1]; ++k)
      answers.place(source, part[asked.records[k] - first]);
  // `across` is ascending, so the answers, by rank in rank order, line up with it.
  const std::vector<int> across_part = exchange(comm, answers).records;

  global_index_t cut = 0;
  for (index_t t = 0; t < graph.num_tets(); ++t)
    for (global_index_t k = graph.offsets[t]; k < graph.offsets[t + 1]; ++k) {
      const global_index_t n = graph.neighbours[k];
      const int other =
          n >= first && n < last
              ? part[n - first]
              : across_part[std::lower_bound(across.begin(), across.end(), n) - across.begin()];
      cut += other != part[t] ? 1 : 0;
    }
  DESCENT_MPI_CHECK(MPI_Allreduce(MPI_IN_PLACE, &cut, 1, MPI_INT64_T, MPI_SUM, comm));
  return cut / 2;  // each cut face seen from both of its tets
}

PartitionQuality partition_quality(MPI_Comm comm, std::span<const LocalMesh> held, int num_parts,
                                   global_index_t cut_faces) {
  PartitionQuality q;
  q.tets_per_part.assign(num_parts, 0);
  q.shared_vertices_per_part.assign(num_parts, 0);
  q.neighbours_per_part.assign(num_parts, 0);
  q.shared_pairs_per_part.assign(num_parts, 0);
  for (const LocalMesh& local : held) {
    q.tets_per_part[local.rank] = local.num_tets();
    q.shared_vertices_per_part[local.rank] = local.num_shared();
    q.neighbours_per_part[local.rank] = static_cast<int>(local.neighbours.size());
    for (const auto& list : local.shared_with)
      q.shared_pairs_per_part[local.rank] += static_cast<global_index_t>(list.size());
  }
  for (auto* values : {&q.tets_per_part, &q.shared_vertices_per_part, &q.shared_pairs_per_part})
    DESCENT_MPI_CHECK(
        MPI_Allreduce(MPI_IN_PLACE, values->data(), num_parts, MPI_INT64_T, MPI_SUM, comm));
  DESCENT_MPI_CHECK(
      MPI_Allreduce(MPI_IN_PLACE, q.neighbours_per_part.data(), num_parts, MPI_INT, MPI_SUM, comm));
  q.cut_faces = cut_faces;
  global_index_t total = 0;
  for (const global_index_t t : q.tets_per_part) total += t;
  const double mean = static_cast<double>(total) / num_parts;
  q.imbalance = *std::max_element(q.tets_per_part.begin(), q.tets_per_part.end()) / mean;
  return q;
}

std::string describe(const PartitionQuality& q) {
  std::ostringstream os;
  const std::size_t parts = q.tets_per_part.size();
  os << parts << " parts, imbalance " << q.imbalance << ", cut faces " << q.cut_faces;
  constexpr std::size_t kListed = 16;
  if (parts <= kListed) {
    os << "; tets/shared vertices/neighbours per part:";
    for (std::size_t p = 0; p < parts; ++p)
      os << ' ' << q.tets_per_part[p] << '/' << q.shared_vertices_per_part[p] << '/'
         << q.neighbours_per_part[p];
  } else {
    auto range = [&](const auto& values) {
      const auto [lo, hi] = std::minmax_element(values.begin(), values.end());
      return detail::concat(*lo, "-", *hi);
    };
    os << "; per part: tets " << range(q.tets_per_part) << ", shared vertices "
       << range(q.shared_vertices_per_part) << ", neighbours " << range(q.neighbours_per_part);
  }
  return os.str();
}

}  // namespace descent
