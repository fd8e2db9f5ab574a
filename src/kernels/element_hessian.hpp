#pragma once
// The full 12x12 Hessian of one element's V Psi(F) (for Newton and for
// tests), and its positive semi-definite projection.
// Layout: h[(3a+i)*12 + 3b+j] = d2(V Psi)/dx_a,i dx_b,j for corners a, b and
// axes i, j. Since dF = sum_a dx_a b_a^T (tet.hpp), with the model's
//   dPdF[(3i+m)*9 + 3j+n] = dP_im/dF_jn,
//   h[(3a+i)*12 + 3b+j] = V sum_{m,n} dPdF[(3i+m)*9 + 3j+n] b_a,m b_b,n,
// i.e. H = V B^T dPdF B with B the 9x12 map from corner moves to dF.
#include <cmath>

#include "kernels/element.hpp"

namespace descent {

// H = V B^T dPdF B, contracted in two passes (9x12 then 12x12).
template <class Real>
DESCENT_HOST_DEVICE inline void contract_stress_derivative(const Real dpdf[81],
                                                           const TetRest<Real>& rest, Real h[144]) {
  Real b[4][3];
  for (int a = 0; a < 4; ++a) {
    const Vec3<Real> ba = corner_operator(rest.dm_inv, a);
    b[a][0] = ba.x;
    b[a][1] = ba.y;
    b[a][2] = ba.z;
  }
  // half[(3i+m)][3b+j] = sum_n dPdF[(3i+m)*9 + 3j+n] b_b,n
  Real half[9][12];
  for (int r = 0; r < 9; ++r)
    for (int c = 0; c < 4; ++c)
      for (int j = 0; j < 3; ++j)
        half[r][3 * c + j] = dpdf[9 * r + 3 * j] * b[c][0] + dpdf[9 * r + 3 * j + 1] * b[c][1] +
                             dpdf[9 * r + 3 * j + 2] * b[c][2];
  for (int a = 0; a < 4; ++a)
    for (int i = 0; i < 3; ++i)
      for (int col = 0; col < 12; ++col)
        h[(3 * a + i) * 12 + col] =
            rest.volume * (b[a][0] * half[3 * i][col] + b[a][1] * half[3 * i + 1][col] +
                           b[a][2] * half[3 * i + 2][col]);
}

template <class Real, class Model>
DESCENT_HOST_DEVICE inline void element_hessian(const Model& model, const TetRest<Real>& rest,
                                                const TetCorners<Real>& c, Real h[144]) {
  const Mat3<Real> f = deformation_gradient(c.x[0], c.x[1], c.x[2], c.x[3], rest.dm_inv);
  Real dpdf[81];
  model.stress_derivative(f, dpdf);
  contract_stress_derivative(dpdf, rest, h);
}

// Replaces the symmetric n x n matrix m (row-major, n <= 12) by its nearest
// positive semi-definite matrix: eigenvalues below 0 are set to 0. Cyclic
// Jacobi eigen-decomposition, at most 20 sweeps, stopping once the
// off-diagonal mass is below round-off (typically 6-9 sweeps for n = 12).
// A matrix with no negative eigenvalue is left bit-for-bit unchanged.
// Whether the symmetric n x n matrix m (row-major, n <= 12) is positive
// definite: a Cholesky factorisation meets only positive pivots.
template <class Real>
DESCENT_HOST_DEVICE inline bool positive_definite(const Real* m, int n) {
  constexpr int kMaxN = 12;
  Real l[kMaxN * kMaxN];
  for (int j = 0; j < n; ++j) {
    Real s = m[n * j + j];
    for (int k = 0; k < j; ++k) s -= l[n * j + k] * l[n * j + k];
    if (!(s > Real(0))) return false;
    const Real ljj = std::sqrt(s);
    l[n * j + j] = ljj;
    for (int i = j + 1; i < n; ++i) {
      Real t = m[n * i + j];
      for (int k = 0; k < j; ++k) t -= l[n * i + k] * l[n * j + k];
      l[n * i + j] = t / ljj;
    }
  }
  return true;
}

template <class Real>
DESCENT_HOST_DEVICE inline void project_psd(Real* m, int n) {
  constexpr int kMaxN = 12;
  // The common case costs one Cholesky, not the eigen-decomposition: a
  // positive definite matrix stays as it is.
  if (positive_definite(m, n)) return;
  constexpr int kMaxSweeps = 20;
  // Squared relative off-diagonal mass at which the diagonal is the spectrum.
  const Real tolerance = sizeof(Real) <= 4 ? Real(1e-14) : Real(1e-32);
  Real a[kMaxN * kMaxN];
  Real v[kMaxN * kMaxN];  // columns: eigenvectors
  for (int k = 0; k < n * n; ++k) a[k] = m[k];
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) v[n * i + j] = i == j ? Real(1) : Real(0);

