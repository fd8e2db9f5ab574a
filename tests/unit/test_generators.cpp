// The box, double helix, ball and car generators: counts, orientation, volume,
// conformity, connectivity, bounds, determinism and parameter checks.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <iostream>
#include <limits>
#include <numbers>
#include <numeric>
#include <set>
#include <string>
#include <vector>

#include "common/error.hpp"
#include "meshes/generators.hpp"

namespace descent {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kInf = std::numeric_limits<double>::infinity();

std::array<double, 3> vertex(const Mesh& mesh, index_t v) {
  return {mesh.positions[3 * v], mesh.positions[3 * v + 1], mesh.positions[3 * v + 2]};
}

// det[x1 - x0, x2 - x0, x3 - x0] / 6.
double signed_volume(const Mesh& mesh, index_t tet) {
  const index_t* v = &mesh.tets[4 * tet];
  const auto x0 = vertex(mesh, v[0]);
  double e[3][3];
  for (int row = 0; row < 3; ++row) {
    const auto x = vertex(mesh, v[row + 1]);
    for (int axis = 0; axis < 3; ++axis) e[row][axis] = x[axis] - x0[axis];
  }
  const double det = e[0][0] * (e[1][1] * e[2][2] - e[1][2] * e[2][1]) -
                     e[0][1] * (e[1][0] * e[2][2] - e[1][2] * e[2][0]) +
                     e[0][2] * (e[1][0] * e[2][1] - e[1][1] * e[2][0]);
  return det / 6;
}

double total_volume(const Mesh& mesh) {
  double volume = 0;
  for (index_t t = 0; t < mesh.num_tets(); ++t) volume += signed_volume(mesh, t);
  return volume;
}

void expect_positive_volumes(const Mesh& mesh) {
  index_t num_bad = 0;
  for (index_t t = 0; t < mesh.num_tets(); ++t)
    if (!(signed_volume(mesh, t) > 0)) ++num_bad;
  EXPECT_EQ(num_bad, 0) << "tets with volume <= 0 in " << mesh.source;
}

// One triangular face of one tet, its vertices sorted.
struct FaceUse {
  std::array<index_t, 3> vertices;
  index_t tet;
};

// Faces grouped by their vertex set: uses with equal vertices are adjacent.
std::vector<FaceUse> sorted_face_uses(const Mesh& mesh) {
  std::vector<FaceUse> uses;
  uses.reserve(4 * std::size_t(mesh.num_tets()));
  for (index_t t = 0; t < mesh.num_tets(); ++t)
    for (int skipped = 0; skipped < 4; ++skipped) {
      FaceUse use{{}, t};
      int n = 0;
      for (int c = 0; c < 4; ++c)
        if (c != skipped) use.vertices[n++] = mesh.tets[4 * t + c];
      std::sort(use.vertices.begin(), use.vertices.end());
      uses.push_back(use);
    }
  std::sort(uses.begin(), uses.end(), [](const FaceUse& a, const FaceUse& b) {
    return a.vertices != b.vertices ? a.vertices < b.vertices : a.tet < b.tet;
  });
  return uses;
}

// Calls visit(first, count) for each distinct face: its uses are uses[first, first + count).
template <class Visit>
void for_each_face(const std::vector<FaceUse>& uses, Visit visit) {
  for (std::size_t first = 0; first < uses.size();) {
    std::size_t end = first + 1;
    while (end < uses.size() && uses[end].vertices == uses[first].vertices) ++end;
    visit(first, end - first);
    first = end;
  }
}

// Number of groups of tets connected through shared faces.
int count_face_components(const Mesh& mesh, const std::vector<FaceUse>& uses) {
  std::vector<index_t> parent(mesh.num_tets());
  std::iota(parent.begin(), parent.end(), 0);
  auto root = [&](index_t t) {
    while (parent[t] != t) t = parent[t] = parent[parent[t]];
    return t;
  };
  for_each_face(uses, [&](std::size_t first, std::size_t count) {
    for (std::size_t u = first + 1; u < first + count; ++u)
      parent[root(uses[u].tet)] = root(uses[first].tet);
  });
  int num_components = 0;
  for (index_t t = 0; t < mesh.num_tets(); ++t)
    if (root(t) == t) ++num_components;
  return num_components;
}

void expect_all_vertices_used(const Mesh& mesh) {
  std::vector<bool> used(mesh.num_vertices(), false);
  for (index_t v : mesh.tets) used[v] = true;
  EXPECT_EQ(std::count(used.begin(), used.end(), false), 0) << "unreferenced vertices";
}

// ---------------------------------------------------------------- box

BoxParams box_params(int tets_per_cell) {
  BoxParams params;
  params.cells = {3, 4, 5};
  params.size = {1.5, 0.7, 2.25};
  params.origin = {-0.5, 2.0, 0.125};
  params.tets_per_cell = tets_per_cell;
  return params;
}

class BoxTest : public ::testing::TestWithParam<int> {};

TEST_P(BoxTest, CountsVolumesAndBounds) {
  const BoxParams params = box_params(GetParam());
  const Mesh mesh = make_box(params);
  const auto [nx, ny, nz] = params.cells;
  EXPECT_EQ(mesh.num_vertices(), (nx + 1) * (ny + 1) * (nz + 1));
  EXPECT_EQ(mesh.num_tets(), nx * ny * nz * params.tets_per_cell);
  expect_positive_volumes(mesh);
  expect_all_vertices_used(mesh);
  const double box_volume = params.size[0] * params.size[1] * params.size[2];
  EXPECT_NEAR(total_volume(mesh), box_volume, 1e-12 * box_volume);
  for (index_t v = 0; v < mesh.num_vertices(); ++v)
    for (int axis = 0; axis < 3; ++axis) {
      EXPECT_GE(vertex(mesh, v)[axis], params.origin[axis]);
      EXPECT_LE(vertex(mesh, v)[axis], params.origin[axis] + params.size[axis]);
    }
}

TEST_P(BoxTest, FacesConformAndBoundaryLiesOnTheSurface) {
  const BoxParams params = box_params(GetParam());
  const Mesh mesh = make_box(params);
  // A boundary face has all three vertices on one of the six box planes.
  auto on_box_surface = [&](const std::array<index_t, 3>& face) {
    for (int axis = 0; axis < 3; ++axis)
      for (double plane : {params.origin[axis], params.origin[axis] + params.size[axis]}) {
        bool all_on_plane = true;
        for (index_t v : face) all_on_plane &= vertex(mesh, v)[axis] == plane;
        if (all_on_plane) return true;
      }
    return false;
  };
  const std::vector<FaceUse> uses = sorted_face_uses(mesh);
  int num_boundary = 0, num_interior = 0, num_bad = 0;
  for_each_face(uses, [&](std::size_t first, std::size_t count) {
    if (count == 2) {
      ++num_interior;
      if (on_box_surface(uses[first].vertices)) ++num_bad;
    } else if (count == 1) {
      ++num_boundary;
      if (!on_box_surface(uses[first].vertices)) ++num_bad;
    } else {
      ++num_bad;
    }
  });
  EXPECT_EQ(num_bad, 0);
  // Two triangles per boundary quad.
  const auto [nx, ny, nz] = params.cells;
  EXPECT_EQ(num_boundary, 2 * 2 * (nx * ny + ny * nz + nz * nx));
  EXPECT_EQ(num_boundary + 2 * num_interior, 4 * mesh.num_tets());
  EXPECT_EQ(count_face_components(mesh, uses), 1);
}

TEST_P(BoxTest, OneCellIsValid) {
  BoxParams params;
  params.cells = {1, 1, 1};
  params.tets_per_cell = GetParam();
  const Mesh mesh = make_box(params);
  EXPECT_EQ(mesh.num_vertices(), 8);
  EXPECT_EQ(mesh.num_tets(), GetParam());
  expect_positive_volumes(mesh);
  EXPECT_NEAR(total_volume(mesh), 1.0, 1e-12);
}

std::string tets_per_cell_name(const ::testing::TestParamInfo<int>& param_info) {
  return std::to_string(param_info.param) + "Tets";
}
INSTANTIATE_TEST_SUITE_P(TetsPerCell, BoxTest, ::testing::Values(5, 6), tets_per_cell_name);

// Expects make_box to throw InputError whose message contains `key`.
void expect_box_rejected(const BoxParams& params, const std::string& key) {
  try {
    make_box(params);
    ADD_FAILURE() << "no InputError for " << key;
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find(key), std::string::npos) << error.what();
  }
}

