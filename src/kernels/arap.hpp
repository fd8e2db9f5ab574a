#pragma once
// As-rigid-as-possible energy of projective dynamics (DESIGN §1, paper 1
// Eq. 16 scaled by mu):
//   Psi(F) = mu sum_k (sigma_k - 1)^2,   sigma = signed singular values of F.
// Since sum_k (sigma_k - 1)^2 = |S - I|_F^2 for the polar F = R S, this is the
// corotated model without its volumetric term (lambda = 0), and is computed
// by it: P = 2 mu (F - R), dPdF = 2 mu I - sum_{k<l} 2 mu / (sigma_k + sigma_l)
// W_kl (x) W_kl. It resists no volume change beyond what shear implies, so
// its small-strain limit is linear elasticity with shear modulus mu and
// lambda = 0 (a uniaxial slope of 2 mu, not E). Defined and smooth for
// inverted elements: the paper's fallback model for them (Eqs. 17-19).
#include "kernels/corotated.hpp"

namespace descent {

template <class Real>
struct Arap {
  // Defined (finite, smooth) for inverted elements, det F <= 0.
  static constexpr bool kInvertible = true;
  Real mu;

  // Only the shear modulus of (E, nu) enters: mu = E / (2 (1 + nu)).
  static Arap from_young_poisson(Real young, Real poisson) {
    return {young / (Real(2) * (Real(1) + poisson))};
  }

  DESCENT_HOST_DEVICE Corotated<Real> as_corotated() const { return {mu, Real(0)}; }

  DESCENT_HOST_DEVICE Real energy(const Mat3<Real>& f) const { return as_corotated().energy(f); }

  DESCENT_HOST_DEVICE Mat3<Real> stress(const Mat3<Real>& f) const {
    return as_corotated().stress(f);
  }

  DESCENT_HOST_DEVICE void hessian_diagonal(const Mat3<Real>& f, const Vec3<Real> b[4],
                                            Vec3<Real> out[4]) const {
    as_corotated().hessian_diagonal(f, b, out);
  }

  DESCENT_HOST_DEVICE void stress_derivative(const Mat3<Real>& f, Real dpdf[81]) const {
    as_corotated().stress_derivative(f, dpdf);
  }
};

}  // namespace descent
