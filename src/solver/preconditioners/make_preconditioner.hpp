#pragma once
// The preconditioner solver.preconditioner names, on the host execution (the
// methods' vectors and the CPU engine's live there). Null for "jacobi": the
// methods and the engine keep their own fused diagonal. With obstacles'
// barriers (contact.method = "energy") and `contact_qt`, the step-start
// positions the barriers' lagged friction is taken from (3 per local vertex,
// living as long as the preconditioner), a multilevel P^-1 takes the
// obstacles' contact blocks into its finest operator at each refresh.
// Collective.
#include <memory>

#include "io/scene.hpp"
#include "solver/local_problem.hpp"
#include "solver/preconditioners/preconditioner.hpp"

namespace descent {

// Whether the multilevel P^-1 that solver.preconditioner = "auto" names
// fits the problem: not where its operator is singular, a quasi-static body
// that nothing holds (its rigid motions cost nothing), and with contact
// between bodies only for a method that `takes_pairs`, newton's CG, which
// refreshes it at each iterate with the pairs' diagonal (their couplings,
// which the hierarchy's operators do not know, slowed the Chebyshev
// descent: docs/contact.md). Collective (one allreduce: whether any rank
// holds a dof).
template <class Real>
bool multilevel_fits(LocalProblem<Real>& problem, bool takes_pairs);

// With solver.preconditioner = "auto", null (Jacobi's) where the multilevel
// P^-1 that preconditioner_of() names does not fit.
template <class Real>
std::unique_ptr<Preconditioner<Real>> make_host_preconditioner(LocalProblem<Real>& problem,
                                                               const SolverSpec& spec,
                                                               const Real* contact_qt = nullptr);

}  // namespace descent
