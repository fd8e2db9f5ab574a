#pragma once
// The energies of the accepted checks of one run of a descent method (since
// it last (re)started: the step's start or a rollback) and the relative
// error they imply: the accuracy target of every method that checks its
// energy (solver.accuracy; issue 11 for Chebyshev, issue 24 for the others).
//
// Once the error falls geometrically, eps_k - eps* = D r / (1 - r) with D
// the last decrease between checks and r the ratio of the last two
// decreases. With a Chebyshev bound (rate phi > 0) r is taken as at least
// the bound's own ratio over the same iterations, B(k) / B(k_prev), so an
// early burst of fast decrease does not pass for convergence; methods
// without one (phi = 0: gradient descent, Nesterov, NCG, L-BFGS, linear CG's
// quadratic) read r from the decreases alone. Non-monotone stretches (the
// Chebyshev and Nesterov errors oscillate between checks) give no estimate.
//
// Nor does a window that starts at the (re)start: its fall is the fast
// start (the modes the bound covers), and beside it the next window's small
// decrease reads as convergence whether the error has vanished or stalls
// (a mode outside [a, b], or the nonlinearity the estimate at the guess did
// not see). With the multilevel preconditioner, windows from the restart
// stopped the 316K helix at e = 1.2e-4 for a target of 1e-6 (a fall of
// 2000x, then 4.5x, then 0.27x a window) and an armadillo at 2.9e-3 for
// 1e-4 (e_8 5.4e-3, e_16 2.9e-3).
//
// Without a bound the fast start lasts longer than a window: under a
// first-order method the decrease ratio r rises check by check as the fast
// modes die out (for a quadratic and a stationary iteration the decreases
// are a positive sum of geometric sequences, whose ratio never falls), so
// the latest r under-reads the error left, by 7x and more on the small
// helix (gd stopped at e = 0.66 for 0.1, jacobi_gd at 0.80 for 1e-2). Such a
// method stops only on a confirmed reading: the estimate below the target
// at two checks running, and the minimum it predicts, eps_k - (eps_k -
// eps*), settled: fallen since the previous check by at most half the
// error left (while r still rises each check finds more error left than
// the last predicted). bench/results/accuracy_methods.md measures it.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <vector>

#include "solver/spectrum.hpp"

namespace descent {

// The stopping rule of the accuracy target TOL, shared by every method that
// reads its error from a CheckHistory: the step ends once the estimate is
// below kTargetShare TOL (after the Chebyshev bound's own count, where
// there is a bound; confirmed, where there is none), or below
// kConfidentShare TOL on the energies alone (with a bound).
constexpr double kTargetShare = 0.5;
constexpr double kConfidentShare = 0.1;
// The wide window of the error estimate, in checks: a stiff body's error
// oscillates over several checks (an armadillo at kappa 5e5 stopped at 16x
// its target on one check's small decrease).
constexpr int kWideWindow = 4;
// A reading is confirmed when the predicted minimum fell since the previous
// check by at most this share of the error left.
constexpr double kSettledShare = 0.5;

// What a history says about the accuracy target (CheckHistory::read).
struct AccuracyReading {
  // The larger of the estimates over the last checks and over the last two
  // windows of kWideWindow checks (the former alone while the latter is
  // unknown); NaN when neither is known.
  double estimate = std::numeric_limits<double>::quiet_NaN();
  // The last checks' estimate at or below kTargetShare TOL and the wide
  // one not above it.
  bool below = false;
  // Both known and at or below kConfidentShare TOL.
  bool far_below = false;
  // below at the previous check too, and the predicted minimum settled
  // (the rule of methods without a bound).
  bool confirmed = false;
  // The changes over the last two checks and over the last two wide windows
  // all lie within the round-off `noise`: the energies resolve no more
  // progress (a float step at its floor, a target below what the precision
  // resolves), whatever the estimate says.
  bool at_resolution = false;
};

class CheckHistory {
 public:
  // The recurrence (re)starts at a state of energy `energy`.
  void restart(double energy) {
    k_.assign(1, 0);
    energy_.assign(1, energy);
  }
  // An accepted check after `k` iterations since the restart.
  void record(int k, double energy) {
    k_.push_back(k);
    energy_.push_back(energy);
  }
  bool empty() const { return energy_.empty(); }
  double restart_energy() const { return energy_.front(); }

  // The relative error (eps_k - eps*) / (eps_initial - eps*) of the last
  // recorded state, for the run's Chebyshev rate phi (solver/spectrum.hpp;
  // 0: no bound), from the decreases over the last two windows of `window`
  // checks each (a wider window is not fooled by one check near a turning
  // point of the oscillating error); NaN when there are not 2 windows of
  // evenly spaced, decreasing checks after the restart's first window.
  double relative_error(double initial_energy, double phi, int window = 1) const {
    return relative(initial_energy, energy_.size(), remaining(phi, window, energy_.size()));
  }

