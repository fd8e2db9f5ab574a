#pragma once
// The element pass over blocks of tets on the host: each block's corners and
// rest data are loaded into Lanes (kernels/cpu/lanes.hpp), the model's own
// gradient and Hessian diagonal (kernels/element.hpp) run once for the whole
// block, and each lane's results go where the tet-by-tet loop puts them
// (12 corner reals per tet, or added to the vertex partials in tet order or
// atomically; kernels/element_out.hpp). Bitwise the tet-by-tet results
// (lanes.hpp says why), so every later sum is unchanged.
//
// Models whose stress, Hessian diagonal and stress derivative choose only
// by select() (kernels/real_math.hpp): neo-Hookean, StVK, Mooney-Rivlin,
// Fung, and corotated and arap (the SVD's sweeps, sorting and Givens
// rotations, kernels/svd3.hpp); with conversion (kernels/conversion.hpp,
// the interpolant's clamps and blends as selects) each of them too. With
// conversion (Converting) the passes read, and the element pass updates,
// one interpolant per tet as the tet-by-tet loop does.
#include <cstdint>
#include <limits>

#include "common/mesh.hpp"
#include "kernels/arap.hpp"
#include "kernels/conversion.hpp"
#include "kernels/corotated.hpp"
#include "kernels/cpu/lanes.hpp"
#include "kernels/element.hpp"
#include "kernels/element_hessian_product.hpp"
#include "kernels/element_out.hpp"
#include "kernels/fung.hpp"
#include "kernels/mooney_rivlin.hpp"
#include "kernels/neo_hookean.hpp"
#include "kernels/stvk.hpp"

