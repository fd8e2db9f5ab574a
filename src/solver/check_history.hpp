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
// Nor does a window that starts at the (re)start: its fall is the fast
// start (the modes the bound covers), and beside it the next window's small
// decrease reads as convergence whether the error has vanished or stalls
// (a mode outside [a, b], or the nonlinearity the estimate at the guess did
// not see). With the multilevel preconditioner, windows from the restart
// stopped the 316K helix at e = 1.2e-4 for a target of 1e-6 (a fall of
// 2000x, then 4.5x, then 0.27x a window) and an armadillo at 2.9e-3 for
// 1e-4 (e_8 5.4e-3, e_16 2.9e-3).
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
  // decreasing checks after the restart's first window.
  double relative_error(double initial_energy, double phi, int window = 1) const {
    const double unknown = std::numeric_limits<double>::quiet_NaN();
    const std::size_t n = energy_.size(), w = static_cast<std::size_t>(window);
    if (window < 1 || n < 2 * w + 2) return unknown;
    const std::size_t i0 = n - 1 - 2 * w, i1 = n - 1 - w, i2 = n - 1;
    if (k_[i2] - k_[i1] != k_[i1] - k_[i0]) return unknown;
    const double d1 = energy_[i0] - energy_[i1], d2 = energy_[i1] - energy_[i2];
    if (!(d1 > 0 && d2 > 0)) return unknown;
    const double bound_ratio =
        chebyshev_error_bound(phi, k_[i2]) / chebyshev_error_bound(phi, k_[i1]);
    const double r = std::max(d2 / d1, bound_ratio);  // per window
    if (!(r < 1)) return unknown;
    const double remaining = d2 * r / (1 - r);
    const double span = initial_energy - energy_.back() + remaining;
    return span > 0 ? remaining / span : unknown;
  }

 private:
  std::vector<int> k_;
  std::vector<double> energy_;
};

}  // namespace descent
