#pragma once
// Small scenes built in code for the MPI tests (no files needed).
#include "io/scene.hpp"
#include "meshes/generators.hpp"

namespace descent::testing {

// The double helix at a low resolution (a few thousand tets), hanging from
// its top cap under gravity.
inline Scene small_helix_scene() {
  Scene scene;
  scene.mesh.generator = "double_helix";
  scene.mesh.helix.resolution = 1.2;
  const double height = double_helix_height(scene.mesh.helix);
  FixedRegion top;
  top.box_min = {-1.0, height - 0.04, -1.0};
  top.box_max = {1.0, height + 1.0, 1.0};
  scene.fixed.push_back(top);
  scene.material.young = 1e5;
  scene.material.poisson = 0.3;
  scene.material.density = 1000;
  scene.time.dt = 1.0 / 30.0;
  scene.solver.iterations = 96;
  return scene;
}

// `scene` with the paper's fixed Chebyshev parameters set explicitly (rho
// 0.96, 10 plain iterations, alpha_max 1): the method before the automatic
// parameters, whose collectives and behaviour some tests pin down.
inline Scene fixed_chebyshev(Scene scene) {
  scene.solver.chebyshev_parameters = "fixed";
  scene.solver.rho = 0.96;
  scene.solver.chebyshev_delay = 10;
  scene.solver.alpha_max = 1.0;
  return scene;
}

}  // namespace descent::testing
