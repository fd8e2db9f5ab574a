#include "solver/chebyshev_descent.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>

#include "common/error.hpp"
#include "common/splitmix.hpp"
#include "solver/check_history.hpp"
#include "solver/methods/chebyshev_phases.hpp"
#include "solver/preconditioners/make_preconditioner.hpp"
#include "solver/spectrum.hpp"
#include "solver/step_control.hpp"

namespace descent {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// Adds the time from construction to destruction to `total`.
struct ScopedTimer {
  double& total;
  Clock::time_point start = Clock::now();
  ~ScopedTimer() { total += seconds_since(start); }
};

// Weight of the noise in the Lanczos start vector, relative to the RMS of
// its motion part.
constexpr double kStartNoise = 0.05;
// The smallest eigenvalue bound admitted is upper / kMaxCondition: the
// exact Hessian can be indefinite (a compressed neo-Hookean body), where
// Lanczos finds lambda_min <= 0 and no Chebyshev interval exists.
constexpr double kMaxCondition = 1e8;

// The parameters the step's iterations run with, changed by rollbacks.
struct Schedule {
  bool automatic = false;
  int delay = 0;     // plain iterations after a (re)start
  double alpha = 0;  // step length
  double lower = 0;  // automatic: spectrum bounds
  double upper = 0;
  double phi = 0;  // the bound's rate (0: no single rate, e.g. phases)
  double rho = 0;  // of the single phase (automatic or fixed)

  void set_bounds(double a, double b) {
    const ChebyshevParameters p = chebyshev_parameters(a, b);
    lower = a;
    upper = b;
    alpha = p.alpha;
    rho = p.rho;
    phi = p.phi;
  }
};

}  // namespace

template <class Real>
BodyState<Real> rest_state(const LocalMesh& mesh) {
  BodyState<Real> s;
  s.q.assign(mesh.rest_positions.begin(), mesh.rest_positions.end());
  s.v.assign(s.q.size(), Real(0));
  s.v_prev.assign(s.q.size(), Real(0));
  return s;
}

template <class Real>
ChebyshevDescent<Real>::ChebyshevDescent(LocalProblem<Real>& problem, const SolverSpec& spec,
                                         std::unique_ptr<IterationEngine<Real>> engine)
    : problem_(problem), spec_(spec), engine_(std::move(engine)) {
  DESCENT_VERIFY(spec.method == "chebyshev",
                 "the Chebyshev stepper runs solver.method = chebyshev");
  memory_.alpha = spec.alpha_max;
  if (preconditioner_of(spec) != "jacobi" &&
      (spec.preconditioner != "auto" || automatic_multilevel_fits()))
    engine_->use_preconditioner(spec);
  const auto staging = engine_->staging();
  q_ = staging.q;
  y_ = staging.y;
  qt_ = staging.qt;
}

template <class Real>
bool ChebyshevDescent<Real>::automatic_multilevel_fits() {
  // Not on a device: the multilevel preconditioner's device path has not run
  // on one yet (docs/multilevel.md).
  if (engine_->on_device()) return false;
  // Nor where it does not fit the problem (an inverted tet or a random box
  // recovering its rest shape quasi-statically, nothing held:
  // tests/mpi/test_recovery.cpp stalled with it).
  return multilevel_fits(problem_, false);
}

