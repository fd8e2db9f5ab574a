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

// Whether any lane of a choice holds: for T the choice itself. Code that
// selects may skip computing a side that no lane takes.
DESCENT_HOST_DEVICE inline bool any_lane(bool c) { return c; }

// frexp's exponent of x alone: x = m 2^e with |m| in [0.5, 1), 0 for x = 0.
template <class Real>
DESCENT_HOST_DEVICE inline int frexp_exponent(Real x) {
  int e = 0;
  frexp(x, &e);
  return e;
}

}  // namespace descent
