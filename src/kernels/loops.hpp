#pragma once
// The element and vertex loops, written once over any execution
// (kernels/execution.hpp): the Chebyshev engine of every backend, the local
// problem of the other methods and the Hessian products all launch these.
// Each body only loads and stores; the physics is the inline math of
// src/kernels, unchanged.
//
// Layout (the execution's memory, local numbering of partition/partition.hpp):
//   x, q, y, qt, p, force, floor, diag: 3 reals per vertex, xyz-interleaved
//   tets: 4 local vertex ids per tet; rest: one TetRest per tet
//   corner values (gather): 12 reals per tet, corner a of tet t at [12 t + 3 a, +3)
//   partial: `width` reals per vertex, gradient xyz at [width v, +3) and,
//   with the Hessian diagonal (width 6), its xyz at [width v + 3, +3)
#include <cstdint>
#include <limits>

#include "common/mesh.hpp"
#include "kernels/conversion.hpp"
#include "kernels/element.hpp"
#include "kernels/element_hessian_product.hpp"
#include "kernels/element_out.hpp"
#include "kernels/execution.hpp"
#include "kernels/in_double.hpp"
#include "kernels/vertex.hpp"
#if !defined(__CUDACC__)
#include "kernels/cpu/lane_models.hpp"
#endif

// A body launched by an execution: host and device under nvcc.
#define DESCENT_LAMBDA [=] DESCENT_HOST_DEVICE
// After the parameter list of the hottest body, the gather element pass of
// every CPU iteration: inlined into the host execution's loop, so the loop
// keeps its invariants in registers as a hand-written loop does (the body is
// too large for GCC to inline unasked). Measured with callgrind on the 41K
// helix: 4.2% fewer instructions per run; on every body it costs more (GCC
// then stops inlining the deformation gradient). nvcc inlines device code
// by itself.
#if defined(__CUDACC__)
#define DESCENT_INLINE_BODY
#else
#define DESCENT_INLINE_BODY __attribute__((always_inline))
#endif

