#include "solver/methods/nonlinear_cg.hpp"

namespace descent {

template <class Real>
NonlinearCg<Real>::NonlinearCg(LocalProblem<Real>& problem, const SolverSpec& spec)
    : MethodBase<Real>(problem, spec), hessian_(problem) {
  for (auto* v : {&g_, &d_, &dir_, &hdir_}) v->assign(this->size(), Real(0));
}

template <class Real>
void NonlinearCg<Real>::iterate(StepStats& stats) {
  const std::size_t n = this->size();
  bool have_direction = false;
  double z_prev = 0;
  for (int k = 0; k < this->spec_.iterations; ++k) {
    const bool refresh = k % this->spec_.hessian_interval == 0;
    this->gradient(this->q_.data(), g_.data(), refresh ? d_.data() : nullptr, refresh);
    // z = P^-1 g into hdir_ (free until the curvature below) with a
    // preconditioner other than D^-1.
    const bool general = this->preconditioner() != nullptr;
    if (general) this->precondition(g_.data(), d_.data(), hdir_.data());
    double dots[2] = {general ? this->local_dot(g_.data(), hdir_.data())
                              : this->local_weighted_norm2(g_.data(), d_.data()),
                      have_direction ? this->local_dot(g_.data(), dir_.data()) : 0.0};
    this->problem_.global_dots(dots, 2);
    const double z = dots[0];
    double beta = have_direction && z_prev > 0 ? z / z_prev : 0.0;
    double slope = -z + beta * dots[1];  // g . dq
    // Not a descent direction (P changed, or the energy is far from
    // quadratic): restart from the preconditioned gradient.
    if (slope >= 0) {
      beta = 0;
      slope = -z;
    }
    const Real b = static_cast<Real>(beta);
    if (general) {
#pragma omp parallel for schedule(static)
      for (std::size_t dof = 0; dof < n; ++dof) dir_[dof] = -hdir_[dof] + b * dir_[dof];
    } else {
#pragma omp parallel for schedule(static)
      for (std::size_t dof = 0; dof < n; ++dof) dir_[dof] = -g_[dof] / d_[dof] + b * dir_[dof];
    }
    hessian_.product(this->q_.data(), dir_.data(), hdir_.data(), this->qt_.data());
    double curvature = this->local_dot(dir_.data(), hdir_.data());
    this->problem_.global_dots(&curvature, 1);
    // Negative curvature along dq: the Jacobi scale (t = 1) instead.
    const double t = curvature > 0 ? -slope / curvature : 1.0;
    const Real step = static_cast<Real>(this->alpha_ * t);
    const Real* q = this->q_.data();
    Real* next = this->move_target();
#pragma omp parallel for schedule(static)
    for (std::size_t dof = 0; dof < n; ++dof) next[dof] = q[dof] + step * dir_[dof];
    this->finish_move();
    z_prev = z;
    // A move the body guard cut is no longer along dq: the next direction
    // starts again from the preconditioned gradient, as nesterov drops its
    // momentum there.
    have_direction = this->momentum_guarded();
    stats.iterations = k + 1;
    this->report(k + 1);
    const auto outcome = this->check(k, stats);
    if (MethodBase<Real>::ends_step(outcome)) break;
    if (outcome == MethodBase<Real>::Check::rolled_back) have_direction = false;
  }
}

template class NonlinearCg<double>;
template class NonlinearCg<float>;

}  // namespace descent
