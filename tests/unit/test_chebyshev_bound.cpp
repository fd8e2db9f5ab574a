// The arithmetic of the automatic parameters (solver/spectrum.hpp,
// solver/check_history.hpp), by hand-checkable numbers: alpha and rho from
// [a, b], the Chebyshev bound against T_k evaluated by its recurrence, the
// iteration count that meets a tolerance, the tridiagonal's extremes against
// a dense solver, and the relative error read off a geometric energy decay.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <limits>
#include <random>

#include "solver/check_history.hpp"
#include "solver/spectrum.hpp"

namespace descent {
namespace {

// T_k(x) by its three-term recurrence (x >= 1: no cancellation).
double chebyshev_t(int k, double x) {
  double t0 = 1, t1 = x;
  if (k == 0) return t0;
  for (int j = 1; j < k; ++j) {
    const double t2 = 2 * x * t1 - t0;
    t0 = t1;
    t1 = t2;
  }
  return t1;
}

TEST(ChebyshevBound, ParametersFromTheInterval) {
  // [1, 3]: alpha 2 / 4, rho 2 / 4, phi = acosh(2).
  const ChebyshevParameters p = chebyshev_parameters(1.0, 3.0);
  EXPECT_DOUBLE_EQ(p.alpha, 0.5);
  EXPECT_DOUBLE_EQ(p.rho, 0.5);
  EXPECT_NEAR(p.phi, std::acosh(2.0), 1e-15);
  EXPECT_NEAR(chebyshev_rate(0.5), std::acosh(2.0), 1e-15);
  // kappa 1e4: phi = 2 atanh(1e-2), the same rate from rho.
  const ChebyshevParameters q = chebyshev_parameters(2.5e-4, 2.5);
  EXPECT_NEAR(q.phi, 2 * std::atanh(1e-2), 1e-15);
  EXPECT_NEAR(chebyshev_rate(q.rho), q.phi, 1e-10);
  EXPECT_THROW(chebyshev_parameters(0.0, 1.0), std::exception);
  EXPECT_THROW(chebyshev_parameters(2.0, 1.0), std::exception);
}

TEST(ChebyshevBound, EqualsTheSquaredInverseOfTk) {
  for (double rho : {0.5, 0.9, 0.999, 0.99998}) {
    const double phi = chebyshev_rate(rho);
    for (int k : {0, 1, 2, 7, 40, 96}) {
      // The reference itself: 1/rho rounded by 1e-16 moves T_k(1/rho) by up
      // to k / sinh(phi) of that, 1e-12 at rho = 0.99998, k = 96.
      const double t = chebyshev_t(k, 1 / rho);
      EXPECT_NEAR(chebyshev_error_bound(phi, k), 1 / (t * t), 1e-11 / (t * t))
          << "rho " << rho << " k " << k;
    }
  }
  // Far out the bound underflows to 0, never to NaN.
  EXPECT_EQ(chebyshev_error_bound(chebyshev_rate(0.5), 100000), 0.0);
}

TEST(ChebyshevBound, IterationsMeetTheTolerance) {
  for (double kappa : {10.0, 1e4, 1e6}) {
    const double phi = chebyshev_parameters(1.0, kappa).phi;
    for (double tol : {1e-1, 1e-3, 1e-6}) {
      const int k = chebyshev_iterations_for(phi, tol);
      EXPECT_LE(chebyshev_error_bound(phi, k), tol) << kappa << " " << tol;
      EXPECT_GT(chebyshev_error_bound(phi, k - 1), tol) << kappa << " " << tol;
    }
  }
  // The 41K helix: kappa 1.1e4 needs 157 iterations for 1e-2.
  EXPECT_NEAR(chebyshev_iterations_for(chebyshev_parameters(1.0, 1.1e4).phi, 1e-2), 157, 1);
  EXPECT_EQ(chebyshev_iterations_for(1.0, 1.0), 0);
}

TEST(ChebyshevBound, TridiagonalExtremesMatchADenseSolver) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0.1, 2.0);
  for (int m : {1, 2, 5, 30}) {
    std::vector<double> alpha(m), beta(m - 1);
    Eigen::MatrixXd t = Eigen::MatrixXd::Zero(m, m);
    for (int i = 0; i < m; ++i) t(i, i) = alpha[i] = u(rng);
    for (int i = 0; i + 1 < m; ++i) t(i, i + 1) = t(i + 1, i) = beta[i] = u(rng);
    const Eigen::VectorXd values = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(t).eigenvalues();
    const RitzExtremes r = tridiagonal_extremes(alpha, beta);
    EXPECT_NEAR(r.lowest, values.minCoeff(), 1e-13) << m;
    EXPECT_NEAR(r.highest, values.maxCoeff(), 1e-13) << m;
  }
}

