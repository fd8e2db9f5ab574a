#pragma once
// Signed singular value decomposition of a 3x3 matrix, A = U diag(sigma) V^T,
// with U and V rotations (det +1) and sigma[0] >= sigma[1] >= |sigma[2]|;
// sigma[2] < 0 exactly when det A < 0, so an inverted element keeps a proper
// rotation and carries the reflection in its smallest stretch.
//
// Method: one-sided (Hestenes) Jacobi on the columns of A, then a Givens QR
// for U, in the spirit of McAdams et al. 2011 (fixed sweep count, no
// convergence loop, no data-dependent control flow: every choice is a
// select(), kernels/real_math.hpp, so a block of tets takes it in lanes).
// Why one-sided rather than McAdams's eigen-analysis of A^T A: the rotation
// angles are computed from the current columns of A V, not from A^T A, so
// the condition number is not squared. With two singular values below
// ~1e-8 sigma_max, the eigenvectors of A^T A that separate them are lost in
// round-off and the off-diagonal that QR leaves behind reaches 1.5e-8 ||A||
// (measured with exact eigenvectors of A^T A); here the reconstruction stays
// at round-off (~3e-15 ||A||).
//  1. Scale A by a power of two so its largest entry lies in [0.5, 1): the
//     squared column norms can neither overflow nor underflow.
//  2. Sweep the column pairs (0,1), (0,2), (1,2) with Jacobi rotations that
//     make the pair orthogonal; B = A V keeps orthogonalised columns, V
//     accumulates the rotations. Cyclic Jacobi converges quadratically; a
//     fixed count of sweeps (kSvd3Sweeps) reaches working precision.
//  3. Sort the columns of B by norm, descending, each swap negating one
//     column so det V stays +1.
//  4. Givens QR of B = U R (rows (0,1), (0,2), (1,2)), each rotation chosen so
//     the surviving diagonal entry is >= 0. R is diagonal up to round-off
//     because B's columns are orthogonal; sigma = diag(R), and
//     R_00 R_11 R_22 = det A carries the sign onto sigma[2]. A zero column
//     (rank deficiency) needs no special case: its Givens rotation is the
//     identity and U is still a rotation.
#include <cmath>

#include "kernels/mat3.hpp"
#include "kernels/real_math.hpp"

