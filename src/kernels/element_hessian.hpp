#pragma once
// The full 12x12 Hessian of one element's V Psi(F) (for Newton and for
// tests), and its positive semi-definite projection.
// Layout: h[(3a+i)*12 + 3b+j] = d2(V Psi)/dx_a,i dx_b,j for corners a, b and
// axes i, j. Since dF = sum_a dx_a b_a^T (tet.hpp), with the model's
//   dPdF[(3i+m)*9 + 3j+n] = dP_im/dF_jn,
//   h[(3a+i)*12 + 3b+j] = V sum_{m,n} dPdF[(3i+m)*9 + 3j+n] b_a,m b_b,n,
// i.e. H = V B^T dPdF B with B the 9x12 map from corner moves to dF.
#include <cmath>
#include <limits>

#include "kernels/element.hpp"
#include "kernels/real_math.hpp"
#include "kernels/svd3.hpp"

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

// Whether the symmetric n x n matrix m + shift I (m row-major, n <= 12) is
// positive definite: a Cholesky factorisation meets only positive pivots.
// On lanes, per lane: it stops once every lane has met a pivot <= 0, and a
// lane that met one runs on with NaN (its answer is already false).
template <class Real>
DESCENT_HOST_DEVICE inline MaskOf<Real> positive_definite(const Real* m, int n, Real shift = 0) {
  constexpr int kMaxN = 12;
  Real l[kMaxN * kMaxN];
  MaskOf<Real> definite = Real(0) < Real(1);
  for (int j = 0; j < n; ++j) {
    Real s = m[n * j + j] + shift;
    for (int k = 0; k < j; ++k) s -= l[n * j + k] * l[n * j + k];
    definite = definite & (s > Real(0));
    if (!any_lane(definite)) return definite;
    const Real ljj = sqrt(s);
    l[n * j + j] = ljj;
    for (int i = j + 1; i < n; ++i) {
      Real t = m[n * i + j];
      for (int k = 0; k < j; ++k) t -= l[n * i + k] * l[n * j + k];
      l[n * i + j] = t / ljj;
    }
  }
  return definite;
}

