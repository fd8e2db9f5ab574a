#pragma once
// Procedural meshes: the paper's double helix, a box, a ball and a car. Each
// is an exact function of its parameters (same parameters, same mesh, bit for
// bit). Each comes whole (make_*) and, but the car, as one rank's MeshSlice
// (make_*_slice), which no rank builds the whole mesh for.
#include <mpi.h>

#include <array>
#include <string>

#include "common/mesh.hpp"
#include "common/mesh_slice.hpp"

namespace descent {

// Two intertwined helical tubes (the second rotated by half a turn about the
// axis) joined by end caps. The axis is +y (gravity pulls along -y in the
// default scenes); the body spans y in [0, height] (double_helix_height): a
// bottom cap, `turns` turns of both tubes, a top cap. Each cap is a solid disk
// of radius helix_radius + tube_radius and thickness 2 * tube_radius.
// `resolution` is the one knob: the body is voxelized on cells of edge about
// tube_radius / resolution, so the tet count grows with its cube, and the named
// presets below reproduce the paper's four sizes with the default geometry.
// Throws InputError for non-positive or non-finite parameters, tubes that
// would overlap, and a resolution too low to leave any cell in the body.
struct DoubleHelixParams {
  double resolution = 1.0;
  double helix_radius = 0.25;  // axis to tube centre, metres
  double tube_radius = 0.08;
  double pitch = 0.5;  // rise per turn
  double turns = 2.0;
};

// Resolution of the paper's sizes: "41k", "82k", "158k", "316k" (tet counts
// within 5% of 41,000 / 82,000 / 158,000 / 316,000 with the default geometry).
// Throws InputError naming the preset and the valid names otherwise.
double double_helix_preset_resolution(const std::string& name);

Mesh make_double_helix(const DoubleHelixParams& params);

// Rank r of P's block of the same mesh: exactly
// slice_of(make_double_helix(params), r, P), while each rank voxelizes and
// stores about 1/P of the grid and a few layers of cells. Collective over
// comm. Throws the serial generator's InputError on every rank, except that
// global ids are 64-bit (no 32-bit limit on the whole mesh, only on one
// rank's block).
MeshSlice make_double_helix_slice(MPI_Comm comm, const DoubleHelixParams& params);

// turns * pitch + 4 * tube_radius: the helical part plus both caps.
double double_helix_height(const DoubleHelixParams& params);

// An axis-aligned box of cells[0] x cells[1] x cells[2] hexahedral cells over
// [origin, origin + size], each split into 5 or 6 positively oriented tets.
struct BoxParams {
  std::array<int, 3> cells{4, 4, 4};
  std::array<double, 3> size{1.0, 1.0, 1.0};
  std::array<double, 3> origin{0.0, 0.0, 0.0};
  int tets_per_cell = 6;
};

Mesh make_box(const BoxParams& params);

// Rank r of P's block of the same mesh, exactly slice_of(make_box(params), r,
// P), from closed forms. Collective over comm; throws as make_box on every
// rank, with the 32-bit limit on one rank's block instead of the whole box.
MeshSlice make_box_slice(MPI_Comm comm, const BoxParams& params);

// A ball of `radius` about `centre`: a box of cells^3 cells (six tets each)
// over a cube, every point moved along its ray from the centre onto the
// sphere of its cube shell (meshes/ball.cpp), so the surface is the sphere's
// to the cells' resolution and no cell is cut.
struct BallParams {
  int cells = 8;  // along each axis of the cube
  double radius = 0.5;
  std::array<double, 3> centre{0.0, 0.0, 0.0};
};

Mesh make_ball(const BallParams& params);

// Rank r of P's block of the same mesh (the box's slice, moved alike).
MeshSlice make_ball_slice(MPI_Comm comm, const BallParams& params);

// A car (paper 2's car scenes; meshes/car.cpp): a chassis slab, a cabin on it
// and four wheels, voxelized on cells of about length / cells (six tets each).
// The length runs along +x, the height along +y (the wheels stand on
// y = origin[1]), the width along +z; `origin` is the corner of least x, y, z
// of its bounding box. Small enough to build whole on one rank (a scene
// scatters it).
struct CarParams {
  int cells = 24;                                   // along the length, in [8, 4000]
  double length = 4.2, width = 1.8, height = 1.45;  // metres
  std::array<double, 3> origin{0.0, 0.0, 0.0};
};

Mesh make_car(const CarParams& params);

}  // namespace descent
