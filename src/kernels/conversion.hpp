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
    if (previous - decay > l) l = previous - decay;
    return l < Real(0) ? Real(0) : (l > Real(1) ? Real(1) : l);
  }
};

// Element energy V ((1 - l) Psi + l Psi_arap) with the stored interpolant,
// the one the gradient used. An inverted element of a model undefined there
// counts as pure arap, as Eq. 17 will make it (sigma_min <= 0 gives l = 1):
// so a step that inverts an element is judged, not rejected outright. l is
// not re-derived from F otherwise: the gradient treats l as constant, and an
// energy whose l moved with F would not descend along it.
template <class Real, class Model>
DESCENT_HOST_DEVICE inline Real converted_energy(const Model& model, const Conversion<Real>& conv,
                                                 Real l, const TetRest<Real>& rest,
                                                 const TetCorners<Real>& c) {
  const Mat3<Real> f = deformation_gradient(c.x[0], c.x[1], c.x[2], c.x[3], rest.dm_inv);
  if constexpr (!Model::kInvertible) {
    if (det(f) <= Real(0)) l = Real(1);
  }
  const Real e = l < Real(1) ? element_energy_of(model, rest, f) : Real(0);
  const Real e_arap = l > Real(0) ? rest.volume * conv.arap.energy(f) : Real(0);
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
  // At l = 1 the model is not evaluated at all: it may be undefined or
  // overflow there (an inverted or crushed element), and 0 * inf is NaN.
  const bool with_model = l < Real(1);
  Mat3<Real> p{};
  if (with_model) p = model.stress(f);
  if (l > Real(0)) {
    const Mat3<Real> p_arap = conv.arap.stress(f);
    for (int k = 0; k < 9; ++k) p.m[k] = (Real(1) - l) * p.m[k] + l * p_arap.m[k];
  }
  Vec3<Real> b[4];
  for (int a = 0; a < 4; ++a) {
    b[a] = corner_operator(rest.dm_inv, a);
    const Vec3<Real> pb = mul(p, b[a]);
    grad[a] = {rest.volume * pb.x, rest.volume * pb.y, rest.volume * pb.z};
  }
  if (!diag) return;
  if (with_model) {
    model.hessian_diagonal(f, b, diag);
  } else {
    for (int a = 0; a < 4; ++a) diag[a] = {Real(0), Real(0), Real(0)};
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
// (Eq. 17 from the stored `previous`). At l = 1 the model is not evaluated:
// it may be undefined or overflow there (an inverted or crushed element),
// as arap's own dP/dF does at F = 0.
template <class Real, class Model>
DESCENT_HOST_DEVICE inline void converted_preconditioner_dpdf(const Model& model,
                                                              const Conversion<Real>& conv,
                                                              Real previous, const Mat3<Real>& f,
                                                              Real dpdf[81]) {
  const Real l = conv.next_interpolant(previous, f);
  if (l < Real(1))
    model.stress_derivative(f, dpdf);
  else
    for (int k = 0; k < 81; ++k) dpdf[k] = 0;
  for (int k = 0; k < 81; ++k) dpdf[k] *= Real(1) - l;
  for (int k = 0; k < 9; ++k) dpdf[10 * k] += l * Real(2) * conv.arap.mu;
}

// The hybrid element Hessian (1 - l) H + l H_arap at the stored interpolant
// l applied to p (l held constant, as converted_gradient holds it), for the
// spectrum estimate of the preconditioned Hessian. At l = 1 the model is not
// evaluated, as in the gradient.
template <class Real, class Model>
DESCENT_HOST_DEVICE inline void converted_hessian_product(
    const Model& model, const Conversion<Real>& conv, Real l, const TetRest<Real>& rest,
    const TetCorners<Real>& c, const Vec3<Real> p[4], Vec3<Real> out[4]) {
  Vec3<Real> base[4] = {}, blended[4] = {};
  if (l < Real(1)) element_hessian_product(model, rest, c, p, base);
  if (l > Real(0)) element_hessian_product(conv.arap, rest, c, p, blended);
  for (int a = 0; a < 4; ++a)
    out[a] = {(Real(1) - l) * base[a].x + l * blended[a].x,
              (Real(1) - l) * base[a].y + l * blended[a].y,
              (Real(1) - l) * base[a].z + l * blended[a].z};
}

}  // namespace descent
