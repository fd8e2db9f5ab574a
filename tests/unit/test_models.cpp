// Every energy-density model (stvk, neo_hookean, mooney_rivlin, fung,
// corotated, arap) against central finite differences: stress from energy,
// stress derivative dPdF from stress, the 12x12 element Hessian and the
// Hessian diagonal from element gradients; plus the rest state, rotation
// invariance, the small-strain uniaxial slope, repeated singular values, the
// PSD projection, inverted elements and a float build. Errors are normwise:
// an entry's error over the larger of the entry and the norm of the whole
// stress or Hessian (rel_err), the worst printed per model.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "kernels/arap.hpp"
#include "kernels/corotated.hpp"
#include "kernels/element.hpp"
#include "kernels/element_hessian.hpp"
#include "kernels/fung.hpp"
#include "kernels/mooney_rivlin.hpp"
#include "kernels/neo_hookean.hpp"
#include "kernels/stvk.hpp"
#include "random_element.hpp"
#include "random_rotation.hpp"

namespace descent {

// Every member of every model compiles for float and double.
template struct StVK<float>;
template struct StVK<double>;
template struct NeoHookean<float>;
template struct NeoHookean<double>;
template struct MooneyRivlin<float>;
template struct MooneyRivlin<double>;
template struct Fung<float>;
template struct Fung<double>;
template struct Corotated<float>;
template struct Corotated<double>;
template struct Arap<float>;
template struct Arap<double>;

namespace {

constexpr double kYoung = 1.0e5;
constexpr double kPoisson = 0.4;
constexpr double kMu = kYoung / (2 * (1 + kPoisson));
constexpr double kMooneyC2 = 1.0e4;
constexpr double kFungC2 = 5.0e3;
constexpr double kFungC3 = 0.8;
constexpr double kTolerance = 1e-6;  // normwise relative error of every FD check

// Small-strain slopes of P_11 (axial) and P_22 (lateral) at
// F = diag(1 + e, 1 - nu e, 1 - nu e), e -> 0.
// Linear elasticity with shear modulus mu' and bulk modulus kappa gives
//   P_11 / e = kappa (1 - 2 nu) + 4/3 mu' (1 + nu),
//   P_22 / e = kappa (1 - 2 nu) - 2/3 mu' (1 + nu),
// which for mu' = mu is (E, 0). A model that adds dmu to the shear modulus
// and nothing to kappa thus has slopes (E + 4/3 (1 + nu) dmu,
// -2/3 (1 + nu) dmu): Mooney-Rivlin dmu = 2 c2 (Ibar2 - 3 ~ 2 |dev eps|^2),
// Fung dmu = 2 c2 c3 (exp(c3 x) - 1 ~ c3 x, Ibar1 - 3 ~ 2 |dev eps|^2).
// arap is mu sum (sigma_k - 1)^2: P = 2 mu diag(sigma - 1) for diagonal F,
// slopes (2 mu, -2 mu nu) = (E / (1 + nu), -E nu / (1 + nu)).
struct StVKCase {
  static constexpr const char* kName = "stvk";
  static constexpr double kAxialSlope = kYoung;
  static constexpr double kLateralSlope = 0;
  template <class Real>
  static StVK<Real> make() {
    return StVK<Real>::from_young_poisson(Real(kYoung), Real(kPoisson));
  }
};

struct NeoHookeanCase {
  static constexpr const char* kName = "neo_hookean";
  static constexpr double kAxialSlope = kYoung;
  static constexpr double kLateralSlope = 0;
  template <class Real>
  static NeoHookean<Real> make() {
    return NeoHookean<Real>::from_young_poisson(Real(kYoung), Real(kPoisson));
  }
};

struct MooneyRivlinCase {
  static constexpr const char* kName = "mooney_rivlin";
  static constexpr double kAxialSlope = kYoung + 8.0 / 3.0 * (1 + kPoisson) * kMooneyC2;
  static constexpr double kLateralSlope = -4.0 / 3.0 * (1 + kPoisson) * kMooneyC2;
  template <class Real>
  static MooneyRivlin<Real> make() {
    return MooneyRivlin<Real>::from_young_poisson(Real(kYoung), Real(kPoisson), Real(kMooneyC2));
  }
};

struct FungCase {
  static constexpr const char* kName = "fung";
  static constexpr double kAxialSlope = kYoung + 8.0 / 3.0 * (1 + kPoisson) * kFungC2 * kFungC3;
  static constexpr double kLateralSlope = -4.0 / 3.0 * (1 + kPoisson) * kFungC2 * kFungC3;
  template <class Real>
  static Fung<Real> make() {
    return Fung<Real>::from_young_poisson(Real(kYoung), Real(kPoisson), Real(kFungC2),
                                          Real(kFungC3));
  }
};

struct CorotatedCase {
  static constexpr const char* kName = "corotated";
  static constexpr double kAxialSlope = kYoung;
  static constexpr double kLateralSlope = 0;
  template <class Real>
  static Corotated<Real> make() {
    return Corotated<Real>::from_young_poisson(Real(kYoung), Real(kPoisson));
  }
};

struct ArapCase {
  static constexpr const char* kName = "arap";
  static constexpr double kAxialSlope = 2 * kMu;
  static constexpr double kLateralSlope = -2 * kMu * kPoisson;
  template <class Real>
  static Arap<Real> make() {
    return Arap<Real>::from_young_poisson(Real(kYoung), Real(kPoisson));
  }
};

using Rng = std::mt19937_64;

Mat3<double> identity() { return {{1, 0, 0, 0, 1, 0, 0, 0, 1}}; }

Mat3<double> diagonal(double x, double y, double z) { return {{x, 0, 0, 0, y, 0, 0, 0, z}}; }

// Identity plus uniform entries in [-amp, amp], redrawn until det lies in
// [det_min, det_max].
Mat3<double> random_f(Rng& rng, double amp, double det_min = 0.2, double det_max = 1e30) {
  std::uniform_real_distribution<double> u(-amp, amp);
  for (;;) {
    Mat3<double> f = identity();
    for (double& v : f.m) v += u(rng);
    const double j = det(f);
    if (j >= det_min && j <= det_max) return f;
  }
}

using testing::random_rotation;

// Error relative to the larger of the entry and `scale` (the norm of the
// whole stress or Hessian, so tiny entries are not judged by round-off).
double rel_err(double got, double want, double scale) {
  return std::abs(got - want) / std::max({std::abs(want), std::abs(got), scale});
}

double norm(const double* a, int n) {
  double s = 0;
  for (int k = 0; k < n; ++k) s += a[k] * a[k];
  return std::sqrt(s);
}

using testing::ElementCase;
using testing::random_element;

double& coord(TetCorners<double>& c, int a, int i) {
  return i == 0 ? c.x[a].x : (i == 1 ? c.x[a].y : c.x[a].z);
}
double coord(const Vec3<double>& v, int i) { return i == 0 ? v.x : (i == 1 ? v.y : v.z); }

// Cholesky of the n x n matrix h + shift I; false at a non-positive pivot,
// i.e. when h has an eigenvalue <= -shift.
bool shifted_cholesky_succeeds(const double* h, int n, double shift) {
  std::vector<double> l(h, h + n * n);
  for (int k = 0; k < n; ++k) l[n * k + k] += shift;
  for (int j = 0; j < n; ++j) {
    double pivot = l[n * j + j];
    for (int k = 0; k < j; ++k) pivot -= l[n * j + k] * l[n * j + k];
    if (!(pivot > 0)) return false;
    l[n * j + j] = std::sqrt(pivot);
    for (int i = j + 1; i < n; ++i) {
      double s = l[n * i + j];
      for (int k = 0; k < j; ++k) s -= l[n * i + k] * l[n * j + k];
      l[n * i + j] = s / l[n * j + j];
    }
  }
  return true;
}

// No eigenvalue below -1e-9 max|eigenvalue|; ||h||_F / sqrt(n) <= max|eigenvalue|.
// (The zero matrix, which StVK's projection gives under strong compression, is PSD.)
bool is_psd(const double* h, int n) {
  const double h_norm = norm(h, n * n);
  return h_norm == 0 || shifted_cholesky_succeeds(h, n, 1e-9 * h_norm / std::sqrt(double(n)));
}

template <class Case>
class ModelTest : public ::testing::Test {
 protected:
  using Model = decltype(Case::template make<double>());
  const Model model = Case::template make<double>();

