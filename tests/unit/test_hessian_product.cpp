// element_hessian_product (kernels/element_hessian_product.hpp) against
// central differences of the element gradient along the same direction, and
// against the 12x12 element_hessian times the direction, for four models on
// random elements (stretched up to |F - I| ~ 0.5); and the projective-
// dynamics diagonal (kernels/projective_dynamics.hpp) against FD curvature.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include "kernels/arap.hpp"
#include "kernels/conversion.hpp"
#include "kernels/corotated.hpp"
#include "kernels/element.hpp"
#include "kernels/element_hessian_product.hpp"
#include "kernels/neo_hookean.hpp"
#include "kernels/projective_dynamics.hpp"
#include "kernels/stvk.hpp"
#include "random_element.hpp"

namespace descent {
namespace {

using Rng = std::mt19937_64;

using testing::random_element;

template <class Model>
void check_model(const Model& model, const char* name) {
  Rng rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  double worst_fd = 0, worst_matrix = 0;
  for (double amp : {0.02, 0.2, 0.5}) {
    for (int sample = 0; sample < 300; ++sample) {
      const testing::ElementCase e = random_element(rng, amp);
      Vec3<double> p[4], hp[4];
      for (auto& v : p) v = {u(rng), u(rng), u(rng)};
      element_hessian_product(model, e.rest, e.x, p, hp);

      // Central differences of the gradient along p.
      const double step = 1e-6;
      TetCorners<double> xp = e.x, xm = e.x;
      for (int a = 0; a < 4; ++a) {
        xp.x[a] = {e.x.x[a].x + step * p[a].x, e.x.x[a].y + step * p[a].y,
                   e.x.x[a].z + step * p[a].z};
        xm.x[a] = {e.x.x[a].x - step * p[a].x, e.x.x[a].y - step * p[a].y,
                   e.x.x[a].z - step * p[a].z};
      }
      Vec3<double> gp[4], gm[4];
      element_gradient(model, e.rest, xp, gp);
      element_gradient(model, e.rest, xm, gm);
      double h[144];
      element_hessian(model, e.rest, e.x, h);
      const double pv[12] = {p[0].x, p[0].y, p[0].z, p[1].x, p[1].y, p[1].z,
                             p[2].x, p[2].y, p[2].z, p[3].x, p[3].y, p[3].z};
      double scale = 0, fd_err = 0, matrix_err = 0;
      for (int a = 0; a < 4; ++a) {
        const double got[3] = {hp[a].x, hp[a].y, hp[a].z};
        const double fd[3] = {(gp[a].x - gm[a].x) / (2 * step), (gp[a].y - gm[a].y) / (2 * step),
                              (gp[a].z - gm[a].z) / (2 * step)};
        for (int i = 0; i < 3; ++i) {
          double hv = 0;
          for (int s = 0; s < 12; ++s) hv += h[(3 * a + i) * 12 + s] * pv[s];
          scale = std::max(scale, std::abs(fd[i]));
          fd_err = std::max(fd_err, std::abs(got[i] - fd[i]));
          matrix_err = std::max(matrix_err, std::abs(got[i] - hv));
        }
      }
      worst_fd = std::max(worst_fd, fd_err / scale);
      worst_matrix = std::max(worst_matrix, matrix_err / scale);
    }
  }
  std::printf("%-12s H p vs FD of gradient: %.2e, vs 12x12 H times p: %.2e (normwise)\n", name,
              worst_fd, worst_matrix);
  EXPECT_LE(worst_fd, 1e-6) << name;
  EXPECT_LE(worst_matrix, 1e-12) << name;
}

// The hybrid product of model conversion (kernels/conversion.hpp) at a
// fixed interpolant l: central differences of the blended gradient
// (1 - l) grad Psi + l grad Psi_arap, and at l = 0 and 1 the plain products.
TEST(ConvertedHessianProduct, IsTheProductOfTheBlendAtAFixedInterpolant) {
  Rng rng(17);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const NeoHookean<double> model = NeoHookean<double>::from_young_poisson(1e6, 0.3);
  const Conversion<double> conv{0.05, 0.15, 0.05, Arap<double>::from_young_poisson(1e6, 0.3)};
  double worst = 0, worst_ends = 0;
  for (double l : {0.0, 0.3, 0.7, 1.0}) {
    for (int sample = 0; sample < 200; ++sample) {
      const testing::ElementCase e = random_element(rng, 0.3);
      Vec3<double> p[4], hp[4];
      for (auto& v : p) v = {u(rng), u(rng), u(rng)};
      converted_hessian_product(model, conv, l, e.rest, e.x, p, hp);
      auto blended_gradient = [&](double sign, Vec3<double> g[4]) {
        const double step = 1e-6;
        TetCorners<double> x = e.x;
        for (int a = 0; a < 4; ++a)
          x.x[a] = {e.x.x[a].x + sign * step * p[a].x, e.x.x[a].y + sign * step * p[a].y,
                    e.x.x[a].z + sign * step * p[a].z};
        Vec3<double> gm[4], ga[4];
        element_gradient(model, e.rest, x, gm);
        element_gradient(conv.arap, e.rest, x, ga);
        for (int a = 0; a < 4; ++a)
          g[a] = {(1 - l) * gm[a].x + l * ga[a].x, (1 - l) * gm[a].y + l * ga[a].y,
                  (1 - l) * gm[a].z + l * ga[a].z};
        return step;
      };
      Vec3<double> gp[4], gm[4];
      const double step = blended_gradient(+1, gp);
      blended_gradient(-1, gm);
      // At the ends the blend is one model's product, bit for bit.
      Vec3<double> plain[4] = {};
      if (l == 0.0) element_hessian_product(model, e.rest, e.x, p, plain);
      if (l == 1.0) element_hessian_product(conv.arap, e.rest, e.x, p, plain);
      double scale = 0, err = 0, err_end = 0;
      for (int a = 0; a < 4; ++a) {
        const double got[3] = {hp[a].x, hp[a].y, hp[a].z};
        const double fd[3] = {(gp[a].x - gm[a].x) / (2 * step), (gp[a].y - gm[a].y) / (2 * step),
                              (gp[a].z - gm[a].z) / (2 * step)};
        const double base[3] = {plain[a].x, plain[a].y, plain[a].z};
        for (int i = 0; i < 3; ++i) {
          scale = std::max(scale, std::abs(fd[i]));
          err = std::max(err, std::abs(got[i] - fd[i]));
          if (l == 0.0 || l == 1.0) err_end = std::max(err_end, std::abs(got[i] - base[i]));
        }
      }
      worst = std::max(worst, err / scale);
      worst_ends = std::max(worst_ends, err_end / scale);
    }
  }
  std::printf(
      "converted H p vs FD of the blended gradient: %.2e; at l = 0, 1 vs one model's: %.2e\n",
      worst, worst_ends);
  EXPECT_LE(worst, 1e-6);
  EXPECT_EQ(worst_ends, 0.0);
}

TEST(ElementHessianProduct, MatchesFiniteDifferencesAndTheMatrix) {
  check_model(NeoHookean<double>::from_young_poisson(1e6, 0.3), "neo_hookean");
  check_model(StVK<double>::from_young_poisson(1e6, 0.3), "stvk");
  check_model(Corotated<double>::from_young_poisson(1e6, 0.3), "corotated");
  check_model(Arap<double>::from_young_poisson(1e6, 0.3), "arap");
}

}  // namespace
}  // namespace descent

