#pragma once
// The spectrum of the Jacobi-preconditioned Hessian D^-1 H and what the
// Chebyshev semi-iterative method takes from it (DESIGN §1, issue 11).
//
// With the eigenvalues of D^-1 H in [a, b], the step alpha = 2 / (a + b)
// gives the Jacobi iteration matrix I - alpha D^-1 H the spectral radius
// rho = (b - a) / (b + a), the rho of the Chebyshev recurrence, and after k
// accelerated iterations the relative energy error of a quadratic is at most
// 1 / T_k(1/rho)^2 = 1 / cosh(k phi)^2 with phi = acosh(1/rho) =
// 2 atanh(sqrt(a / b)): the bound the accuracy target counts iterations by.
//
// The bounds come from a Lanczos run on D^-1 H (engine-side vectors, the
// engine's Hessian product): its extreme Ritz values lie inside the
// spectrum, converging fast at the top and slowly at the bottom, so the top
// gets a margin and the bottom is what the start vector makes of it
// (solver/chebyshev_descent.cpp chooses it).
#include <vector>

#include "solver/iteration_engine.hpp"
#include "solver/local_problem.hpp"

namespace descent {

// The extreme eigenvalues of the symmetric tridiagonal matrix with diagonal
// `alpha` (m entries) and off-diagonal `beta` (m - 1 entries).
struct RitzExtremes {
  double lowest = 0, highest = 0;
};
RitzExtremes tridiagonal_extremes(const std::vector<double>& alpha,
                                  const std::vector<double>& beta);

// A Lanczos run on D^-1 H (D-inner product) from the vector in the engine's
// staging().vector, at the engine's current iterate and diagonal: at most
// `steps` steps, fewer when the Krylov space is exhausted. Collective: 1 + 2
// per step counted allreduces (problem.global_dots).
struct LanczosRun {
  RitzExtremes ritz;
  int steps = 0;
};
template <class Real>
LanczosRun lanczos(IterationEngine<Real>& engine, LocalProblem<Real>& problem, int steps);

// The Chebyshev method's parameters for eigenvalues in [lower, upper].
struct ChebyshevParameters {
  double alpha = 0;  // 2 / (lower + upper)
  double rho = 0;    // (upper - lower) / (upper + lower)
  double phi = 0;    // acosh(1 / rho): the bound's rate per iteration
};
ChebyshevParameters chebyshev_parameters(double lower, double upper);
// phi for a given rho in (0, 1) (fixed parameters).
double chebyshev_rate(double rho);

// 1 / T_k(1/rho)^2 for rate phi = acosh(1/rho): the bound on the relative
// energy error after k accelerated iterations (1 at k = 0).
double chebyshev_error_bound(double phi, int k);
// The least k with chebyshev_error_bound(phi, k) <= tolerance.
int chebyshev_iterations_for(double phi, double tolerance);

}  // namespace descent
