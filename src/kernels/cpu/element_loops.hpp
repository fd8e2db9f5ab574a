#pragma once
// CPU (OpenMP) loops over element and vertex ranges. They call the inline
// math of kernels/element.hpp and are the oracle for other backends.
//
// Layout: x is xyz-interleaved local positions (3 per vertex); tets holds 4
// local vertex ids per tet; rest one TetRest per tet. Per-corner outputs are
// 12 reals per tet: corner a of tet t at [12 t + 3 a, +3). Scatter to
// vertices is a deterministic gather over a vertex -> (4 t + a) table, so the
// result does not depend on the thread count.
#include <cstdint>

#include "common/mesh.hpp"
#include "kernels/conversion.hpp"
#include "kernels/element.hpp"

namespace descent::cpu {

template <class Real>
inline TetCorners<Real> load_corners(const Real* x, const index_t* tet) {
  TetCorners<Real> c;
  for (int a = 0; a < 4; ++a) {
    const Real* p = x + 3 * static_cast<std::int64_t>(tet[a]);
    c.x[a] = {p[0], p[1], p[2]};
  }
  return c;
}

template <class Real>
inline void store_corners(const Vec3<Real> values[4], Real* out) {
  for (int a = 0; a < 4; ++a) {
    out[3 * a] = values[a].x;
    out[3 * a + 1] = values[a].y;
    out[3 * a + 2] = values[a].z;
  }
}

// Per-corner gradients of tets [begin, end), and Hessian diagonals too when
// `diag_out` is not null (one pass, F computed once per tet).
template <class Real, class Model>
void element_gradients(const Model& model, const Real* x, const index_t* tets,
                       const TetRest<Real>* rest, index_t begin, index_t end, Real* grad_out,
                       Real* diag_out) {
#pragma omp parallel for schedule(static)
  for (index_t t = begin; t < end; ++t) {
    const TetCorners<Real> c = load_corners(x, tets + 4 * static_cast<std::int64_t>(t));
    Vec3<Real> g[4];
    element_gradient(model, rest[t], c, g);
    store_corners(g, grad_out + 12 * static_cast<std::int64_t>(t));
    if (diag_out) {
      Vec3<Real> d[4];
      element_hessian_diagonal(model, rest[t], c, d);
      store_corners(d, diag_out + 12 * static_cast<std::int64_t>(t));
    }
  }
}

// Sum of V_e Psi(F_e) over tets [begin, end), and the sum of the terms'
// magnitudes (the scale of its round-off), accumulated in double.
struct EnergySum {
  double value = 0;
  double magnitude = 0;
};

template <class Real, class Model>
EnergySum element_energy_sum(const Model& model, const Real* x, const index_t* tets,
                             const TetRest<Real>* rest, index_t begin, index_t end) {
  double value = 0, magnitude = 0;
#pragma omp parallel for schedule(static) reduction(+ : value, magnitude)
  for (index_t t = begin; t < end; ++t) {
    const double e =
        element_energy(model, rest[t], load_corners(x, tets + 4 * static_cast<std::int64_t>(t)));
    value += e;
    magnitude += e < 0 ? -e : e;
  }
  return {value, magnitude};
}

// element_gradients with invertible model conversion: `interpolant` holds
// one l per tet, updated in place (Eq. 17) before the hybrid gradient.
template <class Real, class Model>
void converted_element_gradients(const Model& model, const Conversion<Real>& conv,
                                 Real* interpolant, const Real* x, const index_t* tets,
                                 const TetRest<Real>* rest, index_t begin, index_t end,
                                 Real* grad_out, Real* diag_out) {
#pragma omp parallel for schedule(static)
  for (index_t t = begin; t < end; ++t) {
    const TetCorners<Real> c = load_corners(x, tets + 4 * static_cast<std::int64_t>(t));
    Vec3<Real> g[4], d[4];
    converted_gradient(model, conv, interpolant[t], rest[t], c, g, diag_out ? d : nullptr);
    store_corners(g, grad_out + 12 * static_cast<std::int64_t>(t));
    if (diag_out) store_corners(d, diag_out + 12 * static_cast<std::int64_t>(t));
  }
}

template <class Real, class Model>
EnergySum converted_element_energy_sum(const Model& model, const Conversion<Real>& conv,
                                       const Real* interpolant, const Real* x, const index_t* tets,
                                       const TetRest<Real>* rest, index_t begin, index_t end) {
  double value = 0, magnitude = 0;
#pragma omp parallel for schedule(static) reduction(+ : value, magnitude)
  for (index_t t = begin; t < end; ++t) {
    const double e = converted_energy(model, conv, interpolant[t], rest[t],
                                      load_corners(x, tets + 4 * static_cast<std::int64_t>(t)));
    value += e;
    magnitude += e < 0 ? -e : e;
  }
  return {value, magnitude};
}

// out[stride v + i] = sum over the corners (4 t + a) listed for vertex v of
// corner_values[12 t + 3 a + i], for vertices [begin, end). The table is CSR:
// corners of v at corner_ids[offsets[v] .. offsets[v + 1]), ascending.
template <class Real>
void gather_corners(const index_t* offsets, const index_t* corner_ids, index_t begin, index_t end,
                    const Real* corner_values, Real* out, int stride) {
#pragma omp parallel for schedule(static)
  for (index_t v = begin; v < end; ++v) {
    Real s0 = 0, s1 = 0, s2 = 0;
    for (index_t k = offsets[v]; k < offsets[v + 1]; ++k) {
      const Real* c = corner_values + 3 * static_cast<std::int64_t>(corner_ids[k]);
      s0 += c[0];
      s1 += c[1];
      s2 += c[2];
    }
    Real* o = out + static_cast<std::int64_t>(stride) * v;
    o[0] = s0;
    o[1] = s1;
    o[2] = s2;
  }
}

}  // namespace descent::cpu
