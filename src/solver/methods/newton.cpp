#include "solver/methods/newton.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace descent {

template <class Real>
Newton<Real>::Newton(LocalProblem<Real>& problem, const SolverSpec& spec)
    : MethodBase<Real>(problem, spec), hessian_(problem) {
  for (auto* v : {&g_, &dq_, &r_, &z_, &p_, &ap_, &trial_}) v->assign(this->size(), Real(0));
  // Collective set-up (gathers to rank 0): every rank builds its Newton alike.
  if (spec.newton_solver == "ldlt") ldlt_ = std::make_unique<NewtonLdlt<Real>>(problem, hessian_);
  // Collective (PETSc start on first use, matrix pattern); throws InputError
  // in a build without PETSc.
  if (spec.newton_solver == "petsc")
    petsc_ = std::make_unique<NewtonPetsc<Real>>(problem, hessian_, spec);
}

template <class Real>
int Newton<Real>::solve(double rhs_norm2, bool& positive) {
  const std::size_t n = this->size();
  const Real* diag = hessian_.diagonal().data();
  for (std::size_t k = 0; k < n; ++k) {
    dq_[k] = 0;
    r_[k] = -g_[k];
  }
  this->precondition(r_.data(), diag, z_.data());
  p_ = z_;
  double rz = this->local_dot(r_.data(), z_.data());
  this->problem_.global_dots(&rz, 1);
  const double stop = this->spec_.cg_tolerance * this->spec_.cg_tolerance * rhs_norm2;
  int it = 0;
  while (it < this->spec_.cg_iterations) {
    hessian_.apply(p_.data(), ap_.data());
    double pap = this->local_dot(p_.data(), ap_.data());
    this->problem_.global_dots(&pap, 1);
    ++it;
    if (!(pap > 0)) {  // not positive definite along p
      positive = false;
      break;
    }
    const Real a = static_cast<Real>(rz / pap);
#pragma omp parallel for schedule(static)
    for (std::size_t k = 0; k < n; ++k) {
      dq_[k] += a * p_[k];
      r_[k] -= a * ap_[k];
    }
    this->precondition(r_.data(), diag, z_.data());
    double dots[2] = {this->local_dot(r_.data(), z_.data()), this->local_dot(r_.data(), r_.data())};
    this->problem_.global_dots(dots, 2);
    if (dots[1] <= stop) break;
    const Real beta = static_cast<Real>(dots[0] / rz);
    rz = dots[0];
#pragma omp parallel for schedule(static)
    for (std::size_t k = 0; k < n; ++k) p_[k] = z_[k] + beta * p_[k];
  }
  return it;
}

template <class Real>
BodyContact<Real>* Newton<Real>::pairs() {
  BodyContact<Real>* bodies = this->problem_.body_contact();
  return bodies && this->problem_.has_contact_barrier() ? bodies : nullptr;
}

template <class Real>
double Newton<Real>::longest_safe_step() {
  const ObstacleContact<Real>* contact = this->problem_.contact();
  const bool obstacles = contact && contact->energy_method();
  if (!obstacles && !pairs()) return 1.0;
  double fraction = 1;
  if (obstacles) {
    const ContactView<Real> view = contact->view();
    for (index_t s = 0; s < view.num_vertices; ++s) {
      const std::size_t v = static_cast<std::size_t>(view.vertices[s]);
      fraction =
          std::min(fraction, static_cast<double>(move_fraction(
                                 view.obstacles, view.num_obstacles, this->q_.data() + 3 * v,
                                 dq_.data() + 3 * v, kGapKept<Real>, kLeastGap<Real> * view.dh)));
    }
  }
  if (pairs()) fraction = std::min(fraction, pairs()->path_fraction(this->q_.data(), dq_.data()));
  return -this->problem_.global_max(-fraction);
}

template <class Real>
Energy Newton<Real>::local_energy(const Real* q) {
  Energy e = this->problem_.local_energy(q, this->y_.data(), this->qt_.data());
  if (pairs()) {
    const double pair_energy = pairs()->measured_energy(q);
    e.value += pair_energy;
    e.magnitude += std::abs(pair_energy);
  }
  return e;
}

