#pragma once
// The paper's method (paper 1, Algorithm 1; DESIGN §1), the one Chebyshev
// stepper of every backend: Jacobi-preconditioned descent with Chebyshev
// acceleration, the Hessian diagonal re-evaluated every M iterations, and
// step-length control by the total energy every check_interval iterations.
// The iterates live in an IterationEngine (the host's or a device's); this
// class keeps the step control on the host and only launches between
// checks. The energy check is the only collective of the iterations.
//
// Parameters (solver.chebyshev_parameters):
//   fixed: rho, chebyshev_delay, phases and alpha_max as given; if the
//     energy rose since the last check, roll back to the checked state,
//     alpha <- gamma alpha, restart Chebyshev; each step starts from
//     alpha_prev / gamma capped at alpha_max (the paper's control).
//   auto: [a, b] bounds the spectrum of D^-1 H (solver/spectrum.hpp),
//     estimated by Lanczos at the step's initial guess (the bottom also from
//     a rigid translation's quotient) and reused for spectrum_interval
//     steps; alpha = 2 / (a + b), rho = (b - a) / (b + a); plain iterations
//     through the first check, then the semi-iterative method. A rise the
//     Chebyshev bound allows (its error is not monotone) is passed through,
//     keeping the best checked state; a larger rise or a non-finite energy
//     rolls back to it with b <- b / gamma and restarts the same way, and
//     the next step estimates anew.
// With solver.accuracy the step ends at the first check where the energy
// decrease says the relative error is below the target and the Chebyshev
// bound agrees (or the decrease alone says it is far below), within
// solver.iterations.
#include <limits>
#include <memory>
#include <vector>

#include "io/scene.hpp"
#include "solver/iteration_engine.hpp"
#include "solver/local_problem.hpp"
#include "solver/stepper.hpp"

namespace descent {

template <class Real>
class ChebyshevDescent final : public Stepper<Real> {
 public:
  ChebyshevDescent(LocalProblem<Real>& problem, const SolverSpec& spec,
                   std::unique_ptr<IterationEngine<Real>> engine);
  StepStats step(BodyState<Real>& state) override;

  StepMemory memory() const override { return memory_; }
  void set_memory(const StepMemory& memory) override { memory_ = memory; }

  // LocalProblem::local_region_sums at the end of the last step (the
  // reaction is the gradient of that step's potential).
  std::vector<double> local_region_sums() override {
    return problem_.local_region_sums(q_, y_, qt_);
  }

  const Preconditioner<Real>* preconditioner() const override { return engine_->preconditioner(); }
  const IterationEngine<Real>& engine() const { return *engine_; }
  IterationEngine<Real>& engine() { return *engine_; }

  // Wall time of all steps so far: iterating (launch to completion), the
  // energy checks (reduction, allreduce, accept or roll back) and the
  // spectrum estimates.
  double iterate_seconds() const { return iterate_seconds_; }
  double check_seconds() const { return check_seconds_; }
  double estimate_seconds() const { return estimate_seconds_; }
  // Rebuilding a preconditioner other than D^-1 (at step starts, rollbacks).
  double refresh_seconds() const { return refresh_seconds_; }
  int estimates() const { return estimates_; }

 private:
  // Whether solver.preconditioner = "auto" takes the multilevel one here
  // (it does for the automatic parameters on the CPU, for a body with
  // inertia or held dofs). Collective.
  bool automatic_multilevel_fits();
  // Estimates the spectrum when the memory says it is due (first step, after
  // a rollback, every spectrum_interval steps). True when it did: the
  // engine's diagonal is then fresh at the initial guess.
  bool prepare_spectrum(const BodyState<Real>& state, StepStats& stats);
  // The Lanczos start vector into the engine's staging: the velocity (the
  // motion the step continues, rich in the slow modes), else the
  // acceleration of gravity and loads, plus a little deterministic noise by
  // global id so that every mode is present. Returns the smallest Rayleigh
  // quotient of a rigid translation without its strain (0: none, e.g.
  // quasi-static). One allreduce for both.
  double stage_start_vector(const BodyState<Real>& state);

  LocalProblem<Real>& problem_;
  SolverSpec spec_;
  StepMemory memory_;
  std::unique_ptr<IterationEngine<Real>> engine_;
  // The engine's host buffers, 3 per local vertex: the step's inertial
  // target and start positions, and the iterate (initial guess going in,
  // result coming out).
  Real *y_, *qt_, *q_;
  bool force_on_engine_nonzero_ = true;  // until the first upload says otherwise
  std::vector<Real> interpolants_;
  double iterate_seconds_ = 0, check_seconds_ = 0, estimate_seconds_ = 0, refresh_seconds_ = 0;
  int estimates_ = 0;
  // Steps since P^-1 was last rebuilt at a step's start: a run (and a
  // restart, which therefore continues bit for bit only with
  // solver.preconditioner_refresh = 1) rebuilds it at its first step.
  int steps_since_refresh_ = std::numeric_limits<int>::max();
};

}  // namespace descent
