#include "solver/methods/method_base.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "kernels/vertex.hpp"
#include "solver/preconditioners/make_preconditioner.hpp"
#include "solver/spectrum.hpp"
#include "solver/step_control.hpp"

namespace descent {

template <class Real>
MethodBase<Real>::MethodBase(LocalProblem<Real>& problem, const SolverSpec& spec, bool own_guess)
    : problem_(problem),
      spec_(spec),
      alpha_(spec.alpha_max),
      fixed_(problem.fixed_axes()),
      barrier_(problem.has_contact_barrier()),
      steps_since_refresh_(spec.preconditioner_refresh),
      own_guess_(own_guess) {
  const std::size_t n = 3 * static_cast<std::size_t>(problem.num_vertices());
  for (auto* v : {&y_, &qt_, &q_, &q_checked_}) v->resize(n);
  // After qt_ has its memory: a multilevel P^-1 reads the obstacles' lags
  // from there at each refresh.
  preconditioner_ = make_host_preconditioner(problem, spec, qt_.data());
}

template <class Real>
void MethodBase<Real>::refresh_preconditioner(const Real* q) {
  if (preconditioner_) preconditioner_->refresh(q);
}

template <class Real>
StepStats MethodBase<Real>::step(BodyState<Real>& state) {
  const double t_next = state.time + static_cast<double>(problem_.dt());
  problem_.begin_step(t_next);
  predict_positions(spec_, problem_, state, qt_.data(), y_.data(), q_.data(),
                    this->take_guess_from_start());
  problem_.hold_fixed(t_next, q_.data());
  if (preconditioner_ && steps_since_refresh_++ >= spec_.preconditioner_refresh - 1) {
    preconditioner_->refresh(q_.data());
    steps_since_refresh_ = 1;
  }

  StepStats stats;
  alpha_ = std::min(spec_.alpha_max, alpha_ / spec_.gamma);
  check_ = EnergyCheck(problem_.energy_changes_within_step(), problem_.energy_noise_floor());
  if (!own_guess_) {
    initial_local_energy_ = check_.reevaluate() ? Energy{} : local_energy_at(q_.data());
    q_checked_ = q_;
    report(0);
  }
  history_ = CheckHistory();
  restart_at_ = 0;
  stats.error_estimate = std::numeric_limits<double>::quiet_NaN();
  step_velocity_ = state.v.data();
  iterate(stats);
  step_velocity_ = nullptr;
  // No state with finite energy: the body keeps the step's start (the last
  // good state) and the caller stops the run.
  if (!stats.finite) return stats;

  problem_.end_contact_step(q_.data(), qt_.data());
  commit_step(q_.data(), qt_.data(), problem_.dt(), t_next, state);
  stats.alpha = this->memory().alpha;
  if (stats.energy == 0) stats.energy = check_.checked_energy();
  return stats;
}

template <class Real>
void MethodBase<Real>::gradient(const Real* q, Real* g, Real* diag, bool refresh) {
  const auto assembled = problem_.elastic_gradient(q, refresh);
  if (barrier_)
    problem_.add_contact_gradient(q, qt_.data(), assembled.width, refresh ? nullptr : diag);
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
    if (refresh) diag[dof] = dof_diagonal(terms, mass[v], a[width * v + 3 + axis], floor[dof]);
    g[dof] = held(dof) ? Real(0)
                       : dof_gradient(terms, mass[v], a[width * v + axis], q[dof], y_[dof],
                                      qt_[dof], force[dof], axis);
  }
}

template <class Real>
Real* MethodBase<Real>::move_target() {
  if (!barrier_) return q_.data();
  target_.resize(q_.size());
  return target_.data();
}

template <class Real>
void MethodBase<Real>::finish_move(const Real* from) {
  if (!barrier_) return;
  problem_.guard_contact_moves(from ? from : q_.data(), target_.data());
  q_.swap(target_);
}