// A Lanczos matrix recorded from a box thrown onto a floor (extremes
// suite, neo-Hookean): unscaled, Eigen's tridiagonal QL gave up on it and
// returned its values unsorted.
TEST(ChebyshevBound, TridiagonalExtremesOfABadlyScaledLanczosMatrix) {
  const std::vector<double> alpha = {
      25.177522697122313, 3443.3809333649292, 1393.4138388160354, 722.48253081714529,
      58.928903604330777, 3182.5996349608376, 1474.8163480033161, 240.37249369651551,
      992.15169357515015, 8.2066462729878022, 928.38056551622742, 410.10415968140995,
      3.3540685841275506, 261.83377382636553, 3345.9796002462308, 2.8540729843327002,
      3511.8189225300175, 17.627456257129086, 249.19867373102775, 797.48481185941887};
  const std::vector<double> beta = {
      279.99644460184936, 540.9263924293823,  222.32559048140024, 184.84849867117251,
      163.46179117367038, 819.88796564367476, 419.65686176113087, 311.45830609099824,
      21.968003686330409, 20.848376923539114, 618.49970304305543, 7.3100020683867504,
      7.1630027027550813, 918.81388795875193, 15.875107792071544, 77.622483248438385,
      215.92606048127826, 4.6822178858184902, 439.87289330446475};
  const int m = static_cast<int>(alpha.size());
  Eigen::MatrixXd t = Eigen::MatrixXd::Zero(m, m);
  for (int i = 0; i < m; ++i) t(i, i) = alpha[i];
  for (int i = 0; i + 1 < m; ++i) t(i, i + 1) = t(i + 1, i) = beta[i];
  const Eigen::VectorXd values = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(t).eigenvalues();
  const RitzExtremes r = tridiagonal_extremes(alpha, beta);
  EXPECT_NEAR(r.lowest, values.minCoeff(), 1e-9);
  EXPECT_NEAR(r.highest, values.maxCoeff(), 1e-9);
}

TEST(CheckHistory, ReadsTheRelativeErrorOfAGeometricDecay) {
  // eps_k = eps* + 100 r^j at checks j = 0, 1, ...: the remaining error is
  // known exactly once the decay is geometric.
  const double star = 5.0, r = 0.6;
  const double slow_bound = chebyshev_rate(0.001);  // a bound faster than r: r decides
  CheckHistory h;
  h.restart(star + 100);
  EXPECT_TRUE(std::isnan(h.relative_error(star + 100, slow_bound)));
  for (int j = 1; j <= 6; ++j) h.record(8 * j, star + 100 * std::pow(r, j));
  EXPECT_NEAR(h.relative_error(star + 100, slow_bound), std::pow(r, 6), 1e-12);
  // A bound slower than the observed decay wins: the estimate grows.
  const double fast_phi = chebyshev_rate(0.9999);
  EXPECT_GT(h.relative_error(star + 100, fast_phi), std::pow(r, 6));
}

// One check near a turning point (a decrease far below the trend) fools a
// one-check estimate into a small error, not one over wider windows.
TEST(CheckHistory, AWideWindowIsNotFooledByOneFlatCheck) {
  const double r = 0.9, phi = chebyshev_rate(0.001);
  CheckHistory h;
  h.restart(100);
  for (int j = 1; j <= 8; ++j) h.record(8 * j, 100 * std::pow(r, j));
  h.record(72, 100 * std::pow(r, 8) - 1e-6);  // almost no decrease
  const double truth = std::pow(r, 8);
  EXPECT_LT(h.relative_error(100, phi), 1e-3 * truth);
  EXPECT_GT(h.relative_error(100, phi, 4), 0.5 * truth);
  EXPECT_TRUE(std::isnan(h.relative_error(100, phi, 5))) << "needs 2 windows of 5 checks";
}

