#include "solver/chebyshev_descent.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "common/error.hpp"
#include "kernels/vertex.hpp"
#include "solver/methods/chebyshev_phases.hpp"
#include "solver/step_control.hpp"

namespace descent {

template <class Real>
BodyState<Real> rest_state(const LocalMesh& mesh) {
  BodyState<Real> s;
  s.q.assign(mesh.rest_positions.begin(), mesh.rest_positions.end());
  s.v.assign(s.q.size(), Real(0));
  s.v_prev.assign(s.q.size(), Real(0));
  return s;
}

template <class Real>
ChebyshevDescent<Real>::ChebyshevDescent(LocalProblem<Real>& problem, const SolverSpec& spec)
    : problem_(problem), spec_(spec), alpha_(spec.alpha_max) {
  const std::size_t n = 3 * static_cast<std::size_t>(problem.num_vertices());
  for (auto* v : {&y_, &qt_, &q_, &q_prev_, &q_checked_, &q_next_, &diag_}) v->resize(n);
}

template <class Real>
StepStats ChebyshevDescent<Real>::step(BodyState<Real>& state) {
  const double t_next = state.time + static_cast<double>(problem_.dt());
  problem_.begin_step(t_next);
  predict_positions(spec_, problem_, state, qt_.data(), y_.data(), q_.data(),
                    this->take_guess_from_start());
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

  // The initial guess is the first checked state (step_control.hpp).
  EnergyCheck check(problem_.energy_changes_within_step());
  const Energy initial_local_energy =
      check.reevaluate() ? Energy{} : problem_.local_energy(q_.data(), y_.data(), qt_.data());
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
    omega = chebyshev_omega(chebyshev_k, spec_.chebyshev_delay, rho2, omega);
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
                             check.reevaluate()
                                 ? problem_.local_energy(q_checked_.data(), y_.data(), qt_.data())
                                 : initial_local_energy};
    if (check.accept<Real>(problem_.global_energies(local, check.count()), stats)) {
      q_checked_ = q_;
      continue;
    }
    // The energy rose (or is not finite): back to the checked state, shorter
    // step. Only the rank whose own terms were not finite looks for the culprit.
    if (!stats.rejected_at.found() && !finite(local[0]))
      stats.rejected_at = problem_.find_non_finite(q_.data(), y_.data(), qt_.data());
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
  if (!check.checked_finite()) {
    stats.finite = false;
    stats.failed_at = problem_.find_non_finite(q_checked_.data(), y_.data(), qt_.data());
    stats.alpha = alpha_;
    stats.energy = check.checked_energy();
    return stats;
  }

  commit_step(q_.data(), qt_.data(), problem_.dt(), t_next, state);
  stats.alpha = alpha_;
  stats.energy = check.checked_energy();
  return stats;
}

template BodyState<double> rest_state(const LocalMesh&);
template BodyState<float> rest_state(const LocalMesh&);
template class ChebyshevDescent<double>;
template class ChebyshevDescent<float>;

}  // namespace descent
