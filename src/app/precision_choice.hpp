#pragma once
// --precision auto (issue 22 part 3): the solver's Real type from the backend
// and the accuracy target. bench/results/precision.md measures what float
// leaves, against Newton in double in the double problem: with the
// multilevel preconditioner a floor of 1e-7 of a step's decrease (the
// rounding of the minimum), so float met 1e-2 .. 1e-5 on the 82K helix;
// with Jacobi's a floor where its updates fall below half a unit, 1.7e-6 at
// 9K tets and 1.6e-5 at 82K (met to 1e-5 and to 1e-4). Both floors rise
// with the mesh and, relative to the step's decrease, for a body that moves
// less per step, and a step learns its floor only where its checks reach it
// (CheckHistory's at_resolution), after spending the iterations. So auto
// asks for a wide margin: float for targets of 1e-3 and looser, and for a
// fixed iteration budget (no target: the paper's GPU setting). On the CPU
// float gained 1.3-1.5x on the helix: auto stays double there, the
// precision every CPU test and figure was verified in, and --precision
// float asks for the gain where the target allows it.
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
    return {false, "double (auto: solver.accuracy below 1e-3, where float's floor can bind)"};
  return {true, "float (auto: a GPU, solver.accuracy 1e-3 or looser)"};
}

}  // namespace descent
