#pragma once
// The same kernel data with its values widened to double: a float run's
// energy checks evaluate eps in double from the float iterate, rest data and
// material (issue 22, mixed precision). The energy then judged is a fixed
// function of the float state, free of float's round-off: evaluated in
// float, the terms' round-off (about 1e-4 of the energy's magnitude at the
// checks' tolerance) hides a step's whole decrease on a body that moves
// little, and the accuracy target could never be confirmed. For double data
// each function returns a copy, so a double run computes what it did before.
#include "kernels/arap.hpp"
#include "kernels/conversion.hpp"
#include "kernels/corotated.hpp"
#include "kernels/element.hpp"
#include "kernels/fung.hpp"
#include "kernels/mooney_rivlin.hpp"
#include "kernels/neo_hookean.hpp"
#include "kernels/obstacle_contact.hpp"
#include "kernels/stvk.hpp"
#include "kernels/vertex.hpp"

namespace descent {

// An energy evaluated and summed in double carries a round-off of this many
// double epsilons per unit of its terms' magnitude (a generous multiple:
// step_control.hpp's energy_roundoff). Quantities of another kind that join
// the magnitude are divided by it (loops::local_energy's state resolution).
constexpr double kRoundoffEpsilons = 1024;

template <class Real>
DESCENT_HOST_DEVICE inline Vec3<double> in_double(const Vec3<Real>& v) {
  return {v.x, v.y, v.z};
}

template <class Real>
DESCENT_HOST_DEVICE inline Mat3<double> in_double(const Mat3<Real>& a) {
  Mat3<double> wide;
  for (int i = 0; i < 9; ++i) wide.m[i] = a.m[i];
  return wide;
}

template <class Real>
DESCENT_HOST_DEVICE inline TetCorners<double> in_double(const TetCorners<Real>& c) {
  return {{in_double(c.x[0]), in_double(c.x[1]), in_double(c.x[2]), in_double(c.x[3])}};
}

template <class Real>
DESCENT_HOST_DEVICE inline TetRest<double> in_double(const TetRest<Real>& rest) {
  return {in_double(rest.dm_inv), rest.volume};
}

template <class Real>
DESCENT_HOST_DEVICE inline VertexTerms<double> in_double(const VertexTerms<Real>& t) {
  return {t.inv_h2, t.damping_over_h, {t.gravity[0], t.gravity[1], t.gravity[2]}};
}

// The material models, field by field.
template <class Real>
inline StVK<double> in_double(const StVK<Real>& m) {
  return {m.mu, m.lambda};
}
template <class Real>
inline NeoHookean<double> in_double(const NeoHookean<Real>& m) {
  return {m.mu, m.kappa};
}
template <class Real>
inline MooneyRivlin<double> in_double(const MooneyRivlin<Real>& m) {
  return {in_double(m.neo_hookean), m.c2};
}
template <class Real>
inline Fung<double> in_double(const Fung<Real>& m) {
  return {in_double(m.neo_hookean), m.c2, m.c3};
}
template <class Real>
inline Corotated<double> in_double(const Corotated<Real>& m) {
  return {m.mu, m.lambda};
}
template <class Real>
inline Arap<double> in_double(const Arap<Real>& m) {
  // Not `return {m.mu}`: nvcc's host pass rejects the one-member aggregate
  // so (CUDA 13.0, g++ host compiler).
  Arap<double> wide{};
  wide.mu = m.mu;
  return wide;
}
template <class Real>
inline Conversion<double> in_double(const Conversion<Real>& c) {
  return {c.lambda_minus, c.lambda_plus, c.decay, in_double(c.arap)};
}

template <class Real>
DESCENT_HOST_DEVICE inline ObstacleGeometry<double> in_double(const ObstacleGeometry<Real>& o) {
  ObstacleGeometry<double> wide;
  wide.kind = o.kind;
  for (int i = 0; i < 3; ++i) {
    wide.a[i] = o.a[i];
    wide.b[i] = o.b[i];
    wide.shift[i] = o.shift[i];
  }
  wide.radius = o.radius;
  for (int i = 0; i < 9; ++i) wide.rotation[i] = o.rotation[i];
  return wide;
}

template <class Real>
DESCENT_HOST_DEVICE inline FrictionLag<double> in_double(const FrictionLag<Real>& lag) {
  FrictionLag<double> wide;
  wide.mu_lambda = lag.mu_lambda;
  for (int i = 0; i < 3; ++i) {
    wide.n[i] = lag.n[i];
    wide.w[i] = lag.w[i];
  }
  return wide;
}

}  // namespace descent
