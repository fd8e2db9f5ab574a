#pragma once
// Corotated linear elements of paper 2 (Dahl & Bargteil 2019, Eqs. 1-8), the
// element physics of solver.method = linear_cg:
//   F = Q F~ (polar, by 2x2 Jacobi sweeps, §3.3),  eps = sym(F~) - I  (Eq. 4),
//   sigma = lambda tr(eps) I + 2 mu eps  (Eq. 5),  P = Q sigma,
// gradient of the element energy on corner a: V P b_a (tet.hpp), i.e. minus
// the force of Eq. 6 (V sigma b_a = sigma n_a / 3 with the area normals n_a).
// The stiffness K of Eq. 8 is the derivative with Q held fixed:
//   dF = sum_a p_a b_a^T,  deps = sym(Q^T dF),
//   (K p)_a = V Q (lambda tr(deps) I + 2 mu deps) b_a,
// symmetric positive semidefinite (the Hessian of V (mu |deps|^2 +
// lambda/2 tr(deps)^2)), so PCG is well posed. With the exact polar factor,
// P equals the nonlinear corotated model's stress (kernels/corotated.hpp):
// both are R sigma(S - I).
//
// Layout: Q is a Mat3, row-major, 9 reals per tet.
#include <cmath>

#include "kernels/corotated.hpp"
#include "kernels/element.hpp"
#include "kernels/real_math.hpp"
#include "kernels/tet.hpp"

namespace descent {

// |A - A^T| relative to |A| below which the polar sweeps stop early.
template <class Real>
DESCENT_HOST_DEVICE inline Real polar_symmetry_tolerance() {
  return Real(64) * (sizeof(Real) == sizeof(float) ? Real(1.2e-7) : Real(2.3e-16));
}

// Polar decomposition F = Q S, S symmetric, by cyclic 2x2 Jacobi sweeps: each
// plane rotation G in the (i, j) plane makes S_ij = S_ji with S <- G^T S,
// Q <- Q G (a rotation, so det Q = 1 even for det F < 0; S then carries the
// sign). Stops after `max_sweeps` sweeps of the three planes or once S is
// symmetric to round-off. Returns Q; `sweeps_done` the sweeps made.
template <class Real>
DESCENT_HOST_DEVICE inline Mat3<Real> polar_rotation(const Mat3<Real>& f, int max_sweeps,
                                                     int* sweeps_done = nullptr) {
  Mat3<Real> s = f;
  Mat3<Real> q = {{1, 0, 0, 0, 1, 0, 0, 0, 1}};
  const Real scale = ddot(f, f);
  const Real tolerance = polar_symmetry_tolerance<Real>();
  const int planes[3][2] = {{0, 1}, {0, 2}, {1, 2}};
  int sweep = 0;
  for (; sweep < max_sweeps; ++sweep) {
    Real asymmetry = 0;
    for (int k = 0; k < 3; ++k) {
      const int i = planes[k][0], j = planes[k][1];
      const Real d = s.m[3 * i + j] - s.m[3 * j + i];
      asymmetry += d * d;
    }
    if (asymmetry <= tolerance * tolerance * scale) break;
    for (int k = 0; k < 3; ++k) {
      const int i = planes[k][0], j = planes[k][1];
      // G = [[c, -s], [s, c]] in the (i, j) plane: (G^T S)_ij - (G^T S)_ji =
      // s a - c b with a = S_ii + S_jj, b = S_ji - S_ij; c = a/r, s = b/r
      // zeroes it and leaves the 2x2 trace r >= 0.
      const Real a = s.m[3 * i + i] + s.m[3 * j + j];
      const Real b = s.m[3 * j + i] - s.m[3 * i + j];
      const Real r = sqrt(a * a + b * b);
      if (r == Real(0)) continue;
      const Real c = a / r, sn = b / r;
      for (int col = 0; col < 3; ++col) {  // rows i, j of S: S <- G^T S
        const Real si = s.m[3 * i + col], sj = s.m[3 * j + col];
        s.m[3 * i + col] = c * si + sn * sj;
        s.m[3 * j + col] = -sn * si + c * sj;
      }
      for (int row_index = 0; row_index < 3; ++row_index) {  // columns i, j of Q: Q <- Q G
        const Real qi = q.m[3 * row_index + i], qj = q.m[3 * row_index + j];
        q.m[3 * row_index + i] = c * qi + sn * qj;
        q.m[3 * row_index + j] = -sn * qi + c * qj;
      }
    }
  }
  if (sweeps_done) *sweeps_done = sweep;
  return q;
}

// sigma(sym(Q^T A)) = lambda tr I + 2 mu sym(Q^T A), premultiplied by Q.
template <class Real>
DESCENT_HOST_DEVICE inline Mat3<Real> corotated_linear_stress(const Corotated<Real>& model,
                                                              const Mat3<Real>& q,
                                                              const Mat3<Real>& a,
                                                              bool subtract_identity) {
  Mat3<Real> qta;  // Q^T A
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      qta.m[3 * i + j] = q.m[i] * a.m[j] + q.m[3 + i] * a.m[3 + j] + q.m[6 + i] * a.m[6 + j];
  Mat3<Real> strain;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      strain.m[3 * i + j] = Real(0.5) * (qta.m[3 * i + j] + qta.m[3 * j + i]) -
                            (subtract_identity && i == j ? Real(1) : Real(0));
  const Real trace = strain.m[0] + strain.m[4] + strain.m[8];
  Mat3<Real> sigma;
  for (int k = 0; k < 9; ++k) sigma.m[k] = Real(2) * model.mu * strain.m[k];
  for (int i = 0; i < 3; ++i) sigma.m[4 * i] += model.lambda * trace;
  return mul(q, sigma);
}

// Element energy V (mu |eps|^2 + lambda/2 tr(eps)^2) with Q fixed.
template <class Real>
DESCENT_HOST_DEVICE inline Real corotated_linear_energy(const Corotated<Real>& model,
                                                        const TetRest<Real>& rest,
                                                        const Mat3<Real>& q,
                                                        const TetCorners<Real>& x) {
  const Mat3<Real> f = deformation_gradient(x.x[0], x.x[1], x.x[2], x.x[3], rest.dm_inv);
  Real e[9];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      const Real qf_ij = q.m[i] * f.m[j] + q.m[3 + i] * f.m[3 + j] + q.m[6 + i] * f.m[6 + j];
      const Real qf_ji = q.m[j] * f.m[i] + q.m[3 + j] * f.m[3 + i] + q.m[6 + j] * f.m[6 + i];
      e[3 * i + j] = Real(0.5) * (qf_ij + qf_ji) - (i == j ? Real(1) : Real(0));
    }
  Real norm2 = 0;
  for (int k = 0; k < 9; ++k) norm2 += e[k] * e[k];
  const Real trace = e[0] + e[4] + e[8];
  return rest.volume * (model.mu * norm2 + Real(0.5) * model.lambda * trace * trace);
}

