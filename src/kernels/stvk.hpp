#pragma once
// St. Venant-Kirchhoff energy density (DESIGN §1, paper 1 Eq. 12):
//   Psi(F) = mu tr(E^2) + lambda/2 (tr E)^2,   E = 1/2 (F^T F - I).
// A polynomial in F: defined (and finite) for inverted elements too, though
// it resists compression weakly. Psi(I) = 0, P(I) = 0, and its small-strain
// limit is linear elasticity with (E, nu).
#include "kernels/mat3.hpp"

namespace descent {

template <class Real>
struct StVK {
  // Defined (finite, smooth) for inverted elements, det F <= 0.
  static constexpr bool kInvertible = true;
  Real mu;
  Real lambda;

  static StVK from_young_poisson(Real young, Real poisson) {
    const Real mu = young / (Real(2) * (Real(1) + poisson));
    const Real lambda = young * poisson / ((Real(1) + poisson) * (Real(1) - Real(2) * poisson));
    return {mu, lambda};
  }

  // Green strain E = 1/2 (F^T F - I), symmetric.
  DESCENT_HOST_DEVICE static Mat3<Real> green_strain(const Mat3<Real>& f) {
    Mat3<Real> e;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        e.m[3 * i + j] = Real(0.5) * (f.m[i] * f.m[j] + f.m[3 + i] * f.m[3 + j] +
                                      f.m[6 + i] * f.m[6 + j] - (i == j ? Real(1) : Real(0)));
    return e;
  }

  // Second Piola-Kirchhoff stress S = 2 mu E + lambda tr(E) I.
  DESCENT_HOST_DEVICE Mat3<Real> second_piola(const Mat3<Real>& f) const {
    Mat3<Real> s = green_strain(f);
    const Real tr = s.m[0] + s.m[4] + s.m[8];
    for (int k = 0; k < 9; ++k) s.m[k] *= Real(2) * mu;
    for (int k = 0; k < 3; ++k) s.m[4 * k] += lambda * tr;
    return s;
  }

  DESCENT_HOST_DEVICE Real energy(const Mat3<Real>& f) const {
    const Mat3<Real> e = green_strain(f);
    const Real tr = e.m[0] + e.m[4] + e.m[8];
    return mu * ddot(e, e) + lambda / Real(2) * tr * tr;
  }

  // P = F S.
  DESCENT_HOST_DEVICE Mat3<Real> stress(const Mat3<Real>& f) const {
    return mul(f, second_piola(f));
  }

  // dP = dF S + F dS with dS = mu (dF^T F + F^T dF) + lambda (F : dF) I, so
  //   dP_ij/dF_kl = delta_ik S_lj + mu (F F^T)_ik delta_jl + mu F_il F_kj
  //                 + lambda F_ij F_kl.
  // Along dF = e_i b^T (row i of F moved by b) this gives
  //   b^T S b + mu |F_i|^2 |b|^2 + (mu + lambda) (F_i . b)^2,   F_i = row i.
  DESCENT_HOST_DEVICE void hessian_diagonal(const Mat3<Real>& f, const Vec3<Real> b[4],
                                            Vec3<Real> out[4]) const {
    const Mat3<Real> s = second_piola(f);
    for (int a = 0; a < 4; ++a) {
      const Real bsb = dot(b[a], mul(s, b[a]));
      const Real bb = dot(b[a], b[a]);
      Real d[3];
      for (int i = 0; i < 3; ++i) {
        const Vec3<Real> fi = row(f, i);
        const Real fb = dot(fi, b[a]);
        d[i] = bsb + mu * dot(fi, fi) * bb + (mu + lambda) * fb * fb;
      }
      out[a] = {d[0], d[1], d[2]};
    }
  }

  // dPdF[(3i+j)*9 + 3k+l] = dP_ij/dF_kl, the formula above.
  DESCENT_HOST_DEVICE void stress_derivative(const Mat3<Real>& f, Real dpdf[81]) const {
    const Mat3<Real> s = second_piola(f);
    for (int i = 0; i < 3; ++i) {
      for (int k = 0; k < 3; ++k) {
        const Real ffik = f.m[3 * i] * f.m[3 * k] + f.m[3 * i + 1] * f.m[3 * k + 1] +
                          f.m[3 * i + 2] * f.m[3 * k + 2];
        for (int j = 0; j < 3; ++j) {
          for (int l = 0; l < 3; ++l) {
            Real v =
                mu * f.m[3 * i + l] * f.m[3 * k + j] + lambda * f.m[3 * i + j] * f.m[3 * k + l];
            if (i == k) v += s.m[3 * l + j];
            if (j == l) v += mu * ffik;
            dpdf[(3 * i + j) * 9 + 3 * k + l] = v;
          }
        }
      }
    }
  }
};

}  // namespace descent
