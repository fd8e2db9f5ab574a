#include "app/tune_command.hpp"

#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <memory>
#include <sstream>

#include "app/scene_mesh.hpp"
#include "app/simulation.hpp"

namespace descent {

namespace {

struct Phases {
  std::vector<double> rho;
  std::vector<int> lengths;  // of all phases but the last
};

SolverSpec with_phases(SolverSpec spec, const Phases& p) {
  spec.method = "chebyshev";
  spec.phase_rho = p.rho;
  spec.phase_lengths = p.lengths;
  return spec;
}

std::string describe(const Phases& p) {
  std::ostringstream s;
  s.precision(6);
  s << "phase_rho = [";
  for (std::size_t i = 0; i < p.rho.size(); ++i) s << (i ? ", " : "") << p.rho[i];
  s << "]\nphase_lengths = [";
  for (std::size_t i = 0; i < p.lengths.size(); ++i) s << (i ? ", " : "") << p.lengths[i];
  s << "]";
  return s.str();
}

}  // namespace

CLI::App* add_tune_subcommand(CLI::App& app, TuneOptions& options) {
  CLI::App* tune = app.add_subcommand(
      "tune", "Tune Chebyshev phases and their rho by pre-simulation (paper 1, Eq. 9)");
  tune->add_option("--phases", options.phases, "Number of phases P")->check(CLI::PositiveNumber);
  tune->add_option("--epsilon", options.epsilon, "Eq. 9's step for rho (default 0.05)")
      ->check(CLI::Range(1e-6, 0.5));
  tune->add_option("--shift", options.shift, "Iterations a phase boundary moves per trial")
      ->check(CLI::PositiveNumber);
  tune->add_option("--warmup", options.warmup, "Frames of the scene's method first")
      ->check(CLI::NonNegativeNumber);
  tune->add_option("--frames", options.frames, "Pre-simulation states the cost sums over")
      ->check(CLI::PositiveNumber);
  tune->add_option("--max-cycles", options.max_cycles, "Upper bound on tuning cycles")
      ->check(CLI::PositiveNumber);
  tune->add_option("--tune-out", options.out_file, "File for the tuned scene keys");
  tune->add_flag("--quiet", options.quiet, "No progress output");
  return tune;
}

int run_tune(MPI_Comm comm, const Scene& scene, const TuneOptions& options) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  const Mesh mesh = build_scene_mesh(scene.mesh);
  Simulation<double> sim(comm, scene, mesh);
  for (int f = 0; f < options.warmup; ++f) sim.step();
  std::vector<BodyState<double>> states;
  for (int f = 0; f < options.frames; ++f) {
    states.push_back(sim.state());
    sim.step();
  }
  const int budget = scene.solver.iterations;
  auto cost = [&](const Phases& p) {
    const SolverSpec spec = with_phases(scene.solver, p);
    double sum = 0;
    for (const BodyState<double>& s : states) {
      std::unique_ptr<Stepper<double>> stepper = make_stepper(sim.problem(), spec);
      BodyState<double> copy = s;
      const StepStats stats = stepper->step(copy);
      if (!std::isfinite(stats.energy)) return std::numeric_limits<double>::infinity();
      sum += stats.energy;
    }
    return sum;
  };

  // Start: P equal phases at the scene's rho.
  Phases best;
  const int length = budget / options.phases;
  for (int p = 0; p < options.phases; ++p) {
    best.rho.push_back(scene.solver.rho);
    if (p + 1 < options.phases) best.lengths.push_back(length);
  }
  double best_cost = cost(best);
  const double start_cost = best_cost;
  int evaluations = 1;
  for (int cycle = 0; cycle < options.max_cycles; ++cycle) {
    std::vector<Phases> candidates;
    for (std::size_t p = 0; p < best.rho.size(); ++p)
      for (double sign : {+1.0, -1.0}) {
        Phases c = best;
        c.rho[p] = 1 - (1 + sign * options.epsilon) * (1 - c.rho[p]);  // Eq. 9
        if (c.rho[p] >= 0 && c.rho[p] < 1) candidates.push_back(c);
      }
    for (std::size_t b = 0; b < best.lengths.size(); ++b)
      for (int sign : {+1, -1}) {
        Phases c = best;
        // Moving boundary b shifts iterations between phases b and b + 1.
        c.lengths[b] += sign * options.shift;
        if (b + 1 < c.lengths.size()) c.lengths[b + 1] -= sign * options.shift;
        int total = 0;
        bool valid = c.lengths[b] >= 1;
        for (int l : c.lengths) {
          valid = valid && l >= 1;
          total += l;
        }
        if (valid && total < budget) candidates.push_back(c);
      }
    const Phases* chosen = nullptr;
    double chosen_cost = best_cost;
    for (const Phases& c : candidates) {
      const double value = cost(c);
      ++evaluations;
      // A decrease within round-off of eps is no decrease.
      if (value < chosen_cost - 1e-12 * std::abs(chosen_cost)) {
        chosen_cost = value;
        chosen = &c;
      }
    }
    if (!chosen) break;
    best = *chosen;
    best_cost = chosen_cost;
    if (rank == 0 && !options.quiet)
      std::fprintf(stderr, "tune: cycle %d: cost %.12e (start %.12e)\n  %s\n", cycle + 1, best_cost,
                   start_cost, describe(best).c_str());
  }
  if (rank == 0) {
    std::ofstream out(options.out_file);
    out << "# descent tune: " << options.phases << " phases, Eq. 9 with epsilon " << options.epsilon
        << ", " << evaluations << " pre-simulation evaluations over " << options.frames
        << " state(s) after " << options.warmup << " frames\n"
        << "[solver]\n"
        << describe(best) << "\n";
    std::printf("[solver]\n%s\n", describe(best).c_str());
    if (!options.quiet)
      std::fprintf(stderr, "tune: wrote %s (%d evaluations; cost %.12e -> %.12e)\n",
                   options.out_file.c_str(), evaluations, start_cost, best_cost);
  }
  return 0;
}

}  // namespace descent
