#pragma once
// Collectives counted at the MPI boundary through the PMPI profiling
// interface: a test executable that compiles pmpi_counters.cpp has its
// MPI_Allreduce, MPI_Bcast, MPI_Barrier, MPI_Reduce, MPI_Allgather,
// MPI_Gather and MPI_Allgatherv replaced by counting wrappers around the
// PMPI_ originals.

namespace descent::testing {

// Calls of MPI_Allreduce so far on this rank.
long pmpi_allreduces();
// Calls of the other collectives listed above so far on this rank, but
// MPI_Allgatherv.
long pmpi_other_collectives();
// Calls of MPI_Allgatherv (the multilevel preconditioner's coarsest solve).
long pmpi_allgathervs();

}  // namespace descent::testing
