// Contact pairs between surface primitives (kernels/primitive_distance.hpp,
// kernels/pair_contact.hpp): distances against brute-force minimisation,
// every gradient and Hessian against finite differences in every region of
// the closest points (triangle face, edges and corners; edge interiors and
// ends), the mollifier of nearly parallel edges, and the barrier terms'
// exact and positive semi-definite Hessians.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <array>
#include <cmath>
#include <functional>
#include <random>

#include "kernels/pair_contact.hpp"
#include "kernels/primitive_distance.hpp"

namespace descent {
namespace {

using X = std::array<double, 12>;

// A random rotation and shift applied to every point of a configuration,
// so no test leans on axis-aligned coordinates.
X moved(const X& x, std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  Eigen::Quaterniond q(n(rng), n(rng), n(rng), n(rng));
  q.normalize();
  const Eigen::Matrix3d r = q.toRotationMatrix();
  const Eigen::Vector3d shift(n(rng), n(rng), n(rng));
  X out;
  for (int k = 0; k < 4; ++k) {
    const Eigen::Vector3d p = r * Eigen::Vector3d(x[3 * k], x[3 * k + 1], x[3 * k + 2]) + shift;
    for (int i = 0; i < 3; ++i) out[3 * k + i] = p[i];
  }
  return out;
}

X jiggled(X x, std::mt19937& rng, double amount) {
  std::uniform_real_distribution<double> u(-amount, amount);
  for (double& v : x) v += u(rng);
  return x;
}

// Closest distance^2 by sampling the parameters finely and refining: an
// independent check of the region search.
double brute_d2(PairKind kind, const X& x) {
  auto at = [&](double s, double t) {
    double r[3];
    for (int i = 0; i < 3; ++i) {
      if (kind == PairKind::vertex_triangle)
        r[i] = x[i] - (x[3 + i] + s * (x[6 + i] - x[3 + i]) + t * (x[9 + i] - x[3 + i]));
      else
        r[i] = x[i] + s * (x[3 + i] - x[i]) - x[6 + i] - t * (x[9 + i] - x[6 + i]);
    }
    return r[0] * r[0] + r[1] * r[1] + r[2] * r[2];
  };
  auto allowed = [&](double s, double t) {
    if (kind == PairKind::vertex_triangle) return s >= 0 && t >= 0 && s + t <= 1;
    return s >= 0 && s <= 1 && t >= 0 && t <= 1;
  };
  double best = 1e300, bs = 0, bt = 0;
  constexpr int kSteps = 200;
  for (int i = 0; i <= kSteps; ++i)
    for (int j = 0; j <= kSteps; ++j) {
      const double s = double(i) / kSteps, t = double(j) / kSteps;
      if (allowed(s, t) && at(s, t) < best) best = at(s, t), bs = s, bt = t;
    }
  for (double h = 1.0 / kSteps; h > 1e-12; h *= 0.5)
    for (int di = -1; di <= 1; ++di)
      for (int dj = -1; dj <= 1; ++dj) {
        const double s = bs + di * h, t = bt + dj * h;
        if (allowed(s, t) && at(s, t) < best) best = at(s, t), bs = s, bt = t;
      }
  return best;
}

double d2_of(PairKind kind, const X& x) {
  return kind == PairKind::vertex_triangle ? point_triangle_distance(x.data(), false).d2
                                           : edge_edge_distance(x.data(), false).d2;
}

// Central differences of a scalar function of x and of a 12-vector one.
std::array<double, 12> fd_gradient(const std::function<double(const X&)>& f, const X& x, double h) {
  std::array<double, 12> g;
  for (int a = 0; a < 12; ++a) {
    X plus = x, minus = x;
    plus[a] += h;
    minus[a] -= h;
    g[a] = (f(plus) - f(minus)) / (2 * h);
  }
  return g;
}

std::array<double, 144> fd_jacobian(const std::function<std::array<double, 12>(const X&)>& f,
                                    const X& x, double h) {
  std::array<double, 144> j;
  for (int b = 0; b < 12; ++b) {
    X plus = x, minus = x;
    plus[b] += h;
    minus[b] -= h;
    const std::array<double, 12> gp = f(plus), gm = f(minus);
    for (int a = 0; a < 12; ++a) j[12 * a + b] = (gp[a] - gm[a]) / (2 * h);
  }
  return j;
}

double max_abs(const double* v, int n) {
  double m = 0;
  for (int i = 0; i < n; ++i) m = std::max(m, std::abs(v[i]));
  return m;
}

// The least eigenvalue of a symmetric 12 x 12 matrix (row-major).
double lowest_eigenvalue(const double* h) {
  const Eigen::Map<const Eigen::Matrix<double, 12, 12, Eigen::RowMajor>> m(h);
  return Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 12, 12>>(m).eigenvalues().minCoeff();
}

// d^2 of `kind` at x: its value against brute force, its gradient and
// Hessian against finite differences.
void check_distance(PairKind kind, const X& x, const std::string& what) {
  SCOPED_TRACE(what);
  const PairDistance<double> d = kind == PairKind::vertex_triangle
                                     ? point_triangle_distance(x.data(), true)
                                     : edge_edge_distance(x.data(), true);
  EXPECT_NEAR(d.d2, brute_d2(kind, x), 1e-9 * (1 + d.d2));
  const std::array<double, 12> g = fd_gradient([&](const X& y) { return d2_of(kind, y); }, x, 1e-6);
  for (int a = 0; a < 12; ++a) EXPECT_NEAR(d.grad[a], g[a], 1e-6 * (1 + max_abs(g.data(), 12)));
  const std::array<double, 144> h = fd_jacobian(
      [&](const X& y) {
        const PairDistance<double> e = kind == PairKind::vertex_triangle
                                           ? point_triangle_distance(y.data(), false)
                                           : edge_edge_distance(y.data(), false);
        std::array<double, 12> out;
        std::copy(e.grad, e.grad + 12, out.begin());
        return out;
      },
      x, 1e-6);
  for (int a = 0; a < 144; ++a)
    EXPECT_NEAR(d.hess[a], h[a], 1e-5 * (1 + max_abs(h.data(), 144))) << "entry " << a;
}

// Triangle (0,0,0), (1,0,0), (0,1,0) and a vertex above each region.
TEST(PairContact, PointTriangleDistanceInEveryRegion) {
  std::mt19937 rng(7);
  const std::array<std::pair<const char*, std::array<double, 2>>, 7> above = {{
      {"face", {0.2, 0.3}},
      {"edge ab", {0.5, -0.4}},
      {"edge ac", {-0.4, 0.5}},
      {"edge bc", {0.8, 0.8}},
      {"corner a", {-0.4, -0.4}},
      {"corner b", {1.5, -0.3}},
      {"corner c", {-0.3, 1.5}},
  }};
  for (const auto& [name, xy] : above)
    for (int trial = 0; trial < 5; ++trial) {
      const X x = moved(jiggled({xy[0], xy[1], 0.3, 0, 0, 0, 1, 0, 0, 0, 1, 0}, rng, 0.05), rng);
      check_distance(PairKind::vertex_triangle, x, name);
    }
}

// p0 p1 along x at z = 0, q0 q1 along y at z = 0.3, moved so that the closest
// parameters are interior, or one or both at an end.
TEST(PairContact, EdgeEdgeDistanceInEveryRegion) {
  std::mt19937 rng(11);
  const std::array<std::pair<const char*, std::array<double, 2>>, 4> shift = {{
      {"both interior", {0.0, 0.0}},
      {"s at an end", {1.0, 0.0}},
      {"t at an end", {0.0, -1.0}},
      {"both at ends", {1.2, 1.3}},
  }};
  for (const auto& [name, xy] : shift)
    for (int trial = 0; trial < 5; ++trial) {
      const X x =
          moved(jiggled({-0.5, 0, 0, 0.5, 0, 0, xy[0], -0.5 + xy[1], 0.3, xy[0], 0.5 + xy[1], 0.3},
                        rng, 0.05),
                rng);
      check_distance(PairKind::edge_edge, x, name);
    }
}

TEST(PairContact, ParallelismMollifierDerivatives) {
  std::mt19937 rng(3);
  // Nearly parallel (e below eps) and crossing (e beyond: m = 1).
  for (double tilt : {0.01, 0.5}) {
    const X x = moved({0, 0, 0, 1, 0, 0, 0, 0.1, 0.2, 1, 0.1 + tilt, 0.2}, rng);
    const double eps = 1e-3 * 1.0 * 1.0;
    const Parallelism<double> p = edge_parallelism(x.data(), eps, true);
    EXPECT_EQ(p.m < 1, tilt < 0.1);
    const auto e_of = [&](const X& y) { return edge_parallelism(y.data(), eps, false).e; };
    const std::array<double, 12> g = fd_gradient(e_of, x, 1e-6);
    for (int a = 0; a < 12; ++a) EXPECT_NEAR(p.grad[a], g[a], 1e-7);
    const std::array<double, 144> h = fd_jacobian(
        [&](const X& y) {
          const Parallelism<double> q = edge_parallelism(y.data(), eps, false);
          std::array<double, 12> out;
          std::copy(q.grad, q.grad + 12, out.begin());
          return out;
        },
        x, 1e-6);
    for (int a = 0; a < 144; ++a) EXPECT_NEAR(p.hess[a], h[a], 1e-6);
  }
}

// The barrier terms at distances inside dh: energy, gradient and exact
// Hessian by finite differences; the psd Hessian positive semi-definite.
void check_pair(PairKind kind, const X& x, double dh, double eps, const std::string& what) {
  SCOPED_TRACE(what);
  constexpr double kappa = 1e4;
  const PairTerms<double> t = pair_barrier(kind, x.data(), kappa, dh, eps, PairHessian::exact);
  ASSERT_GT(t.energy, 0.0);
  ASSERT_LT(t.distance, dh);
  const double h = 1e-3 * t.distance;
  const auto energy = [&](const X& y) {
    return pair_barrier(kind, y.data(), kappa, dh, eps, PairHessian::none).energy;
  };
  const std::array<double, 12> g = fd_gradient(energy, x, h);
  const double gscale = max_abs(g.data(), 12);
  for (int a = 0; a < 12; ++a) EXPECT_NEAR(t.grad[a], g[a], 1e-5 * gscale);
  const std::array<double, 144> hess = fd_jacobian(
      [&](const X& y) {
        const PairTerms<double> u = pair_barrier(kind, y.data(), kappa, dh, eps, PairHessian::none);
        std::array<double, 12> out;
        std::copy(u.grad, u.grad + 12, out.begin());
        return out;
      },
      x, h);
  const double hscale = max_abs(hess.data(), 144);
  for (int a = 0; a < 144; ++a) EXPECT_NEAR(t.hess[a], hess[a], 1e-4 * hscale) << "entry " << a;
  const PairTerms<double> psd = pair_barrier(kind, x.data(), kappa, dh, eps, PairHessian::psd);
  EXPECT_GE(lowest_eigenvalue(psd.hess), -1e-9 * hscale);
}

TEST(PairContact, BarrierTermsMatchFiniteDifferences) {
  std::mt19937 rng(5);
  const double dh = 0.1;
  for (double gap : {0.005, 0.03, 0.08}) {
    const X face = moved({0.2, 0.3, gap, 0, 0, 0, 1, 0, 0, 0, 1, 0}, rng);
    check_pair(PairKind::vertex_triangle, face, dh, 0, "vertex over the face");
    const X corner = moved({-gap / 2, -gap / 2, gap / 2, 0, 0, 0, 1, 0, 0, 0, 1, 0}, rng);
    check_pair(PairKind::vertex_triangle, corner, dh, 0, "vertex by a corner");
    const X crossing = moved({-0.5, 0, 0, 0.5, 0.1, 0, 0.05, -0.5, gap, -0.1, 0.5, gap}, rng);
    check_pair(PairKind::edge_edge, crossing, dh, 1e-3, "crossing edges");
    // Nearly parallel: the mollifier (eps = 1e-3 |u|^2 |v|^2) is active.
    const X parallel = moved({0, 0, 0, 1, 0, 0, 0.3, 0.01, gap, 1.3, 0.03, gap}, rng);
    ASSERT_LT(edge_parallelism(parallel.data(), 1e-3, false).m, 1.0);
    check_pair(PairKind::edge_edge, parallel, dh, 1e-3, "nearly parallel edges");
  }
}

TEST(PairContact, NoTermBeyondTheActivationDistanceAndInfiniteAtContact) {
  const X far = {0.2, 0.3, 0.2, 0, 0, 0, 1, 0, 0, 0, 1, 0};
  const PairTerms<double> none =
      pair_barrier(PairKind::vertex_triangle, far.data(), 1.0, 0.1, 0.0, PairHessian::exact);
  EXPECT_EQ(none.energy, 0.0);
  EXPECT_EQ(max_abs(none.grad, 12), 0.0);
  EXPECT_EQ(max_abs(none.hess, 144), 0.0);
  // Closer is dearer, and a vertex on the corner it touches is at +inf.
  double previous = 0;
  for (double gap : {0.05, 1e-2, 1e-4, 1e-8}) {
    const X near = {0.2, 0.3, gap, 0, 0, 0, 1, 0, 0, 0, 1, 0};
    const double e =
        pair_barrier(PairKind::vertex_triangle, near.data(), 1.0, 0.1, 0.0, PairHessian::none)
            .energy;
    EXPECT_GT(e, previous) << "gap " << gap;
    previous = e;
  }
  const X touching = {1, 0, 0, 0, 0, 0, 1, 0, 0, 0, 1, 0};
  EXPECT_TRUE(std::isinf(
      pair_barrier(PairKind::vertex_triangle, touching.data(), 1.0, 0.1, 0.0, PairHessian::none)
          .energy));
}

// Over a face the positive semi-definite part is the exact Hessian along the
// normal: the vertex's diagonal block agrees to round-off at d = dh / 20.
TEST(PairContact, PsdDiagonalIsTheExactOneNearContact) {
  std::mt19937 rng(9);
  const X x = moved({0.2, 0.3, 0.005, 0, 0, 0, 1, 0, 0, 0, 1, 0}, rng);
  const PairTerms<double> exact =
      pair_barrier(PairKind::vertex_triangle, x.data(), 1.0, 0.1, 0.0, PairHessian::exact);
  const PairTerms<double> psd =
      pair_barrier(PairKind::vertex_triangle, x.data(), 1.0, 0.1, 0.0, PairHessian::psd);
  double worst = 0, scale = 0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      worst = std::max(worst, std::abs(exact.hess[12 * i + j] - psd.hess[12 * i + j]));
      scale = std::max(scale, std::abs(exact.hess[12 * i + j]));
    }
  EXPECT_GT(scale, 0.0);
  EXPECT_LT(worst, 1e-9 * scale);
}

// Lagged friction of a pair: its normal force and normal from the step
// start, the closest points' relative slip since; gradient and Hessian by
// finite differences in the sticking (|slip| < eps_h) and sliding regimes,
// the Hessian positive semi-definite, no term beyond dh at the start.
TEST(PairContact, FrictionMatchesFiniteDifferencesAndIsConvex) {
  std::mt19937 rng(21);
  std::normal_distribution<double> n(0.0, 1.0);
  const double dh = 0.1, kappa = 1e3, mu = 0.4, eps_h = 1e-3;
  const X face = moved({0.2, 0.3, 0.03, 0, 0, 0, 1, 0, 0, 0, 1, 0}, rng);
  const X crossing = moved({-0.5, 0, 0, 0.5, 0.1, 0, 0.05, -0.5, 0.03, -0.1, 0.5, 0.03}, rng);
  for (const auto& [kind, xt] :
       {std::pair{PairKind::vertex_triangle, face}, std::pair{PairKind::edge_edge, crossing}}) {
    const PairFrictionLag<double> lag = pair_friction_lag(kind, xt.data(), kappa, dh, mu);
    ASSERT_GT(lag.mu_lambda, 0.0);
    EXPECT_NEAR(std::hypot(lag.n[0], lag.n[1], lag.n[2]), 1.0, 1e-12);
    for (double slip : {3e-4, 3e-2}) {  // sticking, sliding
      X x = xt;
      for (double& v : x) v += slip * n(rng);
      const auto friction = [&](const X& y, PairHessian h) {
        PairTerms<double> t;
        add_pair_friction(lag, eps_h, y.data(), xt.data(), h, t);
        return t;
      };
      const PairTerms<double> t = friction(x, PairHessian::exact);
      const double h = 1e-3 * slip;
      const std::array<double, 12> g =
          fd_gradient([&](const X& y) { return friction(y, PairHessian::none).energy; }, x, h);
      for (int a = 0; a < 12; ++a) EXPECT_NEAR(t.grad[a], g[a], 1e-5 * max_abs(g.data(), 12));
      const std::array<double, 144> hess = fd_jacobian(
          [&](const X& y) {
            const PairTerms<double> u = friction(y, PairHessian::none);
            std::array<double, 12> out;
            std::copy(u.grad, u.grad + 12, out.begin());
            return out;
          },
          x, h);
      for (int a = 0; a < 144; ++a)
        EXPECT_NEAR(t.hess[a], hess[a], 1e-4 * max_abs(hess.data(), 144)) << "entry " << a;
      EXPECT_GE(lowest_eigenvalue(t.hess), -1e-9 * max_abs(t.hess, 144));
    }
  }
  const X far = {0.2, 0.3, 0.2, 0, 0, 0, 1, 0, 0, 0, 1, 0};
  EXPECT_EQ(pair_friction_lag(PairKind::vertex_triangle, far.data(), kappa, dh, mu).mu_lambda, 0.0);
}

}  // namespace
}  // namespace descent
