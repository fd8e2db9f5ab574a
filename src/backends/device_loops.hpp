#pragma once
// The launches of the device stepper, written once over any execution
// (backends/exec_host.hpp, kernels/cuda/exec_cuda.cuh). Each body only loads
// and stores; the physics is the inline math of src/kernels, unchanged.
//
// Layout (all device memory, local numbering of partition/partition.hpp):
//   x, q, y, qt, force, floor, diag: 3 reals per vertex, xyz-interleaved
//   tets: 4 local vertex ids per tet; rest: one TetRest per tet
//   corner values (gather): 12 reals per tet, corner a of tet t at [12 t + 3 a, +3)
//   partial: `width` reals per vertex, gradient xyz at [width v, +3) and,
//   with the Hessian diagonal (width 6), its xyz at [width v + 3, +3)
#include <cstdint>

#include "backends/exec_host.hpp"
#include "kernels/conversion.hpp"
#include "kernels/element.hpp"
#include "kernels/vertex.hpp"

// A body launched by an execution: host and device under nvcc.
#define DESCENT_LAMBDA [=] DESCENT_HOST_DEVICE

namespace descent::device {

template <class Real>
DESCENT_HOST_DEVICE inline TetCorners<Real> tet_corners(const Real* x, const index_t* tet) {
  TetCorners<Real> c;
  for (int a = 0; a < 4; ++a) {
    const Real* p = x + 3 * static_cast<std::int64_t>(tet[a]);
    c.x[a] = {p[0], p[1], p[2]};
  }
  return c;
}

// Where an element pass puts its per-corner results: the corner arrays
// (gather; `corner_diag` null without the diagonal) or, added atomically,
// the vertex partials (scatter; `partial` null in gather).
template <class Real>
struct ElementOut {
  Real* corner_grad = nullptr;
  Real* corner_diag = nullptr;
  Real* partial = nullptr;
  int width = 3;
};

// Gradient (and, when `with_diag`, the Hessian diagonal) of tets [begin,
// end). With conversion (Converting) each tet's interpolant is updated in
// place first (Eq. 17), as the CPU loops do.
template <bool Converting, class Exec, class Real, class Model>
void element_pass(Exec& exec, int stream, const Model& model, const Conversion<Real>& conv,
                  Real* interpolant, const Real* x, const index_t* tets, const TetRest<Real>* rest,
                  index_t begin, index_t end, bool with_diag, ElementOut<Real> out) {
  exec.for_each(
      stream, begin, end, DESCENT_LAMBDA(index_t t) {
        const index_t* tet = tets + 4 * static_cast<std::int64_t>(t);
        const TetCorners<Real> c = tet_corners(x, tet);
        Vec3<Real> g[4], d[4];
        if (Converting) {  // a constant: nvcc lambdas cannot first-capture under if constexpr
          converted_gradient(model, conv, interpolant[t], rest[t], c, g, with_diag ? d : nullptr);
        } else {
          element_gradient(model, rest[t], c, g);
          if (with_diag) element_hessian_diagonal(model, rest[t], c, d);
        }
        if (out.partial == nullptr) {
          Real* og = out.corner_grad + 12 * static_cast<std::int64_t>(t);
          for (int a = 0; a < 4; ++a) {
            og[3 * a] = g[a].x;
            og[3 * a + 1] = g[a].y;
            og[3 * a + 2] = g[a].z;
          }
          if (with_diag) {
            Real* od = out.corner_diag + 12 * static_cast<std::int64_t>(t);
            for (int a = 0; a < 4; ++a) {
              od[3 * a] = d[a].x;
              od[3 * a + 1] = d[a].y;
              od[3 * a + 2] = d[a].z;
            }
          }
          return;
        }
        for (int a = 0; a < 4; ++a) {
          Real* p = out.partial + static_cast<std::int64_t>(out.width) * tet[a];
          atomic_add(p, g[a].x);
          atomic_add(p + 1, g[a].y);
          atomic_add(p + 2, g[a].z);
          if (with_diag) {
            atomic_add(p + 3, d[a].x);
            atomic_add(p + 4, d[a].y);
            atomic_add(p + 5, d[a].z);
          }
        }
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

// Step length and Chebyshev weight of one iteration, read by the vertex
// update from device memory so a captured sequence is replayed with new values.
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
        if (vd.fixed[v] & (1u << axis)) {
          q_next[dof] = q[dof];
          return;
        }
        const Real g = dof_gradient(vd.terms, vd.mass[v], a[axis], q[dof], vd.y[dof], vd.qt[dof],
                                    vd.force[dof], axis);
        q_next[dof] =
            chebyshev_dof(q[dof], q_prev[dof], g, diag[dof], params->alpha, params->omega);
      });
}

// This rank's share of eps(q): element terms of all its tets plus the vertex
// terms of its owned vertices [0, num_owned), in double, with magnitudes.
// One reduction over both (index i: tet i and owned vertex i), so a check
// waits for the device once.
template <bool Converting, class Exec, class Real, class Model>
Sum2 local_energy(Exec& exec, int stream, const Model& model, const Conversion<Real>& conv,
                  const Real* interpolant, const Real* q, const index_t* tets,
                  const TetRest<Real>* rest, index_t num_tets, VertexData<Real> vd,
                  index_t num_owned) {
  const index_t n = num_tets > num_owned ? num_tets : num_owned;
  return exec.reduce(
      stream, n, DESCENT_LAMBDA(index_t i)->Sum2 {
        Sum2 s;
        if (i < num_tets) {
          const TetCorners<Real> c = tet_corners(q, tets + 4 * static_cast<std::int64_t>(i));
          double e;
          if (Converting)
            e = converted_energy(model, conv, interpolant[i], rest[i], c);
          else
            e = element_energy(model, rest[i], c);
          s.value = e;
          s.magnitude = e < 0 ? -e : e;
        }
        if (i < num_owned) {
          for (int axis = 0; axis < 3; ++axis) {
            const std::int64_t k = 3 * static_cast<std::int64_t>(i) + axis;
            const double term =
                dof_energy(vd.terms, vd.mass[i], q[k], vd.y[k], vd.qt[k], vd.force[k], axis);
            s.value += term;
            s.magnitude += term < 0 ? -term : term;
          }
        }
        return s;
      });
}

}  // namespace descent::device
