#pragma once
// What every time-stepping method (solver.method) and every backend offers
// the run driver: advance the body by one implicit step of the incremental
// potential in LocalProblem, and report how the step went. Methods differ
// only in how they descend on eps; the problem, halo and reduction are shared.
#include <functional>
#include <memory>
#include <utility>
#include <vector>

#include "io/scene.hpp"
#include "partition/local_mesh.hpp"
#include "solver/preconditioners/preconditioner.hpp"

namespace descent {

template <class Real>
class LocalProblem;

// Positions and velocities of one rank's local vertices (xyz-interleaved).
template <class Real>
struct BodyState {
  std::vector<Real> q, v, v_prev;
  double time = 0;
};

template <class Real>
BodyState<Real> rest_state(const LocalMesh& mesh);

// Where a rank-local scan found the first non-finite value of a state
// (LocalProblem::find_non_finite). Ids are global (the input mesh's numbering),
// so a message names the same vertex or tet whatever the rank count.
struct NonFiniteSite {
  enum class Kind {
    none,            // nothing non-finite on this rank
    position,        // a coordinate of vertex `id`
    velocity,        // the inertial target y = q_t + h v of vertex `id`
    element_energy,  // V Psi(F) of tet `id`
    // Tet `id` is inverted (det F <= 0) and its model is undefined there (the
    // neo-Hookean family): its energy is +inf by design, the barrier that
    // makes the step control reject inversion. Expected in a trial; a step
    // that cannot leave it fails like any other.
    inverted_element,
    vertex_energy,  // the inertia/gravity/load/damping term of vertex `id`
    sum,            // every term finite, their sum not (overflow)
  };
  Kind kind = Kind::none;
  long long id = -1;
  double value = 0;  // the offending value (coordinate, energy)
  bool found() const { return kind != Kind::none; }
};

const char* describe(NonFiniteSite::Kind kind);

struct StepStats {
  int iterations = 0;
  int rollbacks = 0;
  double alpha = 0;           // at the end of the step (methods without one: 0)
  double initial_energy = 0;  // eps of the initial guess
  double energy = 0;          // eps at the last accepted check
  // An accepted check may exceed the previous one by at most this much: the
  // round-off of evaluating eps (see energy_roundoff), not a real rise.
  double energy_tolerance = 0;
  bool stalled = false;  // alpha fell below alpha_min before the iteration budget
  // Checks rolled back because the trial state's energy was not finite on
  // some rank (known on every rank: the count rides in the energy reduction).
  int nonfinite_rollbacks = 0;
  // False when no state with finite energy was reached in the whole step: the
  // body state was then left as it was at the start of the step (the last
  // good state) and the run must stop.
  bool finite = true;
  // This rank's own findings, from a local scan made only when the reduced
  // count says a state was non-finite (empty on ranks that saw nothing): the
  // first rolled-back trial of the step, and with finite == false the state
  // the step could not leave.
  NonFiniteSite rejected_at, failed_at;
  // The step was taken twice: its predicted initial guess led to no finite
  // state, and the retry from the step start q_t (always finite: the last
  // accepted state) succeeded or failed in its place (Simulation::step).
  bool retried_from_start = false;
  // The step ended at its first rollback to a predicted guess whose own
  // energy is not finite, for Simulation::step to retake from the start.
  bool abandoned_guess = false;

  // Chebyshev (0 for other methods): the bounds of the spectrum of D^-1 H
  // the step used (the automatic parameters' estimate, widened by any
  // rollback; with fixed parameters 0) and the rho of its last iteration.
  double lambda_min = 0, lambda_max = 0, rho = 0;
  int spectrum_steps = 0;  // Lanczos steps this step spent estimating them (0: reused)
  // The relative error of eps the step's last check estimates it left
  // (solver.accuracy; NaN when the checks gave no estimate).
  double error_estimate = 0;
  // The step ended because its energies resolved no more progress, its
  // estimate short of the target (CheckHistory's at_resolution).
  bool at_resolution = false;
};

// What a method carries from one step to the next: part of a checkpoint, so
// a restart continues bit for bit, and what `descent study` hands from its
// warm-up to every case.
struct StepMemory {
  double alpha = 0;  // step length (methods without one: 0)
  // Automatic Chebyshev: the spectrum bounds it reuses (0: none yet), the
  // steps since they were estimated, and whether the next step must
  // estimate them anew (the last one rolled back).
  double lambda_min = 0, lambda_max = 0;
  int steps_since_estimate = 0;
  bool reestimate = false;
  // The factor on lambda_max the steps use: grown by a rollback's widening
  // (the curvature met along the path lay above the estimate), relaxed by
  // gamma after each step without one, as the fixed parameters' alpha is.
  double widening = 1;
};

template <class Real>
class Stepper {
 public:
  virtual ~Stepper() = default;
  virtual StepStats step(BodyState<Real>& state) = 0;

  // What the method carries from step to step (part of a checkpoint).
  virtual StepMemory memory() const { return {}; }
  virtual void set_memory(const StepMemory&) {}

  // LocalProblem::local_region_sums at the end of the last step.
  virtual std::vector<double> local_region_sums() = 0;

  // The preconditioner other than Jacobi's the method applies (null with
  // Jacobi's or none).
  virtual const Preconditioner<Real>* preconditioner() const { return nullptr; }

  // Called with the current iterate after every iteration of a step (and
  // with k = 0 for the initial guess), for `descent study`: local dofs of q,
  // the inertial target y and the step-start positions q_t (xyz-interleaved).
  // Not set in runs; the methods never depend on it.
  using Observer = std::function<void(int k, const Real* q, const Real* y, const Real* qt)>;
  void set_observer(Observer observer) { observer_ = std::move(observer); }

  // The next step starts from q_t (solver.init = "position") whatever
  // solver.init says: once, for the retry of a failed step.
  void guess_next_step_from_start() { guess_from_start_ = true; }
  // The next step may end at its first rollback to a predicted guess of
  // non-finite energy (StepStats::abandoned_guess): once, from a caller that
  // then retakes it (Simulation::step).
  void abandon_non_finite_guess_next_step() { abandon_guess_ = true; }

 protected:
  // Whether this step's prediction must start from q_t; clears the request.
  bool take_guess_from_start() { return std::exchange(guess_from_start_, false); }
  // Whether this step may abandon a non-finite predicted guess; clears the
  // permission.
  bool take_abandon_guess() { return std::exchange(abandon_guess_, false); }

  void observe(int k, const Real* q, const Real* y, const Real* qt) const {
    if (observer_) observer_(k, q, y, qt);
  }
  // Whether an observer is set: a method that must form q to show it can
  // skip that work otherwise.
  bool observed() const { return static_cast<bool>(observer_); }

 private:
  Observer observer_;
  bool guess_from_start_ = false;
  bool abandon_guess_ = false;
};

// The method named by spec.method over `problem` (which must outlive it).
template <class Real>
std::unique_ptr<Stepper<Real>> make_stepper(LocalProblem<Real>& problem, const SolverSpec& spec);

}  // namespace descent
