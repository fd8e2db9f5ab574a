#include "common/error.hpp"
#include "solver/chebyshev_descent.hpp"
#include "solver/methods/gradient_descent.hpp"
#include "solver/methods/lbfgs.hpp"
#include "solver/methods/linear_cg.hpp"
#include "solver/methods/nesterov.hpp"
#include "solver/methods/newton.hpp"
#include "solver/methods/nonlinear_cg.hpp"
#include "solver/methods/pd_chebyshev.hpp"
#include "solver/petsc/tao_method.hpp"
#include "solver/stepper.hpp"

namespace descent {

template <class Real>
std::unique_ptr<Stepper<Real>> make_stepper(LocalProblem<Real>& problem, const SolverSpec& spec) {
  if (spec.method == "chebyshev")
    return std::make_unique<ChebyshevDescent<Real>>(
        problem, spec, make_host_engine(problem, problem.halo(), EngineOptions{}));
  if (spec.method == "gd") return std::make_unique<GradientDescent<Real>>(problem, spec, false);
  if (spec.method == "jacobi_gd")
    return std::make_unique<GradientDescent<Real>>(problem, spec, true);
  if (spec.method == "nesterov") return std::make_unique<Nesterov<Real>>(problem, spec);
  if (spec.method == "ncg") return std::make_unique<NonlinearCg<Real>>(problem, spec);
  if (spec.method == "lbfgs") return std::make_unique<Lbfgs<Real>>(problem, spec);
  if (spec.method == "newton") return std::make_unique<Newton<Real>>(problem, spec);
  if (spec.method == "pd_chebyshev") return std::make_unique<PdChebyshev<Real>>(problem, spec);
  if (spec.method == "linear_cg") return std::make_unique<LinearCg<Real>>(problem, spec);
  // PETSc TAO's peers of ncg and lbfgs (docs/tao.md); without PETSc they
  // refuse with an InputError naming the package.
  if (spec.method == "tao_bncg") return std::make_unique<TaoMethod<Real>>(problem, spec, "bncg");
  if (spec.method == "tao_blmvm") return std::make_unique<TaoMethod<Real>>(problem, spec, "blmvm");
  // The scene checks admit only the methods listed here.
  throw LogicError(detail::concat("no stepper for solver.method = ", spec.method));
}

template std::unique_ptr<Stepper<double>> make_stepper(LocalProblem<double>&, const SolverSpec&);
template std::unique_ptr<Stepper<float>> make_stepper(LocalProblem<float>&, const SolverSpec&);

}  // namespace descent
