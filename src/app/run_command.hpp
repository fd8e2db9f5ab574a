#pragma once
// `descent run`: simulate a scene on all ranks of comm, writing frames,
// stats and a progress line per frame.
#include <mpi.h>

#include <string>

#include "backends/backend.hpp"
#include "io/scene.hpp"

namespace descent {

struct RunOptions {
  bool quiet = false;    // no progress output (warnings and errors still on stderr)
  bool verbose = false;  // also say what is only detail, e.g. why no GPU is used
  // Reuse an output directory that already holds a run. Without it such a
  // directory is left alone and the run goes to DIR.1, DIR.2, ...
  bool overwrite = false;
  // Continue a killed run from its last checkpoint in output.dir (same scene,
  // same rank count): frames and stats after the checkpoint are replaced.
  bool restart = false;
  // The solver's real type: "float", "double", or "auto" (float on a GPU,
  // double on the CPU).
  std::string precision = "auto";
  BackendRequest backend;  // --backend, --assembly, --share-device, --no-graphs
  // --partition PIECES.h5: this rank's piece of a partition made beforehand
  // by `descent partition` (for as many ranks as this run has); empty:
  // partition now.
  std::string partition_file;
};

// Returns the process exit code: 0 on success, kStoppedExitCode
// (app/stop_request.hpp) when a signal stopped the run. Collective.
int run_scene(MPI_Comm comm, const Scene& scene, const RunOptions& options);

}  // namespace descent
