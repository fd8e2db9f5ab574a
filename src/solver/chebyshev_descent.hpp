#pragma once
// The paper's method (paper 1, Algorithm 1; DESIGN §1): Jacobi-preconditioned
// descent with Chebyshev acceleration, the Hessian diagonal re-evaluated every
// M iterations, and step-length control by the total energy every
// check_interval iterations: if the energy rose since the last check, roll
// back to the checked state, alpha <- gamma alpha, restart Chebyshev; end the
// step once alpha < alpha_min. Each step starts from alpha_prev / gamma
// (capped at alpha_max). The energy check is the only collective.
#include <vector>

#include "io/scene.hpp"
#include "solver/local_problem.hpp"
#include "solver/stepper.hpp"

namespace descent {

template <class Real>
class ChebyshevDescent final : public Stepper<Real> {
 public:
  ChebyshevDescent(LocalProblem<Real>& problem, const SolverSpec& spec);
  StepStats step(BodyState<Real>& state) override;

  // The step length carried from step to step (part of a checkpoint).
  double alpha() const override { return alpha_; }
  void set_alpha(double alpha) override { alpha_ = alpha; }

  // LocalProblem::local_region_sums at the end of the last step (the
  // reaction is the gradient of that step's potential).
  std::vector<double> local_region_sums() override {
    return problem_.local_region_sums(q_.data(), y_.data(), qt_.data());
  }

 private:
  LocalProblem<Real>& problem_;
  SolverSpec spec_;
  double alpha_;
  std::vector<Real> y_, qt_, q_, q_prev_, q_checked_, q_next_, diag_;
};

}  // namespace descent
