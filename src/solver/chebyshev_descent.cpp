#include "solver/chebyshev_descent.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "common/error.hpp"
#include "kernels/vertex.hpp"
#include "solver/methods/chebyshev_phases.hpp"
#include "solver/methods/optimized_init.hpp"

namespace descent {

template <class Real>
BodyState<Real> rest_state(const LocalMesh& mesh) {
  BodyState<Real> s;
  s.q.assign(mesh.rest_positions.begin(), mesh.rest_positions.end());
  s.v.assign(s.q.size(), Real(0));
  s.v_prev.assign(s.q.size(), Real(0));
  return s;
}

// Round-off scale of an energy summed from terms of total magnitude
// `magnitude`, each term evaluated in Real: a generous multiple of Real's
// epsilon (the terms are summed in double).
template <class Real>
double energy_roundoff(double magnitude) {
  return 1024 * std::numeric_limits<Real>::epsilon() * magnitude;
}

template <class Real>
ChebyshevDescent<Real>::ChebyshevDescent(LocalProblem<Real>& problem, const SolverSpec& spec)
    : problem_(problem), spec_(spec), alpha_(spec.alpha_max) {
  const std::size_t n = 3 * static_cast<std::size_t>(problem.num_vertices());
  for (auto* v : {&y_, &qt_, &q_, &q_prev_, &q_checked_, &q_next_, &diag_}) v->resize(n);
}

// Prediction of q_{t+1} (paper 1, §4.4); the caller then puts held axes
// where their motion says.
template <class Real>
void ChebyshevDescent<Real>::initial_guess(const BodyState<Real>& state) {
  const Real h = problem_.dt();
  const Real eta = static_cast<Real>(spec_.eta);
  // Weights of h v and of h (v - v_prev) in the guess q_t + ... .
  const Real w_velocity = spec_.init == "position" ? Real(0) : Real(1);
  const Real w_acceleration = spec_.init == "constant_acceleration" ? eta : Real(0);
  const std::size_t n = q_.size();
#pragma omp parallel for schedule(static)
  for (std::size_t k = 0; k < n; ++k) {
    const Real qt = state.q[k], v = state.v[k];
    qt_[k] = qt;
    y_[k] = qt + h * v;
    q_[k] = qt + h * (w_velocity * v + w_acceleration * (v - state.v_prev[k]));
  }
  // Eq. 10 (solver/methods/optimized_init.hpp): q_t + d h v, d from y and q_t.
  if (spec_.init == "optimized") {
    std::vector<Real> hv(n);
    for (std::size_t k = 0; k < n; ++k) hv[k] = h * state.v[k];
    const Real d =
        static_cast<Real>(optimized_step_weight(problem_, qt_.data(), y_.data(), hv.data()));
    for (std::size_t k = 0; k < n; ++k) q_[k] = qt_[k] + d * hv[k];
  }
}

template <class Real>
StepStats ChebyshevDescent<Real>::step(BodyState<Real>& state) {
  const double t_next = state.time + static_cast<double>(problem_.dt());
  problem_.begin_step(t_next);
  initial_guess(state);
  problem_.hold_fixed(t_next, q_.data());
  StepStats stats;
  alpha_ = std::min(spec_.alpha_max, alpha_ / spec_.gamma);
  const auto& mass = problem_.mass();
  const auto& fixed = problem_.fixed_axes();
  const VertexTerms<Real> terms = problem_.vertex_terms();
  const Real* floor = problem_.diagonal_floor().data();
  const Real* force = problem_.external_force().data();
  const ChebyshevPhases phases(spec_);
  const std::size_t n = q_.size();

  // The initial guess is the first checked state; its energy is summed with
  // the first check's (one allreduce for both). With model conversion the
  // energy function itself moves as interpolants change (Eq. 17), so every
  // check re-evaluates the checked state too and compares both under the
  // same interpolants; the pair still travels in one allreduce.
  const bool reevaluate = problem_.energy_changes_within_step();
  const Energy initial_local_energy =
      reevaluate ? Energy{} : problem_.local_energy(q_.data(), y_.data(), qt_.data());
  bool first_check = true;
  double checked_energy = 0;
  bool checked_finite = true;  // a non-finite checked state yields to any finite one
  q_checked_ = q_;
  q_prev_ = q_;
  Real omega = 1;
  int chebyshev_k = 0;  // iterations since the last (re)start of Chebyshev

  this->observe(0, q_.data(), y_.data(), qt_.data());
  for (int k = 0; k < spec_.iterations; ++k) {
    const bool refresh_diagonal = k % spec_.hessian_interval == 0;
    // A new phase restarts the recurrence, skipping the plain iterations of S.
    if (phases.starts_phase(k)) chebyshev_k = spec_.chebyshev_delay;
    const Real rho2 = static_cast<Real>(phases.rho(k) * phases.rho(k));
    const auto assembled = problem_.elastic_gradient(q_.data(), refresh_diagonal);
    if (chebyshev_k < spec_.chebyshev_delay)
      omega = 1;
    else if (chebyshev_k == spec_.chebyshev_delay)
      omega = Real(2) / (Real(2) - rho2);
    else
      omega = Real(4) / (Real(4) - rho2 * omega);
    const Real alpha = static_cast<Real>(alpha_);
    const Real* a = assembled.values;
    const int width = assembled.width;

#pragma omp parallel for schedule(static)
    for (std::size_t dof = 0; dof < n; ++dof) {
      const std::size_t v = dof / 3;
      const int axis = static_cast<int>(dof % 3);
      if (refresh_diagonal)
        diag_[dof] = dof_diagonal(terms, mass[v], a[width * v + 3 + axis], floor[dof]);
      if (fixed[v] & (1u << axis)) {
        q_next_[dof] = q_[dof];
        continue;
      }
      const Real g = dof_gradient(terms, mass[v], a[width * v + axis], q_[dof], y_[dof], qt_[dof],
                                  force[dof], axis);
      q_next_[dof] = chebyshev_dof(q_[dof], q_prev_[dof], g, diag_[dof], alpha, omega);
    }
    std::swap(q_prev_, q_);
    std::swap(q_, q_next_);
    ++chebyshev_k;
    stats.iterations = k + 1;
    this->observe(k + 1, q_.data(), y_.data(), qt_.data());

    const bool last = k + 1 == spec_.iterations;
    if ((k + 1) % spec_.check_interval != 0 && !last) continue;
    const Energy local[2] = {problem_.local_energy(q_.data(), y_.data(), qt_.data()),
                             reevaluate
                                 ? problem_.local_energy(q_checked_.data(), y_.data(), qt_.data())
                                 : initial_local_energy};
    const EnergySums sums = problem_.global_energies(local, first_check || reevaluate ? 2 : 1);
    if (first_check || reevaluate) {
      checked_energy = sums.energy[1].value;
      checked_finite = sums.finite[1];
    }
    if (first_check) {
      stats.initial_energy = checked_energy;
      first_check = false;
    }
    // A rise within the round-off of the energy's evaluation is no rise: near
    // the minimum it is noise, and reading it as a rise would shrink alpha
    // for nothing.
    const double tolerance = energy_roundoff<Real>(sums.energy[0].magnitude);
    stats.energy_tolerance = tolerance;
    if (sums.finite[0] && (!checked_finite || sums.energy[0].value <= checked_energy + tolerance)) {
      checked_energy = sums.energy[0].value;
      checked_finite = true;
      q_checked_ = q_;
      continue;
    }
    // The energy rose (or is not finite): back to the checked state, shorter step.
    if (!sums.finite[0]) {
      ++stats.nonfinite_rollbacks;
      // Only the rank whose own terms were not finite looks for the culprit.
      if (!stats.rejected_at.found() &&
          !(std::isfinite(local[0].value) && std::isfinite(local[0].magnitude)))
        stats.rejected_at = problem_.find_non_finite(q_.data(), y_.data(), qt_.data());
    }
    q_ = q_checked_;
    q_prev_ = q_checked_;
    chebyshev_k = 0;
    ++stats.rollbacks;
    alpha_ *= spec_.gamma;
    if (alpha_ < spec_.alpha_min) {
      stats.stalled = true;
      break;
    }
  }

  // No state with finite energy was reached (e.g. the initial guess was not
  // finite and no trial was either): the body keeps the step's start, the last
  // good state, and the caller stops the run. Every rank knows it from the
  // reduction; each names what it holds that is not finite.
  if (!checked_finite) {
    stats.finite = false;
    stats.failed_at = problem_.find_non_finite(q_checked_.data(), y_.data(), qt_.data());
    stats.alpha = alpha_;
    stats.energy = checked_energy;
    return stats;
  }

  const Real inv_h = Real(1) / problem_.dt();
#pragma omp parallel for schedule(static)
  for (std::size_t k = 0; k < n; ++k) {
    state.v_prev[k] = state.v[k];
    state.v[k] = (q_[k] - qt_[k]) * inv_h;
    state.q[k] = q_[k];
  }
  state.time = t_next;
  stats.alpha = alpha_;
  stats.energy = checked_energy;
  return stats;
}

template BodyState<double> rest_state(const LocalMesh&);
template BodyState<float> rest_state(const LocalMesh&);
template class ChebyshevDescent<double>;
template class ChebyshevDescent<float>;

}  // namespace descent
