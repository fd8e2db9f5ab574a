#pragma once
// What every time-stepping method (solver.method) and every backend offers
// the run driver: advance the body by one implicit step of the incremental
// potential in LocalProblem, and report how the step went. Methods differ
// only in how they descend on eps; the problem, halo and reduction are shared.
#include <memory>
#include <vector>

#include "io/scene.hpp"
#include "partition/partition.hpp"

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
};

template <class Real>
class Stepper {
 public:
  virtual ~Stepper() = default;
  virtual StepStats step(BodyState<Real>& state) = 0;

  // The step length carried from step to step (part of a checkpoint);
  // methods without one keep 0.
  virtual double alpha() const { return 0; }
  virtual void set_alpha(double) {}

  // LocalProblem::local_region_sums at the end of the last step.
  virtual std::vector<double> local_region_sums() = 0;
};

// The method named by spec.method over `problem` (which must outlive it).
template <class Real>
std::unique_ptr<Stepper<Real>> make_stepper(LocalProblem<Real>& problem, const SolverSpec& spec);

}  // namespace descent
