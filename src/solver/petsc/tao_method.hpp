#pragma once
// PETSc TAO's unconstrained minimisers on our eps (solver.method = "tao_bncg":
// TAO's bound-constrained nonlinear CG, "tao_blmvm": its limited-memory
// variable-metric quasi-Newton; docs/tao.md), as independent peers of ncg and
// lbfgs in `descent study`: the same eps, gradient, held dofs and initial
// guess (MethodBase), TAO's own directions and line search (More-Thuente,
// TAO's default for both).
//
// Layout. One PETSc Vec of the free dofs: rank r holds, in order, the dofs
// 3 v + i of its owned vertices v in [0, num_owned) that are not held (held
// dofs stay at their prescribed values in q and never reach TAO; their
// gradient is 0 anyway). Shared vertices owned elsewhere get their owner's
// values through one Halo sum in which only the owner contributes (the
// others add zeros, so every sharer holds the owner's value exactly).
// TAO's variables are x = D0^1/2 q per free dof, D0 the Jacobi diagonal of
// the Hessian at the step's initial guess (one gradient-and-diagonal pass per
// step), so TAO's identity metric is the Jacobi preconditioner our ncg and
// lbfgs use, and its gradient is D0^-1/2 g. Unscaled, TAO's first step -g
// inverts elements and its line search fails (-descent_tao_jacobi false in
// the PETSc options turns the scaling off).
//
// Outside eps's domain (an inverted element in a line-search trial) the
// objective is a finite wall (see evaluate in tao_method.cpp), so More-
// Thuente backtracks.
//
// Per objective-and-gradient evaluation (TAO always asks for both): that
// halo sum, our gradient (one halo exchange of partial sums) and the energy
// (one EnergyReduction allreduce); the owned free dofs of the gradient are
// complete on their owner and go to TAO's gradient Vec. Per TAO iteration,
// TAO's own inner products and norms (VecDot, VecNorm, ...: MPI_Allreduce
// inside PETSc, counted by petsc_collectives()), and the monitor writes
// TAO's iterate into q (one more halo sum) to report it to the study.
//
// Stopping: TAO's iteration cap is solver.iterations; its only tolerance is
// |g| <= solver.newton_tolerance |g0| (Newton's relative gradient criterion,
// here on the scaled gradient;
// TAO's default absolute and f-relative ones are switched off so the study
// sees every iteration). TAO also stops where its line search fails. With
// solver.accuracy TAO's eps every check_interval iterations goes to the
// energy checks' estimator (solver/check_history.hpp, no bound), which ends
// the solve on a confirmed reading (TAO_CONVERGED_USER).
// solver.petsc_options (-tao_bncg_type fr, -tao_ls_type armijo, ...) apply
// after these settings (TaoSetFromOptions).
//
// Communicator: PETSC_COMM_WORLD when the mesh spans several ranks,
// MPI_COMM_SELF for a one-rank mesh (a serial run beside a distributed one).
#include <memory>
#include <string>
#include <vector>

#include "solver/methods/method_base.hpp"

namespace descent {

template <class Real>
class TaoMethod final : public MethodBase<Real> {
 public:
  // type: "bncg" or "blmvm" (TAO's names). Collective; throws InputError
  // naming the missing package in a build without PETSc.
  TaoMethod(LocalProblem<Real>& problem, const SolverSpec& spec, const char* type);
  ~TaoMethod() override;
  TaoMethod(const TaoMethod&) = delete;
  TaoMethod& operator=(const TaoMethod&) = delete;

  // Of the last step: objective-and-gradient evaluations, and TAO's reason
  // for stopping (TaoConvergedReason's name).
  int evaluations() const { return evaluations_; }
  // Of which outside eps's domain (an inverted element; see evaluate).
  int nonfinite_evaluations() const { return nonfinite_; }
  const std::string& reason() const { return reason_; }
  // TAO's |D0^-1/2 g| (2-norm over the free dofs of all ranks) at each of
  // its monitored iterates of the last step, the initial guess first.
  const std::vector<double>& gradient_norms() const { return gradient_norms_; }
  // This rank's share (owned free dofs) of our |grad eps|^2, unscaled, at the
  // same iterates (NaN where TAO's iterate was not its last evaluation).
  const std::vector<double>& local_gradient_norms2() const { return local_norms2_; }

  // For TAO's callbacks (tao_method.cpp), x and g this rank's entries of
  // TAO's Vecs. Objective and gradient at x; g gets the owned free dofs'
  // gradient.
  double evaluate(const double* x, double* g);
  // TAO's iteration k is done at x, with |g| = gnorm: reported to the
  // observer.
  void monitor(int k, double gnorm, const double* x);
  struct Petsc;  // PETSc objects (tao_method.cpp)

 private:
  void iterate(StepStats& stats) override;
  // q_ from TAO's free dofs, shared vertices from their owners.
  void unpack(const double* x);

  const char* type_;
  std::vector<std::size_t> free_;  // local dof of each of this rank's Vec entries
  std::vector<Real> g_, d_;
  std::vector<double> scale_;  // per Vec entry: sqrt of the Jacobi diagonal (or 1)
  std::vector<double> gradient_norms_, local_norms2_, last_x_;
  double last_norm2_ = 0;
  double last_finite_ = 0;  // eps at the last finite evaluation of the step
  int nonfinite_ = 0;
  std::unique_ptr<Petsc> petsc_;
  int evaluations_ = 0;
  int reported_ = 0;
  std::string reason_;
};

}  // namespace descent
