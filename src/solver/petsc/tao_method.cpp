#include "solver/petsc/tao_method.hpp"

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <string>

#include "common/error.hpp"
#include "solver/check_history.hpp"
#include "solver/petsc/petsc_session.hpp"

#ifdef DESCENT_HAVE_PETSC
#include <petsctao.h>
#endif

namespace descent {

#ifdef DESCENT_HAVE_PETSC

template <class Real>
struct TaoMethod<Real>::Petsc {
  MPI_Comm comm = MPI_COMM_SELF;
  Vec x = nullptr;
  Tao tao = nullptr;
  // An exception thrown inside a TAO callback, rethrown after TaoSolve.
  std::exception_ptr error;
  TaoMethod<Real>* method = nullptr;
  // solver.accuracy: TAO's eps every check_interval iterations, read as the
  // other descent methods read their energy checks (no bound).
  CheckHistory history;
  double target = 0, initial = 0, estimate = 0;
  int interval = 1;
};

namespace {

void check(PetscErrorCode code, const char* call) {
  if (code != 0) throw Error(detail::concat("PETSc TAO: ", call, " failed (error ", code, ")"));
}

// TAO's callbacks: C entry points over TaoMethod<Real>::Petsc, which keep
// exceptions out of PETSc.
template <class Real>
struct Callbacks {
  static PetscErrorCode objective_and_gradient(Tao, Vec x, PetscReal* f, Vec g, void* context) {
    auto* petsc = static_cast<typename TaoMethod<Real>::Petsc*>(context);
    const PetscScalar* xs = nullptr;
    PetscScalar* gs = nullptr;
    if (VecGetArrayRead(x, &xs) || VecGetArray(g, &gs)) return PETSC_ERR_LIB;
    PetscErrorCode code = 0;
    try {
      *f = petsc->method->evaluate(xs, gs);
    } catch (...) {
      petsc->error = std::current_exception();
      code = PETSC_ERR_USER;
    }
    if (VecRestoreArray(g, &gs) || VecRestoreArrayRead(x, &xs)) return PETSC_ERR_LIB;
    return code;
  }

  static PetscErrorCode monitor(Tao tao, void* context) {
    auto* petsc = static_cast<typename TaoMethod<Real>::Petsc*>(context);
    PetscInt k = 0;
    PetscReal f = 0, gnorm = 0, cnorm = 0, xdiff = 0;
    TaoConvergedReason reason{};
    Vec x = nullptr;
    if (TaoGetSolutionStatus(tao, &k, &f, &gnorm, &cnorm, &xdiff, &reason) ||
        TaoGetSolution(tao, &x))
      return PETSC_ERR_LIB;
    const PetscScalar* xs = nullptr;
    if (VecGetArrayRead(x, &xs)) return PETSC_ERR_LIB;
    PetscErrorCode code = 0;
    try {
      petsc->method->monitor(static_cast<int>(k), gnorm, xs);
    } catch (...) {
      petsc->error = std::current_exception();
      code = PETSC_ERR_USER;
    }
    if (VecRestoreArrayRead(x, &xs)) return PETSC_ERR_LIB;
    return code;
  }

