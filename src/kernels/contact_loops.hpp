#pragma once
// The loops of obstacle contact over a rank's surface vertices, written once
// over any execution (kernels/execution.hpp), as kernels/loops.hpp's are.
//
// Layout: x, qt, p, hp, diag: 3 reals per local vertex, xyz-interleaved;
// partial: `width` reals per vertex (gradient xyz, then with width 6 the
// Hessian diagonal xyz); vertices: surface vertex s -> local id, the owned
// ones first; lags: `num_obstacles` per surface vertex.
#include <cmath>
#include <cstdint>

#include "kernels/execution.hpp"
#include "kernels/in_double.hpp"
#include "kernels/loops.hpp"
#include "kernels/obstacle_contact.hpp"

namespace descent {

namespace loops {

template <class Real>
DESCENT_HOST_DEVICE inline ContactTerms<Real> contact_terms(const ContactView<Real>& c, index_t s,
                                                            const Real* x, const Real* qt,
                                                            bool exact) {
  const std::int64_t v = c.vertices[s];
  return vertex_contact(c.obstacles, c.lags + static_cast<std::int64_t>(c.num_obstacles) * s,
                        c.num_obstacles, c.kappa[s], c.dh, c.eps_h, x + 3 * v, qt + 3 * v, exact);
}

// Per row of a positive semi-definite 3x3 block, the sum of its absolute
// values: a diagonal that dominates the block (Gershgorin), so the block's
// share of D^-1 H stays at most 1 however stiff the barrier is.
template <class Real>
DESCENT_HOST_DEVICE inline Real dominant_diagonal(const Real* h, int i) {
  const Real a = h[3 * i], b = h[3 * i + 1], c = h[3 * i + 2];
  return (a < 0 ? -a : a) + (b < 0 ? -b : b) + (c < 0 ? -c : c);
}

// A preconditioner P^-1 fixed at a refresh knows the barrier as it was then;
// as a gap closes the barrier stiffens by orders of magnitude within a step
// and P^-1 H gains eigenvalues far above Chebyshev's bound on those dofs.
// The iteration then applies S P^-1 S with S = diag(s) on surface dofs,
//   s^2 = (base + reference) / (base + max(now, reference)) <= 1,
// base the dof's stiffness without contact, reference and now its contact
// diagonal at the refresh and here: symmetric, 1 wherever the barrier has
// not stiffened, and on a dof the barrier dominates, its step is cut by the
// stiffening as a refreshed P^-1 would cut it.
template <class Real>
DESCENT_HOST_DEVICE inline Real contact_scale(const ContactView<Real>& c, index_t s, int i,
                                              Real now) {
  const Real base = c.base[3 * s + i], reference = c.reference[3 * s + i];
  return std::sqrt((base + reference) / (base + (now > reference ? now : reference)));
}

// Adds the contact gradient at x to the assembled partials (every surface
// vertex, after the exchange: each sharer adds the same), and with width 6
// the dominant diagonal of its projected Hessian to the diagonal partials.
// `diag` (3 per vertex; may be null) is raised to at least the vertex
// curvature plus that diagonal, so that iterations between two refreshes
// never take a step longer than the barrier allows as it stiffens. With
// c.scale, each surface dof's scale for a fixed P^-1 (contact_scale).
template <class Exec, class Real>
void add_contact_gradient(Exec& exec, int stream, ContactView<Real> c, VertexData<Real> vd,
                          const Real* x, Real* partial, int width, Real* diag) {
  exec.for_each(
      stream, 0, c.num_vertices, DESCENT_LAMBDA(index_t s) {
        const ContactTerms<Real> t = contact_terms(c, s, x, vd.qt, false);
        const std::int64_t v = c.vertices[s];
        Real* p = partial + width * v;
        for (int i = 0; i < 3; ++i) {
          p[i] += t.grad[i];
          const Real d = dominant_diagonal(t.hess, i);
          if (width == 6) p[3 + i] += d;
          if (diag) {
            const Real least = dof_diagonal(vd.terms, vd.mass[v], d, Real(0));
            if (diag[3 * v + i] < least) diag[3 * v + i] = least;
          }
          if (c.scale) c.scale[3 * s + i] = contact_scale(c, s, i, d);
        }
      });
}

// c.reference <- the contact diagonal at x (at a refresh of P^-1).
template <class Exec, class Real>
void contact_reference(Exec& exec, int stream, ContactView<Real> c, const Real* x, const Real* qt) {
  exec.for_each(
      stream, 0, c.num_vertices, DESCENT_LAMBDA(index_t s) {
        const ContactTerms<Real> t = contact_terms(c, s, x, qt, false);
        for (int i = 0; i < 3; ++i) c.reference[3 * s + i] = dominant_diagonal(t.hess, i);
      });
}

// w <- S w on surface dofs (the scales of the last add_contact_gradient).
template <class Exec, class Real>
void apply_contact_scale(Exec& exec, int stream, ContactView<Real> c, Real* w) {
  exec.for_each(
      stream, 0, c.num_vertices, DESCENT_LAMBDA(index_t s) {
        const std::int64_t v = c.vertices[s];
        for (int i = 0; i < 3; ++i) w[3 * v + i] *= c.scale[3 * s + i];
      });
}

// Keeps every surface vertex's move from q to q_next outside the obstacles
// (kernels/obstacle_contact.hpp, guard_move, with kGapKept and kLeastGap).
// A vertex whose move needs no cut keeps q_next bit for bit.
template <class Exec, class Real>
void guard_moves(Exec& exec, int stream, ContactView<Real> c, const std::uint8_t* fixed,
                 const Real* q, Real* q_next) {
  exec.for_each(
      stream, 0, c.num_vertices, DESCENT_LAMBDA(index_t s) {
        const std::int64_t v = c.vertices[s];
        Real d[3], cut[3];
        for (int i = 0; i < 3; ++i) d[i] = cut[i] = q_next[3 * v + i] - q[3 * v + i];
        guard_move(c.obstacles, c.num_obstacles, q + 3 * v, kGapKept<Real>, kLeastGap<Real> * c.dh,
                   fixed[v], cut);
        if (cut[0] != d[0] || cut[1] != d[1] || cut[2] != d[2])
          for (int i = 0; i < 3; ++i) q_next[3 * v + i] = q[3 * v + i] + cut[i];
      });
}

// hp += H_contact p on the free dofs of every surface vertex, H the exact
// contact Hessian at x (Lanczos' products).
template <class Exec, class Real>
void add_contact_hessian_product(Exec& exec, int stream, ContactView<Real> c, VertexData<Real> vd,
                                 const Real* x, const Real* p, Real* hp) {
  exec.for_each(
      stream, 0, c.num_vertices, DESCENT_LAMBDA(index_t s) {
        const ContactTerms<Real> t = contact_terms(c, s, x, vd.qt, true);
        const std::int64_t v = c.vertices[s];
        for (int i = 0; i < 3; ++i)
          if (!held(vd.fixed, 3 * v + i))
            hp[3 * v + i] += t.hess[3 * i] * p[3 * v] + t.hess[3 * i + 1] * p[3 * v + 1] +
                             t.hess[3 * i + 2] * p[3 * v + 2];
      });
}

// The projected contact Hessian blocks of owned surface vertices added to
// their diagonal blocks (9 values each at diagonal_slots[v]) of an assembled
// operator, held rows and columns left out.
template <class Exec, class Real>
void add_contact_blocks(Exec& exec, int stream, ContactView<Real> c, const std::uint8_t* fixed,
                        const Real* x, const Real* qt, const index_t* diagonal_slots,
                        Real* values) {
  exec.for_each(
      stream, 0, c.num_owned, DESCENT_LAMBDA(index_t s) {
        const ContactTerms<Real> t = contact_terms(c, s, x, qt, false);
        const std::int64_t v = c.vertices[s];
        Real* block = values + 9 * static_cast<std::int64_t>(diagonal_slots[v]);
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j)
            if (!held(fixed, 3 * v + i) && !held(fixed, 3 * v + j))
              block[3 * i + j] += t.hess[3 * i + j];
      });
}

// This rank's contact energy at x over its owned surface vertices, with
// magnitudes (every term is >= 0). Evaluated in double whatever Real, as
// loops::local_energy's terms are (kernels/in_double.hpp): a float run's
// checks judge a resting body's barrier free of float's round-off too. The
// terms are vertex_contact's, obstacle by obstacle in its order, so a double
// run sums them as it did before.
template <class Exec, class Real>
Sum2 contact_energy(Exec& exec, int stream, ContactView<Real> c, const Real* x, const Real* qt) {
  return exec.reduce(
      stream, c.num_owned, DESCENT_LAMBDA(index_t s)->Sum2 {
        const std::int64_t v = c.vertices[s];
        const double xs[3] = {x[3 * v], x[3 * v + 1], x[3 * v + 2]};
        const double ts[3] = {qt[3 * v], qt[3 * v + 1], qt[3 * v + 2]};
        const FrictionLag<Real>* lags = c.lags + static_cast<std::int64_t>(c.num_obstacles) * s;
        ContactTerms<double> terms;
        for (int k = 0; k < c.num_obstacles; ++k) {
          add_barrier(in_double(c.obstacles[k]), static_cast<double>(c.kappa[s]),
                      static_cast<double>(c.dh), xs, false, terms);
          add_friction(in_double(lags[k]), static_cast<double>(c.eps_h), xs, ts, false, terms);
        }
        return {terms.energy, terms.energy};
      });
}

}  // namespace loops
}  // namespace descent
