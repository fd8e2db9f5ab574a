#include "common/error.hpp"
#include "solver/chebyshev_descent.hpp"
#include "solver/stepper.hpp"

namespace descent {

template <class Real>
std::unique_ptr<Stepper<Real>> make_stepper(LocalProblem<Real>& problem, const SolverSpec& spec) {
  if (spec.method == "chebyshev") return std::make_unique<ChebyshevDescent<Real>>(problem, spec);
  // The scene checks admit only the methods listed here.
  throw LogicError(detail::concat("no stepper for solver.method = ", spec.method));
}

template std::unique_ptr<Stepper<double>> make_stepper(LocalProblem<double>&, const SolverSpec&);
template std::unique_ptr<Stepper<float>> make_stepper(LocalProblem<float>&, const SolverSpec&);

}  // namespace descent
