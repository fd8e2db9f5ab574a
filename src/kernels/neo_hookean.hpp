#pragma once
// Compressible neo-Hookean energy density (DESIGN §1, paper 1 Eq. 13):
//   Psi(F) = mu/2 (J^(-2/3) I1 - 3) + kappa/2 (J - 1)^2,
// I1 = tr(F^T F), J = det F, kappa = lambda + 2 mu / 3. Psi(I) = 0, P(I) = 0,
// and the small-strain limit is linear elasticity with (E, nu).
// J^(-2/3) uses the real cube root, so Psi stays defined (and large) for
// inverted elements and is infinite only at J = 0.
#include <cmath>

#include "kernels/mat3.hpp"

namespace descent {

template <class Real>
struct NeoHookean {
  Real mu;
  Real kappa;

  static NeoHookean from_young_poisson(Real young, Real poisson) {
    const Real mu = young / (Real(2) * (Real(1) + poisson));
    const Real lambda = young * poisson / ((Real(1) + poisson) * (Real(1) - Real(2) * poisson));
    return {mu, lambda + Real(2) * mu / Real(3)};
  }

  DESCENT_HOST_DEVICE Real energy(const Mat3<Real>& f) const {
    const Real j = det(f);
    const Real j_m23 = Real(1) / (std::cbrt(j) * std::cbrt(j));
    return mu / Real(2) * (j_m23 * ddot(f, f) - Real(3)) + kappa / Real(2) * (j - 1) * (j - 1);
  }

  // First Piola-Kirchhoff stress P = dPsi/dF, written with cof(F) = J F^-T so
  // no inverse is formed:
  //   P = mu J^(-2/3) F - mu/3 I1 J^(-5/3) cof(F) + kappa (J - 1) cof(F).
  DESCENT_HOST_DEVICE Mat3<Real> stress(const Mat3<Real>& f) const {
    const Mat3<Real> c = cofactor(f);
    const Real j = f.m[0] * c.m[0] + f.m[1] * c.m[1] + f.m[2] * c.m[2];
    const Real cbrt_j = std::cbrt(j);
    const Real j_m23 = Real(1) / (cbrt_j * cbrt_j);
    const Real i1 = ddot(f, f);
    const Real a = mu * j_m23;
    const Real b = -mu / Real(3) * i1 * j_m23 / j + kappa * (j - Real(1));
    Mat3<Real> p;
    for (int k = 0; k < 9; ++k) p.m[k] = a * f.m[k] + b * c.m[k];
    return p;
  }

  // Second derivatives of Psi along dF = e_i b_a^T (row i of F moved by b_a)
  // for the four corners a and three axes i. det F is linear in each row, so
  // d2J = 0 along such a dF and only J' = cof(F)_i . b_a enters:
  //   d2/dt2 J^(-2/3) I1 = 10/9 J^(-8/3) J'^2 I1 - 8/3 J^(-5/3) J' (F_i . b_a)
  //                        + 2 J^(-2/3) |b_a|^2,      d2/dt2 (J-1)^2 = 2 J'^2.
  DESCENT_HOST_DEVICE void hessian_diagonal(const Mat3<Real>& f, const Vec3<Real> b[4],
                                            Vec3<Real> out[4]) const {
    const Mat3<Real> c = cofactor(f);
    const Real j = f.m[0] * c.m[0] + f.m[1] * c.m[1] + f.m[2] * c.m[2];
    const Real i1 = ddot(f, f);
    const Real cbrt_j = std::cbrt(j);
    const Real j_m23 = Real(1) / (cbrt_j * cbrt_j);
    const Real inv_j = Real(1) / j;
    for (int a = 0; a < 4; ++a) {
      Real d[3];
      for (int i = 0; i < 3; ++i) {
        const Real dj = dot(row(c, i), b[a]);
        const Real fb = dot(row(f, i), b[a]);
        const Real iso = j_m23 * (Real(10) / Real(9) * inv_j * inv_j * dj * dj * i1 -
                                  Real(8) / Real(3) * inv_j * dj * fb + Real(2) * dot(b[a], b[a]));
        d[i] = mu / Real(2) * iso + kappa * dj * dj;
      }
      out[a] = {d[0], d[1], d[2]};
    }
  }
};

}  // namespace descent