template <class Real>
void Newton<Real>::iterate(StepStats& stats) {
  const std::size_t n = this->size();
  gradient_norms_.clear();
  cg_iterations_.clear();
  petsc_reductions_.clear();
  projected_solves_ = 0;
  double g0 = 0;
  double energy = std::numeric_limits<double>::quiet_NaN();  // eps(q_), once known
  for (int k = 0; k <= this->spec_.newton_iterations; ++k) {
    // The pairs found again where a vertex has drifted half the cap from
    // where they were found (the step's start finds them; the line search
    // keeps every vertex within the cap): one allreduce per iteration.
    if (k > 0 && pairs() &&
        this->problem_.global_max(pairs()->needs_rebuild(this->q_.data()) ? 1.0 : 0.0) > 0)
      pairs()->rebuild_here(this->q_.data());
    this->gradient(this->q_.data(), g_.data(), nullptr, false);
    double gg = this->local_dot(g_.data(), g_.data());
    this->problem_.global_dots(&gg, 1);
    const double norm = std::sqrt(gg);
    gradient_norms_.push_back(norm);
    if (k == 0) g0 = norm;
    if (norm <= this->spec_.newton_tolerance * g0 || k == this->spec_.newton_iterations) break;

    // The exact Hessian first (quadratic convergence); the projected one when
    // CG meets non-positive curvature (LDL^T: a D entry <= 0) or the result
    // is no descent direction.
    bool project = this->spec_.newton_projection == "always";
    double slope = 0;
    // P^-1 of the CG (solver.preconditioner other than Jacobi's) at this
    // iterate's Hessian: the step's start built it at the guess.
    if (k > 0 && !ldlt_ && !petsc_) this->refresh_preconditioner(this->q_.data());
    for (;;) {
      hessian_.assemble(this->q_.data(), project);
      hessian_.assemble_contact(this->q_.data(), this->qt_.data(), project);
      bool positive = true;
      if (ldlt_) {
        positive = ldlt_->solve(g_.data(), dq_.data());
        cg_iterations_.push_back(0);
      } else if (petsc_) {
        positive = petsc_->solve(g_.data(), dq_.data(), this->q_.data());
        cg_iterations_.push_back(petsc_->iterations());
        petsc_reductions_.push_back(petsc_->reductions());
      } else {
        cg_iterations_.push_back(solve(gg, positive));
      }
      slope = this->local_dot(g_.data(), dq_.data());
      this->problem_.global_dots(&slope, 1);
      if ((positive && slope < 0) || project) break;
      project = true;
      ++projected_solves_;
    }

    // The accuracy target from Newton's decrement lambda^2 = -g.dq (g^T H^-1
    // g for the system solved): the quadratic model at q_k puts its minimum
    // lambda^2 / 2 below eps(q_k), so eps(q_k) - eps* ~ lambda^2 / 2 and
    //   e_k ~ (lambda^2 / 2) / (eps_0 - eps_k + lambda^2 / 2);
    // e_k <= TOL is the decrement's tolerance
    //   lambda^2 / 2 <= TOL / (1 - TOL) (eps_0 - eps_k),
    // the decrease made so far setting its scale. At k = 0 nothing has been
    // decreased (e_0 = 1). The step along dq, already solved for, is still
    // taken (one more energy evaluation): its line search only lowers eps,
    // so the result's e is at most the estimate's. No descent direction
    // (round-off): no estimate.
    const double half_decrement = std::max(0.0, -0.5 * slope);
    const double decreased = k > 0 ? stats.initial_energy - energy : 0.0;
    const double estimate = half_decrement > 0
                                ? half_decrement / (std::max(0.0, decreased) + half_decrement)
                                : std::numeric_limits<double>::quiet_NaN();
    stats.error_estimate = estimate;
    const bool target_met = this->spec_.accuracy > 0 && estimate <= this->spec_.accuracy;

    // Armijo backtracking from the longest step that keeps every contact
    // gap (obstacles and pairs); eps(q) rides with the first trial.
    double t = longest_safe_step();
    if (!(t > 0)) {  // dq closes a gap already at its floor: no move is safe
      stats.stalled = true;
      break;
    }
    bool accepted = false;
    for (int trial = 0; trial < 60; ++trial) {
      for (std::size_t i = 0; i < n; ++i) trial_[i] = this->q_[i] + static_cast<Real>(t) * dq_[i];
      const bool with_current = std::isnan(energy);
      const Energy local[2] = {local_energy(trial_.data()),
                               with_current ? local_energy(this->q_.data()) : Energy{}};
      const EnergySums sums = this->problem_.global_energies(local, with_current ? 2 : 1);
      if (with_current) {
        energy = sums.energy[1].value;
        if (k == 0) stats.initial_energy = energy;
      }
      const double tolerance = energy_roundoff(sums.energy[0].magnitude);
      if (sums.finite[0] && sums.energy[0].value <= energy + 1e-4 * t * slope + tolerance) {
        energy = sums.energy[0].value;
        accepted = true;
        break;
      }
      ++stats.rollbacks;
      t *= 0.5;
    }
    if (!accepted) {  // no decrease along dq at any length: round-off floor
      stats.stalled = true;
      break;
    }
    this->q_ = trial_;
    stats.iterations = k + 1;
    this->report(k + 1);
    if (target_met) break;
  }
  if (!std::isnan(energy)) stats.energy = energy;
}

template class Newton<double>;
template class Newton<float>;

}  // namespace descent
