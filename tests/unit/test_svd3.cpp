// The signed 3x3 SVD against Eigen's JacobiSVD on over a million matrices of
// seven families (uniform, inverted, near-singular, repeated singular values,
// rank-deficient, tiny and huge scales): reconstruction, orthogonality,
// det U = det V = +1, ordering and sign convention, singular values. Prints
// the worst errors per family; also the polar helper and a float build.
#include <gtest/gtest.h>

#include <Eigen/SVD>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "kernels/svd3.hpp"
#include "random_rotation.hpp"

namespace descent {
namespace {

// Bounds for double; observed worst values are printed by the tests.
constexpr double kReconstructionBound = 1e-13;  // ||U S V^T - A||_F / ||A||_F
constexpr double kOrthogonalityBound = 1e-13;   // ||U^T U - I||_F, ||V^T V - I||_F
constexpr double kDeterminantBound = 1e-13;     // |det U - 1|, |det V - 1|
constexpr double kSingularValueBound = 1e-10;   // |sigma - sigma_eigen| / sigma_max

using Rng = std::mt19937_64;

template <class Real>
Mat3<Real> transpose(const Mat3<Real>& a) {
  return {{a.m[0], a.m[3], a.m[6], a.m[1], a.m[4], a.m[7], a.m[2], a.m[5], a.m[8]}};
}

template <class Real>
Real frobenius(const Mat3<Real>& a) {
  return std::sqrt(ddot(a, a));
}

template <class Real>
Mat3<Real> diagonal(Real x, Real y, Real z) {
  return {{x, 0, 0, 0, y, 0, 0, 0, z}};
}

using testing::random_rotation;

Mat3<double> uniform_matrix(Rng& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Mat3<double> a;
  for (double& v : a.m) v = u(rng);
  return a;
}

// R1 diag(s) R2 with the given stretches.
Mat3<double> with_stretches(Rng& rng, double s0, double s1, double s2) {
  return mul(random_rotation(rng), mul(diagonal(s0, s1, s2), random_rotation(rng)));
}

struct Family {
  std::string name;
  int count;
  std::function<Mat3<double>(Rng&)> make;
};

std::vector<Family> families() {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  return {
      {"uniform", 300000, uniform_matrix},
      {"inverted (det < 0)", 150000,
       [](Rng& rng) {
         Mat3<double> a = uniform_matrix(rng);
         if (det(a) > 0)
           for (int k = 0; k < 3; ++k) a.m[k] = -a.m[k];
         return a;
       }},
      {"near-singular", 150000,
       [unit](Rng& rng) mutable {
         // One, or two, singular values down to 1e-14 relative; either sign.
         const double t = std::pow(10.0, -14.0 * unit(rng));
         const double sign = unit(rng) < 0.5 ? -1.0 : 1.0;
         if (unit(rng) < 0.5) return with_stretches(rng, 1.0, unit(rng), sign * t);
         return with_stretches(rng, 1.0, t, sign * t * unit(rng));
       }},
      {"repeated singular values", 150000,
       [unit](Rng& rng) mutable {
         const double s = unit(rng), t = unit(rng);
         const double sign = unit(rng) < 0.5 ? -1.0 : 1.0;
         const double near = 1.0 + 1e-9 * (unit(rng) - 0.5);  // exact or nearly repeated
         switch (rng() % 4) {
           case 0:
             return with_stretches(rng, s, s, sign * t);
           case 1:
             return with_stretches(rng, s, t, sign * t);
           case 2:
             return with_stretches(rng, s, s * near, sign * s);
           default:
             return with_stretches(rng, s, s, sign * s * near);
         }
       }},
      {"rank-deficient", 100000,
       [unit](Rng& rng) mutable {
         const int rank = static_cast<int>(rng() % 3);  // 0, 1 or 2
         if (rank == 0) return Mat3<double>{};
         return with_stretches(rng, 1.0, rank == 2 ? unit(rng) : 0.0, 0.0);
       }},
      {"tiny scale (1e-150)", 100000,
       [](Rng& rng) {
         Mat3<double> a = uniform_matrix(rng);
         for (double& v : a.m) v *= 1e-150;
         return a;
       }},
      {"huge scale (1e150)", 100000,
       [](Rng& rng) {
         Mat3<double> a = uniform_matrix(rng);
         for (double& v : a.m) v *= 1e150;
         return a;
       }},
  };
}

struct Worst {
  double reconstruction = 0, orthogonality = 0, determinant = 0, singular_value = 0;
};

// Errors of one decomposition; returns false with a message on a broken
// ordering or sign convention.
template <class Real>
bool check(const Mat3<Real>& a, const Svd3<Real>& d, Worst& worst, std::string& message) {
  const Mat3<Real> identity = diagonal<Real>(1, 1, 1);
  const Mat3<Real> us = mul(d.u, diagonal(d.sigma[0], d.sigma[1], d.sigma[2]));
  const Mat3<Real> usvt = mul(us, transpose(d.v));
  // Norms of A and of the residual divided by max |a_ij| first, so that
  // squaring entries of 1e-150 does not underflow.
  Real max_abs = 0;
  for (Real v : a.m) max_abs = std::max(max_abs, std::abs(v));
  Mat3<Real> diff, a_unit, utu = mul(transpose(d.u), d.u), vtv = mul(transpose(d.v), d.v);
  for (int k = 0; k < 9; ++k) {
    diff.m[k] = (usvt.m[k] - a.m[k]) / max_abs;
    a_unit.m[k] = a.m[k] / max_abs;
    utu.m[k] -= identity.m[k];
    vtv.m[k] -= identity.m[k];
  }
  if (max_abs > 0)
    worst.reconstruction =
        std::max<double>(worst.reconstruction, frobenius(diff) / frobenius(a_unit));
  worst.orthogonality =
      std::max<double>(worst.orthogonality, std::max(frobenius(utu), frobenius(vtv)));
  worst.determinant = std::max<double>(
      worst.determinant, std::max(std::abs(det(d.u) - Real(1)), std::abs(det(d.v) - Real(1))));

  // sigma[k+1] may exceed sigma[k] by round-off when they are (nearly) equal.
  const Real slack = Real(64) * std::numeric_limits<Real>::epsilon() * d.sigma[0];
  if (d.sigma[1] < 0 || d.sigma[0] + slack < d.sigma[1] ||
      d.sigma[1] + slack < std::abs(d.sigma[2])) {
    message = "ordering sigma0 >= sigma1 >= |sigma2| broken";
    return false;
  }
  // The sign of sigma[2] is that of det A wherever det A is not round-off.
  const Real det_a = det(a);
  const Real det_scale = d.sigma[0] * d.sigma[0] * d.sigma[0];
  if (std::abs(det_a) > Real(1e-10) * det_scale && (det_a < 0) != (d.sigma[2] < 0)) {
    message = "sign of sigma[2] differs from sign of det A";
    return false;
  }
  return true;
}

TEST(Svd3, MatchesEigenOnAMillionMatrices) {
  Rng rng(2024);
  Worst overall;
  int total = 0;
  for (const Family& family : families()) {
    Worst worst;
    for (int sample = 0; sample < family.count; ++sample, ++total) {
      const Mat3<double> a = family.make(rng);
      const Svd3<double> d = svd3(a);
      std::string message;
      ASSERT_TRUE(check(a, d, worst, message)) << family.name << ": " << message;

      const Eigen::Matrix3d ae =
          Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(a.m);
      const Eigen::Vector3d s = Eigen::JacobiSVD<Eigen::Matrix3d>(ae).singularValues();
      if (s(0) > 0) {
        const double ours[3] = {d.sigma[0], d.sigma[1], std::abs(d.sigma[2])};
        for (int k = 0; k < 3; ++k)
          worst.singular_value = std::max(worst.singular_value, std::abs(ours[k] - s(k)) / s(0));
      }
    }
    std::printf("svd3 %-26s n=%6d  reconstruction %.2e  orthogonality %.2e  det %.2e  sigma %.2e\n",
                family.name.c_str(), family.count, worst.reconstruction, worst.orthogonality,
                worst.determinant, worst.singular_value);
    EXPECT_LE(worst.reconstruction, kReconstructionBound) << family.name;
    EXPECT_LE(worst.orthogonality, kOrthogonalityBound) << family.name;
    EXPECT_LE(worst.determinant, kDeterminantBound) << family.name;
    EXPECT_LE(worst.singular_value, kSingularValueBound) << family.name;
    overall.reconstruction = std::max(overall.reconstruction, worst.reconstruction);
    overall.orthogonality = std::max(overall.orthogonality, worst.orthogonality);
    overall.determinant = std::max(overall.determinant, worst.determinant);
    overall.singular_value = std::max(overall.singular_value, worst.singular_value);
  }
  std::printf(
      "svd3 worst over %d matrices: reconstruction %.2e  orthogonality %.2e  det %.2e  "
      "sigma vs Eigen %.2e\n",
      total, overall.reconstruction, overall.orthogonality, overall.determinant,
      overall.singular_value);
  EXPECT_GE(total, 1000000);
}

TEST(Svd3, ExactCasesKeepTheirStructure) {
  const Svd3<double> zero = svd3(Mat3<double>{});
  for (double s : zero.sigma) EXPECT_EQ(s, 0.0);
  EXPECT_EQ(det(zero.u), 1.0);
  EXPECT_EQ(det(zero.v), 1.0);

  const Svd3<double> identity = svd3(diagonal(1.0, 1.0, 1.0));
  for (double s : identity.sigma) EXPECT_DOUBLE_EQ(s, 1.0);

  // A reflection: one negative singular value, rotations with det +1.
  const Svd3<double> reflection = svd3(diagonal(2.0, -3.0, 1.0));
  EXPECT_DOUBLE_EQ(reflection.sigma[0], 3.0);
  EXPECT_DOUBLE_EQ(reflection.sigma[1], 2.0);
  EXPECT_DOUBLE_EQ(reflection.sigma[2], -1.0);
  EXPECT_NEAR(det(reflection.u), 1.0, 1e-15);
  EXPECT_NEAR(det(reflection.v), 1.0, 1e-15);
}

TEST(Svd3, PolarGivesRotationTimesSymmetric) {
  Rng rng(5);
  double worst = 0;
  for (int sample = 0; sample < 10000; ++sample) {
    const Mat3<double> f = uniform_matrix(rng);
    const Polar<double> p = polar(f);
    const Mat3<double> rs = mul(p.r, p.s);
    Mat3<double> rtr = mul(transpose(p.r), p.r);
    for (int k = 0; k < 3; ++k) rtr.m[4 * k] -= 1;
    double recon = 0, asym = 0;
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) {
        recon = std::max(recon, std::abs(rs(i, j) - f(i, j)));
        asym = std::max(asym, std::abs(p.s(i, j) - p.s(j, i)));
      }
    }
    worst = std::max({worst, recon / frobenius(f), asym / frobenius(f), frobenius(rtr)});
    EXPECT_NEAR(det(p.r), 1.0, 1e-13);
  }
  EXPECT_LE(worst, 1e-13);
}

