#pragma once
// P^-1 of the descent (DESIGN §1, "Preconditioners"): the fixed SPD operator
// every method that preconditions its gradient applies (chebyshev,
// jacobi_gd, nesterov, ncg, lbfgs, linear_cg). solver.preconditioner names
// it:
//   "jacobi"      D^-1, the diagonal of the Hessian (the paper's; the
//                 methods and the Chebyshev engine keep their own fused path)
//   "multilevel"  one symmetric V-cycle of smoothed aggregation
//                 (preconditioners/multilevel/)
//   "petsc_gamg"  one V-cycle of PETSc's PCGAMG (builds with PETSc, CPU)
//
// Vectors hold 3 reals per local vertex, xyz-interleaved in LocalMesh order,
// in the memory of the execution the preconditioner was made for. Applying
// P^-1 needs only neighbour exchanges and at most one small collective, so a
// method stays free of inner products if it was.
#include <cstddef>
#include <string>
#include <vector>

namespace descent {

// What a preconditioner did so far, for the stats and the benchmarks.
struct PreconditionerStats {
  long refreshes = 0;
  long applications = 0;
  double refresh_seconds = 0;  // rebuilding the operators at a state
  double apply_seconds = 0;
  // Collectives of its own (set-up excluded), per refresh and per
  // application together: MPI_Allreduce calls, and gathers (MPI_Allgather,
  // MPI_Allgatherv).
  long allreduces = 0;
  long gathers = 0;
  // Point-to-point messages its own halos sent (set-up excluded).
  long messages = 0;
  std::size_t memory_bytes = 0;  // what it holds beyond the method's vectors
  // Unknowns per level, finest first (one entry for a one-level method).
  std::vector<long long> level_dofs;
};

template <class Real>
class Preconditioner {
 public:
  virtual ~Preconditioner() = default;

  // Rebuilds what depends on the state at positions q (3 per local vertex):
  // at each step's start and after a rollback, at the state the method
  // continues from. P^-1 is then fixed until the next refresh. Collective.
  virtual void refresh(const Real* q) = 0;
  // With model conversion: where the method keeps each local tet's
  // interpolant l (memory of the same execution), for refresh to read; by
  // default the problem's (LocalProblem::interpolants).
  virtual void read_interpolants_from(const Real* /*interpolants*/) {}

  // z = P^-1 r. r is complete on every local vertex (shared ones bitwise
  // equal on all sharers) and 0 on held dofs; so is z. r and z are
  // distinct arrays.
  virtual void apply(const Real* r, Real* z) = 0;

  virtual PreconditionerStats stats() const = 0;
  // One line for the run's set-up report: the levels and their sizes.
  virtual std::string describe() const = 0;
};

}  // namespace descent
