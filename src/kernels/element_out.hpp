#pragma once
// Where an element pass puts its per-corner results (layout of
// kernels/loops.hpp):
//   gather:   the corner arrays, 12 reals per tet (`corner_diag` null
//             without the diagonal), summed per vertex later by
//             loops::gather_corners in the CSR's order;
//   scatter:  added atomically to the vertex partials (`partial`, `width`
//             reals per vertex), in whatever order the threads reach them;
//   in order: added to the vertex partials without atomics, tet by tet in
//             ascending order (`in_order`): one thread only. Each vertex's
//             sum then takes its terms in the order the gather's CSR lists
//             them (corners 4 t + a, ascending) and starts from the same
//             zero, so it is bitwise the gather's, without the corner arrays'
//             round trip through memory.
#include "kernels/execution.hpp"

namespace descent::loops {

template <class Real>
struct ElementOut {
  Real* corner_grad = nullptr;
  Real* corner_diag = nullptr;
  Real* partial = nullptr;
  int width = 3;
  bool in_order = false;
};

// value added to *target: atomically in scatter, plainly in order.
template <class Real>
DESCENT_HOST_DEVICE inline void add_to_partial(const ElementOut<Real>& out, Real* target,
                                               Real value) {
  if (out.in_order)
    *target += value;
  else
    atomic_add(target, value);
}

}  // namespace descent::loops
