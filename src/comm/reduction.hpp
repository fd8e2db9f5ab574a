#pragma once
// The one global reduction of the descent iteration: the total energy, with a
// count of ranks whose local terms were not finite riding in the same
// MPI_Allreduce (no second collective for the NaN check).
#include <mpi.h>

namespace descent {

// An energy and the sum of the magnitudes of its terms: the scale of its
// round-off, so a change below that scale is not read as a rise.
struct Energy {
  double value = 0;
  double magnitude = 0;
};

// Up to two energies travel together: the first check of a time step also
// carries the energy of the step's initial guess, so the initial guess costs
// no collective of its own.
struct EnergySums {
  Energy energy[2];
  bool all_finite = true;
};

struct ReductionCounters {
  long allreduces = 0;
  double seconds = 0;
};

class EnergyReduction {
 public:
  explicit EnergyReduction(MPI_Comm comm) : comm_(comm) {}
  // Global sums of `count` (1 or 2) local energies; one MPI_Allreduce.
  EnergySums sum(const Energy* local, int count);
  const ReductionCounters& counters() const { return counters_; }

 private:
  MPI_Comm comm_;
  ReductionCounters counters_;
};

}  // namespace descent
