#include "solver/preconditioners/make_preconditioner.hpp"

#include "common/error.hpp"
#include "solver/preconditioners/multilevel/multilevel_preconditioner.hpp"
#include "solver/preconditioners/petsc_gamg.hpp"

namespace descent {

template <class Real>
std::unique_ptr<Preconditioner<Real>> make_host_preconditioner(LocalProblem<Real>& problem,
                                                               const SolverSpec& spec) {
  const std::string kind = preconditioner_of(spec);
  if (kind == "jacobi") return nullptr;
  if (kind == "multilevel") return make_host_multilevel(problem, spec);
  if (kind == "petsc_gamg") return make_petsc_gamg_preconditioner(problem, spec);
  // The scene checks admit only the preconditioners listed here.
  throw LogicError(detail::concat("no preconditioner for solver.preconditioner = ", kind));
}

template std::unique_ptr<Preconditioner<double>> make_host_preconditioner(LocalProblem<double>&,
                                                                          const SolverSpec&);
template std::unique_ptr<Preconditioner<float>> make_host_preconditioner(LocalProblem<float>&,
                                                                         const SolverSpec&);

}  // namespace descent
