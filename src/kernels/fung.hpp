#pragma once
// Isotropic Fung energy density (DESIGN §1, paper 1 Eq. 15):
//   Psi(F) = neo-Hookean(F) + c2 (exp(c3 (Ibar1 - 3)) - 1),   Ibar1 = J^(-2/3) I1,
// stiffening exponentially with distortion, as soft tissue does. Near F = I,
// exp(c3 x) - 1 ~ c3 x with Ibar1 - 3 ~ 2 |dev eps|^2, so the term adds
// 2 c2 c3 to the shear modulus; the bulk modulus stays kappa.
//
// With g = c2 exp(c3 (Ibar1 - 3)) and D = dIbar1/dF:
//   dPsi = (mu/2 + g c3) dIbar1 + volumetric:  the neo-Hookean stress with
//          shear modulus mu + 2 g c3;
//   d2Psi = that neo-Hookean's d2Psi + g c3^2 D (x) D,
//   D = 2 J^(-2/3) F - 2/3 I1 J^(-5/3) cof F.
#include <cmath>

#include "kernels/neo_hookean.hpp"
#include "kernels/real_math.hpp"

namespace descent {

template <class Real>
struct Fung {
  // Built on J^(-2/3): meaningless for det F <= 0, where element_energy
  // makes it infinite so that no step into inversion is accepted.
  static constexpr bool kInvertible = false;
  NeoHookean<Real> neo_hookean;
  Real c2;
  Real c3;

  static Fung from_young_poisson(Real young, Real poisson, Real c2, Real c3) {
    return {NeoHookean<Real>::from_young_poisson(young, poisson), c2, c3};
  }

  // g and D of the header comment, and the neo-Hookean that carries the
  // isochoric part of the exponential term.
  struct Terms {
    Real g;
    Mat3<Real> d;
    NeoHookean<Real> stiffened;
  };

  DESCENT_HOST_DEVICE Terms terms(const Mat3<Real>& f) const {
    const Mat3<Real> cof = cofactor(f);
    const Real j = f.m[0] * cof.m[0] + f.m[1] * cof.m[1] + f.m[2] * cof.m[2];
    const Real root_j = cube_root(j);
    const Real j_m23 = Real(1) / (root_j * root_j);
    const Real i1 = ddot(f, f);
    Terms r;
    r.g = c2 * exponential(c3 * (j_m23 * i1 - Real(3)));
    const Real b = -Real(2) / Real(3) * i1 * j_m23 / j;
    for (int k = 0; k < 9; ++k) r.d.m[k] = Real(2) * j_m23 * f.m[k] + b * cof.m[k];
    r.stiffened = {neo_hookean.mu + Real(2) * r.g * c3, neo_hookean.kappa};
    return r;
  }

  DESCENT_HOST_DEVICE Real energy(const Mat3<Real>& f) const {
    const Real j = det(f);
    const Real root_j = cube_root(j);
    const Real ibar1 = ddot(f, f) / (root_j * root_j);
    return neo_hookean.energy(f) + c2 * (exponential(c3 * (ibar1 - Real(3))) - Real(1));
  }

  DESCENT_HOST_DEVICE Mat3<Real> stress(const Mat3<Real>& f) const {
    return terms(f).stiffened.stress(f);
  }

  // The stiffened neo-Hookean diagonal plus g c3^2 (D_i . b)^2 along e_i b^T.
  DESCENT_HOST_DEVICE void hessian_diagonal(const Mat3<Real>& f, const Vec3<Real> b[4],
                                            Vec3<Real> out[4]) const {
    const Terms r = terms(f);
    r.stiffened.hessian_diagonal(f, b, out);
    const Real s = r.g * c3 * c3;
    for (int a = 0; a < 4; ++a) {
      const Vec3<Real> db = mul(r.d, b[a]);
      out[a].x += s * db.x * db.x;
      out[a].y += s * db.y * db.y;
      out[a].z += s * db.z * db.z;
    }
  }

  DESCENT_HOST_DEVICE void stress_derivative(const Mat3<Real>& f, Real dpdf[81]) const {
    const Terms r = terms(f);
    r.stiffened.stress_derivative(f, dpdf);
    add_outer(r.d, r.g * c3 * c3, dpdf);
  }
};

}  // namespace descent
