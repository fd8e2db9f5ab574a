#pragma once
// The paper's method (solver/chebyshev_descent.hpp) with the iteration on a
// device (DESIGN §4): the host keeps the step control, the device engine
// keeps the mesh and the iterates. Per step the host sends the initial guess,
// inertial target, step-start positions and loads, and receives the final
// positions; between checks it only launches. The energy check stays the one
// MPI_Allreduce (LocalProblem::global_energies), fed by a device reduction.
// Not supported here: the per-iteration observer of `descent study` (it
// would copy every iterate back); study runs use the CPU backend.
#include <memory>
#include <vector>

#include "backends/device_engine.hpp"
#include "io/scene.hpp"
#include "solver/local_problem.hpp"
#include "solver/stepper.hpp"

namespace descent {

template <class Real>
class DeviceChebyshev final : public Stepper<Real> {
 public:
  DeviceChebyshev(LocalProblem<Real>& problem, const SolverSpec& spec,
                  std::unique_ptr<DeviceEngine<Real>> engine);
  StepStats step(BodyState<Real>& state) override;

  double alpha() const override { return alpha_; }
  void set_alpha(double alpha) override { alpha_ = alpha; }

  std::vector<double> local_region_sums() override {
    return problem_.local_region_sums(q_, y_, qt_);
  }

  const DeviceEngine<Real>& engine() const { return *engine_; }
  DeviceEngine<Real>& engine() { return *engine_; }

  // Wall time of all steps so far: iterating (launch to completion) and the
  // energy checks (device reduction, the allreduce, accept or roll back).
  double iterate_seconds() const { return iterate_seconds_; }
  double check_seconds() const { return check_seconds_; }

 private:
  LocalProblem<Real>& problem_;
  SolverSpec spec_;
  double alpha_;
  std::unique_ptr<DeviceEngine<Real>> engine_;
  // The engine's pinned host buffers, 3 per local vertex: the step's
  // inertial target and start positions, and the iterate (initial guess
  // going in, result coming out).
  Real *y_, *qt_, *q_;
  std::size_t n_;                        // 3 per local vertex
  bool force_on_device_nonzero_ = true;  // until the first upload says otherwise
  std::vector<Real> interpolants_;
  double iterate_seconds_ = 0, check_seconds_ = 0;
};

}  // namespace descent
