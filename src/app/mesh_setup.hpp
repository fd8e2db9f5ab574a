#pragma once
// The mesh of a scene, set up on every rank of a run: this rank's slice read
// or generated, the dual graph partitioned, tets and vertices moved to their
// ranks (partition/distribute.hpp); or this rank's piece read from a
// partition file (`descent partition`). Shared by run, study and tune.
#include <mpi.h>

#include <string>

#include "io/scene.hpp"
#include "partition/distribute.hpp"

namespace descent {

struct MeshSetupOptions {
  std::string partition_file;  // --partition PIECES.h5; empty: partition now
  bool talk = false;           // progress lines on rank 0 (mesh, partition, times)
};

// Collective. Failures on any rank end every rank with one message (agree).
// Warnings (the reader's, re-oriented tets, unused vertices) go to stderr
// from rank 0 whatever `talk` says.
DistributedMesh set_up_mesh(MPI_Comm comm, const Scene& scene, const MeshSetupOptions& options);

}  // namespace descent