namespace descent {

template <class Real>
struct Svd3 {
  Mat3<Real> u;   // rotation, det +1
  Real sigma[3];  // sigma[0] >= sigma[1] >= |sigma[2]| (up to round-off)
  Mat3<Real> v;   // rotation, det +1
};

// Column-pair sweeps. Measured worst reconstruction error over 2e7 double
// matrices (uniform, graded entries 1e-3..1e3, clustered, near-singular, rank
// deficient): 1.6e-5 after 3 sweeps, round-off (3e-15) after 4, as the
// quadratic convergence of cyclic Jacobi predicts; float reaches its
// round-off (2e-6) after 4 too. A missing sweep would cost accuracy only:
// U and V are products of rotations whatever the count.
inline constexpr int kSvd3Sweeps = 4;

namespace svd3_detail {

// Makes columns p and q of b orthogonal by a plane rotation and applies the
// same rotation to the columns of v:
//   b_p <- c b_p - s b_q,   b_q <- s b_p + c b_q.
// With alpha = |b_p|^2, beta = |b_q|^2, gamma = b_p . b_q, the new columns are
// orthogonal when t = s / c solves gamma t^2 + (beta - alpha) t - gamma = 0.
// The root of smaller size (|t| <= 1, the stable choice) is
//   t = rho / d,   rho = 2 gamma,   d = tau + sign(tau) sqrt(tau^2 + rho^2),
// tau = beta - alpha, free of cancellation; then c = |d| / sqrt(d^2 + rho^2)
// and s = sign(d) rho / sqrt(d^2 + rho^2): two square roots and one division
// per pair. d = rho = 0 (nothing to do, e.g. the zero matrix) gives c = 1.
template <class Real>
DESCENT_HOST_DEVICE inline void orthogonalize_columns(Mat3<Real>& b, Mat3<Real>& v, int p, int q) {
  Real alpha = 0, beta = 0, gamma = 0;
  for (int r = 0; r < 3; ++r) {
    alpha += b.m[3 * r + p] * b.m[3 * r + p];
    beta += b.m[3 * r + q] * b.m[3 * r + q];
    gamma += b.m[3 * r + p] * b.m[3 * r + q];
  }
  const Real tau = beta - alpha, rho = Real(2) * gamma;
  const Real d = tau + copysign(sqrt(tau * tau + rho * rho), tau);
  const Real len2 = d * d + rho * rho;
  const auto nonzero = len2 > Real(0);
  const Real inv_len = select(nonzero, Real(1) / sqrt(len2), Real(0));
  const Real c = select(nonzero, abs(d) * inv_len, Real(1));
  const Real s = select(d < Real(0), -rho, rho) * inv_len;
  for (int r = 0; r < 3; ++r) {
    const Real bp = b.m[3 * r + p], bq = b.m[3 * r + q];
    b.m[3 * r + p] = c * bp - s * bq;
    b.m[3 * r + q] = s * bp + c * bq;
    const Real vp = v.m[3 * r + p], vq = v.m[3 * r + q];
    v.m[3 * r + p] = c * vp - s * vq;
    v.m[3 * r + q] = s * vp + c * vq;
  }
}

// Puts the longer of columns p < q of b first: (b_p, b_q) <- (b_q, -b_p) in
// b and v alike, a rotation by 90 degrees, so B = A V and det V = +1 hold.
template <class Real>
DESCENT_HOST_DEVICE inline void order_columns(Mat3<Real>& b, Mat3<Real>& v, int p, int q) {
  Real np = 0, nq = 0;
  for (int r = 0; r < 3; ++r) {
    np += b.m[3 * r + p] * b.m[3 * r + p];
    nq += b.m[3 * r + q] * b.m[3 * r + q];
  }
  const auto keep = nq <= np;
  for (int r = 0; r < 3; ++r) {
    const Real bp = b.m[3 * r + p], bq = b.m[3 * r + q];
    b.m[3 * r + p] = select(keep, bp, bq);
    b.m[3 * r + q] = select(keep, bq, -bp);
    const Real vp = v.m[3 * r + p], vq = v.m[3 * r + q];
    v.m[3 * r + p] = select(keep, vp, vq);
    v.m[3 * r + q] = select(keep, vq, -vp);
  }
}

// Rotates rows p and q of r so that r(q, col) = 0 and r(p, col) = hypot >= 0,
// and accumulates u <- u G^T so that u r stays unchanged. Entries too small to
// square (both below ~1e-154 after scaling) are left alone: the identity.
template <class Real>
DESCENT_HOST_DEVICE inline void eliminate_below(Mat3<Real>& r, Mat3<Real>& u, int p, int q,
                                                int col) {
  const Real a = r.m[3 * p + col], b = r.m[3 * q + col];
  const Real h2 = a * a + b * b;
  const auto nonzero = h2 > Real(0);
  const Real inv_h = select(nonzero, Real(1) / sqrt(h2), Real(0));
  const Real c = select(nonzero, a * inv_h, Real(1));
  const Real s = b * inv_h;
  for (int k = 0; k < 3; ++k) {
    const Real rp = r.m[3 * p + k], rq = r.m[3 * q + k];
    r.m[3 * p + k] = c * rp + s * rq;
    r.m[3 * q + k] = c * rq - s * rp;
    const Real up = u.m[3 * k + p], uq = u.m[3 * k + q];
    u.m[3 * k + p] = c * up + s * uq;
    u.m[3 * k + q] = c * uq - s * up;
  }
}

}  // namespace svd3_detail

template <class Real>
DESCENT_HOST_DEVICE inline Svd3<Real> svd3(const Mat3<Real>& a) {
  // The largest |a_k|, NaN skipped (as fmax skips it).
  Real max_abs = 0;
  for (int k = 0; k < 9; ++k) {
    const Real entry = abs(a.m[k]);
    max_abs = select(entry > max_abs, entry, max_abs);
  }
  // max_abs = m 2^exponent, m in [0.5, 1); 0 for a = 0.
  const auto exponent = frexp_exponent(max_abs);
  const Real to_unit = ldexp(Real(1), -exponent);

  Mat3<Real> b;
  for (int k = 0; k < 9; ++k) b.m[k] = a.m[k] * to_unit;
  Mat3<Real> v{{1, 0, 0, 0, 1, 0, 0, 0, 1}};
  for (int sweep = 0; sweep < kSvd3Sweeps; ++sweep) {
    svd3_detail::orthogonalize_columns(b, v, 0, 1);
    svd3_detail::orthogonalize_columns(b, v, 0, 2);
    svd3_detail::orthogonalize_columns(b, v, 1, 2);
  }
  svd3_detail::order_columns(b, v, 0, 1);
  svd3_detail::order_columns(b, v, 0, 2);
  svd3_detail::order_columns(b, v, 1, 2);

  Mat3<Real> u{{1, 0, 0, 0, 1, 0, 0, 0, 1}};
  svd3_detail::eliminate_below(b, u, 0, 1, 0);
  svd3_detail::eliminate_below(b, u, 0, 2, 0);
  svd3_detail::eliminate_below(b, u, 1, 2, 1);

  Svd3<Real> result{u, {}, v};
  for (int k = 0; k < 3; ++k) result.sigma[k] = ldexp(b.m[4 * k], exponent);
  return result;
}

// Polar decomposition F = R S from the signed SVD: R = U V^T a rotation,
// S = V diag(sigma) V^T symmetric (indefinite when det F < 0).
template <class Real>
struct Polar {
  Mat3<Real> r;
  Mat3<Real> s;
};

template <class Real>
DESCENT_HOST_DEVICE inline Polar<Real> polar(const Mat3<Real>& f) {
  const Svd3<Real> d = svd3(f);
  Polar<Real> result;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      Real r = 0, s = 0;
      for (int k = 0; k < 3; ++k) {
        r += d.u.m[3 * i + k] * d.v.m[3 * j + k];
        s += d.v.m[3 * i + k] * d.sigma[k] * d.v.m[3 * j + k];
      }
      result.r.m[3 * i + j] = r;
      result.s.m[3 * i + j] = s;
    }
  }
  return result;
}

}  // namespace descent
