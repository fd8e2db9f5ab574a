// METIS, serial: the dual graph gathered on rank 0, METIS_PartGraphKway
// there (what METIS_PartMeshDual runs on the same graph), the parts
// scattered back in slice order.
#include <metis.h>

#include <limits>
#include <string>

#include "comm/mpi_check.hpp"
#include "common/error.hpp"
#include "partition/graph_partition.hpp"

namespace descent {
namespace {

const char* metis_status_name(int status) {
  switch (status) {
    case METIS_ERROR_INPUT:
      return "METIS_ERROR_INPUT";
    case METIS_ERROR_MEMORY:
      return "METIS_ERROR_MEMORY";
    default:
      return "METIS_ERROR";
  }
}

// Counts and displacements of a Gatherv/Scatterv by rank, refusing what an
// int cannot hold.
struct Layout {
  std::vector<int> counts, offsets;
};

Layout gather_layout(MPI_Comm comm, global_index_t mine) {
  int size = 1;
  MPI_Comm_size(comm, &size);
  std::vector<global_index_t> all(size);
  DESCENT_MPI_CHECK(MPI_Allgather(&mine, 1, MPI_INT64_T, all.data(), 1, MPI_INT64_T, comm));
  Layout layout{std::vector<int>(size), std::vector<int>(size)};
  global_index_t offset = 0;
  for (int r = 0; r < size; ++r) {
    layout.counts[r] = static_cast<int>(all[r]);
    layout.offsets[r] = static_cast<int>(offset);
    offset += all[r];
  }
  return layout;
}

}  // namespace

std::vector<int> partition_with_metis(MPI_Comm comm, const DualGraph& graph, int nparts,
                                      int tries) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  // idx_t is METIS's index type (32-bit in Debian's libmetis): the whole
  // graph must fit it, on rank 0.
  global_index_t arcs = static_cast<global_index_t>(graph.neighbours.size());
  DESCENT_MPI_CHECK(MPI_Allreduce(MPI_IN_PLACE, &arcs, 1, MPI_INT64_T, MPI_SUM, comm));
  constexpr global_index_t kIdxMax = std::numeric_limits<idx_t>::max();
  if (graph.num_global_tets > kIdxMax || arcs > kIdxMax)
    throw MetisError(detail::concat("METIS is built with ", 8 * sizeof(idx_t),
                                    "-bit indices and cannot hold ", graph.num_global_tets,
                                    " tets with ", arcs,
                                    " face adjacencies: use partition.method = \"ptscotch\""));

  const Layout tets = gather_layout(comm, graph.num_tets());
  const Layout adjacency =
      gather_layout(comm, static_cast<global_index_t>(graph.neighbours.size()));
  std::vector<idx_t> degree(graph.num_tets()),
      neighbours(graph.neighbours.begin(), graph.neighbours.end());
  for (index_t t = 0; t < graph.num_tets(); ++t)
    degree[t] = static_cast<idx_t>(graph.offsets[t + 1] - graph.offsets[t]);
  std::vector<idx_t> xadj, adjncy, all_parts;
  if (rank == 0) {
    xadj.resize(graph.num_global_tets + 1);
    adjncy.resize(arcs);
    all_parts.resize(graph.num_global_tets);
  }
  static_assert(sizeof(idx_t) == sizeof(int), "gathered as MPI_INT");
  DESCENT_MPI_CHECK(MPI_Gatherv(degree.data(), graph.num_tets(), MPI_INT, xadj.data() + 1,
                                tets.counts.data(), tets.offsets.data(), MPI_INT, 0, comm));
  DESCENT_MPI_CHECK(MPI_Gatherv(neighbours.data(), static_cast<int>(neighbours.size()), MPI_INT,
                                adjncy.data(), adjacency.counts.data(), adjacency.offsets.data(),
                                MPI_INT, 0, comm));
  degree = {};
  neighbours = {};

  // A METIS failure on rank 0 must end every rank: its verdict is broadcast.
  int status = METIS_OK;
  if (rank == 0) {
    for (global_index_t t = 0; t < graph.num_global_tets; ++t) xadj[t + 1] += xadj[t];
    idx_t num_vertices = static_cast<idx_t>(graph.num_global_tets), constraints = 1, parts = nparts,
          cut = 0;
    idx_t options[METIS_NOPTIONS];
    METIS_SetDefaultOptions(options);
    options[METIS_OPTION_SEED] = 1;  // the same partition on every run
    options[METIS_OPTION_NCUTS] = tries;
    status = METIS_PartGraphKway(&num_vertices, &constraints, xadj.data(), adjncy.data(), nullptr,
                                 nullptr, nullptr, &parts, nullptr, nullptr, options, &cut,
                                 all_parts.data());
    xadj = {};
    adjncy = {};
  }
  DESCENT_MPI_CHECK(MPI_Bcast(&status, 1, MPI_INT, 0, comm));
  if (status != METIS_OK)
    throw MetisError(detail::concat("METIS_PartGraphKway failed with ", metis_status_name(status),
                                    " (", graph.num_global_tets, " tets, ", nparts, " parts)"));
  std::vector<int> part(graph.num_tets());
  DESCENT_MPI_CHECK(MPI_Scatterv(all_parts.data(), tets.counts.data(), tets.offsets.data(), MPI_INT,
                                 part.data(), graph.num_tets(), MPI_INT, 0, comm));
  return part;
}

}  // namespace descent
