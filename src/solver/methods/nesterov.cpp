#include "solver/methods/nesterov.hpp"

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
    const Real beta = Real(momentum_k) / Real(momentum_k + 3);
    Real* q = this->q_.data();
    // Held dofs have q = q_prev, so x keeps them in place.
#pragma omp parallel for schedule(static)
    for (std::size_t dof = 0; dof < n; ++dof) x_[dof] = q[dof] + beta * (q[dof] - q_prev_[dof]);
    this->gradient(x_.data(), g_.data(), refresh ? d_.data() : nullptr);
    const Real alpha = static_cast<Real>(this->alpha_);
    if (this->preconditioner()) {
      this->precondition(g_.data(), d_.data(), g_.data());
#pragma omp parallel for schedule(static)
      for (std::size_t dof = 0; dof < n; ++dof) {
        q_prev_[dof] = q[dof];
        q[dof] = x_[dof] - alpha * g_[dof];
      }
    } else {
#pragma omp parallel for schedule(static)
      for (std::size_t dof = 0; dof < n; ++dof) {
        q_prev_[dof] = q[dof];
        q[dof] = x_[dof] - alpha * g_[dof] / d_[dof];
      }
    }
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
