#pragma once
// The mesh a scene asks for: generated, or read from a file and scaled; or
// its bodies ([[body]]) placed and joined into one mesh.
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

// The scene's mesh: [mesh]'s, or its bodies each built, placed (Body's
// scale, rotation and translation about its rest centroid) and appended in
// order, with Mesh::body_vertex_offsets, after checking that no two overlap
// (contact/body_overlap.hpp). On the calling rank alone.
Mesh build_scene_mesh(const Scene& scene, MeshReadReport* report = nullptr);

// Collective: this rank's slice of it. The bodies are built on rank 0 and
// scattered (a scene of several bodies is made of meshes one rank can hold).
MeshSlice build_scene_mesh_slice(MPI_Comm comm, const Scene& scene,
                                 MeshReadReport* report = nullptr);

}  // namespace descent
