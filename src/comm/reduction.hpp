#pragma once
// The one global reduction of the descent iteration: the total energy, with a
// count of ranks whose local terms were not finite riding in the same
// MPI_Allreduce (no second collective for the NaN check).
#include <mpi.h>

#include <cstdint>
#include <limits>
#include <vector>

namespace descent {

// An energy and the sum of the magnitudes of its terms: the scale of its
// round-off, so a change below that scale is not read as a rise. The terms
// are evaluated in double (loops::local_energy); a term evaluated in another
// precision counts with in_double_units.
struct Energy {
  double value = 0;
  double magnitude = 0;
};

// The magnitude of terms evaluated in Real, in Energy::magnitude's units:
// weighted by Real's epsilon over double's (2^29 for a float run's
// body-contact pairs).
template <class Real>
double in_double_units(double magnitude) {
  return magnitude *
         (std::numeric_limits<Real>::epsilon() / std::numeric_limits<double>::epsilon());
}

// Up to two energies travel together: the first check of a time step also
// carries the energy of the step's initial guess, so the initial guess costs
// no collective of its own.
struct EnergySums {
  Energy energy[2];
  bool finite[2] = {true, true};  // no rank had a non-finite term in energy[k]
};

struct ReductionCounters {
  long allreduces = 0;        // energy checks
  long other_allreduces = 0;  // per-frame measurements
  // Inner products and maxima of methods other than chebyshev (one
  // MPI_Allreduce each, possibly several values fused).
  long dot_allreduces = 0;
  double seconds = 0;
  // Newton's direct solver (newton_solver = "ldlt"): gathers to rank 0 and
  // scatters from it (MPI_Gather/Gatherv, MPI_Scatterv), never allreduces.
  long root_gathers = 0;
  long root_scatters = 0;
};

class EnergyReduction {
 public:
  explicit EnergyReduction(MPI_Comm comm) : comm_(comm) {}
  // Global sums of `count` (1 or 2) local energies; one MPI_Allreduce.
  EnergySums sum(const Energy* local, int count);
  // Sums `values` over all ranks in place: for per-frame measurements, never
  // inside the iteration loop (counted apart from the energy checks).
  void sum_in_place(std::vector<double>& values);

  // Sums `count` local partial inner products over all ranks in place: one
  // MPI_Allreduce, counted in dot_allreduces and timed in seconds.
  void sum_dots(double* values, int count);
  // The maximum of `value` over all ranks: one MPI_Allreduce, counted as a dot.
  double max_of(double value);
  // The maxima of `count` values over all ranks, in place: one MPI_Allreduce,
  // counted as a dot.
  void max_in_place(double* values, int count);

  // For Newton's direct solver (solver/methods/newton_ldlt.hpp), which
  // assembles the global system on rank 0. Each is one collective, counted
  // in root_gathers or root_scatters. `counts` (values per rank, rank order)
  // is read on rank 0 only; blocks lie in rank order without gaps.
  // Rank 0's count of each rank's values (MPI_Gather); empty on other ranks.
  std::vector<int> gather_counts(int count);
  // Every rank's `count` values, concatenated on rank 0 (MPI_Gatherv); recv
  // is resized on rank 0 and untouched elsewhere.
  void gather_to_root(const double* send, int count, const std::vector<int>& counts,
                      std::vector<double>& recv);
  void gather_to_root(const std::int32_t* send, int count, const std::vector<int>& counts,
                      std::vector<std::int32_t>& recv);
  // Rank r receives its block of rank 0's `send` into recv[0, count)
  // (MPI_Scatterv); send is read on rank 0 only.
  void scatter_from_root(const std::vector<double>& send, const std::vector<int>& counts,
                         double* recv, int count);

  const ReductionCounters& counters() const { return counters_; }

 private:
  MPI_Comm comm_;
  ReductionCounters counters_;
};

}  // namespace descent
