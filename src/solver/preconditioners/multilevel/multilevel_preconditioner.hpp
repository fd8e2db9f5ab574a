#pragma once
// solver.preconditioner = "multilevel": one symmetric V-cycle of smoothed
// aggregation as P^-1 (DESIGN §1, "Preconditioners"; the hierarchy in
// hierarchy.hpp, the loops in kernels/multilevel_loops.hpp).
//
// What each level applies: every level at the refresh state. A refresh (each
// step's start, after a rollback) assembles the finest operator, the Hessian
// of eps at q with each element's dP/dF projected to positive semi-definite
// (the Galerkin operator of newton_projection), held dofs removed, forms the
// coarser operators as Galerkin products P^T A P and factors the coarsest;
// P^-1 is then fixed until the next refresh, as the Chebyshev semi-iteration
// assumes. The V-cycle on level l < L (L the coarsest):
//   pre-smoothing   x = S b (solver.multilevel_smoother_degree steps of
//                   Chebyshev-Jacobi from 0 on [b_l / 30, b_l], b_l =
//                   1.1 x lambda_max(D_l^-1 A_l) by Lanczos at the refresh)
//   coarse level    x += P V_{l+1}(P^T (b - A x))
//   post-smoothing  x += S (b - A x), the same polynomial,
// and on L an exact solve. S is symmetric and the post-smoother the
// pre-smoother's adjoint, so P^-1 is symmetric; it is positive definite when
// the bound lies above lambda_max, which the 10% margin keeps.
//
// Messages per V-cycle: per level l < L, 2 x degree products (one halo
// exchange of partial sums each) and one restriction (an exchange on level
// l + 1, none onto L); one MPI_Allgatherv of the coarsest level's partial
// right-hand sides (coarse_solver.hpp): the one collective. Per refresh:
// 1 + 2 x 10 MPI_Allgather of a few reals (the smoother bounds of all
// levels at once, summed in rank order so that every rank gets the same
// bits), one exchange per level for the diagonals, and an MPI_Allgather
// and MPI_Allgatherv of the coarsest operator.
//
// Backends: on the host every loop is an OpenMP loop; with the CUDA engine
// the finest operator is assembled on the device and every level's
// products, smoother updates and transfers run there, while the Galerkin
// products, the smoother bounds and the coarsest solve run on the host (the
// finest operator is copied down once per refresh, the coarsest vectors
// once per V-cycle).
#include <memory>

#include "io/scene.hpp"
#include "solver/local_problem.hpp"
#include "solver/preconditioners/preconditioner.hpp"

namespace descent {

// The host execution's preconditioner, for the methods and the CPU engine;
// with `contact_qt`, the obstacles' contact blocks as make_host_preconditioner
// says. Collective (builds the hierarchy).
template <class Real>
std::unique_ptr<Preconditioner<Real>> make_host_multilevel(LocalProblem<Real>& problem,
                                                           const SolverSpec& spec,
                                                           const Real* contact_qt = nullptr);

}  // namespace descent
