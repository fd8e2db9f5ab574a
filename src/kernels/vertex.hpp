#pragma once
// Per-vertex terms of the incremental potential (DESIGN §1) and the descent
// update. Per degree of freedom (one axis of one vertex), with lumped mass m,
// inertial target y = q_t + h v_t, gravity component g, air damping c and
// external (surface-load) force f:
//   energy    m/(2h^2) (q - y)^2 - m g q + c m/(2h) (q - q_t)^2 - f q
//   gradient  elastic + m/h^2 (q - y) - m g + c m/h (q - q_t) - f
//   diagonal  max(m/h^2 + c m/h + elastic, floor)
// The floor is m/h^2 + c m/h in dynamics (so d >= m/h^2 per axis) and a
// fraction of the rest stiffness in quasi-static solves, where 1/h^2 = c = 0.
#include "kernels/host_device.hpp"

namespace descent {

template <class Real>
struct VertexTerms {
  Real inv_h2;          // 1/h^2
  Real damping_over_h;  // c/h
  Real gravity[3];
};

template <class Real>
DESCENT_HOST_DEVICE inline Real dof_energy(const VertexTerms<Real>& t, Real m, Real q, Real y,
                                           Real qt, Real f, int axis) {
  return m * (Real(0.5) * t.inv_h2 * (q - y) * (q - y) - t.gravity[axis] * q +
              Real(0.5) * t.damping_over_h * (q - qt) * (q - qt)) -
         f * q;
}

template <class Real>
DESCENT_HOST_DEVICE inline Real dof_gradient(const VertexTerms<Real>& t, Real m, Real elastic,
                                             Real q, Real y, Real qt, Real f, int axis) {
  return elastic + m * (t.inv_h2 * (q - y) - t.gravity[axis] + t.damping_over_h * (q - qt)) - f;
}

template <class Real>
DESCENT_HOST_DEVICE inline Real dof_diagonal(const VertexTerms<Real>& t, Real m, Real elastic,
                                             Real floor) {
  const Real d = m * (t.inv_h2 + t.damping_over_h) + elastic;
  return d > floor ? d : floor;
}

// One Jacobi-preconditioned descent step with Chebyshev acceleration
// (paper 1, Algorithm 1 steps 3-4): q_bar = q - alpha g / d, then
// q+ = omega (q_bar - q_prev) + q_prev.
template <class Real>
DESCENT_HOST_DEVICE inline Real chebyshev_dof(Real q, Real q_prev, Real g, Real d, Real alpha,
                                              Real omega) {
  const Real q_bar = q - alpha * g / d;
  return omega * (q_bar - q_prev) + q_prev;
}

}  // namespace descent
