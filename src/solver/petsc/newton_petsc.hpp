#pragma once
// Newton's distributed linear solver through PETSc (solver.newton_solver =
// "petsc"): the exact Newton system H dq = -g assembled into a parallel AIJ
// matrix, solved by PETSc's CG preconditioned with smoothed-aggregation AMG
// (PCGAMG) by default, any KSP/PC of PETSc's options database otherwise
// (-pc_type hypre, -ksp_type minres, ...; docs/petsc.md).
//
// The matrix: petsc/assembled_hessian.hpp (rows by ownership, block size 3,
// the element Hessians plus the vertex curvature, held dofs as identity rows
// and columns, the pattern fixed once and refilled per solve, the rigid-body
// modes of the positions as GAMG's near null space). Held dofs get right-hand
// side 0, so dq = 0 there, as in the masked CG and in newton_ldlt.
//
// Collectives: the constructor starts PETSc on first use (PetscInitialize,
// collective) and builds the matrix (PETSc collectives) plus one halo
// exchange (point-to-point); per solve, PETSc's assembly, preconditioner
// set-up and Krylov iterations, whose MPI_Allreduce calls PETSc makes itself
// and our EnergyReduction never sees: reductions() returns PETSc's own count
// of them (petsc_allreduce_ct, -log_view's "MPI Reductions"), which is near
// but not exact: on the small helix, 2 ranks, 5 solves, PETSc counted 994
// where the PMPI wrappers saw 1109 MPI_Allreduce calls (the exact number is
// measured at the MPI boundary by tests/mpi/test_newton_petsc and
// bench/newton_step.sh). One halo exchange returns dq to the shared
// vertices.
//
// Defaults set before the options database is read: KSPCG with the
// unpreconditioned residual norm (our CG's stopping rule, unless
// -ksp_norm_type is given), PCGAMG with threshold 0 (-pc_gamg_threshold).
#include <memory>

#include "solver/local_problem.hpp"
#include "solver/methods/hessian_operator.hpp"

namespace descent {

template <class Real>
class NewtonPetsc {
 public:
  // Collective over the problem's ranks. Throws InputError (naming the
  // missing package) in a build without PETSc.
  NewtonPetsc(LocalProblem<Real>& problem, const HessianOperator<Real>& hessian,
              const SolverSpec& spec);
  ~NewtonPetsc();
  NewtonPetsc(const NewtonPetsc&) = delete;
  NewtonPetsc& operator=(const NewtonPetsc&) = delete;

  // dq = -H^-1 g (to spec.cg_tolerance relative to |g|, unpreconditioned
  // residual) with H the element Hessians last stored by hessian.assemble
  // plus the vertex curvature; g, dq and q 3 reals per local vertex, q the
  // positions whose rigid-body modes form GAMG's near null space (rest
  // positions when null). Returns false when the Krylov method met
  // non-positive curvature (KSP_DIVERGED_INDEFINITE_MAT or _PC) or failed
  // otherwise (breakdown, NaN, preconditioner failure): Newton then falls
  // back to the projected Hessian. Reaching spec.cg_iterations is not a
  // failure (as in our CG). Collective.
  bool solve(const Real* g, Real* dq, const Real* q = nullptr);

  // Of the last solve: Krylov iterations, PETSc's converged reason (a
  // KSPConvergedReason), and the MPI reductions PETSc counted during it
  // (assembly, preconditioner set-up, Krylov iterations; 0 on one rank).
  int iterations() const { return iterations_; }
  int reason() const { return reason_; }
  long reductions() const { return reductions_; }

  // The assembled matrix applied to x (3 reals per local vertex, y complete
  // on every local vertex); for tests that compare it with HessianOperator.
  // Assembles from the stored element Hessians first. Collective.
  void multiply(const Real* x, Real* y);

 private:
  struct State;  // PETSc objects: only newton_petsc.cpp includes PETSc

  LocalProblem<Real>& problem_;
  std::unique_ptr<State> state_;
  int iterations_ = 0;
  int reason_ = 0;
  long reductions_ = 0;
};

}  // namespace descent