// The same code in float: bounds a few ulp of float.
TEST(Svd3, FloatBuildIsAccurateToFloatPrecision) {
  Rng rng(9);
  Worst worst;
  for (int sample = 0; sample < 100000; ++sample) {
    const Mat3<double> ad =
        sample % 2 ? uniform_matrix(rng) : with_stretches(rng, 1.0, 0.5, sample % 4 ? 0.5 : -1e-4);
    Mat3<float> a;
    for (int k = 0; k < 9; ++k) a.m[k] = static_cast<float>(ad.m[k]);
    std::string message;
    ASSERT_TRUE(check(a, svd3(a), worst, message)) << message;
  }
  std::printf("svd3<float> reconstruction %.2e  orthogonality %.2e  det %.2e\n",
              worst.reconstruction, worst.orthogonality, worst.determinant);
  EXPECT_LE(worst.reconstruction, 2e-6);
  EXPECT_LE(worst.orthogonality, 2e-6);
  EXPECT_LE(worst.determinant, 2e-6);
}

// Speed, printed for information only (never asserted: machines differ).
TEST(Svd3, ThroughputIsReported) {
  Rng rng(1);
  std::vector<Mat3<double>> inputs(1000000);
  for (Mat3<double>& a : inputs) a = uniform_matrix(rng);
  double checksum = 0;
  const auto start = std::chrono::steady_clock::now();
  for (const Mat3<double>& a : inputs) checksum += svd3(a).v.m[8];
  const auto ours = std::chrono::steady_clock::now();
  for (const Mat3<double>& a : inputs) {
    const Eigen::Matrix3d ae = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(a.m);
    Eigen::JacobiSVD<Eigen::Matrix3d> svd(ae, Eigen::ComputeFullU | Eigen::ComputeFullV);
    checksum += svd.matrixV()(2, 2);
  }
  const auto eigen = std::chrono::steady_clock::now();
  const auto ns = [](auto d) { return std::chrono::duration<double, std::nano>(d).count() / 1e6; };
  std::printf(
      "svd3 %.0f ns per 3x3 (U, sigma, V); Eigen JacobiSVD with U, V %.0f ns (checksum %g)\n",
      ns(ours - start), ns(eigen - ours), checksum);
}

}  // namespace
}  // namespace descent
