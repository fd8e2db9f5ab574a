// The host element pass in lanes (kernels/cpu/lane_models.hpp) gives bitwise
// the tet-by-tet gradient and Hessian diagonal of every model that runs in
// lanes, in double and float, on tet counts that are not a multiple of the
// lane width and on ranges that start inside a block; corotated and arap
// (the SVD's selects) included, and every model with conversion (the
// interpolants too). So are the Hessian products of the spectrum estimate
// and the multilevel preconditioner's projected element Hessians. The
// energies in double lanes are bitwise the
// tet-by-tet energies in double, from double and float data, inverted
// elements included. Added to the vertex partials in tet order (one
// thread), every pass's sums are bitwise those of the corner arrays and the
// gather.
#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include "kernels/arap.hpp"
#include "kernels/corotated.hpp"
#include "kernels/cpu/host_exec.hpp"
#include "kernels/loops.hpp"
#include "kernels/multilevel_loops.hpp"
#include "meshes/generators.hpp"
#include "partition/local_mesh.hpp"
#include "random_element.hpp"

namespace descent {
namespace {

static_assert(LaneModel<NeoHookean<double>, kLaneWidth<double>>);
static_assert(LaneModel<StVK<float>, kLaneWidth<float>>);
static_assert(LaneModel<MooneyRivlin<double>, kLaneWidth<double>>);
static_assert(LaneModel<Fung<float>, kLaneWidth<float>>);
static_assert(LaneModel<Corotated<double>, kLaneWidth<double>>);
static_assert(LaneModel<Arap<float>, kLaneWidth<float>>);

// `n` random deformed tets, each with its own 4 vertices (3 reals each).
template <class Real>
struct TetSet {
  std::vector<Real> x;
  std::vector<index_t> tets;
  std::vector<TetRest<Real>> rest;
};

template <class Real>
TetSet<Real> random_tets(int n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  TetSet<Real> set;
  for (int t = 0; t < n; ++t) {
    const testing::ElementCase e = testing::random_element(rng, 0.3);
    TetRest<Real> r;
    for (int k = 0; k < 9; ++k) r.dm_inv.m[k] = static_cast<Real>(e.rest.dm_inv.m[k]);
    r.volume = static_cast<Real>(e.rest.volume);
    set.rest.push_back(r);
    for (int a = 0; a < 4; ++a) {
      set.tets.push_back(static_cast<index_t>(4 * t + a));
      set.x.push_back(static_cast<Real>(e.x.x[a].x));
      set.x.push_back(static_cast<Real>(e.x.x[a].y));
      set.x.push_back(static_cast<Real>(e.x.x[a].z));
    }
  }
  return set;
}

// For a model defined on inverted elements: random tets with every third
// turned inside out (two corners swapped) and the last collapsed to a point
// (F = 0), where the SVD's selects take their other sides.
template <class Real, class Model>
TetSet<Real> test_tets(int n, std::uint64_t seed) {
  TetSet<Real> set = random_tets<Real>(n, seed);
  if constexpr (Model::kInvertible) {
    for (int t = 0; t < n; t += 3) std::swap(set.tets[4 * t], set.tets[4 * t + 1]);
    for (int a = 1; a < 4; ++a) set.tets[4 * (n - 1) + a] = set.tets[4 * (n - 1)];
  }
  return set;
}

// The lane pass against the tet-by-tet math over tets [begin, n), bit for bit.
template <class Real, class Model>
void expect_lanes_match(const Model& model, int n, index_t begin) {
  const TetSet<Real> set = test_tets<Real, Model>(n, 7 + n);
  std::vector<Real> grad(12 * n, Real(-1)), diag(12 * n, Real(-1));
  HostExec exec;
  loops::ElementOut<Real> out;
  out.corner_grad = grad.data();
  out.corner_diag = diag.data();
  const Conversion<Real> no_conversion{};
  loops::element_pass<false>(exec, 0, model, no_conversion, static_cast<Real*>(nullptr),
                             set.x.data(), set.tets.data(), set.rest.data(), begin, n, true, out);
  for (index_t t = 0; t < n; ++t) {
    const Real* g = grad.data() + 12 * t;
    const Real* d = diag.data() + 12 * t;
    if (t < begin) {  // outside the range: untouched
      for (int k = 0; k < 12; ++k) ASSERT_EQ(g[k], Real(-1)) << "tet " << t;
      continue;
    }
    const TetCorners<Real> c = loops::tet_corners(set.x.data(), set.tets.data(), t);
    Vec3<Real> want_g[4], want_d[4];
    element_gradient(model, set.rest[t], c, want_g);
    element_hessian_diagonal(model, set.rest[t], c, want_d);
    for (int a = 0; a < 4; ++a) {
      ASSERT_EQ(std::memcmp(g + 3 * a, &want_g[a], 3 * sizeof(Real)), 0)
          << "gradient, tet " << t << " corner " << a << " of " << n << " from " << begin;
      ASSERT_EQ(std::memcmp(d + 3 * a, &want_d[a], 3 * sizeof(Real)), 0)
          << "diagonal, tet " << t << " corner " << a << " of " << n << " from " << begin;
    }
  }
}

// The Hessian-product pass in lanes against element_hessian_product tet by
// tet over tets [begin, n), bit for bit.
template <class Real, class Model>
void expect_products_match(const Model& model, int n, index_t begin) {
  const TetSet<Real> set = test_tets<Real, Model>(n, 5 + n);
  std::mt19937_64 rng(3 + n);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::vector<Real> p(set.x.size());
  for (Real& v : p) v = static_cast<Real>(unit(rng));
  std::vector<Real> hp(12 * n, Real(-1));
  HostExec exec;
  loops::ElementOut<Real> out;
  out.corner_grad = hp.data();
  const Conversion<Real> no_conversion{};
  loops::hessian_product_pass<false>(exec, 0, model, no_conversion,
                                     static_cast<const Real*>(nullptr), set.x.data(), p.data(),
                                     set.tets.data(), set.rest.data(), begin, n, out);
  for (index_t t = begin; t < n; ++t) {
    const TetCorners<Real> c = loops::tet_corners(set.x.data(), set.tets.data(), t);
    const TetCorners<Real> pc = loops::tet_corners(p.data(), set.tets.data(), t);
    Vec3<Real> want[4];
    element_hessian_product(model, set.rest[t], c, pc.x, want);
    for (int a = 0; a < 4; ++a)
      ASSERT_EQ(std::memcmp(hp.data() + 12 * t + 3 * a, &want[a], 3 * sizeof(Real)), 0)
          << "product, tet " << t << " corner " << a << " of " << n << " from " << begin;
  }
  for (index_t t = 0; t < begin; ++t) ASSERT_EQ(hp[12 * t], Real(-1)) << "tet " << t;
}

// f(model) for every model, in Real, at E = 1e5 Pa and nu = 0.3.
template <class Real, class F>
void for_each_model(F f) {
  const Real e = Real(1e5), nu = Real(0.3);
  f(NeoHookean<Real>::from_young_poisson(e, nu));
  f(StVK<Real>::from_young_poisson(e, nu));
  f(MooneyRivlin<Real>::from_young_poisson(e, nu, Real(1e4)));
  f(Fung<Real>::from_young_poisson(e, nu, Real(1e4), Real(2)));
  f(Corotated<Real>::from_young_poisson(e, nu));
  f(Arap<Real>::from_young_poisson(e, nu));
}

// f(n, begin) for tet counts 1, W - 1, W and 3W + 3 (W the lane width of
// Real) and ranges [begin, n) from 0 and from inside a block.
template <class Real, class F>
void for_each_range(F f) {
  constexpr int w = kLaneWidth<Real>;
  for (const int n : {1, w - 1, w, 3 * w + 3})
    for (const index_t begin : {index_t{0}, index_t{n / 2}}) f(n, begin);
}

template <class Real>
void every_lane_model() {
  for_each_range<Real>([](int n, index_t begin) {
    for_each_model<Real>([&](const auto& model) {
      expect_lanes_match<Real>(model, n, begin);
      expect_products_match<Real>(model, n, begin);
    });
  });
}

TEST(Lanes, DoubleEqualsTetByTet) { every_lane_model<double>(); }
TEST(Lanes, FloatEqualsTetByTet) { every_lane_model<float>(); }

// Whether the 3 reals at got are bitwise want's, a NaN standing for any
// NaN: its sign and payload depend on the order of an operation's operands,
// which the compiler chooses per loop, and every NaN check sees it the same.
template <class Real>
bool same_or_both_nan(const Real* got, const Vec3<Real>& want) {
  const Real w[3] = {want.x, want.y, want.z};
  for (int k = 0; k < 3; ++k)
    if (std::memcmp(got + k, w + k, sizeof(Real)) != 0 && !(std::isnan(got[k]) && std::isnan(w[k])))
      return false;
  return true;
}

// With conversion: the interpolants, gradients, diagonals, Hessian products
// and energies of the lane passes against converted_gradient,
// converted_hessian_product and converted_energy tet by tet, bit for bit.
// Every third tet inverted and the last collapsed (l = 1 there: the model is
// not taken), and a band (lambda_minus, lambda_plus) = (0.6, 1.1) that puts
// the others' l inside (0, 1) or at 0; the stored interpolants cycle through
// 0, 0.3, 0.97 and 1, so the decay holds some. The product at an inverted
// tet's stored l < 1 takes a model undefined there (NaN, as tet by tet).
template <class Real, class Model>
void expect_conversion_matches(const Model& model, int n, index_t begin) {
  TetSet<Real> set = random_tets<Real>(n, 13 + n);
  for (int t = 0; t < n; t += 3) std::swap(set.tets[4 * t], set.tets[4 * t + 1]);
  for (int a = 1; a < 4; ++a) set.tets[4 * (n - 1) + a] = set.tets[4 * (n - 1)];
  const Conversion<Real> conv{Real(0.6), Real(1.1), Real(0.05),
                              Arap<Real>::from_young_poisson(Real(1e5), Real(0.3))};
  const Real start[4] = {Real(0), Real(0.3), Real(0.97), Real(1)};
  std::vector<Real> l(n), l_lanes(n);
  for (int t = 0; t < n; ++t) l[t] = l_lanes[t] = start[t % 4];

  std::vector<Real> grad(12 * n, Real(-1)), diag(12 * n, Real(-1)), hp(12 * n, Real(-1));
  std::vector<Real> p(set.x.size());
  for (std::size_t k = 0; k < p.size(); ++k) p[k] = static_cast<Real>(std::sin(1.0 + k));
  HostExec exec;
  loops::ElementOut<Real> out;
  out.corner_grad = hp.data();
  loops::hessian_product_pass<true>(exec, 0, model, conv, static_cast<const Real*>(l_lanes.data()),
                                    set.x.data(), p.data(), set.tets.data(), set.rest.data(), begin,
                                    n, out);
  const auto wide = in_double(model);
  const Conversion<double> wide_conv = in_double(conv);
  std::vector<double> energy(n, -1.0);
  element_energies_lanes<true, kLaneWidth<double>>(exec, 0, wide, wide_conv, l_lanes.data(),
                                                   set.x.data(), set.tets.data(), set.rest.data(),
                                                   n, energy.data());
  out.corner_grad = grad.data();
  out.corner_diag = diag.data();
  loops::element_pass<true>(exec, 0, model, conv, l_lanes.data(), set.x.data(), set.tets.data(),
                            set.rest.data(), begin, n, true, out);

  int blended = 0, arap_only = 0;
  for (index_t t = 0; t < n; ++t) {
    const TetCorners<Real> c = loops::tet_corners(set.x.data(), set.tets.data(), t);
    const double want_energy = converted_energy(wide, wide_conv, static_cast<double>(l[t]),
                                                in_double(set.rest[t]), in_double(c));
    ASSERT_EQ(std::memcmp(&energy[t], &want_energy, sizeof(double)), 0) << "energy, tet " << t;
    if (t < begin) {
      ASSERT_EQ(l_lanes[t], l[t]) << "interpolant outside the range, tet " << t;
      continue;
    }
    const TetCorners<Real> pc = loops::tet_corners(p.data(), set.tets.data(), t);
    Vec3<Real> want_hp[4], want_g[4], want_d[4];
    converted_hessian_product(model, conv, l[t], set.rest[t], c, pc.x, want_hp);
    converted_gradient(model, conv, l[t], set.rest[t], c, want_g, want_d);
    ASSERT_EQ(std::memcmp(&l_lanes[t], &l[t], sizeof(Real)), 0) << "interpolant, tet " << t;
    blended += l[t] > Real(0) && l[t] < Real(1);
    arap_only += l[t] == Real(1);
    for (int a = 0; a < 4; ++a) {
      ASSERT_TRUE(same_or_both_nan(hp.data() + 12 * t + 3 * a, want_hp[a]))
          << "product, tet " << t << " corner " << a;
      ASSERT_TRUE(same_or_both_nan(grad.data() + 12 * t + 3 * a, want_g[a]))
          << "gradient, tet " << t << " corner " << a;
      ASSERT_TRUE(same_or_both_nan(diag.data() + 12 * t + 3 * a, want_d[a]))
          << "diagonal, tet " << t << " corner " << a;
    }
  }
  if (n - begin >= 8) {  // both sides of the blend were taken
    EXPECT_GT(blended, 0);
    EXPECT_GT(arap_only, 0);
  }
}

template <class Real>
void every_lane_model_converted() {
  for_each_range<Real>([](int n, index_t begin) {
    for_each_model<Real>(
        [&](const auto& model) { expect_conversion_matches<Real>(model, n, begin); });
  });
}

TEST(Lanes, DoubleConversionEqualsTetByTet) { every_lane_model_converted<double>(); }
TEST(Lanes, FloatConversionEqualsTetByTet) { every_lane_model_converted<float>(); }

// The multilevel preconditioner's element Hessians in lanes
// (loops::add_element_hessians on the host) against each tet's own
// dP/dF, projection and contraction, bit for bit: every third tet inverted
// (dP/dF not positive definite: the projection's full path, beside tets
// whose dP/dF is definite in the same block), some dofs held,
// the tets taken in reverse order from `begin`, with and without conversion.
template <class Real, bool Converting, class Model>
void expect_hessians_match(const Model& model, int n, index_t begin) {
  TetSet<Real> set = random_tets<Real>(n, 17 + n);
  for (int t = 0; t < n; t += 3) std::swap(set.tets[4 * t], set.tets[4 * t + 1]);
  const Conversion<Real> conv{Real(0.6), Real(1.1), Real(0.05),
                              Arap<Real>::from_young_poisson(Real(1e5), Real(0.3))};
  std::vector<Real> l(n);
  for (int t = 0; t < n; ++t) l[t] = Real(0.3) * Real(t % 4);
  std::vector<index_t> order(n), slots(16 * n);
  for (int k = 0; k < n; ++k) order[k] = n - 1 - k;
  for (int k = 0; k < 16 * n; ++k) slots[k] = k;  // each tet its own 16 blocks
  std::vector<std::uint8_t> fixed(4 * n, 0);
  for (int v = 1; v < 4 * n; v += 7) fixed[v] = static_cast<std::uint8_t>(1 + v % 7);
  std::vector<Real> got(9 * 16 * n, Real(0)), want(9 * 16 * n, Real(0));
  HostExec exec;
  loops::add_element_hessians<Converting>(exec, 0, model, conv, l.data(), set.x.data(),
                                          set.tets.data(), set.rest.data(), order.data(), begin, n,
                                          slots.data(), fixed.data(), got.data());
  int projected = 0;
  for (index_t k = begin; k < n; ++k) {
    const index_t t = order[k];
    const TetCorners<Real> c = loops::tet_corners(set.x.data(), set.tets.data(), t);
    const Mat3<Real> f = deformation_gradient(c.x[0], c.x[1], c.x[2], c.x[3], set.rest[t].dm_inv);
    Real dpdf[81];
    if constexpr (Converting)
      converted_preconditioner_dpdf(model, conv, l[t], f, dpdf);
    else
      model.stress_derivative(f, dpdf);
    if (!loops::finite_entries(dpdf)) continue;
    Real before[81];
    std::memcpy(before, dpdf, sizeof(before));
    project_isotropic_psd(f, dpdf);
    projected += std::memcmp(before, dpdf, sizeof(before)) != 0;
    Real h[144];
    contract_stress_derivative(dpdf, set.rest[t], h);
    loops::add_element_blocks(h, set.tets.data() + 4 * t, slots.data() + 16 * t, fixed.data(),
                              want.data());
  }
  for (std::size_t e = 0; e < got.size(); ++e)
    ASSERT_EQ(std::memcmp(&got[e], &want[e], sizeof(Real)), 0)
        << "entry " << e << " (tet " << e / 144 << ") of " << n << " from " << begin << ": "
        << got[e] << " against " << want[e];
  // The projection's full path was taken (with conversion an inverted tet
  // is arap's, 2 mu I, already definite).
  if (!Converting && n - begin >= 6) {
    EXPECT_GT(projected, 0);
  }
}

template <class Real>
void every_lane_model_hessians() {
  for_each_range<Real>([](int n, index_t begin) {
    for_each_model<Real>([&](const auto& model) {
      expect_hessians_match<Real, false>(model, n, begin);
      expect_hessians_match<Real, true>(model, n, begin);
    });
  });
}

TEST(Lanes, DoubleElementHessiansEqualTetByTet) { every_lane_model_hessians<double>(); }
TEST(Lanes, FloatElementHessiansEqualTetByTet) { every_lane_model_hessians<float>(); }

// element_energies_lanes against element_energy of the widened data
// (loops::local_energy's tet-by-tet terms), bit for bit; every third tet is
// turned inside out (two corners swapped), which the models not defined
// there make infinite.
template <class Real, class Model>
void expect_energies_match(const Model& model, int n) {
  TetSet<Real> set = random_tets<Real>(n, 11 + n);
  for (int t = 0; t < n; t += 3) std::swap(set.tets[4 * t], set.tets[4 * t + 1]);
  const auto wide = in_double(model);
  std::vector<double> energy(n, -1.0);
  HostExec exec;
  element_energies_lanes<false, kLaneWidth<double>>(
      exec, 0, wide, Conversion<double>{}, static_cast<const Real*>(nullptr), set.x.data(),
      set.tets.data(), set.rest.data(), n, energy.data());
  int inverted = 0;
  for (index_t t = 0; t < n; ++t) {
    const double want =
        element_energy(wide, in_double(set.rest[t]),
                       in_double(loops::tet_corners(set.x.data(), set.tets.data(), t)));
    ASSERT_EQ(std::memcmp(&energy[t], &want, sizeof(double)), 0)
        << "tet " << t << " of " << n << ": " << energy[t] << " against " << want;
    inverted += std::isinf(want);
  }
  // The flips were seen where the model is undefined; an invertible model
  // keeps a finite energy there.
  EXPECT_EQ(inverted, Model::kInvertible ? 0 : (n + 2) / 3);
}

template <class Real>
void every_lane_model_energy() {
  // Counts for the double lanes the energies run in.
  for_each_range<double>([](int n, index_t begin) {
    if (begin != 0) return;  // the energies take every tet
    for_each_model<Real>([&](const auto& model) { expect_energies_match<Real>(model, n); });
  });
}

TEST(Lanes, EnergiesFromDoubleEqualTetByTet) { every_lane_model_energy<double>(); }
TEST(Lanes, EnergiesFromFloatEqualTetByTet) { every_lane_model_energy<float>(); }

}  // namespace
}  // namespace descent

