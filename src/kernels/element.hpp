#pragma once
// Element terms of the incremental potential for any energy-density model.
// A model provides energy(F), stress(F) (first Piola-Kirchhoff P) and
// hessian_diagonal(F, b, out): d2Psi along dF = e_i b_a^T for each corner a
// and axis i (the diagonal of the 12x12 element Hessian divided by V).
#include <limits>

#include "kernels/tet.hpp"

namespace descent {

template <class Real>
struct TetCorners {
  Vec3<Real> x[4];
};

// Whether an element of det F = j has energy: a model not defined for
// inverted elements (Model::kInvertible false) gives them infinite energy,
// so the energy check rejects any step into inversion instead of letting a
// long step tunnel through J = 0.
template <class Model, class Real>
DESCENT_HOST_DEVICE inline bool outside_domain(Real j) {
  if constexpr (Model::kInvertible) return false;
  return j <= Real(0);
}

// V Psi(F); infinite outside the model's domain (outside_domain).
template <class Real, class Model>
DESCENT_HOST_DEVICE inline Real element_energy_of(const Model& model, const TetRest<Real>& rest,
                                                  const Mat3<Real>& f) {
  if constexpr (!Model::kInvertible) {
    if (outside_domain<Model>(det(f))) return std::numeric_limits<Real>::infinity();
  }
  return rest.volume * model.energy(f);
}

template <class Real, class Model>
DESCENT_HOST_DEVICE inline Real element_energy(const Model& model, const TetRest<Real>& rest,
                                               const TetCorners<Real>& c) {
  return element_energy_of(model, rest,
                           deformation_gradient(c.x[0], c.x[1], c.x[2], c.x[3], rest.dm_inv));
}

// grad[a] = V P b_a: the element's contribution to dE/dx of corner a.
template <class Real, class Model>
DESCENT_HOST_DEVICE inline void element_gradient(const Model& model, const TetRest<Real>& rest,
                                                 const TetCorners<Real>& c, Vec3<Real> grad[4]) {
  const Mat3<Real> f = deformation_gradient(c.x[0], c.x[1], c.x[2], c.x[3], rest.dm_inv);
  const Mat3<Real> p = model.stress(f);
  for (int a = 0; a < 4; ++a) {
    const Vec3<Real> pb = mul(p, corner_operator(rest.dm_inv, a));
    grad[a] = {rest.volume * pb.x, rest.volume * pb.y, rest.volume * pb.z};
  }
}

// diag[a] = V (d2Psi along e_x b_a^T, e_y b_a^T, e_z b_a^T): the element's
// contribution to the Hessian diagonal of corner a. Not clamped: a model may
// give negative curvature, the vertex update clamps the assembled total.
template <class Real, class Model>
DESCENT_HOST_DEVICE inline void element_hessian_diagonal(const Model& model,
                                                         const TetRest<Real>& rest,
                                                         const TetCorners<Real>& c,
                                                         Vec3<Real> diag[4]) {
  const Mat3<Real> f = deformation_gradient(c.x[0], c.x[1], c.x[2], c.x[3], rest.dm_inv);
  Vec3<Real> b[4];
  for (int a = 0; a < 4; ++a) b[a] = corner_operator(rest.dm_inv, a);
  model.hessian_diagonal(f, b, diag);
  for (int a = 0; a < 4; ++a) {
    diag[a].x *= rest.volume;
    diag[a].y *= rest.volume;
    diag[a].z *= rest.volume;
  }
}

}  // namespace descent
