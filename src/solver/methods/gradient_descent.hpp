#pragma once
// `gd` and `jacobi_gd` (paper 1, §3-4.1): q <- q - alpha P^-1 g with the
// paper's step control. jacobi_gd: P = diag(H), re-evaluated every M
// iterations (chebyshev without acceleration; no inner product). gd: P =
// max diag(H) times I, a scalar so that alpha = 1 is a stable scale for the
// plain gradient; the maximum costs one MPI_Allreduce every M iterations.
#include "solver/methods/method_base.hpp"

namespace descent {

template <class Real>
class GradientDescent final : public MethodBase<Real> {
 public:
  GradientDescent(LocalProblem<Real>& problem, const SolverSpec& spec, bool jacobi);

 private:
  void iterate(StepStats& stats) override;
  bool jacobi_;
  std::vector<Real> g_, d_;
};

}  // namespace descent
