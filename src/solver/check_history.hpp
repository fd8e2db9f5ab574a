#pragma once
// The energies of the accepted checks of one Chebyshev run (since the
// recurrence last (re)started) and the relative error they imply: the a
// posteriori half of the accuracy target (solver.accuracy, issue 11).
//
// Once the error falls geometrically, eps_k - eps* = D r / (1 - r) with D
// the last decrease between checks and r the ratio of the last two
// decreases. r is taken as at least the Chebyshev bound's own ratio over the
// same iterations, B(k) / B(k_prev), so an early burst of fast decrease does
// not pass for convergence. Non-monotone stretches (the Chebyshev error
// oscillates between checks) give no estimate.
//
// Nor do two windows from the (re)start whose energies contradict the bound:
// there the decay is not the bound's, and the first window's fast start
// (the modes inside [a, b]) says nothing of the slow rest (a mode outside).
// The 316K helix with the multilevel preconditioner, whose P^-1 H reached
// 1.2 at the iterates against b = 1.1 at the refresh state, fell 2000x in
// its first 8 iterations and 4.5x in the next 8, then 0.27x per 8: the
// estimate from the first two windows was 1.7e-7, the error 1.2e-4.
#include <cmath>
#include <limits>
#include <vector>

#include "solver/spectrum.hpp"

namespace descent {

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
  // recorded state, for the run's rate phi (solver/spectrum.hpp), from the
  // decreases over the last two windows of `window` checks each (a wider
  // window is not fooled by one check near a turning point of the
  // oscillating error); NaN when there are not 2 windows of evenly spaced,
  // decreasing checks, or when they start at the restart and contradict the
  // bound by more than `noise` (the energy's round-off).
  double relative_error(double initial_energy, double phi, int window, double noise) const {
    const double unknown = std::numeric_limits<double>::quiet_NaN();
    const std::size_t n = energy_.size(), w = static_cast<std::size_t>(window);
    if (window < 1 || n < 2 * w + 1) return unknown;
    const std::size_t i0 = n - 1 - 2 * w, i1 = n - 1 - w, i2 = n - 1;
    if (k_[i2] - k_[i1] != k_[i1] - k_[i0]) return unknown;
    const double d1 = energy_[i0] - energy_[i1], d2 = energy_[i1] - energy_[i2];
    if (!(d1 > 0 && d2 > 0)) return unknown;
    if (i0 == 0 && contradicts_bound(phi, noise)) return unknown;
    const double bound_ratio =
        chebyshev_error_bound(phi, k_[i2]) / chebyshev_error_bound(phi, k_[i1]);
    const double r = std::max(d2 / d1, bound_ratio);  // per window
    if (!(r < 1)) return unknown;
    const double remaining = d2 * r / (1 - r);
    const double span = initial_energy - energy_.back() + remaining;
    return span > 0 ? remaining / span : unknown;
  }

  // Whether the last decrease is larger than the bound B for rate phi
  // allows, by more than `noise`. Where the spectrum lies in [a, b] the
  // error of a quadratic after k iterations from the restart is at most
  // B(k) (eps_0 - eps*); with eps* <= eps_last, eps_0 - eps* <= (eps_0 -
  // eps_last) / (1 - B(k_last)), so eps_prev - eps_last <= eps_prev - eps*
  // <= B(k_prev) (eps_0 - eps_last) / (1 - B(k_last)).
  bool contradicts_bound(double phi, double noise) const {
    const std::size_t n = energy_.size();
    if (n < 3) return false;
    const double last_decrease = energy_[n - 2] - energy_[n - 1];
    const double allowed = chebyshev_error_bound(phi, k_[n - 2]) *
                           (energy_.front() - energy_[n - 1]) /
                           (1 - chebyshev_error_bound(phi, k_[n - 1]));
    return last_decrease > allowed + noise;
  }

 private:
  std::vector<int> k_;
  std::vector<double> energy_;
};

}  // namespace descent
