#include "solver/preconditioners/make_preconditioner.hpp"

#include <algorithm>

#include "common/error.hpp"
#include "solver/preconditioners/multilevel/multilevel_preconditioner.hpp"
#include "solver/preconditioners/petsc_gamg.hpp"

namespace descent {

template <class Real>
bool multilevel_fits(LocalProblem<Real>& problem, bool takes_pairs) {
  if (problem.body_contact() && !takes_pairs) return false;
  if (problem.vertex_terms().inv_h2 > 0) return true;
  const auto& fixed = problem.fixed_axes();
  const bool held = std::any_of(fixed.begin(), fixed.end(), [](std::uint8_t f) { return f != 0; });
  return problem.global_max(held ? 1.0 : 0.0) > 0;
}

template <class Real>
std::unique_ptr<Preconditioner<Real>> make_host_preconditioner(LocalProblem<Real>& problem,
                                                               const SolverSpec& spec,
                                                               const Real* contact_qt) {
  const std::string kind = preconditioner_of(spec);
  if (kind == "jacobi") return nullptr;
  if (spec.preconditioner == "auto" && !multilevel_fits(problem, spec.method == "newton"))
    return nullptr;
  if (kind == "multilevel") return make_host_multilevel(problem, spec, contact_qt);
  if (kind == "petsc_gamg") return make_petsc_gamg_preconditioner(problem, spec);
  // The scene checks admit only the preconditioners listed here.
  throw LogicError(detail::concat("no preconditioner for solver.preconditioner = ", kind));
}

template bool multilevel_fits(LocalProblem<double>&, bool);
template bool multilevel_fits(LocalProblem<float>&, bool);
template std::unique_ptr<Preconditioner<double>> make_host_preconditioner(LocalProblem<double>&,
                                                                          const SolverSpec&,
                                                                          const double*);
template std::unique_ptr<Preconditioner<float>> make_host_preconditioner(LocalProblem<float>&,
                                                                         const SolverSpec&,
                                                                         const float*);

}  // namespace descent
