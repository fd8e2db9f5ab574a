// The ball generator: a box of n x n x n cells over the cube [-1, 1]^3 (six
// tets per cell), each point p moved along its ray to p |p|_inf / |p|_2, which
// takes every cube shell onto a sphere, the cube's faces onto the ball's
// surface; then scaled by the radius and moved to the centre. A function of
// the box's points alone, so the slice is the box's slice moved alike.
#include <algorithm>
#include <cmath>

#include "common/error.hpp"
#include "meshes/generators.hpp"

namespace descent {

namespace {

BoxParams cube_of(const BallParams& params) {
  if (!(params.cells >= 1))
    throw InputError(detail::concat("ball: cells must be at least 1, got ", params.cells));
  if (!(params.radius > 0) || !std::isfinite(params.radius))
    throw InputError(detail::concat("ball: radius must be > 0, got ", params.radius));
  for (double c : params.centre)
    if (!std::isfinite(c)) throw InputError("ball: centre must be finite");
  BoxParams box;
  box.cells = {params.cells, params.cells, params.cells};
  box.size = {2.0, 2.0, 2.0};
  box.origin = {-1.0, -1.0, -1.0};
  box.tets_per_cell = 6;
  return box;
}

void round_off(const BallParams& params, std::vector<double>& positions) {
  for (std::size_t v = 0; v < positions.size() / 3; ++v) {
    double* x = &positions[3 * v];
    const double inf = std::max({std::abs(x[0]), std::abs(x[1]), std::abs(x[2])});
    const double two = std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
    const double to_sphere = two > 0 ? inf / two : 0.0;
    for (int i = 0; i < 3; ++i) x[i] = params.centre[i] + params.radius * to_sphere * x[i];
  }
}

std::string source_of(const BallParams& params) {
  return detail::concat("ball ", params.cells, "^3 cells, radius ", params.radius);
}

}  // namespace

Mesh make_ball(const BallParams& params) {
  Mesh mesh = make_box(cube_of(params));
  round_off(params, mesh.positions);
  mesh.source = source_of(params);
  return mesh;
}

MeshSlice make_ball_slice(MPI_Comm comm, const BallParams& params) {
  MeshSlice slice = make_box_slice(comm, cube_of(params));
  round_off(params, slice.positions);
  slice.source = source_of(params);
  return slice;
}

}  // namespace descent
