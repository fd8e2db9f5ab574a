#pragma once
// The constant system matrix of projective dynamics for the `arap` energy
// (Wang 2015; paper 1, §4.1 "comparison to projective dynamics"): with the
// projections R_e held fixed, V mu |F - R|_F^2 is quadratic in the corners,
// with Hessian 2 mu V (b_a . b_b) I_3 between corners a and b (F = sum_a
// x_a b_a^T, tet.hpp). Its diagonal, per corner the same on all three axes,
// is the Jacobi preconditioner of pd_chebyshev; it does not change with q.
#include "kernels/arap.hpp"
#include "kernels/tet.hpp"

namespace descent {

template <class Real>
DESCENT_HOST_DEVICE inline void pd_element_diagonal(const Arap<Real>& model,
                                                    const TetRest<Real>& rest, Vec3<Real> out[4]) {
  for (int a = 0; a < 4; ++a) {
    const Vec3<Real> b = corner_operator(rest.dm_inv, a);
    const Real d = Real(2) * model.mu * rest.volume * dot(b, b);
    out[a] = {d, d, d};
  }
}

}  // namespace descent
