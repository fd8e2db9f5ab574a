// The double helix's voxelization: a cell belongs to the body when its centre
// lies inside a cap or within tube_radius of a strand centreline.
#include "meshes/double_helix_grid.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "common/error.hpp"

namespace descent::helix {
namespace {

constexpr double kPi = std::numbers::pi;

// Squared distance from a point to a strand centreline, given the point's
// distance rho from the axis and its phase in [0, pi]: how far, in radians of
// the helix parameter, the point lies above the strand point at its own angle,
// reduced by whole turns (and by symmetry to its absolute value).
//
// Over the helix parameter offset u the squared distance is
//   rho^2 + R^2 - 2 rho R cos u + b^2 (phase - u)^2.
// Its global minimiser lies in [0, phase] (any u outside is beaten by one
// inside with the same cos u or a whole turn nearer) and is the first root of
//   h(u) = k sin u + u - phase,  k = rho R / b^2.
// h is concave on [0, pi] and h(0) <= 0, so Newton from u = 0 climbs
// monotonically to that root with h' > 0 on the way.
double squared_distance_to_strand(double rho, double phase, const Geometry& g) {
  const double b = g.rise_per_radian;
  const double k = rho * g.helix_radius / (b * b);
  constexpr int kMaxIterations = 50;
  constexpr double kStepTolerance = 1e-10;  // radians; the distance is stationary there
  double u = 0;
  for (int iteration = 0; iteration < kMaxIterations; ++iteration) {
    const double h = k * std::sin(u) + u - phase;
    const double slope = k * std::cos(u) + 1;
    if (!(slope > 0)) break;
    const double step = -h / slope;
    if (!(step > kStepTolerance)) break;
    u = std::min(u + step, phase);
  }
  const double offset = b * (phase - u);
  return rho * rho + g.helix_radius * g.helix_radius - 2 * rho * g.helix_radius * std::cos(u) +
         offset * offset;
}

// Phase of a point relative to strand 0, reduced to [-pi, pi]; see
// squared_distance_to_strand. Relative to strand 1 it is shifted by pi.
double reduced_phase(double y, double angle, const Geometry& g) {
  const double phase = (y - g.cap_thickness) / g.rise_per_radian - angle;
  return phase - 2 * kPi * std::nearbyint(phase / (2 * kPi));
}

void require_positive_finite(double value, const char* name) {
  if (!std::isfinite(value) || !(value > 0))
    throw InputError(
        detail::concat("mesh.helix.", name, " must be a finite number > 0, got ", value));
}

}  // namespace

Geometry geometry_of(const DoubleHelixParams& params) {
  Geometry g;
  g.helix_radius = params.helix_radius;
  g.tube_radius = params.tube_radius;
  g.rise_per_radian = params.pitch / (2 * kPi);
  g.cap_thickness = 2 * params.tube_radius;
  g.height = double_helix_height(params);
  g.outer_radius = params.helix_radius + params.tube_radius;
  return g;
}

void validate(const DoubleHelixParams& params) {
  require_positive_finite(params.resolution, "resolution");
  require_positive_finite(params.helix_radius, "helix_radius");
  require_positive_finite(params.tube_radius, "tube_radius");
  require_positive_finite(params.pitch, "pitch");
  require_positive_finite(params.turns, "turns");
  if (!(params.tube_radius < params.helix_radius))
    throw InputError(detail::concat("mesh.helix.tube_radius (", params.tube_radius,
                                    ") must be < mesh.helix.helix_radius (", params.helix_radius,
                                    "), or the two tubes overlap at the axis"));
  // By the screw symmetry every point of strand 0 is equally far from strand 1.
  const Geometry g = geometry_of(params);
  const double strand_gap =
      std::sqrt(squared_distance_to_strand(g.helix_radius, kPi, g)) - 2 * g.tube_radius;
  if (!(strand_gap > 0))
    throw InputError(detail::concat(
        "mesh.helix.pitch (", params.pitch, ") is too small for mesh.helix.tube_radius (",
        params.tube_radius, "): the tubes of neighbouring turns would overlap"));
}

Grid make_grid(const DoubleHelixParams& params, const Geometry& g, NodeIndexing indexing) {
  // Whole cells must fit the body's bounding box exactly, so the edges are
  // rounded from tube_radius / resolution per axis.
  const double target_edge = params.tube_radius / params.resolution;
  const double cells_across = 2 * g.outer_radius / target_edge;
  const double cells_high = g.height / target_edge;
  const double layer_nodes = (cells_across + 2) * (cells_across + 2);
  const double nodes = indexing == NodeIndexing::kWholeGrid ? layer_nodes * (cells_high + 2)
                                                            : std::max(layer_nodes, cells_high + 2);
  if (!(nodes < std::numeric_limits<index_t>::max()))
    throw InputError(detail::concat(
        "mesh.helix.resolution = ", params.resolution,
        " is too high: ", indexing == NodeIndexing::kWholeGrid ? "the grid" : "a layer of the grid",
        " needs more nodes than a 32-bit index holds"));
  Grid grid;
  grid.nx = grid.nz = std::max<index_t>(1, index_t(std::lround(cells_across)));
  grid.ny = std::max<index_t>(1, index_t(std::lround(cells_high)));
  grid.outer_radius = g.outer_radius;
  grid.height = g.height;
  return grid;
}

std::vector<Column> columns_of(const Grid& grid) {
  std::vector<Column> columns(grid.cells_per_layer());
  for (index_t k = 0; k < grid.nz; ++k)
    for (index_t i = 0; i < grid.nx; ++i) {
      const double x = grid.centre_x(i), z = grid.centre_x(k);
      columns[std::size_t(k) * grid.nx + i] = {std::hypot(x, z), std::atan2(-z, x)};
    }
  return columns;
}

void voxelize_layer(const Grid& grid, const Geometry& g, const std::vector<Column>& columns,
                    index_t j, std::uint8_t* layer) {
  const double r = g.tube_radius;
  const double y = grid.centre_y(j);
  const bool in_cap_layer = y < g.cap_thickness || y > g.height - g.cap_thickness;
  for (index_t k = 0; k < grid.nz; ++k)
    for (index_t i = 0; i < grid.nx; ++i) {
      const Column& column = columns[std::size_t(k) * grid.nx + i];
      bool in_body;
      if (in_cap_layer) {
        in_body = column.rho < g.outer_radius;
      } else if (std::abs(column.rho - g.helix_radius) >= r) {
        in_body = false;  // outside the annulus that holds both tubes
      } else {
        // Strand 1 has the phase of strand 0 shifted by pi; the nearer strand
        // is the one of smaller absolute reduced phase, at most pi / 2.
        const double phase = std::abs(reduced_phase(y, column.angle, g));
        const double nearer_phase = std::min(phase, kPi - phase);
        in_body = squared_distance_to_strand(column.rho, nearer_phase, g) < r * r;
      }
      layer[std::size_t(k) * grid.nx + i] = in_body ? 1 : 0;
    }
}

void throw_no_cell_in_body(const DoubleHelixParams& params) {
  throw InputError(detail::concat(
      "mesh.helix.resolution = ", params.resolution, " is too low: no grid cell (edge about ",
      params.tube_radius / params.resolution, ") has its centre inside the body"));
}

std::string source_of(const DoubleHelixParams& params) {
  return detail::concat("double helix (resolution ", params.resolution, ", helix radius ",
                        params.helix_radius, ", tube radius ", params.tube_radius, ", pitch ",
                        params.pitch, ", turns ", params.turns, ")");
}

}  // namespace descent::helix
