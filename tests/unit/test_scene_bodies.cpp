// The mesh of a scene of several bodies (app/scene_mesh.hpp): bodies placed
// by scale, rotation and translation about their rest centroids, joined in
// order with their vertex offsets, and refused when two overlap, whether a
// vertex lies inside the other body, a surface edge crosses its surface, or
// one body holds the other whole; bodies that only touch pass.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include "app/scene_mesh.hpp"
#include "common/error.hpp"
#include "meshes/generators.hpp"

namespace descent {
namespace {

Body box(std::array<int, 3> cells, std::array<double, 3> size, std::array<double, 3> origin) {
  Body body;
  body.mesh.generator = "box";
  body.mesh.box.cells = cells;
  body.mesh.box.size = size;
  body.mesh.box.origin = origin;
  return body;
}

Scene scene_of(std::vector<Body> bodies) {
  Scene scene;
  scene.bodies = std::move(bodies);
  return scene;
}

// Bounds of body b's vertices: lo xyz, hi xyz.
std::array<double, 6> bounds(const Mesh& mesh, int b) {
  std::array<double, 6> box{1e300, 1e300, 1e300, -1e300, -1e300, -1e300};
  for (global_index_t v = mesh.body_vertex_offsets[b]; v < mesh.body_vertex_offsets[b + 1]; ++v)
    for (int d = 0; d < 3; ++d) {
      box[d] = std::min(box[d], mesh.positions[3 * v + d]);
      box[3 + d] = std::max(box[3 + d], mesh.positions[3 * v + d]);
    }
  return box;
}

std::string overlap_error(const Scene& scene) {
  try {
    build_scene_mesh(scene);
  } catch (const InputError& error) {
    return error.what();
  }
  ADD_FAILURE() << "no InputError";
  return "";
}

TEST(SceneBodies, BodiesArePlacedAboutTheirCentroidAndJoinedInOrder) {
  Body first = box({2, 1, 1}, {0.2, 0.1, 0.1}, {0, 0, 0});
  Body second = box({2, 1, 1}, {0.2, 0.1, 0.1}, {0, 0, 0});
  second.scale = 2;
  second.rotate_axis = {0, 0, 3};  // normalised on use
  second.rotate_degrees = 90;
  second.translate = {1, 0, 0};
  const Mesh mesh = build_scene_mesh(scene_of({first, second}));
  const Mesh one = make_box(first.mesh.box);
  ASSERT_EQ(mesh.body_vertex_offsets,
            (std::vector<global_index_t>{0, one.num_vertices(), 2 * one.num_vertices()}));
  ASSERT_EQ(mesh.num_tets(), 2 * one.num_tets());
  // The first body is untouched, bit for bit; the second's tets use its own vertices.
  for (index_t k = 0; k < 3 * one.num_vertices(); ++k)
    ASSERT_EQ(mesh.positions[k], one.positions[k]);
  for (index_t k = 0; k < 4 * one.num_tets(); ++k)
    ASSERT_EQ(mesh.tets[4 * one.num_tets() + k], one.tets[k] + one.num_vertices());
  // Doubled about its centre (0.1, 0.05, 0.05), turned a quarter about z,
  // moved by +1 in x: extents (0.2, 0.4, 0.2) about (1.1, 0.05, 0.05).
  const std::array<double, 6> b = bounds(mesh, 1);
  const double want[6] = {1.0, -0.15, -0.05, 1.2, 0.25, 0.15};
  for (int k = 0; k < 6; ++k) EXPECT_NEAR(b[k], want[k], 1e-14) << "bound " << k;
}

TEST(SceneBodies, ABodyInsideAnotherIsAnErrorNamingBoth) {
  const std::string message = overlap_error(scene_of(
      {box({2, 2, 2}, {1, 1, 1}, {0, 0, 0}), box({1, 1, 1}, {0.2, 0.2, 0.2}, {0.4, 0.4, 0.4})}));
  EXPECT_NE(message.find("body.1 ("), std::string::npos) << message;
  EXPECT_NE(message.find("and body.0 ("), std::string::npos) << message;
  EXPECT_NE(message.find("a vertex of the first lies inside the second"), std::string::npos)
      << message;
}

TEST(SceneBodies, BarsCrossingWithNoVertexInsideAreAnError) {
  // A cross of two bars through each other, no vertex of either inside the
  // other: only their surfaces' edges and triangles meet.
  Body along_x = box({5, 1, 1}, {1, 0.1, 0.1}, {-0.5, 0, -0.05});
  Body along_z = box({1, 1, 5}, {0.1, 0.1, 1}, {-0.05, 0.03, -0.5});
  const std::string message = overlap_error(scene_of({along_x, along_z}));
  EXPECT_NE(message.find("a surface edge of the first crosses the surface of the second"),
            std::string::npos)
      << message;
  EXPECT_NE(message.find("overlap near ("), std::string::npos) << message;
}

TEST(SceneBodies, BodiesThatTouchOrNearlyTouchPass) {
  // Stacked face on face, then turned alike about the vertical (the shared
  // plane then holds only to rounding), then 1e-9 apart.
  Body low = box({2, 1, 2}, {0.4, 0.1, 0.4}, {0, 0, 0});
  Body high = box({3, 1, 3}, {0.4, 0.1, 0.4}, {0, 0.1, 0});
  EXPECT_NO_THROW(build_scene_mesh(scene_of({low, high})));
  low.rotate_degrees = high.rotate_degrees = 30;
  EXPECT_NO_THROW(build_scene_mesh(scene_of({low, high})));
  high.translate = {0.05, 1e-9, 0.05};
  EXPECT_NO_THROW(build_scene_mesh(scene_of({low, high})));
  // ... and sunk 1e-3 into each other, they overlap.
  high.translate = {0.05, -1e-3, 0.05};
  EXPECT_NE(overlap_error(scene_of({low, high})).find("overlap"), std::string::npos);
}

TEST(SceneBodies, AMeshOfOneBodyHasNoOffsets) {
  Scene scene;
  scene.mesh.generator = "box";
  EXPECT_TRUE(build_scene_mesh(scene).body_vertex_offsets.empty());
}

}  // namespace
}  // namespace descent
