#pragma once
// `ncg` (paper 1, Eq. 4 with the Jacobi preconditioner of §4.1): Fletcher-
// Reeves nonlinear CG on P^-1 g, P = diag(H) every M iterations,
//   z_k = g . P^-1 g,   dq = -P^-1 g + (z_k / z_{k-1}) dq_prev,
// and the step length from the exact Hessian along dq (as the paper does):
//   t = -g . dq / (dq . H dq),   q <- q + alpha t dq,
// under the paper's step control (a rollback also restarts the direction).
// Collectives per iteration: 2 MPI_Allreduce ([z_k, g . dq_prev] fused, then
// dq . H dq), plus the energy checks.
#include "solver/methods/hessian_operator.hpp"
#include "solver/methods/method_base.hpp"

namespace descent {

template <class Real>
class NonlinearCg final : public MethodBase<Real> {
 public:
  NonlinearCg(LocalProblem<Real>& problem, const SolverSpec& spec);

 private:
  void iterate(StepStats& stats) override;
  HessianOperator<Real> hessian_;
  std::vector<Real> g_, d_, dir_, hdir_;
};

}  // namespace descent
