#pragma once
// `pd_chebyshev` (Wang 2015, Chebyshev-accelerated Jacobi projective
// dynamics; paper 1, Fig. 4) on the `arap` energy. With the projections R_e
// held, the PD global matrix A = M/h^2 (+ c M/h) + sum_e 2 mu V_e B_e^T B_e
// is constant, and A q - b(R(q)) is exactly grad eps(q) for arap (P = 2 mu
// (F - R)), so one PD iteration with one Jacobi sweep of the global solve is
//   q <- q - diag(A)^-1 grad eps(q),
// accelerated by the same Chebyshev recurrence (solver.rho, chebyshev_delay)
// and under the same step control as the other methods. The only difference
// from `chebyshev` is the preconditioner: diag(A), constant, instead of the
// Hessian diagonal every M iterations. No inner product. With
// solver.accuracy the energy checks' estimate is read with the bound of
// solver.rho, as chebyshev's fixed parameters read theirs.
#include "solver/methods/method_base.hpp"

namespace descent {

template <class Real>
class PdChebyshev final : public MethodBase<Real> {
 public:
  PdChebyshev(LocalProblem<Real>& problem, const SolverSpec& spec);

 private:
  void iterate(StepStats& stats) override;
  double bound_rate() const override;
  std::vector<Real> g_, d_, q_prev_;
};

}  // namespace descent
