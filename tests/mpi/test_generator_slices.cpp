// The slice generators against the serial ones: on every rank count, rank r's
// slice is exactly slice_of(whole mesh, r, P), doubles compared bit for bit;
// bad parameters throw the serial generator's InputError on every rank; and
// the helix's ranks voxelize only their slab and fetch only the cell layers
// their blocks touch.
#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "common/error.hpp"
#include "common/mesh_slice.hpp"
#include "meshes/double_helix_slice.hpp"
#include "meshes/generators.hpp"
#include "world_rank.hpp"

namespace descent {
namespace {

using testing::world_rank;
using testing::world_size;

void expect_same_slice(const MeshSlice& actual, const MeshSlice& expected) {
  EXPECT_EQ(actual.source, expected.source);
  EXPECT_EQ(actual.num_global_tets, expected.num_global_tets);
  EXPECT_EQ(actual.num_global_vertices, expected.num_global_vertices);
  EXPECT_EQ(actual.first_tet, expected.first_tet);
  EXPECT_EQ(actual.first_vertex, expected.first_vertex);
  EXPECT_EQ(actual.tets, expected.tets);
  ASSERT_EQ(actual.positions.size(), expected.positions.size());
  if (expected.positions.empty()) return;
  EXPECT_EQ(std::memcmp(actual.positions.data(), expected.positions.data(),
                        expected.positions.size() * sizeof(double)),
            0)
      << "positions differ in their bits";
}

// ---------------------------------------------------------------- double helix

DoubleHelixParams helix_params(double resolution, double tube_radius = 0.08, double turns = 2) {
  DoubleHelixParams params;
  params.resolution = resolution;
  params.tube_radius = tube_radius;
  params.turns = turns;
  return params;
}

// This rank's slice and work, after checking the slice against the serial mesh.
helix::SliceAndWork expect_helix_slice_matches_serial(const DoubleHelixParams& params) {
  const MeshSlice expected = slice_of(make_double_helix(params), world_rank(), world_size());
  helix::SliceAndWork result = helix::make_slice_and_work(MPI_COMM_WORLD, params);
  expect_same_slice(result.slice, expected);
  return result;
}

TEST(HelixSlice, DefaultGeometryMatchesTheSerialMesh) {
  for (double resolution : {1.2, 2.42}) {
    SCOPED_TRACE(resolution);
    const DoubleHelixParams params = helix_params(resolution);
    const MeshSlice expected = slice_of(make_double_helix(params), world_rank(), world_size());
    expect_same_slice(make_double_helix_slice(MPI_COMM_WORLD, params), expected);
  }
}

// Thin tubes at low resolution voxelize into islands. The component counts
// and sizes were found by a flood fill over the whole grid; components cross
// slabs at 2 ranks and more, so the counts check the matching across slabs.
TEST(HelixSlice, IslandsAreDroppedAsInTheSerialMesh) {
  struct Case {
    DoubleHelixParams params;
    std::int64_t num_components, body_cells, largest;
  };
  const Case cases[] = {
      // Two largest of 143 cells (a cap each with its stubs): the lower wins.
      {helix_params(0.7, 0.03, 2), 12, 506, 143},
      // The largest (221 cells) is not the first found in cell order.
      {helix_params(0.7, 0.03, 1.3), 8, 428, 221},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.params.turns);
    const helix::SliceWork work = expect_helix_slice_matches_serial(c.params).work;
    EXPECT_EQ(work.num_components, c.num_components);
    EXPECT_EQ(work.body_cells_dropped, c.body_cells - c.largest);
    EXPECT_EQ(make_double_helix(c.params).num_tets(), 6 * c.largest);
  }
}

TEST(HelixSlice, FewerCellLayersThanRanks) {
  struct Case {
    DoubleHelixParams params;
    index_t ny;
  };
  const Case cases[] = {
      {helix_params(0.2, 0.08, 0.25), 1},  // two components, the larger of 1 cell
      {helix_params(0.2, 0.08, 1.0), 2},   // four 1-cell islands: 6 tets on up to 4 ranks
      {helix_params(0.36, 0.08, 0.5), 3},  // 120 tets
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.params.turns);
    EXPECT_EQ(expect_helix_slice_matches_serial(c.params).work.ny, c.ny);
  }
}

// Node layer of a vertex: its y in units of the cell height.
index_t node_layer_of(const Mesh& mesh, index_t vertex, const DoubleHelixParams& params,
                      index_t ny) {
  return index_t(std::lround(mesh.positions[3 * vertex + 1] / double_helix_height(params) * ny));
}

