#include "solver/preconditioners/petsc_gamg.hpp"

#include "common/error.hpp"
#include "solver/petsc/petsc_session.hpp"

#ifdef DESCENT_HAVE_PETSC
#include <petscksp.h>

#include <chrono>
#include <sstream>

#include "solver/methods/hessian_operator.hpp"
#include "solver/petsc/assembled_hessian.hpp"
#endif

namespace descent {

namespace {
// The scene key, for errors.
constexpr const char* kWhat = "solver.preconditioner = \"petsc_gamg\"";
}  // namespace

#ifdef DESCENT_HAVE_PETSC

#define DESCENT_PETSC_CHECK(call) DESCENT_PETSC_CALL(kWhat, call)

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// What this rank holds of matrix `a` (MatGetInfo, MAT_LOCAL), estimated from
// its allocated entries: a value and a column index each, plus a row offset
// per row (PETSc 3.18's MatInfo::memory no longer tracks allocations).
std::size_t matrix_bytes(Mat a) {
  MatInfo info;
  PetscInt rows = 0;
  DESCENT_PETSC_CHECK(MatGetInfo(a, MAT_LOCAL, &info));
  DESCENT_PETSC_CHECK(MatGetLocalSize(a, &rows, nullptr));
  return std::size_t(info.nz_allocated) * (sizeof(PetscScalar) + sizeof(PetscInt)) +
         std::size_t(rows + 1) * sizeof(PetscInt);
}

}  // namespace

template <class Real>
struct PetscGamgPreconditioner<Real>::State {
  HessianOperator<Real> elements;  // the PSD-projected element Hessians of the last refresh
  AssembledHessian<Real> hessian;
  PC pc = nullptr;
  Vec r = nullptr, z = nullptr;  // owned dofs, PETSc's row order

  explicit State(LocalProblem<Real>& problem)
      : elements(problem), hessian(problem, elements, kWhat) {}
  ~State() {
    if (!PetscInitializeCalled || PetscFinalizeCalled) return;  // PETSc already gone
    PCDestroy(&pc);
    VecDestroy(&z);
    VecDestroy(&r);
  }
};

template <class Real>
PetscGamgPreconditioner<Real>::PetscGamgPreconditioner(LocalProblem<Real>& problem,
                                                       const SolverSpec& spec)
    : problem_(problem) {
  start_petsc(spec.petsc_options, kWhat);
  state_ = std::make_unique<State>(problem);
  State& s = *state_;
  DESCENT_PETSC_CHECK(MatCreateVecs(s.hessian.matrix(), &s.z, &s.r));
}

template <class Real>
PetscGamgPreconditioner<Real>::~PetscGamgPreconditioner() = default;

template <class Real>
void PetscGamgPreconditioner<Real>::refresh(const Real* q) {
  State& s = *state_;
  const Clock::time_point start = Clock::now();
  const PetscLogDouble reductions_before = petsc_allreduce_ct;
  s.elements.assemble(q, true);
  s.hessian.assemble();
  s.hessian.set_rigid_body_modes(q);
  // A new PC at every refresh: PETSc 3.18's GAMG, set up again on a PC it
  // set up before, keeps state of the earlier set-up. After a refresh at
  // rest, P^-1 x at the stretched small helix differed from a fresh set-up's
  // by 5-7% of its largest entry on 1-3 ranks (17% on 2 with PCReset first).
  // A new PC equals a fresh set-up bit for bit (tests/mpi/test_petsc_gamg),
  // and the refresh takes as long (0.05-0.07 s there on 2 ranks).
  const Mat matrix = s.hessian.matrix();
  DESCENT_PETSC_CHECK(PCDestroy(&s.pc));
  DESCENT_PETSC_CHECK(PCCreate(s.hessian.comm(), &s.pc));
  DESCENT_PETSC_CHECK(PCSetOptionsPrefix(s.pc, "gamg_"));
  DESCENT_PETSC_CHECK(PCSetOperators(s.pc, matrix, matrix));
  DESCENT_PETSC_CHECK(PCSetType(s.pc, PCGAMG));
  // Threshold 0 drops the held dofs' zero couplings from the aggregation
  // graph (newton_petsc.cpp says what that gains).
  PetscReal threshold = 0.0;
  DESCENT_PETSC_CHECK(PCGAMGSetThreshold(s.pc, &threshold, 1));
  DESCENT_PETSC_CHECK(PCSetFromOptions(s.pc));
  DESCENT_PETSC_CHECK(PCSetUp(s.pc));
  // PETSc leaves part of the set-up to the first application (the coarse
  // level's LU factorization among others; a dozen MPI_Allreduce on 2
  // ranks): one V-cycle on 0 here, so that apply() makes no collective.
  DESCENT_PETSC_CHECK(VecSet(s.r, 0.0));
  DESCENT_PETSC_CHECK(PCApply(s.pc, s.r, s.z));
  PCType type = nullptr;
  DESCENT_PETSC_CHECK(PCGetType(s.pc, &type));
  pc_type_ = type;

  // Level sizes (finest first) and what this rank holds: the element
  // Hessians, the fine matrix, and for a multigrid PC (GAMG, unless the
  // options chose another) every coarse operator and interpolation.
  PetscInt fine_rows = 0;
  DESCENT_PETSC_CHECK(MatGetSize(matrix, &fine_rows, nullptr));
  std::size_t bytes = s.elements.element_hessians().size() * sizeof(Real) + matrix_bytes(matrix);
  stats_.level_dofs.assign(1, fine_rows);
  PetscBool multigrid = PETSC_FALSE;
  DESCENT_PETSC_CHECK(PetscObjectTypeCompareAny(PetscObject(s.pc), &multigrid, PCMG, PCGAMG, ""));
  if (multigrid) {
    PetscInt levels = 0;
    DESCENT_PETSC_CHECK(PCMGGetLevels(s.pc, &levels));
    // PCMG numbers its levels coarsest (0) to finest (levels - 1).
    for (PetscInt l = levels - 2; l >= 0; --l) {
      KSP smoother = nullptr;
      Mat a = nullptr, interpolation = nullptr;
      PetscInt rows = 0;
      DESCENT_PETSC_CHECK(PCMGGetSmoother(s.pc, l, &smoother));
      DESCENT_PETSC_CHECK(KSPGetOperators(smoother, &a, nullptr));
      DESCENT_PETSC_CHECK(MatGetSize(a, &rows, nullptr));
      DESCENT_PETSC_CHECK(PCMGGetInterpolation(s.pc, l + 1, &interpolation));
      stats_.level_dofs.push_back(rows);
      bytes += matrix_bytes(a) + matrix_bytes(interpolation);
    }
  }
  stats_.memory_bytes = bytes;
  stats_.allreduces += long(petsc_allreduce_ct - reductions_before);
  stats_.refreshes += 1;
  stats_.refresh_seconds += seconds_since(start);
}

