#pragma once
// What defines a run, so that --restart continues only the run a checkpoint
// came from. The identity is text, one "key = value" line per entry:
//   every scene key (scene_schema.hpp) but those a restart may change,
//   every [[fixed]] and [[load]] entry's keys (fixed.0.box_min, ...),
//   mesh.digest   a hash of the rest mesh (ids, coordinates, tets), the
//                 same whatever the rank count or partition,
//   partition.digest  a hash of which rank holds which tet (a checkpoint
//                 holds one rank's local state, in its local order),
//   precision     the solver's real type ("float" or "double").
// Text, not a bare hash, so a mismatch can name the key that differs.
#include <mpi.h>

#include <cstdint>
#include <string>

#include "io/scene.hpp"
#include "partition/local_mesh.hpp"

namespace descent {

// Keys a restart may change: how long the run goes on and what it writes.
// mesh.file is left to the digest, so a mesh moved to another path still
// restarts.
inline constexpr const char* kRestartMayChange[] = {"time.frames", "output.dir", "output.every",
                                                    "output.checkpoint_every", "mesh.file"};

// Collective: sums a hash of every owned vertex (global id, rest position)
// and every local tet (global id, global vertex ids) over the ranks.
std::uint64_t mesh_digest(MPI_Comm comm, const LocalMesh& local);

// Collective: a hash of (rank, global tet id) over every local tet.
std::uint64_t partition_digest(MPI_Comm comm, const LocalMesh& local);

struct MeshDigests {
  std::uint64_t mesh = 0, partition = 0;
};

std::string run_identity(const Scene& scene, const MeshDigests& digests,
                         const std::string& precision);

// Empty when `saved` and `now` agree; else one sentence naming the first key
// that differs (in `now`'s order) with both values.
std::string identity_difference(const std::string& saved, const std::string& now);

}  // namespace descent
