#pragma once
// Peak resident memory of every rank, for the log: what a user sizing a job
// needs, and what the set-up benchmarks record.
#include <mpi.h>

#include <string>

namespace descent {

// Collective: one line on rank 0, e.g. "peak RSS per rank: 412 412 398 401
// MB (mean 406, rank 0 +1%)"; up to 16 ranks listed, else min/mean/max. The
// peak is the process's since it started (getrusage). Empty on other ranks.
std::string peak_memory_report(MPI_Comm comm);

}  // namespace descent
