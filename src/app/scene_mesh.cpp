#include "app/scene_mesh.hpp"

#include "common/error.hpp"
#include "io/mesh_h5.hpp"
#include "meshes/generators.hpp"

namespace descent {

namespace {

void check_generator(const MeshSpec& spec) {
  if (spec.generator != "double_helix" && spec.generator != "box")
    throw InputError("mesh.generator '" + spec.generator + "' is not one of: double_helix, box");
}

void scale(std::vector<double>& positions, double factor) {
  if (factor != 1.0)
    for (double& x : positions) x *= factor;
}

}  // namespace

Mesh build_scene_mesh(const MeshSpec& spec, MeshReadReport* report) {
  Mesh mesh;
  if (!spec.file.empty()) {
    mesh = read_mesh(spec.file, report);
  } else {
    check_generator(spec);
    mesh = spec.generator == "double_helix" ? make_double_helix(spec.helix) : make_box(spec.box);
  }
  scale(mesh.positions, spec.scale);
  return mesh;
}

MeshSlice build_scene_mesh_slice(MPI_Comm comm, const MeshSpec& spec, MeshReadReport* report) {
  MeshSlice slice;
  if (!spec.file.empty()) {
    slice = read_mesh_slice(comm, spec.file, report);
  } else {
    check_generator(spec);
    slice = spec.generator == "double_helix" ? make_double_helix_slice(comm, spec.helix)
                                             : make_box_slice(comm, spec.box);
  }
  scale(slice.positions, spec.scale);
  return slice;
}

}  // namespace descent
