// The corotated linear element of paper 2 (kernels/corotated_linear.hpp):
// the polar sweeps give a rotation that symmetrises F; the gradient is the
// central difference of the energy, the stiffness product the central
// difference of the gradient (Q fixed), the diagonal the product on unit
// vectors; and with the converged polar factor the gradient equals the
// nonlinear corotated model's (kernels/corotated.hpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <random>

#include "kernels/corotated_linear.hpp"
#include "random_element.hpp"

namespace descent {
namespace {

using testing::random_element;

const Corotated<double> kModel = Corotated<double>::from_young_poisson(1e5, 0.4);

Mat3<double> element_f(const testing::ElementCase& e) {
  return deformation_gradient(e.x.x[0], e.x.x[1], e.x.x[2], e.x.x[3], e.rest.dm_inv);
}

TetCorners<double> moved(const TetCorners<double>& x, const Vec3<double> p[4], double t) {
  TetCorners<double> y = x;
  for (int a = 0; a < 4; ++a)
    y.x[a] = {x.x[a].x + t * p[a].x, x.x[a].y + t * p[a].y, x.x[a].z + t * p[a].z};
  return y;
}

double component(const Vec3<double>& v, int i) { return i == 0 ? v.x : i == 1 ? v.y : v.z; }

struct PolarQuality {
  double orthogonality = 0, det_error = 0, asymmetry = 0;
  int most_sweeps = 0;
};

// Worst |Q^T Q - I|, |det Q - 1|, |Q^T F - F^T Q| / |F| over `samples`
// random elements with det F in [det_min, det_max].
PolarQuality polar_quality(std::uint64_t seed, double det_min, double det_max, int max_sweeps) {
  std::mt19937_64 rng(seed);
  PolarQuality worst;
  for (int sample = 0; sample < 500; ++sample) {
    const Mat3<double> f = element_f(random_element(rng, 0.6, det_min, det_max));
    int sweeps = 0;
    const Mat3<double> q = polar_rotation(f, max_sweeps, &sweeps);
    worst.most_sweeps = std::max(worst.most_sweeps, sweeps);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        double qtq = 0, sij = 0, sji = 0;
        for (int k = 0; k < 3; ++k) {
          qtq += q.m[3 * k + i] * q.m[3 * k + j];
          sij += q.m[3 * k + i] * f.m[3 * k + j];
          sji += q.m[3 * k + j] * f.m[3 * k + i];
        }
        worst.orthogonality = std::max(worst.orthogonality, std::abs(qtq - (i == j ? 1.0 : 0.0)));
        worst.asymmetry = std::max(worst.asymmetry, std::abs(sij - sji) / std::sqrt(ddot(f, f)));
      }
    worst.det_error = std::max(worst.det_error, std::abs(det(q) - 1));
  }
  return worst;
}

// Prints the quality and checks that Q is a rotation.
void expect_rotation(const char* range, const PolarQuality& w) {
  std::printf(
      "polar, det F in %s: |Q^T Q - I| %.1e, |det Q - 1| %.1e, asymmetry %.1e after <= %d "
      "sweeps\n",
      range, w.orthogonality, w.det_error, w.asymmetry, w.most_sweeps);
  EXPECT_LE(w.orthogonality, 1e-13) << range;
  EXPECT_LE(w.det_error, 1e-13) << range;
}

TEST(CorotatedLinear, PolarSweepsConvergeToARotationThatSymmetrisesF) {
  const PolarQuality w = polar_quality(3, 0.2, 3.0, 100);
  expect_rotation("[0.2, 3]", w);
  EXPECT_LE(w.asymmetry, 1e-12);
  EXPECT_LT(w.most_sweeps, 100);  // converged before the limit
}

// Cyclic Jacobi converges only linearly, slowly where sigma_i + sigma_j is
// small (inverted or nearly flat elements): the sweep limit binds there, and
// Q must still be a rotation.
TEST(CorotatedLinear, PolarSweepsStayARotationForInvertedElements) {
  const PolarQuality w = polar_quality(4, -0.5, 0.0, 100);
  expect_rotation("[-0.5, 0]", w);
  EXPECT_LE(w.asymmetry, 1e-3);
}

TEST(CorotatedLinear, OneSweepAlreadyRemovesMostAsymmetry) {
  // Paper 2, §3.3: the decomposition is "symmetric enough" after one sweep.
  std::mt19937_64 rng(5);
  double before = 0, after = 0;
  for (int sample = 0; sample < 300; ++sample) {
    const Mat3<double> f = element_f(random_element(rng, 0.3));
    const Mat3<double> q = polar_rotation(f, 1);
    for (int i = 0; i < 3; ++i)
      for (int j = i + 1; j < 3; ++j) {
        before += std::abs(f.m[3 * i + j] - f.m[3 * j + i]);
        double sij = 0, sji = 0;
        for (int k = 0; k < 3; ++k) {
          sij += q.m[3 * k + i] * f.m[3 * k + j];
          sji += q.m[3 * k + j] * f.m[3 * k + i];
        }
        after += std::abs(sij - sji);
      }
  }
  std::printf("asymmetry of Q^T F after one sweep: %.3f of F's\n", after / before);
  EXPECT_LT(after, 0.1 * before);
}

TEST(CorotatedLinear, GradientProductAndDiagonalMatchFiniteDifferences) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  double worst_gradient = 0, worst_product = 0, worst_diagonal = 0, worst_symmetry = 0;
  for (double amp : {0.02, 0.2, 0.5}) {
    for (int sample = 0; sample < 200; ++sample) {
      const auto e = random_element(rng, amp);
      // Q from one sweep: K must be the derivative for any fixed Q.
      const Mat3<double> q = polar_rotation(element_f(e), 1 + sample % 3);
      Vec3<double> p[4], w[4], g[4], kp[4], kw[4], diag[4];
      for (auto& v : p) v = {u(rng), u(rng), u(rng)};
      for (auto& v : w) v = {u(rng), u(rng), u(rng)};
      corotated_linear_gradient(kModel, e.rest, q, e.x, g);
      corotated_linear_product(kModel, e.rest, q, p, kp);
      corotated_linear_product(kModel, e.rest, q, w, kw);
      corotated_linear_diagonal(kModel, e.rest, q, diag);

      const double step = 1e-6;
      const double de = (corotated_linear_energy(kModel, e.rest, q, moved(e.x, p, step)) -
                         corotated_linear_energy(kModel, e.rest, q, moved(e.x, p, -step))) /
                        (2 * step);
      double gp = 0, scale_g = 0;
      for (int a = 0; a < 4; ++a) {
        gp += dot(g[a], p[a]);
        scale_g += std::sqrt(dot(g[a], g[a]) * dot(p[a], p[a]));
      }
      worst_gradient = std::max(worst_gradient, std::abs(gp - de) / scale_g);

      Vec3<double> gplus[4], gminus[4];
      corotated_linear_gradient(kModel, e.rest, q, moved(e.x, p, step), gplus);
      corotated_linear_gradient(kModel, e.rest, q, moved(e.x, p, -step), gminus);
      double scale = 0, err = 0;
      for (int a = 0; a < 4; ++a)
        for (int i = 0; i < 3; ++i) {
          const double fd = (component(gplus[a], i) - component(gminus[a], i)) / (2 * step);
          scale = std::max(scale, std::abs(fd));
          err = std::max(err, std::abs(component(kp[a], i) - fd));
        }
      worst_product = std::max(worst_product, err / scale);

      // Symmetry: w.K p = p.K w.
      double wkp = 0, pkw = 0, mag = 0;
      for (int a = 0; a < 4; ++a) {
        wkp += dot(w[a], kp[a]);
        pkw += dot(p[a], kw[a]);
        mag += std::abs(dot(w[a], kp[a]));
      }
      worst_symmetry = std::max(worst_symmetry, std::abs(wkp - pkw) / mag);

      // Diagonal: e_(a i) . K e_(a i).
      for (int a = 0; a < 4; ++a)
        for (int i = 0; i < 3; ++i) {
          Vec3<double> unit[4] = {}, k_unit[4];
          unit[a] = {i == 0 ? 1.0 : 0.0, i == 1 ? 1.0 : 0.0, i == 2 ? 1.0 : 0.0};
          corotated_linear_product(kModel, e.rest, q, unit, k_unit);
          const double exact = component(k_unit[a], i);
          EXPECT_GT(exact, 0);
          worst_diagonal =
              std::max(worst_diagonal, std::abs(component(diag[a], i) - exact) / exact);
        }
    }
  }
  std::printf(
      "corotated linear: gradient vs FD %.1e, K p vs FD %.1e, diagonal %.1e, "
      "asymmetry of K %.1e\n",
      worst_gradient, worst_product, worst_diagonal, worst_symmetry);
  EXPECT_LE(worst_gradient, 1e-8);
  EXPECT_LE(worst_product, 1e-7);
  EXPECT_LE(worst_diagonal, 1e-12);
  EXPECT_LE(worst_symmetry, 1e-12);
}

TEST(CorotatedLinear, ConvergedPolarGivesTheCorotatedModelsGradient) {
  std::mt19937_64 rng(9);
  double worst = 0;
  for (int sample = 0; sample < 300; ++sample) {
    const auto e = random_element(rng, 0.4);
    const Mat3<double> q = polar_rotation(element_f(e), 50);
    Vec3<double> linear[4], nonlinear[4];
    corotated_linear_gradient(kModel, e.rest, q, e.x, linear);
    element_gradient(kModel, e.rest, e.x, nonlinear);
    double scale = 0, err = 0;
    for (int a = 0; a < 4; ++a)
      for (int i = 0; i < 3; ++i) {
        scale = std::max(scale, std::abs(component(nonlinear[a], i)));
        err = std::max(err, std::abs(component(linear[a], i) - component(nonlinear[a], i)));
      }
    worst = std::max(worst, err / scale);
  }
  std::printf("converged corotated linear vs corotated gradient: %.1e\n", worst);
  EXPECT_LE(worst, 1e-10);
}

}  // namespace
}  // namespace descent
