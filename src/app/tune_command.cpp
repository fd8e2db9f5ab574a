#include "app/tune_command.hpp"

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <memory>
#include <sstream>

#include "app/count_option.hpp"
#include "app/mesh_setup.hpp"
#include "app/simulation.hpp"

namespace descent {

namespace {

// The first and largest steps: a factor 10 on 1 - rho, 2 on alpha.
const double kLargestGapStep = std::log(10.0);
const double kLargestAlphaStep = std::log(2.0);

// A candidate: per phase x_p = log(1 - rho_p), y = log(alpha_max), and the
// lengths of all phases but the last.
struct Candidate {
  std::vector<double> log_gap;
  double log_alpha = 0;
  std::vector<int> lengths;
};

SolverSpec fixed_spec(SolverSpec spec, const Candidate& c) {
  spec.method = "chebyshev";
  spec.chebyshev_parameters = "fixed";
  spec.accuracy = 0;
  spec.phase_rho.clear();
  for (double x : c.log_gap) spec.phase_rho.push_back(1 - std::exp(x));
  spec.phase_lengths = c.lengths;
  spec.alpha_max = std::exp(c.log_alpha);
  spec.alpha_min = std::min(spec.alpha_min, spec.alpha_max);
  return spec;
}

std::string describe(const Candidate& c) {
  std::ostringstream s;
  // Every digit: a rho of 1 - 1e-9 written with 8 would read back as 1.
  s.precision(std::numeric_limits<double>::max_digits10);
  s << "chebyshev_parameters = \"fixed\"\nphase_rho = [";
  for (std::size_t i = 0; i < c.log_gap.size(); ++i)
    s << (i ? ", " : "") << 1 - std::exp(c.log_gap[i]);
  s << "]\nphase_lengths = [";
  for (std::size_t i = 0; i < c.lengths.size(); ++i) s << (i ? ", " : "") << c.lengths[i];
  s << "]\nalpha_max = " << std::exp(c.log_alpha);
  return s.str();
}

// Neighbours of `c` at steps (dx in log(1 - rho), dy in log(alpha)) and
// boundary shifts of `shift`, valid for a budget of `budget` iterations.
std::vector<Candidate> neighbours(const Candidate& c, double dx, double dy, int shift, int budget) {
  std::vector<Candidate> out;
  for (std::size_t p = 0; p < c.log_gap.size(); ++p)
    for (double sign : {+1.0, -1.0}) {
      Candidate n = c;
      n.log_gap[p] += sign * dx;
      // rho in (0, 1) and 1 - rho resolvable in double.
      if (n.log_gap[p] < 0 && n.log_gap[p] > std::log(1e-12)) out.push_back(n);
    }
  for (double sign : {+1.0, -1.0}) {
    Candidate n = c;
    n.log_alpha += sign * dy;
    out.push_back(n);
  }
  for (std::size_t b = 0; b < c.lengths.size(); ++b)
    for (int sign : {+1, -1}) {
      Candidate n = c;
      // Moving boundary b shifts iterations between phases b and b + 1.
      n.lengths[b] += sign * shift;
      if (b + 1 < n.lengths.size()) n.lengths[b + 1] -= sign * shift;
      int total = 0;
      bool valid = true;
      for (int l : n.lengths) {
        valid = valid && l >= 1;
        total += l;
      }
      if (valid && total < budget) out.push_back(n);
    }
  return out;
}

}  // namespace

CLI::App* add_tune_subcommand(CLI::App& app, TuneOptions& options) {
  CLI::App* tune = app.add_subcommand(
      "tune",
      "Tune Chebyshev's fixed phases, rho and alpha by pre-simulation (paper 1, Eq. 9, as a "
      "compass search in log(1 - rho))");
  tune->add_option("--phases", options.phases, "Number of phases P")->check(at_least(1));
  tune->add_option("--epsilon", options.epsilon,
                   "Smallest step of log(1 - rho) and log(alpha) (Eq. 9's eps; default 0.05)")
      ->check(CLI::Range(1e-6, 0.5));
  tune->add_option("--shift", options.shift, "Iterations a phase boundary moves per trial")
      ->check(at_least(1));
  tune->add_option("--warmup", options.warmup, "Frames of the scene's method first")
      ->check(at_least(0));
  tune->add_option("--frames", options.frames, "Pre-simulation states the cost sums over")
      ->check(at_least(1));
  tune->add_option("--max-cycles", options.max_cycles, "Upper bound on tuning cycles")
      ->check(at_least(1));
  tune->add_option("--tune-out", options.out_file, "File for the tuned scene keys");
  tune->add_flag("--quiet", options.quiet, "No progress output");
  return tune;
}

int run_tune(MPI_Comm comm, const Scene& scene, const TuneOptions& options) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  Simulation<double> sim(comm, scene, set_up_mesh(comm, scene, {}));
  for (int f = 0; f < options.warmup; ++f) sim.step();
  std::vector<BodyState<double>> states;
  std::vector<StepMemory> memories;
  for (int f = 0; f < options.frames; ++f) {
    states.push_back(sim.state());
    memories.push_back(sim.stepper().memory());
    sim.step();
  }
  const int budget = scene.solver.iterations;
  // Sum of eps after one step from each state; +inf when a step fails.
  auto cost_of = [&](const SolverSpec& spec, bool automatic) {
    double sum = 0;
    for (std::size_t s = 0; s < states.size(); ++s) {
      std::unique_ptr<Stepper<double>> stepper = make_stepper(sim.problem(), spec);
      // The automatic parameters as a run has them there (the warm-up's
      // estimate); fixed candidates start at their alpha_max, as a tuned
      // run's first step does.
      if (automatic) stepper->set_memory(memories[s]);
      BodyState<double> copy = states[s];
      const StepStats stats = stepper->step(copy);
      if (!stats.finite || !std::isfinite(stats.energy))
        return std::numeric_limits<double>::infinity();
      sum += stats.energy;
    }
    return sum;
  };

