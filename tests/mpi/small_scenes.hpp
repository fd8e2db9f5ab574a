#pragma once
// Small scenes built in code for the MPI tests (no files needed).
#include <algorithm>
#include <array>
#include <vector>

#include "common/mesh.hpp"
#include "io/scene.hpp"
#include "meshes/generators.hpp"

namespace descent::testing {

// The double helix at a low resolution (a few thousand tets), hanging from
// its top cap under gravity, with Jacobi's preconditioner: the paper's
// method, whose counts and behaviour the tests that use this scene pin down
// (the multilevel preconditioner has tests of its own).
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
  scene.solver.preconditioner = "jacobi";
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

// A box body of 3 x 3 x 3 cells, 0.2 m on a side, moved to `translate` and
// thrown along x at vx.
inline Body box(std::array<double, 3> translate, double vx) {
  Body body;
  body.mesh.generator = "box";
  body.mesh.box.cells = {3, 3, 3};
  body.mesh.box.size = {0.2, 0.2, 0.2};
  body.translate = translate;
  body.velocity = {vx, 0, 0};
  return body;
}

// Two boxes 0.3 apart along x, offset across so edges and faces meet off
// centre, closing at 2 vx; no gravity.
inline Scene head_on(double vx) {
  Scene scene;
  scene.bodies = {box({-0.25, 0, 0}, vx), box({0.25, 0.03, 0.02}, -vx)};
  scene.gravity = {0, 0, 0};
  scene.material.young = 1e5;
  scene.time.dt = 0.01;
  scene.solver.iterations = 300;
  return scene;
}

// The mesh's positions stretched along the helix axis (y) from its held top
// by `factor` (< 1 compresses): far from equilibrium, so Newton needs several
// iterations, with the exact Hessian indefinite on the way, and |g0| is large
// against the floor where eps's round-off stops an energy line search.
inline std::vector<double> stretched_positions(const Mesh& mesh, double factor = 1.2) {
  std::vector<double> stretched = mesh.positions;
  double top = -1e300;
  for (std::size_t k = 1; k < stretched.size(); k += 3) top = std::max(top, stretched[k]);
  for (std::size_t k = 1; k < stretched.size(); k += 3)
    stretched[k] = top + factor * (stretched[k] - top);
  return stretched;
}

}  // namespace descent::testing
