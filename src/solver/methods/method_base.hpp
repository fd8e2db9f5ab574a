#pragma once
// What the methods beyond chebyshev share (docs/methods.md): the step frame
// (initial guess as chebyshev's, held dofs, v = (q - q_t)/h), the full
// gradient of eps with the Jacobi diagonal, owned-dof inner products, and the
// paper's step-length control by the energy every check_interval iterations
// (§4.2, c = 0: roll back to the checked state and alpha <- gamma alpha when
// the energy rose; stop once alpha < alpha_min). With solver.accuracy the
// same checks end the step where the energies say the relative error is
// below the target (solver/check_history.hpp: Chebyshev's estimator, read
// without a bound unless the method has one), within solver.iterations.
//
// Layout: every vector holds 3 reals per local vertex, xyz-interleaved, in
// LocalMesh order. Inner products sum owned vertices [0, num_owned) only, so
// each dof counts once over all ranks; shared vertices are updated
// redundantly and identically by every sharer (their gradient totals are
// bitwise equal), so no position exchange is needed.
#include <memory>
#include <vector>

#include "io/scene.hpp"
#include "solver/check_history.hpp"
#include "solver/local_problem.hpp"
#include "solver/preconditioners/preconditioner.hpp"
#include "solver/step_control.hpp"
#include "solver/stepper.hpp"

namespace descent {

template <class Real>
class MethodBase : public Stepper<Real> {
 public:
  // own_guess: the method replaces the predicted initial guess by its own in
  // iterate() (and observes it there as iteration 0); the energy check's
  // initial state is then not evaluated.
  MethodBase(LocalProblem<Real>& problem, const SolverSpec& spec, bool own_guess = false);
  StepStats step(BodyState<Real>& state) final;
  StepMemory memory() const override { return {alpha_}; }
  void set_memory(const StepMemory& memory) override { alpha_ = memory.alpha; }
  std::vector<double> local_region_sums() override {
    return problem_.local_region_sums(q_.data(), y_.data(), qt_.data());
  }

 protected:
  // The iterations of one step, from q_ (the initial guess, held dofs in
  // place); leaves the result in q_.
  virtual void iterate(StepStats& stats) = 0;

  // g = grad eps(q), 0 on held dofs; with refresh also the clamped Hessian
  // diagonal (kernels/vertex.hpp dof_diagonal) per dof into diag. Contact
  // barriers (contact.method = "energy") are part of eps; between refreshes
  // they raise diag, when not null, where they have stiffened, as
  // chebyshev's iterations do. Nesterov asks for that: its extrapolated
  // points reach into closing pairs, and over a diagonal kept from before a
  // pair closed its next move jumped by the barrier's force (a box's
  // vertices sent 31 m in a 20 m/s impact). gd, jacobi_gd and lbfgs keep
  // theirs to the refresh.
  void gradient(const Real* q, Real* g, Real* diag, bool refresh);
  // An update of q_ in two calls: move_target() is where to write every dof
  // of the new iterate (computed from q_, which it may be), and
  // finish_move() makes it q_. With contact barriers the target is a
  // buffer of its own and finish_move() first cuts each
  // surface vertex's move from q_ as chebyshev's guard does, each move
  // proven free of crossings before it is made (LocalProblem::
  // guard_contact_moves; gradient(q_) must be the last gradient
  // evaluated); without, q_ is updated in place, as before. With `from`
  // the move starts there instead of at q_: the point of the last gradient
  // (nesterov's extrapolated point), which the guard's ghosts then hold.
  Real* move_target();
  void finish_move(const Real* from = nullptr);
  // With contact barriers: the move q_ -> to cut and proven in place as
  // finish_move() does, for a point the method evaluates that is not an
  // iterate (nesterov's extrapolation); nothing without. Only where
  // momentum_guarded().
  void guard_extrapolation(Real* to);
  // Whether nesterov may carry its momentum into the next move (true
  // without contact between bodies). Not under the body guard's safe mode,
  // whose bound is the nearest gap measured at the last gradient's point;
  // nor after a move the guard cut on some rank: the momentum of the cut
  // vertices' neighbours carried on into the pair, and pushed an interior
  // vertex of a box through its own surface into the other box (20 m/s).
  bool momentum_guarded() const;
  // z = P^-1 g (z may be g): D^-1 (d, the diagonal the method keeps) or the
  // preconditioner solver.preconditioner names, which MethodBase rebuilds at
  // each step's initial guess (every solver.preconditioner_refresh steps)
  // and after each rollback.
  void precondition(const Real* g, const Real* d, Real* z);
  // A method whose operator changes within a step (newton: each iteration's
  // Hessian) rebuilds P^-1 at q itself; nothing with Jacobi's.
  void refresh_preconditioner(const Real* q);
  // The preconditioner other than Jacobi's (null with Jacobi).
  const Preconditioner<Real>* preconditioner() const override { return preconditioner_.get(); }

  // This rank's share of a . b (owned dofs); sum with problem_.global_dots.
  double local_dot(const Real* a, const Real* b) const;
  // This rank's share of sum a^2 / d (owned dofs).
  double local_weighted_norm2(const Real* a, const Real* d) const;
  void report(int k) const { this->observe(k, q_.data(), y_.data(), qt_.data()); }
  bool held(std::size_t dof) const { return fixed_[dof / 3] & (1u << (dof % 3)); }
  // v_t of the step being taken (3 per local vertex), valid inside iterate().
  const Real* step_velocity() const { return step_velocity_; }
  std::size_t size() const { return q_.size(); }

  // The energy check after iteration k (0-based).
  enum class Check {
    none,         // no check after this iteration
    accepted,     // the trial is the new checked state
    rolled_back,  // back to the checked state, alpha shortened
    stalled,      // alpha fell below alpha_min: the step ends
    converged,    // accepted, and the accuracy target is met: the step ends
  };
  Check check(int k, StepStats& stats);
  static bool ends_step(Check c) { return c == Check::stalled || c == Check::converged; }
  // The Chebyshev rate phi (solver/spectrum.hpp) that bounds the method's
  // error after k iterations since a (re)start, for the accuracy target's
  // estimate; 0 (the default) where no such bound holds.
  virtual double bound_rate() const { return 0; }

  LocalProblem<Real>& problem_;
  SolverSpec spec_;
  double alpha_;
  std::vector<Real> y_, qt_, q_, q_checked_;

 private:
  const std::vector<std::uint8_t>& fixed_;
  std::unique_ptr<Preconditioner<Real>> preconditioner_;
  // This rank's share of eps(q) with the pairs between bodies (each pair
  // counted once; +inf when the guard could not prove a path free of
  // crossings) besides LocalProblem::local_energy's terms.
  Energy local_energy_at(const Real* q);

  bool barrier_;               // contact barriers in eps
  std::vector<Real> target_;   // move_target() with a barrier
  std::vector<Real> scratch_;  // P^-1 g in place
  int steps_since_refresh_;    // a run rebuilds P^-1 at its first step
  const Real* step_velocity_ = nullptr;
  bool own_guess_;
  // Step-control state of the current step.
  EnergyCheck check_{false, 0.0};
  Energy initial_local_energy_{};
  // The accepted checks' energies since the step's start or the last
  // rollback (after iteration restart_at_), for the accuracy target.
  CheckHistory history_;
  int restart_at_ = 0;
};

}  // namespace descent
