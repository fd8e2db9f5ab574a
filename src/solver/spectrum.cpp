#include "solver/spectrum.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>

#include "common/error.hpp"

namespace descent {

RitzExtremes tridiagonal_extremes(const std::vector<double>& alpha,
                                  const std::vector<double>& beta) {
  const Eigen::Index m = static_cast<Eigen::Index>(alpha.size());
  DESCENT_VERIFY(m > 0 && beta.size() + 1 == alpha.size(), "tridiagonal of ", alpha.size(),
                 " diagonal and ", beta.size(), " off-diagonal entries");
  // Scaled to entries of at most 1 first: Eigen's computeFromTridiagonal
  // does not scale (its compute() does), and unscaled its QL iteration gave
  // up on a Lanczos matrix of a box pressed into a floor (entries 3 .. 3,500,
  // two Ritz values equal to 12 digits) and returned unsorted values: a
  // "lowest" of 1,342 above a "highest" of 1,042, where they are -13.7 and
  // 3,599.
  double scale = 0;
  for (double a : alpha) scale = std::max(scale, std::abs(a));
  for (double b : beta) scale = std::max(scale, std::abs(b));
  if (!(scale > 0)) return {0, 0};
  Eigen::VectorXd diagonal(m), sub(m > 1 ? m - 1 : 0);
  for (Eigen::Index i = 0; i < m; ++i) diagonal[i] = alpha[i] / scale;
  for (Eigen::Index i = 0; i + 1 < m; ++i) sub[i] = beta[i] / scale;
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> solver;
  solver.computeFromTridiagonal(diagonal, sub, Eigen::EigenvaluesOnly);
  if (solver.info() == Eigen::Success) {
    const Eigen::VectorXd& values = solver.eigenvalues();  // ascending
    return {scale * values[0], scale * values[m - 1]};
  }
  // Still no convergence: Gershgorin's discs enclose every eigenvalue, so
  // the bounds stay valid, only wider.
  RitzExtremes discs{alpha[0], alpha[0]};
  for (Eigen::Index i = 0; i < m; ++i) {
    const double radius =
        (i > 0 ? std::abs(beta[i - 1]) : 0.0) + (i + 1 < m ? std::abs(beta[i]) : 0.0);
    discs.lowest = std::min(discs.lowest, alpha[i] - radius);
    discs.highest = std::max(discs.highest, alpha[i] + radius);
  }
  return discs;
}

template <class Real>
LanczosRun lanczos(IterationEngine<Real>& engine, LocalProblem<Real>& problem, int steps) {
  LanczosRun run;
  double norm2 = engine.lanczos_begin();
  problem.global_dots(&norm2, 1);
  if (!(norm2 > 0) || !std::isfinite(norm2)) return run;  // nothing to estimate from
  // alpha_j: diagonal of T; beta_j = |w_j|_D couples steps j and j + 1.
  std::vector<double> alpha, beta;
  double beta_prev = 0, scale = std::sqrt(norm2);
  for (int j = 0; j < steps; ++j) {
    engine.lanczos_next(scale);
    double a = engine.lanczos_product();
    problem.global_dots(&a, 1);
    if (!std::isfinite(a)) break;
    alpha.push_back(a);
    double w2 = engine.lanczos_orthogonalize(a, beta_prev);
    problem.global_dots(&w2, 1);
    const double b = std::sqrt(std::max(w2, 0.0));
    // An invariant subspace (the start vector had few components): T is
    // exact there.
    if (!(b > 1e-12 * std::abs(a)) || !std::isfinite(b)) break;
    beta.push_back(b);
    beta_prev = scale = b;
  }
  if (alpha.empty()) return run;
  beta.resize(alpha.size() - 1);
  run.ritz = tridiagonal_extremes(alpha, beta);
  run.steps = static_cast<int>(alpha.size());
  return run;
}

ChebyshevParameters chebyshev_parameters(double lower, double upper) {
  DESCENT_VERIFY(lower > 0 && upper > lower, "Chebyshev bounds [", lower, ", ", upper, "]");
  ChebyshevParameters p;
  p.alpha = 2 / (lower + upper);
  p.rho = (upper - lower) / (upper + lower);
  p.phi = 2 * std::atanh(std::sqrt(lower / upper));
  return p;
}

double chebyshev_rate(double rho) {
  DESCENT_VERIFY(rho > 0 && rho < 1, "Chebyshev rho ", rho, " outside (0, 1)");
  // acosh(1 + delta) with delta = 1/rho - 1 formed without cancellation.
  const double delta = (1 - rho) / rho;
  return std::log1p(delta + std::sqrt(delta * (2 + delta)));
}

double chebyshev_error_bound(double phi, int k) {
  // 1 / cosh(x)^2 = 4 e^-2x / (1 + e^-2x)^2, finite for any x.
  const double e = std::exp(-2 * phi * k);
  return 4 * e / ((1 + e) * (1 + e));
}

int chebyshev_iterations_for(double phi, double tolerance) {
  if (tolerance >= 1) return 0;
  const double k = std::acosh(1 / std::sqrt(tolerance)) / phi;
  if (!(k < std::numeric_limits<int>::max() / 2)) return std::numeric_limits<int>::max() / 2;
  return static_cast<int>(std::ceil(k));
}

template LanczosRun lanczos(IterationEngine<double>&, LocalProblem<double>&, int);
template LanczosRun lanczos(IterationEngine<float>&, LocalProblem<float>&, int);

}  // namespace descent
