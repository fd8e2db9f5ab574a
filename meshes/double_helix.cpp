// The double helix generator. The body is voxelized on a regular grid: a cell
// belongs to it when its centre lies inside a cap or within tube_radius of a
// strand centreline. Each body cell becomes six Kuhn tets (hex_split.hpp), so
// the mesh is conforming by construction and exactly reproducible.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <vector>

#include "common/error.hpp"
#include "meshes/generators.hpp"
#include "meshes/hex_split.hpp"

namespace descent {
namespace {

constexpr double kPi = std::numbers::pi;

// Strand 0 has the centreline (R cos t, cap + b t, -R sin t) for every real t
// (a right-handed helix about +y, clipped by the body's y-range), with
// R = helix_radius, b = pitch / 2pi and cap = cap_thickness; strand 1 is strand
// 0 turned by pi about the axis.
struct HelixGeometry {
  double helix_radius;
  double tube_radius;
  double rise_per_radian;  // b
  double cap_thickness;
  double height;
  double outer_radius;  // of the caps and of the grid: helix_radius + tube_radius
};

HelixGeometry geometry_of(const DoubleHelixParams& params) {
  HelixGeometry g;
  g.helix_radius = params.helix_radius;
  g.tube_radius = params.tube_radius;
  g.rise_per_radian = params.pitch / (2 * kPi);
  g.cap_thickness = 2 * params.tube_radius;
  g.height = double_helix_height(params);
  g.outer_radius = params.helix_radius + params.tube_radius;
  return g;
}

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
double squared_distance_to_strand(double rho, double phase, const HelixGeometry& g) {
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
double reduced_phase(double y, double angle, const HelixGeometry& g) {
  const double phase = (y - g.cap_thickness) / g.rise_per_radian - angle;
  return phase - 2 * kPi * std::nearbyint(phase / (2 * kPi));
}

void require_positive_finite(double value, const char* name) {
  if (!std::isfinite(value) || !(value > 0))
    throw InputError(
        detail::concat("mesh.helix.", name, " must be a finite number > 0, got ", value));
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
  const HelixGeometry g = geometry_of(params);
  const double strand_gap =
      std::sqrt(squared_distance_to_strand(g.helix_radius, kPi, g)) - 2 * g.tube_radius;
  if (!(strand_gap > 0))
    throw InputError(detail::concat(
        "mesh.helix.pitch (", params.pitch, ") is too small for mesh.helix.tube_radius (",
        params.tube_radius, "): the tubes of neighbouring turns would overlap"));
}

// A regular grid over [-outer, outer] x [0, height] x [-outer, outer] with
// near-cubic cells. Cells and nodes are numbered x fastest, then z, then y.
struct Grid {
  index_t nx, ny, nz;  // cells per axis
  double outer_radius, height;

  std::int64_t num_cells() const { return std::int64_t(nx) * ny * nz; }
  std::int64_t num_nodes() const { return std::int64_t(nx + 1) * (ny + 1) * (nz + 1); }
  index_t cell(index_t i, index_t j, index_t k) const { return (j * nz + k) * nx + i; }
  index_t node(index_t i, index_t j, index_t k) const { return (j * (nz + 1) + k) * (nx + 1) + i; }
  // Coordinates of node i along x (or z), j along y; exact and symmetric at the ends.
  double node_x(index_t i) const { return outer_radius * (double(2 * i - nx) / nx); }
  double node_y(index_t j) const { return height * (double(j) / ny); }
  double centre_x(index_t i) const { return outer_radius * (double(2 * i + 1 - nx) / nx); }
  double centre_y(index_t j) const { return height * ((j + 0.5) / ny); }
};

Grid make_grid(const DoubleHelixParams& params, const HelixGeometry& g) {
  // Whole cells must fit the body's bounding box exactly, so the edges are
  // rounded from tube_radius / resolution per axis.
  const double target_edge = params.tube_radius / params.resolution;
  const double cells_across = 2 * g.outer_radius / target_edge;
  const double cells_high = g.height / target_edge;
  const double nodes = (cells_across + 2) * (cells_across + 2) * (cells_high + 2);
  if (!(nodes < std::numeric_limits<index_t>::max()))
    throw InputError(detail::concat("mesh.helix.resolution = ", params.resolution,
                                    " is too high: the grid needs more nodes than a 32-bit "
                                    "index holds"));
  Grid grid;
  grid.nx = grid.nz = std::max<index_t>(1, index_t(std::lround(cells_across)));
  grid.ny = std::max<index_t>(1, index_t(std::lround(cells_high)));
  grid.outer_radius = g.outer_radius;
  grid.height = g.height;
  return grid;
}

// 1 for cells whose centre lies in the body, else 0; indexed by Grid::cell.
std::vector<std::uint8_t> voxelize(const Grid& grid, const HelixGeometry& g) {
  // Per (x, z) column: distance from the axis and angle, so that a point is
  // (rho cos angle, y, -rho sin angle) as on the strands.
  struct Column {
    double rho;
    double angle;
  };
  std::vector<Column> columns(std::size_t(grid.nx) * grid.nz);
  for (index_t k = 0; k < grid.nz; ++k)
    for (index_t i = 0; i < grid.nx; ++i) {
      const double x = grid.centre_x(i), z = grid.centre_x(k);
      columns[std::size_t(k) * grid.nx + i] = {std::hypot(x, z), std::atan2(-z, x)};
    }

  const double r = g.tube_radius;
  std::vector<std::uint8_t> inside(grid.num_cells(), 0);
  for (index_t j = 0; j < grid.ny; ++j) {
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
        inside[grid.cell(i, j, k)] = in_body ? 1 : 0;
      }
  }
  return inside;
}

// Clears every body cell outside the largest face-connected component (the
// first found, in cell order, among equals). Voxelizing thin parts could
// leave islands; the presets have none.
void keep_largest_component(const Grid& grid, std::vector<std::uint8_t>& inside) {
  constexpr index_t kUnvisited = -1;
  std::vector<index_t> component(inside.size(), kUnvisited);
  std::vector<index_t> stack;
  index_t num_components = 0, largest = kUnvisited;
  std::int64_t largest_size = 0;
  for (index_t j = 0; j < grid.ny; ++j)
    for (index_t k = 0; k < grid.nz; ++k)
      for (index_t i = 0; i < grid.nx; ++i) {
        const index_t seed = grid.cell(i, j, k);
        if (!inside[seed] || component[seed] != kUnvisited) continue;
        const index_t id = num_components++;
        std::int64_t size = 0;
        component[seed] = id;
        stack.push_back(seed);
        while (!stack.empty()) {
          const index_t cell = stack.back();
          stack.pop_back();
          ++size;
          const index_t ci = cell % grid.nx, ck = (cell / grid.nx) % grid.nz,
                        cj = cell / (grid.nx * grid.nz);
          auto visit = [&](index_t ni, index_t nj, index_t nk) {
            const index_t neighbour = grid.cell(ni, nj, nk);
            if (inside[neighbour] && component[neighbour] == kUnvisited) {
              component[neighbour] = id;
              stack.push_back(neighbour);
            }
          };
          if (ci > 0) visit(ci - 1, cj, ck);
          if (ci + 1 < grid.nx) visit(ci + 1, cj, ck);
          if (cj > 0) visit(ci, cj - 1, ck);
          if (cj + 1 < grid.ny) visit(ci, cj + 1, ck);
          if (ck > 0) visit(ci, cj, ck - 1);
          if (ck + 1 < grid.nz) visit(ci, cj, ck + 1);
        }
        if (size > largest_size) {
          largest_size = size;
          largest = id;
        }
      }
  if (num_components <= 1) return;
  for (std::size_t cell = 0; cell < inside.size(); ++cell)
    if (component[cell] != largest) inside[cell] = 0;
}

// Corner c (numbered as in hex_split.hpp) of cell (i, j, k), as a grid node.
index_t corner_node(const Grid& grid, index_t i, index_t j, index_t k, int corner) {
  return grid.node(i + (corner & 1), j + ((corner >> 1) & 1), k + ((corner >> 2) & 1));
}

// Six Kuhn tets per body cell, on the grid nodes they use, numbered densely in
// grid node order; tets come in grid cell order.
Mesh tetrahedralize(const Grid& grid, const std::vector<std::uint8_t>& inside) {
  const std::int64_t num_body_cells = std::count(inside.begin(), inside.end(), 1);
  if (num_body_cells * 6 > std::numeric_limits<index_t>::max())
    throw InputError("mesh.helix.resolution is too high: more tets than a 32-bit index holds");

  constexpr index_t kUnused = -1;
  std::vector<index_t> vertex_of_node(grid.num_nodes(), kUnused);
  for (index_t j = 0; j < grid.ny; ++j)
    for (index_t k = 0; k < grid.nz; ++k)
      for (index_t i = 0; i < grid.nx; ++i)
        if (inside[grid.cell(i, j, k)])
          for (int corner = 0; corner < 8; ++corner)
            vertex_of_node[corner_node(grid, i, j, k, corner)] = 0;

  Mesh mesh;
  index_t num_vertices = 0;
  for (index_t j = 0; j <= grid.ny; ++j)
    for (index_t k = 0; k <= grid.nz; ++k)
      for (index_t i = 0; i <= grid.nx; ++i) {
        index_t& vertex = vertex_of_node[grid.node(i, j, k)];
        if (vertex == kUnused) continue;
        vertex = num_vertices++;
        mesh.positions.insert(mesh.positions.end(),
                              {grid.node_x(i), grid.node_y(j), grid.node_x(k)});
      }

  mesh.tets.reserve(std::size_t(num_body_cells) * 6 * 4);
  for (index_t j = 0; j < grid.ny; ++j)
    for (index_t k = 0; k < grid.nz; ++k)
      for (index_t i = 0; i < grid.nx; ++i) {
        if (!inside[grid.cell(i, j, k)]) continue;
        index_t corner_vertex[8];
        for (int corner = 0; corner < 8; ++corner)
          corner_vertex[corner] = vertex_of_node[corner_node(grid, i, j, k, corner)];
        for (const hex_split::TetCorners& tet : hex_split::kKuhnTets)
          for (int corner : tet) mesh.tets.push_back(corner_vertex[corner]);
      }
  return mesh;
}

}  // namespace

double double_helix_height(const DoubleHelixParams& params) {
  return params.turns * params.pitch + 4 * params.tube_radius;
}

double double_helix_preset_resolution(const std::string& name) {
  // Found by experiment with the default geometry. The grid size changes in
  // steps, so each value sits mid-way along its step; the comments give the
  // grid (cells across x and z, cells along y) and the tet count.
  if (name == "41k") return 2.42;   // 20 x 40: 40,872 tets (-0.3%)
  if (name == "82k") return 3.075;  // 25 x 51: 79,680 tets (-2.8%)
  if (name == "158k") return 3.8;   // 31 x 63: 154,656 tets (-2.1%)
  if (name == "316k") return 4.8;   // 40 x 79: 324,624 tets (+2.7%)
  throw InputError(detail::concat("unknown double helix preset '", name,
                                  "'; valid presets: 41k, 82k, 158k, 316k"));
}

Mesh make_double_helix(const DoubleHelixParams& params) {
  validate(params);
  const HelixGeometry g = geometry_of(params);
  const Grid grid = make_grid(params, g);
  std::vector<std::uint8_t> inside = voxelize(grid, g);
  if (std::find(inside.begin(), inside.end(), 1) == inside.end())
    throw InputError(detail::concat(
        "mesh.helix.resolution = ", params.resolution, " is too low: no grid cell (edge about ",
        params.tube_radius / params.resolution, ") has its centre inside the body"));
  keep_largest_component(grid, inside);
  Mesh mesh = tetrahedralize(grid, inside);
  mesh.source = detail::concat("double helix (resolution ", params.resolution, ", helix radius ",
                               params.helix_radius, ", tube radius ", params.tube_radius,
                               ", pitch ", params.pitch, ", turns ", params.turns, ")");
  return mesh;
}

}  // namespace descent
