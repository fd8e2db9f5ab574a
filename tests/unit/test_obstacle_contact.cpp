// The obstacle contact kernels (kernels/obstacle_contact.hpp) against
// central finite differences: the gap's normal and curvature from the gap,
// the barrier's derivatives, and a vertex's contact gradient from its energy
// and exact Hessian from its gradient (plane, sphere and box, moved and
// rotated; barrier and lagged friction in both regimes); the friction's
// majorant for the diagonal lies above it. Then the guard: no
// guarded move of random size ever ends inside an obstacle, and a move that
// needs no cut is left bit for bit. And the checks' contact energy of float
// data is the double evaluation of that data (issue 22, mixed precision).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "kernels/contact_loops.hpp"
#include "kernels/cpu/host_exec.hpp"
#include "kernels/in_double.hpp"
#include "kernels/obstacle_contact.hpp"

namespace descent {
namespace {

constexpr double kFdStep = 1e-6;
constexpr double kTolerance = 1e-5;  // relative to the larger of the value and the scale

// A rotation by `angle` about the unit axis (Rodrigues), row-major.
void rotation(const double axis[3], double angle, double* r) {
  const double c = std::cos(angle), s = std::sin(angle);
  const double k[3] = {axis[0], axis[1], axis[2]};
  const double cross[9] = {0, -k[2], k[1], k[2], 0, -k[0], -k[1], k[0], 0};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      r[3 * i + j] = (i == j ? c : 0.0) + s * cross[3 * i + j] + (1 - c) * k[i] * k[j];
}

ObstacleGeometry<double> moved(ObstacleGeometry<double> o) {
  const double axis[3] = {0.48, 0.6, 0.64};
  rotation(axis, 0.7, o.rotation);
  o.shift[0] = 0.1;
  o.shift[1] = -0.2;
  o.shift[2] = 0.05;
  return o;
}

ObstacleGeometry<double> plane() {
  ObstacleGeometry<double> o{};
  o.kind = kObstaclePlane;
  o.b[0] = 0.6;
  o.b[1] = 0.8;
  return moved(o);
}

ObstacleGeometry<double> sphere() {
  ObstacleGeometry<double> o{};
  o.kind = kObstacleSphere;
  o.a[0] = 0.2;
  o.radius = 0.5;
  return moved(o);
}

ObstacleGeometry<double> box() {
  ObstacleGeometry<double> o{};
  o.kind = kObstacleBox;
  for (int i = 0; i < 3; ++i) {
    o.a[i] = -0.3 - 0.1 * i;
    o.b[i] = 0.4 + 0.05 * i;
  }
  return moved(o);
}

std::vector<ObstacleGeometry<double>> all_kinds() { return {plane(), sphere(), box()}; }

// A point at gap `g` from `o` along a random direction's projection: found
// by stepping along the normal from a random point outside.
std::vector<double> point_at_gap(const ObstacleGeometry<double>& o, double g, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-2, 2);
  for (;;) {
    std::vector<double> x = {u(rng), u(rng), u(rng)};
    Gap<double> gap = obstacle_gap(o, x.data());
    if (gap.g < 0.05) continue;
    for (int it = 0; it < 50; ++it) {
      gap = obstacle_gap(o, x.data());
      for (int i = 0; i < 3; ++i) x[i] += (g - gap.g) * gap.n[i];
    }
    if (std::abs(obstacle_gap(o, x.data()).g - g) < 1e-12) return x;
  }
}

double relative(double value, double reference, double scale) {
  return std::abs(value - reference) / std::max({std::abs(reference), scale, 1e-300});
}

TEST(ObstacleGap, NormalAndCurvatureAreTheGapsDerivatives) {
  std::mt19937 rng(7);
  for (const ObstacleGeometry<double>& o : all_kinds()) {
    for (int trial = 0; trial < 20; ++trial) {
      const std::vector<double> x = point_at_gap(o, 0.01 + 0.02 * trial, rng);
      const Gap<double> gap = obstacle_gap(o, x.data());
      EXPECT_NEAR(gap.n[0] * gap.n[0] + gap.n[1] * gap.n[1] + gap.n[2] * gap.n[2], 1.0, 1e-12);
      for (int j = 0; j < 3; ++j) {
        std::vector<double> xp = x, xm = x;
        xp[j] += kFdStep;
        xm[j] -= kFdStep;
        const Gap<double> gp = obstacle_gap(o, xp.data()), gm = obstacle_gap(o, xm.data());
        EXPECT_LT(relative(gap.n[j], (gp.g - gm.g) / (2 * kFdStep), 1.0), kTolerance)
            << "kind " << o.kind << " axis " << j;
        for (int i = 0; i < 3; ++i)
          EXPECT_LT(relative(gap.curvature[3 * i + j], (gp.n[i] - gm.n[i]) / (2 * kFdStep), 1.0),
                    1e-4)
              << "kind " << o.kind << " entry " << i << j;
      }
    }
  }
}

TEST(ObstacleGap, InsideIsNegative) {
  ObstacleGeometry<double> s = sphere();
  // The sphere's centre in the world: R a + c.
  double c[3];
  for (int i = 0; i < 3; ++i)
    c[i] = s.rotation[3 * i] * s.a[0] + s.rotation[3 * i + 1] * s.a[1] +
           s.rotation[3 * i + 2] * s.a[2] + s.shift[i];
  EXPECT_NEAR(obstacle_gap(s, c).g, -0.5, 1e-12);
  ObstacleGeometry<double> b = box();
  double inside[3];
  const double x0[3] = {0.3, -0.35, 0.0};  // in its own frame: 0.05 above the face y = -0.4
  for (int i = 0; i < 3; ++i)
    inside[i] = b.rotation[3 * i] * x0[0] + b.rotation[3 * i + 1] * x0[1] +
                b.rotation[3 * i + 2] * x0[2] + b.shift[i];
  EXPECT_NEAR(obstacle_gap(b, inside).g, -0.05, 1e-12);
}

TEST(Barrier, DerivativesAndSupport) {
  const double dh = 1e-2;
  for (double g : {1e-5, 1e-4, 1e-3, 5e-3, 9e-3}) {
    const BarrierValue<double> b = barrier(g, dh);
    const double h = g * 1e-5;
    const BarrierValue<double> p = barrier(g + h, dh), m = barrier(g - h, dh);
    EXPECT_LT(relative(b.first, (p.energy - m.energy) / (2 * h), 0.0), 1e-6) << g;
    EXPECT_LT(relative(b.second, (p.first - m.first) / (2 * h), 0.0), 1e-6) << g;
    EXPECT_GT(b.energy, 0);
    EXPECT_LT(b.first, 0);
    EXPECT_GT(b.second, 0);  // convex: the projected Hessian is PSD
  }
  EXPECT_EQ(barrier(dh, dh).energy, 0.0);
  EXPECT_EQ(barrier(2 * dh, dh).first, 0.0);
  EXPECT_TRUE(std::isinf(barrier(0.0, dh).energy));
  EXPECT_TRUE(std::isinf(barrier(-1e-3, dh).energy));
}

// One vertex against every kind of obstacle with friction lags in the
// sticking (|u| < eps_h) and sliding regimes.
struct VertexCase {
  std::vector<ObstacleGeometry<double>> obstacles;
  std::vector<FrictionLag<double>> lags;
  std::vector<double> x, xt;
};

VertexCase vertex_case(double slip, std::mt19937& rng) {
  VertexCase c;
  c.obstacles = all_kinds();
  // A point inside the activation distance of the plane.
  c.x = point_at_gap(c.obstacles[0], 0.004, rng);
  for (const ObstacleGeometry<double>& o : c.obstacles) {
    FrictionLag<double> lag{};
    const Gap<double> gap = obstacle_gap(o, c.x.data());
    lag.mu_lambda = 3.0;
    for (int i = 0; i < 3; ++i) {
      lag.n[i] = gap.n[i];
      lag.w[i] = 0.001 * (i + 1);
    }
    c.lags.push_back(lag);
  }
  std::uniform_real_distribution<double> u(-1, 1);
  c.xt = c.x;
  for (int i = 0; i < 3; ++i) c.xt[i] -= slip * u(rng) + c.lags[0].w[i];
  return c;
}

TEST(VertexContact, GradientAndExactHessianFromFiniteDifferences) {
  std::mt19937 rng(11);
  const double kappa = 50, dh = 0.01, eps_h = 1e-3;
  for (double slip : {2e-4, 5e-3}) {  // sticking and sliding against eps_h
    for (int trial = 0; trial < 10; ++trial) {
      const VertexCase c = vertex_case(slip, rng);
      const ContactTerms<double> t = vertex_contact(c.obstacles.data(), c.lags.data(), 3, kappa, dh,
                                                    eps_h, c.x.data(), c.xt.data(), true);
      ASSERT_GT(t.energy, 0);
      double grad_scale = 0, hess_scale = 0;
      for (int i = 0; i < 3; ++i) grad_scale = std::max(grad_scale, std::abs(t.grad[i]));
      for (int i = 0; i < 9; ++i) hess_scale = std::max(hess_scale, std::abs(t.hess[i]));
      for (int j = 0; j < 3; ++j) {
        std::vector<double> xp = c.x, xm = c.x;
        const double h = 1e-7;
        xp[j] += h;
        xm[j] -= h;
        const ContactTerms<double> p = vertex_contact(c.obstacles.data(), c.lags.data(), 3, kappa,
                                                      dh, eps_h, xp.data(), c.xt.data(), true);
        const ContactTerms<double> m = vertex_contact(c.obstacles.data(), c.lags.data(), 3, kappa,
                                                      dh, eps_h, xm.data(), c.xt.data(), true);
        EXPECT_LT(relative(t.grad[j], (p.energy - m.energy) / (2 * h), grad_scale), 1e-5)
            << "slip " << slip << " axis " << j;
        for (int i = 0; i < 3; ++i)
          EXPECT_LT(relative(t.hess[3 * i + j], (p.grad[i] - m.grad[i]) / (2 * h), hess_scale),
                    1e-5)
              << "slip " << slip << " entry " << i << j;
      }
    }
  }
}

// A float run's checks judge the contact energy of its float state in
// double (loops::contact_energy): equal to the double terms of the widened
// float data to double's round-off, where float's own evaluation is off by
// float's (~1e-7).
TEST(ContactEnergy, FloatDataIsEvaluatedInDouble) {
  std::mt19937 rng(5);
  const float kappa = 50, dh = 0.01f, eps_h = 1e-3f;
  for (double slip : {2e-4, 5e-3}) {
    for (int trial = 0; trial < 10; ++trial) {
      const VertexCase c = vertex_case(slip, rng);
      std::vector<ObstacleGeometry<float>> obstacles;
      std::vector<ObstacleGeometry<double>> wide_obstacles;
      for (const ObstacleGeometry<double>& o : c.obstacles) {
        ObstacleGeometry<float> f{};
        f.kind = o.kind;
        for (int i = 0; i < 3; ++i) {
          f.a[i] = static_cast<float>(o.a[i]);
          f.b[i] = static_cast<float>(o.b[i]);
          f.shift[i] = static_cast<float>(o.shift[i]);
        }
        f.radius = static_cast<float>(o.radius);
        for (int i = 0; i < 9; ++i) f.rotation[i] = static_cast<float>(o.rotation[i]);
        obstacles.push_back(f);
        wide_obstacles.push_back(in_double(f));
      }
      std::vector<FrictionLag<float>> lags;
      std::vector<FrictionLag<double>> wide_lags;
      for (const FrictionLag<double>& l : c.lags) {
        FrictionLag<float> f{static_cast<float>(l.mu_lambda), {}, {}};
        for (int i = 0; i < 3; ++i) {
          f.n[i] = static_cast<float>(l.n[i]);
          f.w[i] = static_cast<float>(l.w[i]);
        }
        lags.push_back(f);
        wide_lags.push_back(in_double(f));
      }
      const std::vector<float> x(c.x.begin(), c.x.end()), xt(c.xt.begin(), c.xt.end());
      const std::vector<double> wide_x(x.begin(), x.end()), wide_xt(xt.begin(), xt.end());
      const index_t vertex = 0;
      ContactView<float> view;
      view.num_obstacles = 3;
      view.obstacles = obstacles.data();
      view.num_vertices = view.num_owned = 1;
      view.vertices = &vertex;
      view.kappa = &kappa;
      view.lags = lags.data();
      view.dh = dh;
      view.eps_h = eps_h;
      HostExec host;
      const double got = loops::contact_energy(host, 0, view, x.data(), xt.data()).value;
      const double want =
          vertex_contact(wide_obstacles.data(), wide_lags.data(), 3, double(kappa), double(dh),
                         double(eps_h), wide_x.data(), wide_xt.data(), false)
              .energy;
      ASSERT_GT(want, 0);
      EXPECT_NEAR(got, want, 1e-14 * want) << "slip " << slip << " trial " << trial;
    }
  }
}

TEST(VertexContact, ProjectedHessianIsPositiveSemiDefinite) {
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> u(-1, 1);
  for (double slip : {2e-4, 5e-3}) {
    const VertexCase c = vertex_case(slip, rng);
    const ContactTerms<double> t = vertex_contact(c.obstacles.data(), c.lags.data(), 3, 50.0, 0.01,
                                                  1e-3, c.x.data(), c.xt.data(), false);
    for (int trial = 0; trial < 200; ++trial) {
      const double p[3] = {u(rng), u(rng), u(rng)};
      double php = 0;
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) php += p[i] * t.hess[3 * i + j] * p[j];
      EXPECT_GE(php, -1e-9 * (std::abs(t.hess[0]) + std::abs(t.hess[4]) + std::abs(t.hess[8])));
    }
  }
}

