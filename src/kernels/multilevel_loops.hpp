#pragma once
// The loops of the multilevel preconditioner (solver/preconditioners/
// multilevel/), written once over any execution (kernels/execution.hpp) like
// kernels/loops.hpp: the assembly of the finest level's operator from the
// PSD-projected element Hessians, and the V-cycle's block products,
// Chebyshev-Jacobi smoother updates, restriction and prolongation.
//
// Layout (the execution's memory):
//   level vectors: `block` reals per node (3 at the finest level: xyz of a
//     vertex; 6 above: a rigid motion, translation then rotation)
//   operators: block CSR over a level's local nodes (offsets per row,
//     columns per block, block * block values per block, row-major)
//   prolongation P from level l + 1 to level l: block CSR over level l's
//     nodes, blocks fine_block x 6; its transpose as per-coarse-node lists
//     of (fine node, slot of P)
//   tet_slots: 16 per tet, the slot of block (corner a, corner b) at
//     [16 t + 4 a + b] in the finest operator
#include <cstdint>

#include "common/mesh.hpp"
#include "kernels/conversion.hpp"
#include "kernels/element_hessian.hpp"
#include "kernels/execution.hpp"
#include "kernels/loops.hpp"
#include "kernels/vertex.hpp"

namespace descent::loops {

// Adds one tet's element Hessian h (layout of element_hessian.hpp) to the
// finest operator's blocks at its tet_slots, held dofs' rows and columns
// left out.
template <class Real>
DESCENT_HOST_DEVICE inline void add_element_blocks(Real h[144], const index_t* tet,
                                                   const index_t* slots, const std::uint8_t* fixed,
                                                   Real* values) {
  // Held dofs' rows and columns zeroed first (most tets have none).
  if (fixed[tet[0]] | fixed[tet[1]] | fixed[tet[2]] | fixed[tet[3]])
    for (int i = 0; i < 12; ++i)
      if (held(fixed, 3 * tet[i / 3] + i % 3))
        for (int j = 0; j < 12; ++j) h[12 * i + j] = h[12 * j + i] = 0;
  for (int a = 0; a < 4; ++a)
    for (int b = 0; b < 4; ++b) {
      Real* block = values + 9 * static_cast<std::int64_t>(slots[4 * a + b]);
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) block[3 * i + j] += h[(3 * a + i) * 12 + 3 * b + j];
    }
}

// Whether all 81 entries of dP/dF are finite (per lane on lanes).
template <class Real>
DESCENT_HOST_DEVICE inline MaskOf<Real> finite_entries(const Real dpdf[81]) {
  MaskOf<Real> finite = Real(0) < Real(1);
  for (int e = 0; e < 81; ++e) finite = finite & (dpdf[e] - dpdf[e] == Real(0));
  return finite;
}

#if !defined(__CUDACC__)
// The host's add_element_hessians for a model that runs in lanes: blocks of
// W tets of order[begin, end) take dP/dF, its projection and the contraction
// in lanes (kernels/cpu/lane_models.hpp, bitwise each tet's own), then each
// lane's Hessian is added as one tet's is.
template <bool Converting, int W, class Exec, class Real, class Model>
void add_element_hessians_lanes(Exec& exec, int stream, const Model& model,
                                const Conversion<Real>& conv, const Real* interpolant,
                                const Real* x, const index_t* tets, const TetRest<Real>* rest,
                                const index_t* order, index_t begin, index_t end,
                                const index_t* tet_slots, const std::uint8_t* fixed, Real* values) {
  using L = Lanes<Real, W>;
  const auto lanes = lane_model<W>(model);
  const auto lane_conv = lane_conversion<W>(conv);
  for_each_block<W>(exec, stream, begin, end, [=](index_t first, int count) {
    const BlockTets<W> ids = block_tets<W>(first, count, order);
    TetCorners<L> c;
    TetRest<L> r;
    load_lanes<W>(x, tets, rest, ids, c, r);
    const Mat3<L> f = deformation_gradient(c.x[0], c.x[1], c.x[2], c.x[3], r.dm_inv);
    L dpdf[81];
    if constexpr (Converting)
      converted_preconditioner_dpdf(lanes, lane_conv, load_values<W, Real>(interpolant, ids), f,
                                    dpdf);
    else
      lanes.stress_derivative(f, dpdf);
    const auto finite = finite_entries(dpdf);
    project_isotropic_psd(f, dpdf);
    L h[144];
    contract_stress_derivative(dpdf, r, h);
    for (int l = 0; l < count; ++l) {
      if (!finite.bits[l]) continue;
      Real lane_h[144];
      for (int e = 0; e < 144; ++e) lane_h[e] = h[e].v[l];
      const index_t t = ids.t[l];
      add_element_blocks(lane_h, tets + 4 * static_cast<std::int64_t>(t),
                         tet_slots + 16 * static_cast<std::int64_t>(t), fixed, values);
    }
  });
}
#endif