  for (int sweep = 0; sweep < kMaxSweeps; ++sweep) {
    Real off = 0, total = 0;
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        const Real sq = a[n * i + j] * a[n * i + j];
        total += sq;
        if (i != j) off += sq;
      }
    if (off <= tolerance * total) break;
    for (int p = 0; p < n - 1; ++p) {
      for (int q = p + 1; q < n; ++q) {
        const Real apq = a[n * p + q];
        if (apq == Real(0)) continue;
        // A <- J^T A J with J the rotation in the (p, q) plane that zeroes
        // a_pq: t = tan of its angle, the smaller root of t^2 + 2 theta t - 1.
        const Real theta = (a[n * q + q] - a[n * p + p]) / (Real(2) * apq);
        const Real t =
            std::copysign(Real(1), theta) / (std::abs(theta) + std::sqrt(theta * theta + Real(1)));
        const Real c = Real(1) / std::sqrt(t * t + Real(1));
        const Real s = t * c;
        for (int k = 0; k < n; ++k) {  // columns p, q
          const Real akp = a[n * k + p], akq = a[n * k + q];
          a[n * k + p] = c * akp - s * akq;
          a[n * k + q] = s * akp + c * akq;
          const Real vkp = v[n * k + p], vkq = v[n * k + q];
          v[n * k + p] = c * vkp - s * vkq;
          v[n * k + q] = s * vkp + c * vkq;
        }
        for (int k = 0; k < n; ++k) {  // rows p, q
          const Real apk = a[n * p + k], aqk = a[n * q + k];
          a[n * p + k] = c * apk - s * aqk;
          a[n * q + k] = s * apk + c * aqk;
        }
        a[n * p + q] = 0;
        a[n * q + p] = 0;
      }
    }
  }

  bool has_negative = false;
  for (int k = 0; k < n; ++k) has_negative = has_negative || a[n * k + k] < Real(0);
  if (!has_negative) return;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      Real sum = 0;
      for (int k = 0; k < n; ++k) {
        const Real eigenvalue = a[n * k + k] > Real(0) ? a[n * k + k] : Real(0);
        sum += v[n * i + k] * eigenvalue * v[n * j + k];
      }
      m[n * i + j] = sum;
    }
}

// The element Hessian with dPdF projected to PSD first (9x9 instead of
// 12x12): V B^T M B is PSD whenever M is, so the result is PSD, and it equals
// element_hessian wherever dPdF already is. It is not the nearest PSD matrix
// to the 12x12 Hessian (that projection can keep curvature the 9x9 one
// removes), the usual trade for Newton's method on elastic bodies.
// V B^T dPdF B with dPdF (overwritten) projected to PSD first.
template <class Real>
DESCENT_HOST_DEVICE inline void projected_hessian(Real dpdf[81], const TetRest<Real>& rest,
                                                  Real h[144]) {
  project_psd(dpdf, 9);
  contract_stress_derivative(dpdf, rest, h);
}

template <class Real, class Model>
DESCENT_HOST_DEVICE inline void element_hessian_psd(const Model& model, const TetRest<Real>& rest,
                                                    const TetCorners<Real>& c, Real h[144]) {
  const Mat3<Real> f = deformation_gradient(c.x[0], c.x[1], c.x[2], c.x[3], rest.dm_inv);
  Real dpdf[81];
  model.stress_derivative(f, dpdf);
  projected_hessian(dpdf, rest, h);
}

}  // namespace descent
