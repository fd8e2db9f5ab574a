#pragma once
// What defines a run, so that --restart continues only the run a checkpoint
// came from. The identity is text, one "key = value" line per entry:
//   every scene key (scene_schema.hpp) but those a restart may change,
//   every [[fixed]] and [[load]] entry's keys (fixed.0.box_min, ...),
//   mesh.digest   a hash of the rest mesh (ids, coordinates, tets), the
//                 same whatever the rank count or partition,
//   precision     the solver's real type ("float" or "double").
// Text, not a bare hash, so a mismatch can name the key that differs.
#include <mpi.h>

#include <cstdint>
#include <string>

#include "io/scene.hpp"
#include "partition/partition.hpp"

namespace descent {

// Keys a restart may change: how long the run goes on and what it writes.
// mesh.file is left to the digest, so a mesh moved to another path still
// restarts.
inline constexpr const char* kRestartMayChange[] = {"time.frames", "output.dir", "output.every",
                                                    "output.checkpoint_every", "mesh.file"};

// Collective: sums a hash of every owned vertex (global id, rest position)
// and every local tet (global id, global vertex ids) over the ranks.
std::uint64_t mesh_digest(MPI_Comm comm, const LocalMesh& local);

std::string run_identity(const Scene& scene, std::uint64_t mesh_digest,
                         const std::string& precision);

// Empty when `saved` and `now` agree; else one sentence naming the first key
// that differs (in `now`'s order) with both values.
std::string identity_difference(const std::string& saved, const std::string& now);

}  // namespace descent
