#pragma once
// The Hessian of eps (elastic element terms + the vertex terms' m (1/h^2 +
// c/h) per dof, and with assemble_contact the obstacles' contact terms)
// applied to a direction, distributed like the gradient: per-tet
// corner products, gathered to vertices and completed through the halo.
// Rows and columns of held dofs are masked out (the product is 0 there).
//
// Two forms: `product` evaluates the exact element Hessian along p from dPdF
// at q (no storage; nonlinear CG's step length), and assemble/apply keeps the
// 12x12 element Hessians of one q, exact or PSD-projected
// (kernels/element_hessian.hpp, 144 reals per tet) for the many products of
// Newton's linear solve. Layout: vectors 3 reals per local vertex, xyz-interleaved.
#include <vector>

#include "solver/local_problem.hpp"

namespace descent {

template <class Real>
class HessianOperator {
 public:
  explicit HessianOperator(LocalProblem<Real>& problem);

  // out = H(q) p with the exact (unprojected) element Hessians; given the
  // step start qt, with the contact barriers' exact terms at q too
  // (contact.method = "energy": the obstacles', and the pairs' between
  // bodies, collective with the contact neighbours).
  void product(const Real* q, const Real* p, Real* out, const Real* qt = nullptr);

  // Stores the element Hessians at q, PSD-projected when `project`, and the
  // diagonal of their assembly (Jacobi preconditioner; 1 on held dofs).
  void assemble(const Real* q, bool project);
  // After assemble(): the contact barriers' terms (contact.method =
  // "energy") at q from step start qt join the operator and its diagonal:
  // the obstacles' barrier and lagged friction, one 3x3 block per surface
  // vertex, stored; the pairs between bodies, evaluated at q by each
  // apply() (BodyContact::add_hessian_product, collective with the contact
  // neighbours). Exact, or when `project` in the positive semi-definite
  // form the engine's diagonal takes (kernels/obstacle_contact.hpp,
  // kernels/pair_contact.hpp). Each sharer of a vertex adds the same.
  // Nothing without barriers.
  void assemble_contact(const Real* q, const Real* qt, bool project);
  void apply(const Real* p, Real* out);
  const std::vector<Real>& diagonal() const { return diagonal_; }
  // The stored element Hessians (144 per local tet, row-major, rows and
  // columns in corner order: the tet's 4 vertices x xyz) and the vertex
  // terms' curvature m (1/h^2 + c/h) per dof, for Newton's direct solver.
  const std::vector<Real>& element_hessians() const { return hessians_; }
  const std::vector<Real>& vertex_curvature() const { return vertex_curvature_; }

 private:
  // out += vertex terms p; out = 0 on held dofs.
  void finish(const Real* p, Real* out) const;
  LocalProblem<Real>& problem_;
  std::vector<Real> corners_;   // 12 per tet, with threads only
  std::vector<Real> hessians_;  // 144 per tet, row-major
  std::vector<Real> diagonal_;
  std::vector<Real> vertex_curvature_;  // m (1/h^2 + c/h) per dof
  // 9 per surface vertex (ObstacleContact::vertices() order), row-major:
  // the contact blocks of the last assemble_contact, empty after assemble().
  std::vector<Real> contact_blocks_;
  // The pairs' form (none: no pairs) and the positions the last
  // assemble_contact took them at (3 per local vertex).
  PairHessian pair_hessian_ = PairHessian::none;
  std::vector<Real> pairs_at_;
};

}  // namespace descent