TEST(BoxParams, BadValuesThrowInputErrorNamingTheParameter) {
  BoxParams params;
  params.cells[1] = 0;
  expect_box_rejected(params, "mesh.box.cells[1]");
  params = {};
  params.size[2] = -1;
  expect_box_rejected(params, "mesh.box.size[2]");
  params = {};
  params.size[0] = std::nan("");
  expect_box_rejected(params, "mesh.box.size[0]");
  params = {};
  params.origin[0] = kInf;
  expect_box_rejected(params, "mesh.box.origin[0]");
  params = {};
  params.tets_per_cell = 4;
  expect_box_rejected(params, "mesh.box.tets_per_cell");
  params = {};
  params.cells = {5000, 5000, 5000};
  expect_box_rejected(params, "mesh.box.cells");
}

// ---------------------------------------------------------------- double helix

const std::vector<std::pair<std::string, int>> kPaperSizes = {
    {"41k", 41000}, {"82k", 82000}, {"158k", 158000}, {"316k", 316000}};

DoubleHelixParams preset(const std::string& name) {
  DoubleHelixParams params;
  params.resolution = double_helix_preset_resolution(name);
  return params;
}

// Distance from p to the centreline of `strand` as the header defines it:
// (R cos(t + strand pi), 2 r + pitch t / 2pi, -R sin(t + strand pi)), by dense
// sampling of t over the body's height and a golden-section refinement.
double brute_force_distance_to_strand(const DoubleHelixParams& params, int strand,
                                      const std::array<double, 3>& p) {
  const double b = params.pitch / (2 * kPi), cap = 2 * params.tube_radius;
  auto distance = [&](double t) {
    const double dx = params.helix_radius * std::cos(t + strand * kPi) - p[0];
    const double dy = cap + b * t - p[1];
    const double dz = -params.helix_radius * std::sin(t + strand * kPi) - p[2];
    return std::sqrt(dx * dx + dy * dy + dz * dz);
  };
  const double t_low = (-params.tube_radius - cap) / b;
  const double t_high = (double_helix_height(params) + params.tube_radius - cap) / b;
  const int num_samples = 1000;
  const double step = (t_high - t_low) / num_samples;
  double best_t = t_low, best_distance = distance(t_low);
  for (int s = 1; s <= num_samples; ++s) {
    const double t = t_low + s * step;
    if (distance(t) < best_distance) {
      best_t = t;
      best_distance = distance(t);
    }
  }
  double lo = best_t - step, hi = best_t + step;
  const double golden = (std::sqrt(5.0) - 1) / 2;
  for (int iteration = 0; iteration < 100; ++iteration) {
    const double a = hi - golden * (hi - lo), c = lo + golden * (hi - lo);
    if (distance(a) < distance(c))
      hi = c;
    else
      lo = a;
  }
  return distance((lo + hi) / 2);
}