template <class Real>
double ChebyshevDescent<Real>::stage_start_vector(const BodyState<Real>& state) {
  const LocalMesh& mesh = problem_.mesh();
  const auto& fixed = problem_.fixed_axes();
  const auto& mass = problem_.mass();
  const auto& force = problem_.external_force();
  const VertexTerms<Real> terms = problem_.vertex_terms();
  auto free_dof = [&](std::size_t k) { return !(fixed[k / 3] & (1u << (k % 3))); };
  auto acceleration = [&](std::size_t k) {
    return mass[k / 3] > 0 ? static_cast<double>(terms.gravity[k % 3]) + force[k] / mass[k / 3]
                           : 0.0;
  };
  // One allreduce: over owned free dofs |v|^2, |acceleration|^2 and their
  // count, then the engine's translation sums.
  double sums[9] = {0, 0, 0};
  for (std::size_t k = 0; k < 3 * static_cast<std::size_t>(mesh.num_owned); ++k) {
    if (!free_dof(k)) continue;
    sums[0] += static_cast<double>(state.v[k]) * state.v[k];
    sums[1] += acceleration(k) * acceleration(k);
    sums[2] += 1;
  }
  const std::array<double, 6> translation = engine_->translation_sums();
  std::copy(translation.begin(), translation.end(), sums + 3);
  problem_.global_dots(sums, 9);

  const bool moving = sums[0] > 0;
  const double rms = sums[2] > 0 ? std::sqrt((moving ? sums[0] : sums[1]) / sums[2]) : 0;
  const double scale = rms > 0 ? kStartNoise * rms : 1;
  Real* s = engine_->staging().vector;
  for (std::size_t k = 0; k < 3 * static_cast<std::size_t>(mesh.num_vertices()); ++k) {
    const double motion =
        moving ? static_cast<double>(state.v[k]) : (rms > 0 ? acceleration(k) : 0);
    const std::uint64_t id = 3 * static_cast<std::uint64_t>(mesh.global_vertex[k / 3]) + k % 3;
    s[k] = static_cast<Real>(motion + scale * unit_noise(id));
  }
  double lowest = 0;
  for (int axis = 0; axis < 3; ++axis) {
    const double curvature = sums[3 + 2 * axis], diagonal = sums[4 + 2 * axis];
    if (curvature > 0 && diagonal > 0)
      lowest = lowest > 0 ? std::min(lowest, curvature / diagonal) : curvature / diagonal;
  }
  return lowest;
}

template <class Real>
bool ChebyshevDescent<Real>::prepare_spectrum(const BodyState<Real>& state, StepStats& stats) {
  const bool due =
      !(memory_.lambda_max > 0) || memory_.reestimate ||
      (spec_.spectrum_interval > 0 && memory_.steps_since_estimate >= spec_.spectrum_interval);
  if (!due) {
    ++memory_.steps_since_estimate;
    return false;
  }
  ScopedTimer timer{estimate_seconds_};
  if (!engine_->preconditioner()) engine_->refresh_diagonal();
  const double translation = stage_start_vector(state);
  const LanczosRun run = lanczos(*engine_, problem_, spec_.spectrum_steps);
  ++estimates_;
  stats.spectrum_steps = run.steps;
  if (run.steps > 0 && run.ritz.highest > 0 && std::isfinite(run.ritz.highest)) {
    const double upper = (1 + spec_.spectrum_margin) * run.ritz.highest;
    // A widening keeps the b it reached, not its factor: the new estimate
    // may already lie as high.
    if (memory_.lambda_max > 0)
      memory_.widening = std::max(1.0, memory_.widening * memory_.lambda_max / upper);
    memory_.lambda_max = upper;
    // Lanczos approaches the bottom from above, slowly where it is a
    // cluster of slow modes; a rigid translation's quotient often lies
    // lower (the stiff body whose lowest modes are its sway). A Ritz value
    // at or below zero is a direction of negative curvature at the guess
    // (a compressed neo-Hookean pin, a barrier's gap curvature), which no
    // positive bound covers: the translation's quotient bounds the rest
    // (bowling on 2 ranks: a Ritz value of -0.22 left the floor below,
    // b / 1e8, and 16 steps ended at the 1,000-iteration cap with e ~ 1).
    double lower = run.ritz.lowest;
    if (translation > 0 && (translation < lower || !(lower > 0))) lower = translation;
    memory_.lambda_min = std::max(lower, upper / kMaxCondition);
  } else if (!(memory_.lambda_max > 0)) {
    // Nothing to estimate from (no free dof moves, or a non-finite
    // Hessian): the Jacobi bound of a diagonally dominant matrix, 2.
    memory_.lambda_max = 2;
    memory_.lambda_min = 2 / kMaxCondition;
  }
  memory_.steps_since_estimate = 1;
  memory_.reestimate = false;
  return true;
}