namespace descent {

// A model's parameters broadcast to every lane.
template <int W, class T>
NeoHookean<Lanes<T, W>> lane_model(const NeoHookean<T>& m) {
  return {m.mu, m.kappa};
}
template <int W, class T>
StVK<Lanes<T, W>> lane_model(const StVK<T>& m) {
  return {m.mu, m.lambda};
}
template <int W, class T>
MooneyRivlin<Lanes<T, W>> lane_model(const MooneyRivlin<T>& m) {
  return {lane_model<W>(m.neo_hookean), m.c2};
}
template <int W, class T>
Fung<Lanes<T, W>> lane_model(const Fung<T>& m) {
  return {lane_model<W>(m.neo_hookean), m.c2, m.c3};
}
template <int W, class T>
Corotated<Lanes<T, W>> lane_model(const Corotated<T>& m) {
  return {m.mu, m.lambda};
}
template <int W, class T>
Arap<Lanes<T, W>> lane_model(const Arap<T>& m) {
  return {m.mu};
}

template <int W, class T>
Conversion<Lanes<T, W>> lane_conversion(const Conversion<T>& c) {
  return {c.lambda_minus, c.lambda_plus, c.decay, lane_model<W>(c.arap)};
}

// Whether Model runs in lanes of width W.
template <class Model, int W>
concept LaneModel = requires(const Model& m) {
  lane_model<W>(m);
};

// f(first, count) for each block of W tets of [begin, end): tets [first,
// first + count), count <= W.
template <int W, class Exec, class F>
void for_each_block(Exec& exec, int stream, index_t begin, index_t end, F f) {
  const index_t blocks = (end - begin + W - 1) / W;
  exec.for_each(stream, 0, blocks, [=](index_t b) {
    const index_t first = begin + b * W;
    f(first, end - first < W ? static_cast<int>(end - first) : W);
  });
}

// The tet of each lane of a block.
template <int W>
struct BlockTets {
  index_t t[W];
};

// The block [first, first + count) of tets, or of the list `order` (tets
// order[first], ...): lanes past `count` repeat the block's last tet,
// computed and not stored.
template <int W>
BlockTets<W> block_tets(index_t first, int count, const index_t* order = nullptr) {
  BlockTets<W> ids;
  for (int l = 0; l < W; ++l) {
    const index_t k = first + (l < count ? l : count - 1);
    ids.t[l] = order ? order[k] : k;
  }
  return ids;
}

// The block's corners of x (3 reals per vertex) into lanes. The lanes' real
// L may be wider than the data's T (a float run's energy in double,
// kernels/in_double.hpp): each value is converted as in_double does.
template <int W, class L, class T>
void load_corners(const T* x, const index_t* tets, const BlockTets<W>& ids,
                  TetCorners<Lanes<L, W>>& c) {
  for (int l = 0; l < W; ++l) {
    const index_t* tet = tets + 4 * static_cast<std::int64_t>(ids.t[l]);
    for (int a = 0; a < 4; ++a) {
      const T* p = x + 3 * static_cast<std::int64_t>(tet[a]);
      c.x[a].x.v[l] = static_cast<L>(p[0]);
      c.x[a].y.v[l] = static_cast<L>(p[1]);
      c.x[a].z.v[l] = static_cast<L>(p[2]);
    }
  }
}

// The block's corners of x and its rest data into lanes.
template <int W, class L, class T>
void load_lanes(const T* x, const index_t* tets, const TetRest<T>* rest, const BlockTets<W>& ids,
                TetCorners<Lanes<L, W>>& c, TetRest<Lanes<L, W>>& r) {
  load_corners<W>(x, tets, ids, c);
  for (int l = 0; l < W; ++l) {
    const TetRest<T>& source = rest[ids.t[l]];
    for (int k = 0; k < 9; ++k) r.dm_inv.m[k].v[l] = static_cast<L>(source.dm_inv.m[k]);
    r.volume.v[l] = static_cast<L>(source.volume);
  }
}

// One value per tet (the interpolants) of the block into lanes, converted
// to L as load_corners converts.
template <int W, class L, class T>
Lanes<L, W> load_values(const T* values, const BlockTets<W>& ids) {
  Lanes<L, W> v;
  for (int l = 0; l < W; ++l) v.v[l] = static_cast<L>(values[ids.t[l]]);
  return v;
}

// The first `count` lanes of v into one value per tet from tet `first` on.
template <int W, class T>
void store_values(const Lanes<T, W>& v, index_t first, int count, T* values) {
  for (int l = 0; l < count; ++l) values[first + l] = v.v[l];
}

// The first `count` lanes of per-corner values into 12 reals per tet from
// tet `first` on.
template <int W, class T>
void store_lanes(const Vec3<Lanes<T, W>> values[4], index_t first, int count, T* out) {
  for (int l = 0; l < count; ++l) {
    T* o = out + 12 * static_cast<std::int64_t>(first + l);
    for (int a = 0; a < 4; ++a) {
      o[3 * a] = values[a].x.v[l];
      o[3 * a + 1] = values[a].y.v[l];
      o[3 * a + 2] = values[a].z.v[l];
    }
  }
}

// The first `count` lanes of per-corner values added to the vertex partials
// (`width` reals per vertex, from `offset` on), tet by tet from `first` on,
// as loops::put_corners adds one tet's: plainly in order, else atomically.
template <int W, class T>
void add_lanes(const loops::ElementOut<T>& out, const Vec3<Lanes<T, W>> values[4],
               const index_t* tets, index_t first, int count, int offset) {
  for (int l = 0; l < count; ++l) {
    const index_t* tet = tets + 4 * static_cast<std::int64_t>(first + l);
    for (int a = 0; a < 4; ++a) {
      T* p = out.partial + static_cast<std::int64_t>(out.width) * tet[a] + offset;
      loops::add_to_partial(out, p, values[a].x.v[l]);
      loops::add_to_partial(out, p + 1, values[a].y.v[l]);
      loops::add_to_partial(out, p + 2, values[a].z.v[l]);
    }
  }
}

// The block's per-corner results to `out` (kernels/element_out.hpp):
// gradients, or with `diagonal` the Hessian diagonal's.
template <int W, class T>
void put_lanes(const loops::ElementOut<T>& out, const Vec3<Lanes<T, W>> values[4],
               const index_t* tets, index_t first, int count, bool diagonal) {
  if (out.partial)
    add_lanes<W>(out, values, tets, first, count, diagonal ? 3 : 0);
  else
    store_lanes<W>(values, first, count, diagonal ? out.corner_diag : out.corner_grad);
}

// The element pass of tets [begin, end) in blocks of W: gradients and, with
// `with_diag`, the Hessian diagonal to `out`; with conversion (Converting)
// each tet's interpolant updated in place first.
template <bool Converting, int W, class Exec, class Real, class Model>
void element_pass_lanes(Exec& exec, int stream, const Model& model, const Conversion<Real>& conv,
                        Real* interpolant, const Real* x, const index_t* tets,
                        const TetRest<Real>* rest, index_t begin, index_t end, bool with_diag,
                        const loops::ElementOut<Real>& out) {
  using L = Lanes<Real, W>;
  const auto lanes = lane_model<W>(model);
  const auto lane_conv = lane_conversion<W>(conv);
  for_each_block<W>(exec, stream, begin, end, [=](index_t first, int count) {
    TetCorners<L> c;
    TetRest<L> r;
    const BlockTets<W> ids = block_tets<W>(first, count);
    load_lanes<W>(x, tets, rest, ids, c, r);
    Vec3<L> values[4];
    if constexpr (Converting) {
      L l = load_values<W, Real>(interpolant, ids);
      Vec3<L> diag[4];
      converted_gradient(lanes, lane_conv, l, r, c, values, with_diag ? diag : nullptr);
      store_values<W>(l, first, count, interpolant);
      put_lanes<W>(out, values, tets, first, count, false);
      if (with_diag) put_lanes<W>(out, diag, tets, first, count, true);
      return;
    }
    element_gradient(lanes, r, c, values);
    put_lanes<W>(out, values, tets, first, count, false);
    if (!with_diag) return;
    element_hessian_diagonal(lanes, r, c, values);
    put_lanes<W>(out, values, tets, first, count, true);
  });
}

// The Hessian-product pass of tets [begin, end) in blocks of W: the product
// of each element's exact Hessian at x with the corners of p to `out`, as
// loops::hessian_product_pass puts it; with conversion the blend at each
// tet's stored interpolant.
template <bool Converting, int W, class Exec, class Real, class Model>
void hessian_product_pass_lanes(Exec& exec, int stream, const Model& model,
                                const Conversion<Real>& conv, const Real* interpolant,
                                const Real* x, const Real* p, const index_t* tets,
                                const TetRest<Real>* rest, index_t begin, index_t end,
                                const loops::ElementOut<Real>& out) {
  using L = Lanes<Real, W>;
  const auto lanes = lane_model<W>(model);
  const auto lane_conv = lane_conversion<W>(conv);
  for_each_block<W>(exec, stream, begin, end, [=](index_t first, int count) {
    TetCorners<L> c, pc;
    TetRest<L> r;
    const BlockTets<W> ids = block_tets<W>(first, count);
    load_lanes<W>(x, tets, rest, ids, c, r);
    load_corners<W>(p, tets, ids, pc);
    Vec3<L> values[4];
    if constexpr (Converting)
      converted_hessian_product(lanes, lane_conv, load_values<W, Real>(interpolant, ids), r, c,
                                pc.x, values);
    else
      element_hessian_product(lanes, r, c, pc.x, values);
    put_lanes<W>(out, values, tets, first, count, false);
  });
}

// energy[t] = element_energy(model, rest[t], corners of t) for tets [0,
// num_tets), in blocks of W, or with conversion (Converting)
// converted_energy at the tet's interpolant: the model in double
// (in_double's), the data in T widened as in_double widens it, so each value
// is bitwise the one the tet-by-tet energy loop (loops::local_energy)
// computes.
template <bool Converting, int W, class Exec, class T, class Model>
void element_energies_lanes(Exec& exec, int stream, const Model& model,
                            const Conversion<double>& conv, const T* interpolant, const T* x,
                            const index_t* tets, const TetRest<T>* rest, index_t num_tets,
                            double* energy) {
  using L = Lanes<double, W>;
  const auto lanes = lane_model<W>(model);
  const auto lane_conv = lane_conversion<W>(conv);
  using LaneModelType = decltype(lanes);
  for_each_block<W>(exec, stream, 0, num_tets, [=](index_t first, int count) {
    TetCorners<L> c;
    TetRest<L> r;
    const BlockTets<W> ids = block_tets<W>(first, count);
    load_lanes<W>(x, tets, rest, ids, c, r);
    if constexpr (Converting) {
      const L l = load_values<W, double>(interpolant, ids);
      store_values<W>(converted_energy(lanes, lane_conv, l, r, c), first, count, energy);
      return;
    }
    const Mat3<L> f = deformation_gradient(c.x[0], c.x[1], c.x[2], c.x[3], r.dm_inv);
    const L value = r.volume * lanes.energy(f);
    L j = 0;
    if constexpr (!LaneModelType::kInvertible) j = det(f);
    for (int l = 0; l < count; ++l)
      energy[first + l] =
          outside_domain<Model>(j.v[l]) ? std::numeric_limits<double>::infinity() : value.v[l];
  });
}

}  // namespace descent
