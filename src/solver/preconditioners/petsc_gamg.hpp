#pragma once
// solver.preconditioner = "petsc_gamg": P^-1 is one V-cycle of PETSc's
// smoothed-aggregation AMG (PCGAMG) on the PSD-projected Hessian of eps.
//
// refresh(q) stores the PSD-projected element Hessians at q
// (HessianOperator::assemble(q, true)), refills the distributed matrix of
// petsc/assembled_hessian.hpp with them plus the vertex curvature
// m (1/h^2 + c/h) (held dofs: identity rows and columns; the pattern is fixed
// at construction), attaches the rigid-body modes of q as the near null
// space, and sets up the AMG hierarchy (PCSetUp). apply(r) hands the owned
// dofs of r to PCApply (one V-cycle, no Krylov method around it), zeroes the
// held dofs of the result and returns the owner's values to the sharers of
// each shared vertex through one halo exchange, so all sharers hold bitwise
// equal values.
//
// PETSc's defaults except the threshold, 0 as in newton_petsc (PETSc's -1
// keeps the held dofs' zero couplings in the aggregation graph): Chebyshev
// smoothers with Jacobi on the levels, a direct solve on the coarsest, which
// make the V-cycle a fixed symmetric positive definite operator. The options
// database is read with the prefix "gamg_", so the PETSc options of Newton's
// solver (-pc_type hypre, ...) do not reach the preconditioner:
// -gamg_pc_gamg_threshold 0.01, -gamg_pc_mg_levels 3,
// -gamg_mg_levels_ksp_max_it 3, -gamg_pc_type hypre, ... from PETSC_OPTIONS,
// --petsc-options and solver.petsc_options (petsc/petsc_session.hpp).
// Options that change the smoothers must keep the V-cycle symmetric
// positive definite, which the tests check for the defaults only
// (-gamg_mg_levels_pc_type sor gave NaN on the small helix; -gamg_pc_type
// hypre stayed symmetric, a one-level PC to stats()).
//
// Collectives: all in refresh, PETSc's own (assembly, the AMG set-up, and
// what PETSc leaves to the first application, done there on a zero vector):
// 615 MPI_Allreduce per refresh on the small helix on 2 ranks, of which
// PETSc's log counts 508 (petsc_allreduce_ct, as newton_petsc reports it).
// stats().allreduces is that count: near, not exact. apply() makes none:
// the V-cycle's transfers are point-to-point, then one halo exchange.
//
// Builds without PETSc compile this file; the constructor then throws
// InputError naming the missing package.
#include <memory>
#include <string>

#include "solver/local_problem.hpp"
#include "solver/preconditioners/preconditioner.hpp"

namespace descent {

template <class Real>
class PetscGamgPreconditioner final : public Preconditioner<Real> {
 public:
  // Starts PETSc on first use and fixes the matrix's pattern. Collective.
  // Throws InputError in a build without PETSc.
  PetscGamgPreconditioner(LocalProblem<Real>& problem, const SolverSpec& spec);
  ~PetscGamgPreconditioner() override;
  PetscGamgPreconditioner(const PetscGamgPreconditioner&) = delete;
  PetscGamgPreconditioner& operator=(const PetscGamgPreconditioner&) = delete;

  void refresh(const Real* q) override;
  void apply(const Real* r, Real* z) override;
  PreconditionerStats stats() const override { return stats_; }
  std::string describe() const override;

 private:
  // The element Hessians and PETSc's objects: only petsc_gamg.cpp includes PETSc.
  struct State;
  LocalProblem<Real>& problem_;
  std::unique_ptr<State> state_;
  PreconditionerStats stats_;
  std::string pc_type_;  // PETSc's name of the preconditioner set up ("gamg")
};

// The petsc_gamg preconditioner of `problem`, or InputError
// (solver.preconditioner = "petsc_gamg" needs PETSc) in a build without it.
template <class Real>
std::unique_ptr<Preconditioner<Real>> make_petsc_gamg_preconditioner(LocalProblem<Real>& problem,
                                                                     const SolverSpec& spec);

}  // namespace descent
