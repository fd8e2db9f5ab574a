#pragma once
// Chebyshev phases (paper 1, §4.3): the iterations of a step split into P
// phases, each with its own rho; a phase starts by restarting the Chebyshev
// recurrence. Phase p covers iterations [start_p, start_p + length_p); the
// last phase runs to the end of the budget. No phases listed: one phase with
// solver.rho, the method as before.
#include <vector>

#include "io/scene.hpp"

namespace descent {

class ChebyshevPhases {
 public:
  explicit ChebyshevPhases(const SolverSpec& spec) {
    if (spec.phase_rho.empty()) {
      starts_ = {0};
      rho_ = {spec.rho};
      return;
    }
    int start = 0;
    for (std::size_t p = 0; p < spec.phase_rho.size(); ++p) {
      starts_.push_back(start);
      rho_.push_back(spec.phase_rho[p]);
      if (p < spec.phase_lengths.size()) start += spec.phase_lengths[p];
    }
  }
  // rho of the phase iteration k (0-based) belongs to.
  double rho(int k) const { return rho_[phase_of(k)]; }
  // Whether iteration k > 0 opens a phase (the recurrence restarts there).
  bool starts_phase(int k) const {
    if (k == 0) return false;
    for (int s : starts_)
      if (s == k) return true;
    return false;
  }

 private:
  std::size_t phase_of(int k) const {
    std::size_t p = 0;
    while (p + 1 < starts_.size() && starts_[p + 1] <= k) ++p;
    return p;
  }
  std::vector<int> starts_;
  std::vector<double> rho_;
};

}  // namespace descent
