#pragma once
// The math functions of the element kernels, called unqualified (sqrt(x),
// not std::sqrt(x)): for float and double they are std's, and a real type of
// another kind brings its own overloads by argument-dependent lookup, as the
// operation counter of bench/roofline/flop_count.cpp does to count what each
// model computes per tet.
#include <cmath>

#include "kernels/cube_root.hpp"    // cube_root: vectorisable, in place of std::cbrt
#include "kernels/exponential.hpp"  // exponential: vectorisable, in place of std::exp

namespace descent {

using std::abs;
using std::copysign;
using std::fmax;
using std::frexp;
using std::ldexp;
using std::sqrt;

}  // namespace descent