TEST(DoubleHelix, PresetsMatchThePapersSizes) {
  for (const auto& [name, paper_count] : kPaperSizes) {
    const Mesh mesh = make_double_helix(preset(name));
    std::cout << "preset " << name << ": " << mesh.num_tets() << " tets, " << mesh.num_vertices()
              << " vertices\n";
    EXPECT_NEAR(mesh.num_tets(), paper_count, 0.15 * paper_count) << name;
  }
}

TEST(DoubleHelix, PresetMeshesAreValidConnectedAndBounded) {
  for (const auto& [name, paper_count] : kPaperSizes) {
    SCOPED_TRACE(name);
    const DoubleHelixParams params = preset(name);
    const Mesh mesh = make_double_helix(params);
    expect_positive_volumes(mesh);
    expect_all_vertices_used(mesh);

    const std::vector<FaceUse> uses = sorted_face_uses(mesh);
    int num_overused = 0;
    for_each_face(uses, [&](std::size_t, std::size_t count) { num_overused += count > 2; });
    EXPECT_EQ(num_overused, 0) << "faces shared by more than two tets";
    EXPECT_EQ(count_face_components(mesh, uses), 1);

    const double cell = params.tube_radius / params.resolution;
    const double max_radius = params.helix_radius + params.tube_radius + cell;
    double y_min = kInf, y_max = -kInf, radius_max = 0;
    for (index_t v = 0; v < mesh.num_vertices(); ++v) {
      const auto x = vertex(mesh, v);
      y_min = std::min(y_min, x[1]);
      y_max = std::max(y_max, x[1]);
      radius_max = std::max(radius_max, std::hypot(x[0], x[2]));
    }
    EXPECT_EQ(y_min, 0.0);
    EXPECT_EQ(y_max, double_helix_height(params));
    EXPECT_LE(radius_max, max_radius);
  }
}

