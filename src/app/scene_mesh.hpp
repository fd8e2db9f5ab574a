#pragma once
// The mesh a scene asks for: generated, or read from a file and scaled.
#include "common/mesh.hpp"
#include "io/mesh_io.hpp"
#include "io/scene.hpp"

namespace descent {

Mesh build_scene_mesh(const MeshSpec& spec, MeshReadReport* report = nullptr);

}  // namespace descent
