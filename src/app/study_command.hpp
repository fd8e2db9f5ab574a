#pragma once
// `descent study SCENE`: the speed-accuracy trade of the methods on one
// scene (issue 5). After `warmup` frames of the scene's own method, for each
// case (a label and solver keys) one time step is observed iteration by
// iteration against Newton's eps* from the same state: relative error e_k,
// wall time (median of `repeats` runs), collectives and time inside them.
// Written to out_dir: study.csv (every case, iteration and measured frame),
// pareto.csv (the cheapest case and budget per error level), accuracy.csv
// (per case with solver.accuracy: how many steps ended at or below the
// target, the worst and median e / TOL, whether at least 90% did and all
// within 3 TOL; also printed at the end) and a progress line per case.
// tools/plot_study.py draws the PNGs.
#include <mpi.h>

#include <functional>
#include <string>
#include <vector>

#include "io/scene.hpp"

namespace CLI {
class App;
}

namespace descent {

struct StudyCase {
  std::string label;
  std::vector<std::string> overrides;  // scene overrides ("solver.method=\"gd\"", ...)
};

struct StudyOptions {
  std::vector<std::string> case_texts;  // --case, parsed by parse_study_case
  std::vector<StudyCase> cases;
  int warmup = 10;  // frames of the scene's method before the first measurement
  int frames = 1;   // measured frames
  int every = 1;    // frames advanced between measured frames
  int repeats = 3;  // timing repeats per case (median per iteration)
  std::string out_dir = "study";
  std::string precision = "double";  // the methods' Real; eps* and eps(q_k) in double
  // Newton's linear solver for the truth eps*: "auto" is "petsc" (CG with
  // algebraic multigrid) in a build with PETSc where the scene leaves
  // solver.newton_solver at its default "cg", else the scene's; or "cg",
  // "ldlt", "petsc".
  std::string truth_solver = "auto";
  bool quiet = false;
};

// The `study` subcommand's options, filling `options` (scene and --set are
// the caller's, shared with the other subcommands).
CLI::App* add_study_subcommand(CLI::App& app, StudyOptions& options);

// Returns the exit code. Collective. `read(overrides)` reads the scene with
// the command line's --set plus `overrides` (each case's solver keys).
int run_study(MPI_Comm comm, const std::function<Scene(const std::vector<std::string>&)>& read,
              StudyOptions options);

// "label:key=value key=value" (keys without the "solver." prefix) or a bare
// method name; an InputError names the text otherwise.
StudyCase parse_study_case(const std::string& text);

}  // namespace descent