  void report(const char* what, double worst) {
    std::printf("%-14s %-44s worst %.2e\n", Case::kName, what, worst);
  }

  // Worst error of P against central differences of Psi at f.
  double stress_error(const Mat3<double>& f) const {
    const Mat3<double> p = model.stress(f);
    const double p_norm = norm(p.m, 9);
    double worst = 0;
    for (int k = 0; k < 9; ++k) {
      const double h = 1e-6;
      Mat3<double> fp = f, fm = f;
      fp.m[k] += h;
      fm.m[k] -= h;
      const double fd = (model.energy(fp) - model.energy(fm)) / (2 * h);
      worst = std::max(worst, rel_err(p.m[k], fd, p_norm));
    }
    return worst;
  }

  // Worst error of dPdF against central differences of P at f, and of its
  // asymmetry.
  double stress_derivative_error(const Mat3<double>& f) const {
    double dpdf[81];
    model.stress_derivative(f, dpdf);
    const double scale = norm(dpdf, 81);
    double worst = 0;
    for (int c = 0; c < 9; ++c) {
      const double h = 1e-6;
      Mat3<double> fp = f, fm = f;
      fp.m[c] += h;
      fm.m[c] -= h;
      const Mat3<double> pp = model.stress(fp), pm = model.stress(fm);
      for (int r = 0; r < 9; ++r) {
        const double fd = (pp.m[r] - pm.m[r]) / (2 * h);
        worst = std::max(worst, rel_err(dpdf[9 * r + c], fd, scale));
        worst = std::max(worst, rel_err(dpdf[9 * r + c], dpdf[9 * c + r], scale));
      }
    }
    return worst;
  }
};

struct CaseNames {
  template <class Case>
  static std::string GetName(int) {
    return Case::kName;
  }
};

using Cases =
    ::testing::Types<StVKCase, NeoHookeanCase, MooneyRivlinCase, FungCase, CorotatedCase, ArapCase>;
TYPED_TEST_SUITE(ModelTest, Cases, CaseNames);

TYPED_TEST(ModelTest, RestStateHasZeroEnergyAndStress) {
  EXPECT_NEAR(this->model.energy(identity()), 0.0, 1e-9 * kYoung);
  for (double v : this->model.stress(identity()).m) EXPECT_NEAR(v, 0.0, 1e-9 * kYoung);
}

TYPED_TEST(ModelTest, StressMatchesFiniteDifferencesOfEnergy) {
  Rng rng(7);
  double worst = 0;
  for (double amp : {0.05, 0.3, 0.8})
    for (int sample = 0; sample < 1000; ++sample)
      worst = std::max(worst, this->stress_error(random_f(rng, amp)));
  this->report("stress vs FD of energy", worst);
  EXPECT_LE(worst, kTolerance);
}

TYPED_TEST(ModelTest, StressDerivativeMatchesFiniteDifferencesOfStress) {
  Rng rng(8);
  double worst = 0;
  for (double amp : {0.05, 0.3, 0.8})
    for (int sample = 0; sample < 1000; ++sample)
      worst = std::max(worst, this->stress_derivative_error(random_f(rng, amp)));
  this->report("dPdF vs FD of stress (and symmetry)", worst);
  EXPECT_LE(worst, kTolerance);
}

// Equal, nearly equal and triple singular values, where SVD-based formulas
// have removable singularities.
TYPED_TEST(ModelTest, RepeatedSingularValuesNeedNoSpecialCase) {
  Rng rng(9);
  std::uniform_real_distribution<double> u(0.6, 1.5);
  double worst = 0;
  for (int sample = 0; sample < 1000; ++sample) {
    const double s = u(rng), t = u(rng), near = 1 + 1e-9 * (sample % 3);
    const Mat3<double> stretch = sample % 2 ? diagonal(s, s * near, t) : diagonal(s, s, s * near);
    const Mat3<double> f = mul(random_rotation(rng), mul(stretch, random_rotation(rng)));
    worst = std::max({worst, this->stress_error(f), this->stress_derivative_error(f)});
  }
  this->report("stress and dPdF at repeated singular values", worst);
  EXPECT_LE(worst, kTolerance);
}

TYPED_TEST(ModelTest, ElementHessianMatchesFiniteDifferencesOfGradient) {
  Rng rng(3);
  double worst = 0;
  for (double amp : {0.02, 0.2, 0.5}) {
    for (int sample = 0; sample < 300; ++sample) {
      ElementCase e = random_element(rng, amp);
      double h[144];
      element_hessian(this->model, e.rest, e.x, h);
      const double scale = norm(h, 144);
      for (int b = 0; b < 4; ++b) {
        for (int j = 0; j < 3; ++j) {
          const double step = 1e-6;
          TetCorners<double> xp = e.x, xm = e.x;
          coord(xp, b, j) += step;
          coord(xm, b, j) -= step;
          Vec3<double> gp[4], gm[4];
          element_gradient(this->model, e.rest, xp, gp);
          element_gradient(this->model, e.rest, xm, gm);
          for (int a = 0; a < 4; ++a) {
            for (int i = 0; i < 3; ++i) {
              const double fd = (coord(gp[a], i) - coord(gm[a], i)) / (2 * step);
              worst = std::max(worst, rel_err(h[(3 * a + i) * 12 + 3 * b + j], fd, scale));
            }
          }
        }
      }
    }
  }
  this->report("element Hessian vs FD of element gradient", worst);
  EXPECT_LE(worst, kTolerance);
}

TYPED_TEST(ModelTest, HessianDiagonalIsTheElementHessianDiagonal) {
  Rng rng(5);
  double worst_fd = 0, worst_exact = 0;
  for (double amp : {0.02, 0.2, 0.5}) {
    for (int sample = 0; sample < 1000; ++sample) {
      ElementCase e = random_element(rng, amp);
      Vec3<double> d[4];
      element_hessian_diagonal(this->model, e.rest, e.x, d);
      double h[144];
      element_hessian(this->model, e.rest, e.x, h);
      const double scale = norm(h, 144);
      for (int a = 0; a < 4; ++a) {
        for (int i = 0; i < 3; ++i) {
          const double step = 1e-6;
          TetCorners<double> xp = e.x, xm = e.x;
          coord(xp, a, i) += step;
          coord(xm, a, i) -= step;
          Vec3<double> gp[4], gm[4];
          element_gradient(this->model, e.rest, xp, gp);
          element_gradient(this->model, e.rest, xm, gm);
          const double fd = (coord(gp[a], i) - coord(gm[a], i)) / (2 * step);
          worst_fd = std::max(worst_fd, rel_err(coord(d[a], i), fd, scale));
          worst_exact = std::max(worst_exact, rel_err(coord(d[a], i), h[(3 * a + i) * 13], scale));
        }
      }
    }
  }
  this->report("Hessian diagonal vs FD of element gradient", worst_fd);
  this->report("Hessian diagonal vs element Hessian", worst_exact);
  EXPECT_LE(worst_fd, kTolerance);
  EXPECT_LE(worst_exact, 1e-12);
}

TYPED_TEST(ModelTest, IsRotationInvariant) {
  Rng rng(11);
  double worst_energy = 0, worst_stress = 0;
  for (int sample = 0; sample < 1000; ++sample) {
    const Mat3<double> f = random_f(rng, 0.6);
    const Mat3<double> r = random_rotation(rng);
    const Mat3<double> p = this->model.stress(f);
    const Mat3<double> rp = mul(r, p), p_rotated = this->model.stress(mul(r, f));
    const double psi = this->model.energy(f);
    // Psi changes by P : dF under a perturbation dF; round-off in F is ~1e-16 |F|.
    const double energy_scale = std::abs(psi) + norm(p.m, 9) * norm(f.m, 9);
    worst_energy =
        std::max(worst_energy, std::abs(this->model.energy(mul(r, f)) - psi) / energy_scale);
    for (int k = 0; k < 9; ++k)
      worst_stress = std::max(worst_stress, rel_err(p_rotated.m[k], rp.m[k], norm(p.m, 9)));
  }
  this->report("rotation invariance of Psi", worst_energy);
  this->report("rotation equivariance of P", worst_stress);
  EXPECT_LE(worst_energy, 1e-12);
  EXPECT_LE(worst_stress, 1e-10);
}

TYPED_TEST(ModelTest, SmallStrainUniaxialSlope) {
  const double e = 1e-6;
  const Mat3<double> f = diagonal(1 + e, 1 - kPoisson * e, 1 - kPoisson * e);
  const Mat3<double> p = this->model.stress(f);
  std::printf("%-14s small-strain slopes: axial %.6g (want %.6g), lateral %.6g (want %.6g)\n",
              TypeParam::kName, p(0, 0) / e, TypeParam::kAxialSlope, p(1, 1) / e,
              TypeParam::kLateralSlope);
  EXPECT_NEAR(p(0, 0) / e, TypeParam::kAxialSlope, 1e-3 * TypeParam::kAxialSlope);
  EXPECT_NEAR(p(1, 1) / e, TypeParam::kLateralSlope, 1e-3 * TypeParam::kAxialSlope);
  EXPECT_NEAR(p(2, 2) / e, TypeParam::kLateralSlope, 1e-3 * TypeParam::kAxialSlope);
}

TYPED_TEST(ModelTest, ProjectedElementHessianIsPositiveSemiDefinite) {
  Rng rng(13);
  int indefinite_before = 0, samples = 0;
  for (int sample = 0; sample < 2000; ++sample, ++samples) {
    // Half large deformations, half inverted elements (det F in [-2, -0.05]).
    const ElementCase e =
        sample % 2 ? random_element(rng, 0.8) : random_element(rng, 1.0, -2.0, -0.05);
    double h[144], h_psd[144];
    element_hessian(this->model, e.rest, e.x, h);
    element_hessian_psd(this->model, e.rest, e.x, h_psd);
    if (!is_psd(h, 12)) ++indefinite_before;
    ASSERT_TRUE(is_psd(h_psd, 12)) << "sample " << sample;
  }
  std::printf("%-14s element Hessians indefinite before projection: %d of %d\n", TypeParam::kName,
              indefinite_before, samples);
  EXPECT_GT(indefinite_before, 0) << "the samples never exercised the projection";
}

// The multilevel preconditioner's projection in the frame of F's SVD
// (project_isotropic_psd) against the full 9x9 eigen-decomposition, on
// stretched, compressed and inverted F: the models are isotropic, so both
// give the same matrix.
TYPED_TEST(ModelTest, ProjectionInTheSvdFrameMatchesTheFullOne) {
  Rng rng(29);
  double worst = 0;
  int projected = 0;
  for (int sample = 0; sample < 2000; ++sample) {
    const Mat3<double> f = sample % 3 == 0 ? random_f(rng, 1.5, -2.0, -0.05) : random_f(rng, 0.6);
    double full[81], frame[81];
    this->model.stress_derivative(f, full);
    std::copy(full, full + 81, frame);
    if (!positive_definite(full, 9)) ++projected;
    project_psd(full, 9);
    project_isotropic_psd(f, frame);
    const double scale = norm(full, 81);
    for (int k = 0; k < 81; ++k) worst = std::max(worst, rel_err(frame[k], full[k], scale));
  }
  this->report("PSD projection in the SVD frame vs 9x9", worst);
  EXPECT_GT(projected, 0) << "the samples never needed a projection";
  EXPECT_LE(worst, 1e-9);
}

TYPED_TEST(ModelTest, ProjectionKeepsPositiveSemiDefiniteHessians) {
  // Near the rest state under mild tension every model's dPdF is PSD, so the
  // projection must leave the element Hessian as it is.
  Rng rng(17);
  std::uniform_real_distribution<double> stretch(1.0, 1.02);
  double worst = 0;
  for (int sample = 0; sample < 200; ++sample) {
    const Mat3<double> f =
        mul(random_rotation(rng), diagonal(stretch(rng), stretch(rng), stretch(rng)));
    ElementCase e = random_element(rng, 0.0);
    for (int a = 1; a < 4; ++a) {  // x_a = x_0 + F (X_a - X_0)
      const Vec3<double> dx = {e.x.x[a].x - e.x.x[0].x, e.x.x[a].y - e.x.x[0].y,
                               e.x.x[a].z - e.x.x[0].z};
      const Vec3<double> fdx = mul(f, dx);
      e.x.x[a] = {e.x.x[0].x + fdx.x, e.x.x[0].y + fdx.y, e.x.x[0].z + fdx.z};
    }
    double h[144], h_psd[144];
    element_hessian(this->model, e.rest, e.x, h);
    element_hessian_psd(this->model, e.rest, e.x, h_psd);
    const double scale = norm(h, 144);
    for (int k = 0; k < 144; ++k) worst = std::max(worst, rel_err(h_psd[k], h[k], scale));
  }
  this->report("PSD projection of PSD Hessians (change)", worst);
  EXPECT_LE(worst, 1e-12);
}

TYPED_TEST(ModelTest, InvertedElementsStayFinite) {
  Rng rng(19);
  const Vec3<double> b[4] = {{-1, -1, -1}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  for (int sample = 0; sample < 2000; ++sample) {
    const Mat3<double> f = random_f(rng, 1.5, -2.0, -0.05);
    const Mat3<double> p = this->model.stress(f);
    double dpdf[81];
    this->model.stress_derivative(f, dpdf);
    Vec3<double> d[4];
    this->model.hessian_diagonal(f, b, d);
    ASSERT_TRUE(std::isfinite(this->model.energy(f)));
    for (double v : p.m) ASSERT_TRUE(std::isfinite(v));
    for (double v : dpdf) ASSERT_TRUE(std::isfinite(v));
    for (const Vec3<double>& v : d)
      ASSERT_TRUE(std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z));
  }
}

// The float instantiation agrees with double to float precision.
TYPED_TEST(ModelTest, FloatBuildMatchesDouble) {
  Rng rng(23);
  const auto model_f = TypeParam::template make<float>();
  double worst = 0;
  for (int sample = 0; sample < 200; ++sample) {
    const ElementCase e = random_element(rng, 0.3);
    TetRest<float> rest_f;
    TetCorners<float> x_f;
    for (int k = 0; k < 9; ++k) rest_f.dm_inv.m[k] = float(e.rest.dm_inv.m[k]);
    rest_f.volume = float(e.rest.volume);
    for (int a = 0; a < 4; ++a)
      x_f.x[a] = {float(e.x.x[a].x), float(e.x.x[a].y), float(e.x.x[a].z)};
    double h[144];
    float h_f[144], h_psd_f[144];
    element_hessian(this->model, e.rest, e.x, h);
    element_hessian(model_f, rest_f, x_f, h_f);
    element_hessian_psd(model_f, rest_f, x_f, h_psd_f);
    Vec3<double> g[4];
    Vec3<float> g_f[4], d_f[4];
    element_gradient(this->model, e.rest, e.x, g);
    element_gradient(model_f, rest_f, x_f, g_f);
    element_hessian_diagonal(model_f, rest_f, x_f, d_f);
    const double e_d = element_energy(this->model, e.rest, e.x);
    const double e_f = element_energy(model_f, rest_f, x_f);
    const double h_scale = norm(h, 144);
    double g_norm = 0;
    for (const Vec3<double>& v : g) g_norm += dot(v, v);
    worst = std::max(worst, std::abs(e_f - e_d) / std::max(std::abs(e_d), 1e-3 * kMu));
    for (int k = 0; k < 144; ++k) {
      worst = std::max(worst, rel_err(h_f[k], h[k], h_scale));
      ASSERT_TRUE(std::isfinite(h_psd_f[k]));
    }
    for (int a = 0; a < 4; ++a)
      for (int i = 0; i < 3; ++i) {
        const float gf = i == 0 ? g_f[a].x : (i == 1 ? g_f[a].y : g_f[a].z);
        const float df = i == 0 ? d_f[a].x : (i == 1 ? d_f[a].y : d_f[a].z);
        worst = std::max(worst, rel_err(gf, coord(g[a], i), std::sqrt(g_norm)));
        worst = std::max(worst, rel_err(df, h[(3 * a + i) * 13], h_scale));
      }
  }
  this->report("float vs double (energy, gradient, Hessian)", worst);
  EXPECT_LE(worst, 1e-4);
}

// project_psd against a matrix of known spectrum Q diag(d) Q^T, with negative,
// zero and repeated eigenvalues, for n = 9 and 12.
TEST(ProjectPsd, ClampsNegativeEigenvaluesOfAKnownSpectrum) {
  Rng rng(29);
  std::normal_distribution<double> normal(0.0, 1.0);
  double worst = 0;
  for (int n : {9, 12}) {
    for (int sample = 0; sample < 500; ++sample) {
      // Random orthogonal Q by Gram-Schmidt on Gaussian columns (column k: q[n*i + k]).
      std::vector<double> q(n * n);
      for (double& v : q) v = normal(rng);
      for (int k = 0; k < n; ++k) {
        for (int pass = 0; pass < 2; ++pass)  // twice, for orthogonality to round-off
          for (int j = 0; j < k; ++j) {
            double d = 0;
            for (int i = 0; i < n; ++i) d += q[n * i + k] * q[n * i + j];
            for (int i = 0; i < n; ++i) q[n * i + k] -= d * q[n * i + j];
          }
        double len = 0;
        for (int i = 0; i < n; ++i) len += q[n * i + k] * q[n * i + k];
        for (int i = 0; i < n; ++i) q[n * i + k] /= std::sqrt(len);
      }
      std::vector<double> eig(n);
      for (int k = 0; k < n; ++k) eig[k] = normal(rng);
      eig[0] = 0;
      eig[1] = eig[2];                                      // a repeated eigenvalue
      if (sample % 2) eig[3] = eig[4] = -std::abs(eig[4]);  // a repeated negative one
      std::vector<double> m(n * n), want(n * n);
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
          double s = 0, s_clamped = 0;
          for (int k = 0; k < n; ++k) {
            s += q[n * i + k] * eig[k] * q[n * j + k];
            s_clamped += q[n * i + k] * std::max(eig[k], 0.0) * q[n * j + k];
          }
          m[n * i + j] = s;
          want[n * i + j] = s_clamped;
        }
      project_psd(m.data(), n);
      double max_eig = 0;
      for (double v : eig) max_eig = std::max(max_eig, std::abs(v));
      for (int k = 0; k < n * n; ++k) worst = std::max(worst, std::abs(m[k] - want[k]) / max_eig);
    }
  }
  std::printf("project_psd vs known spectrum: worst %.2e (relative to max |eigenvalue|)\n", worst);
  EXPECT_LE(worst, 1e-12);
}

}  // namespace
}  // namespace descent
