#pragma once
// The pieces of a time step that every descent method and every backend
// share (paper 1, §4.3-4.4; DESIGN §1): the prediction of q_{t+1} that starts
// the iteration, the Chebyshev weight recurrence, and the energy check that
// accepts a trial state or sends the method back to the checked one.
#include <algorithm>
#include <cmath>
#include <limits>

#include "comm/reduction.hpp"
#include "io/scene.hpp"
#include "kernels/in_double.hpp"
#include "solver/local_problem.hpp"
#include "solver/stepper.hpp"

namespace descent {

// Round-off scale of an energy summed from terms of total magnitude
// `magnitude` (Energy: terms evaluated and summed in double, whatever the
// run's Real): a generous multiple of double's epsilon.
inline double energy_roundoff(double magnitude) {
  return kRoundoffEpsilons * std::numeric_limits<double>::epsilon() * magnitude;
}

// Chebyshev weight (paper 1, Eq. 8) for the iteration `since_restart`
// iterations after Chebyshev last (re)started: 1 for the first `delay` (S)
// plain iterations, then the recurrence from `omega`, the previous weight.
template <class Real>
Real chebyshev_omega(int since_restart, int delay, Real rho2, Real omega) {
  if (since_restart < delay) return 1;
  if (since_restart == delay) return Real(2) / (Real(2) - rho2);
  return Real(4) / (Real(4) - rho2 * omega);
}

// The prediction of q_{t+1} (paper 1, §4.4) for solver.init: fills the
// step-start positions qt, the inertial target y = q_t + h v and the initial
// guess q (3 reals per local vertex, xyz-interleaved). The caller then puts
// held axes where their motion says. init = "optimized" (Eq. 10) costs one
// gradient, one Hessian product and one allreduce. from_start: q = q_t
// whatever spec.init says (Stepper::guess_next_step_from_start). With
// obstacles the guess is then kept outside them
// (LocalProblem::begin_contact_step).
template <class Real>
void predict_positions(const SolverSpec& spec, LocalProblem<Real>& problem,
                       const BodyState<Real>& state, Real* qt, Real* y, Real* q,
                       bool from_start = false);

// Ends a step at its result q (3 reals per local vertex): implicit Euler's
// velocity v = (q - q_t) / h, the previous velocity kept for the next
// prediction, and the clock advanced to t_next.
template <class Real>
void commit_step(const Real* q, const Real* qt, Real h, double t_next, BodyState<Real>& state) {
  const Real inv_h = Real(1) / h;
  const std::size_t n = state.q.size();
#pragma omp parallel for schedule(static)
  for (std::size_t k = 0; k < n; ++k) {
    state.v_prev[k] = state.v[k];
    state.v[k] = (q[k] - qt[k]) * inv_h;
    state.q[k] = q[k];
  }
  state.time = t_next;
}

// The energy check: eps is reduced every check_interval iterations and a
// trial whose energy rose (or is not finite) is rejected. The initial guess
// is the first checked state; its energy rides in the first check's
// reduction. With model conversion the energy function itself moves as the
// interpolants change (Eq. 17), so every check re-evaluates the checked
// state too and compares both under the same interpolants; the pair still
// travels in one allreduce.
class EnergyCheck {
 public:
  // `noise_floor`: an energy change below it is no change either
  // (LocalProblem::energy_noise_floor).
  EnergyCheck(bool reevaluate, double noise_floor)
      : reevaluate_(reevaluate), noise_floor_(noise_floor) {}

  // Whether the caller must evaluate the checked state's energy beside the
  // trial's at every check (or only the initial guess's, once, up front).
  bool reevaluate() const { return reevaluate_; }
  // Energies the next check reduces: the trial's, and the checked state's
  // when it is summed (the first check, or every check with reevaluate).
  int count() const { return first_ || reevaluate_ ? 2 : 1; }

  // What a check makes of a trial state.
  enum class Verdict {
    accepted,   // no rise: the trial becomes the checked state
    tolerated,  // a rise within `allowed_rise`: the iteration goes on, the
                // checked state stays the best one
    rejected,   // a larger rise or a non-finite energy: roll back
  };

  // Judges the trial from the reduced sums of count() energies (trial first)
  // and records the check in `stats`; a non-finite trial is counted in
  // stats.nonfinite_rollbacks. A rise up to `allowed_rise` above the checked
  // energy is tolerated (0: every rise beyond round-off is rejected).
  Verdict judge(const EnergySums& sums, StepStats& stats, double allowed_rise = 0) {
    if (count() == 2) {
      checked_energy_ = sums.energy[1].value;
      checked_finite_ = sums.finite[1];
    }
    if (first_) {
      stats.initial_energy = checked_energy_;
      first_ = false;
    }
    // A rise within the round-off of the energy's evaluation is no rise: near
    // the minimum it is noise, and reading it as a rise would shrink alpha
    // for nothing.
    const double tolerance = std::max(energy_roundoff(sums.energy[0].magnitude), noise_floor_);
    stats.energy_tolerance = tolerance;
    if (!sums.finite[0]) {
      ++stats.nonfinite_rollbacks;
      return Verdict::rejected;
    }
    if (!checked_finite_ || sums.energy[0].value <= checked_energy_ + tolerance) {
      checked_energy_ = sums.energy[0].value;
      checked_finite_ = true;
      return Verdict::accepted;
    }
    return sums.energy[0].value <= checked_energy_ + tolerance + allowed_rise ? Verdict::tolerated
                                                                              : Verdict::rejected;
  }

  // judge() without tolerated rises: true when the trial is accepted.
  bool accept(const EnergySums& sums, StepStats& stats) {
    return judge(sums, stats) == Verdict::accepted;
  }

  double checked_energy() const { return checked_energy_; }
  // False while no state with finite energy has been reached in the step (a
  // non-finite checked state yields to any finite trial).
  bool checked_finite() const { return checked_finite_; }

 private:
  bool reevaluate_;
  double noise_floor_;
  bool first_ = true;
  double checked_energy_ = 0;
  bool checked_finite_ = true;
};

inline bool finite(const Energy& e) { return std::isfinite(e.value) && std::isfinite(e.magnitude); }

}  // namespace descent
