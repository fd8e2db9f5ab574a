#pragma once
// `descent tune SCENE`: the paper's pre-simulation tuning of Chebyshev phases
// (paper 1, §4.3, Eq. 9). From the states of `frames` consecutive frames
// (after `warmup` frames of the scene's method), one step of `chebyshev` is
// run per candidate; its cost is the sum over those states of eps at the end
// of the step (eps* of each state is a constant, so this orders candidates as
// the sum of their errors would). A cycle tries, for every phase, rho <-
// 1 - (1 +- eps)(1 - rho), and every boundary between two phases moved by
// +- `shift` iterations; the best change is kept; tuning ends when no change
// lowers the cost. The result is written as scene keys (solver.phase_rho,
// solver.phase_lengths) to `out_file` and printed.
#include <mpi.h>

#include <functional>
#include <string>
#include <vector>

#include "io/scene.hpp"

namespace CLI {
class App;
}

namespace descent {

struct TuneOptions {
  int phases = 2;
  double epsilon = 0.05;  // Eq. 9
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
