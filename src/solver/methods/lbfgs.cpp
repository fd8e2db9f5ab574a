#include "solver/methods/lbfgs.hpp"

namespace descent {

template <class Real>
Lbfgs<Real>::Lbfgs(LocalProblem<Real>& problem, const SolverSpec& spec)
    : MethodBase<Real>(problem, spec) {
  for (auto* v : {&g_, &d_, &r_, &q_last_, &g_last_}) v->assign(this->size(), Real(0));
}

template <class Real>
void Lbfgs<Real>::iterate(StepStats& stats) {
  const std::size_t n = this->size();
  const std::size_t m = static_cast<std::size_t>(this->spec_.history);
  history_.clear();
  bool have_last = false;
  double scale = 1;  // s.y / y.P^-1 y of the newest pair
  for (int k = 0; k < this->spec_.iterations; ++k) {
    const bool refresh = k % this->spec_.hessian_interval == 0;
    this->gradient(this->q_.data(), g_.data(), refresh ? d_.data() : nullptr, refresh);
    if (have_last) {
      Pair pair;
      if (history_.size() == m) {  // reuse the oldest pair's storage
        pair = std::move(history_.front());
        history_.pop_front();
      }
      pair.s.resize(n);
      pair.y.resize(n);
      for (std::size_t dof = 0; dof < n; ++dof) {
        pair.s[dof] = this->q_[dof] - q_last_[dof];
        pair.y[dof] = g_[dof] - g_last_[dof];
      }
      // y . P^-1 y: with a preconditioner other than D^-1 one more
      // application (into r_, free until the recursion below).
      const bool general = this->preconditioner() != nullptr;
      if (general) this->precondition(pair.y.data(), d_.data(), r_.data());
      double dots[2] = {this->local_dot(pair.s.data(), pair.y.data()),
                        general ? this->local_dot(pair.y.data(), r_.data())
                                : this->local_weighted_norm2(pair.y.data(), d_.data())};
      this->problem_.global_dots(dots, 2);
      // Only pairs of positive curvature keep the inverse estimate SPD.
      if (dots[0] > 0 && dots[1] > 0) {
        pair.rho = 1.0 / dots[0];
        scale = dots[0] / dots[1];
        history_.push_back(std::move(pair));
      }
    }
    // Two-loop recursion: r = H_k g.
    r_ = g_;
    std::vector<double> a(history_.size());
    for (std::size_t i = history_.size(); i-- > 0;) {
      double dot = this->local_dot(history_[i].s.data(), r_.data());
      this->problem_.global_dots(&dot, 1);
      a[i] = history_[i].rho * dot;
      const Real ai = static_cast<Real>(a[i]);
      const Real* y = history_[i].y.data();
      for (std::size_t dof = 0; dof < n; ++dof) r_[dof] -= ai * y[dof];
    }
    const Real s0 = static_cast<Real>(history_.empty() ? 1.0 : scale);
    if (this->preconditioner()) {
      this->precondition(r_.data(), d_.data(), r_.data());
      for (std::size_t dof = 0; dof < n; ++dof) r_[dof] *= s0;
    } else {
      for (std::size_t dof = 0; dof < n; ++dof) r_[dof] *= s0 / d_[dof];
    }
    for (std::size_t i = 0; i < history_.size(); ++i) {
      double dot = this->local_dot(history_[i].y.data(), r_.data());
      this->problem_.global_dots(&dot, 1);
      const Real c = static_cast<Real>(a[i] - history_[i].rho * dot);
      const Real* s = history_[i].s.data();
      for (std::size_t dof = 0; dof < n; ++dof) r_[dof] += c * s[dof];
    }
    q_last_ = this->q_;
    g_last_ = g_;
    have_last = true;
    const Real alpha = static_cast<Real>(this->alpha_);
    Real* next = this->move_target();
    for (std::size_t dof = 0; dof < n; ++dof) next[dof] = this->q_[dof] - alpha * r_[dof];
    this->finish_move();
    stats.iterations = k + 1;
    this->report(k + 1);
    const auto outcome = this->check(k, stats);
    if (MethodBase<Real>::ends_step(outcome)) break;
    if (outcome == MethodBase<Real>::Check::rolled_back) {
      history_.clear();
      have_last = false;
    }
  }
}

template class Lbfgs<double>;
template class Lbfgs<float>;

}  // namespace descent
