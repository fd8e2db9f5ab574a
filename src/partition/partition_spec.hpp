#pragma once
// How the mesh is split across ranks and numbered on each: scene keys
// partition.method, partition.tries (src/partition/graph_partition.hpp says
// what they do) and partition.reorder (src/partition/local_order.hpp).
#include <string>

namespace descent {

struct PartitionSpec {
  // "auto" (METIS below 500K tets, PT-Scotch above), "metis" (on rank 0, the
  // quality reference) or "ptscotch" (in parallel).
  std::string method = "auto";
  // Partitions computed, from different seeds, keeping the one with the
  // fewest faces between parts: a single partition's cut varies by 10-40%
  // from seed to seed (bench/results/partition_quality).
  int tries = 3;
  // Each rank's local numbering: "rcm" (reverse Cuthill-McKee within each
  // vertex class, tets by their lowest vertex; partition/local_order.hpp) or
  // "none" (ascending global id, the input's order).
  std::string reorder = "rcm";
};

}  // namespace descent
