#pragma once
// The two meshes the partition tests split (test_partition,
// test_geometric_partition): a box of 600 tets and a coarse double helix.
#include "common/mesh.hpp"
#include "meshes/generators.hpp"

namespace descent::testing {

inline Mesh small_box() {
  BoxParams box;
  box.cells = {6, 5, 4};
  box.tets_per_cell = 5;
  return make_box(box);
}

inline Mesh small_helix() {
  DoubleHelixParams helix;
  helix.resolution = 1.2;
  return make_double_helix(helix);
}

}  // namespace descent::testing