// The mesh holds exactly the grid cells whose centre lies in the body, checked
// against the definition with a brute-force distance to the strands.
TEST(DoubleHelix, CellsAreThoseWhoseCentreIsInsideTheBody) {
  const DoubleHelixParams params = preset("41k");
  const Mesh mesh = make_double_helix(params);
  const double outer = params.helix_radius + params.tube_radius;
  const double height = double_helix_height(params);

  // Cell edges: the smallest spacing of distinct vertex coordinates per axis.
  std::array<int, 3> num_cells{};
  for (int axis = 0; axis < 3; ++axis) {
    std::set<double> coordinates;
    for (index_t v = 0; v < mesh.num_vertices(); ++v) coordinates.insert(vertex(mesh, v)[axis]);
    double edge = kInf;
    for (auto it = std::next(coordinates.begin()); it != coordinates.end(); ++it)
      edge = std::min(edge, *it - *std::prev(it));
    num_cells[axis] = int(std::lround((axis == 1 ? height : 2 * outer) / edge));
  }
  const std::array<double, 3> low{-outer, 0.0, -outer};
  const std::array<double, 3> extent{2 * outer, height, 2 * outer};
  auto cell_of = [&](const std::array<int, 3>& ijk) {
    return (ijk[1] * num_cells[2] + ijk[2]) * num_cells[0] + ijk[0];
  };

  std::vector<bool> in_mesh(num_cells[0] * num_cells[1] * num_cells[2], false);
  for (index_t t = 0; t < mesh.num_tets(); ++t) {
    std::array<int, 3> ijk;
    for (int axis = 0; axis < 3; ++axis) {
      double centroid = 0;
      for (int c = 0; c < 4; ++c) centroid += vertex(mesh, mesh.tets[4 * t + c])[axis] / 4;
      ijk[axis] = int(std::floor((centroid - low[axis]) / extent[axis] * num_cells[axis]));
    }
    in_mesh[cell_of(ijk)] = true;
  }

  const double r = params.tube_radius, cap = 2 * r;
  const double tie = 1e-9;
  int num_mismatches = 0, num_inside = 0;
  for (int j = 0; j < num_cells[1]; ++j)
    for (int k = 0; k < num_cells[2]; ++k)
      for (int i = 0; i < num_cells[0]; ++i) {
        std::array<double, 3> centre;
        const std::array<int, 3> ijk{i, j, k};
        for (int axis = 0; axis < 3; ++axis)
          centre[axis] = low[axis] + extent[axis] * (ijk[axis] + 0.5) / num_cells[axis];
        const double rho = std::hypot(centre[0], centre[2]);
        const double y = centre[1];
        const double tube_distance = std::min(brute_force_distance_to_strand(params, 0, centre),
                                              brute_force_distance_to_strand(params, 1, centre));
        if (std::abs(tube_distance - r) < tie || std::abs(rho - outer) < tie ||
            std::abs(y - cap) < tie || std::abs(y - (height - cap)) < tie)
          continue;  // on the surface: either answer is right
        const bool in_cap = (y < cap || y > height - cap) && rho < outer;
        const bool inside = in_cap || tube_distance < r;
        num_inside += inside;
        num_mismatches += inside != in_mesh[cell_of(ijk)];
      }
  EXPECT_EQ(num_mismatches, 0);
  EXPECT_EQ(6 * num_inside, mesh.num_tets());
}