namespace descent {
namespace {

// A box of 3 x 2 x 2 cells (72 tets, shared vertices) with its points moved
// at random by up to 10% of a cell, and its vertex -> corner table.
template <class Real>
struct SharedMesh {
  std::vector<Real> x;
  std::vector<TetRest<Real>> rest;
  LocalMesh mesh;
};

template <class Real>
SharedMesh<Real> shared_mesh() {
  BoxParams box;
  box.cells = {3, 2, 2};
  const Mesh m = make_box(box);
  SharedMesh<Real> s;
  s.mesh.tets = m.tets;
  s.mesh.global_vertex.resize(m.num_vertices());
  s.mesh.global_tet.resize(m.num_tets());
  build_vertex_corners(s.mesh);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> shift(-0.05, 0.05);
  for (double v : m.positions) s.x.push_back(static_cast<Real>(1.1 * v + shift(rng)));
  for (index_t t = 0; t < m.num_tets(); ++t) {
    const index_t* tet = m.tets.data() + 4 * t;
    auto at = [&](int a) {
      const double* p = m.positions.data() + 3 * tet[a];
      return Vec3<Real>{static_cast<Real>(p[0]), static_cast<Real>(p[1]), static_cast<Real>(p[2])};
    };
    s.rest.push_back(tet_rest(at(0), at(1), at(2), at(3)));
  }
  return s;
}

// The passes' results assembled both ways: in tet order into the partials
// (width 6), over tets [0, split) then [split, n) as the engine runs the
// boundary and the interior, against the corner arrays and the gather of
// every vertex, bit for bit; with conversion the interpolants too.
template <class Real, bool Converting, class Model>
void expect_in_order_matches_gather(const Model& model) {
  SharedMesh<Real> s = shared_mesh<Real>();
  const index_t nt = s.mesh.num_tets(), nv = s.mesh.num_vertices();
  const index_t split = nt / 2 + 3;  // inside a block
  const Conversion<Real> conv{Real(0.98), Real(1.02), Real(0.05),
                              Arap<Real>::from_young_poisson(Real(1e5), Real(0.3))};
  std::vector<Real> p(s.x.size());
  for (std::size_t k = 0; k < p.size(); ++k) p[k] = static_cast<Real>(std::cos(2.0 + k));
  // In order is one thread's (the engine takes it only then).
  struct OneThread {
    int threads = omp_get_max_threads();
    OneThread() { omp_set_num_threads(1); }
    ~OneThread() { omp_set_num_threads(threads); }
  } one_thread;
  HostExec exec;
  ASSERT_TRUE(exec.serial());
  const Real* no_l = nullptr;
  auto both = [&](auto pass, int width, bool with_diag, const char* what) {
    std::vector<Real> corners_g(12 * nt), corners_d(12 * nt), gathered(width * nv, Real(-1));
    loops::ElementOut<Real> gather_out;
    gather_out.corner_grad = corners_g.data();
    gather_out.corner_diag = with_diag ? corners_d.data() : nullptr;
    std::vector<Real> l_gather(nt, Real(0.5)), l_order(nt, Real(0.5));
    pass(gather_out, 0, nt, l_gather.data());
    loops::gather_corners(exec, 0, s.mesh.corner_offsets.data(), s.mesh.vertex_corners.data(), 0,
                          nv, corners_g.data(), gathered.data(), width, 0);
    if (with_diag)
      loops::gather_corners(exec, 0, s.mesh.corner_offsets.data(), s.mesh.vertex_corners.data(), 0,
                            nv, corners_d.data(), gathered.data(), width, 3);
    std::vector<Real> in_order(width * nv, Real(0));
    loops::ElementOut<Real> order_out;
    order_out.partial = in_order.data();
    order_out.width = width;
    order_out.in_order = true;
    pass(order_out, 0, split, l_order.data());
    pass(order_out, split, nt, l_order.data());
    ASSERT_EQ(std::memcmp(in_order.data(), gathered.data(), in_order.size() * sizeof(Real)), 0)
        << what;
    ASSERT_EQ(std::memcmp(l_order.data(), l_gather.data(), nt * sizeof(Real)), 0) << what;
  };
  both(
      [&](const loops::ElementOut<Real>& out, index_t begin, index_t end, Real* l) {
        loops::element_pass<Converting>(exec, 0, model, conv, Converting ? l : nullptr, s.x.data(),
                                        s.mesh.tets.data(), s.rest.data(), begin, end, true, out);
      },
      6, true, "gradient and diagonal");
  both(
      [&](const loops::ElementOut<Real>& out, index_t begin, index_t end, Real* l) {
        loops::element_pass<Converting>(exec, 0, model, conv, Converting ? l : nullptr, s.x.data(),
                                        s.mesh.tets.data(), s.rest.data(), begin, end, false, out);
      },
      3, false, "gradient");
  both(
      [&](const loops::ElementOut<Real>& out, index_t begin, index_t end, Real* l) {
        loops::hessian_product_pass<Converting>(
            exec, 0, model, conv, Converting ? static_cast<const Real*>(l) : no_l, s.x.data(),
            p.data(), s.mesh.tets.data(), s.rest.data(), begin, end, out);
      },
      3, false, "Hessian product");
}

template <class Real>
void every_model_in_order() {
  for_each_model<Real>([](const auto& model) {
    expect_in_order_matches_gather<Real, false>(model);
    expect_in_order_matches_gather<Real, true>(model);
  });
}

TEST(Lanes, DoubleInOrderAssemblyEqualsGather) { every_model_in_order<double>(); }
TEST(Lanes, FloatInOrderAssemblyEqualsGather) { every_model_in_order<float>(); }

}  // namespace
}  // namespace descent
