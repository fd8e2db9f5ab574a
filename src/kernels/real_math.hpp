#pragma once
// The math functions of the element kernels, called unqualified (sqrt(x),
// not std::sqrt(x)): for float and double they are std's, and a real type of
// another kind brings its own overloads by argument-dependent lookup, as the
// operation counter of bench/roofline/op_count.cpp does to count what each
// model computes per tet.
#include <cmath>

#include "kernels/cube_root.hpp"    // cube_root: vectorisable, in place of std::cbrt
#include "kernels/exponential.hpp"  // exponential: vectorisable, in place of std::exp
#include "kernels/host_device.hpp"

namespace descent {

using std::abs;
using std::copysign;
using std::fmax;
using std::frexp;
using std::ldexp;
using std::sqrt;

// The math's choices between two values, written so that a real type whose
// comparisons give per-lane masks (kernels/cpu/lanes.hpp) computes both and
// keeps the chosen one's bits: select(c, a, b) is c ? a : b.
template <class Real>
DESCENT_HOST_DEVICE inline Real select(bool c, Real a, Real b) {
  return c ? a : b;
}

// A comparison's result: bool for T; per lane for a type of lanes, whose
// masks combine with &, | and ! as bools do.
template <class Real>
using MaskOf = decltype(Real() < Real());

// The real of one lane: T itself here; kernels/cpu/lanes.hpp specialises it.
template <class Real>
struct ScalarOf {
  using type = Real;
};

// Whether any (all) lanes of a choice hold: for T the choice itself. Code
// that selects may skip computing a side that no lane takes, and stop a
// loop once every lane is done.
DESCENT_HOST_DEVICE inline bool any_lane(bool c) { return c; }
DESCENT_HOST_DEVICE inline bool all_lanes(bool c) { return c; }

// frexp's exponent of x alone: x = m 2^e with |m| in [0.5, 1), 0 for x = 0.
template <class Real>
DESCENT_HOST_DEVICE inline int frexp_exponent(Real x) {
  int e = 0;
  frexp(x, &e);
  return e;
}

}  // namespace descent