TEST(DoubleHelix, VolumeIsCloseToTheAnalyticVolume) {
  const DoubleHelixParams params = preset("82k");
  const double R = params.helix_radius, r = params.tube_radius;
  // By the screw symmetry every horizontal slice of a tube has the same area,
  // so a tube between the caps holds exactly pi r^2 times its centreline length.
  const double centreline_length = params.turns * std::hypot(2 * kPi * R, params.pitch);
  const double tubes = 2 * kPi * r * r * centreline_length;
  const double caps = 2 * kPi * (R + r) * (R + r) * (2 * r);
  const double analytic = tubes + caps;
  const double volume = total_volume(make_double_helix(params));
  std::cout << "82k volume " << volume << ", analytic " << analytic << ", relative error "
            << (volume - analytic) / analytic << "\n";
  EXPECT_NEAR(volume, analytic, 0.03 * analytic);
}

TEST(DoubleHelix, SameParametersGiveTheSameMesh) {
  DoubleHelixParams params = preset("82k");
  params.turns = 1.5;
  params.pitch = 0.4;
  const Mesh first = make_double_helix(params);
  const Mesh second = make_double_helix(params);
  EXPECT_EQ(first.positions, second.positions);
  EXPECT_EQ(first.tets, second.tets);
  EXPECT_EQ(first.source, second.source);
}

TEST(DoubleHelix, OtherGeometriesAreValid) {
  DoubleHelixParams params;
  params.resolution = 3;
  params.helix_radius = 0.1;
  params.tube_radius = 0.05;
  params.pitch = 0.3;
  params.turns = 3.25;
  const Mesh mesh = make_double_helix(params);
  expect_positive_volumes(mesh);
  expect_all_vertices_used(mesh);
  EXPECT_EQ(count_face_components(mesh, sorted_face_uses(mesh)), 1);
}

// Expects make_double_helix to throw InputError whose message contains `key`.
void expect_helix_rejected(const DoubleHelixParams& params, const std::string& key) {
  try {
    make_double_helix(params);
    ADD_FAILURE() << "no InputError for " << key;
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find(key), std::string::npos) << error.what();
  }
}

TEST(DoubleHelixParams, BadValuesThrowInputErrorNamingTheParameter) {
  const std::vector<std::pair<double DoubleHelixParams::*, std::string>> fields = {
      {&DoubleHelixParams::resolution, "mesh.helix.resolution"},
      {&DoubleHelixParams::helix_radius, "mesh.helix.helix_radius"},
      {&DoubleHelixParams::tube_radius, "mesh.helix.tube_radius"},
      {&DoubleHelixParams::pitch, "mesh.helix.pitch"},
      {&DoubleHelixParams::turns, "mesh.helix.turns"}};
  for (const auto& [field, key] : fields)
    for (double bad : {0.0, -1.0, std::nan(""), kInf}) {
      DoubleHelixParams params;
      params.*field = bad;
      expect_helix_rejected(params, key);
    }
}

