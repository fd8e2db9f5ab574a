#pragma once
// What the run driver does when a step met non-finite values: a status per
// step for stats.csv, a warning naming a rolled-back trial's culprit, and the
// stop, with a message naming frame, rank and element, when a step reached no
// state with finite energy. The detection itself rides on the energy
// reduction (StepStats::finite, nonfinite_rollbacks); only the failure path
// here makes a collective of its own.
#include <mpi.h>

#include <string>

#include "common/error.hpp"
#include "solver/stepper.hpp"

namespace descent {

// The `status` column of stats.csv for a step (FrameStats::status).
const char* step_status(const StepStats& step);

// One line on stderr, from the rank whose local scan found `site`: a trial
// state of `frame` had a non-finite value there and was rolled back.
void warn_rolled_back(int frame, int rank, const NonFiniteSite& site);

// A step that reached no finite state: the run cannot go on.
struct NonFiniteError : Error {
  using Error::Error;
};

// Collective; every rank calls it after a step with step.finite false (all
// know it from the reduction). One MPI_Allreduce chooses the reporter: the
// lowest rank whose scan found a culprit, else rank 0 (the sum overflowed).
// Throws NonFiniteError naming frame, rank and culprit on the reporter;
// returns on the others, which must end the run as well. `last_good` says
// where the last good state was written.
void report_failed_step(MPI_Comm comm, int frame, const StepStats& step,
                        const std::string& last_good);

}  // namespace descent