// A rank voxelizes its BlockRange of cell layers and fetches the kept cells of
// at most its tets' cell layers and one more each side, plus the two cell
// layers around each node layer of its vertices: its share and a few layers.
TEST(HelixSlice, EachRankVoxelizesItsSlabAndFetchesAFewLayersMore) {
  const DoubleHelixParams params = helix_params(2.42);
  const Mesh mesh = make_double_helix(params);
  const helix::SliceWork work = expect_helix_slice_matches_serial(params).work;
  const std::int64_t slab_layers = (work.ny + world_size() - 1) / world_size();
  EXPECT_LE(work.cells_voxelized, slab_layers * work.nx * work.nz);

  const MeshSlice expected = slice_of(mesh, world_rank(), world_size());
  std::int64_t layers_needed = 0;
  if (expected.num_tets() > 0) {
    index_t lowest = work.ny, highest = 0;
    for (global_index_t vertex : expected.tets) {
      lowest = std::min(lowest, node_layer_of(mesh, index_t(vertex), params, work.ny));
      highest = std::max(highest, node_layer_of(mesh, index_t(vertex), params, work.ny));
    }
    // Cell layers lowest .. highest - 1, and one each side.
    layers_needed += (highest - lowest) + 2;
  }
  if (expected.num_vertices() > 0) {
    const index_t first = node_layer_of(mesh, index_t(expected.first_vertex), params, work.ny);
    const index_t last = node_layer_of(
        mesh, index_t(expected.first_vertex + expected.num_vertices() - 1), params, work.ny);
    // Cell layers first - 1 .. last.
    layers_needed += (last - first) + 2;
  }
  EXPECT_LE(work.cell_layers_fetched, layers_needed);
}

// ---------------------------------------------------------------- box

BoxParams box_params(std::array<int, 3> cells, int tets_per_cell) {
  BoxParams params;
  params.cells = cells;
  params.size = {1.5, 0.7, 2.25};
  params.origin = {-0.5, 2.0, 0.125};
  params.tets_per_cell = tets_per_cell;
  return params;
}

TEST(BoxSlice, MatchesTheSerialBox) {
  for (int tets_per_cell : {5, 6})
    for (std::array<int, 3> cells :
         {std::array{3, 4, 5}, std::array{1, 1, 1}, std::array{7, 1, 2}}) {
      const BoxParams params = box_params(cells, tets_per_cell);
      SCOPED_TRACE(make_box(params).source);
      expect_same_slice(make_box_slice(MPI_COMM_WORLD, params),
                        slice_of(make_box(params), world_rank(), world_size()));
    }
}

TEST(BallSlice, MatchesTheSerialBall) {
  for (int cells : {1, 3, 6}) {
    BallParams params;
    params.cells = cells;
    params.radius = 0.7;
    params.centre = {0.5, -1, 2};
    SCOPED_TRACE(make_ball(params).source);
    expect_same_slice(make_ball_slice(MPI_COMM_WORLD, params),
                      slice_of(make_ball(params), world_rank(), world_size()));
  }
}

// ---------------------------------------------------------------- bad parameters

// The message of the InputError `generate` throws, or "" when it throws none.
template <class Generate>
std::string input_error_of(Generate generate) {
  try {
    generate();
  } catch (const InputError& error) {
    return error.what();
  }
  return "";
}

TEST(SliceGenerators, BadHelixParametersThrowTheSerialInputErrorOnEveryRank) {
  std::vector<DoubleHelixParams> bad(7);
  bad[0].resolution = 0;
  bad[1].helix_radius = std::nan("");
  bad[2].tube_radius = -1;
  bad[3].pitch = 0.2;  // neighbouring turns' tubes overlap
  bad[4].turns = std::numeric_limits<double>::infinity();
  bad[5].tube_radius = bad[5].helix_radius;
  bad[6].resolution = 0.05;  // no cell in the body: found after voxelizing
  for (const DoubleHelixParams& params : bad) {
    const std::string serial = input_error_of([&] { make_double_helix(params); });
    ASSERT_NE(serial, "");
    EXPECT_EQ(input_error_of([&] { make_double_helix_slice(MPI_COMM_WORLD, params); }), serial);
  }
  // The 32-bit limit is on the whole grid in serial, on one layer in slices.
  const std::string too_high =
      input_error_of([&] { make_double_helix_slice(MPI_COMM_WORLD, helix_params(1e4)); });
  EXPECT_NE(too_high.find("mesh.helix.resolution = 10000 is too high"), std::string::npos)
      << too_high;
}

TEST(SliceGenerators, BadBoxParametersThrowTheSerialInputErrorOnEveryRank) {
  std::vector<BoxParams> bad(5);
  bad[0].cells[1] = 0;
  bad[1].size[2] = -1;
  bad[2].size[0] = std::nan("");
  bad[3].origin[0] = std::numeric_limits<double>::infinity();
  bad[4].tets_per_cell = 4;
  for (const BoxParams& params : bad) {
    const std::string serial = input_error_of([&] { make_box(params); });
    ASSERT_NE(serial, "");
    EXPECT_EQ(input_error_of([&] { make_box_slice(MPI_COMM_WORLD, params); }), serial);
  }
  // 7.5e11 tets: beyond a 32-bit count per rank on a few ranks.
  BoxParams huge;
  huge.cells = {5000, 5000, 5000};
  EXPECT_NE(input_error_of([&] {
              make_box_slice(MPI_COMM_WORLD, huge);
            }).find("mesh.box.cells 5000 x 5000 x 5000 gives 750000000000 tets"),
            std::string::npos);
}

}  // namespace
}  // namespace descent
