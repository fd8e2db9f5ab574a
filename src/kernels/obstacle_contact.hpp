#pragma once
// Contact of one vertex with rigid obstacles (docs/contact.md): the gap to an
// obstacle's surface, the barrier that keeps it open and lagged friction,
// as terms of eps per surface vertex. Host and device.
//
// Gap g(x): signed distance from x to the obstacle's surface, negative inside
// the solid; n = dg/dx its unit normal (outward from the solid) and
// C = d2g/dx2 its curvature (row-major 3x3; 0 for a plane and inside a box,
// (I - n n^T)/r outside a sphere of centre distance r, (P - n n^T)/g outside a
// box, P the projector on the axes along which x lies beyond the box). The
// distance to a convex solid is convex outside it, so g(x + d) >= g(x) + n.d:
// the crossing guard below rests on that.
//
// Barrier (IPC, Li et al. 2020): b(g) = -(g - dh)^2 ln(g / dh) for 0 < g < dh,
// 0 beyond dh, +inf at g <= 0; C2 at dh, convex on (0, dh). A vertex's term is
// kappa b(g).
//
// Friction, lagged over a step: normal force lambda = -kappa b'(g_t) and
// normal n_t from the step start, the tangential slip u = P_t (x - x_t - w)
// relative to the obstacle (w: the obstacle's displacement at x_t over the
// step, P_t = I - n_t n_t^T), and the term mu lambda f0(|u|) with IPC's
// smoothing over eps_h = eps_v h:
//   f0(y) = -y^3/(3 eps_h^2) + y^2/eps_h + eps_h/3   (y < eps_h),  y beyond.
// Its Hessian is positive semi-definite everywhere.
#include <cmath>

#include "common/mesh.hpp"
#include "kernels/host_device.hpp"

