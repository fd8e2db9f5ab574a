#include "solver/methods/method_base.hpp"

#include <algorithm>
#include <limits>

#include "kernels/vertex.hpp"
#include "solver/methods/optimized_init.hpp"

namespace descent {

template <class Real>
MethodBase<Real>::MethodBase(LocalProblem<Real>& problem, const SolverSpec& spec)
    : problem_(problem), spec_(spec), alpha_(spec.alpha_max), fixed_(problem.fixed_axes()) {
  const std::size_t n = 3 * static_cast<std::size_t>(problem.num_vertices());
  for (auto* v : {&y_, &qt_, &q_, &q_checked_}) v->resize(n);
}

template <class Real>
StepStats MethodBase<Real>::step(BodyState<Real>& state) {
  const double t_next = state.time + static_cast<double>(problem_.dt());
  problem_.begin_step(t_next);
  // The prediction of q_{t+1} of paper 1, §4.4, as in ChebyshevDescent.
  const Real h = problem_.dt();
  const Real w_velocity = spec_.init == "position" ? Real(0) : Real(1);
  const Real w_acceleration =
      spec_.init == "constant_acceleration" ? static_cast<Real>(spec_.eta) : Real(0);
  const std::size_t n = q_.size();
  for (std::size_t k = 0; k < n; ++k) {
    const Real qt = state.q[k], v = state.v[k];
    qt_[k] = qt;
    y_[k] = qt + h * v;
    q_[k] = qt + h * (w_velocity * v + w_acceleration * (v - state.v_prev[k]));
  }
  if (spec_.init == "optimized") {  // Eq. 10
    std::vector<Real> hv(n);
    for (std::size_t k = 0; k < n; ++k) hv[k] = h * state.v[k];
    const Real d =
        static_cast<Real>(optimized_step_weight(problem_, qt_.data(), y_.data(), hv.data()));
    for (std::size_t k = 0; k < n; ++k) q_[k] = qt_[k] + d * hv[k];
  }
  problem_.hold_fixed(t_next, q_.data());

  StepStats stats;
  alpha_ = std::min(spec_.alpha_max, alpha_ / spec_.gamma);
  first_check_ = true;
  checked_finite_ = true;
  checked_energy_ = 0;
  initial_local_energy_ = problem_.energy_changes_within_step()
                              ? Energy{}
                              : problem_.local_energy(q_.data(), y_.data(), qt_.data());
  q_checked_ = q_;
  report(0);
  iterate(stats);

  const Real inv_h = Real(1) / h;
  for (std::size_t k = 0; k < n; ++k) {
    state.v_prev[k] = state.v[k];
    state.v[k] = (q_[k] - qt_[k]) * inv_h;
    state.q[k] = q_[k];
  }
  state.time = t_next;
  stats.alpha = alpha_;
  if (stats.energy == 0) stats.energy = checked_energy_;
  return stats;
}

template <class Real>
void MethodBase<Real>::gradient(const Real* q, Real* g, Real* diag) {
  const auto assembled = problem_.elastic_gradient(q, diag != nullptr);
  const Real* a = assembled.values;
  const int width = assembled.width;
  const auto& mass = problem_.mass();
  const VertexTerms<Real> terms = problem_.vertex_terms();
  const Real* floor = problem_.diagonal_floor().data();
  const Real* force = problem_.external_force().data();
  const std::size_t n = q_.size();
#pragma omp parallel for schedule(static)
  for (std::size_t dof = 0; dof < n; ++dof) {
    const std::size_t v = dof / 3;
    const int axis = static_cast<int>(dof % 3);
    if (diag) diag[dof] = dof_diagonal(terms, mass[v], a[width * v + 3 + axis], floor[dof]);
    g[dof] = held(dof) ? Real(0)
                       : dof_gradient(terms, mass[v], a[width * v + axis], q[dof], y_[dof],
                                      qt_[dof], force[dof], axis);
  }
}

template <class Real>
double MethodBase<Real>::local_dot(const Real* a, const Real* b) const {
  const std::size_t n = 3 * static_cast<std::size_t>(problem_.mesh().num_owned);
  double sum = 0;
#pragma omp parallel for schedule(static) reduction(+ : sum)
  for (std::size_t k = 0; k < n; ++k) sum += static_cast<double>(a[k]) * b[k];
  return sum;
}

template <class Real>
double MethodBase<Real>::local_weighted_norm2(const Real* a, const Real* d) const {
  const std::size_t n = 3 * static_cast<std::size_t>(problem_.mesh().num_owned);
  double sum = 0;
#pragma omp parallel for schedule(static) reduction(+ : sum)
  for (std::size_t k = 0; k < n; ++k) sum += static_cast<double>(a[k]) * a[k] / d[k];
  return sum;
}

// As ChebyshevDescent's check: the initial guess's energy rides in the first
// check's reduction; with conversion the checked state is re-evaluated under
// the same interpolants; a rise within round-off is no rise.
template <class Real>
typename MethodBase<Real>::Check MethodBase<Real>::check(int k, StepStats& stats) {
  const bool last = k + 1 == spec_.iterations;
  if ((k + 1) % spec_.check_interval != 0 && !last) return Check::none;
  const bool reevaluate = problem_.energy_changes_within_step();
  const Energy local[2] = {problem_.local_energy(q_.data(), y_.data(), qt_.data()),
                           reevaluate
                               ? problem_.local_energy(q_checked_.data(), y_.data(), qt_.data())
                               : initial_local_energy_};
  const EnergySums sums = problem_.global_energies(local, first_check_ || reevaluate ? 2 : 1);
  if (first_check_ || reevaluate) {
    checked_energy_ = sums.energy[1].value;
    checked_finite_ = sums.finite[1];
  }
  if (first_check_) {
    stats.initial_energy = checked_energy_;
    first_check_ = false;
  }
  const double tolerance = 1024 * std::numeric_limits<Real>::epsilon() * sums.energy[0].magnitude;
  stats.energy_tolerance = tolerance;
  if (sums.finite[0] && (!checked_finite_ || sums.energy[0].value <= checked_energy_ + tolerance)) {
    checked_energy_ = sums.energy[0].value;
    checked_finite_ = true;
    q_checked_ = q_;
    return Check::accepted;
  }
  q_ = q_checked_;
  ++stats.rollbacks;
  if (!sums.finite[0]) ++stats.nonfinite_rollbacks;
  alpha_ *= spec_.gamma;
  if (alpha_ < spec_.alpha_min) {
    stats.stalled = true;
    return Check::stalled;
  }
  return Check::rolled_back;
}

template class MethodBase<double>;
template class MethodBase<float>;

}  // namespace descent
