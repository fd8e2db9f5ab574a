#include "app/study_trace.hpp"

#include <cmath>
#include <ctime>
#include <limits>

#include "solver/petsc/petsc_session.hpp"

namespace descent {

namespace {
// A trial iterate may leave eps's domain (an inverted neo-Hookean element):
// its energy is then NaN in the records, never the partial finite sum.
double finite_or_nan(const EnergySums& sums) {
  return sums.finite[0] ? sums.energy[0].value : std::numeric_limits<double>::quiet_NaN();
}

double cpu_now() { return static_cast<double>(std::clock()) / CLOCKS_PER_SEC; }

// What a case starts from, as a running simulation would have it: an
// automatic Chebyshev case the warm-up's spectrum estimate (a property of
// the state, whichever method reached it, and of the preconditioner: a case
// with another one estimates anew) and, when the warm-up ran it too, its
// step length; a case of the warm-up's own method and preconditioner its
// step length; other cases start fresh.
StepMemory carried_memory(const SolverSpec& warmup, const StepMemory& memory,
                          const SolverSpec& spec) {
  const bool same_method =
      spec.method == warmup.method &&
      (spec.method != "chebyshev" || spec.chebyshev_parameters == warmup.chebyshev_parameters);
  const bool automatic = spec.method == "chebyshev" && spec.chebyshev_parameters == "auto";
  StepMemory carried;
  if (same_method || automatic) carried = memory;
  // The spectrum is the state's and the preconditioner's: another P^-1
  // estimates its own; the step length belongs to the method.
  const bool other_preconditioner = preconditioner_of(spec) != preconditioner_of(warmup);
  if (other_preconditioner) {
    carried.lambda_min = carried.lambda_max = 0;
    carried.widening = 1;
  }
  if (!same_method || other_preconditioner) carried.alpha = automatic ? 0 : spec.alpha_max;
  return carried;
}

// This rank's share (owned vertices) of sum m |(q - q_t)/h|^2 / 2, as an Energy
// so it rides in the measurement's reduction beside eps.
template <class Real>
Energy local_kinetic(const LocalProblem<Real>& problem, const Real* q, const Real* qt) {
  const auto& mass = problem.mass();
  const double inv_h = 1.0 / problem.dt();
  double sum = 0;
  for (index_t v = 0; v < problem.mesh().num_owned; ++v)
    for (int a = 0; a < 3; ++a) {
      const std::size_t k = 3 * static_cast<std::size_t>(v) + a;
      const double velocity = (static_cast<double>(q[k]) - qt[k]) * inv_h;
      sum += 0.5 * mass[v] * velocity * velocity;
    }
  return {sum, sum};
}

// eps(q) and the kinetic energy of this rank, evaluated by the double
// `twin` when given (a float iterate widened to double and measured in the
// twin's problem: its held dofs, q_t and y = q_t + h v are the twin's, in
// double), else by the stepper's own problem. The float run's own copies of
// those differ from the twin's by float's rounding; the held positions'
// half an ulp (6e-8 m at the helix's cap) moves eps linearly, by the cap's
// reaction times the shift, which read as e = 1e-5 of a step's decrease
// that no iteration can remove: a difference between the two problems, not
// an error the step left.
template <class Real>
class LocalMeasure {
 public:
  LocalMeasure(const LocalProblem<Real>& own, const Simulation<double>* twin)
      : own_(own), twin_(twin) {
    if (!twin_) return;
    const BodyState<double>& start = twin_->state();
    const double h = twin_->problem().dt();
    t_next_ = start.time + h;
    qt_ = start.q;
    y_.resize(qt_.size());
    for (std::size_t k = 0; k < y_.size(); ++k) y_[k] = start.q[k] + h * start.v[k];
  }

  void operator()(const Real* q, const Real* y, const Real* qt, Energy out[2]) {
    if (!twin_) {
      out[0] = own_.local_energy(q, y, qt);
      // The barrier between bodies is part of eps: measured at the pairs the
      // step found, the iteration's state left as it is.
      if (const BodyContact<Real>* pairs = own_.body_contact()) {
        const double e = pairs->measured_energy(q);
        out[0].value += e;
        out[0].magnitude += std::abs(e);
      }
      out[1] = local_kinetic(own_, q, qt);
      return;
    }
    const LocalProblem<double>& measuring = twin_->problem();
    q_.assign(q, q + qt_.size());
    measuring.hold_fixed(t_next_, q_.data());
    out[0] = measuring.local_energy(q_.data(), y_.data(), qt_.data());
    out[1] = local_kinetic(measuring, q_.data(), qt_.data());
  }