// Adds the PSD-projected element Hessians of tets order[begin, end) at x to
// the finest operator, held dofs' rows and columns left out. No two of
// these tets may share a vertex (one colour of the set-up's colouring), so
// no two threads add to one block and the sum is the same on every thread
// count. With conversion, Eq. 19's blend at the interpolant the tet's next
// gradient takes. An element whose Hessian is not finite (a crushed tet of
// a model that overflows there) adds nothing: one element's curvature left
// out costs the V-cycle little, a NaN in the operator everything. On the
// host a model that runs in lanes takes blocks of tets at once
// (add_element_hessians_lanes), bitwise the same sums.
template <bool Converting, class Exec, class Real, class Model>
void add_element_hessians(Exec& exec, int stream, const Model& model, const Conversion<Real>& conv,
                          const Real* interpolant, const Real* x, const index_t* tets,
                          const TetRest<Real>* rest, const index_t* order, index_t begin,
                          index_t end, const index_t* tet_slots, const std::uint8_t* fixed,
                          Real* values) {
#if !defined(__CUDACC__)
  if constexpr (Exec::kHostMemory && LaneModel<Model, kLaneWidth<Real>>) {
    add_element_hessians_lanes<Converting, kLaneWidth<Real>>(exec, stream, model, conv, interpolant,
                                                             x, tets, rest, order, begin, end,
                                                             tet_slots, fixed, values);
    return;
  }
#endif
  exec.for_each(
      stream, begin, end, DESCENT_LAMBDA(index_t k) {
        const index_t t = order[k];
        const TetCorners<Real> c = tet_corners(x, tets, t);
        const Mat3<Real> f = deformation_gradient(c.x[0], c.x[1], c.x[2], c.x[3], rest[t].dm_inv);
        Real dpdf[81];
        // Not `if constexpr`: nvcc's extended lambdas cannot first capture
        // inside one.
        if (Converting)
          converted_preconditioner_dpdf(model, conv, interpolant[t], f, dpdf);
        else
          model.stress_derivative(f, dpdf);
        if (!finite_entries(dpdf)) return;
        project_isotropic_psd(f, dpdf);
        Real h[144];
        contract_stress_derivative(dpdf, rest[t], h);
        add_element_blocks(h, tets + 4 * static_cast<std::int64_t>(t),
                           tet_slots + 16 * static_cast<std::int64_t>(t), fixed, values);
      });
}

// The vertex terms' curvature m (1/h^2 + c/h) on the free diagonal entries
// of owned vertices [0, num_owned) (each vertex counted by one rank).
template <class Exec, class Real>
void add_vertex_curvature(Exec& exec, int stream, index_t num_owned, VertexTerms<Real> terms,
                          const Real* mass, const std::uint8_t* fixed,
                          const index_t* diagonal_slots, Real* values) {
  exec.for_each(
      stream, 0, num_owned, DESCENT_LAMBDA(index_t v) {
        const Real curvature = dof_diagonal(terms, mass[v], Real(0), Real(0));
        Real* block = values + 9 * static_cast<std::int64_t>(diagonal_slots[v]);
        for (int i = 0; i < 3; ++i)
          if (!held(fixed, 3 * v + i)) block[4 * i] += curvature;
      });
}

// `diagonal` (3 per vertex) on the free diagonal entries of owned vertices
// [0, num_owned): terms each sharer of a vertex evaluates alike.
template <class Exec, class Real>
void add_owned_diagonal(Exec& exec, int stream, index_t num_owned, const Real* diagonal,
                        const std::uint8_t* fixed, const index_t* diagonal_slots, Real* values) {
  exec.for_each(
      stream, 0, num_owned, DESCENT_LAMBDA(index_t v) {
        Real* block = values + 9 * static_cast<std::int64_t>(diagonal_slots[v]);
        for (int i = 0; i < 3; ++i)
          if (!held(fixed, 3 * v + i)) block[4 * i] += diagonal[3 * v + i];
      });
}

// y = A x on rows [begin, end) (this rank's partial rows).
template <int B, class Exec, class Real>
void block_product(Exec& exec, int stream, index_t begin, index_t end, const index_t* offsets,
                   const index_t* columns, const Real* values, const Real* x, Real* y) {
  exec.for_each(
      stream, begin, end, DESCENT_LAMBDA(index_t r) {
        Real out[B];
        for (int i = 0; i < B; ++i) out[i] = 0;
        for (index_t s = offsets[r]; s < offsets[r + 1]; ++s) {
          const Real* a = values + B * B * static_cast<std::int64_t>(s);
          const Real* in = x + B * static_cast<std::int64_t>(columns[s]);
          for (int i = 0; i < B; ++i)
            for (int j = 0; j < B; ++j) out[i] += a[B * i + j] * in[j];
        }
        for (int i = 0; i < B; ++i) y[B * static_cast<std::int64_t>(r) + i] = out[i];
      });
}

// The Chebyshev-Jacobi smoother's updates over n unknowns (D^-1 = inv, 0 on
// unknowns that carry nothing). From x = 0: r = b, d = c inv r, x = d.
template <class Exec, class Real>
void smoother_start(Exec& exec, int stream, index_t n, const Real* b, const Real* inv, Real c,
                    Real* r, Real* d, Real* x) {
  exec.for_each(
      stream, 0, n, DESCENT_LAMBDA(index_t k) {
        r[k] = b[k];
        d[k] = c * inv[k] * b[k];
        x[k] = d[k];
      });
}

