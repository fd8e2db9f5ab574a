#pragma once
// Newton's distributed linear solver through PETSc (solver.newton_solver =
// "petsc"): the exact Newton system H dq = -g assembled into a parallel AIJ
// matrix, solved by PETSc's CG preconditioned with smoothed-aggregation AMG
// (PCGAMG) by default, any KSP/PC of PETSc's options database otherwise
// (-pc_type hypre, -ksp_type minres, ...; docs/petsc.md).
//
// Layout. PETSc's rows follow our ownership: rank r owns the 3 dofs of each
// of its owned vertices (LocalMesh: local ids [0, num_owned)), numbered
// contiguously from offset_r = sum over ranks s < r of 3 num_owned_s, dof
// 3 v + i of owned local vertex v at PETSc row offset_r + 3 v + i. Shared
// vertices owned elsewhere learn their owner's numbers once, through a
// Halo<double> sum in which only the owner contributes (so the sum is the
// owner's value exactly). Block size 3 (one block per vertex).
//
// Values. Every tet lies on one rank, which adds its 12x12 element Hessian
// (HessianOperator::element_hessians, corner order = the tet's 4 vertices x
// xyz) with global indices; rows owned by another rank travel through PETSc's
// stash at assembly. Each owner adds its owned dofs' vertex curvature
// m (1/h^2 + c/h) once. Held dofs get an identity row and column (entries
// coupling them stay in the pattern as explicit zeros) and right-hand side 0,
// so dq = 0 there, as in the masked CG and in newton_ldlt. The pattern is
// fixed in the constructor (MATPREALLOCATOR: exact preallocation including
// off-rank contributions) and every solve refills the same matrix
// (MatZeroEntries, add, assemble).
//
// Near null space: the six rigid-body modes of the positions passed to solve
// (MatNullSpaceCreateRigidBody), which GAMG needs for elasticity.
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
// Communicator: MPI_COMM_WORLD (PETSc's world) when the mesh spans several
// ranks, MPI_COMM_SELF for a one-rank mesh.
//
// Defaults set before the options database is read: KSPCG with the
// unpreconditioned residual norm (our CG's stopping rule, unless
// -ksp_norm_type is given), PCGAMG with threshold 0 (-pc_gamg_threshold).
#include <memory>
#include <vector>

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
  void assemble();
  // Owned values of `owned` (3 per owned vertex, double) to every local
  // vertex: shared ones from their owner through the halo.
  void to_local(const double* owned, Real* local);

  LocalProblem<Real>& problem_;
  const HessianOperator<Real>& hessian_;
  std::unique_ptr<State> state_;
  std::vector<int> block_;  // per local vertex: PETSc block (vertex) index
  std::vector<double> exchange_;
  int iterations_ = 0;
  int reason_ = 0;
  long reductions_ = 0;
};

}  // namespace descent
