#pragma once
// The mesh a scene asks for: generated, or read from a file and scaled.
#include <mpi.h>

#include "common/mesh.hpp"
#include "common/mesh_slice.hpp"
#include "io/mesh_io.hpp"
#include "io/scene.hpp"

namespace descent {

// The whole mesh, on the calling rank alone (tests, small tools).
Mesh build_scene_mesh(const MeshSpec& spec, MeshReadReport* report = nullptr);

// Collective: this rank's slice of it (common/mesh_slice.hpp). Generators
// make only the slice; .h5 files are read block by block on every rank;
// the other formats are parsed on rank 0 and its blocks sent out. `report`
// gets the reader's warnings on rank 0.
MeshSlice build_scene_mesh_slice(MPI_Comm comm, const MeshSpec& spec,
                                 MeshReadReport* report = nullptr);

}  // namespace descent