// From a given x with y = A x: r = b - y, d = c inv r, x += d.
template <class Exec, class Real>
void smoother_restart(Exec& exec, int stream, index_t n, const Real* b, const Real* y,
                      const Real* inv, Real c, Real* r, Real* d, Real* x) {
  exec.for_each(
      stream, 0, n, DESCENT_LAMBDA(index_t k) {
        r[k] = b[k] - y[k];
        d[k] = c * inv[k] * r[k];
        x[k] += d[k];
      });
}

// With y = A d: r -= y, d = c1 d + c2 inv r, x += d.
template <class Exec, class Real>
void smoother_step(Exec& exec, int stream, index_t n, const Real* y, const Real* inv, Real c1,
                   Real c2, Real* r, Real* d, Real* x) {
  exec.for_each(
      stream, 0, n, DESCENT_LAMBDA(index_t k) {
        r[k] -= y[k];
        d[k] = c1 * d[k] + c2 * inv[k] * r[k];
        x[k] += d[k];
      });
}

// r -= y.
template <class Exec, class Real>
void subtract(Exec& exec, int stream, index_t n, const Real* y, Real* r) {
  exec.for_each(
      stream, 0, n, DESCENT_LAMBDA(index_t k) { r[k] -= y[k]; });
}

// b_c[I] = sum of P_vI^T r[v] over the owned fine nodes v < num_owned of
// P's column I (each fine node counted by one rank): this rank's partial
// sum. The lists ascend, so owned nodes come first.
template <int FB, class Exec, class Real>
void restrict_owned(Exec& exec, int stream, index_t num_coarse, const index_t* t_offsets,
                    const index_t* t_rows, const index_t* t_slots, index_t num_owned,
                    const Real* p_values, const Real* r, Real* b_c) {
  exec.for_each(
      stream, 0, num_coarse, DESCENT_LAMBDA(index_t c) {
        Real out[6] = {0, 0, 0, 0, 0, 0};
        for (index_t k = t_offsets[c]; k < t_offsets[c + 1]; ++k) {
          const index_t v = t_rows[k];
          if (v >= num_owned) break;
          const Real* p = p_values + 6 * FB * static_cast<std::int64_t>(t_slots[k]);
          const Real* in = r + FB * static_cast<std::int64_t>(v);
          for (int i = 0; i < FB; ++i)
            for (int j = 0; j < 6; ++j) out[j] += p[6 * i + j] * in[i];
        }
        for (int j = 0; j < 6; ++j) b_c[6 * static_cast<std::int64_t>(c) + j] = out[j];
      });
}

// The same sums row by row on one thread: b_c zeroed, then each owned fine
// row adds its blocks in ascending row order, so every coarse node receives
// its terms in the order restrict_owned adds them (the same bits), reading
// P in its own order rather than through the transpose's indirection (3-4x
// faster on the host).
template <int FB, class Real>
void restrict_owned_serial(index_t num_coarse, const index_t* offsets, const index_t* columns,
                           index_t num_owned, const Real* p_values, const Real* r, Real* b_c) {
  for (std::int64_t k = 0; k < 6 * static_cast<std::int64_t>(num_coarse); ++k) b_c[k] = 0;
  for (index_t v = 0; v < num_owned; ++v) {
    const Real* in = r + FB * static_cast<std::int64_t>(v);
    for (index_t s = offsets[v]; s < offsets[v + 1]; ++s) {
      const Real* p = p_values + 6 * FB * static_cast<std::int64_t>(s);
      Real* out = b_c + 6 * static_cast<std::int64_t>(columns[s]);
      for (int j = 0; j < 6; ++j) {
        Real sum = out[j];
        for (int i = 0; i < FB; ++i) sum += p[6 * i + j] * in[i];
        out[j] = sum;
      }
    }
  }
}

// x[v] += sum_I P_vI x_c[I] for every fine node v < n.
template <int FB, class Exec, class Real>
void prolong_add(Exec& exec, int stream, index_t n, const index_t* offsets, const index_t* columns,
                 const Real* p_values, const Real* x_c, Real* x) {
  exec.for_each(
      stream, 0, n, DESCENT_LAMBDA(index_t v) {
        Real out[FB];
        for (int i = 0; i < FB; ++i) out[i] = 0;
        for (index_t s = offsets[v]; s < offsets[v + 1]; ++s) {
          const Real* p = p_values + 6 * FB * static_cast<std::int64_t>(s);
          const Real* in = x_c + 6 * static_cast<std::int64_t>(columns[s]);
          for (int i = 0; i < FB; ++i)
            for (int j = 0; j < 6; ++j) out[i] += p[6 * i + j] * in[j];
        }
        for (int i = 0; i < FB; ++i) x[FB * static_cast<std::int64_t>(v) + i] += out[i];
      });
}

}  // namespace descent::loops