namespace descent::loops {

template <class Real>
DESCENT_HOST_DEVICE inline TetCorners<Real> tet_corners(const Real* x, const index_t* tet) {
  TetCorners<Real> c;
  for (int a = 0; a < 4; ++a) {
    const Real* p = x + 3 * static_cast<std::int64_t>(tet[a]);
    c.x[a] = {p[0], p[1], p[2]};
  }
  return c;
}

// The corners of tet t of `tets` (4 local ids per tet).
template <class Real>
DESCENT_HOST_DEVICE inline TetCorners<Real> tet_corners(const Real* x, const index_t* tets,
                                                        index_t t) {
  return tet_corners(x, tets + 4 * static_cast<std::int64_t>(t));
}

// values[a] into the 12 corner reals of one tet at `out`.
template <class Real>
DESCENT_HOST_DEVICE inline void store_corners(const Vec3<Real> values[4], Real* out) {
  for (int a = 0; a < 4; ++a) {
    out[3 * a] = values[a].x;
    out[3 * a + 1] = values[a].y;
    out[3 * a + 2] = values[a].z;
  }
}

// One tet's per-corner results (and the diagonal's, with `diag`) to `out`.
template <class Real>
DESCENT_HOST_DEVICE inline void put_corners(const ElementOut<Real>& out, const index_t* tets,
                                            index_t t, const Vec3<Real> g[4],
                                            const Vec3<Real>* diag) {
  if (out.partial == nullptr) {
    store_corners(g, out.corner_grad + 12 * static_cast<std::int64_t>(t));
    if (diag) store_corners(diag, out.corner_diag + 12 * static_cast<std::int64_t>(t));
    return;
  }
  const index_t* tet = tets + 4 * static_cast<std::int64_t>(t);
  for (int a = 0; a < 4; ++a) {
    Real* p = out.partial + static_cast<std::int64_t>(out.width) * tet[a];
    add_to_partial(out, p, g[a].x);
    add_to_partial(out, p + 1, g[a].y);
    add_to_partial(out, p + 2, g[a].z);
    if (diag) {
      add_to_partial(out, p + 3, diag[a].x);
      add_to_partial(out, p + 4, diag[a].y);
      add_to_partial(out, p + 5, diag[a].z);
    }
  }
}

// One tet's gradient per corner, and its Hessian diagonal when `diag` is not
// null; with conversion (Converting) its interpolant is updated first (Eq. 17).
// `interpolant` holds one l per tet (read only with conversion).
template <bool Converting, class Real, class Model>
DESCENT_HOST_DEVICE inline void element_results(const Model& model, const Conversion<Real>& conv,
                                                Real* interpolant, index_t t,
                                                const TetRest<Real>& rest,
                                                const TetCorners<Real>& c, Vec3<Real> g[4],
                                                Vec3<Real>* diag) {
  if constexpr (Converting) {
    converted_gradient(model, conv, interpolant[t], rest, c, g, diag);
  } else {
    element_gradient(model, rest, c, g);
    if (diag) element_hessian_diagonal(model, rest, c, diag);
  }
}

// Gradient (and, when `with_diag`, the Hessian diagonal) of tets [begin,
// end). With conversion (Converting) each tet's interpolant is updated in
// place first (Eq. 17). Gather and scatter are separate loops, so neither
// tests the other's case per tet. On the host, a model that runs in lanes
// takes blocks of tets at once (kernels/cpu/lane_models.hpp), bitwise the
// same results.
template <bool Converting, class Exec, class Real, class Model>
void element_pass(Exec& exec, int stream, const Model& model, const Conversion<Real>& conv,
                  Real* interpolant, const Real* x, const index_t* tets, const TetRest<Real>* rest,
                  index_t begin, index_t end, bool with_diag, ElementOut<Real> out) {
#if !defined(__CUDACC__)
  if constexpr (Exec::kHostMemory && LaneModel<Model, kLaneWidth<Real>>) {
    element_pass_lanes<Converting, kLaneWidth<Real>>(exec, stream, model, conv, interpolant, x,
                                                     tets, rest, begin, end, with_diag, out);
    return;
  }
#endif
  if (out.partial == nullptr) {
    exec.for_each(
        stream, begin, end, DESCENT_LAMBDA(index_t t) DESCENT_INLINE_BODY {
          Vec3<Real> g[4], d[4];
          element_results<Converting>(model, conv, interpolant, t, rest[t], tet_corners(x, tets, t),
                                      g, with_diag ? d : nullptr);
          store_corners(g, out.corner_grad + 12 * static_cast<std::int64_t>(t));
          if (with_diag) store_corners(d, out.corner_diag + 12 * static_cast<std::int64_t>(t));
        });
    return;
  }
  exec.for_each(
      stream, begin, end, DESCENT_LAMBDA(index_t t) {
        Vec3<Real> g[4], d[4];
        element_results<Converting>(model, conv, interpolant, t, rest[t], tet_corners(x, tets, t),
                                    g, with_diag ? d : nullptr);
        put_corners(out, tets, t, g, with_diag ? d : nullptr);
      });
}

// The element Hessians at x applied to p, of tets [begin, end), into
// out.corner_grad (gather) or out.partial (scatter; width 3). With
// conversion the blend of Eq. 17 at each tet's stored interpolant, held
// constant as the gradient holds it (kernels/conversion.hpp).
template <bool Converting, class Exec, class Real, class Model>
void hessian_product_pass(Exec& exec, int stream, const Model& model, const Conversion<Real>& conv,
                          const Real* interpolant, const Real* x, const Real* p,
                          const index_t* tets, const TetRest<Real>* rest, index_t begin,
                          index_t end, ElementOut<Real> out) {
#if !defined(__CUDACC__)
  // On the host, a lane model in blocks of tets, bitwise the same products
  // (kernels/cpu/lane_models.hpp).
  if constexpr (Exec::kHostMemory && LaneModel<Model, kLaneWidth<Real>>) {
    hessian_product_pass_lanes<Converting, kLaneWidth<Real>>(exec, stream, model, conv, interpolant,
                                                             x, p, tets, rest, begin, end, out);
    return;
  }
#endif
  exec.for_each(
      stream, begin, end, DESCENT_LAMBDA(index_t t) {
        const TetCorners<Real> c = tet_corners(x, tets, t);
        const TetCorners<Real> pc = tet_corners(p, tets, t);
        Vec3<Real> hp[4];
        if (Converting)
          converted_hessian_product(model, conv, interpolant[t], rest[t], c, pc.x, hp);
        else
          element_hessian_product(model, rest[t], c, pc.x, hp);
        put_corners(out, tets, t, hp, static_cast<const Vec3<Real>*>(nullptr));
      });
}

// partial[width v + offset + i] = sum of the corner values listed for vertex
// v in the CSR table (corners 4 t + a, ascending), for v in [begin, end): a
// fixed order, so the result does not depend on the execution.
template <class Exec, class Real>
void gather_corners(Exec& exec, int stream, const index_t* offsets, const index_t* corner_ids,
                    index_t begin, index_t end, const Real* corner_values, Real* partial, int width,
                    int offset) {
  exec.for_each(
      stream, begin, end, DESCENT_LAMBDA(index_t v) {
        Real s0 = 0, s1 = 0, s2 = 0;
        for (index_t k = offsets[v]; k < offsets[v + 1]; ++k) {
          const Real* c = corner_values + 3 * static_cast<std::int64_t>(corner_ids[k]);
          s0 += c[0];
          s1 += c[1];
          s2 += c[2];
        }
        Real* o = partial + static_cast<std::int64_t>(width) * v + offset;
        o[0] = s0;
        o[1] = s1;
        o[2] = s2;
      });
}

// Per-vertex data of the fused vertex update, constant over a step.
template <class Real>
struct VertexData {
  const Real* mass;           // 1 per vertex
  const std::uint8_t* fixed;  // 1 per vertex, bit i: axis i held
  const Real* floor;          // 3 per vertex
  const Real* force;          // 3 per vertex
  const Real* y;              // 3 per vertex
  const Real* qt;             // 3 per vertex
  VertexTerms<Real> terms;
};

DESCENT_HOST_DEVICE inline bool held(const std::uint8_t* fixed, index_t dof) {
  return (fixed[dof / 3] & (1u << (dof % 3))) != 0;
}

// Step length and Chebyshev weight of one iteration, read by the vertex
// update from the execution's memory so a captured sequence is replayed
// with new values.
template <class Real>
struct IterationParams {
  Real alpha;
  Real omega;
};

// The fused vertex update over all dofs: the diagonal (when refreshed) from
// the assembled partials, the descent direction, Chebyshev, fixed axes held.
template <class Exec, class Real>
void vertex_update(Exec& exec, int stream, index_t num_dofs, VertexData<Real> vd,
                   const Real* partial, int width, bool refresh, Real* diag, const Real* q,
                   const Real* q_prev, Real* q_next, const IterationParams<Real>* params) {
  exec.for_each(
      stream, 0, num_dofs, DESCENT_LAMBDA(index_t dof) {
        const index_t v = dof / 3;
        const int axis = static_cast<int>(dof % 3);
        const Real* a = partial + static_cast<std::int64_t>(width) * v;
        if (refresh) diag[dof] = dof_diagonal(vd.terms, vd.mass[v], a[3 + axis], vd.floor[dof]);
        if (held(vd.fixed, dof)) {
          q_next[dof] = q[dof];
          return;
        }
        const Real g = dof_gradient(vd.terms, vd.mass[v], a[axis], q[dof], vd.y[dof], vd.qt[dof],
                                    vd.force[dof], axis);
        q_next[dof] =
            chebyshev_dof(q[dof], q_prev[dof], g, diag[dof], params->alpha, params->omega);
      });
}

// The full gradient of eps per dof from assembled elastic partials (width
// 3), 0 on held dofs: what a preconditioner other than Jacobi's is applied to.
template <class Exec, class Real>
void gradient_dofs(Exec& exec, int stream, index_t num_dofs, VertexData<Real> vd,
                   const Real* partial, const Real* q, Real* g) {
  exec.for_each(
      stream, 0, num_dofs, DESCENT_LAMBDA(index_t dof) {
        const index_t v = dof / 3;
        g[dof] =
            held(vd.fixed, dof)
                ? Real(0)
                : dof_gradient(vd.terms, vd.mass[v],
                               partial[3 * static_cast<std::int64_t>(v) + dof % 3], q[dof],
                               vd.y[dof], vd.qt[dof], vd.force[dof], static_cast<int>(dof % 3));
      });
}

// The Chebyshev update along a preconditioned direction dq = P^-1 g (0 on
// held dofs): q_next = omega (q - alpha dq - q_prev) + q_prev, held dofs kept.
template <class Exec, class Real>
void preconditioned_update(Exec& exec, int stream, index_t num_dofs, const std::uint8_t* fixed,
                           const Real* dq, const Real* q, const Real* q_prev, Real* q_next,
                           const IterationParams<Real>* params) {
  exec.for_each(
      stream, 0, num_dofs, DESCENT_LAMBDA(index_t dof) {
        q_next[dof] = held(fixed, dof) ? q[dof]
                                       : chebyshev_dof(q[dof], q_prev[dof], dq[dof], Real(1),
                                                       params->alpha, params->omega);
      });
}

// The Hessian diagonal alone from assembled partials (width 6), as the
// refreshing vertex update computes it.
template <class Exec, class Real>
void diagonal_update(Exec& exec, int stream, index_t num_dofs, VertexData<Real> vd,
                     const Real* partial, Real* diag) {
  exec.for_each(
      stream, 0, num_dofs, DESCENT_LAMBDA(index_t dof) {
        const index_t v = dof / 3;
        diag[dof] =
            dof_diagonal(vd.terms, vd.mass[v],
                         partial[6 * static_cast<std::int64_t>(v) + 3 + dof % 3], vd.floor[dof]);
      });
}

// The Hessian of eps applied to p from the assembled elastic part (width 3):
// hp = elastic + m (1/h^2 + c/h) p on free dofs, 0 on held ones. Returns
// p . hp over owned dofs [0, num_owned_dofs) (in double).
template <class Exec, class Real>
double hessian_vertex_terms(Exec& exec, int stream, index_t num_dofs, index_t num_owned_dofs,
                            VertexData<Real> vd, const Real* elastic, const Real* p, Real* hp) {
  return exec
      .reduce(
          stream, num_dofs,
          DESCENT_LAMBDA(index_t dof)->Sum2 {
            const Real curvature = dof_diagonal(vd.terms, vd.mass[dof / 3], Real(0), Real(0));
            const Real value = held(vd.fixed, dof) ? Real(0) : elastic[dof] + curvature * p[dof];
            hp[dof] = value;
            return {dof < num_owned_dofs ? static_cast<double>(p[dof]) * value : 0.0, 0.0};
          })
      .value;
}

// The Rayleigh quotient's parts of a rigid translation along `axis` with
// the elastic term left out (a translation strains nothing but the held
// boundary): the sums over owned free dofs of that axis of the vertex terms'
// curvature m (1/h^2 + c/h) and of the diagonal d.
template <class Exec, class Real>
Sum2 translation_sums(Exec& exec, int stream, index_t num_owned, VertexData<Real> vd,
                      const Real* diag, int axis) {
  return exec.reduce(
      stream, num_owned, DESCENT_LAMBDA(index_t v)->Sum2 {
        const index_t dof = 3 * v + axis;
        if (held(vd.fixed, dof)) return {0.0, 0.0};
        return {static_cast<double>(dof_diagonal(vd.terms, vd.mass[v], Real(0), Real(0))),
                static_cast<double>(diag[dof])};
      });
}

// The vector operations of a Lanczos step (solver/spectrum.hpp) on vectors
// of 3 reals per vertex, D the iteration's diagonal.
// w = 0 on held dofs.
template <class Exec, class Real>
void zero_held(Exec& exec, int stream, index_t num_dofs, const std::uint8_t* fixed, Real* w) {
  exec.for_each(
      stream, 0, num_dofs, DESCENT_LAMBDA(index_t dof) {
        if (held(fixed, dof)) w[dof] = 0;
      });
}

// sum over dofs [0, num_dofs) of w d w (in double; `magnitude` unused).
template <class Exec, class Real>
double weighted_norm2(Exec& exec, int stream, index_t num_dofs, const Real* d, const Real* w) {
  return exec
      .reduce(
          stream, num_dofs,
          DESCENT_LAMBDA(index_t dof)->Sum2 {
            return {static_cast<double>(w[dof]) * d[dof] * w[dof], 0.0};
          })
      .value;
}

// v_prev <- v, v <- w / beta.
template <class Exec, class Real>
void lanczos_advance(Exec& exec, int stream, index_t num_dofs, Real inv_beta, const Real* w,
                     Real* v, Real* v_prev) {
  exec.for_each(
      stream, 0, num_dofs, DESCENT_LAMBDA(index_t dof) {
        v_prev[dof] = v[dof];
        v[dof] = w[dof] * inv_beta;
      });
}

// w <- D^-1 y - alpha v - beta_prev v_prev (the Lanczos three-term step).
template <class Exec, class Real>
void lanczos_residual(Exec& exec, int stream, index_t num_dofs, const Real* y, const Real* d,
                      const Real* v, const Real* v_prev, Real alpha, Real beta_prev, Real* w) {
  exec.for_each(
      stream, 0, num_dofs, DESCENT_LAMBDA(index_t dof) {
        w[dof] = y[dof] / d[dof] - alpha * v[dof] - beta_prev * v_prev[dof];
      });
}

// Lanczos on P^-1 H for a preconditioner P^-1 other than D^-1: the
// residual-space vectors u (u = P v) travel beside the solution-space v.
// u_prev <- u, u <- s / beta; v <- z / beta (z = P^-1 s).
template <class Exec, class Real>
void lanczos_advance_preconditioned(Exec& exec, int stream, index_t num_dofs, Real inv_beta,
                                    const Real* s, const Real* z, Real* u, Real* u_prev, Real* v) {
  exec.for_each(
      stream, 0, num_dofs, DESCENT_LAMBDA(index_t dof) {
        u_prev[dof] = u[dof];
        u[dof] = s[dof] * inv_beta;
        v[dof] = z[dof] * inv_beta;
      });
}

// s <- y - alpha u - beta_prev u_prev (the three-term step in residual space).
template <class Exec, class Real>
void lanczos_residual_preconditioned(Exec& exec, int stream, index_t num_dofs, const Real* y,
                                     const Real* u, const Real* u_prev, Real alpha, Real beta_prev,
                                     Real* s) {
  exec.for_each(
      stream, 0, num_dofs,
      DESCENT_LAMBDA(index_t dof) { s[dof] = y[dof] - alpha * u[dof] - beta_prev * u_prev[dof]; });
}

// sum over dofs [0, num_dofs) of a b (in double).
template <class Exec, class Real>
double inner_product(Exec& exec, int stream, index_t num_dofs, const Real* a, const Real* b) {
  return exec
      .reduce(
          stream, num_dofs,
          DESCENT_LAMBDA(index_t dof)->Sum2 {
            return {static_cast<double>(a[dof]) * b[dof], 0.0};
          })
      .value;
}

// This rank's share of eps(q): element terms of all its tets plus the vertex
// terms of its owned vertices [0, num_owned), with magnitudes. Evaluated in
// double whatever Real (kernels/in_double.hpp): a float run's checks judge
// its float iterates by their energy free of float's round-off. One
// reduction over both (index i: tet i and owned vertex i), so a check waits
// for the execution once.
//
// The magnitude also holds the resolution of states in Real. Two states
// each within one unit in the last place (at most eps_Real |q_k|) of a
// third differ by up to two in each free dof, which changes eps by about
// R = 1/2 sum_k d_k (2 eps_Real q_k)^2, with d_k `curvature` (3 per vertex,
// the Hessian diagonal at rest). A float iterate at its floor moves between
// such states from check to check: a change within R is float's, not the
// descent's, and no error below R can be vouched for. Measured on the small
// helix against Newton in double (tests/mpi/test_mixed_precision.cpp), the
// floor lies at 0.1 R/4 with the multilevel preconditioner (the rounding of
// the minimum, about R/48) and at 0.35-0.6 R/4 with Jacobi's and Nesterov,
// whose updates below half a unit are lost. R is a bound already, so it
// joins the magnitude divided by the round-off multiple (kRoundoffEpsilons
// double epsilons per unit, kernels/in_double.hpp); multiplied by it, R
// grew with the rest stiffness (as 1/dx^2) to above a 1e-3 target at 82K
// tets.
//
// On the host, a model that runs in lanes (kernels/cpu/lane_models.hpp)
// first computes its tets' energies in blocks into `tet_energy` (num_tets
// doubles; may be null elsewhere), bitwise the values of the loop below,
// which then sums them in the same order: the same energy, without a scalar
// cube root per tet in double.
template <bool Converting, class Exec, class Real, class Model>
Sum2 local_energy(Exec& exec, int stream, const Model& model, const Conversion<Real>& conv,
                  const Real* interpolant, const Real* q, const index_t* tets,
                  const TetRest<Real>* rest, index_t num_tets, VertexData<Real> vd,
                  const Real* curvature, index_t num_owned, double* tet_energy) {
  const index_t n = num_tets > num_owned ? num_tets : num_owned;
  constexpr double kStateResolution =
      2 * std::numeric_limits<Real>::epsilon() *
      (std::numeric_limits<Real>::epsilon() / std::numeric_limits<double>::epsilon()) /
      kRoundoffEpsilons;
  const auto wide_model = in_double(model);
  const Conversion<double> wide_conv = in_double(conv);
  const VertexTerms<double> terms = in_double(vd.terms);
  const double* energies = nullptr;
#if !defined(__CUDACC__)
  if constexpr (Exec::kHostMemory && LaneModel<decltype(wide_model), kLaneWidth<double>>) {
    if (tet_energy) {
      element_energies_lanes<Converting, kLaneWidth<double>>(
          exec, stream, wide_model, wide_conv, interpolant, q, tets, rest, num_tets, tet_energy);
      energies = tet_energy;
    }
  }
#endif
  return exec.reduce(
      stream, n, DESCENT_LAMBDA(index_t i)->Sum2 {
        Sum2 s;
        if (i < num_tets) {
          double e;
          if (energies) {
            e = energies[i];
          } else {
            const TetCorners<double> c = in_double(tet_corners(q, tets, i));
            const TetRest<double> r = in_double(rest[i]);
            e = Converting ? converted_energy(wide_model, wide_conv,
                                              static_cast<double>(interpolant[i]), r, c)
                           : element_energy(wide_model, r, c);
          }
          s.value = e;
          s.magnitude = e < 0 ? -e : e;
        }
        if (i < num_owned) {
          for (int axis = 0; axis < 3; ++axis) {
            const std::int64_t k = 3 * static_cast<std::int64_t>(i) + axis;
            const double term =
                dof_energy<double>(terms, vd.mass[i], q[k], vd.y[k], vd.qt[k], vd.force[k], axis);
            s.value += term;
            s.magnitude += term < 0 ? -term : term;
            if (!held(vd.fixed, k)) {
              const double qk = q[k];
              s.magnitude += kStateResolution * static_cast<double>(curvature[k]) * qk * qk;
            }
          }
        }
        return s;
      });
}

}  // namespace descent::loops