template <class Real>
void MethodBase<Real>::guard_extrapolation(Real* to) {
  if (barrier_) problem_.guard_contact_moves(q_.data(), to);
}

template <class Real>
bool MethodBase<Real>::momentum_guarded() const {
  const BodyContact<Real>* bodies = problem_.body_contact();
  return !bodies || (!bodies->safe_guard_on() && !bodies->moves_cut());
}

template <class Real>
Energy MethodBase<Real>::local_energy_at(const Real* q) {
  Energy e = problem_.local_energy(q, y_.data(), qt_.data());
  if (BodyContact<Real>* bodies = problem_.body_contact()) {
    const double pairs = bodies->local_energy(q);
    e = {e.value + pairs, e.magnitude + in_double_units<Real>(std::abs(pairs))};
  }
  return e;
}

template <class Real>
void MethodBase<Real>::precondition(const Real* g, const Real* d, Real* z) {
  if (preconditioner_) {
    if (g != z) {
      preconditioner_->apply(g, z);
      return;
    }
    // In place: P^-1 reads its input to the end.
    scratch_.resize(q_.size());
    preconditioner_->apply(g, scratch_.data());
    std::copy(scratch_.begin(), scratch_.end(), z);
    return;
  }
  const std::size_t n = q_.size();
#pragma omp parallel for schedule(static)
  for (std::size_t dof = 0; dof < n; ++dof) z[dof] = g[dof] / d[dof];
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

// The shared energy check (solver/step_control.hpp) after iteration k.
template <class Real>
typename MethodBase<Real>::Check MethodBase<Real>::check(int k, StepStats& stats) {
  const bool last = k + 1 == spec_.iterations;
  if ((k + 1) % spec_.check_interval != 0 && !last) return Check::none;
  const Energy local[2] = {local_energy_at(q_.data()), check_.reevaluate()
                                                           ? local_energy_at(q_checked_.data())
                                                           : initial_local_energy_};
  const EnergySums sums = problem_.global_energies(local, check_.count());
  BodyContact<Real>* bodies = problem_.body_contact();
  if (check_.accept(sums, stats)) {
    q_checked_ = q_;
    // Pairs between bodies found again where a surface vertex has drifted
    // half its cap from where they were found (as chebyshev_descent.cpp).
    if (bodies && problem_.global_max(bodies->needs_rebuild(q_.data()) ? 1.0 : 0.0) > 0)
      bodies->rebuild_here(q_.data());
    // The accuracy target from the accepted checks' energies
    // (solver/check_history.hpp): with a bound as chebyshev reads it (before
    // the bound's count only when far below the target), without one on a
    // confirmed reading.
    if (history_.empty()) history_.restart(stats.initial_energy);
    const int since_restart = k + 1 - restart_at_;
    history_.record(since_restart, check_.checked_energy());
    const double phi = bound_rate(), target = spec_.accuracy;
    const AccuracyReading reading =
        history_.read(stats.initial_energy, phi, target, stats.energy_tolerance);
    stats.error_estimate = reading.estimate;
    if (target > 0) {
      const bool past_bound =
          phi <= 0 || since_restart >= chebyshev_iterations_for(phi, kTargetShare * target);
      const bool met =
          phi > 0 ? reading.far_below || (reading.below && past_bound) : reading.confirmed;
      if (met) return Check::converged;
      // Every change within round-off: more iterations cannot show progress
      // (as chebyshev_descent.cpp ends such a step).
      if (reading.at_resolution && past_bound) {
        stats.at_resolution = true;
        return Check::converged;
      }
    }
    return Check::accepted;
  }
  q_ = q_checked_;
  // A path the guard could not prove free of crossings made the energy
  // infinite on every rank: the safe guard for the rest of the step.
  if (bodies && !sums.finite[0]) bodies->use_safe_guard();
  history_.restart(check_.checked_energy());
  restart_at_ = k + 1;
  if (preconditioner_) {
    preconditioner_->refresh(q_.data());
    steps_since_refresh_ = 1;
  }
  ++stats.rollbacks;
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
