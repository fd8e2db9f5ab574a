#include "partition/graph_partition.hpp"

#include <algorithm>

#include "comm/mpi_check.hpp"
#include "common/error.hpp"

namespace descent {

PartitionMethod choose_partition_method(const std::string& name, global_index_t num_tets) {
  if (name == "metis") return PartitionMethod::metis;
  if (name == "ptscotch") {
    if (!have_ptscotch())
      throw InputError(
          "partition.method = \"ptscotch\": this descent was built without PT-Scotch (Debian: "
          "libptscotch-dev); \"metis\" partitions on rank 0");
    return PartitionMethod::ptscotch;
  }
  if (name == "rcb") return PartitionMethod::rcb;
  if (name == "auto")
    return num_tets >= kSerialPartitionLimit && have_ptscotch() ? PartitionMethod::ptscotch
                                                                : PartitionMethod::metis;
  throw InputError("partition.method '" + name + "' is not one of: auto, metis, ptscotch, rcb");
}

const char* to_string(PartitionMethod method) {
  switch (method) {
    case PartitionMethod::metis:
      return "METIS";
    case PartitionMethod::ptscotch:
      return "PT-Scotch";
    case PartitionMethod::rcb:
      return "RCB";
  }
  return "";
}

GraphPartition partition_dual_graph(MPI_Comm comm, const DualGraph& graph, int nparts,
                                    PartitionMethod method, int tries) {
  DESCENT_VERIFY(nparts >= 1 && tries >= 1, "nparts = ", nparts, ", tries = ", tries);
  DESCENT_VERIFY(method != PartitionMethod::rcb, "RCB partitions tets, not the dual graph");
  if (graph.num_global_tets < nparts)
    throw PartitionError(detail::concat("cannot split ", graph.num_global_tets, " tets into ",
                                        nparts, " parts: fewer tets than parts"));
  GraphPartition best;
  if (nparts == 1) {
    best.part.assign(graph.num_tets(), 0);
    return best;
  }
  if (method == PartitionMethod::metis) {
    best.part = partition_with_metis(comm, graph, nparts, tries);
    best.cut_faces = count_cut_faces(comm, graph, best.part);
  } else {
    for (int t = 0; t < tries; ++t) {
      std::vector<int> part = partition_with_ptscotch(comm, graph, nparts, 2 * (t + 1));
      const global_index_t cut = count_cut_faces(comm, graph, part);
      if (t == 0 || cut < best.cut_faces) best = {std::move(part), cut};
    }
  }
  // Partitioners may leave a part empty on tiny meshes; every rank needs work.
  std::vector<global_index_t> count(nparts, 0);
  for (int p : best.part) ++count[p];
  DESCENT_MPI_CHECK(MPI_Allreduce(MPI_IN_PLACE, count.data(), nparts, MPI_INT64_T, MPI_SUM, comm));
  const auto empty = std::find(count.begin(), count.end(), 0);
  if (empty != count.end())
    throw PartitionError(detail::concat(to_string(method), " left part ", empty - count.begin(),
                                        " without tets (", graph.num_global_tets, " tets, ", nparts,
                                        " parts): use fewer ranks"));
  return best;
}

}  // namespace descent
