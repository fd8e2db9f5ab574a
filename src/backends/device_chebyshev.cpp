#include "backends/device_chebyshev.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "common/error.hpp"
#include "solver/methods/chebyshev_phases.hpp"
#include "solver/step_control.hpp"

namespace descent {

template <class Real>
DeviceChebyshev<Real>::DeviceChebyshev(LocalProblem<Real>& problem, const SolverSpec& spec,
                                       std::unique_ptr<DeviceEngine<Real>> engine)
    : problem_(problem), spec_(spec), alpha_(spec.alpha_max), engine_(std::move(engine)) {
  DESCENT_VERIFY(spec.method == "chebyshev", "the device stepper runs solver.method = chebyshev");
  n_ = 3 * static_cast<std::size_t>(problem.num_vertices());
  const auto staging = engine_->staging();
  q_ = staging.q;
  y_ = staging.y;
  qt_ = staging.qt;
}

template <class Real>
StepStats DeviceChebyshev<Real>::step(BodyState<Real>& state) {
  const double t_next = state.time + static_cast<double>(problem_.dt());
  problem_.begin_step(t_next);
  predict_positions(spec_, problem_, state, qt_, y_, q_, this->take_guess_from_start());
  problem_.hold_fixed(t_next, q_);
  EnergyCheck check(problem_.energy_changes_within_step());
  const bool reevaluate = check.reevaluate();
  // Loads travel only when some are applied (or were: back to zero).
  const auto& force = problem_.external_force();
  const bool force_nonzero =
      std::any_of(force.begin(), force.end(), [](Real f) { return f != Real(0); });
  const bool upload_force = force_nonzero || force_on_device_nonzero_;
  if (upload_force) std::copy(force.begin(), force.end(), engine_->staging().force);
  force_on_device_nonzero_ = force_nonzero;
  engine_->begin_step(upload_force, reevaluate ? problem_.interpolants().data() : nullptr);

  StepStats stats;
  alpha_ = std::min(spec_.alpha_max, alpha_ / spec_.gamma);
  const ChebyshevPhases phases(spec_);
  const Energy initial_local_energy = reevaluate ? Energy{} : engine_->local_energy(false);
  Real omega = 1;
  int chebyshev_k = 0;
  std::vector<std::uint8_t> refresh;
  std::vector<Real> alphas, omegas;

  for (int k = 0; k < spec_.iterations;) {
    // The iterations up to the next check run on the device as one block;
    // their parameters are known now, as a check is the only thing that
    // changes alpha or restarts Chebyshev.
    const int end =
        std::min(spec_.iterations, (k / spec_.check_interval + 1) * spec_.check_interval);
    refresh.clear();
    alphas.clear();
    omegas.clear();
    for (int j = k; j < end; ++j) {
      if (phases.starts_phase(j)) chebyshev_k = spec_.chebyshev_delay;
      const Real rho2 = static_cast<Real>(phases.rho(j) * phases.rho(j));
      omega = chebyshev_omega(chebyshev_k, spec_.chebyshev_delay, rho2, omega);
      refresh.push_back(j % spec_.hessian_interval == 0 ? 1 : 0);
      alphas.push_back(static_cast<Real>(alpha_));
      omegas.push_back(omega);
      ++chebyshev_k;
    }
    // Timed to completion, so the check's share is its own (the check waits
    // for the device anyway).
    const auto t0 = std::chrono::steady_clock::now();
    engine_->iterate(end - k, refresh.data(), alphas.data(), omegas.data());
    engine_->synchronize();
    const auto t1 = std::chrono::steady_clock::now();
    iterate_seconds_ += std::chrono::duration<double>(t1 - t0).count();
    // Charged to the check: from here to the next block.
    struct CheckTimer {
      std::chrono::steady_clock::time_point start;
      double& total;
      ~CheckTimer() {
        total += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      }
    } check_timer{t1, check_seconds_};
    k = end;
    stats.iterations = k;

    const Energy local[2] = {engine_->local_energy(false),
                             reevaluate ? engine_->local_energy(true) : initial_local_energy};
    if (check.accept<Real>(problem_.global_energies(local, check.count()), stats)) {
      engine_->accept();
      continue;
    }
    if (!stats.rejected_at.found() && !finite(local[0])) {
      engine_->download(false);
      stats.rejected_at = problem_.find_non_finite(q_, y_, qt_);
    }
    engine_->rollback();
    chebyshev_k = 0;
    ++stats.rollbacks;
    alpha_ *= spec_.gamma;
    if (alpha_ < spec_.alpha_min) {
      stats.stalled = true;
      break;
    }
  }

  if (reevaluate) {
    interpolants_.resize(problem_.interpolants().size());
    engine_->download_interpolants(interpolants_.data());
    problem_.set_interpolants(interpolants_);
  }
  if (!check.checked_finite()) {
    stats.finite = false;
    engine_->download(true);
    stats.failed_at = problem_.find_non_finite(q_, y_, qt_);
    stats.alpha = alpha_;
    stats.energy = check.checked_energy();
    return stats;
  }

  engine_->download(false);
  commit_step(q_, qt_, problem_.dt(), t_next, state);
  stats.alpha = alpha_;
  stats.energy = check.checked_energy();
  return stats;
}

template class DeviceChebyshev<double>;
template class DeviceChebyshev<float>;

}  // namespace descent
