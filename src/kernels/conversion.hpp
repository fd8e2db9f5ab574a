#pragma once
// Invertible model conversion (paper 1, Eqs. 17-19): an element whose
// smallest signed singular value falls toward lambda_minus is blended toward
// the arap energy, which is defined and well behaved for inverted elements.
// Per element an interpolant l in [0, 1] (state, carried across iterations
// and steps, starting at 0):
//   l <- min(1, max(0, l - L, (lambda_plus - sigma_min) / (lambda_plus - lambda_minus)))
//   Psi_hybrid = (1 - l) Psi + l Psi_arap
//   preconditioner diag((1 - l) H + l A^T A)
// where A^T A is the constant matrix of projective dynamics: for the arap
// energy mu |F - R|^2 its diagonal is 2 mu V |b_a|^2 on every axis of corner a.
//
// Every choice is a select() (kernels/real_math.hpp), so a block of tets
// takes these functions in lanes (kernels/cpu/lane_models.hpp); a term that
// no lane of the block needs (the model where every l = 1, arap where every
// l = 0) is skipped, as one tet skips it.
#include "kernels/arap.hpp"
#include "kernels/element.hpp"
#include "kernels/element_hessian_product.hpp"
#include "kernels/svd3.hpp"

namespace descent {

template <class Real>
struct Conversion {
  Real lambda_minus;
  Real lambda_plus;
  Real decay;  // L
  Arap<Real> arap;

