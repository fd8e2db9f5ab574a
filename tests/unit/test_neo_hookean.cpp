// Neo-Hookean energy, stress and Hessian diagonal against central finite
// differences, on one element and on many random deformations (mild and
// large), plus Psi(I) = 0, P(I) = 0 and rotation invariance.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "kernels/element.hpp"
#include "kernels/neo_hookean.hpp"

namespace descent {
namespace {

using Model = NeoHookean<double>;
const Model kModel = Model::from_young_poisson(1.0e5, 0.4);

Mat3<double> identity() { return {{1, 0, 0, 0, 1, 0, 0, 0, 1}}; }

// Random F = R S-ish with det > 0: identity plus a perturbation of size `amp`,
// redrawn until well away from inversion.
Mat3<double> random_f(std::mt19937_64& rng, double amp) {
  std::uniform_real_distribution<double> u(-amp, amp);
  for (;;) {
    Mat3<double> f = identity();
    for (double& v : f.m) v += u(rng);
    if (det(f) > 0.2) return f;
  }
}

Mat3<double> rotation(double ax, double ay, double az) {
  const Mat3<double> rx{{1, 0, 0, 0, std::cos(ax), -std::sin(ax), 0, std::sin(ax), std::cos(ax)}};
  const Mat3<double> ry{{std::cos(ay), 0, std::sin(ay), 0, 1, 0, -std::sin(ay), 0, std::cos(ay)}};
  const Mat3<double> rz{{std::cos(az), -std::sin(az), 0, std::sin(az), std::cos(az), 0, 0, 0, 1}};
  return mul(rz, mul(ry, rx));
}

// Error relative to the larger of the entry and `scale` (the norm of the
// whole stress or gradient, so tiny entries are not judged by round-off).
double rel_err(double got, double want, double scale) {
  return std::abs(got - want) / std::max({std::abs(want), std::abs(got), scale});
}

TEST(NeoHookean, RestStateHasZeroEnergyAndStress) {
  EXPECT_NEAR(kModel.energy(identity()), 0.0, 1e-9);
  const Mat3<double> p = kModel.stress(identity());
  for (double v : p.m) EXPECT_NEAR(v, 0.0, 1e-9);
}

TEST(NeoHookean, SmallStrainLimitIsLinearElasticity) {
  // Uniaxial small strain e along x with free lateral contraction -nu e gives
  // sigma_xx = E e; the neo-Hookean P_xx at that F must match to O(e^2).
  const double e = 1e-6, nu = 0.4;
  const Mat3<double> f{{1 + e, 0, 0, 0, 1 - nu * e, 0, 0, 0, 1 - nu * e}};
  EXPECT_NEAR(kModel.stress(f)(0, 0) / e, 1.0e5, 1.0e5 * 1e-4);
  EXPECT_NEAR(kModel.stress(f)(1, 1) / e, 0.0, 1.0e5 * 1e-4);
}

TEST(NeoHookean, StressMatchesFiniteDifferencesOfEnergy) {
  std::mt19937_64 rng(7);
  double worst = 0;
  for (double amp : {0.05, 0.3, 0.8}) {
    for (int sample = 0; sample < 2000; ++sample) {
      const Mat3<double> f = random_f(rng, amp);
      const Mat3<double> p = kModel.stress(f);
      const double p_norm = std::sqrt(ddot(p, p));
      for (int k = 0; k < 9; ++k) {
        const double h = 1e-6;
        Mat3<double> fp = f, fm = f;
        fp.m[k] += h;
        fm.m[k] -= h;
        const double fd = (kModel.energy(fp) - kModel.energy(fm)) / (2 * h);
        worst = std::max(worst, rel_err(p.m[k], fd, p_norm));
      }
    }
  }
  EXPECT_LE(worst, 1e-6);
}

TEST(NeoHookean, EnergyIsRotationInvariant) {
  std::mt19937_64 rng(11);
  for (int sample = 0; sample < 1000; ++sample) {
    const Mat3<double> f = random_f(rng, 0.6);
    const Mat3<double> r = rotation(rng() % 1000 * 0.01, rng() % 1000 * 0.01, rng() % 1000 * 0.01);
    EXPECT_NEAR(kModel.energy(mul(r, f)), kModel.energy(f), 1e-9 * (1 + kModel.energy(f)));
  }
}

// A random tet with positive rest volume and a random deformed position.
struct ElementCase {
  TetRest<double> rest;
  TetCorners<double> x;
};

ElementCase random_element(std::mt19937_64& rng, double amp) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const Vec3<double> base[4] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  for (;;) {
    TetCorners<double> rest_x, x;
    for (int a = 0; a < 4; ++a) {
      rest_x.x[a] = {base[a].x + 0.2 * u(rng), base[a].y + 0.2 * u(rng), base[a].z + 0.2 * u(rng)};
      x.x[a] = {rest_x.x[a].x + amp * u(rng), rest_x.x[a].y + amp * u(rng),
                rest_x.x[a].z + amp * u(rng)};
    }
    const TetRest<double> rest = tet_rest(rest_x.x[0], rest_x.x[1], rest_x.x[2], rest_x.x[3]);
    const double j = det(deformation_gradient(x.x[0], x.x[1], x.x[2], x.x[3], rest.dm_inv));
    if (rest.volume > 0.05 && j > 0.2) return {rest, x};
  }
}

double& coord(TetCorners<double>& c, int a, int i) {
  return i == 0 ? c.x[a].x : (i == 1 ? c.x[a].y : c.x[a].z);
}
double coord(const Vec3<double>& v, int i) { return i == 0 ? v.x : (i == 1 ? v.y : v.z); }

TEST(NeoHookean, ElementGradientMatchesFiniteDifferences) {
  std::mt19937_64 rng(3);
  double worst = 0;
  for (double amp : {0.02, 0.2, 0.5}) {
    for (int sample = 0; sample < 1000; ++sample) {
      ElementCase e = random_element(rng, amp);
      Vec3<double> g[4];
      element_gradient(kModel, e.rest, e.x, g);
      double gnorm = 0;
      for (int a = 0; a < 4; ++a) gnorm += dot(g[a], g[a]);
      for (int a = 0; a < 4; ++a) {
        for (int i = 0; i < 3; ++i) {
          const double h = 1e-6;
          TetCorners<double> xp = e.x, xm = e.x;
          coord(xp, a, i) += h;
          coord(xm, a, i) -= h;
          const double fd =
              (element_energy(kModel, e.rest, xp) - element_energy(kModel, e.rest, xm)) / (2 * h);
          worst = std::max(worst, rel_err(coord(g[a], i), fd, std::sqrt(gnorm)));
        }
      }
    }
  }
  EXPECT_LE(worst, 1e-6);
}

TEST(NeoHookean, HessianDiagonalMatchesFiniteDifferencesOfGradient) {
  std::mt19937_64 rng(5);
  double worst = 0;
  for (double amp : {0.02, 0.2, 0.5}) {
    for (int sample = 0; sample < 1000; ++sample) {
      ElementCase e = random_element(rng, amp);
      Vec3<double> d[4];
      element_hessian_diagonal(kModel, e.rest, e.x, d);
      for (int a = 0; a < 4; ++a) {
        for (int i = 0; i < 3; ++i) {
          const double h = 1e-6;
          TetCorners<double> xp = e.x, xm = e.x;
          coord(xp, a, i) += h;
          coord(xm, a, i) -= h;
          Vec3<double> gp[4], gm[4];
          element_gradient(kModel, e.rest, xp, gp);
          element_gradient(kModel, e.rest, xm, gm);
          const double fd = (coord(gp[a], i) - coord(gm[a], i)) / (2 * h);
          worst = std::max(worst, rel_err(coord(d[a], i), fd, 1e-3 * kModel.mu * e.rest.volume));
        }
      }
    }
  }
  EXPECT_LE(worst, 1e-6);
}

}  // namespace
}  // namespace descent
