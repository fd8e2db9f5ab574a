#pragma once
// --precision auto (issue 22 part 3): the solver's Real type from the backend
// and the accuracy target. bench/results/precision.md measures what float
// leaves: its error floor (the float gradient's round-off: the iteration
// converges to where the float forces balance) was 1.3e-5 to 1.7e-5 on the
// 9K helix and 8.6e-6 on the 82K helix with the energies judged in double,
// so float met targets 1e-2 .. 1e-4 and not 1e-5. The floor rises for a body
// that moves less per step (e is relative to the step's decrease), and a
// step learns it only where its checks reach it (CheckHistory's
// at_resolution), after spending the iterations. So auto asks for a margin
// of about 100x: float for targets of 1e-3 and looser, and for a fixed
// iteration budget (no target: the paper's GPU setting). On the CPU float
// gained 1.0-1.6x on the 9K helix (in cache), 1.37x on the 82K helix with
// the multilevel preconditioner at 1e-2 (0.7x at 1e-3, where its steps end
// at round-off late: docs/cpu.md) and 1.4-1.7x with Jacobi's: auto stays
// double there, the precision every CPU test and figure was verified in, and
// --precision float asks for the gain where the target allows it.
#include <string>

namespace descent {

// The tightest accuracy target auto runs in float on a GPU; below it, double.
constexpr double kFloatAccuracyTarget = 1e-3;

struct PrecisionChoice {
  bool use_float = false;
  std::string why;  // one line for the run's log
};

// `requested`: "auto", "float" or "double"; `accuracy`: solver.accuracy (0:
// a fixed iteration budget).
inline PrecisionChoice choose_precision(const std::string& requested, bool on_gpu,
                                        double accuracy) {
  if (requested == "float") return {true, "float (asked)"};
  if (requested == "double") return {false, "double (asked)"};
  if (!on_gpu) return {false, "double (auto: the CPU)"};
  if (accuracy > 0 && accuracy < kFloatAccuracyTarget)
    return {false, "double (auto: solver.accuracy below 1e-3, float's error floor is near 1e-5)"};
  return {true, "float (auto: a GPU, solver.accuracy 1e-3 or looser)"};
}

}  // namespace descent
