// The car generator: a lattice of nearly cubic cells over the car's bounding
// box, keeping each cell whose centre lies in one of its parts (a chassis
// slab over the whole footprint, a cabin on it, four wheels: disks in the
// x-y plane, each as thick as a seventh of the width, flush with a side),
// each kept cell split into the six Kuhn tets, which conform across any set
// of cells. The parts are convex and overlap in face-adjacent cells, so the
// body is one piece without cells that meet only at an edge.
//
// Layout: lattice node (i, j, k) of (nx + 1) x (ny + 1) x (nz + 1); the used
// nodes are numbered in lattice order (x fastest), the tets in cell order.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "common/error.hpp"
#include "meshes/generators.hpp"
#include "meshes/hex_split.hpp"

namespace descent {
namespace {

// The parts as fractions of the car's length (x), height (y) and width (z).
constexpr double kWheelRadius = 0.22;            // of the height
constexpr double kWheelCentres[2] = {0.2, 0.8};  // along the length
constexpr double kWheelThickness = 1.0 / 7.0;    // of the width
constexpr double kChassis[2] = {0.2, 0.6};       // bottom and top, of the height
constexpr double kCabinX[2] = {0.25, 0.78};      // of the length
constexpr double kCabinZ[2] = {0.08, 0.92};      // of the width

void validate(const CarParams& params) {
  if (params.cells < 8 || params.cells > 4000)
    throw InputError(detail::concat("car.cells must be in [8, 4000] (cells along the length), got ",
                                    params.cells));
  const double sizes[3] = {params.length, params.height, params.width};
  const char* names[3] = {"length", "height", "width"};
  for (int axis = 0; axis < 3; ++axis)
    if (!std::isfinite(sizes[axis]) || !(sizes[axis] > 0))
      throw InputError(
          detail::concat("car.", names[axis], " must be a finite number > 0, got ", sizes[axis]));
  for (double c : params.origin)
    if (!std::isfinite(c)) throw InputError("car.origin must be finite");
}

struct Lattice {
  std::int64_t n[3];  // cells along x, y, z
  double edge[3];     // cell edge along x, y, z
};

// Cells of about length / cells along every axis, a whole number of them
// (at least 4) along the height and the width, so the sizes come out exact.
Lattice lattice_of(const CarParams& params) {
  const double edge = params.length / params.cells;
  Lattice lattice{};
  const double sizes[3] = {params.length, params.height, params.width};
  for (int axis = 0; axis < 3; ++axis) {
    lattice.n[axis] = std::max<std::int64_t>(4, std::llround(sizes[axis] / edge));
    lattice.edge[axis] = sizes[axis] / static_cast<double>(lattice.n[axis]);
  }
  if (double(lattice.n[0]) * lattice.n[1] * lattice.n[2] * 6 > 2e9)
    throw InputError(
        detail::concat("car.cells ", params.cells, " gives more tets than a 32-bit index holds"));
  return lattice;
}

// Whether the point (x, y, z), relative to the car's origin, lies in a part.
bool inside(const CarParams& params, double x, double y, double z) {
  const double L = params.length, H = params.height, W = params.width;
  const double xs = x / L, ys = y / H, zs = z / W;
  if (ys >= kChassis[0] && ys <= kChassis[1]) return true;
  if (ys > kChassis[1] && xs >= kCabinX[0] && xs <= kCabinX[1] && zs >= kCabinZ[0] &&
      zs <= kCabinZ[1])
    return true;
  const bool at_a_side = zs <= kWheelThickness || zs >= 1 - kWheelThickness;
  if (!at_a_side) return false;
  const double r = kWheelRadius * H;
  for (double centre : kWheelCentres) {
    const double dx = x - centre * L, dy = y - r;
    if (dx * dx + dy * dy <= r * r) return true;
  }
  return false;
}

}  // namespace

Mesh make_car(const CarParams& params) {
  validate(params);
  const Lattice lattice = lattice_of(params);
  const std::int64_t nx = lattice.n[0], ny = lattice.n[1], nz = lattice.n[2];
  auto cell_index = [&](std::int64_t i, std::int64_t j, std::int64_t k) {
    return (k * ny + j) * nx + i;
  };
  auto node_index = [&](std::int64_t i, std::int64_t j, std::int64_t k) {
    return (k * (ny + 1) + j) * (nx + 1) + i;
  };

  std::vector<std::uint8_t> kept(static_cast<std::size_t>(nx * ny * nz), 0);
  std::vector<index_t> node_id(static_cast<std::size_t>((nx + 1) * (ny + 1) * (nz + 1)), -1);
  for (std::int64_t k = 0; k < nz; ++k)
    for (std::int64_t j = 0; j < ny; ++j)
      for (std::int64_t i = 0; i < nx; ++i) {
        if (!inside(params, (i + 0.5) * lattice.edge[0], (j + 0.5) * lattice.edge[1],
                    (k + 0.5) * lattice.edge[2]))
          continue;
        kept[cell_index(i, j, k)] = 1;
        for (int corner = 0; corner < 8; ++corner)
          node_id[node_index(i + (corner & 1), j + ((corner >> 1) & 1), k + ((corner >> 2) & 1))] =
              0;
      }

  Mesh mesh;
  index_t next = 0;
  for (std::int64_t k = 0; k <= nz; ++k)
    for (std::int64_t j = 0; j <= ny; ++j)
      for (std::int64_t i = 0; i <= nx; ++i) {
        index_t& id = node_id[node_index(i, j, k)];
        if (id < 0) continue;
        id = next++;
        mesh.positions.insert(mesh.positions.end(),
                              {params.origin[0] + params.length * (double(i) / nx),
                               params.origin[1] + params.height * (double(j) / ny),
                               params.origin[2] + params.width * (double(k) / nz)});
      }
  for (std::int64_t k = 0; k < nz; ++k)
    for (std::int64_t j = 0; j < ny; ++j)
      for (std::int64_t i = 0; i < nx; ++i) {
        if (!kept[cell_index(i, j, k)]) continue;
        index_t corner_node[8];
        for (int corner = 0; corner < 8; ++corner)
          corner_node[corner] = node_id[node_index(i + (corner & 1), j + ((corner >> 1) & 1),
                                                   k + ((corner >> 2) & 1))];
        for (const hex_split::TetCorners& tet : hex_split::kKuhnTets)
          for (int corner : tet) mesh.tets.push_back(corner_node[corner]);
      }
  mesh.source = detail::concat("car ", nx, "x", ny, "x", nz, " cells, length ", params.length);
  return mesh;
}

}  // namespace descent
