#pragma once
// The optimised-step initialisation (paper 1, §4.4, Eq. 10): q0 = q_t + d h v_t
// with d minimising the quadratic model of eps along h v_t at q_t,
//   d = -(h v . grad eps(q_t)) / (h v . H(q_t) h v),
// H the exact Hessian (HessianOperator::product). Held dofs do not count
// (the caller then holds them). Costs one gradient, one Hessian product and
// one MPI_Allreduce (both inner products fused); d = 1 (constant velocity)
// where the curvature along h v is not positive or h v is zero.
// Layout: 3 reals per local vertex, xyz-interleaved.
#include "solver/local_problem.hpp"

namespace descent {

template <class Real>
double optimized_step_weight(LocalProblem<Real>& problem, const Real* qt, const Real* y,
                             const Real* hv);

}  // namespace descent
