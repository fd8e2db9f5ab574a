#include "solver/petsc/newton_petsc.hpp"

#include "common/error.hpp"
#include "solver/petsc/petsc_session.hpp"

#ifdef DESCENT_HAVE_PETSC
#include <petscksp.h>
#endif

#include <algorithm>
#include <string>

namespace descent {

#ifdef DESCENT_HAVE_PETSC

namespace {

void check(PetscErrorCode code, const char* call, const char* file, int line) {
  if (code != 0)
    throw Error(detail::concat(file, ":", line, ": newton_solver = \"petsc\": ", call,
                               " failed with PETSc error ", int(code)));
}

}  // namespace

#define DESCENT_PETSC_CHECK(call) check((call), #call, __FILE__, __LINE__)

template <class Real>
struct NewtonPetsc<Real>::State {
  MPI_Comm comm = MPI_COMM_NULL;
  std::unique_ptr<Halo<double>> halo;  // shared vertices' values from their owner
  Mat matrix = nullptr;
  Vec rhs = nullptr, solution = nullptr, coordinates = nullptr;
  KSP ksp = nullptr;
  std::vector<PetscScalar> diagonal;  // per owned dof: curvature, 1 on held dofs

  ~State() {
    if (!PetscInitializeCalled || PetscFinalizeCalled) return;  // PETSc already gone
    KSPDestroy(&ksp);
    VecDestroy(&coordinates);
    VecDestroy(&solution);
    VecDestroy(&rhs);
    MatDestroy(&matrix);
  }
};

template <class Real>
NewtonPetsc<Real>::NewtonPetsc(LocalProblem<Real>& problem, const HessianOperator<Real>& hessian,
                               const SolverSpec& spec)
    : problem_(problem), hessian_(hessian) {
  start_petsc(spec.petsc_options, "solver.newton_solver = \"petsc\"");
  const LocalMesh& mesh = problem.mesh();
  const index_t nt = mesh.num_tets(), no = mesh.num_owned, nv = mesh.num_vertices();
  state_ = std::make_unique<State>();
  State& s = *state_;

  // The mesh's communicator: PETSc's world when the mesh spans it, or this
  // rank alone (a one-rank run beside others, e.g. a one-rank reference).
  s.comm = mesh.num_ranks == 1 ? PETSC_COMM_SELF : PETSC_COMM_WORLD;
  int size = 1, rank = 0;
  MPI_Comm_size(s.comm, &size);
  MPI_Comm_rank(s.comm, &rank);
  if (size != mesh.num_ranks || rank != mesh.rank)
    throw Error(detail::concat("newton_solver = \"petsc\": the mesh spans ", mesh.num_ranks,
                               " ranks, PETSc's world ", size, ": run on MPI_COMM_WORLD"));
  s.halo = std::make_unique<Halo<double>>(s.comm, mesh);

  // Rows: this rank's block of 3 no, offsets by PETSc's layout (a scan).
  PetscLayout layout = nullptr;
  PetscInt first = 0, last = 0;
  DESCENT_PETSC_CHECK(PetscLayoutCreate(s.comm, &layout));
  DESCENT_PETSC_CHECK(PetscLayoutSetLocalSize(layout, 3 * PetscInt(no)));
  DESCENT_PETSC_CHECK(PetscLayoutSetBlockSize(layout, 3));
  DESCENT_PETSC_CHECK(PetscLayoutSetUp(layout));
  DESCENT_PETSC_CHECK(PetscLayoutGetRange(layout, &first, &last));
  DESCENT_PETSC_CHECK(PetscLayoutDestroy(&layout));

  // Block (vertex) numbers of all local vertices: the owner's, exactly.
  exchange_.assign(3 * std::size_t(nv), 0.0);
  for (index_t v = 0; v < no; ++v) exchange_[v] = double(first / 3 + v);
  s.halo->sum(exchange_.data(), 1);
  block_.resize(nv);
  for (index_t v = 0; v < nv; ++v) block_[v] = int(exchange_[v]);

  // The pattern: each tet's 4x4 vertex blocks and every owned diagonal block.
  Mat pattern = nullptr;
  DESCENT_PETSC_CHECK(MatCreate(s.comm, &pattern));
  DESCENT_PETSC_CHECK(MatSetType(pattern, MATPREALLOCATOR));
  DESCENT_PETSC_CHECK(MatSetSizes(pattern, 3 * no, 3 * no, PETSC_DETERMINE, PETSC_DETERMINE));
  DESCENT_PETSC_CHECK(MatSetBlockSize(pattern, 3));
  DESCENT_PETSC_CHECK(MatSetUp(pattern));
  const std::vector<PetscScalar> zeros(144, 0.0);
  for (index_t t = 0; t < nt; ++t) {
    PetscInt blocks[4];
    for (int a = 0; a < 4; ++a) blocks[a] = block_[mesh.tets[4 * t + a]];
    DESCENT_PETSC_CHECK(
        MatSetValuesBlocked(pattern, 4, blocks, 4, blocks, zeros.data(), ADD_VALUES));
  }
  for (index_t v = 0; v < no; ++v) {
    const PetscInt b = block_[v];
    DESCENT_PETSC_CHECK(MatSetValuesBlocked(pattern, 1, &b, 1, &b, zeros.data(), ADD_VALUES));
  }
  DESCENT_PETSC_CHECK(MatAssemblyBegin(pattern, MAT_FINAL_ASSEMBLY));
  DESCENT_PETSC_CHECK(MatAssemblyEnd(pattern, MAT_FINAL_ASSEMBLY));

  DESCENT_PETSC_CHECK(MatCreate(s.comm, &s.matrix));
  DESCENT_PETSC_CHECK(MatSetSizes(s.matrix, 3 * no, 3 * no, PETSC_DETERMINE, PETSC_DETERMINE));
  DESCENT_PETSC_CHECK(MatSetBlockSize(s.matrix, 3));
  DESCENT_PETSC_CHECK(MatSetType(s.matrix, MATAIJ));
  DESCENT_PETSC_CHECK(MatPreallocatorPreallocate(pattern, PETSC_TRUE, s.matrix));
  DESCENT_PETSC_CHECK(MatDestroy(&pattern));
  // The pattern is final; later assemblies send the same off-rank entries.
  DESCENT_PETSC_CHECK(MatSetOption(s.matrix, MAT_NEW_NONZERO_ALLOCATION_ERR, PETSC_TRUE));
  DESCENT_PETSC_CHECK(MatSetOption(s.matrix, MAT_SUBSET_OFF_PROC_ENTRIES, PETSC_TRUE));
  DESCENT_PETSC_CHECK(MatSetOption(s.matrix, MAT_SYMMETRIC, PETSC_TRUE));
  DESCENT_PETSC_CHECK(MatSetOption(s.matrix, MAT_SYMMETRY_ETERNAL, PETSC_TRUE));
  DESCENT_PETSC_CHECK(MatCreateVecs(s.matrix, &s.solution, &s.rhs));
  DESCENT_PETSC_CHECK(VecDuplicate(s.rhs, &s.coordinates));

  // The vertex curvature is fixed for the run (HessianOperator computes it once).
  const auto& fixed = problem.fixed_axes();
  s.diagonal.resize(3 * std::size_t(no));
  for (std::size_t k = 0; k < s.diagonal.size(); ++k)
    s.diagonal[k] = (fixed[k / 3] >> (k % 3)) & 1u ? 1.0 : double(hessian.vertex_curvature()[k]);

  // CG + GAMG to |r| <= cg_tolerance |b| in the unpreconditioned norm, as our
  // CG stops; then the options database (-ksp_type, -pc_type hypre, ...).
  DESCENT_PETSC_CHECK(KSPCreate(s.comm, &s.ksp));
  DESCENT_PETSC_CHECK(KSPSetOperators(s.ksp, s.matrix, s.matrix));
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
void NewtonPetsc<Real>::assemble() {
  State& s = *state_;
  const LocalMesh& mesh = problem_.mesh();
  const index_t nt = mesh.num_tets(), no = mesh.num_owned;
  const auto& fixed = problem_.fixed_axes();
  const Real* h = hessian_.element_hessians().data();
  DESCENT_PETSC_CHECK(MatZeroEntries(s.matrix));
  // MatSetValues is not thread safe: one pass on one thread, each tet's
  // block in double with its held rows and columns zeroed on the way.
  PetscScalar block[144];
  for (index_t t = 0; t < nt; ++t) {
    bool held[12];
    for (int c = 0; c < 12; ++c) held[c] = (fixed[mesh.tets[4 * t + c / 3]] >> (c % 3)) & 1u;
    const Real* in = h + 144 * std::size_t(t);
    for (int r = 0; r < 12; ++r)
      for (int c = 0; c < 12; ++c)
        block[12 * r + c] = held[r] || held[c] ? 0.0 : double(in[12 * r + c]);
    PetscInt blocks[4];
    for (int a = 0; a < 4; ++a) blocks[a] = block_[mesh.tets[4 * t + a]];
    DESCENT_PETSC_CHECK(MatSetValuesBlocked(s.matrix, 4, blocks, 4, blocks, block, ADD_VALUES));
  }
  for (index_t v = 0; v < no; ++v)
    for (int i = 0; i < 3; ++i) {
      const PetscInt row = 3 * PetscInt(block_[v]) + i;
      DESCENT_PETSC_CHECK(
          MatSetValues(s.matrix, 1, &row, 1, &row, &s.diagonal[3 * v + i], ADD_VALUES));
    }
  DESCENT_PETSC_CHECK(MatAssemblyBegin(s.matrix, MAT_FINAL_ASSEMBLY));
  DESCENT_PETSC_CHECK(MatAssemblyEnd(s.matrix, MAT_FINAL_ASSEMBLY));
}

template <class Real>
void NewtonPetsc<Real>::to_local(const double* owned, Real* local) {
  const LocalMesh& mesh = problem_.mesh();
  const std::size_t no = mesh.num_owned, nv = mesh.num_vertices();
  std::fill(exchange_.begin(), exchange_.end(), 0.0);
  std::copy(owned, owned + 3 * no, exchange_.begin());
  state_->halo->sum(exchange_.data(), 3);
  for (std::size_t k = 0; k < 3 * nv; ++k) local[k] = static_cast<Real>(exchange_[k]);
}

template <class Real>
bool NewtonPetsc<Real>::solve(const Real* g, Real* dq, const Real* q) {
  State& s = *state_;
  const LocalMesh& mesh = problem_.mesh();
  const std::size_t no = mesh.num_owned;
  const auto& fixed = problem_.fixed_axes();
  auto held = [&](std::size_t dof) { return (fixed[dof / 3] >> (dof % 3)) & 1u; };
  const PetscLogDouble reductions_before = petsc_allreduce_ct;
  assemble();

  // GAMG's near null space: rigid-body modes about the current positions.
  PetscScalar* x = nullptr;
  DESCENT_PETSC_CHECK(VecGetArray(s.coordinates, &x));
  for (std::size_t k = 0; k < 3 * no; ++k) x[k] = q ? double(q[k]) : mesh.rest_positions[k];
  DESCENT_PETSC_CHECK(VecRestoreArray(s.coordinates, &x));
  MatNullSpace rigid = nullptr;
  DESCENT_PETSC_CHECK(MatNullSpaceCreateRigidBody(s.coordinates, &rigid));
  DESCENT_PETSC_CHECK(MatSetNearNullSpace(s.matrix, rigid));
  DESCENT_PETSC_CHECK(MatNullSpaceDestroy(&rigid));

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
  to_local(x, dq);
  DESCENT_PETSC_CHECK(VecRestoreArray(s.solution, &x));
  reductions_ = long(petsc_allreduce_ct - reductions_before);
  return reason > 0 || reason == KSP_DIVERGED_ITS;
}

template <class Real>
void NewtonPetsc<Real>::multiply(const Real* in, Real* out) {
  State& s = *state_;
  const std::size_t no = problem_.mesh().num_owned;
  assemble();
  PetscScalar* x = nullptr;
  DESCENT_PETSC_CHECK(VecGetArray(s.rhs, &x));
  for (std::size_t k = 0; k < 3 * no; ++k) x[k] = double(in[k]);
  DESCENT_PETSC_CHECK(VecRestoreArray(s.rhs, &x));
  DESCENT_PETSC_CHECK(MatMult(s.matrix, s.rhs, s.solution));
  DESCENT_PETSC_CHECK(VecGetArray(s.solution, &x));
  to_local(x, out);
  DESCENT_PETSC_CHECK(VecRestoreArray(s.solution, &x));
}

#else  // no PETSc: the constructor refuses, naming the package

template <class Real>
struct NewtonPetsc<Real>::State {};

template <class Real>
NewtonPetsc<Real>::NewtonPetsc(LocalProblem<Real>& problem, const HessianOperator<Real>& hessian,
                               const SolverSpec& spec)
    : problem_(problem), hessian_(hessian) {
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