  // The estimates over the last checks and the last wide windows against
  // the target TOL (> 0). `noise`: the energy's round-off (a check's
  // tolerance; 0: not known); two windows running whose changes both lie
  // within it say the error left is at most that, as far as the energies
  // can tell (a step already at its minimum, a small body converged in a
  // few checks), where the ratio of two round-off changes says nothing.
  AccuracyReading read(double initial_energy, double phi, double target, double noise = 0) const {
    const std::size_t n = energy_.size();
    const Window now = window_at(initial_energy, phi, target, noise, n);
    AccuracyReading reading;
    reading.estimate = now.estimate;
    reading.below = now.below;
    reading.far_below =
        now.near <= kConfidentShare * target && now.wide <= kConfidentShare * target;
    reading.at_resolution = within_noise(1, n, noise) && within_noise(kWideWindow, n, noise);
    if (now.below && n >= 2) {
      const Window before = window_at(initial_energy, phi, target, noise, n - 1);
      const double left = energy_[n - 1] - now.minimum;
      reading.confirmed = before.below && before.minimum - now.minimum <= kSettledShare * left;
    }
    return reading;
  }

 private:
  // A reading of the first n checks: the near and wide relative errors,
  // their combined estimate, the predicted minimum eps_k - (the larger
  // error left) and whether it is below the target.
  struct Window {
    double near, wide, estimate, minimum;
    bool below;
  };
  Window window_at(double initial_energy, double phi, double target, double noise,
                   std::size_t n) const {
    // The energies cannot vouch for less error left than their round-off:
    // an extrapolation below it (a float step at its floor, converging fast
    // under the multilevel preconditioner, read 4e-13 at e = 1.3e-5) is
    // read as the round-off.
    auto vouched = [noise](double left) { return left < noise ? noise : left; };
    const double near_left = vouched(remaining(phi, 1, n, noise));
    const double wide_left = vouched(remaining(phi, kWideWindow, n, noise));
    Window w;
    w.near = relative(initial_energy, n, near_left, noise);
    w.wide = relative(initial_energy, n, wide_left, noise);
    w.estimate = std::isnan(w.wide) ? w.near : std::max(w.near, w.wide);
    w.minimum =
        energy_[n - 1] - (std::isnan(wide_left) ? near_left : std::max(near_left, wide_left));
    w.below = w.near <= kTargetShare * target && !(w.wide > kTargetShare * target);
    return w;
  }

  // The decreases d1, d2 over the last two windows of `window` checks
  // before the n-th check, ending at iterations k1 and k2; known is false
  // when there are not two evenly spaced windows after the restart's first.
  struct Decreases {
    bool known = false;
    double d1 = 0, d2 = 0;
    int k1 = 0, k2 = 0;
  };
  Decreases decreases(int window, std::size_t n) const {
    const std::size_t w = static_cast<std::size_t>(window);
    if (window < 1 || n < 2 * w + 2) return {};
    const std::size_t i0 = n - 1 - 2 * w, i1 = n - 1 - w, i2 = n - 1;
    if (k_[i2] - k_[i1] != k_[i1] - k_[i0]) return {};
    return {true, energy_[i0] - energy_[i1], energy_[i1] - energy_[i2], k_[i1], k_[i2]};
  }
  static bool within(const Decreases& d, double noise) {
    return noise > 0 && d.known && std::abs(d.d1) <= noise && std::abs(d.d2) <= noise;
  }
  bool within_noise(int window, std::size_t n, double noise) const {
    return within(decreases(window, n), noise);
  }

  // eps_k - eps* at the n-th check (the first n recorded), NaN when unknown.
  //
  // Decreases within the round-off `noise` give no ratio of their own; the
  // error left is then the tail of a decrease of at most the noise at the
  // last ratio the energies resolved (the latest windows before n whose
  // decreases both exceed it), or the noise itself where none did. A slow
  // method's decreases fall below the noise while its error is still a few
  // times it: Nesterov's float step on the small helix read half its error
  // at the noise alone (tests/mpi/test_mixed_precision.cpp).
  double remaining(double phi, int window, std::size_t n, double noise = 0) const {
    const Decreases d = decreases(window, n);
    if (!d.known) return std::numeric_limits<double>::quiet_NaN();
    if (!within(d, noise)) return tail(d, phi, d.d2);
    for (std::size_t m = n - 1; m > 0; --m) {
      const Decreases resolved = decreases(window, m);
      if (!resolved.known) break;
      if (resolved.d1 > noise && resolved.d2 > noise) {
        const double left = tail(resolved, phi, noise);
        return std::isnan(left) ? noise : left;
      }
    }
    return noise;
  }
  // What is left after a decrease `last` at the ratio of the windows `d`
  // (at least the bound's own, with a bound); NaN without a ratio below 1.
  static double tail(const Decreases& d, double phi, double last) {
    if (!(d.d1 > 0 && d.d2 > 0)) return std::numeric_limits<double>::quiet_NaN();
    const double bound_ratio =
        phi > 0 ? chebyshev_error_bound(phi, d.k2) / chebyshev_error_bound(phi, d.k1) : 0.0;
    const double r = std::max(d.d2 / d.d1, bound_ratio);  // per window
    if (!(r < 1)) return std::numeric_limits<double>::quiet_NaN();
    return last * r / (1 - r);
  }
  // The error left at the n-th check relative to the initial one; 0 where
  // the energies cannot tell the initial state from the minimum (all the
  // step's change, and the error left, within the round-off `noise`).
  double relative(double initial_energy, std::size_t n, double left, double noise = 0) const {
    const double fallen = initial_energy - energy_[n - 1];
    if (noise > 0 && left <= noise && std::abs(fallen) <= noise) return 0;
    const double span = fallen + left;
    return span > 0 ? left / span : std::numeric_limits<double>::quiet_NaN();
  }

  std::vector<int> k_;
  std::vector<double> energy_;
};

}  // namespace descent