 private:
  const LocalProblem<Real>& own_;
  const Simulation<double>* twin_;
  double t_next_ = 0;
  std::vector<double> q_, y_, qt_;
};
}  // namespace

template <class Real>
StepTrace trace_step(MPI_Comm comm, Simulation<Real>& sim, const SolverSpec& spec,
                     const Simulation<double>* twin) {
  StepTrace trace;
  trace.spec = spec;
  EnergyReduction measure(comm);
  LocalProblem<Real>& problem = sim.problem();
  LocalMeasure<Real> local_measure(problem, twin);
  std::unique_ptr<Stepper<Real>> stepper = make_stepper(problem, spec);
  StepMemory carried = carried_memory(sim.solver_spec(), sim.stepper().memory(), spec);
  // An automatic Chebyshev case with a preconditioner the warm-up did not
  // run estimates its spectrum first, untimed, by a step from the same state
  // (the problem's conversion interpolants put back after it): a running
  // simulation holds an estimate from an earlier step, made once every
  // spectrum_interval steps.
  if (spec.method == "chebyshev" && spec.chebyshev_parameters == "auto" &&
      !(carried.lambda_max > 0)) {
    const std::vector<Real> interpolants = problem.interpolants();
    BodyState<Real> scratch = sim.state();
    stepper->set_memory(carried);
    stepper->step(scratch);
    problem.set_interpolants(interpolants);
    const StepMemory estimated = stepper->memory();
    carried.lambda_min = estimated.lambda_min;
    carried.lambda_max = estimated.lambda_max;
    carried.steps_since_estimate = 1;
    carried.reestimate = false;
  }
  stepper->set_memory(carried);
  BodyState<Real> state = sim.state();

  // Ours through EnergyReduction, and those PETSc makes itself (TAO's inner
  // products and norms, the AMG Newton's Krylov solves:
  // solver/petsc/petsc_session.hpp).
  auto collectives = [&sim] {
    const ReductionCounters& c = sim.reduction_counters();
    return c.allreduces + c.dot_allreduces + petsc_collectives();
  };
  MPI_Barrier(comm);
  const long collectives_start = collectives();
  const double reduce_start = sim.reduction_counters().seconds;
  double paused = 0, cpu_paused = 0;
  const double cpu_start = cpu_now();
  const double start = MPI_Wtime();
  stepper->set_observer([&](int k, const Real* q, const Real* y, const Real* qt) {
    const double now = MPI_Wtime(), cpu = cpu_now();
    IterationRecord r;
    r.cpu_seconds = cpu - cpu_start - cpu_paused;
    r.k = k;
    r.seconds = now - start - paused;
    r.collectives = collectives() - collectives_start;
    r.reduce_seconds = sim.reduction_counters().seconds - reduce_start;
    Energy local[2];
    local_measure(q, y, qt, local);
    const EnergySums sums = measure.sum(local, 2);
    r.energy = finite_or_nan(sums);
    r.kinetic = sums.energy[1].value;
    trace.records.push_back(r);
    paused += MPI_Wtime() - now;
    cpu_paused += cpu_now() - cpu;
  });
  const BodyState<Real> before = state;
  trace.stats = stepper->step(state);
  // The step's last record: its final state (after a last check's rollback)
  // with the time and collectives of the whole step, the last check included.
  const double end = MPI_Wtime();
  IterationRecord last;
  last.k = trace.stats.iterations;
  last.seconds = end - start - paused;
  last.cpu_seconds = cpu_now() - cpu_start - cpu_paused;
  last.collectives = collectives() - collectives_start;
  last.reduce_seconds = sim.reduction_counters().seconds - reduce_start;
  std::vector<Real> y(before.q.size());
  const Real h = problem.dt();
  for (std::size_t k = 0; k < y.size(); ++k) y[k] = before.q[k] + h * before.v[k];
  Energy local[2];
  local_measure(state.q.data(), y.data(), before.q.data(), local);
  const EnergySums sums = measure.sum(local, 2);
  last.energy = finite_or_nan(sums);
  last.kinetic = sums.energy[1].value;
  if (!trace.records.empty() && trace.records.back().k == last.k) trace.records.pop_back();
  trace.records.push_back(last);
  return trace;
}

std::vector<double> relative_errors(const StepTrace& trace, double energy_star) {
  std::vector<double> e;
  if (trace.records.empty()) return e;
  const double span = trace.records.front().energy - energy_star;
  for (const IterationRecord& r : trace.records) e.push_back((r.energy - energy_star) / span);
  return e;
}

template StepTrace trace_step(MPI_Comm, Simulation<double>&, const SolverSpec&,
                              const Simulation<double>*);
template StepTrace trace_step(MPI_Comm, Simulation<float>&, const SolverSpec&,
                              const Simulation<double>*);

}  // namespace descent
