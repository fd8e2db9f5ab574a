#pragma once
// `descent partition SCENE -n P [-o PIECES.h5] [--stats FILE.csv]`: the
// scene's mesh partitioned once into P parts, on however many ranks run the
// command (P need not equal them). It prints the partition's quality (tets,
// shared vertices and neighbours per part, faces between parts, imbalance)
// and writes the parts (partition/partition_file.hpp), which `descent run
// --partition PIECES.h5` on P ranks reads instead of partitioning again.
#include <mpi.h>

#include <string>

#include "io/scene.hpp"

namespace CLI {
class App;
}

namespace descent {

struct PartitionOptions {
  int parts = 0;
  std::string out_file;    // PIECES.h5; empty: report only
  std::string stats_file;  // one CSV row per part; empty: none
  bool quiet = false;
};

CLI::App* add_partition_subcommand(CLI::App& app, PartitionOptions& options);

// Collective; returns the exit code.
int run_partition(MPI_Comm comm, const Scene& scene, const PartitionOptions& options);

}  // namespace descent