// The friction's diagonal comes from a majorant: the quadratic with its
// gradient and Hessian at s lies above mu lambda f0 along any move (so a
// Jacobi step from it cannot overshoot the sticking core), its Hessian is at
// least the exact one, and in the sticking core's centre they agree.
TEST(FrictionMajorant, LiesAboveTheFrictionAndItsExactHessian) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  const double mu_lambda = 3.0, eps_h = 1e-3;
  const double n[3] = {0.36, 0.48, 0.8};
  for (double slip : {0.0, 3e-4, 9e-4, 2e-3, 5e-2}) {  // sticking to sliding
    for (int trial = 0; trial < 50; ++trial) {
      double s[3];
      for (double& c : s) c = slip * u(rng);
      const ContactTerms<double> exact = friction_on_slip(mu_lambda, n, eps_h, s, true);
      const ContactTerms<double> major = friction_on_slip(mu_lambda, n, eps_h, s, false);
      for (int i = 0; i < 3; ++i) EXPECT_EQ(major.grad[i], exact.grad[i]);
      const double scale = mu_lambda * std::max(slip, eps_h);
      for (double reach : {1e-4, 1e-3, 1e-2, 1e-1}) {
        double d[3], ds[3], gd = 0, dmd = 0, ddiff = 0;
        for (int i = 0; i < 3; ++i) {
          d[i] = reach * u(rng);
          ds[i] = s[i] + d[i];
          gd += major.grad[i] * d[i];
        }
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j) {
            dmd += d[i] * major.hess[3 * i + j] * d[j];
            ddiff += d[i] * (major.hess[3 * i + j] - exact.hess[3 * i + j]) * d[j];
          }
        const double moved = friction_on_slip(mu_lambda, n, eps_h, ds, false).energy;
        EXPECT_LE(moved, major.energy + gd + 0.5 * dmd + 1e-12 * scale)
            << "slip " << slip << " reach " << reach;
        EXPECT_GE(ddiff, -1e-12 * mu_lambda / eps_h * reach * reach);
      }
    }
  }
  const double centre[3] = {0, 0, 0};
  const ContactTerms<double> exact = friction_on_slip(mu_lambda, n, eps_h, centre, true);
  const ContactTerms<double> major = friction_on_slip(mu_lambda, n, eps_h, centre, false);
  for (int k = 0; k < 9; ++k) EXPECT_EQ(major.hess[k], exact.hess[k]);
}