  // TAO's own tests, then the accuracy target: TAO's eps at its iterations
  // (known on every rank, no collective) into the energy checks' estimator.
  static PetscErrorCode converged(Tao tao, void* context) {
    auto* petsc = static_cast<typename TaoMethod<Real>::Petsc*>(context);
    if (TaoDefaultConvergenceTest(tao, nullptr)) return PETSC_ERR_LIB;
    PetscInt k = 0;
    PetscReal f = 0, gnorm = 0, cnorm = 0, xdiff = 0;
    TaoConvergedReason reason{};
    if (TaoGetSolutionStatus(tao, &k, &f, &gnorm, &cnorm, &xdiff, &reason)) return PETSC_ERR_LIB;
    if (reason != TAO_CONTINUE_ITERATING) return 0;
    if (k == 0) {
      petsc->initial = f;
      petsc->history.restart(f);
      return 0;
    }
    if (k % petsc->interval != 0) return 0;
    petsc->history.record(static_cast<int>(k), f);
    const AccuracyReading reading = petsc->history.read(petsc->initial, 0.0, petsc->target);
    petsc->estimate = reading.estimate;
    if (reading.confirmed && TaoSetConvergedReason(tao, TAO_CONVERGED_USER)) return PETSC_ERR_LIB;
    return 0;
  }
};

}  // namespace

template <class Real>
TaoMethod<Real>::TaoMethod(LocalProblem<Real>& problem, const SolverSpec& spec, const char* type)
    : MethodBase<Real>(problem, spec), type_(type) {
  start_petsc(spec.petsc_options, detail::concat("solver.method = \"", spec.method, "\""));
  g_.assign(this->size(), Real(0));
  d_.assign(this->size(), Real(1));
  const std::size_t owned = 3 * static_cast<std::size_t>(problem.mesh().num_owned);
  for (std::size_t dof = 0; dof < owned; ++dof)
    if (!this->held(dof)) free_.push_back(dof);
  petsc_ = std::make_unique<Petsc>();
  petsc_->method = this;
  petsc_->comm = problem.mesh().num_ranks > 1 ? PETSC_COMM_WORLD : MPI_COMM_SELF;
  check(
      VecCreateMPI(petsc_->comm, static_cast<PetscInt>(free_.size()), PETSC_DETERMINE, &petsc_->x),
      "VecCreateMPI");
}

template <class Real>
TaoMethod<Real>::~TaoMethod() {
  if (petsc_->tao) TaoDestroy(&petsc_->tao);
  if (petsc_->x) VecDestroy(&petsc_->x);
}

template <class Real>
void TaoMethod<Real>::unpack(const double* x) {
  Real* q = this->q_.data();
  for (std::size_t i = 0; i < free_.size(); ++i) q[free_[i]] = static_cast<Real>(x[i] / scale_[i]);
  if (this->problem_.mesh().num_ranks == 1) return;
  // Shared vertices owned elsewhere: zeros here, the owner's value after the
  // sum (held dofs too: the owner's prescribed value, the same number).
  const std::size_t owned = 3 * static_cast<std::size_t>(this->problem_.mesh().num_owned);
  std::fill(this->q_.begin() + static_cast<std::ptrdiff_t>(owned), this->q_.end(), Real(0));
  this->problem_.halo().sum(q, 3);
}

template <class Real>
double TaoMethod<Real>::evaluate(const double* x, double* g) {
  ++evaluations_;
  unpack(x);
  this->gradient(this->q_.data(), g_.data(), nullptr, false);
  const Energy local =
      this->problem_.local_energy(this->q_.data(), this->y_.data(), this->qt_.data());
  const EnergySums sums = this->problem_.global_energies(&local, 1);
  last_x_.assign(x, x + free_.size());
  last_norm2_ = 0;
  for (std::size_t i = 0; i < free_.size(); ++i) {
    const double gi = static_cast<double>(g_[free_[i]]);
    last_norm2_ += gi * gi;
    g[i] = gi / scale_[i];
  }
  // Outside eps's domain (an inverted element): a finite wall, the last
  // finite eps plus its magnitude, with zero slope. More-Thuente's
  // safeguarded interpolation then backtracks into the domain; an infinite
  // value would send its interpolated step to 0 and fail the search.
  if (!sums.finite[0] || !std::isfinite(sums.energy[0].value)) {
    ++nonfinite_;
    std::fill(g, g + free_.size(), 0.0);
    last_norm2_ = std::numeric_limits<double>::quiet_NaN();
    if (!std::isfinite(last_finite_)) return PETSC_INFINITY;
    return last_finite_ + std::max(1.0, std::abs(last_finite_));
  }
  last_finite_ = sums.energy[0].value;
  return sums.energy[0].value;
}

template <class Real>
void TaoMethod<Real>::monitor(int k, double gnorm, const double* x) {
  if (k > 0 && k <= reported_) return;
  if (k == 0 && !gradient_norms_.empty()) return;
  gradient_norms_.push_back(gnorm);
  // Our |g|^2 here when TAO's iterate is the point last evaluated (More-
  // Thuente ends on its accepted trial), else NaN.
  const bool evaluated_here =
      last_x_.size() == free_.size() && std::equal(last_x_.begin(), last_x_.end(), x);
  local_norms2_.push_back(evaluated_here ? last_norm2_ : std::numeric_limits<double>::quiet_NaN());
  // TAO's iteration 0 is the initial guess, which MethodBase reported.
  if (k == 0) return;
  // q_ holds the last evaluated point: a halo exchange only for another one.
  if (!evaluated_here) unpack(x);
  reported_ = k;
  this->report(k);
}

template <class Real>
void TaoMethod<Real>::iterate(StepStats& stats) {
  evaluations_ = 0;
  nonfinite_ = 0;
  last_finite_ = std::numeric_limits<double>::quiet_NaN();
  reported_ = 0;
  gradient_norms_.clear();
  local_norms2_.clear();
  last_x_.clear();
  Petsc& p = *petsc_;
  p.error = nullptr;
  if (p.tao) check(TaoDestroy(&p.tao), "TaoDestroy");
  // TAO's variables x = D0^1/2 q with D0 the Jacobi diagonal at the initial
  // guess: TAO's identity metric is then our Jacobi preconditioner.
  PetscBool jacobi = PETSC_TRUE;
  check(PetscOptionsGetBool(nullptr, nullptr, "-descent_tao_jacobi", &jacobi, nullptr),
        "PetscOptionsGetBool");
  scale_.assign(free_.size(), 1.0);
  if (jacobi) {
    this->gradient(this->q_.data(), g_.data(), d_.data(), true);
    for (std::size_t i = 0; i < free_.size(); ++i)
      scale_[i] = std::sqrt(static_cast<double>(d_[free_[i]]));
  }
  PetscScalar* xs = nullptr;
  check(VecGetArray(p.x, &xs), "VecGetArray");
  for (std::size_t i = 0; i < free_.size(); ++i)
    xs[i] = scale_[i] * static_cast<double>(this->q_[free_[i]]);
  check(VecRestoreArray(p.x, &xs), "VecRestoreArray");

  check(TaoCreate(p.comm, &p.tao), "TaoCreate");
  check(TaoSetType(p.tao, type_), "TaoSetType");
  check(TaoSetSolution(p.tao, p.x), "TaoSetSolution");
  check(TaoSetObjectiveAndGradient(p.tao, nullptr, Callbacks<Real>::objective_and_gradient, &p),
        "TaoSetObjectiveAndGradient");
  check(TaoSetMonitor(p.tao, Callbacks<Real>::monitor, &p, nullptr), "TaoSetMonitor");
  p.target = this->spec_.accuracy;
  p.interval = this->spec_.check_interval;
  p.estimate = std::numeric_limits<double>::quiet_NaN();
  p.history = CheckHistory();
  if (p.target > 0)
    check(TaoSetConvergenceTest(p.tao, Callbacks<Real>::converged, &p), "TaoSetConvergenceTest");
  check(TaoSetMaximumIterations(p.tao, this->spec_.iterations), "TaoSetMaximumIterations");
  check(TaoSetMaximumFunctionEvaluations(p.tao, 1000000000), "TaoSetMaximumFunctionEvaluations");
  check(TaoSetTolerances(p.tao, 0.0, 0.0, this->spec_.newton_tolerance), "TaoSetTolerances");
  check(TaoSetFunctionLowerBound(p.tao, PETSC_NINFINITY), "TaoSetFunctionLowerBound");
  TaoLineSearch search = nullptr;
  check(TaoGetLineSearch(p.tao, &search), "TaoGetLineSearch");
  check(TaoLineSearchSetType(search, TAOLINESEARCHMT), "TaoLineSearchSetType");
  check(TaoSetFromOptions(p.tao), "TaoSetFromOptions");

  const PetscErrorCode solved = TaoSolve(p.tao);
  if (p.error) std::rethrow_exception(p.error);
  check(solved, "TaoSolve");

  PetscInt iterations = 0;
  PetscReal f = 0, gnorm = 0, cnorm = 0, xdiff = 0;
  TaoConvergedReason reason{};
  check(TaoGetSolutionStatus(p.tao, &iterations, &f, &gnorm, &cnorm, &xdiff, &reason),
        "TaoGetSolutionStatus");
  reason_ = TaoConvergedReasons[reason];
  Vec solution = nullptr;
  check(TaoGetSolution(p.tao, &solution), "TaoGetSolution");
  const PetscScalar* final_x = nullptr;
  check(VecGetArrayRead(solution, &final_x), "VecGetArrayRead");
  unpack(final_x);
  check(VecRestoreArrayRead(solution, &final_x), "VecRestoreArrayRead");
  stats.iterations = static_cast<int>(iterations);
  stats.energy = f;
  stats.error_estimate = p.estimate;
  // TAO keeps its best point; it is finite unless even the initial guess was not.
  stats.finite = std::isfinite(f);
}

#else

template <class Real>
struct TaoMethod<Real>::Petsc {};

template <class Real>
TaoMethod<Real>::TaoMethod(LocalProblem<Real>& problem, const SolverSpec& spec, const char* type)
    : MethodBase<Real>(problem, spec), type_(type) {
  start_petsc(spec.petsc_options, detail::concat("solver.method = \"", spec.method, "\""));
}

template <class Real>
TaoMethod<Real>::~TaoMethod() = default;

template <class Real>
void TaoMethod<Real>::unpack(const double*) {}

template <class Real>
double TaoMethod<Real>::evaluate(const double*, double*) {
  return 0;
}

template <class Real>
void TaoMethod<Real>::monitor(int, double, const double*) {}

template <class Real>
void TaoMethod<Real>::iterate(StepStats&) {}

#endif

template class TaoMethod<double>;
template class TaoMethod<float>;

}  // namespace descent
