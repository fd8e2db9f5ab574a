#include "solver/methods/nesterov.hpp"

#include <algorithm>

namespace descent {

template <class Real>
Nesterov<Real>::Nesterov(LocalProblem<Real>& problem, const SolverSpec& spec)
    : MethodBase<Real>(problem, spec) {
  for (auto* v : {&g_, &d_, &q_prev_, &x_}) v->resize(this->size());
}

template <class Real>
void Nesterov<Real>::iterate(StepStats& stats) {
  const std::size_t n = this->size();
  q_prev_ = this->q_;
  int momentum_k = 0;  // iterations since the last (re)start of the momentum
  for (int k = 0; k < this->spec_.iterations; ++k) {
    const bool refresh = k % this->spec_.hessian_interval == 0;
    // The momentum restarts where the contact guard cut the last move or
    // runs its safe mode (MethodBase::momentum_guarded).
    if (!this->momentum_guarded()) momentum_k = 0;
    const Real beta = Real(momentum_k) / Real(momentum_k + 3);
    const Real* q = this->q_.data();
    // Held dofs have q = q_prev, so x keeps them in place.
#pragma omp parallel for schedule(static)
    for (std::size_t dof = 0; dof < n; ++dof) x_[dof] = q[dof] + beta * (q[dof] - q_prev_[dof]);
    // With a contact barrier the extrapolation is a move like the
    // iterates' (the guard cuts and proves it); one that had to be cut is
    // not made. Its gradient raises d where pairs stiffen (gradient()).
    if (momentum_k > 0) {
      this->guard_extrapolation(x_.data());
      if (!this->momentum_guarded()) std::copy(this->q_.begin(), this->q_.end(), x_.begin());
    }
    this->gradient(x_.data(), g_.data(), d_.data(), refresh);
    const Real alpha = static_cast<Real>(this->alpha_);
    // The new iterate, computed from q (target may be q) and x.
    Real* target = this->move_target();
    if (this->preconditioner()) {
      this->precondition(g_.data(), d_.data(), g_.data());
#pragma omp parallel for schedule(static)
      for (std::size_t dof = 0; dof < n; ++dof) {
        q_prev_[dof] = q[dof];
        target[dof] = x_[dof] - alpha * g_[dof];
      }
    } else {
#pragma omp parallel for schedule(static)
      for (std::size_t dof = 0; dof < n; ++dof) {
        q_prev_[dof] = q[dof];
        target[dof] = x_[dof] - alpha * g_[dof] / d_[dof];
      }
    }
    this->finish_move(x_.data());
    ++momentum_k;
    stats.iterations = k + 1;
    this->report(k + 1);
    const auto outcome = this->check(k, stats);
    if (MethodBase<Real>::ends_step(outcome)) break;
    if (outcome == MethodBase<Real>::Check::rolled_back) {
      q_prev_ = this->q_;
      momentum_k = 0;
    }
  }
}

template class Nesterov<double>;
template class Nesterov<float>;

}  // namespace descent
