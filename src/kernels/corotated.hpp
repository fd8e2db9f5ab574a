#pragma once
// Corotated linear elasticity (DESIGN §1, paper 2 Eqs. 3-5):
//   Psi(F) = mu |S - I|_F^2 + lambda/2 (tr(S - I))^2,   F = R S,
// with the polar decomposition taken from the signed SVD F = U diag(sigma) V^T:
// R = U V^T (a rotation even for det F < 0), S = V diag(sigma) V^T. In
// singular values Psi = mu sum (sigma_k - 1)^2 + lambda/2 (sum sigma_k - 3)^2,
// defined and smooth for inverted elements; its small-strain limit is linear
// elasticity with (E, nu).
//
// Stress: psi_k = dPsi/dsigma_k = 2 mu (sigma_k - 1) + lambda (tr S - 3), and
//   P = U diag(psi) V^T = 2 mu (F - R) + lambda (tr S - 3) R.
// Stress derivative, from the eigensystem of an isotropic energy's Hessian
// (Teran et al. 2005; Smith et al. 2019): in the basis of the nine matrices
// u_k v_k^T (scaling), (u_k v_l^T +- u_l v_k^T)/sqrt2 (flip, twist) it is
// block diagonal with flip eigenvalues (psi_k - psi_l)/(sigma_k - sigma_l) =
// 2 mu exactly, so repeated singular values need no limit, and twist
// eigenvalues (psi_k + psi_l)/(sigma_k + sigma_l). Collecting terms,
//   dPdF = 2 mu I + lambda R (x) R + sum_{k<l} c_kl W_kl (x) W_kl,
//   W_kl = u_k v_l^T - u_l v_k^T,  c_kl = (lambda (tr S - 3) - 2 mu) / (sigma_k + sigma_l).
// With the signed convention sigma_k + sigma_l >= 0 for k < l; it vanishes
// only where the rotation itself is undefined (two singular values 0, or an
// inverted element with sigma_0 = sigma_1 = -sigma_2), where the energy is
// not twice differentiable. There the denominator is floored at 1e-6 (F is
// dimensionless), giving a large but finite twist curvature.
#include "kernels/svd3.hpp"

namespace descent {

template <class Real>
struct Corotated {
  // Defined (finite, smooth) for inverted elements, det F <= 0.
  static constexpr bool kInvertible = true;
  Real mu;
  Real lambda;

  static Corotated from_young_poisson(Real young, Real poisson) {
    const Real mu = young / (Real(2) * (Real(1) + poisson));
    const Real lambda = young * poisson / ((Real(1) + poisson) * (Real(1) - Real(2) * poisson));
    return {mu, lambda};
  }

  // SVD-derived quantities of one F.
  struct Terms {
    Svd3<Real> svd;
    Mat3<Real> r;   // U V^T
    Real trace_s;   // sum sigma_k
    Real twist[3];  // c_kl for (k, l) = (0, 1), (0, 2), (1, 2)
  };

  DESCENT_HOST_DEVICE Terms terms(const Mat3<Real>& f) const {
    Terms t;
    t.svd = svd3(f);
    const Mat3<Real>& u = t.svd.u;
    const Mat3<Real>& v = t.svd.v;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        t.r.m[3 * i + j] = u.m[3 * i] * v.m[3 * j] + u.m[3 * i + 1] * v.m[3 * j + 1] +
                           u.m[3 * i + 2] * v.m[3 * j + 2];
    const Real* s = t.svd.sigma;
    t.trace_s = s[0] + s[1] + s[2];
    const Real numerator = lambda * (t.trace_s - Real(3)) - Real(2) * mu;
    const Real min_denominator = Real(1e-6);
    const int pairs[3][2] = {{0, 1}, {0, 2}, {1, 2}};
    for (int p = 0; p < 3; ++p) {
      const Real sum = s[pairs[p][0]] + s[pairs[p][1]];
      t.twist[p] = numerator / select(sum > min_denominator, sum, min_denominator);
    }
    return t;
  }

  DESCENT_HOST_DEVICE Real energy(const Mat3<Real>& f) const {
    const Svd3<Real> d = svd3(f);
    const Real tr = d.sigma[0] + d.sigma[1] + d.sigma[2] - Real(3);
    Real dev = 0;
    for (int k = 0; k < 3; ++k) dev += (d.sigma[k] - Real(1)) * (d.sigma[k] - Real(1));
    return mu * dev + lambda / Real(2) * tr * tr;
  }

  DESCENT_HOST_DEVICE Mat3<Real> stress(const Mat3<Real>& f) const {
    const Terms t = terms(f);
    const Real volumetric = lambda * (t.trace_s - Real(3));
    Mat3<Real> p;
    for (int k = 0; k < 9; ++k) p.m[k] = Real(2) * mu * (f.m[k] - t.r.m[k]) + volumetric * t.r.m[k];
    return p;
  }

  // Along dF = e_i b^T: 2 mu |b|^2 + lambda (R_i . b)^2
  //   + sum_{k<l} c_kl (U_ik w_l - U_il w_k)^2,   w = V^T b.
  DESCENT_HOST_DEVICE void hessian_diagonal(const Mat3<Real>& f, const Vec3<Real> b[4],
                                            Vec3<Real> out[4]) const {
    const Terms t = terms(f);
    const Mat3<Real>& u = t.svd.u;
    const Mat3<Real>& v = t.svd.v;
    const int pairs[3][2] = {{0, 1}, {0, 2}, {1, 2}};
    for (int a = 0; a < 4; ++a) {
      const Real w[3] = {v.m[0] * b[a].x + v.m[3] * b[a].y + v.m[6] * b[a].z,
                         v.m[1] * b[a].x + v.m[4] * b[a].y + v.m[7] * b[a].z,
                         v.m[2] * b[a].x + v.m[5] * b[a].y + v.m[8] * b[a].z};
      const Real bb = dot(b[a], b[a]);
      Real d[3];
      for (int i = 0; i < 3; ++i) {
        const Real rb = dot(row(t.r, i), b[a]);
        Real h = Real(2) * mu * bb + lambda * rb * rb;
        for (int p = 0; p < 3; ++p) {
          const int k = pairs[p][0], l = pairs[p][1];
          const Real wb = u.m[3 * i + k] * w[l] - u.m[3 * i + l] * w[k];
          h += t.twist[p] * wb * wb;
        }
        d[i] = h;
      }
      out[a] = {d[0], d[1], d[2]};
    }
  }

  DESCENT_HOST_DEVICE void stress_derivative(const Mat3<Real>& f, Real dpdf[81]) const {
    const Terms t = terms(f);
    const Mat3<Real>& u = t.svd.u;
    const Mat3<Real>& v = t.svd.v;
    const int pairs[3][2] = {{0, 1}, {0, 2}, {1, 2}};
    Mat3<Real> twist_modes[3];
    for (int p = 0; p < 3; ++p) {
      const int k = pairs[p][0], l = pairs[p][1];
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
          twist_modes[p].m[3 * i + j] =
              u.m[3 * i + k] * v.m[3 * j + l] - u.m[3 * i + l] * v.m[3 * j + k];
    }
    for (int row_index = 0; row_index < 9; ++row_index) {
      for (int col = 0; col < 9; ++col) {
        Real h = lambda * t.r.m[row_index] * t.r.m[col];
        for (int p = 0; p < 3; ++p)
          h += t.twist[p] * twist_modes[p].m[row_index] * twist_modes[p].m[col];
        if (row_index == col) h += Real(2) * mu;
        dpdf[9 * row_index + col] = h;
      }
    }
  }
};

}  // namespace descent
