#pragma once
// Geometry of one linear tetrahedron: rest-shape precomputation and the
// deformation gradient. Corner a of a tet has gradient-operator vector b_a:
// F = Ds Dm^-1 with Ds = [x1-x0, x2-x0, x3-x0] (columns), so dF_ij/dx_a,i =
// (Dm^-1)_(a-1) j for a = 1..3, i.e. b_a is row a-1 of Dm^-1, and
// b_0 = -(b_1 + b_2 + b_3). The gradient of V Psi(F) on corner a is V P b_a.
#include "kernels/mat3.hpp"

namespace descent {

// Per-tet constants, computed once from the rest mesh.
template <class Real>
struct TetRest {
  Mat3<Real> dm_inv;  // Dm^-1, row-major
  Real volume;        // V_e > 0 (positively oriented rest tet)
};

template <class Real>
DESCENT_HOST_DEVICE inline Mat3<Real> edge_matrix(const Vec3<Real>& x0, const Vec3<Real>& x1,
                                                  const Vec3<Real>& x2, const Vec3<Real>& x3) {
  return {{x1.x - x0.x, x2.x - x0.x, x3.x - x0.x, x1.y - x0.y, x2.y - x0.y, x3.y - x0.y,
           x1.z - x0.z, x2.z - x0.z, x3.z - x0.z}};
}

// Rest constants; volume is det(Dm)/6, negative for an inverted rest tet
// (callers validate meshes so this does not happen).
template <class Real>
DESCENT_HOST_DEVICE inline TetRest<Real> tet_rest(const Vec3<Real>& x0, const Vec3<Real>& x1,
                                                  const Vec3<Real>& x2, const Vec3<Real>& x3) {
  const Mat3<Real> dm = edge_matrix(x0, x1, x2, x3);
  const Real d = det(dm);
  const Mat3<Real> c = cofactor(dm);
  TetRest<Real> rest;
  // Dm^-1 = cof(Dm)^T / det(Dm)
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) rest.dm_inv.m[3 * i + j] = c.m[3 * j + i] / d;
  rest.volume = d / Real(6);
  return rest;
}

// b_a for a = 0..3.
template <class Real>
DESCENT_HOST_DEVICE inline Vec3<Real> corner_operator(const Mat3<Real>& dm_inv, int a) {
  if (a > 0) return row(dm_inv, a - 1);
  return {-(dm_inv.m[0] + dm_inv.m[3] + dm_inv.m[6]), -(dm_inv.m[1] + dm_inv.m[4] + dm_inv.m[7]),
          -(dm_inv.m[2] + dm_inv.m[5] + dm_inv.m[8])};
}

template <class Real>
DESCENT_HOST_DEVICE inline Mat3<Real> deformation_gradient(const Vec3<Real>& x0,
                                                           const Vec3<Real>& x1,
                                                           const Vec3<Real>& x2,
                                                           const Vec3<Real>& x3,
                                                           const Mat3<Real>& dm_inv) {
  return mul(edge_matrix(x0, x1, x2, x3), dm_inv);
}

}  // namespace descent
