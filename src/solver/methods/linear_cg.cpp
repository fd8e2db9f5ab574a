#include "solver/methods/linear_cg.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "kernels/corotated_linear.hpp"
#include "kernels/loops.hpp"
#include "solver/check_history.hpp"

namespace descent {

namespace {
// The guess comes from solver.linear_cg_guess; the shared prediction only
// needs to fill q_t and y, which "position" does without any collective.
SolverSpec with_position_prediction(SolverSpec spec) {
  spec.init = "position";
  return spec;
}
}  // namespace

template <class Real>
LinearCg<Real>::LinearCg(LocalProblem<Real>& problem, const SolverSpec& spec)
    : MethodBase<Real>(problem, with_position_prediction(spec), true),
      model_(std::get<Corotated<Real>>(problem.model())) {
  const Real h = problem.dt();
  const Real c = problem.vertex_terms().damping_over_h * h;
  mass_weight_ = Real(1) + h * c;
  stiffness_weight_ = h * h + h * static_cast<Real>(spec.rayleigh_stiffness);
  const std::size_t nt = static_cast<std::size_t>(problem.mesh().num_tets());
  rotations_.resize(9 * nt);
  corners_.resize(12 * nt);
  for (auto* v : {&force_, &inverse_preconditioner_, &v_, &b_, &r_, &z_, &p_, &ap_})
    v->assign(this->size(), Real(0));
}

template <class Real>
void LinearCg<Real>::prepare_elements() {
  const auto& mesh = this->problem_.mesh();
  const index_t nt = mesh.num_tets();
  const index_t* tets = mesh.tets.data();
  const TetRest<Real>* rest = this->problem_.rest().data();
  const Real* qt = this->qt_.data();
  Real* rotations = rotations_.data();
  Real* corners = corners_.data();
  const int max_sweeps = this->spec_.polar_sweeps;
  int most = 0;
  // Force corners first; the stiffness diagonal (Jacobi) reuses corners_
  // after the force is assembled.
#pragma omp parallel for schedule(static) reduction(max : most)
  for (index_t t = 0; t < nt; ++t) {
    const TetCorners<Real> x = loops::tet_corners(qt, &tets[4 * t]);
    int sweeps = 0;
    const Mat3<Real> q = polar_rotation(
        deformation_gradient(x.x[0], x.x[1], x.x[2], x.x[3], rest[t].dm_inv), max_sweeps, &sweeps);
    most = std::max(most, sweeps);
    std::copy(q.m, q.m + 9, &rotations[9 * static_cast<std::size_t>(t)]);
    Vec3<Real> g[4];
    corotated_linear_gradient(model_, rest[t], q, x, g);
    loops::store_corners(g, &corners[12 * static_cast<std::size_t>(t)]);
  }
  most_polar_sweeps_ = most;
  this->problem_.assemble_corners(corners, force_.data());
  for (Real& f : force_) f = -f;

  // The preconditioner's inverse per dof (1 on held dofs, whose rows are out).
  const std::string& kind = this->spec_.linear_cg_preconditioner;
  if (kind == "jacobi") {
#pragma omp parallel for schedule(static)
    for (index_t t = 0; t < nt; ++t) {
      Mat3<Real> q;
      std::copy(&rotations[9 * static_cast<std::size_t>(t)],
                &rotations[9 * static_cast<std::size_t>(t)] + 9, q.m);
      Vec3<Real> d[4];
      corotated_linear_diagonal(model_, rest[t], q, d);
      loops::store_corners(d, &corners[12 * static_cast<std::size_t>(t)]);
    }
    this->problem_.assemble_corners(corners, inverse_preconditioner_.data());
  }
  const auto& mass = this->problem_.mass();
  for (std::size_t dof = 0; dof < this->size(); ++dof) {
    const Real m = mass[dof / 3];
    Real d = 1;
    if (kind == "mass") d = m;
    if (kind == "jacobi") d = mass_weight_ * m + stiffness_weight_ * inverse_preconditioner_[dof];
    inverse_preconditioner_[dof] = this->held(dof) ? Real(1) : Real(1) / d;
  }
}

template <class Real>
void LinearCg<Real>::apply(const Real* p, Real* out) {
  const auto& mesh = this->problem_.mesh();
  const index_t nt = mesh.num_tets();
  const index_t* tets = mesh.tets.data();
  const TetRest<Real>* rest = this->problem_.rest().data();
  const Real* rotations = rotations_.data();
  Real* corners = corners_.data();
#pragma omp parallel for schedule(static)
  for (index_t t = 0; t < nt; ++t) {
    Mat3<Real> q;
    std::copy(&rotations[9 * static_cast<std::size_t>(t)],
              &rotations[9 * static_cast<std::size_t>(t)] + 9, q.m);
    const TetCorners<Real> pc = loops::tet_corners(p, &tets[4 * t]);
    Vec3<Real> kp[4];
    corotated_linear_product(model_, rest[t], q, pc.x, kp);
    loops::store_corners(kp, &corners[12 * static_cast<std::size_t>(t)]);
  }
  this->problem_.assemble_corners(corners, out);
  const auto& mass = this->problem_.mass();
  const std::size_t n = this->size();
#pragma omp parallel for schedule(static)
  for (std::size_t dof = 0; dof < n; ++dof)
    out[dof] = this->held(dof)
                   ? Real(0)
                   : mass_weight_ * mass[dof / 3] * p[dof] + stiffness_weight_ * out[dof];
}

template <class Real>
void LinearCg<Real>::precondition(const Real* r, Real* z) {
  // solver.preconditioner other than Jacobi: built on eps's PSD Hessian at
  // the step start, the operator solved here up to the rotations'
  // derivative and a scale (CG does not see the scale).
  if (this->preconditioner()) {
    MethodBase<Real>::precondition(r, nullptr, z);
    return;
  }
  const std::size_t n = this->size();
#pragma omp parallel for schedule(static)
  for (std::size_t dof = 0; dof < n; ++dof) z[dof] = inverse_preconditioner_[dof] * r[dof];
}

// q = q_t + h v on free dofs; held dofs keep their prescribed positions.
template <class Real>
void LinearCg<Real>::set_positions(const Real* v) {
  const Real h = this->problem_.dt();
  const std::size_t n = this->size();
#pragma omp parallel for schedule(static)
  for (std::size_t dof = 0; dof < n; ++dof)
    if (!this->held(dof)) this->q_[dof] = this->qt_[dof] + h * v[dof];
}

template <class Real>
void LinearCg<Real>::iterate(StepStats& stats) {
  LocalProblem<Real>& problem = this->problem_;
  const std::size_t n = this->size();
  const Real h = problem.dt();
  const Real* v_t = this->step_velocity();
  const auto& mass = problem.mass();
  const VertexTerms<Real>& terms = problem.vertex_terms();
  const Real* load = problem.external_force().data();
  prepare_elements();

  // Right-hand side and initial guess; held dofs: v is their prescribed motion.
  const std::string& guess = this->spec_.linear_cg_guess;
  for (std::size_t dof = 0; dof < n; ++dof) {
    const Real m = mass[dof / 3];
    const Real force = force_[dof] + m * terms.gravity[dof % 3] + load[dof];
    if (this->held(dof)) {
      b_[dof] = 0;
      v_[dof] = (this->q_[dof] - this->qt_[dof]) / h;
      continue;
    }
    b_[dof] = m * v_t[dof] + h * force;
    v_[dof] = guess == "zero" ? Real(0) : guess == "velocity" ? v_t[dof] : v_t[dof] + h * force / m;
  }
  set_positions(v_.data());
  const Energy initial = problem.local_energy(this->q_.data(), this->y_.data(), this->qt_.data());
  this->report(0);

  apply(v_.data(), ap_.data());
  for (std::size_t dof = 0; dof < n; ++dof)
    r_[dof] = this->held(dof) ? Real(0) : b_[dof] - ap_[dof];
  precondition(r_.data(), z_.data());
  p_ = z_;
  double sums[3] = {this->local_dot(r_.data(), z_.data()), this->local_dot(r_.data(), r_.data()),
                    this->local_dot(b_.data(), b_.data())};
  problem.global_dots(sums, 3);
  double rz = sums[0], rr = sums[1];
  const double stop = this->spec_.linear_cg_tolerance * sums[2];
  // The accuracy target from the residual: each iteration lowers the
  // system's quadratic phi(v) = v.Av / 2 - b.v by (r.z)^2 / (2 p.Ap), from
  // the dots CG forms anyway. After every iteration (phi costs no
  // reduction, so CG needs no check_interval: at 8 a step could not stop
  // before 40 iterations, where the small helix's solve converges in 21)
  // phi, relative to phi(v_0) = 0, goes to the energy checks' estimator (no
  // bound: the step ends on a confirmed reading), which reads the relative
  // error of the linear solve,
  //   (phi(v_k) - phi*) / (phi(v_0) - phi*) = |v_k - v*|_A^2 / |v_0 - v*|_A^2,
  // not e of eps: the converged solve is linearly implicit Euler's answer,
  // whose own distance from eps's minimiser (the rotations' derivative
  // dropped, one linearisation) no iteration count removes.
  CheckHistory history;
  history.restart(0.0);
  double phi = 0;
  stats.error_estimate = std::numeric_limits<double>::quiet_NaN();
  const double target = this->spec_.accuracy;
  int k = 0;
  while (k < this->spec_.iterations && rr > stop) {
    apply(p_.data(), ap_.data());
    double pap = this->local_dot(p_.data(), ap_.data());
    problem.global_dots(&pap, 1);
    if (!(pap > 0)) break;  // A is SPD; only a non-finite state gets here
    phi -= 0.5 * rz * rz / pap;
    const Real a = static_cast<Real>(rz / pap);
#pragma omp parallel for schedule(static)
    for (std::size_t dof = 0; dof < n; ++dof) {
      v_[dof] += a * p_[dof];
      r_[dof] -= a * ap_[dof];
    }
    precondition(r_.data(), z_.data());
    double dots[2] = {this->local_dot(r_.data(), z_.data()), this->local_dot(r_.data(), r_.data())};
    problem.global_dots(dots, 2);
    const Real beta = static_cast<Real>(dots[0] / rz);
    rz = dots[0];
    rr = dots[1];
#pragma omp parallel for schedule(static)
    for (std::size_t dof = 0; dof < n; ++dof) p_[dof] = z_[dof] + beta * p_[dof];
    ++k;
    // q only for an observer (descent study); the step's q is formed below.
    if (this->observed()) {
      set_positions(v_.data());
      this->report(k);
    }
    history.record(k, phi);
    const AccuracyReading reading = history.read(0.0, 0.0, target);
    stats.error_estimate = reading.estimate;
    if (target > 0 && reading.confirmed) break;
  }
  set_positions(v_.data());
  cg_iterations_ = k;
  relative_residual2_ = sums[2] > 0 ? rr / sums[2] : 0;
  stats.iterations = k;

  // eps at the guess and at the result, one reduction: the step's stats and
  // the non-finite check (a step ending non-finite leaves the body as it was).
  const Energy local[2] = {problem.local_energy(this->q_.data(), this->y_.data(), this->qt_.data()),
                           initial};
  const EnergySums reduced = problem.global_energies(local, 2);
  stats.energy = reduced.energy[0].value;
  stats.initial_energy = reduced.energy[1].value;
  if (!reduced.finite[0]) {
    stats.finite = false;
    stats.failed_at = problem.find_non_finite(this->q_.data(), this->y_.data(), this->qt_.data());
  }
}

template class LinearCg<double>;
template class LinearCg<float>;

}  // namespace descent
