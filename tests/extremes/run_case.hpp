#pragma once
// Runs one extremes case on every rank of a communicator and measures what
// the suite reports (issue 6): finite or not, the energy across each step,
// rollbacks, alpha, stalled steps, element inversion, and the final
// positions for the distance to a converged reference.
#include <mpi.h>

#include <limits>
#include <string>
#include <vector>

#include "extreme_cases.hpp"

namespace descent::extremes {

struct Result {
  bool finite = true;  // no step failed and every position is finite at the end
  // Every position and velocity finite at the end, failed step or not (a
  // failed step leaves the last good state): never a NaN state.
  bool state_finite = true;
  int failed_frame = 0;  // the first step that reached no finite state (0: none)
  std::string failure;   // what its ranks' scans named (rank, vertex or tet)
  int steps = 0;         // steps run (a failed step ends the run)
  long iterations = 0;   // over all steps
  int rollbacks = 0;     // over all steps
  int nonfinite_rollbacks = 0;
  int stalled_steps = 0;  // steps that ended with alpha below alpha_min
  double final_alpha = 0;
  // eps(q_{t+1}) <= eps(initial guess) + tolerance for every step, the
  // energies evaluated here, apart from the solver's own checks. The solver
  // lets each accepted check exceed the previous one by its round-off
  // tolerance (1024 eps_Real x sum of |terms|), so the step's tolerance is
  // that times the step's accepted checks. Not checked with model
  // conversion: its energy changes within a step.
  bool energy_checked = false;
  int energy_rises = 0;         // steps where it failed
  double worst_rise_ratio = 0;  // max over steps of rise / tolerance; <= 1 holds
  // Inversion over all frames: the smallest det F and smallest signed
  // singular value of any tet, and the most tets with det F <= 0 at once.
  double min_det = std::numeric_limits<double>::infinity();
  double min_sigma = std::numeric_limits<double>::infinity();
  long max_inverted = 0;
  long final_inverted = 0;
  // With Case::recovers: max |sigma - 1| over the tets at the end.
  double worst_stretch = std::numeric_limits<double>::quiet_NaN();
  double wall_s = 0;
  std::vector<double> positions;  // rank 0: final positions, xyz by global vertex id
  double bbox_diagonal = 0;       // of the rest mesh
};

// Collective over comm. `iterations` > 0 overrides solver.iterations, and a
// non-empty `method` overrides solver.method (the reference runs).
template <class Real>
Result run_case(MPI_Comm comm, const Case& c, int iterations = 0, const std::string& method = "");

// max |a - b| over all coordinates, divided by the rest bounding-box diagonal.
double relative_distance(const Result& a, const Result& reference);

}  // namespace descent::extremes