namespace descent {
namespace {

// pd_element_diagonal against central second differences of V mu |F - R|^2
// with R a fixed rotation (the quadratic projective-dynamics energy).
TEST(ProjectiveDynamics, DiagonalIsTheCurvatureOfTheQuadraticEnergy) {
  Rng rng(5);
  const Arap<double> model = Arap<double>::from_young_poisson(1e6, 0.3);
  const Mat3<double> r = {{0.36, 0.48, -0.8, -0.8, 0.6, 0.0, 0.48, 0.64, 0.6}};  // a rotation
  double worst = 0;
  for (int sample = 0; sample < 200; ++sample) {
    const testing::ElementCase e = random_element(rng, 0.3);
    auto energy = [&](const TetCorners<double>& x) {
      const Mat3<double> f = deformation_gradient(x.x[0], x.x[1], x.x[2], x.x[3], e.rest.dm_inv);
      double s = 0;
      for (int k = 0; k < 9; ++k) s += (f.m[k] - r.m[k]) * (f.m[k] - r.m[k]);
      return e.rest.volume * model.mu * s;
    };
    Vec3<double> diag[4];
    pd_element_diagonal(model, e.rest, diag);
    const double step = 1e-3;  // exact for a quadratic up to round-off
    for (int a = 0; a < 4; ++a)
      for (int i = 0; i < 3; ++i) {
        TetCorners<double> xp = e.x, xm = e.x;
        double* cp = i == 0 ? &xp.x[a].x : (i == 1 ? &xp.x[a].y : &xp.x[a].z);
        double* cm = i == 0 ? &xm.x[a].x : (i == 1 ? &xm.x[a].y : &xm.x[a].z);
        *cp += step;
        *cm -= step;
        const double fd = (energy(xp) - 2 * energy(e.x) + energy(xm)) / (step * step);
        const double got = i == 0 ? diag[a].x : (i == 1 ? diag[a].y : diag[a].z);
        worst = std::max(worst, std::abs(got - fd) / std::abs(fd));
      }
  }
  std::printf("pd diagonal vs FD curvature: worst relative %.2e\n", worst);
  EXPECT_LE(worst, 1e-6);
}

}  // namespace
}  // namespace descent