TEST(DoubleHelixParams, OverlappingTubesAreRejected) {
  DoubleHelixParams params;
  params.tube_radius = params.helix_radius;
  expect_helix_rejected(params, "mesh.helix.tube_radius");
  params = {};
  params.pitch = 0.2;  // neighbouring turns 0.1 apart, tubes 0.16 thick
  expect_helix_rejected(params, "mesh.helix.pitch");
}

TEST(DoubleHelixParams, TooLowOrTooHighResolutionIsRejected) {
  DoubleHelixParams params;
  params.resolution = 0.05;
  expect_helix_rejected(params, "mesh.helix.resolution");
  params.resolution = 1e4;
  expect_helix_rejected(params, "mesh.helix.resolution");
}

TEST(DoubleHelixParams, UnknownPresetListsTheValidNames) {
  try {
    double_helix_preset_resolution("100k");
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("100k"), std::string::npos) << message;
    for (const auto& [name, count] : kPaperSizes)
      EXPECT_NE(message.find(name), std::string::npos) << message;
  }
}

// ---------------------------------------------------------------- ball

TEST(Ball, EveryTetPositiveVolumeNearTheSpheresAndSurfaceOnIt) {
  for (int cells : {1, 2, 3, 4, 8, 16}) {
    BallParams params;
    params.cells = cells;
    params.radius = 0.3;
    params.centre = {1, -2, 0.5};
    const Mesh mesh = make_ball(params);
    SCOPED_TRACE(mesh.source);
    EXPECT_EQ(mesh.num_tets(), 6 * cells * cells * cells);
    expect_positive_volumes(mesh);
    // Every vertex within the sphere, the cube's faces on it.
    index_t on_sphere = 0;
    for (index_t v = 0; v < mesh.num_vertices(); ++v) {
      const auto x = vertex(mesh, v);
      const double r = std::hypot(x[0] - 1, x[1] + 2, x[2] - 0.5);
      EXPECT_LE(r, 0.3 * (1 + 1e-12));
      on_sphere += std::abs(r - 0.3) < 1e-12;
    }
    const index_t n = cells + 1;
    EXPECT_EQ(on_sphere, n * n * n - (n - 2) * (n - 2) * (n - 2));
    // The polyhedron inside the sphere: its volume approaches the ball's
    // as the cells shrink (within 5% from 8 cells on).
    const double ball = 4.0 / 3.0 * kPi * 0.3 * 0.3 * 0.3;
    EXPECT_LT(total_volume(mesh), ball);
    if (cells >= 8) {
      EXPECT_NEAR(total_volume(mesh), ball, 0.05 * ball);
    }
  }
}

TEST(Ball, BadValuesThrowInputErrorNamingTheParameter) {
  BallParams params;
  params.cells = 0;
  EXPECT_THROW(make_ball(params), InputError);
  params.cells = 4;
  params.radius = -1;
  EXPECT_THROW(make_ball(params), InputError);
}

// ---------------------------------------------------------------- car

CarParams car_params(int cells) {
  CarParams params;
  params.cells = cells;
  params.length = 4.2;
  params.width = 1.8;
  params.height = 1.45;
  params.origin = {-1.0, 0.5, 2.0};
  return params;
}

// Number of boundary edges (of faces used by one tet) not shared by exactly
// two boundary faces: a voxel body whose cells met only at an edge would
// have such edges, and its surface would not be a closed manifold.
index_t count_non_manifold_boundary_edges(const std::vector<FaceUse>& uses) {
  std::vector<std::array<index_t, 2>> edges;
  for_each_face(uses, [&](std::size_t first, std::size_t count) {
    if (count != 1) return;
    const auto& v = uses[first].vertices;
    edges.push_back({v[0], v[1]});
    edges.push_back({v[0], v[2]});
    edges.push_back({v[1], v[2]});
  });
  std::sort(edges.begin(), edges.end());
  index_t bad = 0;
  for (std::size_t first = 0; first < edges.size();) {
    std::size_t end = first + 1;
    while (end < edges.size() && edges[end] == edges[first]) ++end;
    bad += end - first != 2;
    first = end;
  }
  return bad;
}

