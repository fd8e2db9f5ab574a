#pragma once
// The preconditioner solver.preconditioner names, on the host execution (the
// methods' vectors and the CPU engine's live there). Null for "jacobi": the
// methods and the engine keep their own fused diagonal. Collective.
#include <memory>

#include "io/scene.hpp"
#include "solver/local_problem.hpp"
#include "solver/preconditioners/preconditioner.hpp"

namespace descent {

template <class Real>
std::unique_ptr<Preconditioner<Real>> make_host_preconditioner(LocalProblem<Real>& problem,
                                                               const SolverSpec& spec);

}  // namespace descent
