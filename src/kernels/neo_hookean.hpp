#pragma once
// Compressible neo-Hookean energy density (DESIGN §1, paper 1 Eq. 13):
//   Psi(F) = mu/2 (J^(-2/3) I1 - 3) + kappa/2 (J - 1)^2,
// I1 = tr(F^T F), J = det F, kappa = lambda + 2 mu / 3. Psi(I) = 0, P(I) = 0,
// and the small-strain limit is linear elasticity with (E, nu).
// J^(-2/3) uses the real cube root, so Psi stays defined (and large) for
// inverted elements and is infinite only at J = 0.
#include <cmath>

#include "kernels/mat3.hpp"
#include "kernels/real_math.hpp"

namespace descent {

// Building blocks of 9x9 stress derivatives dPdF, shared by the neo-Hookean
// family. Layout: h[(3i+j)*9 + 3k+l] = dP_ij / dF_kl; vec(A)_(3i+j) = A_ij.

// h += s (vec(a) vec(b)^T + vec(b) vec(a)^T)
template <class Real>
DESCENT_HOST_DEVICE inline void add_symmetric_outer(const Mat3<Real>& a, const Mat3<Real>& b,
                                                    Real s, Real h[81]) {
  for (int r = 0; r < 9; ++r)
    for (int c = 0; c < 9; ++c) h[9 * r + c] += s * (a.m[r] * b.m[c] + b.m[r] * a.m[c]);
}

// h += s vec(a) vec(a)^T
template <class Real>
DESCENT_HOST_DEVICE inline void add_outer(const Mat3<Real>& a, Real s, Real h[81]) {
  for (int r = 0; r < 9; ++r)
    for (int c = 0; c < 9; ++c) h[9 * r + c] += s * a.m[r] * a.m[c];
}

// h += s d2(det F)/dF2, whose entry (ij, kl) is eps_ikm eps_jln F_mn: zero
// when i = k or j = l, else +-F_mn with m, n the remaining row and column.
template <class Real>
DESCENT_HOST_DEVICE inline void add_det_hessian(const Mat3<Real>& f, Real s, Real h[81]) {
  // eps of (i, k, 3-i-k) for i != k: +1 for cyclic order (k = i+1 mod 3).
  const auto eps = [](int i, int k) { return (k - i + 3) % 3 == 1 ? 1 : -1; };
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) {
      if (i == k) continue;
      for (int j = 0; j < 3; ++j)
        for (int l = 0; l < 3; ++l) {
          if (j == l) continue;
          const Real sign = Real(eps(i, k) * eps(j, l));
          h[(3 * i + j) * 9 + 3 * k + l] += s * sign * f.m[3 * (3 - i - k) + 3 - j - l];
        }
    }
}

template <class Real>
struct NeoHookean {
  // Built on J^(-2/3): meaningless for det F <= 0, where element_energy
  // makes it infinite so that no step into inversion is accepted.
  static constexpr bool kInvertible = false;
  Real mu;
  Real kappa;

  static NeoHookean from_young_poisson(Real young, Real poisson) {
    const Real mu = young / (Real(2) * (Real(1) + poisson));
    const Real lambda = young * poisson / ((Real(1) + poisson) * (Real(1) - Real(2) * poisson));
    return {mu, lambda + Real(2) * mu / Real(3)};
  }

  DESCENT_HOST_DEVICE Real energy(const Mat3<Real>& f) const {
    const Real j = det(f);
    const Real root_j = cube_root(j);
    const Real j_m23 = Real(1) / (root_j * root_j);
    return mu / Real(2) * (j_m23 * ddot(f, f) - Real(3)) + kappa / Real(2) * (j - 1) * (j - 1);
  }

  // First Piola-Kirchhoff stress P = dPsi/dF, written with cof(F) = J F^-T so
  // no inverse is formed:
  //   P = mu J^(-2/3) F - mu/3 I1 J^(-5/3) cof(F) + kappa (J - 1) cof(F).
  DESCENT_HOST_DEVICE Mat3<Real> stress(const Mat3<Real>& f) const {
    const Mat3<Real> c = cofactor(f);
    const Real j = f.m[0] * c.m[0] + f.m[1] * c.m[1] + f.m[2] * c.m[2];
    const Real root_j = cube_root(j);
    const Real j_m23 = Real(1) / (root_j * root_j);
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
    const Real root_j = cube_root(j);
    const Real j_m23 = Real(1) / (root_j * root_j);
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

  // dPdF[(3i+j)*9 + 3k+l] = dP_ij/dF_kl. With G = cof(F), dJ = G : dF and
  // dG = d2J/dF2 dF, differentiating P = a F + b G (a, b as in stress) gives
  //   dPdF = a I + c1 (F (x) G + G (x) F) + c2 G (x) G + b d2J/dF2,
  //   c1 = -2/3 mu J^(-5/3),   c2 = 5/9 mu I1 J^(-8/3) + kappa.
  DESCENT_HOST_DEVICE void stress_derivative(const Mat3<Real>& f, Real dpdf[81]) const {
    const Mat3<Real> c = cofactor(f);
    const Real j = f.m[0] * c.m[0] + f.m[1] * c.m[1] + f.m[2] * c.m[2];
    const Real root_j = cube_root(j);
    const Real j_m23 = Real(1) / (root_j * root_j);
    const Real inv_j = Real(1) / j;
    const Real i1 = ddot(f, f);
    const Real a = mu * j_m23;
    const Real b = -mu / Real(3) * i1 * j_m23 * inv_j + kappa * (j - Real(1));
    const Real c1 = -Real(2) / Real(3) * mu * j_m23 * inv_j;
    const Real c2 = Real(5) / Real(9) * mu * i1 * j_m23 * inv_j * inv_j + kappa;
    for (int k = 0; k < 81; ++k) dpdf[k] = 0;
    for (int k = 0; k < 9; ++k) dpdf[10 * k] = a;
    add_symmetric_outer(f, c, c1, dpdf);
    add_outer(c, c2, dpdf);
    add_det_hessian(f, b, dpdf);
  }
};

}  // namespace descent
