#pragma once
// `newton`, the ground truth (DESIGN §1, accuracy metric): at each Newton
// iteration the element Hessians (HessianOperator::assemble; exact, or
// PSD-projected per solver.newton_projection), the system H dq = -g solved
// by preconditioned CG, distributed and without a global matrix, to
// |r| <= cg_tolerance |g|, then a backtracking (Armijo, c = 1e-4, t halved)
// line search on the energy; stop at |g| <= newton_tolerance |g(q0)| or
// after newton_iterations, or with solver.accuracy = TOL after the
// iteration whose decrement says e <= TOL at its start (newton.cpp states
// the relation; newton_iterations stays the cap). One Newton iteration is
// one observed iteration.
// The CG's P^-1: Jacobi's diagonal of H, or with solver.preconditioner =
// "multilevel" one V-cycle of the hierarchy whose finest operator is H's
// projected form at this iterate (MethodBase builds it at the step's guess,
// Newton again at each later iterate; the obstacles' contact blocks join
// it, and the diagonal of the pairs' between bodies, whose couplings stay in
// the CG's products). Per CG
// iteration it adds the V-cycle's one MPI_Allgatherv, per Newton iteration
// its refresh's collectives (docs/multilevel.md).
// With contact barriers (contact.method = "energy": obstacles, pairs
// between bodies) the barriers and lagged friction are part of eps: their
// Hessians join H (HessianOperator::assemble_contact; projected with the
// elements), and the line search starts from the longest step that keeps
// every surface vertex outside every obstacle and every pair above its
// kept gap along the whole path (longest_safe_step, one allreduce more per
// Newton iteration), so no trial crosses and every trial's energy is
// finite. With pairs, one allreduce more per iteration says whether to find
// them again, the trials' energies take the pairs', and each CG product
// their Hessian (neighbour messages only).
// Collectives per Newton iteration: 1 (|g|^2), per linear solve 1 + 2 per CG
// iteration ([r.z, r.r] fused, p.Ap) and 1 (g.dq) (a second solve when the
// exact one falls back), and one energy reduction per line-search trial (the
// first carries eps(q) too).
// With solver.newton_solver = "ldlt" the system is instead assembled and
// factored on rank 0 (newton_ldlt.hpp): per linear solve 1 MPI_Gatherv + 1
// MPI_Scatterv in place of CG's allreduces, then the same 1 (g.dq).
// With solver.newton_solver = "petsc" the system is assembled into a
// distributed PETSc matrix and solved by PETSc's CG + GAMG (or any KSP/PC of
// the options; solver/petsc/newton_petsc.hpp, docs/petsc.md): per linear
// solve PETSc's own reductions (assembly, AMG set-up, 1-2 per Krylov
// iteration; not in our counters: petsc_reductions() has them), then the
// same 1 (g.dq).
#include <memory>
#include <vector>

#include "solver/methods/hessian_operator.hpp"
#include "solver/methods/method_base.hpp"
#include "solver/methods/newton_ldlt.hpp"
#include "solver/petsc/newton_petsc.hpp"

namespace descent {

template <class Real>
class Newton final : public MethodBase<Real> {
 public:
  Newton(LocalProblem<Real>& problem, const SolverSpec& spec);

  // |grad eps| (owned free dofs, all ranks) at every Newton iterate of the
  // last step, the initial guess first; and the CG iterations per solve
  // (0 for an "ldlt" solve: no CG iteration, no CG collective; PETSc's
  // Krylov iterations for a "petsc" solve).
  const std::vector<double>& gradient_norms() const { return gradient_norms_; }
  const std::vector<int>& cg_iterations() const { return cg_iterations_; }
  // Per "petsc" solve of the last step: the MPI reductions PETSc made itself
  // (petsc_allreduce_ct; empty for the other solvers).
  const std::vector<long>& petsc_reductions() const { return petsc_reductions_; }
  // Newton iterations whose exact system was replaced by the projected one.
  int projected_solves() const { return projected_solves_; }

 private:
  void iterate(StepStats& stats) override;
  // PCG for H dq_ = -g_; returns iterations; positive: no p.Hp <= 0 met.
  int solve(double rhs_norm2, bool& positive);
  // With contact barriers (contact.method = "energy"): the largest t <= 1
  // for which the move t dq_ from q_ closes no surface vertex's gap to an
  // obstacle by more than the guard of the other methods lets one iteration
  // close (kernels/obstacle_contact.hpp, move_fraction: a gap is convex, so
  // the whole path stays outside), and keeps every pair between bodies
  // above its kept gap along the path and within the pairs' drift cap
  // (BodyContact::path_fraction), over all ranks (one allreduce); 1
  // without.
  double longest_safe_step();
  // The pairs between bodies when eps holds their barrier, else null.
  BodyContact<Real>* pairs();
  // This rank's share of eps(q): LocalProblem::local_energy's terms and the
  // pairs' (each counted once; collective with the contact neighbours).
  Energy local_energy(const Real* q);
  HessianOperator<Real> hessian_;
  std::unique_ptr<NewtonLdlt<Real>> ldlt_;    // newton_solver = "ldlt" only
  std::unique_ptr<NewtonPetsc<Real>> petsc_;  // newton_solver = "petsc" only
  std::vector<Real> g_, dq_, r_, z_, p_, ap_, trial_;
  std::vector<double> gradient_norms_;
  std::vector<int> cg_iterations_;
  std::vector<long> petsc_reductions_;
  int projected_solves_ = 0;
};

}  // namespace descent
