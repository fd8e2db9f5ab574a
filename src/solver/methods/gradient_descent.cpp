#include "solver/methods/gradient_descent.hpp"

#include <algorithm>

namespace descent {

template <class Real>
GradientDescent<Real>::GradientDescent(LocalProblem<Real>& problem, const SolverSpec& spec,
                                       bool jacobi)
    : MethodBase<Real>(problem, spec), jacobi_(jacobi) {
  g_.resize(this->size());
  d_.resize(this->size());
}

template <class Real>
void GradientDescent<Real>::iterate(StepStats& stats) {
  const std::size_t n = this->size();
  Real scale = 1;  // gd: the global maximum of the diagonal
  for (int k = 0; k < this->spec_.iterations; ++k) {
    const bool refresh = k % this->spec_.hessian_interval == 0;
    this->gradient(this->q_.data(), g_.data(), refresh ? d_.data() : nullptr, refresh);
    if (refresh && !jacobi_) {
      Real local = 0;
      for (std::size_t dof = 0; dof < n; ++dof) local = std::max(local, d_[dof]);
      scale = static_cast<Real>(this->problem_.global_max(static_cast<double>(local)));
    }
    const Real alpha = static_cast<Real>(this->alpha_);
    const Real* q = this->q_.data();
    Real* next = this->move_target();
    if (jacobi_ && this->preconditioner()) {
      // P^-1 g in place of g (the gradient is not needed after).
      this->precondition(g_.data(), d_.data(), d_.data());
#pragma omp parallel for schedule(static)
      for (std::size_t dof = 0; dof < n; ++dof) next[dof] = q[dof] - alpha * d_[dof];
    } else {
#pragma omp parallel for schedule(static)
      for (std::size_t dof = 0; dof < n; ++dof)
        next[dof] = q[dof] - alpha * g_[dof] / (jacobi_ ? d_[dof] : scale);
    }
    this->finish_move();
    stats.iterations = k + 1;
    this->report(k + 1);
    if (MethodBase<Real>::ends_step(this->check(k, stats))) break;
  }
}

template class GradientDescent<double>;
template class GradientDescent<float>;

}  // namespace descent
