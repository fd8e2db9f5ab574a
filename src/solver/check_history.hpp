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
  // recorded state, for the run's rate phi (solver/spectrum.hpp); NaN when
  // the last three checks do not decrease at evenly spaced iterations.
  double relative_error(double initial_energy, double phi) const {
    const double unknown = std::numeric_limits<double>::quiet_NaN();
    const std::size_t n = energy_.size();
    if (n < 3) return unknown;
    const int k0 = k_[n - 3], k1 = k_[n - 2], k2 = k_[n - 1];
    if (k2 - k1 != k1 - k0) return unknown;
    const double d1 = energy_[n - 3] - energy_[n - 2], d2 = energy_[n - 2] - energy_[n - 1];
    if (!(d1 > 0 && d2 > 0)) return unknown;
    const double bound_ratio = chebyshev_error_bound(phi, k2) / chebyshev_error_bound(phi, k1);
    const double r = std::max(d2 / d1, bound_ratio);
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
