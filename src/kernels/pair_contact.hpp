#pragma once
// The terms of one contact pair between surface primitives (issue 21, step
// 3): its lagged friction, and its barrier: kappa b(d) for a vertex and a
// triangle, kappa m(e) b(d) for two edges, with d their distance
// (kernels/primitive_distance.hpp), b the barrier of the obstacles
// (kernels/obstacle_contact.hpp: active below dh, +inf at d = 0) and m the
// mollifier of nearly parallel edges. Host and
// device. Layout of x, the gradient and the Hessian: primitive_distance.hpp.
//
// With D = d^2: B(D) = kappa b(sqrt D), B' = kappa b'(d) / (2 d) (<= 0) and
// B'' = kappa (b''(d) / (4 d^2) - b'(d) / (4 d^3)), so
//   grad = B' grad D,   hess = B'' grad D grad D^T + B' hess D   (exact).
// The positive semi-definite part (psd), for a diagonal or a preconditioner,
// is kappa b''(d) grad d grad d^T = kappa b''(d) / (4 d^2) grad D grad D^T:
// the rest, kappa b'(d) hess d, is the distance's own curvature times the
// barrier's push (b' <= 0); it vanishes along the normal of a face, where the
// psd part is the exact Hessian. Edge pairs add the mollifier's terms to
// `exact` (m'' B grad e grad e^T + m' B hess e + m' (grad e grad B^T +
// grad B grad e^T)) and scale `psd` by m.
#include <cmath>

#include "kernels/obstacle_contact.hpp"
#include "kernels/primitive_distance.hpp"

namespace descent {

enum class PairKind : int { vertex_triangle = 0, edge_edge = 1 };
enum class PairHessian : int { none = 0, exact = 1, psd = 2 };

template <class Real>
struct PairTerms {
  Real energy = 0;
  Real distance = 0;
  Real grad[12] = {};
  Real hess[144] = {};  // row-major, when asked for
};

// The pair's distance^2 and its derivatives (primitive_distance.hpp).
template <class Real>
DESCENT_HOST_DEVICE inline PairDistance<Real> pair_distance(PairKind kind, const Real* x,
                                                            bool with_hessian) {
  return kind == PairKind::vertex_triangle ? point_triangle_distance(x, with_hessian)
                                           : edge_edge_distance(x, with_hessian);
}

// `eps`: the mollifier's threshold for edge pairs (edge_parallelism).
template <class Real>
DESCENT_HOST_DEVICE inline PairTerms<Real> pair_barrier(PairKind kind, const Real* x, Real kappa,
                                                        Real dh, Real eps, PairHessian hessian) {
  const bool exact = hessian == PairHessian::exact;
  const PairDistance<Real> dist = pair_distance(kind, x, exact);
  PairTerms<Real> out;
  const Real d = std::sqrt(dist.d2);
  out.distance = d;
  const BarrierValue<Real> b = barrier(d, dh);
  if (b.energy == Real(0) && b.first == Real(0)) return out;  // beyond dh
  if (!(d > Real(0))) {
    out.energy = Real(INFINITY);
    return out;
  }
  const Real energy = kappa * b.energy;
  const Real first = kappa * b.first / (Real(2) * d);
  const Real psd_second = kappa * b.second / (Real(4) * d * d);
  const Real second = psd_second - kappa * b.first / (Real(4) * d * d * d);
  Real m = 1;
  Parallelism<Real> par{};
  if (kind == PairKind::edge_edge) {
    par = edge_parallelism(x, eps, exact);
    m = par.m;
  }
  out.energy = m * energy;
  for (int a = 0; a < 12; ++a)
    out.grad[a] = m * first * dist.grad[a] + par.dm * energy * par.grad[a];
  if (hessian == PairHessian::none) return out;
  for (int a = 0; a < 12; ++a)
    for (int c = 0; c < 12; ++c) {
      Real h = m * (exact ? second : psd_second) * dist.grad[a] * dist.grad[c];
      if (exact) {
        h += m * first * dist.hess[12 * a + c];
        if (kind == PairKind::edge_edge && par.dm != Real(0))
          h += par.d2m * energy * par.grad[a] * par.grad[c] +
               par.dm * energy * par.hess[12 * a + c] +
               par.dm * first * (par.grad[a] * dist.grad[c] + dist.grad[a] * par.grad[c]);
      }
      out.hess[12 * a + c] = h;
    }
  return out;
}

// Lagged friction between a pair's two sides (IPC's, as for obstacles): at
// the step start x_t, the closest points' coefficients c (r = sum_k c_k x_k),
// the normal n = r / |r| and mu lambda, lambda = -kappa b'(d_t) the barrier's
// normal force. The slip is the closest points' relative move
// s = sum_k c_k (x_k - x_k^t); the term mu lambda f0(|(I - n n^T) s|) with
// f0 of obstacle friction (friction_on_slip). Its Hessian, c c^T times the
// slip's, is positive semi-definite; PairHessian::psd takes the slip's
// majorant (friction_on_slip) in its place.
template <class Real>
struct PairFrictionLag {
  Real mu_lambda = 0;  // 0: no friction (the pair was beyond dh at x_t)
  Real n[3] = {0, 0, 0};
  Real c[4] = {0, 0, 0, 0};
};

// The lag of a pair at step-start positions xt (12 coordinates), with its
// stiffness, dh and the Coulomb coefficient mu.
template <class Real>
DESCENT_HOST_DEVICE inline PairFrictionLag<Real> pair_friction_lag(PairKind kind, const Real* xt,
                                                                   Real kappa, Real dh, Real mu) {
  PairFrictionLag<Real> lag;
  if (!(mu > Real(0))) return lag;
  const PairDistance<Real> dist = pair_distance(kind, xt, false);
  const Real d = std::sqrt(dist.d2);
  if (!(d > Real(0)) || d >= dh) return lag;
  lag.mu_lambda = mu * -kappa * barrier(d, dh).first;
  Real r[3] = {0, 0, 0};
  for (int k = 0; k < 4; ++k) {
    lag.c[k] = dist.coefficient[k];
    for (int i = 0; i < 3; ++i) r[i] += lag.c[k] * xt[3 * k + i];
  }
  for (int i = 0; i < 3; ++i) lag.n[i] = r[i] / d;
  return lag;
}

// Adds the pair's lagged friction at x (step start xt) to `out`, its
// Hessian too unless `hessian` is none.
template <class Real>
DESCENT_HOST_DEVICE inline void add_pair_friction(const PairFrictionLag<Real>& lag, Real eps_h,
                                                  const Real* x, const Real* xt,
                                                  PairHessian hessian, PairTerms<Real>& out) {
  if (!(lag.mu_lambda > Real(0))) return;
  Real s[3] = {0, 0, 0};
  for (int k = 0; k < 4; ++k)
    for (int i = 0; i < 3; ++i) s[i] += lag.c[k] * (x[3 * k + i] - xt[3 * k + i]);
  const ContactTerms<Real> f =
      friction_on_slip(lag.mu_lambda, lag.n, eps_h, s, hessian == PairHessian::exact);
  out.energy += f.energy;
  for (int k = 0; k < 4; ++k)
    for (int i = 0; i < 3; ++i) out.grad[3 * k + i] += lag.c[k] * f.grad[i];
  if (hessian == PairHessian::none) return;
  for (int k = 0; k < 4; ++k)
    for (int l = 0; l < 4; ++l)
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
          out.hess[12 * (3 * k + i) + 3 * l + j] += lag.c[k] * lag.c[l] * f.hess[3 * i + j];
}

}  // namespace descent