namespace descent {

enum ObstacleKind : int { kObstaclePlane = 0, kObstacleSphere = 1, kObstacleBox = 2 };

// One obstacle at one time: its shape in its own rest frame and the rigid
// motion to the world, x = R x0 + c (R row-major).
template <class Real>
struct ObstacleGeometry {
  int kind;
  Real a[3];  // plane: a point on it; sphere: centre; box: box_min
  Real b[3];  // plane: unit normal; box: box_max
  Real radius;
  Real rotation[9];
  Real shift[3];
};

template <class Real>
struct Gap {
  Real g;
  Real n[3];
  Real curvature[9];
};

template <class Real>
DESCENT_HOST_DEVICE inline Gap<Real> obstacle_gap(const ObstacleGeometry<Real>& o, const Real* x) {
  const Real* R = o.rotation;
  // x0 = R^T (x - c)
  Real d[3], x0[3];
  for (int i = 0; i < 3; ++i) d[i] = x[i] - o.shift[i];
  for (int i = 0; i < 3; ++i) x0[i] = R[i] * d[0] + R[3 + i] * d[1] + R[6 + i] * d[2];
  Gap<Real> gap;
  Real n0[3] = {0, 0, 0}, c0[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
  if (o.kind == kObstaclePlane) {
    gap.g = (x0[0] - o.a[0]) * o.b[0] + (x0[1] - o.a[1]) * o.b[1] + (x0[2] - o.a[2]) * o.b[2];
    for (int i = 0; i < 3; ++i) n0[i] = o.b[i];
  } else if (o.kind == kObstacleSphere) {
    Real r[3];
    for (int i = 0; i < 3; ++i) r[i] = x0[i] - o.a[i];
    const Real len = std::sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
    gap.g = len - o.radius;
    if (len > Real(0)) {
      for (int i = 0; i < 3; ++i) n0[i] = r[i] / len;
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
          c0[3 * i + j] = ((i == j ? Real(1) : Real(0)) - n0[i] * n0[j]) / len;
    } else {
      n0[1] = 1;  // the centre itself: any direction is as near
    }
  } else {
    Real r[3];
    bool outside = false;
    for (int i = 0; i < 3; ++i) {
      const Real clamped = x0[i] < o.a[i] ? o.a[i] : (x0[i] > o.b[i] ? o.b[i] : x0[i]);
      r[i] = x0[i] - clamped;
      outside = outside || r[i] != Real(0);
    }
    if (outside) {
      const Real len = std::sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
      gap.g = len;
      for (int i = 0; i < 3; ++i) n0[i] = r[i] / len;
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
          c0[3 * i + j] = ((i == j && r[i] != Real(0) ? Real(1) : Real(0)) - n0[i] * n0[j]) / len;
    } else {
      // Inside: the nearest face.
      gap.g = x0[0] - o.a[0];
      n0[0] = -1;
      for (int i = 0; i < 3; ++i) {
        const Real below = x0[i] - o.a[i], above = o.b[i] - x0[i];
        if (below < gap.g) {
          gap.g = below;
          n0[0] = n0[1] = n0[2] = 0;
          n0[i] = -1;
        }
        if (above < gap.g) {
          gap.g = above;
          n0[0] = n0[1] = n0[2] = 0;
          n0[i] = 1;
        }
      }
      gap.g = -gap.g;
    }
  }
  // n = R n0, C = R C0 R^T
  for (int i = 0; i < 3; ++i)
    gap.n[i] = R[3 * i] * n0[0] + R[3 * i + 1] * n0[1] + R[3 * i + 2] * n0[2];
  Real rc[9];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      rc[3 * i + j] = R[3 * i] * c0[j] + R[3 * i + 1] * c0[3 + j] + R[3 * i + 2] * c0[6 + j];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      gap.curvature[3 * i + j] =
          rc[3 * i] * R[3 * j] + rc[3 * i + 1] * R[3 * j + 1] + rc[3 * i + 2] * R[3 * j + 2];
  return gap;
}

// b(g), b'(g), b''(g) of the barrier with activation distance dh; at g <= 0
// the energy is +inf (derivatives 0: no iterate is ever there).
template <class Real>
struct BarrierValue {
  Real energy, first, second;
};

template <class Real>
DESCENT_HOST_DEVICE inline BarrierValue<Real> barrier(Real g, Real dh) {
  if (g >= dh) return {Real(0), Real(0), Real(0)};
  if (!(g > Real(0))) return {Real(INFINITY), Real(0), Real(0)};
  const Real e = g - dh, l = std::log(g / dh);
  return {-e * e * l, -Real(2) * e * l - e * e / g,
          -Real(2) * l - Real(4) * e / g + e * e / (g * g)};
}

// What one surface vertex's friction with one obstacle carries over a step:
// mu lambda (0: no friction), the step-start normal n_t and the obstacle's
// displacement w at the vertex over the step.
template <class Real>
struct FrictionLag {
  Real mu_lambda;
  Real n[3];
  Real w[3];
};

// A vertex's contact terms: energy, gradient and Hessian (row-major).
template <class Real>
struct ContactTerms {
  Real energy = 0;
  Real grad[3] = {0, 0, 0};
  Real hess[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
};

// Adds the barrier of obstacle `o` at x to `out`: with `exact` its full
// Hessian kappa (b'' n n^T + b' C), else its positive semi-definite part
// kappa b'' n n^T (b' <= 0 and C >= 0, so the curvature term is the negative
// one). Returns the gap.
template <class Real>
DESCENT_HOST_DEVICE inline Real add_barrier(const ObstacleGeometry<Real>& o, Real kappa, Real dh,
                                            const Real* x, bool exact, ContactTerms<Real>& out) {
  const Gap<Real> gap = obstacle_gap(o, x);
  if (gap.g >= dh) return gap.g;
  const BarrierValue<Real> b = barrier(gap.g, dh);
  out.energy += kappa * b.energy;
  for (int i = 0; i < 3; ++i) out.grad[i] += kappa * b.first * gap.n[i];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      out.hess[3 * i + j] += kappa * (b.second * gap.n[i] * gap.n[j] +
                                      (exact ? b.first * gap.curvature[3 * i + j] : Real(0)));
  return gap.g;
}

// Lagged friction on a slip s (3-vector) with lagged normal n: the energy
// mu_lambda f0(|u|), u = (I - n n^T) s, its gradient in s and, row-major,
// with `exact` its Hessian in s (positive semi-definite in both regimes),
// else mu_lambda f1(y)/y (I - n n^T), y = |u|: the curvature of the
// quadratic in u that touches mu_lambda f0(|u|) at u and lies above it
// (f1 = f0' is concave, so f1(y)/y is at least the curvature f1'(y) along
// u). The exact curvature along a sliding u is 0, so a diagonal built from
// it let each iteration carry a contact vertex across the sticking core
// (width eps_h) and back: the snowman's energy oscillated by 0.5% of
// itself and its steps ended at the iteration cap. From the majorant a
// Jacobi step along u stops at the sticking point at most.
template <class Real>
DESCENT_HOST_DEVICE inline ContactTerms<Real> friction_on_slip(Real mu_lambda, const Real* n,
                                                               Real eps_h, const Real* s,
                                                               bool exact) {
  ContactTerms<Real> out;
  const Real sn = s[0] * n[0] + s[1] * n[1] + s[2] * n[2];
  Real u[3];
  for (int i = 0; i < 3; ++i) u[i] = s[i] - sn * n[i];
  const Real y = std::sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
  // f1 = f0', f1(y)/y and the coefficient c = (f1'(y) - f1(y)/y)/y^2 of
  // u u^T in the Hessian of f0(|u|) = f1/y P + c u u^T, per regime.
  Real f0, f1_over_y, c;
  if (y < eps_h) {
    f0 = -y * y * y / (Real(3) * eps_h * eps_h) + y * y / eps_h + eps_h / Real(3);
    f1_over_y = -y / (eps_h * eps_h) + Real(2) / eps_h;
    c = y > Real(0) ? -Real(1) / (eps_h * eps_h * y) : Real(0);
  } else {
    f0 = y;
    f1_over_y = Real(1) / y;
    c = -Real(1) / (y * y * y);
  }
  out.energy = mu_lambda * f0;
  for (int i = 0; i < 3; ++i) out.grad[i] = mu_lambda * f1_over_y * u[i];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      const Real p = (i == j ? Real(1) : Real(0)) - n[i] * n[j];
      out.hess[3 * i + j] = mu_lambda * (f1_over_y * p + (exact ? c * u[i] * u[j] : Real(0)));
    }
  return out;
}

// Adds the lagged friction of one obstacle at x (step start xt) to `out`:
// the slip is the vertex's move relative to the obstacle's, x - xt - w.
// `exact` as friction_on_slip takes it.
template <class Real>
DESCENT_HOST_DEVICE inline void add_friction(const FrictionLag<Real>& lag, Real eps_h,
                                             const Real* x, const Real* xt, bool exact,
                                             ContactTerms<Real>& out) {
  if (!(lag.mu_lambda > Real(0))) return;
  Real s[3];
  for (int i = 0; i < 3; ++i) s[i] = x[i] - xt[i] - lag.w[i];
  const ContactTerms<Real> f = friction_on_slip(lag.mu_lambda, lag.n, eps_h, s, exact);
  out.energy += f.energy;
  for (int i = 0; i < 3; ++i) out.grad[i] += f.grad[i];
  for (int i = 0; i < 9; ++i) out.hess[i] += f.hess[i];
}

// All contact terms of one vertex at x against `count` obstacles (lags[k]
// for obstacle k).
template <class Real>
DESCENT_HOST_DEVICE inline ContactTerms<Real> vertex_contact(
    const ObstacleGeometry<Real>* obstacles, const FrictionLag<Real>* lags, int count, Real kappa,
    Real dh, Real eps_h, const Real* x, const Real* xt, bool exact) {
  ContactTerms<Real> out;
  for (int k = 0; k < count; ++k) {
    add_barrier(obstacles[k], kappa, dh, x, exact, out);
    add_friction(lags[k], eps_h, x, xt, exact, out);
  }
  return out;
}

// One rank's obstacle contact as the loops read it (kernels/contact_loops.hpp):
// surface vertex s -> local id vertices[s], the owned ones first, its
// stiffness kappa[s] and its friction lags [num_obstacles s, + num_obstacles).
template <class Real>
struct ContactView {
  int num_obstacles = 0;
  const ObstacleGeometry<Real>* obstacles = nullptr;
  index_t num_vertices = 0;  // surface vertices
  index_t num_owned = 0;     // of them, owned (the prefix)
  const index_t* vertices = nullptr;
  const Real* kappa = nullptr;
  const FrictionLag<Real>* lags = nullptr;
  Real dh = 0;     // activation distance
  Real eps_h = 0;  // friction's smoothing velocity times h
  // With a preconditioner P^-1 fixed between refreshes (kernels/
  // contact_loops.hpp, contact_scale): 3 reals per surface vertex each, the
  // stiffness that holds the vertex without contact (m/h^2 plus the elastic
  // Hessian diagonal at rest), the contact diagonal at the last refresh,
  // and this iteration's scale. Null with Jacobi's D^-1.
  const Real* base = nullptr;
  Real* reference = nullptr;
  Real* scale = nullptr;
};

// The gap a guarded move keeps of the present one: a vertex closes at most
// 80% of its gap per iteration (IPC's line search stops at 80% of the time
// of impact likewise).
template <class Real>
constexpr Real kGapKept = Real(0.2);
// It never closes a gap below this fraction of the activation distance, where the
// barrier's force is 1e6 kappa dh (far above any step's inertia: a vertex
// stopped from v within h needs m v / h) and its curvature, 1e12 kappa,
// is still finite in single precision.
template <class Real>
constexpr Real kLeastGap = Real(1e-6);

// How much of gap g a move may close: all but max(keep g, least), none when g
// is already below that.
template <class Real>
DESCENT_HOST_DEVICE inline Real closable(Real g, Real keep, Real least) {
  const Real kept = keep * g > least ? keep * g : least;
  return g > kept ? g - kept : Real(0);
}

// The largest s in [0, 1] for which the move s d from x keeps every gap as
// guard_move does (obstacles already touching x, g <= 0, are left out).
template <class Real>
DESCENT_HOST_DEVICE inline Real move_fraction(const ObstacleGeometry<Real>* obstacles, int count,
                                              const Real* x, const Real* d, Real keep, Real least) {
  Real scale = 1;
  for (int k = 0; k < count; ++k) {
    const Gap<Real> gap = obstacle_gap(obstacles[k], x);
    if (!(gap.g > Real(0))) continue;
    const Real closing = -(d[0] * gap.n[0] + d[1] * gap.n[1] + d[2] * gap.n[2]);
    const Real allowed = closable(gap.g, keep, least);
    if (closing > allowed && allowed / closing < scale) scale = allowed / closing;
  }
  return scale;
}

// The largest part of a vertex's move `d` (3 reals, from x) that keeps its
// gap to every obstacle above `keep` times the present one, and above
// `least` (where it is not already below): per obstacle the
// normal component is cut where it would close more than (1 - keep) of the
// gap, then the whole move is scaled where those cuts conflict (g(x + d) >=
// g(x) + n.d, so the linear bound guards the true gap). Axes whose bit is set
// in `held` do not move, and a move that is not finite is none. Vertices
// already inside (g <= 0) are left as they are.
template <class Real>
DESCENT_HOST_DEVICE inline void guard_move(const ObstacleGeometry<Real>* obstacles, int count,
                                           const Real* x, Real keep, Real least, unsigned held,
                                           Real* d) {
  // A diverging iterate (its energy check will roll it back) moves nothing
  // it cannot bound: the vertex stays.
  if (!(d[0] * d[0] + d[1] * d[1] + d[2] * d[2] < Real(INFINITY))) {
    d[0] = d[1] = d[2] = 0;
    return;
  }
  for (int k = 0; k < count; ++k) {
    const Gap<Real> gap = obstacle_gap(obstacles[k], x);
    if (!(gap.g > Real(0))) continue;
    const Real closing = -(d[0] * gap.n[0] + d[1] * gap.n[1] + d[2] * gap.n[2]);
    const Real allowed = closable(gap.g, keep, least);
    if (closing > allowed)
      for (int i = 0; i < 3; ++i) d[i] += (closing - allowed) * gap.n[i];
  }
  for (int i = 0; i < 3; ++i)
    if (held & (1u << i)) d[i] = 0;
  // A later cut may have undone an earlier one (two walls at an acute
  // angle): scale the whole move to the tightest bound.
  const Real scale = move_fraction(obstacles, count, x, d, keep, least);
  if (scale < Real(1))
    for (int i = 0; i < 3; ++i) d[i] *= scale;
}

}  // namespace descent