// Gradient V P b_a of the element energy at corners x (Q fixed).
template <class Real>
DESCENT_HOST_DEVICE inline void corotated_linear_gradient(const Corotated<Real>& model,
                                                          const TetRest<Real>& rest,
                                                          const Mat3<Real>& q,
                                                          const TetCorners<Real>& x,
                                                          Vec3<Real> out[4]) {
  const Mat3<Real> f = deformation_gradient(x.x[0], x.x[1], x.x[2], x.x[3], rest.dm_inv);
  const Mat3<Real> p = corotated_linear_stress(model, q, f, true);
  for (int a = 0; a < 4; ++a) {
    const Vec3<Real> v = mul(p, corner_operator(rest.dm_inv, a));
    out[a] = {rest.volume * v.x, rest.volume * v.y, rest.volume * v.z};
  }
}

// (K p)_a for corner displacements p (Q fixed).
template <class Real>
DESCENT_HOST_DEVICE inline void corotated_linear_product(const Corotated<Real>& model,
                                                         const TetRest<Real>& rest,
                                                         const Mat3<Real>& q, const Vec3<Real> p[4],
                                                         Vec3<Real> out[4]) {
  Vec3<Real> b[4];
  for (int a = 0; a < 4; ++a) b[a] = corner_operator(rest.dm_inv, a);
  Mat3<Real> df = {{0, 0, 0, 0, 0, 0, 0, 0, 0}};
  for (int a = 0; a < 4; ++a) {
    const Real pa[3] = {p[a].x, p[a].y, p[a].z};
    const Real ba[3] = {b[a].x, b[a].y, b[a].z};
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) df.m[3 * i + j] += pa[i] * ba[j];
  }
  const Mat3<Real> dp = corotated_linear_stress(model, q, df, false);
  for (int a = 0; a < 4; ++a) {
    const Vec3<Real> v = mul(dp, b[a]);
    out[a] = {rest.volume * v.x, rest.volume * v.y, rest.volume * v.z};
  }
}

// Diagonal of K per corner and axis: along dF = e_i b^T, deps = sym(r b^T)
// with r = Q^T e_i (row i of Q, unit), so
//   K_(a i)(a i) = V (mu (|b|^2 + (r.b)^2) + lambda (r.b)^2).
template <class Real>
DESCENT_HOST_DEVICE inline void corotated_linear_diagonal(const Corotated<Real>& model,
                                                          const TetRest<Real>& rest,
                                                          const Mat3<Real>& q, Vec3<Real> out[4]) {
  for (int a = 0; a < 4; ++a) {
    const Vec3<Real> b = corner_operator(rest.dm_inv, a);
    const Real bb = dot(b, b);
    Real d[3];
    for (int i = 0; i < 3; ++i) {
      const Real rb = dot(row(q, i), b);
      d[i] = rest.volume * (model.mu * (bb + rb * rb) + model.lambda * rb * rb);
    }
    out[a] = {d[0], d[1], d[2]};
  }
}

}  // namespace descent
