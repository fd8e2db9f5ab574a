#pragma once
// `linear_cg`, paper 2 (Dahl & Bargteil 2019): linearly implicit Euler on
// corotated linear elements (kernels/corotated_linear.hpp),
//   (M (1 + h c) + (h^2 + h beta) K) v = M v_t + h (f_el(q_t) + f_ext),
//   q = q_t + h v,
// with K the corotated stiffness at q_t (rotations Q from at most
// solver.polar_sweeps 2x2 Jacobi sweeps, fixed through the step), c the
// mass-proportional damping (solver.damping) and beta the stiffness-
// proportional one (solver.rayleigh_stiffness): Rayleigh damping C = c M +
// beta K, which appears on the left only (Eq. 9). This is one Newton step on
// eps of the corotated model with the rotation's derivative dropped, so eps
// and e_k in `descent study` measure it like every other method.
//
// Solved matrix-free by PCG (identity, mass or Jacobi preconditioner,
// solver.linear_cg_preconditioner) from the initial guess 0, v_t or
// v_t + h M^-1 (f_el + f_ext) (solver.linear_cg_guess), for at most
// solver.iterations iterations or until r.r <= linear_cg_tolerance b.b
// (paper 2's criterion), or with solver.accuracy = TOL until the relative
// A-norm error of the solve, estimated from the residual's dots, is below
// TOL (linear_cg.cpp says what that measures). Held dofs move as
// prescribed: v there is their motion over the step, and their rows are out
// of the system. One CG iteration is one observed iteration.
//
// Collectives per step (each one MPI_Allreduce): 1 ([r.z, r.r, b.b] at the
// start) + 2 per CG iteration (p.Ap; [r.z, r.r] fused) + 1 energy reduction
// of eps at the start and the end (stats and the non-finite check). No step
// control: the method has no step length.
//
// Layout: vectors hold 3 reals per local vertex, xyz-interleaved; rotations_
// 9 reals per local tet (row-major Q).
#include <vector>

#include "kernels/corotated.hpp"
#include "solver/methods/method_base.hpp"

namespace descent {

template <class Real>
class LinearCg final : public MethodBase<Real> {
 public:
  LinearCg(LocalProblem<Real>& problem, const SolverSpec& spec);
  // No step length: 0 in the stats and checkpoints, as the Stepper contract says.
  StepMemory memory() const override { return {}; }
  void set_memory(const StepMemory&) override {}

  // Of the last step: CG iterations made, r.r / b.b at the end, and the most
  // polar sweeps any of this rank's tets needed (<= solver.polar_sweeps).
  int cg_iterations() const { return cg_iterations_; }
  double relative_residual2() const { return relative_residual2_; }
  int most_polar_sweeps() const { return most_polar_sweeps_; }

 private:
  void iterate(StepStats& stats) override;
  // Rotations at q_t and the elastic force f_el(q_t) into force_.
  void prepare_elements();
  // out = A p on free rows, 0 on held rows (held columns of p count).
  void apply(const Real* p, Real* out);
  void precondition(const Real* r, Real* z);
  void set_positions(const Real* v);

  Corotated<Real> model_;
  Real stiffness_weight_;  // h^2 + h beta
  Real mass_weight_;       // 1 + h c
  std::vector<Real> rotations_, corners_;
  std::vector<Real> force_, inverse_preconditioner_;
  std::vector<Real> v_, b_, r_, z_, p_, ap_;
  int cg_iterations_ = 0;
  double relative_residual2_ = 0;
  int most_polar_sweeps_ = 0;
};

}  // namespace descent
