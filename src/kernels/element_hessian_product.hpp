#pragma once
// The element Hessian applied to a vector without forming the 12x12 matrix,
// for methods that need a curvature along one direction (nonlinear CG's step
// length). With dF = sum_b p_b b_b^T (tet.hpp) and the model's dPdF
// (layout of element_hessian.hpp: dPdF[(3i+m)*9 + 3j+n] = dP_im/dF_jn):
//   dP_im = sum_{j,n} dPdF[(3i+m)*9 + 3j+n] dF_jn,   out_a = V dP b_a,
// which is h p for h = element_hessian (the same contraction, reordered).
#include "kernels/element_hessian.hpp"

namespace descent {

template <class Real, class Model>
DESCENT_HOST_DEVICE inline void element_hessian_product(const Model& model,
                                                        const TetRest<Real>& rest,
                                                        const TetCorners<Real>& c,
                                                        const Vec3<Real> p[4], Vec3<Real> out[4]) {
  const Mat3<Real> f = deformation_gradient(c.x[0], c.x[1], c.x[2], c.x[3], rest.dm_inv);
  Real dpdf[81];
  model.stress_derivative(f, dpdf);
  Vec3<Real> b[4];
  for (int a = 0; a < 4; ++a) b[a] = corner_operator(rest.dm_inv, a);
  Real df[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};  // df[3j + n]
  for (int a = 0; a < 4; ++a) {
    const Real pa[3] = {p[a].x, p[a].y, p[a].z};
    const Real ba[3] = {b[a].x, b[a].y, b[a].z};
    for (int j = 0; j < 3; ++j)
      for (int n = 0; n < 3; ++n) df[3 * j + n] += pa[j] * ba[n];
  }
  Mat3<Real> dp;
  for (int r = 0; r < 9; ++r) {
    Real sum = 0;
    for (int s = 0; s < 9; ++s) sum += dpdf[9 * r + s] * df[s];
    dp.m[r] = sum;
  }
  for (int a = 0; a < 4; ++a) {
    const Vec3<Real> v = mul(dp, b[a]);
    out[a] = {rest.volume * v.x, rest.volume * v.y, rest.volume * v.z};
  }
}

}  // namespace descent
