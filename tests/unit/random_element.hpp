#pragma once
// Test helper: random tets for the finite-difference checks of the element
// functions, shared by the model and Hessian-product tests.
#include <random>

#include "kernels/element.hpp"
#include "kernels/tet.hpp"

namespace descent::testing {

struct ElementCase {
  TetRest<double> rest;
  TetCorners<double> x;
};

// A random tet with positive rest volume, deformed by corner moves of size
// `amp` until det F lies in [det_min, det_max].
inline ElementCase random_element(std::mt19937_64& rng, double amp, double det_min = 0.2,
                                  double det_max = 1e30) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const Vec3<double> base[4] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  for (;;) {
    TetCorners<double> rest_x, x;
    for (int a = 0; a < 4; ++a) {
      rest_x.x[a] = {base[a].x + 0.2 * u(rng), base[a].y + 0.2 * u(rng), base[a].z + 0.2 * u(rng)};
      x.x[a] = {rest_x.x[a].x + amp * u(rng), rest_x.x[a].y + amp * u(rng),
                rest_x.x[a].z + amp * u(rng)};
    }
    const TetRest<double> rest = tet_rest(rest_x.x[0], rest_x.x[1], rest_x.x[2], rest_x.x[3]);
    const double j = det(deformation_gradient(x.x[0], x.x[1], x.x[2], x.x[3], rest.dm_inv));
    if (rest.volume > 0.05 && j >= det_min && j <= det_max) return {rest, x};
  }
}

}  // namespace descent::testing
