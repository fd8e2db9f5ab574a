#include "app/scene_mesh.hpp"

#include <cmath>
#include <limits>

#include "common/error.hpp"
#include "contact/body_overlap.hpp"
#include "io/mesh_h5.hpp"
#include "meshes/generators.hpp"
#include "solver/loads.hpp"

namespace descent {

namespace {

void check_generator(const MeshSpec& spec) {
  if (spec.generator != "double_helix" && spec.generator != "box" && spec.generator != "ball" &&
      spec.generator != "car")
    throw InputError("mesh.generator '" + spec.generator +
                     "' is not one of: double_helix, box, ball, car");
}

void scale(std::vector<double>& positions, double factor) {
  if (factor != 1.0)
    for (double& x : positions) x *= factor;
}

// The centre of volume of a mesh (each tet's centroid weighted by its volume;
// the same point the lumped masses' centre of mass gives).
std::array<double, 3> centroid(const Mesh& mesh) {
  std::array<double, 3> sum{};
  double volume = 0;
  for (index_t t = 0; t < mesh.num_tets(); ++t) {
    const double* x[4];
    for (int a = 0; a < 4; ++a)
      x[a] = &mesh.positions[3 * static_cast<std::size_t>(mesh.tets[4 * t + a])];
    double e[3][3];
    for (int k = 0; k < 3; ++k)
      for (int d = 0; d < 3; ++d) e[k][d] = x[k + 1][d] - x[0][d];
    const double v = (e[0][0] * (e[1][1] * e[2][2] - e[1][2] * e[2][1]) -
                      e[0][1] * (e[1][0] * e[2][2] - e[1][2] * e[2][0]) +
                      e[0][2] * (e[1][0] * e[2][1] - e[1][1] * e[2][0])) /
                     6.0;
    volume += v;
    for (int d = 0; d < 3; ++d) sum[d] += v * (x[0][d] + x[1][d] + x[2][d] + x[3][d]) / 4.0;
  }
  for (double& c : sum) c /= volume;
  return sum;
}

// x = c + translate + Rot(axis, degrees) (scale (X - c)), c the rest centroid;
// the steps a body does not ask for are skipped, so an unmoved body keeps its
// coordinates bit for bit.
void place(Mesh& mesh, const Body& body) {
  const std::array<double, 3> c = centroid(mesh);
  Motion rotation;
  rotation.kind = "rotate";
  rotation.axis = body.rotate_axis;
  rotation.centre = c;
  rotation.angular_velocity = body.rotate_degrees * M_PI / 180.0;  // turned in t = 1 s
  for (index_t v = 0; v < mesh.num_vertices(); ++v) {
    double* x = &mesh.positions[3 * static_cast<std::size_t>(v)];
    if (body.scale != 1.0)
      for (int d = 0; d < 3; ++d) x[d] = c[d] + body.scale * (x[d] - c[d]);
    if (body.rotate_degrees != 0) {
      const std::array<double, 3> turned = moved_position(rotation, x, 1.0);
      for (int d = 0; d < 3; ++d) x[d] = turned[d];
    }
    for (int d = 0; d < 3; ++d) x[d] += body.translate[d];
  }
}

Mesh build_bodies_mesh(const std::vector<Body>& bodies, MeshReadReport* report) {
  Mesh all;
  all.source = detail::concat(bodies.size(), " bodies");
  all.body_vertex_offsets.push_back(0);
  std::vector<std::string> names;
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    MeshReadReport body_report;
    Mesh mesh = build_scene_mesh(bodies[b].mesh, &body_report);
    if (report)
      report->warnings.insert(report->warnings.end(), body_report.warnings.begin(),
                              body_report.warnings.end());
    place(mesh, bodies[b]);
    const index_t first = all.num_vertices();
    const global_index_t total = static_cast<global_index_t>(first) + mesh.num_vertices();
    if (total > std::numeric_limits<index_t>::max())
      throw InputError(detail::concat("body.", b, ": the bodies hold ", total,
                                      " vertices together; a scene of several bodies is built on "
                                      "one rank and takes at most 2^31 - 1"));
    all.positions.insert(all.positions.end(), mesh.positions.begin(), mesh.positions.end());
    for (index_t corner : mesh.tets) all.tets.push_back(first + corner);
    all.body_vertex_offsets.push_back(all.num_vertices());
    names.push_back(detail::concat("body.", b, " (", mesh.source, ")"));
  }
  check_bodies_apart(all, names);
  return all;
}

}  // namespace

Mesh build_scene_mesh(const Scene& scene, MeshReadReport* report) {
  if (scene.bodies.empty()) return build_scene_mesh(scene.mesh, report);
  return build_bodies_mesh(scene.bodies, report);
}

MeshSlice build_scene_mesh_slice(MPI_Comm comm, const Scene& scene, MeshReadReport* report) {
  if (scene.bodies.empty()) return build_scene_mesh_slice(comm, scene.mesh, report);
  if (report) *report = MeshReadReport{};
  return scatter_mesh_from_rank0(
      comm, [&] { return build_bodies_mesh(scene.bodies, report); },
      detail::concat(scene.bodies.size(), " bodies"));
}

Mesh build_scene_mesh(const MeshSpec& spec, MeshReadReport* report) {
  Mesh mesh;
  if (!spec.file.empty()) {
    mesh = read_mesh(spec.file, report);
  } else {
    check_generator(spec);
    mesh = spec.generator == "double_helix" ? make_double_helix(spec.helix)
           : spec.generator == "ball"       ? make_ball(spec.ball)
           : spec.generator == "car"        ? make_car(spec.car)
                                            : make_box(spec.box);
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
    // The car has no slice generator: it is small, built on rank 0 and scattered.
    if (spec.generator == "car")
      return scatter_mesh_from_rank0(
          comm, [&] { return build_scene_mesh(spec, nullptr); }, "car");
    slice = spec.generator == "double_helix" ? make_double_helix_slice(comm, spec.helix)
            : spec.generator == "ball"       ? make_ball_slice(comm, spec.ball)
                                             : make_box_slice(comm, spec.box);
  }
  scale(slice.positions, spec.scale);
  return slice;
}

}  // namespace descent
