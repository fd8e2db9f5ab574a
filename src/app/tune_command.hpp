#pragma once
// `descent tune SCENE`: the paper's pre-simulation tuning of Chebyshev's
// fixed parameters (paper 1, §4.3, Eq. 9), made able to reach the range the
// spectrum asks for. From the states of `frames` consecutive frames (after
// `warmup` frames of the scene's method), one step of Chebyshev with fixed
// parameters is run per candidate; its cost is the sum over those states of
// eps at the end of the step (eps* of each state is a constant, so this
// orders candidates as the sum of their errors would).
//
// The search is a compass search in log(1 - rho_p) of every phase p, in
// log(alpha_max) and in the phase boundaries: Eq. 9's move rho <- 1 - (1 +-
// eps)(1 - rho) is a step of eps in log(1 - rho), but a fixed 5% step needs
// ~100 cycles from 0.96 to 0.9998; here a step that finds no better
// candidate halves, one that does doubles, from and up to a factor 10 on
// 1 - rho (and 2 on alpha). The search ends when every step is below
// `epsilon` or after `max_cycles`. The result is written as scene keys
// (solver.chebyshev_parameters = "fixed", phase_rho, phase_lengths,
// alpha_max) to `out_file` and printed, with the automatic parameters'
// estimate at the same states and both costs for comparison.
#include <mpi.h>

#include <string>

#include "io/scene.hpp"

namespace CLI {
class App;
}

namespace descent {

struct TuneOptions {
  int phases = 2;
  double epsilon = 0.05;  // smallest step of log(1 - rho) and log(alpha) (Eq. 9's eps)
  int shift = 4;          // iterations a phase boundary moves per trial
  int warmup = 10;
  int frames = 2;
  int max_cycles = 60;
  std::string out_file = "tuned_phases.toml";
  bool quiet = false;
};

CLI::App* add_tune_subcommand(CLI::App& app, TuneOptions& options);

// Returns the exit code. Collective.
int run_tune(MPI_Comm comm, const Scene& scene, const TuneOptions& options);

}  // namespace descent
