#pragma once
// Distances between surface primitives for contact between bodies (issue 21,
// step 3): a vertex and a triangle, two edges. Host and device.
//
// Layout: a pair's 12 coordinates x = [x0 | x1 | x2 | x3], xyz each:
//   vertex-triangle: (p, a, b, c);  edge-edge: (p0, p1, q0, q1).
//
// Both distances are d^2 = |r|^2 at the closest points, r = sum_k C_k x_k,
// with coefficients C = C0 + sum_j w_j C_j affine in the closest points'
// free parameters w (barycentric u, v on the triangle; s, t on the edges),
// each either strictly inside its range (free) or held at a bound by the
// closest-point search. Because w minimises |r|^2, the envelope theorem
// gives the exact derivatives from the free parameters alone:
//   grad d^2 = 2 (C^T (x) I) r,
//   hess d^2 = 2 (C C^T) (x) I - F G^-1 F^T,
// with G_jl = 2 e_j.e_l, e_j = sum_k C_jk x_k, and column j of F
// (point k) = 2 C_jk r + 2 C_k e_j. Within each region (face, edge, vertex
// of the triangle; interior or clamped segment parameters) they are those
// of a smooth function; d^2 is C1 across regions.
#include <cmath>

#include "kernels/host_device.hpp"

namespace descent {

template <class Real>
struct PairDistance {
  Real d2;
  Real coefficient[4];  // C at the closest points: r = sum_k C_k x_k
  Real grad[12];
  Real hess[144];  // row-major 12 x 12; filled when asked for
};

namespace primitive_detail {

template <class Real>
DESCENT_HOST_DEVICE inline Real dot3(const Real* a, const Real* b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

// d^2 and its derivatives for coefficients C = c0 + sum_j w[j] cj[j] over
// `free` (0..2) free parameters (see the header comment).
template <class Real>
DESCENT_HOST_DEVICE inline void closest_pair(const Real* x, const Real* c0, const Real (*cj)[4],
                                             const Real* w, int free, bool with_hessian,
                                             PairDistance<Real>& out) {
  Real c[4];
  for (int k = 0; k < 4; ++k) {
    c[k] = c0[k];
    for (int j = 0; j < free; ++j) c[k] += w[j] * cj[j][k];
  }
  Real r[3] = {0, 0, 0}, e[2][3] = {{0, 0, 0}, {0, 0, 0}};
  for (int k = 0; k < 4; ++k)
    for (int i = 0; i < 3; ++i) {
      r[i] += c[k] * x[3 * k + i];
      for (int j = 0; j < free; ++j) e[j][i] += cj[j][k] * x[3 * k + i];
    }
  out.d2 = dot3(r, r);
  for (int k = 0; k < 4; ++k) out.coefficient[k] = c[k];
  for (int k = 0; k < 4; ++k)
    for (int i = 0; i < 3; ++i) out.grad[3 * k + i] = Real(2) * c[k] * r[i];
  if (!with_hessian) return;
  for (int a = 0; a < 12; ++a)
    for (int b = 0; b < 12; ++b)
      out.hess[12 * a + b] = a % 3 == b % 3 ? Real(2) * c[a / 3] * c[b / 3] : Real(0);
  if (free == 0) return;
  // G and its inverse (1x1 or 2x2).
  Real g[2][2], gi[2][2];
  for (int j = 0; j < free; ++j)
    for (int l = 0; l < free; ++l) g[j][l] = Real(2) * dot3(e[j], e[l]);
  if (free == 1) {
    gi[0][0] = Real(1) / g[0][0];
  } else {
    const Real det = g[0][0] * g[1][1] - g[0][1] * g[1][0];
    gi[0][0] = g[1][1] / det;
    gi[1][1] = g[0][0] / det;
    gi[0][1] = -g[0][1] / det;
    gi[1][0] = -g[1][0] / det;
  }
  Real f[12][2];
  for (int k = 0; k < 4; ++k)
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < free; ++j)
        f[3 * k + i][j] = Real(2) * cj[j][k] * r[i] + Real(2) * c[k] * e[j][i];
  for (int a = 0; a < 12; ++a)
    for (int b = 0; b < 12; ++b) {
      Real s = 0;
      for (int j = 0; j < free; ++j)
        for (int l = 0; l < free; ++l) s += f[a][j] * gi[j][l] * f[b][l];
      out.hess[12 * a + b] -= s;
    }
}

template <class Real>
DESCENT_HOST_DEVICE inline Real clamp01(Real v) {
  return v < Real(0) ? Real(0) : (v > Real(1) ? Real(1) : v);
}

}  // namespace primitive_detail

// Vertex p = x[0..3) and triangle (a, b, c) = x[3..12): the closest point's
// region by Ericson's search (Real-Time Collision Detection, 5.1.5), then
// the region's free parameters.
template <class Real>
DESCENT_HOST_DEVICE inline PairDistance<Real> point_triangle_distance(const Real* x,
                                                                      bool with_hessian) {
  using primitive_detail::dot3;
  const Real *p = x, *a = x + 3, *b = x + 6, *c = x + 9;
  Real ab[3], ac[3], ap[3], bp[3], cp[3];
  for (int i = 0; i < 3; ++i) {
    ab[i] = b[i] - a[i];
    ac[i] = c[i] - a[i];
    ap[i] = p[i] - a[i];
    bp[i] = p[i] - b[i];
    cp[i] = p[i] - c[i];
  }
  const Real d1 = dot3(ab, ap), d2 = dot3(ac, ap), d3 = dot3(ab, bp), d4 = dot3(ac, bp),
             d5 = dot3(ab, cp), d6 = dot3(ac, cp);
  const Real vc = d1 * d4 - d3 * d2, vb = d5 * d2 - d1 * d6, va = d3 * d6 - d5 * d4;
  PairDistance<Real> out;
  // Coefficients over (p, a, b, c): r = p - (closest point).
  const Real to_a[4] = {1, -1, 0, 0}, to_b[4] = {1, 0, -1, 0}, to_c[4] = {1, 0, 0, -1};
  const Real none[2][4] = {{0, 0, 0, 0}, {0, 0, 0, 0}};
  if (d1 <= Real(0) && d2 <= Real(0)) {
    primitive_detail::closest_pair<Real>(x, to_a, none, nullptr, 0, with_hessian, out);
  } else if (d3 >= Real(0) && d4 <= d3) {
    primitive_detail::closest_pair<Real>(x, to_b, none, nullptr, 0, with_hessian, out);
  } else if (d6 >= Real(0) && d5 <= d6) {
    primitive_detail::closest_pair<Real>(x, to_c, none, nullptr, 0, with_hessian, out);
  } else if (vc <= Real(0) && d1 >= Real(0) && d3 <= Real(0)) {
    // Edge ab: a + t (b - a).
    const Real t[1] = {d1 / (d1 - d3)};
    const Real along[2][4] = {{0, 1, -1, 0}, {0, 0, 0, 0}};
    primitive_detail::closest_pair<Real>(x, to_a, along, t, 1, with_hessian, out);
  } else if (vb <= Real(0) && d2 >= Real(0) && d6 <= Real(0)) {
    // Edge ac: a + t (c - a).
    const Real t[1] = {d2 / (d2 - d6)};
    const Real along[2][4] = {{0, 1, 0, -1}, {0, 0, 0, 0}};
    primitive_detail::closest_pair<Real>(x, to_a, along, t, 1, with_hessian, out);
  } else if (va <= Real(0) && d4 - d3 >= Real(0) && d5 - d6 >= Real(0)) {
    // Edge bc: b + t (c - b).
    const Real t[1] = {(d4 - d3) / ((d4 - d3) + (d5 - d6))};
    const Real along[2][4] = {{0, 0, 1, -1}, {0, 0, 0, 0}};
    primitive_detail::closest_pair<Real>(x, to_b, along, t, 1, with_hessian, out);
  } else {
    // Face: a + u (b - a) + v (c - a).
    const Real denom = Real(1) / (va + vb + vc);
    const Real w[2] = {vb * denom, vc * denom};
    const Real along[2][4] = {{0, 1, -1, 0}, {0, 1, 0, -1}};
    primitive_detail::closest_pair<Real>(x, to_a, along, w, 2, with_hessian, out);
  }
  return out;
}

// Segments p0 p1 = x[0..6) and q0 q1 = x[6..12): the closest parameters by
// Ericson's clamped search (5.1.9); near-parallel segments take s = 0 (the
// mollifier of edge_parallelism then fades their term).
template <class Real>
DESCENT_HOST_DEVICE inline PairDistance<Real> edge_edge_distance(const Real* x, bool with_hessian) {
  using primitive_detail::clamp01;
  using primitive_detail::dot3;
  const Real *p0 = x, *p1 = x + 3, *q0 = x + 6, *q1 = x + 9;
  Real d1[3], d2[3], r[3];
  for (int i = 0; i < 3; ++i) {
    d1[i] = p1[i] - p0[i];
    d2[i] = q1[i] - q0[i];
    r[i] = p0[i] - q0[i];
  }
  const Real a = dot3(d1, d1), e = dot3(d2, d2), f = dot3(d2, r), c = dot3(d1, r), b = dot3(d1, d2);
  const Real denom = a * e - b * b;
  // Parallel below this relative sine^2 (the closest points are not unique).
  const Real parallel = Real(1e-12) * a * e;
  Real s = denom > parallel ? clamp01((b * f - c * e) / denom) : Real(0);
  Real t = (b * s + f) / e;
  if (t < Real(0)) {
    t = 0;
    s = clamp01(-c / a);
  } else if (t > Real(1)) {
    t = 1;
    s = clamp01((b - c) / a);
  }
  // r = (1 - s) p0 + s p1 - (1 - t) q0 - t q1; each parameter strictly
  // inside (0, 1) is free, one at a bound is held there.
  const Real c0[4] = {1, 0, -1, 0};
  const Real ds[4] = {-1, 1, 0, 0}, dt[4] = {0, 0, 1, -1};
  Real base[4], cj[2][4], w[2];
  for (int k = 0; k < 4; ++k) base[k] = c0[k];
  int free = 0;
  const bool s_free = s > Real(0) && s<Real(1), t_free = t> Real(0) && t < Real(1);
  if (s_free) {
    for (int k = 0; k < 4; ++k) cj[free][k] = ds[k];
    w[free++] = s;
  } else {
    for (int k = 0; k < 4; ++k) base[k] += s * ds[k];
  }
  if (t_free) {
    for (int k = 0; k < 4; ++k) cj[free][k] = dt[k];
    w[free++] = t;
  } else {
    for (int k = 0; k < 4; ++k) base[k] += t * dt[k];
  }
  PairDistance<Real> out;
  primitive_detail::closest_pair<Real>(x, base, cj, w, free, with_hessian, out);
  return out;
}

// IPC's mollifier of nearly parallel edges (Li et al. 2020, Sec. 4.3): with
// u = p1 - p0, v = q1 - q0 and e = |u x v|^2 = |u|^2 |v|^2 - (u.v)^2,
//   m(e) = (2 - e / eps) e / eps  for e < eps,  1 beyond,
// eps = 1e-3 |u_0|^2 |v_0|^2 at rest. An edge-edge term is m(e) b(d): it
// fades to 0 as the edges turn parallel, where their closest points jump.
template <class Real>
struct Parallelism {
  Real m, dm, d2m;  // m(e), m'(e), m''(e)
  Real e;
  Real grad[12];   // de/dx
  Real hess[144];  // d2e/dx2, row-major (when asked for)
};

template <class Real>
DESCENT_HOST_DEVICE inline Parallelism<Real> edge_parallelism(const Real* x, Real eps,
                                                              bool with_hessian) {
  using primitive_detail::dot3;
  Real u[3], v[3];
  for (int i = 0; i < 3; ++i) {
    u[i] = x[3 + i] - x[i];
    v[i] = x[9 + i] - x[6 + i];
  }
  const Real uu = dot3(u, u), vv = dot3(v, v), uv = dot3(u, v);
  Parallelism<Real> out;
  out.e = uu * vv - uv * uv;
  if (out.e < eps) {
    const Real y = out.e / eps;
    out.m = (Real(2) - y) * y;
    out.dm = (Real(2) - Real(2) * y) / eps;
    out.d2m = -Real(2) / (eps * eps);
  } else {
    out.m = 1;
    out.dm = 0;
    out.d2m = 0;
  }
  // de/du = 2 vv u - 2 uv v, de/dv = 2 uu v - 2 uv u; u = x1 - x0, v = x3 - x2.
  Real gu[3], gv[3];
  for (int i = 0; i < 3; ++i) {
    gu[i] = Real(2) * vv * u[i] - Real(2) * uv * v[i];
    gv[i] = Real(2) * uu * v[i] - Real(2) * uv * u[i];
  }
  for (int i = 0; i < 3; ++i) {
    out.grad[i] = -gu[i];
    out.grad[3 + i] = gu[i];
    out.grad[6 + i] = -gv[i];
    out.grad[9 + i] = gv[i];
  }
  if (!with_hessian) return out;
  // d2e/du2 = 2 vv I - 2 v v^T, d2e/dv2 = 2 uu I - 2 u u^T,
  // d2e/du dv = 4 u v^T - 2 v u^T - 2 uv I.
  Real huu[9], hvv[9], huv[9];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      const Real id = i == j ? Real(1) : Real(0);
      huu[3 * i + j] = Real(2) * vv * id - Real(2) * v[i] * v[j];
      hvv[3 * i + j] = Real(2) * uu * id - Real(2) * u[i] * u[j];
      huv[3 * i + j] = Real(4) * u[i] * v[j] - Real(2) * v[i] * u[j] - Real(2) * uv * id;
    }
  // Points 0, 1 carry u with signs -1, +1; points 2, 3 carry v likewise.
  const Real sign[4] = {-1, 1, -1, 1};
  for (int k = 0; k < 4; ++k)
    for (int l = 0; l < 4; ++l)
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
          const bool ku = k < 2, lu = l < 2;
          const Real block = ku && lu     ? huu[3 * i + j]
                             : !ku && !lu ? hvv[3 * i + j]
                             : ku         ? huv[3 * i + j]
                                          : huv[3 * j + i];
          out.hess[12 * (3 * k + i) + 3 * l + j] = sign[k] * sign[l] * block;
        }
  return out;
}

}  // namespace descent