// A fast start followed by a stall (the armadillo's e_8 = 5.4e-3, e_16 =
// 2.9e-3 from e_0 = 1): the first window's fall beside the second's small
// decrease would read as convergence; no estimate until a window after the
// restart's first, which then reads the stall's rate.
TEST(CheckHistory, NoEstimateFromTheRestartsFirstWindow) {
  const double phi = chebyshev_rate(0.5), slow = 0.54;  // per window after the first
  auto error = [&](int j) { return j == 0 ? 1.0 : 5.4e-3 * std::pow(slow, j - 1); };
  CheckHistory h;
  h.restart(error(0));
  h.record(8, error(1));
  h.record(16, error(2));
  EXPECT_TRUE(std::isnan(h.relative_error(error(0), phi)));
  h.record(24, error(3));
  EXPECT_NEAR(h.relative_error(error(0), phi), error(3) / error(0), 1e-12);
}

// Without a bound (phi = 0: gd, nesterov, ncg, lbfgs, linear_cg) the
// decreases alone give the rate: exact for a geometric decay.
TEST(CheckHistory, WithoutABoundTheDecreasesGiveTheRate) {
  const double star = -3.0, r = 0.8;
  CheckHistory h;
  h.restart(star + 10);
  for (int j = 1; j <= 5; ++j) h.record(8 * j, star + 10 * std::pow(r, j));
  EXPECT_NEAR(h.relative_error(star + 10, 0.0), std::pow(r, 5), 1e-12);
  const AccuracyReading reading = h.read(star + 10, 0.0, 2 * std::pow(r, 5) / kTargetShare);
  EXPECT_NEAR(reading.estimate, std::pow(r, 5), 1e-12);
  EXPECT_TRUE(reading.below);
  EXPECT_TRUE(reading.confirmed) << "geometric: the predicted minimum does not move";
}

// A first-order method's fast modes die out over several checks, and the
// ratio of its decreases rises towards its slowest mode's (here e_j = 0.8 *
// 0.2^j + 0.2 * 0.9^j): the latest ratio reads the error as below the target
// at checks 3-5 where it is 1.2-1.5x above; only a confirmed reading, once
// the predicted minimum has settled, ends the step, and there e <= TOL.
TEST(CheckHistory, WithoutABoundOnlyAConfirmedReadingEnds) {
  const double target = 0.1;
  auto error = [](int j) { return 0.8 * std::pow(0.2, j) + 0.2 * std::pow(0.9, j); };
  CheckHistory h;
  h.restart(1.0);
  int misread = 0, confirmed_at = 0;
  for (int j = 1; j <= 40 && confirmed_at == 0; ++j) {
    h.record(8 * j, error(j));
    const AccuracyReading reading = h.read(1.0, 0.0, target);
    if (reading.below && error(j) > target) ++misread;
    if (reading.confirmed) confirmed_at = j;
  }
  EXPECT_EQ(misread, 3) << "the unconfirmed rule would stop at e = 0.15";
  ASSERT_GT(confirmed_at, 0);
  EXPECT_LE(error(confirmed_at), target);
  EXPECT_GT(error(confirmed_at), 0.1 * target) << "nor far below it";
}

// Energies that stop changing beyond their round-off give no ratio, but
// say the error left is at most that round-off: a body converged in a few
// checks, or one whose step starts at its minimum, ends the step instead of
// running to the cap.
TEST(CheckHistory, RoundOffChangesEndTheStep) {
  const double noise = 1e-9, target = 1e-3;
  CheckHistory h;
  h.restart(10.0);
  h.record(8, 4.0);
  h.record(16, 4.0 - 0.5 * noise);
  h.record(24, 4.0 + 0.3 * noise);  // a rise within the round-off
  EXPECT_TRUE(std::isnan(h.relative_error(10.0, 0.0))) << "no ratio of round-off changes";
  AccuracyReading reading = h.read(10.0, 0.0, target, noise);
  EXPECT_NEAR(reading.estimate, noise / 6.0, 1e-3 * noise / 6.0);
  EXPECT_TRUE(reading.below);
  EXPECT_FALSE(reading.confirmed) << "the previous check had no reading";
  h.record(32, 4.0);
  EXPECT_TRUE(h.read(10.0, 0.0, target, noise).confirmed);
  // Nothing moves at all: the step started at its minimum.
  CheckHistory rest;
  rest.restart(2.0);
  for (int j = 1; j <= 4; ++j) rest.record(8 * j, 2.0 + (j % 2 ? 0.2 : -0.2) * noise);
  reading = rest.read(2.0, 0.0, target, noise);
  EXPECT_EQ(reading.estimate, 0.0);
  EXPECT_TRUE(reading.confirmed);
  EXPECT_FALSE(rest.read(2.0, 0.0, target).below) << "without the round-off: no reading";
}