template <class Real>
StepStats ChebyshevDescent<Real>::step(BodyState<Real>& state) {
  const double t_next = state.time + static_cast<double>(problem_.dt());
  problem_.begin_step(t_next);
  const bool from_start = this->take_guess_from_start();
  predict_positions(spec_, problem_, state, qt_, y_, q_, from_start);
  // Extrapolated from the last steps' motion (not the step start itself).
  const bool predicted = !from_start && spec_.init != "position";
  const bool may_abandon_guess = this->take_abandon_guess();
  problem_.hold_fixed(t_next, q_);
  EnergyCheck check(problem_.energy_changes_within_step(), problem_.energy_noise_floor());
  const bool reevaluate = check.reevaluate();
  // Loads travel only when some are applied (or were: back to zero).
  const auto& force = problem_.external_force();
  const bool force_nonzero =
      std::any_of(force.begin(), force.end(), [](Real f) { return f != Real(0); });
  const bool upload_force = force_nonzero || force_on_engine_nonzero_;
  if (upload_force) std::copy(force.begin(), force.end(), engine_->staging().force);
  force_on_engine_nonzero_ = force_nonzero;
  engine_->begin_step(upload_force, reevaluate ? problem_.interpolants().data() : nullptr);
  // P^-1 at the initial guess, every preconditioner_refresh steps (and at
  // the first step of a run or a restart, and after a step that rolled back).
  if (engine_->preconditioner()) {
    if (steps_since_refresh_ >= spec_.preconditioner_refresh || memory_.reestimate) {
      ScopedTimer timer{refresh_seconds_};
      engine_->refresh_preconditioner();
      steps_since_refresh_ = 0;
    }
    ++steps_since_refresh_;
  }

  StepStats stats;
  Schedule schedule;
  schedule.automatic = spec_.chebyshev_parameters == "auto";
  bool diagonal_fresh = false;
  const ChebyshevPhases phases(spec_);
  if (schedule.automatic) {
    diagonal_fresh = prepare_spectrum(state, stats);
    // From a predicted guess, plain iterations up to and through the first
    // check, then the semi-iterative method: the first iterations from an
    // extrapolation are the most nonlinear, and momentum there drove tets
    // through collapse (main job: 7 of 60 steps with a non-finite trial
    // against 1; the other scenes alike, bench/results/chebyshev_auto/).
    // From the step start the recurrence starts at once, as textbooks have
    // it: there momentum is what carries a body out of a shallow basin
    // (tests/mpi/test_recovery.cpp's random box). With a preconditioner
    // other than D^-1 it starts at once from any guess: its steps are
    // nearly Newton's, and the plain iterations only cost (158K helix, one
    // step to e <= 1e-3: 6 iterations against 9; the main job over 60
    // frames: no rollback either way).
    schedule.delay = predicted && !engine_->preconditioner() ? spec_.check_interval + 1 : 1;
    schedule.set_bounds(memory_.lambda_min, memory_.widening * memory_.lambda_max);
  } else {
    memory_.alpha = std::min(spec_.alpha_max, memory_.alpha / spec_.gamma);
    schedule.delay = spec_.chebyshev_delay;
    schedule.alpha = memory_.alpha;
    if (spec_.phase_rho.size() <= 1) {
      schedule.rho = spec_.phase_rho.empty() ? spec_.rho : spec_.phase_rho.front();
      if (schedule.rho > 0 && schedule.rho < 1) schedule.phi = chebyshev_rate(schedule.rho);
    }
  }
  // The accuracy target: no stop before the bound's count since the
  // (re)start, unless the energies alone are conclusive.
  const double target = spec_.accuracy;
  auto bound_iterations = [&] {
    return schedule.phi > 0 ? chebyshev_iterations_for(schedule.phi, kTargetShare * target) : 0;
  };
  int prior_iterations = target > 0 ? bound_iterations() : 0;
  CheckHistory history;
  stats.error_estimate = std::numeric_limits<double>::quiet_NaN();

  const Energy initial_local_energy = reevaluate ? Energy{} : engine_->local_energy(false);
  Real omega = 1;
  int chebyshev_k = 0;  // iterations since the last (re)start of Chebyshev
  bool best_is_current = true;
  // Contact terms in eps (obstacles or pairs with contact.method = "energy");
  // whether a rollback has restarted without widening since the last
  // accepted check, the iteration (since the (re)start) of the rollback
  // that began the present run of such restarts, and their plain
  // iterations.
  const bool barrier = problem_.body_contact() != nullptr ||
                       (problem_.contact() != nullptr && problem_.contact()->energy_method());
  bool momentum_reset = false;
  int momentum_reset_at = 0, plain_after_reset = 0;

  std::vector<std::uint8_t> refresh;
  std::vector<Real> alphas, omegas;
  const bool observed = this->observed();
  this->observe(0, q_, y_, qt_);

  for (int k = 0; k < spec_.iterations;) {
    // The iterations up to the next check run as one block (one at a time
    // when observed); their parameters are known now, as a check is the
    // only thing that changes alpha or restarts Chebyshev.
    const int check_at =
        std::min(spec_.iterations, (k / spec_.check_interval + 1) * spec_.check_interval);
    const int end = observed ? k + 1 : check_at;
    refresh.clear();
    alphas.clear();
    omegas.clear();
    for (int j = k; j < end; ++j) {
      if (!schedule.automatic && phases.starts_phase(j)) chebyshev_k = schedule.delay;
      const double rho = schedule.automatic ? schedule.rho : phases.rho(j);
      const Real rho2 = static_cast<Real>(rho * rho);
      omega = chebyshev_omega(chebyshev_k, schedule.delay, rho2, omega);
      refresh.push_back(j % spec_.hessian_interval == 0 && !(j == 0 && diagonal_fresh) ? 1 : 0);
      alphas.push_back(static_cast<Real>(schedule.alpha));
      omegas.push_back(omega);
      ++chebyshev_k;
    }
    {
      ScopedTimer timer{iterate_seconds_};
      engine_->iterate(end - k, refresh.data(), alphas.data(), omegas.data());
      engine_->synchronize();
    }
    k = end;
    stats.iterations = k;
    if (observed) {
      engine_->download(false);
      this->observe(k, q_, y_, qt_);
    }
    if (k != check_at) continue;

    ScopedTimer check_timer{check_seconds_};
    const Energy local[2] = {engine_->local_energy(false),
                             reevaluate ? engine_->local_energy(true) : initial_local_energy};
    const EnergySums sums = problem_.global_energies(local, check.count());
    // A rise the Chebyshev bound allows since the (re)start is no sign of
    // divergence: its error oscillates between checks.
    const double allowed_rise = schedule.automatic && !history.empty()
                                    ? chebyshev_error_bound(schedule.phi, chebyshev_k) *
                                          (history.restart_energy() - check.checked_energy())
                                    : 0.0;
    const EnergyCheck::Verdict verdict = check.judge(sums, stats, allowed_rise);
    if (history.empty()) history.restart(stats.initial_energy);
    if (verdict == EnergyCheck::Verdict::accepted) {
      momentum_reset = false;
      engine_->accept();
      best_is_current = true;
      // Contact between bodies: its pairs found again where a surface
      // vertex has drifted half its cap from where they were found (one
      // more allreduce per check, in such scenes only).
      if (problem_.body_contact() &&
          problem_.global_max(engine_->contact_pairs_drifted() ? 1.0 : 0.0) > 0)
        engine_->refresh_contact_pairs();
      history.record(chebyshev_k, check.checked_energy());
      if (schedule.phi > 0) {
        // Over the last checks, and over the last windows of kWideWindow
        // (solver/check_history.hpp): before the bound's count only when
        // both are far below the target, after it when what there is says so.
        // With the energy's round-off: a step already at its minimum (a body
        // at rest) ran to the iteration cap, its changes all noise.
        const AccuracyReading reading =
            history.read(stats.initial_energy, schedule.phi, target, stats.energy_tolerance);
        stats.error_estimate = reading.estimate;
        if (target > 0 && (reading.far_below || (reading.below && chebyshev_k >= prior_iterations)))
          break;
        // Past the bound's count with every change within round-off: more
        // iterations cannot show progress (a float step at its floor for a
        // target below it ran to the cap so), the step ends short of its target.
        if (target > 0 && reading.at_resolution && chebyshev_k >= prior_iterations) {
          stats.at_resolution = true;
          break;
        }
      }
      continue;
    }
    if (verdict == EnergyCheck::Verdict::tolerated) {
      best_is_current = false;
      continue;
    }
    // The energy rose (or is not finite): back to the checked state, shorter
    // step. Only the rank whose own terms were not finite looks for the culprit.
    if (!stats.rejected_at.found() && !finite(local[0])) {
      engine_->download(false);
      stats.rejected_at = problem_.find_non_finite(q_, y_, qt_);
    }
    ++stats.rollbacks;
    // Back to an extrapolated guess whose own energy is not finite: the
    // step start usually does better than shrinking the step from it (the
    // crushing armadillo rolled back 12 times a step so), so the caller
    // retakes the step from there first.
    if (predicted && may_abandon_guess && !check.checked_finite()) {
      stats.abandoned_guess = true;
      break;
    }
    engine_->rollback();
    if (problem_.body_contact() && !sums.finite[0]) problem_.body_contact()->use_safe_guard();
    if (engine_->preconditioner()) {
      ScopedTimer timer{refresh_seconds_};
      engine_->refresh_preconditioner();
      steps_since_refresh_ = 1;
    }
    best_is_current = true;
    const int failed_at = chebyshev_k;
    chebyshev_k = 0;
    if (schedule.automatic && barrier && !momentum_reset) {
      // With a contact barrier a rise is most often the recurrence's
      // momentum carrying a closing gap on into the barrier (the snowman:
      // its pairs' energy 0.08 -> 5.3 within one check while the rest fell),
      // which no b prevents: widening only slowed every later step (there
      // to 1,250x the estimate, 13 of 30 steps stalled). The first rollback
      // since an accepted check restarts with plain iterations through the
      // next check at the same bounds; a second one widens. A restarted
      // run that rolls back again no further along than the one that began
      // the restarts doubles the plain iterations: the same rise came back
      // (the pile: +2.08 at the 32nd iteration, 27 times, to the cap).
      // Widening there instead cost 3x the iterations (the widening stays
      // for the next steps).
      const bool repeated = plain_after_reset > 0 && failed_at <= momentum_reset_at;
      plain_after_reset = repeated ? 2 * plain_after_reset : spec_.check_interval + 1;
      if (!repeated) momentum_reset_at = failed_at;
      momentum_reset = true;
      schedule.delay = plain_after_reset;
    } else if (schedule.automatic) {
      // The spectrum reaches above b here (or the step is too long for the
      // energy's curvature): widen, keep the widening for the next steps
      // (a new estimate at the guess does not see the curvature the path
      // met: the crushing armadillo rolled back 2.7 times a step without
      // it), and estimate anew next step.
      schedule.set_bounds(schedule.lower, schedule.upper / spec_.gamma);
      memory_.widening /= spec_.gamma;
      memory_.reestimate = true;
      prior_iterations = target > 0 ? bound_iterations() : 0;
    } else {
      memory_.alpha *= spec_.gamma;
      schedule.alpha = memory_.alpha;
    }
    history.restart(check.checked_energy());
    if (schedule.alpha < spec_.alpha_min) {
      stats.stalled = true;
      break;
    }
  }

  if (schedule.automatic && stats.rollbacks == 0)
    memory_.widening = std::max(1.0, memory_.widening * spec_.gamma);
  stats.alpha = schedule.alpha;
  stats.rho = schedule.rho;
  stats.lambda_min = schedule.lower;
  stats.lambda_max = schedule.upper;
  stats.energy = check.checked_energy();
  if (schedule.automatic) memory_.alpha = schedule.alpha;
  if (reevaluate) {
    interpolants_.resize(problem_.interpolants().size());
    engine_->download_interpolants(interpolants_.data());
    problem_.set_interpolants(interpolants_);
  }
  // No state with finite energy was reached (e.g. the initial guess was not
  // finite and no trial was either): the body keeps the step's start, the
  // last good state, and the caller stops the run. Every rank knows it from
  // the reduction; each names what it holds that is not finite.
  if (!check.checked_finite()) {
    stats.finite = false;
    engine_->download(true);
    stats.failed_at = problem_.find_non_finite(q_, y_, qt_);
    return stats;
  }
  // The step's result is the best checked state: the current iterate unless
  // the last check tolerated a rise.
  engine_->download(!best_is_current);
  problem_.end_contact_step(q_, qt_);
  commit_step(q_, qt_, problem_.dt(), t_next, state);
  return stats;
}

template BodyState<double> rest_state(const LocalMesh&);
template BodyState<float> rest_state(const LocalMesh&);
template class ChebyshevDescent<double>;
template class ChebyshevDescent<float>;

}  // namespace descent