  // Start: P equal phases at the scene's rho (or 0.96, the paper's, when the
  // scene's parameters are automatic) and its alpha_max.
  const double rho0 = scene.solver.chebyshev_parameters == "fixed" ? scene.solver.rho : 0.96;
  Candidate best;
  const int length = budget / options.phases;
  for (int p = 0; p < options.phases; ++p) {
    best.log_gap.push_back(std::log(1 - rho0));
    if (p + 1 < options.phases) best.lengths.push_back(length);
  }
  best.log_alpha = std::log(scene.solver.alpha_max);
  double best_cost = cost_of(fixed_spec(scene.solver, best), false);
  const double start_cost = best_cost;
  int evaluations = 1;
  double dx = kLargestGapStep, dy = kLargestAlphaStep;
  int cycle = 0;
  for (; cycle < options.max_cycles && (dx >= options.epsilon || dy >= options.epsilon); ++cycle) {
    const Candidate* chosen = nullptr;
    double chosen_cost = best_cost;
    const std::vector<Candidate> candidates = neighbours(best, dx, dy, options.shift, budget);
    for (const Candidate& c : candidates) {
      const double value = cost_of(fixed_spec(scene.solver, c), false);
      ++evaluations;
      // A decrease within round-off of eps is no decrease.
      if (value < chosen_cost - 1e-12 * std::abs(chosen_cost)) {
        chosen_cost = value;
        chosen = &c;
      }
    }
    if (!chosen) {  // nothing better at these steps: look closer
      dx /= 2;
      dy /= 2;
      continue;
    }
    best = *chosen;
    best_cost = chosen_cost;
    dx = std::min(2 * dx, kLargestGapStep);
    dy = std::min(2 * dy, kLargestAlphaStep);
    if (rank == 0 && !options.quiet)
      // On stderr: stdout is the tuned [solver] table, for a pipe or a file.
      std::fprintf(stderr, "descent: tune: cycle %d: cost %.12e (start %.12e)\n  %s\n", cycle + 1,
                   best_cost, start_cost, describe(best).c_str());
  }

  // The automatic parameters at the same states, for comparison.
  SolverSpec automatic = scene.solver;
  automatic.method = "chebyshev";
  automatic.chebyshev_parameters = "auto";
  automatic.accuracy = 0;
  automatic.phase_rho.clear();
  automatic.phase_lengths.clear();
  const double automatic_cost = cost_of(automatic, true);
  const StepMemory estimate = memories.front();
  std::string comparison = "automatic parameters: cost " + std::to_string(automatic_cost);
  if (estimate.lambda_max > 0) {
    const double a = estimate.lambda_min, b = estimate.lambda_max;
    std::ostringstream s;
    s.precision(8);
    s << "automatic parameters: spectrum [" << a << ", " << b << "], rho " << (b - a) / (b + a)
      << ", alpha " << 2 / (a + b) << ", cost " << automatic_cost;
    comparison = s.str();
  }

  if (rank == 0) {
    std::ofstream out(options.out_file);
    out.precision(12);
    out << "# descent tune: " << options.phases << " phase(s), compass search in log(1 - rho) "
        << "and log(alpha) down to steps of " << options.epsilon << ", " << cycle << " cycles, "
        << evaluations << " pre-simulation evaluations over " << options.frames
        << " state(s) after " << options.warmup << " frames\n"
        << "# cost (sum of eps after one step): start " << start_cost << ", tuned " << best_cost
        << "\n# " << comparison << "\n[solver]\n"
        << describe(best) << "\n";
    std::printf("[solver]\n%s\n# %s\n", describe(best).c_str(), comparison.c_str());
    if (!options.quiet)
      std::fprintf(stderr,
                   "descent: tune: wrote %s (%d cycles, %d evaluations; cost %.12e -> %.12e)\n",
                   options.out_file.c_str(), cycle, evaluations, start_cost, best_cost);
  }
  return 0;
}

}  // namespace descent