  // Eq. 17.
  DESCENT_HOST_DEVICE Real next_interpolant(Real previous, const Mat3<Real>& f) const {
    const Real sigma_min = svd3(f).sigma[2];
    Real l = (lambda_plus - sigma_min) / (lambda_plus - lambda_minus);
    l = select(previous - decay > l, previous - decay, l);
    return select(l < Real(0), Real(0), select(l > Real(1), Real(1), l));
  }
};

// v where m holds, 0 elsewhere.
template <class Mask, class Real>
DESCENT_HOST_DEVICE inline Vec3<Real> where_or_zero(Mask m, const Vec3<Real>& v) {
  return {select(m, v.x, Real(0)), select(m, v.y, Real(0)), select(m, v.z, Real(0))};
}

// Element energy V ((1 - l) Psi + l Psi_arap) with the stored interpolant,
// the one the gradient used. An inverted element of a model undefined there
// counts as pure arap, as Eq. 17 will make it (sigma_min <= 0 gives l = 1):
// so a step that inverts an element is judged, not rejected outright. l is
// not re-derived from F otherwise: the gradient treats l as constant, and an
// energy whose l moved with F would not descend along it. Where l < 1 the
// element lies in the model's domain, so V Psi is element_energy_of's.
template <class Real, class Model>
DESCENT_HOST_DEVICE inline Real converted_energy(const Model& model, const Conversion<Real>& conv,
                                                 Real l, const TetRest<Real>& rest,
                                                 const TetCorners<Real>& c) {
  const Mat3<Real> f = deformation_gradient(c.x[0], c.x[1], c.x[2], c.x[3], rest.dm_inv);
  if constexpr (!Model::kInvertible) l = select(det(f) <= Real(0), Real(1), l);
  const auto with_model = l < Real(1);
  const auto blended = l > Real(0);
  Real e = 0, e_arap = 0;
  if (any_lane(with_model)) e = select(with_model, rest.volume * model.energy(f), Real(0));
  if (any_lane(blended)) e_arap = select(blended, rest.volume * conv.arap.energy(f), Real(0));
  return (Real(1) - l) * e + l * e_arap;
}

// Updates the element's interpolant `l` from its current F (Eq. 17), then
// the hybrid gradient per corner and, when `diag` is not null, the blended
// preconditioner diagonal (Eq. 19).
template <class Real, class Model>
DESCENT_HOST_DEVICE inline void converted_gradient(const Model& model, const Conversion<Real>& conv,
                                                   Real& l, const TetRest<Real>& rest,
                                                   const TetCorners<Real>& c, Vec3<Real> grad[4],
                                                   Vec3<Real>* diag) {
  const Mat3<Real> f = deformation_gradient(c.x[0], c.x[1], c.x[2], c.x[3], rest.dm_inv);
  l = conv.next_interpolant(l, f);
  // At l = 1 the model's terms are not taken: it may be undefined or
  // overflow there (an inverted or crushed element), and 0 * inf is NaN.
  const auto with_model = l < Real(1);
  const auto blended = l > Real(0);
  Mat3<Real> p{};
  if (any_lane(with_model)) {
    const Mat3<Real> p_model = model.stress(f);
    for (int k = 0; k < 9; ++k) p.m[k] = select(with_model, p_model.m[k], Real(0));
  }
  if (any_lane(blended)) {
    const Mat3<Real> p_arap = conv.arap.stress(f);
    for (int k = 0; k < 9; ++k)
      p.m[k] = select(blended, (Real(1) - l) * p.m[k] + l * p_arap.m[k], p.m[k]);
  }
  Vec3<Real> b[4];
  for (int a = 0; a < 4; ++a) {
    b[a] = corner_operator(rest.dm_inv, a);
    const Vec3<Real> pb = mul(p, b[a]);
    grad[a] = {rest.volume * pb.x, rest.volume * pb.y, rest.volume * pb.z};
  }
  if (!diag) return;
  for (int a = 0; a < 4; ++a) diag[a] = {Real(0), Real(0), Real(0)};
  if (any_lane(with_model)) {
    Vec3<Real> model_diag[4];
    model.hessian_diagonal(f, b, model_diag);
    for (int a = 0; a < 4; ++a) diag[a] = where_or_zero(with_model, model_diag[a]);
  }
  for (int a = 0; a < 4; ++a) {
    const Real pd = Real(2) * conv.arap.mu * dot(b[a], b[a]);
    diag[a] = {rest.volume * ((Real(1) - l) * diag[a].x + l * pd),
               rest.volume * ((Real(1) - l) * diag[a].y + l * pd),
               rest.volume * ((Real(1) - l) * diag[a].z + l * pd)};
  }
}

// The dP/dF a preconditioner takes for the hybrid energy (Eq. 19), layout of
// element_hessian.hpp: (1 - l) dP/dF of the model plus l times arap's at
// rest, 2 mu I (the whole of which converted_gradient's diagonal is the
// diagonal), with l the interpolant the element's next gradient takes at F
// (Eq. 17 from the stored `previous`). At l = 1 the model is not taken:
// it may be undefined or overflow there (an inverted or crushed element),
// as arap's own dP/dF does at F = 0.
template <class Real, class Model>
DESCENT_HOST_DEVICE inline void converted_preconditioner_dpdf(const Model& model,
                                                              const Conversion<Real>& conv,
                                                              Real previous, const Mat3<Real>& f,
                                                              Real dpdf[81]) {
  const Real l = conv.next_interpolant(previous, f);
  const auto with_model = l < Real(1);
  if (any_lane(with_model)) {
    model.stress_derivative(f, dpdf);
    for (int k = 0; k < 81; ++k) dpdf[k] = select(with_model, dpdf[k], Real(0));
  } else {
    for (int k = 0; k < 81; ++k) dpdf[k] = 0;
  }
  for (int k = 0; k < 81; ++k) dpdf[k] *= Real(1) - l;
  for (int k = 0; k < 9; ++k) dpdf[10 * k] += l * Real(2) * conv.arap.mu;
}

// The hybrid element Hessian (1 - l) H + l H_arap at the stored interpolant
// l applied to p (l held constant, as converted_gradient holds it), for the
// spectrum estimate of the preconditioned Hessian. At l = 1 the model is not
// taken, as in the gradient.
template <class Real, class Model>
DESCENT_HOST_DEVICE inline void converted_hessian_product(
    const Model& model, const Conversion<Real>& conv, Real l, const TetRest<Real>& rest,
    const TetCorners<Real>& c, const Vec3<Real> p[4], Vec3<Real> out[4]) {
  const auto with_model = l < Real(1);
  const auto blended = l > Real(0);
  Vec3<Real> base[4] = {}, arap[4] = {};
  if (any_lane(with_model)) {
    element_hessian_product(model, rest, c, p, base);
    for (int a = 0; a < 4; ++a) base[a] = where_or_zero(with_model, base[a]);
  }
  if (any_lane(blended)) {
    element_hessian_product(conv.arap, rest, c, p, arap);
    for (int a = 0; a < 4; ++a) arap[a] = where_or_zero(blended, arap[a]);
  }
  for (int a = 0; a < 4; ++a)
    out[a] = {(Real(1) - l) * base[a].x + l * arap[a].x, (Real(1) - l) * base[a].y + l * arap[a].y,
              (Real(1) - l) * base[a].z + l * arap[a].z};
}

}  // namespace descent
