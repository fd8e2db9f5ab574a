// PT-Scotch on the distributed dual graph: each rank hands over its slice's
// CSR rows as they are. One thread per rank (the ranks already fill the
// cores) and Scotch's deterministic mode with the seed given, so that a run
// and its restart get the same partition.
// Scotch's headers use FILE, int64_t and MPI without including them.
// clang-format off
#include <cstdint>
#include <cstdio>
#include <mpi.h>
#include <ptscotch.h>
// clang-format on

#include <limits>
#include <type_traits>

#include "comm/mpi_check.hpp"
#include "common/error.hpp"
#include "partition/graph_partition.hpp"

namespace descent {
namespace {

// Parts may differ from the mean by this fraction, as METIS's default.
constexpr double kImbalance = 0.03;
// Scotch's "speed" strategy: on the 4M helix and the four shared meshes at
// 2-64 parts it cut as few faces as the default strategy or fewer (the
// default was 16% above METIS on the helix at 4 parts, "speed" 6%), in a
// third less time (bench/results/partition_quality).

void check_scotch(int code, const char* call) {
  if (code != 0)
    throw PartitionError(detail::concat(call, " failed (PT-Scotch returned ", code, ")"));
}

// An array of the graph as SCOTCH_Num: the graph's own where the types
// agree (Scotch's 64-bit build: no copy of the largest set-up array), else a
// copy (the sizes were checked to fit).
class ScotchArray {
 public:
  explicit ScotchArray(const std::vector<global_index_t>& values) {
    if constexpr (std::is_same_v<SCOTCH_Num, global_index_t>) {
      // Scotch reads the arrays it is given and never writes them.
      data_ = const_cast<SCOTCH_Num*>(values.data());
    } else {
      copy_.assign(values.begin(), values.end());
      data_ = copy_.data();
    }
  }
  SCOTCH_Num* data() const { return data_; }

 private:
  std::vector<SCOTCH_Num> copy_;
  SCOTCH_Num* data_ = nullptr;
};

// Owns the Scotch objects of one partitioning, released in reverse order.
struct ScotchSession {
  SCOTCH_Dgraph graph{}, bound{};
  SCOTCH_Context context{};
  SCOTCH_Strat strategy{};
  bool graph_ready = false, bound_ready = false, context_ready = false, strategy_ready = false;
  ~ScotchSession() {
    if (strategy_ready) SCOTCH_stratExit(&strategy);
    if (bound_ready) SCOTCH_dgraphExit(&bound);
    if (context_ready) SCOTCH_contextExit(&context);
    if (graph_ready) SCOTCH_dgraphExit(&graph);
  }
};

}  // namespace

bool have_ptscotch() { return true; }

std::vector<int> partition_with_ptscotch(MPI_Comm comm, const DualGraph& graph, int nparts,
                                         int seed) {
  global_index_t arcs = static_cast<global_index_t>(graph.neighbours.size());
  DESCENT_MPI_CHECK(MPI_Allreduce(MPI_IN_PLACE, &arcs, 1, MPI_INT64_T, MPI_SUM, comm));
  constexpr global_index_t kNumMax = std::numeric_limits<SCOTCH_Num>::max();
  if (graph.num_global_tets > kNumMax || arcs > kNumMax)
    throw PartitionError(detail::concat(
        "PT-Scotch is built with ", 8 * sizeof(SCOTCH_Num),
        "-bit indices (SCOTCH_Num) and cannot "
        "hold ",
        graph.num_global_tets, " tets with ", arcs,
        " face adjacencies: build descent against Debian's 64-bit Scotch (libptscotch-dev "
        "installs it in scotch-int64)"));
  int size = 1;
  MPI_Comm_size(comm, &size);

  const ScotchArray offsets(graph.offsets), neighbours(graph.neighbours);
  const SCOTCH_Num num_tets = graph.num_tets();
  const SCOTCH_Num num_arcs = static_cast<SCOTCH_Num>(graph.neighbours.size());
  std::vector<SCOTCH_Num> part(std::max<SCOTCH_Num>(num_tets, 1));

  ScotchSession s;
  check_scotch(SCOTCH_dgraphInit(&s.graph, comm), "SCOTCH_dgraphInit");
  s.graph_ready = true;
  check_scotch(
      SCOTCH_dgraphBuild(&s.graph, 0, num_tets, num_tets, offsets.data(), offsets.data() + 1,
                         nullptr, nullptr, num_arcs, num_arcs, neighbours.data(), nullptr, nullptr),
      "SCOTCH_dgraphBuild");
  check_scotch(SCOTCH_contextInit(&s.context), "SCOTCH_contextInit");
  s.context_ready = true;
  check_scotch(SCOTCH_contextOptionSetNum(&s.context, SCOTCH_OPTIONNUMDETERMINISTIC, 1),
               "SCOTCH_contextOptionSetNum(DETERMINISTIC)");
  check_scotch(SCOTCH_contextOptionSetNum(&s.context, SCOTCH_OPTIONNUMRANDOMFIXEDSEED, 1),
               "SCOTCH_contextOptionSetNum(RANDOMFIXEDSEED)");
  SCOTCH_contextRandomSeed(&s.context, seed);
  check_scotch(SCOTCH_contextThreadSpawn(&s.context, 1, nullptr), "SCOTCH_contextThreadSpawn");
  check_scotch(SCOTCH_dgraphInit(&s.bound, comm), "SCOTCH_dgraphInit");
  s.bound_ready = true;
  check_scotch(SCOTCH_contextBindDgraph(&s.context, &s.graph, &s.bound),
               "SCOTCH_contextBindDgraph");
  check_scotch(SCOTCH_stratInit(&s.strategy), "SCOTCH_stratInit");
  s.strategy_ready = true;
  check_scotch(
      SCOTCH_stratDgraphMapBuild(&s.strategy, SCOTCH_STRATSPEED, size, nparts, kImbalance),
      "SCOTCH_stratDgraphMapBuild");
  check_scotch(SCOTCH_dgraphPart(&s.bound, nparts, &s.strategy, part.data()), "SCOTCH_dgraphPart");
  return std::vector<int>(part.begin(), part.begin() + num_tets);
}

}  // namespace descent