// A target below the round-off: the energies fall to where their changes
// lie within it and stay there. The reading says so (at_resolution) once the
// last two checks and the last two wide windows all changed within it, with
// the estimate, noise over the fall, still above the target.
TEST(CheckHistory, ChangesWithinRoundOffSayTheResolutionIsReached) {
  const double noise = 1e-4, target = 1e-6;
  CheckHistory h;
  h.restart(10.0);
  h.record(8, 5.0);
  h.record(16, 4.0);
  int k = 16;
  for (int j = 0; j < 2 * kWideWindow; ++j) {
    EXPECT_FALSE(h.read(10.0, 0.0, target, noise).at_resolution) << "check " << j;
    h.record(k += 8, 4.0 + (j % 2 ? 0.4 : -0.4) * noise);
  }
  const AccuracyReading reading = h.read(10.0, 0.0, target, noise);
  EXPECT_TRUE(reading.at_resolution);
  EXPECT_FALSE(reading.below);
  EXPECT_GT(reading.estimate, target);
  h.record(k + 8, 4.0 - 3 * noise);  // a real decrease: progress again
  EXPECT_FALSE(h.read(10.0, 0.0, target, noise).at_resolution);
  EXPECT_FALSE(h.read(10.0, 0.0, target).at_resolution) << "without the round-off: never";
}

// A slow descent whose decreases shrink by 0.8 a check until they fall
// within the round-off: the error left is the tail of a decrease of the
// round-off at that last resolved ratio, 0.8 / 0.2 = 4 noise, not the noise
// alone (Nesterov's float step below its floor read half its error so).
TEST(CheckHistory, WithinRoundOffTheErrorLeftIsTheTailAtTheLastResolvedRatio) {
  const double noise = 1e-4, target = 1e-9;
  CheckHistory h;
  h.restart(10.0);
  double energy = 5.0;
  int k = 8;
  h.record(k, energy);
  for (int j = 0; j <= 10; ++j) h.record(k += 8, energy -= 1e-3 * std::pow(0.8, j));
  ASSERT_GT(1e-3 * std::pow(0.8, 10), noise) << "the last decrease is resolved";
  for (int j = 0; j < 2 * kWideWindow + 2; ++j)
    h.record(k += 8, energy + (j % 2 ? -0.3 : 0.3) * noise);
  const AccuracyReading reading = h.read(10.0, 0.0, target, noise);
  EXPECT_TRUE(reading.at_resolution);
  const double last = energy + (((2 * kWideWindow + 1) % 2) ? -0.3 : 0.3) * noise;
  const double left = 4 * noise;
  EXPECT_NEAR(reading.estimate, left / (10.0 - last + left), 1e-9);
  EXPECT_GT(reading.estimate, 3 * noise / (10.0 - last + noise)) << "more than the noise alone";
}

TEST(CheckHistory, NoEstimateWhileTheEnergyDoesNotFall) {
  const double phi = chebyshev_rate(0.5);
  CheckHistory h;
  h.restart(10);
  h.record(8, 9);
  h.record(16, 9.5);  // a rise
  EXPECT_TRUE(std::isnan(h.relative_error(10, phi)));
  h.record(24, 8);
  EXPECT_TRUE(std::isnan(h.relative_error(10, phi)));  // the last three do not fall
  h.record(40, 7);                                     // uneven spacing
  EXPECT_TRUE(std::isnan(h.relative_error(10, phi)));
}

}  // namespace
}  // namespace descent
