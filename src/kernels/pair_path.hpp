#pragma once
// How far a contact pair (kernels/pair_contact.hpp) may travel along a
// straight move of its four vertices before its distance falls to a floor:
// what keeps every iterate of contact between bodies free of crossings
// (contact/body_contact.hpp). Host and device. x0, x1: the pair's 12
// coordinates before and after the move (layout of primitive_distance.hpp:
// the vertex then the triangle, or the two edges).
//
// The distance d(s) along x0 + s (x1 - x0) is Lipschitz in s with rate L,
// the largest difference between the move of a vertex of one side and one of
// the other (the closest points move by convex combinations of their side's
// moves). Conservative advancement: from s with distance d, the distance
// stays above the floor up to s + (d - floor) / L, where d is evaluated
// again. Moves the two sides share cost nothing; only relative ones close.
#include <cmath>

#include "kernels/obstacle_contact.hpp"
#include "kernels/pair_contact.hpp"

namespace descent {

// Distance evaluations one conservative advancement makes at most; a path
// not proven by then ends where the proof reached (an approach that slows
// near the floor is cut there, which is safe).
constexpr int kPathSteps = 64;

// L: the largest relative move between the pair's two sides (the vertex and
// the triangle, or the two edges). Not finite when a move is not.
template <class Real>
DESCENT_HOST_DEVICE inline double pair_closing_rate(PairKind kind, const Real* x0, const Real* x1) {
  const int side = kind == PairKind::vertex_triangle ? 1 : 2;
  double rate = 0;
  for (int a = 0; a < side; ++a)
    for (int b = side; b < 4; ++b) {
      double s = 0;
      for (int i = 0; i < 3; ++i) {
        const double r = static_cast<double>(x1[3 * a + i] - x0[3 * a + i]) -
                         static_cast<double>(x1[3 * b + i] - x0[3 * b + i]);
        s += r * r;
      }
      if (!(s == s)) return s;  // NaN: a move is not finite
      if (s > rate * rate) rate = std::sqrt(s);
    }
  return rate;
}

// The largest s in [0, 1] for which the distance along x0 + s (x1 - x0) is
// proven to stay above `floor`, from d0 = the distance at x0: 1 when the
// closing rate alone proves it, 0 when d0 is not above the floor or a move
// is not finite.
template <class Real>
DESCENT_HOST_DEVICE inline double pair_path_fraction(PairKind kind, const Real* x0, const Real* x1,
                                                     double d0, double floor) {
  const double rate = pair_closing_rate(kind, x0, x1);
  if (!(d0 > floor) || !std::isfinite(rate)) return 0;
  if (rate <= d0 - floor) return 1;
  double s = 0, d = d0;
  Real x[12];
  for (int step = 0; step < kPathSteps; ++step) {
    s += (d - floor) / rate;
    if (s >= 1) return 1;
    for (int k = 0; k < 12; ++k)
      x[k] = static_cast<Real>(static_cast<double>(x0[k]) + s * static_cast<double>(x1[k] - x0[k]));
    d = std::sqrt(static_cast<double>(pair_distance(kind, x, false).d2));
    if (!(d > floor)) return s;
  }
  return s;
}

// The gap a guarded move keeps of a pair's gap g: kGapKept of it, and at
// least kLeastGap dh (as from obstacles) while g is twice that; below it,
// half of g, so a pair pressed closer (by the step's guess) may still move
// with its two sides: conservative advancement cannot start from its floor.
template <class Real>
DESCENT_HOST_DEVICE inline double pair_kept_gap(double g, double dh) {
  const double least = static_cast<double>(kLeastGap<Real>) * dh;
  const double kept = static_cast<double>(kGapKept<Real>) * g;
  return g > 2 * least ? (kept > least ? kept : least) : 0.5 * g;
}

}  // namespace descent
