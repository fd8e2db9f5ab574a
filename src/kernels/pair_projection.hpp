#pragma once
// The position constraint of one contact pair for contact.method =
// "projection" between bodies (issue 21, step 4; paper 1, Sec. 8's second
// approach, paper 2's collision pass): the step is solved without contact,
// then pairs whose path over the step came within reach are pushed apart,
// mass-weighted (contact/body_projection.hpp runs the passes). Host and
// device. Layout of x: primitive_distance.hpp.
//
// The constraint is a plane: at the pair's first approach to dh/2 along the
// step's straight path x0 -> x1 (conservative advancement,
// kernels/pair_path.hpp; its start if the pair starts nearer), the closest
// points' coefficients c and the normal n = r / |r|, r = sum_k c_k x_k
// (from the second side's closest point to the first's). The pair ends
// apart when C(x) = n . sum_k c_k x_k - dh >= 0. n and c are fixed for the
// pass: a side that went through the other is pulled back to the side it
// came from, wherever the solve left it.
//
// A violated constraint moves each vertex k by
//   dx_k = w lambda inv_m_k c_k n,  lambda = -C / sum_j c_j^2 inv_m_j,
// (w the pass's relaxation), which restores C = 0 when w = 1 and keeps the
// pair's momentum: sum_k m_k dx_k = w lambda n sum_k c_k = 0, the c of each
// side summing to +1 and -1. Friction is Coulomb on the impulse (as for
// obstacles): the closest points' tangential slip over the step is cut by
// mu times the normal correction -C, to zero at most, with the same weights.
#include <cmath>

#include "kernels/pair_contact.hpp"
#include "kernels/pair_path.hpp"

namespace descent {

template <class Real>
struct PairConstraint {
  bool active = false;
  Real n[3] = {0, 0, 0};
  Real c[4] = {0, 0, 0, 0};
};

// The pair's constraint over the step x0 -> x1, with the gap dh it keeps:
// active when the path comes within dh/2 or ends within dh; inactive (and
// unresolvable) also where the pair touches at the point that defines it.
template <class Real>
DESCENT_HOST_DEVICE inline PairConstraint<Real> pair_constraint(PairKind kind, const Real* x0,
                                                                const Real* x1, double dh) {
  PairConstraint<Real> out;
  const double d0 = std::sqrt(static_cast<double>(pair_distance(kind, x0, false).d2));
  const double d1 = std::sqrt(static_cast<double>(pair_distance(kind, x1, false).d2));
  const double s = pair_path_fraction(kind, x0, x1, d0, 0.5 * dh);
  if (s >= 1 && d1 >= dh) return out;
  Real x[12];
  const double at = s >= 1 ? 1.0 : s;
  for (int k = 0; k < 12; ++k)
    x[k] = static_cast<Real>(static_cast<double>(x0[k]) + at * static_cast<double>(x1[k] - x0[k]));
  const PairDistance<Real> dist = pair_distance(kind, x, false);
  const Real d = std::sqrt(dist.d2);
  if (!(d > Real(0))) return out;
  Real r[3] = {0, 0, 0};
  for (int k = 0; k < 4; ++k) {
    out.c[k] = dist.coefficient[k];
    for (int i = 0; i < 3; ++i) r[i] += out.c[k] * x[3 * k + i];
  }
  for (int i = 0; i < 3; ++i) out.n[i] = r[i] / d;
  out.active = true;
  return out;
}

// C(x) of an active constraint (x: the pair's 12 coordinates now).
template <class Real>
DESCENT_HOST_DEVICE inline double pair_constraint_value(const PairConstraint<Real>& con,
                                                        const Real* x, double dh) {
  double value = -dh;
  for (int k = 0; k < 4; ++k)
    for (int i = 0; i < 3; ++i)
      value += static_cast<double>(con.c[k]) * static_cast<double>(con.n[i]) *
               static_cast<double>(x[3 * k + i]);
  return value;
}

// The moves dx (12) that one relaxed projection of the constraint gives
// its vertices at x (step start xt), with inverse masses inv_mass (0: held)
// and relaxation w; zero where the constraint holds or every vertex is held.
// Returns the normal correction -C it closed (0 where none).
template <class Real>
DESCENT_HOST_DEVICE inline double project_pair(const PairConstraint<Real>& con, const Real* x,
                                               const Real* xt, const Real* inv_mass, double dh,
                                               double mu, double w, double* dx) {
  for (int k = 0; k < 12; ++k) dx[k] = 0;
  const double value = pair_constraint_value(con, x, dh);
  if (!(value < 0)) return 0;
  double weight = 0;
  for (int k = 0; k < 4; ++k)
    weight += static_cast<double>(con.c[k]) * static_cast<double>(con.c[k]) *
              static_cast<double>(inv_mass[k]);
  if (!(weight > 0)) return 0;
  const double lambda = -value / weight;
  // The closest points' tangential slip over the step, after the normal
  // correction (which is along n and leaves it as it is).
  double u[3] = {0, 0, 0};
  for (int k = 0; k < 4; ++k)
    for (int i = 0; i < 3; ++i)
      u[i] += static_cast<double>(con.c[k]) * static_cast<double>(x[3 * k + i] - xt[3 * k + i]);
  double un = 0;
  for (int i = 0; i < 3; ++i) un += u[i] * static_cast<double>(con.n[i]);
  for (int i = 0; i < 3; ++i) u[i] -= un * static_cast<double>(con.n[i]);
  const double slip = std::sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
  const double cut = slip > 0 ? std::fmin(1.0, mu * -value / slip) : 0.0;
  for (int k = 0; k < 4; ++k) {
    const double share = w * static_cast<double>(inv_mass[k]) * static_cast<double>(con.c[k]);
    for (int i = 0; i < 3; ++i)
      dx[3 * k + i] = share * (lambda * static_cast<double>(con.n[i]) - cut * u[i] / weight);
  }
  return -value;
}

}  // namespace descent
