#pragma once
// `lbfgs` (paper 1, §3): limited-memory BFGS with m = solver.history pairs
// (s, y) and the Jacobi preconditioner as the initial inverse Hessian,
// scaled by s.y / y.P^-1 y (paper 1, §4.1: "diag^-1(H) as the initial
// inverse Hessian estimate"); q <- q - alpha r with r from the two-loop
// recursion, under the paper's step control (a rollback clears the history).
// Collectives per iteration with h pairs stored: 1 ([s.y, y.P^-1 y] fused)
// + 2h (each two-loop inner product depends on the one before), plus the
// energy checks.
#include <deque>

#include "solver/methods/method_base.hpp"

namespace descent {

template <class Real>
class Lbfgs final : public MethodBase<Real> {
 public:
  Lbfgs(LocalProblem<Real>& problem, const SolverSpec& spec);

 private:
  void iterate(StepStats& stats) override;
  struct Pair {
    std::vector<Real> s, y;
    double rho;  // 1 / s.y
  };
  std::deque<Pair> history_;
  std::vector<Real> g_, d_, r_, q_last_, g_last_;
};

}  // namespace descent