// Replaces the symmetric n x n matrix m (row-major, n <= 12) by its nearest
// positive semi-definite matrix: eigenvalues below 0 are set to 0. Cyclic
// Jacobi eigen-decomposition, at most 20 sweeps, stopping once the
// off-diagonal mass is below round-off (typically 6-9 sweeps for n = 12).
// A matrix with no negative eigenvalue is left bit-for-bit unchanged. On
// lanes each lane stops where it would alone (its rotations masked off), so
// each is bitwise its own projection.
template <class Real>
DESCENT_HOST_DEVICE inline void project_psd(Real* m, int n) {
  constexpr int kMaxN = 12;
  // The common case costs one Cholesky, not the eigen-decomposition: a
  // positive definite matrix stays as it is.
  const MaskOf<Real> definite = positive_definite(m, n);
  if (all_lanes(definite)) return;
  constexpr int kMaxSweeps = 20;
  // Squared relative off-diagonal mass at which the diagonal is the spectrum.
  const Real tolerance = sizeof(typename ScalarOf<Real>::type) <= 4 ? Real(1e-14) : Real(1e-32);
  Real a[kMaxN * kMaxN];
  Real v[kMaxN * kMaxN];  // columns: eigenvectors
  for (int k = 0; k < n * n; ++k) a[k] = m[k];
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) v[n * i + j] = i == j ? Real(1) : Real(0);

  MaskOf<Real> done = definite;
  for (int sweep = 0; sweep < kMaxSweeps; ++sweep) {
    Real off = 0, total = 0;
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        const Real sq = a[n * i + j] * a[n * i + j];
        total += sq;
        if (i != j) off += sq;
      }
    done = done | (off <= tolerance * total);
    if (all_lanes(done)) break;
    for (int p = 0; p < n - 1; ++p) {
      for (int q = p + 1; q < n; ++q) {
        const Real apq = a[n * p + q];
        const MaskOf<Real> rotate = (!done) & (apq != Real(0));
        if (!any_lane(rotate)) continue;
        // A <- J^T A J with J the rotation in the (p, q) plane that zeroes
        // a_pq: t = tan of its angle, the smaller root of t^2 + 2 theta t - 1.
        const Real theta = (a[n * q + q] - a[n * p + p]) / (Real(2) * apq);
        const Real t = copysign(Real(1), theta) / (abs(theta) + sqrt(theta * theta + Real(1)));
        const Real c = Real(1) / sqrt(t * t + Real(1));
        const Real s = t * c;
        for (int k = 0; k < n; ++k) {  // columns p, q
          const Real akp = a[n * k + p], akq = a[n * k + q];
          a[n * k + p] = select(rotate, c * akp - s * akq, akp);
          a[n * k + q] = select(rotate, s * akp + c * akq, akq);
          const Real vkp = v[n * k + p], vkq = v[n * k + q];
          v[n * k + p] = select(rotate, c * vkp - s * vkq, vkp);
          v[n * k + q] = select(rotate, s * vkp + c * vkq, vkq);
        }
        for (int k = 0; k < n; ++k) {  // rows p, q
          const Real apk = a[n * p + k], aqk = a[n * q + k];
          a[n * p + k] = select(rotate, c * apk - s * aqk, apk);
          a[n * q + k] = select(rotate, s * apk + c * aqk, aqk);
        }
        a[n * p + q] = select(rotate, Real(0), a[n * p + q]);
        a[n * q + p] = select(rotate, Real(0), a[n * q + p]);
      }
    }
  }

  MaskOf<Real> has_negative = Real(1) < Real(0);
  for (int k = 0; k < n; ++k) has_negative = has_negative | (a[n * k + k] < Real(0));
  const MaskOf<Real> project = has_negative & (!definite);
  if (!any_lane(project)) return;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      Real sum = 0;
      for (int k = 0; k < n; ++k) {
        const Real eigenvalue = select(a[n * k + k] > Real(0), a[n * k + k], Real(0));
        sum += v[n * i + k] * eigenvalue * v[n * j + k];
      }
      m[n * i + j] = select(project, sum, m[n * i + j]);
    }
}

// The element Hessian with dPdF projected to PSD first (9x9 instead of
// 12x12): V B^T M B is PSD whenever M is, so the result is PSD, and it equals
// element_hessian wherever dPdF already is. It is not the nearest PSD matrix
// to the 12x12 Hessian (that projection can keep curvature the 9x9 one
// removes), the usual trade for Newton's method on elastic bodies.
// The symmetric 2x2 matrix [[p, q], [q, r]] with its negative eigenvalue
// (if any) set to 0: lambda+ times the projector (A - lambda- I) /
// (lambda+ - lambda-) onto its top eigenvector.
template <class Real>
DESCENT_HOST_DEVICE inline void project_psd_2x2(Real& p, Real& q, Real& r) {
  const Real mean = Real(0.5) * (p + r), half = Real(0.5) * (p - r);
  const Real radius = sqrt(half * half + q * q);
  const Real high = mean + radius, low = mean - radius;
  const MaskOf<Real> keep = low >= Real(0), vanish = high <= Real(0);
  const Real scale = high / (high - low);
  p = select(keep, p, select(vanish, Real(0), scale * (p - low)));
  q = select(keep, q, select(vanish, Real(0), scale * q));
  r = select(keep, r, select(vanish, Real(0), scale * (r - low)));
}

