#pragma once
// `nesterov` (paper 1, §4.3, Fig. 5): Jacobi-preconditioned descent with
// Nesterov's momentum for a merely convex problem (strong-convexity
// parameter 0, as the paper notes is usual):
//   x = q + k/(k+3) (q - q_prev),   q_prev <- q,   q <- x - alpha g(x)/d.
// The momentum restarts with every rollback of the paper's step control.
// No inner product: collectives are the energy checks only. With a contact
// barrier (docs/contact.md) x is a guarded move from q like the iterates,
// and the momentum also restarts where the guard cut a move between bodies.
#include "solver/methods/method_base.hpp"

namespace descent {

template <class Real>
class Nesterov final : public MethodBase<Real> {
 public:
  Nesterov(LocalProblem<Real>& problem, const SolverSpec& spec);

 private:
  void iterate(StepStats& stats) override;
  std::vector<Real> g_, d_, q_prev_, x_;
};

}  // namespace descent
