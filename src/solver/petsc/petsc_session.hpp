#pragma once
// PETSc's life in a descent process. PETSc is started on first use, not at
// start-up: runs that use no PETSc solver pay nothing. Its options are, in
// order, PETSC_OPTIONS, --petsc-options (main puts them in PETSC_OPTIONS
// before the start) and the scene's solver.petsc_options; `-log_view`
// prints its summary at finish_petsc().
#include <string>

namespace descent {

// Whether this build has PETSc (CMake found petsc-dev).
bool petsc_compiled();

// Collective over MPI_COMM_WORLD on the first call (PetscInitialize), then
// only inserts `options` into PETSc's database. Throws InputError naming the
// missing package in a build without PETSc, `what` saying what needed it.
void start_petsc(const std::string& options, const std::string& what);

// Before MPI_Finalize, on every rank; nothing when PETSc never started.
void finish_petsc();

// Collectives PETSc itself made since it started, by its own log counters
// (the sum petsc_allreduce_ct + petsc_gather_ct + petsc_scatter_ct, as
// -log_view's "Reductions"): MPI_Allreduce, Bcast, Reduce, Scan, Alltoall,
// Allgather(v) on communicators of more than one rank (PETSc counts none on
// one rank), Gather(v), Scatter(v). 0 in a build without PETSc. The study
// adds it to our EnergyReduction's counts.
long petsc_collectives();

}  // namespace descent
