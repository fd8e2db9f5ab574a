#include "app/scene_mesh.hpp"

#include "common/error.hpp"
#include "meshes/generators.hpp"

namespace descent {

Mesh build_scene_mesh(const MeshSpec& spec, MeshReadReport* report) {
  if (!spec.file.empty()) {
    Mesh mesh = read_mesh(spec.file, report);
    if (spec.scale != 1.0)
      for (double& x : mesh.positions) x *= spec.scale;
    return mesh;
  }
  Mesh mesh;
  if (spec.generator == "double_helix")
    mesh = make_double_helix(spec.helix);
  else if (spec.generator == "box")
    mesh = make_box(spec.box);
  else
    throw InputError("mesh.generator '" + spec.generator + "' is not one of: double_helix, box");
  if (spec.scale != 1.0)
    for (double& x : mesh.positions) x *= spec.scale;
  return mesh;
}

}  // namespace descent
