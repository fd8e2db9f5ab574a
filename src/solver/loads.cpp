#include "solver/loads.hpp"

#include <algorithm>
#include <cmath>

#include "common/error.hpp"

namespace descent {

std::vector<double> local_load_areas(const LocalMesh& mesh, const LoadRegion& region,
                                     double* area) {
  std::vector<double> share(mesh.num_vertices(), 0.0);
  *area = 0;
  for (index_t t = 0; t < mesh.num_tets(); ++t) {
    for (int f = 0; f < 4; ++f) {
      if (!(mesh.surface_faces[t] & (1u << f))) continue;
      index_t v[3];
      const double* p[3];
      bool inside = true;
      for (int k = 0; k < 3; ++k) {
        v[k] = mesh.tets[4 * static_cast<std::size_t>(t) + kTetFaces[f][k]];
        p[k] = &mesh.rest_positions[3 * static_cast<std::size_t>(v[k])];
        inside = inside && region.contains(p[k]);
      }
      if (!inside) continue;
      const double u[3] = {p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2]};
      const double w[3] = {p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2]};
      const double c[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2],
                           u[0] * w[1] - u[1] * w[0]};
      const double face_area = 0.5 * std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
      for (int k = 0; k < 3; ++k) share[v[k]] += face_area / 3.0;
      *area += face_area;
    }
  }
  return share;
}

std::array<double, 3> load_force(const LoadRegion& region, double t) {
  const double scale = region.ramp > 0 ? std::min(1.0, t / region.ramp) : 1.0;
  return {scale * region.force[0], scale * region.force[1], scale * region.force[2]};
}

std::array<double, 3> moved_position(const Motion& motion, const double* x, double t) {
  const double tm = std::min(t, motion.until);
  if (motion.kind == "translate")
    return {x[0] + motion.velocity[0] * tm, x[1] + motion.velocity[1] * tm,
            x[2] + motion.velocity[2] * tm};
  if (motion.kind == "rotate") {
    // Rodrigues: r' = r cos a + (k x r) sin a + k (k . r)(1 - cos a), r = x - centre.
    const auto& ax = motion.axis;
    const double n = std::sqrt(ax[0] * ax[0] + ax[1] * ax[1] + ax[2] * ax[2]);
    const double k[3] = {ax[0] / n, ax[1] / n, ax[2] / n};
    const double r[3] = {x[0] - motion.centre[0], x[1] - motion.centre[1], x[2] - motion.centre[2]};
    const double a = motion.angular_velocity * tm, c = std::cos(a), s = std::sin(a);
    const double kr = k[0] * r[0] + k[1] * r[1] + k[2] * r[2];
    const double kxr[3] = {k[1] * r[2] - k[2] * r[1], k[2] * r[0] - k[0] * r[2],
                           k[0] * r[1] - k[1] * r[0]};
    std::array<double, 3> out;
    for (int i = 0; i < 3; ++i)
      out[i] = motion.centre[i] + r[i] * c + kxr[i] * s + k[i] * kr * (1 - c);
    return out;
  }
  return {x[0], x[1], x[2]};
}

}  // namespace descent