template <class Real>
void PetscGamgPreconditioner<Real>::apply(const Real* r, Real* z) {
  DESCENT_VERIFY(stats_.refreshes > 0, "petsc_gamg: apply() before the first refresh()");
  State& s = *state_;
  const Clock::time_point start = Clock::now();
  const PetscLogDouble reductions_before = petsc_allreduce_ct;
  const std::size_t no = problem_.mesh().num_owned;
  const auto& fixed = problem_.fixed_axes();
  PetscScalar* x = nullptr;
  DESCENT_PETSC_CHECK(VecGetArray(s.r, &x));
  for (std::size_t k = 0; k < 3 * no; ++k) x[k] = double(r[k]);
  DESCENT_PETSC_CHECK(VecRestoreArray(s.r, &x));
  DESCENT_PETSC_CHECK(PCApply(s.pc, s.r, s.z));
  // Held dofs exactly 0 whatever the options chose (the default GAMG leaves
  // 0 there already: threshold 0 cuts their zero couplings from the graph).
  DESCENT_PETSC_CHECK(VecGetArray(s.z, &x));
  for (std::size_t k = 0; k < 3 * no; ++k)
    if ((fixed[k / 3] >> (k % 3)) & 1u) x[k] = 0.0;
  s.hessian.to_local(x, z);
  DESCENT_PETSC_CHECK(VecRestoreArray(s.z, &x));
  stats_.allreduces += long(petsc_allreduce_ct - reductions_before);
  stats_.applications += 1;
  stats_.apply_seconds += seconds_since(start);
}

template <class Real>
std::string PetscGamgPreconditioner<Real>::describe() const {
  if (stats_.refreshes == 0) return "petsc_gamg: not set up yet";
  const std::size_t levels = stats_.level_dofs.size();
  std::ostringstream line;
  line << "petsc_gamg: PETSc PC " << pc_type_ << ", " << levels
       << (levels == 1 ? " level" : " levels") << " (dofs";
  for (long long n : stats_.level_dofs) line << ' ' << n;
  line << ')';
  return line.str();
}

#else  // no PETSc: the constructor refuses, naming the package

template <class Real>
struct PetscGamgPreconditioner<Real>::State {};

template <class Real>
PetscGamgPreconditioner<Real>::PetscGamgPreconditioner(LocalProblem<Real>& problem,
                                                       const SolverSpec& spec)
    : problem_(problem) {
  start_petsc(spec.petsc_options, kWhat);  // throws InputError
}

template <class Real>
PetscGamgPreconditioner<Real>::~PetscGamgPreconditioner() = default;

template <class Real>
void PetscGamgPreconditioner<Real>::refresh(const Real*) {
  throw LogicError("PetscGamgPreconditioner::refresh in a build without PETSc");
}

template <class Real>
void PetscGamgPreconditioner<Real>::apply(const Real*, Real*) {
  throw LogicError("PetscGamgPreconditioner::apply in a build without PETSc");
}

template <class Real>
std::string PetscGamgPreconditioner<Real>::describe() const {
  throw LogicError("PetscGamgPreconditioner::describe in a build without PETSc");
}

#endif

template <class Real>
std::unique_ptr<Preconditioner<Real>> make_petsc_gamg_preconditioner(LocalProblem<Real>& problem,
                                                                     const SolverSpec& spec) {
  return std::make_unique<PetscGamgPreconditioner<Real>>(problem, spec);
}

template class PetscGamgPreconditioner<double>;
template class PetscGamgPreconditioner<float>;
template std::unique_ptr<Preconditioner<double>> make_petsc_gamg_preconditioner(
    LocalProblem<double>&, const SolverSpec&);
template std::unique_ptr<Preconditioner<float>> make_petsc_gamg_preconditioner(LocalProblem<float>&,
                                                                               const SolverSpec&);

}  // namespace descent