TEST(GuardMove, NoGuardedMoveEndsInside) {
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> u(-1, 1);
  const std::vector<ObstacleGeometry<double>> obstacles = all_kinds();
  const double dh = 1e-3, least = kLeastGap<double> * dh;
  int cut = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    std::vector<double> x = {2 * u(rng), 2 * u(rng), 2 * u(rng)};
    bool outside = true;
    for (const auto& o : obstacles) outside = outside && obstacle_gap(o, x.data()).g > 0;
    if (!outside) continue;
    const double size = std::pow(10.0, 3 * u(rng) - 1);
    double d[3] = {size * u(rng), size * u(rng), size * u(rng)};
    const double original[3] = {d[0], d[1], d[2]};
    guard_move(obstacles.data(), 3, x.data(), kGapKept<double>, least, 0u, d);
    const double end[3] = {x[0] + d[0], x[1] + d[1], x[2] + d[2]};
    bool changed = false;
    for (int i = 0; i < 3; ++i) changed = changed || d[i] != original[i];
    cut += changed;
    for (const auto& o : obstacles) {
      const double before = obstacle_gap(o, x.data()).g, after = obstacle_gap(o, end).g;
      EXPECT_GT(after, 0) << "trial " << trial;
      const double kept = std::min(before, std::max(kGapKept<double> * before, least));
      EXPECT_GE(after, kept * (1 - 1e-9)) << "trial " << trial;
    }
  }
  EXPECT_GT(cut, 1000);  // the guard was exercised
}