TEST(Car, OnePieceWithAClosedSurfaceFillingItsBoundingBox) {
  for (int cells : {8, 12, 24, 40}) {
    const CarParams params = car_params(cells);
    const Mesh mesh = make_car(params);
    SCOPED_TRACE(mesh.source);
    expect_positive_volumes(mesh);
    expect_all_vertices_used(mesh);
    const std::vector<FaceUse> uses = sorted_face_uses(mesh);
    for_each_face(uses, [&](std::size_t, std::size_t count) { EXPECT_LE(count, 2u); });
    EXPECT_EQ(count_face_components(mesh, uses), 1);
    EXPECT_EQ(count_non_manifold_boundary_edges(uses), 0);
    // Its bounding box is the car's, exactly.
    const double size[3] = {params.length, params.height, params.width};
    for (int axis = 0; axis < 3; ++axis) {
      double lo = kInf, hi = -kInf;
      for (index_t v = 0; v < mesh.num_vertices(); ++v) {
        lo = std::min(lo, vertex(mesh, v)[axis]);
        hi = std::max(hi, vertex(mesh, v)[axis]);
      }
      EXPECT_EQ(lo, params.origin[axis]);
      EXPECT_EQ(hi, params.origin[axis] + size[axis]);
    }
    // It stands on its wheels: the lowest vertices lie in the wheels' lengths
    // (within a cell of their span) and at the sides, none under the middle.
    const double edge = params.length / cells;
    for (index_t v = 0; v < mesh.num_vertices(); ++v) {
      const auto x = vertex(mesh, v);
      if (x[1] != params.origin[1]) continue;
      const double along = (x[0] - params.origin[0]) / params.length;
      const double across = (x[2] - params.origin[2]) / params.width;
      EXPECT_TRUE(std::abs(along - 0.2) < 0.12 + edge / params.length ||
                  std::abs(along - 0.8) < 0.12 + edge / params.length)
          << along;
      EXPECT_TRUE(across < 0.2 + edge / params.width || across > 0.8 - edge / params.width)
          << across;
    }
    // Volume: at least the chassis and the cabin's, at most those plus four
    // whole wheels, each within the cells' resolution.
    const double L = params.length, W = params.width, H = params.height;
    const double slabs = L * W * 0.4 * H + 0.53 * L * 0.84 * W * 0.4 * H;
    const double wheels = 4 * kPi * (0.22 * H) * (0.22 * H) * W / 7;
    const double cell_layer = 2 * edge * (L * W + L * H + W * H);
    EXPECT_GT(total_volume(mesh), slabs - cell_layer);
    EXPECT_LT(total_volume(mesh), slabs + wheels + cell_layer);
  }
}

TEST(Car, SameParametersGiveTheSameMesh) {
  const Mesh a = make_car(car_params(16)), b = make_car(car_params(16));
  EXPECT_EQ(a.positions, b.positions);
  EXPECT_EQ(a.tets, b.tets);
}

TEST(Car, BadValuesThrowInputErrorNamingTheParameter) {
  auto expect_rejected = [](const CarParams& params, const std::string& key) {
    try {
      make_car(params);
      ADD_FAILURE() << "no InputError for " << key;
    } catch (const InputError& error) {
      EXPECT_NE(std::string(error.what()).find(key), std::string::npos) << error.what();
    }
  };
  CarParams params = car_params(7);
  expect_rejected(params, "car.cells");
  params = car_params(16);
  params.width = 0;
  expect_rejected(params, "car.width");
  params = car_params(16);
  params.height = std::nan("");
  expect_rejected(params, "car.height");
  params = car_params(16);
  params.origin[1] = kInf;
  expect_rejected(params, "car.origin");
}

}  // namespace
}  // namespace descent