// dP/dF (layout above) of an isotropic energy density at F, projected to
// PSD. In the frame of F's signed SVD, F = U diag(sigma) V^T, with dF =
// U dF^ V^T, the dP/dF of an isotropic energy is block diagonal (Teran et
// al. 2005, Smith et al. 2019): a 3x3 block on the stretches dF^_00,
// dF^_11, dF^_22 and 2x2 blocks on the pairs (01, 10), (02, 20), (12, 21).
// Each block loses its negative eigenvalues there and the result is rotated
// back: project_psd's result for these matrices (the eigen-decomposition of
// a block-diagonal matrix is its blocks'), at a tenth of its cost; what lies
// outside the blocks, round-off for an isotropic model, is dropped. All the
// models of src/kernels are isotropic, conversion's blend too.
template <class Real>
DESCENT_HOST_DEVICE inline void project_isotropic_psd(const Mat3<Real>& f, Real dpdf[81]) {
  // The common case costs one Cholesky: a dP/dF with no eigenvalue below
  // -64 machine epsilons of its largest diagonal entry (the round-off of
  // its exact zeros, the rotations at rest) stays as it is. On the hanging
  // helix most elements take this path.
  // On lanes, a lane that takes it keeps its dP/dF (the select at the end).
  Real scale = 0;
  for (int i = 0; i < 9; ++i) {
    const Real entry = abs(dpdf[10 * i]);
    scale = select(scale < entry, entry, scale);
  }
  using Scalar = typename ScalarOf<Real>::type;
  const MaskOf<Real> definite =
      positive_definite(dpdf, 9, Real(64 * std::numeric_limits<Scalar>::epsilon()) * scale);
  if (all_lanes(definite)) return;
  const Svd3<Real> s = svd3(f);
  // r[(3j + n) * 9 + 3a + b] = U_ja V_nb: dF = R dF^ as 9-vectors.
  Real r[81];
  for (int j = 0; j < 3; ++j)
    for (int n = 0; n < 3; ++n)
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) r[(3 * j + n) * 9 + 3 * a + b] = s.u(j, a) * s.v(n, b);
  Real mr[81];  // dPdF R
  for (int p = 0; p < 9; ++p)
    for (int q = 0; q < 9; ++q) {
      Real sum = 0;
      for (int k = 0; k < 9; ++k) sum += dpdf[9 * p + k] * r[9 * k + q];
      mr[9 * p + q] = sum;
    }
  // Entry (p, q) of the rotated matrix R^T dPdF R.
  auto rotated = [&](int p, int q) {
    Real sum = 0;
    for (int k = 0; k < 9; ++k) sum += r[9 * k + p] * mr[9 * k + q];
    return sum;
  };
  constexpr int kStretch[3] = {0, 4, 8};
  constexpr int kPair[3][2] = {{1, 3}, {2, 6}, {5, 7}};
  Real stretch[9];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      stretch[3 * i + j] =
          Real(0.5) * (rotated(kStretch[i], kStretch[j]) + rotated(kStretch[j], kStretch[i]));
  project_psd(stretch, 3);
  Real blocks[81] = {};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) blocks[9 * kStretch[i] + kStretch[j]] = stretch[3 * i + j];
  for (const auto& pair : kPair) {
    const int p = pair[0], q = pair[1];
    Real a = rotated(p, p), b = Real(0.5) * (rotated(p, q) + rotated(q, p)), c = rotated(q, q);
    project_psd_2x2(a, b, c);
    blocks[9 * p + p] = a;
    blocks[9 * p + q] = blocks[9 * q + p] = b;
    blocks[9 * q + q] = c;
  }
  // dPdF = R blocks R^T; blocks has at most 3 entries per column.
  Real rb[81];
  for (int p = 0; p < 9; ++p)
    for (int q = 0; q < 9; ++q) {
      Real sum = 0;
      for (int k = 0; k < 9; ++k)
        sum = select(blocks[9 * k + q] != Real(0), sum + r[9 * p + k] * blocks[9 * k + q], sum);
      rb[9 * p + q] = sum;
    }
  for (int p = 0; p < 9; ++p)
    for (int q = 0; q < 9; ++q) {
      Real sum = 0;
      for (int k = 0; k < 9; ++k) sum += rb[9 * p + k] * r[9 * q + k];
      dpdf[9 * p + q] = select(definite, dpdf[9 * p + q], sum);
    }
}

template <class Real, class Model>
DESCENT_HOST_DEVICE inline void element_hessian_psd(const Model& model, const TetRest<Real>& rest,
                                                    const TetCorners<Real>& c, Real h[144]) {
  const Mat3<Real> f = deformation_gradient(c.x[0], c.x[1], c.x[2], c.x[3], rest.dm_inv);
  Real dpdf[81];
  model.stress_derivative(f, dpdf);
  project_isotropic_psd(f, dpdf);
  contract_stress_derivative(dpdf, rest, h);
}

}  // namespace descent