TEST(GuardMove, HeldAxesStayAndFreeMovesPass) {
  const std::vector<ObstacleGeometry<double>> obstacles = {plane()};
  std::mt19937 rng(19);
  const std::vector<double> at = point_at_gap(obstacles[0], 0.01, rng);
  const double* x = at.data();
  const double g = 0.01;
  const Gap<double> gap = obstacle_gap(obstacles[0], x);
  // Away from the plane: untouched, bit for bit.
  double away[3] = {gap.n[0] * 0.3 + 1e-3, gap.n[1] * 0.3, gap.n[2] * 0.3};
  const double copy[3] = {away[0], away[1], away[2]};
  guard_move(obstacles.data(), 1, x, kGapKept<double>, 1e-9, 0u, away);
  for (int i = 0; i < 3; ++i) EXPECT_EQ(away[i], copy[i]);
  // Into it with y held: y does not move.
  double into[3] = {-gap.n[0] * 10 * g, -gap.n[1] * 10 * g, -gap.n[2] * 10 * g};
  guard_move(obstacles.data(), 1, x, kGapKept<double>, 1e-9, 2u, into);
  EXPECT_EQ(into[1], 0.0);
  const double end[3] = {x[0] + into[0], x[1] + into[1], x[2] + into[2]};
  EXPECT_GE(obstacle_gap(obstacles[0], end).g, kGapKept<double> * g * (1 - 1e-9));
  // A diverged move (inf or NaN) is none.
  for (double bad : {double(INFINITY), double(NAN), 1e300}) {
    double diverged[3] = {bad, -gap.n[1], 0.0};
    guard_move(obstacles.data(), 1, x, kGapKept<double>, 1e-9, 0u, diverged);
    for (int i = 0; i < 3; ++i) EXPECT_EQ(diverged[i], 0.0) << bad;
  }
}

}  // namespace
}  // namespace descent
