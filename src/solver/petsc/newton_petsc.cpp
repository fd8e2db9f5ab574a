#include "solver/petsc/newton_petsc.hpp"

#include "common/error.hpp"
#include "solver/petsc/petsc_session.hpp"

#ifdef DESCENT_HAVE_PETSC
#include <petscksp.h>

#include "solver/petsc/assembled_hessian.hpp"
#endif

namespace descent {

#ifdef DESCENT_HAVE_PETSC

#define DESCENT_PETSC_CHECK(call) DESCENT_PETSC_CALL("newton_solver = \"petsc\"", call)

template <class Real>
struct NewtonPetsc<Real>::State {
  AssembledHessian<Real> hessian;
  Vec rhs = nullptr, solution = nullptr;
  KSP ksp = nullptr;

  State(const LocalProblem<Real>& problem, const HessianOperator<Real>& elements)
      : hessian(problem, elements, "newton_solver = \"petsc\"") {}
  ~State() {
    if (!PetscInitializeCalled || PetscFinalizeCalled) return;  // PETSc already gone
    KSPDestroy(&ksp);
    VecDestroy(&solution);
    VecDestroy(&rhs);
  }
};

template <class Real>
NewtonPetsc<Real>::NewtonPetsc(LocalProblem<Real>& problem, const HessianOperator<Real>& hessian,
                               const SolverSpec& spec)
    : problem_(problem) {
  start_petsc(spec.petsc_options, "solver.newton_solver = \"petsc\"");
  state_ = std::make_unique<State>(problem, hessian);
  State& s = *state_;
  const MPI_Comm comm = s.hessian.comm();
  const Mat matrix = s.hessian.matrix();
  DESCENT_PETSC_CHECK(MatCreateVecs(matrix, &s.solution, &s.rhs));

  // CG + GAMG to |r| <= cg_tolerance |b| in the unpreconditioned norm, as our
  // CG stops; then the options database (-ksp_type, -pc_type hypre, ...).
  DESCENT_PETSC_CHECK(KSPCreate(comm, &s.ksp));
  DESCENT_PETSC_CHECK(KSPSetOperators(s.ksp, matrix, matrix));
  DESCENT_PETSC_CHECK(KSPSetType(s.ksp, KSPCG));
  PC pc = nullptr;
  DESCENT_PETSC_CHECK(KSPGetPC(s.ksp, &pc));
  DESCENT_PETSC_CHECK(PCSetType(pc, PCGAMG));
  // Threshold 0 (PETSc's default is -1: keep every entry) drops the zero
  // couplings of held dofs from the aggregation graph: on the 41K helix,
  // one rank, 118 Krylov iterations per Newton step in place of 243.
  PetscReal threshold = 0.0;
  DESCENT_PETSC_CHECK(PCGAMGSetThreshold(pc, &threshold, 1));
  DESCENT_PETSC_CHECK(
      KSPSetTolerances(s.ksp, spec.cg_tolerance, PETSC_DEFAULT, PETSC_DEFAULT, spec.cg_iterations));
  DESCENT_PETSC_CHECK(KSPSetFromOptions(s.ksp));
  // CG's norm unless the options chose another method or norm (a method
  // without the unpreconditioned norm then keeps its own).
  KSPType type = nullptr;
  PetscBool norm_given = PETSC_FALSE, cg = PETSC_FALSE;
  DESCENT_PETSC_CHECK(KSPGetType(s.ksp, &type));
  DESCENT_PETSC_CHECK(PetscStrcmp(type, KSPCG, &cg));
  DESCENT_PETSC_CHECK(PetscOptionsHasName(nullptr, nullptr, "-ksp_norm_type", &norm_given));
  if (cg && !norm_given) DESCENT_PETSC_CHECK(KSPSetNormType(s.ksp, KSP_NORM_UNPRECONDITIONED));
}

template <class Real>
NewtonPetsc<Real>::~NewtonPetsc() = default;

template <class Real>
bool NewtonPetsc<Real>::solve(const Real* g, Real* dq, const Real* q) {
  State& s = *state_;
  const LocalMesh& mesh = problem_.mesh();
  const std::size_t no = mesh.num_owned;
  const auto& fixed = problem_.fixed_axes();
  auto held = [&](std::size_t dof) { return (fixed[dof / 3] >> (dof % 3)) & 1u; };
  const PetscLogDouble reductions_before = petsc_allreduce_ct;
  s.hessian.assemble();
  // GAMG's near null space: rigid-body modes about the current positions.
  s.hessian.set_rigid_body_modes(q);

  PetscScalar* x = nullptr;
  DESCENT_PETSC_CHECK(VecGetArray(s.rhs, &x));
  for (std::size_t k = 0; k < 3 * no; ++k) x[k] = held(k) ? 0.0 : -double(g[k]);
  DESCENT_PETSC_CHECK(VecRestoreArray(s.rhs, &x));
  DESCENT_PETSC_CHECK(KSPSolve(s.ksp, s.rhs, s.solution));
  PetscInt its = 0;
  KSPConvergedReason reason = KSP_CONVERGED_ITERATING;
  DESCENT_PETSC_CHECK(KSPGetIterationNumber(s.ksp, &its));
  DESCENT_PETSC_CHECK(KSPGetConvergedReason(s.ksp, &reason));
  iterations_ = int(its);
  reason_ = int(reason);

  // Held dofs stay exactly 0 (the preconditioner may smear round-off there).
  DESCENT_PETSC_CHECK(VecGetArray(s.solution, &x));
  for (std::size_t k = 0; k < 3 * no; ++k)
    if (held(k)) x[k] = 0.0;
  s.hessian.to_local(x, dq);
  DESCENT_PETSC_CHECK(VecRestoreArray(s.solution, &x));
  reductions_ = long(petsc_allreduce_ct - reductions_before);
  return reason > 0 || reason == KSP_DIVERGED_ITS;
}

template <class Real>
void NewtonPetsc<Real>::multiply(const Real* in, Real* out) {
  State& s = *state_;
  const std::size_t no = problem_.mesh().num_owned;
  s.hessian.assemble();
  PetscScalar* x = nullptr;
  DESCENT_PETSC_CHECK(VecGetArray(s.rhs, &x));
  for (std::size_t k = 0; k < 3 * no; ++k) x[k] = double(in[k]);
  DESCENT_PETSC_CHECK(VecRestoreArray(s.rhs, &x));
  DESCENT_PETSC_CHECK(MatMult(s.hessian.matrix(), s.rhs, s.solution));
  DESCENT_PETSC_CHECK(VecGetArray(s.solution, &x));
  s.hessian.to_local(x, out);
  DESCENT_PETSC_CHECK(VecRestoreArray(s.solution, &x));
}

#else  // no PETSc: the constructor refuses, naming the package

template <class Real>
struct NewtonPetsc<Real>::State {};

template <class Real>
NewtonPetsc<Real>::NewtonPetsc(LocalProblem<Real>& problem, const HessianOperator<Real>&,
                               const SolverSpec& spec)
    : problem_(problem) {
  start_petsc(spec.petsc_options, "solver.newton_solver = \"petsc\"");  // throws InputError
}

template <class Real>
NewtonPetsc<Real>::~NewtonPetsc() = default;

template <class Real>
bool NewtonPetsc<Real>::solve(const Real*, Real*, const Real*) {
  throw LogicError("NewtonPetsc::solve in a build without PETSc");
}

template <class Real>
void NewtonPetsc<Real>::multiply(const Real*, Real*) {
  throw LogicError("NewtonPetsc::multiply in a build without PETSc");
}

#endif

template class NewtonPetsc<double>;
template class NewtonPetsc<float>;

}  // namespace descent
