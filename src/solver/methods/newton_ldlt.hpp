#pragma once
// Newton's direct linear solver (solver.newton_solver = "ldlt"): the global
// system H dq = -g assembled on rank 0 and factored there with Eigen's sparse
// LDL^T (SimplicialLDLT, AMD ordering). No CG tolerance: the Newton step up
// to round-off, for meshes whose Hessian fits one rank's memory.
//
// Data: every tet lies on exactly one rank (partition_tets) and every vertex
// is owned by exactly one rank (the lowest that uses it, LocalMesh), so rank 0
// sums each element Hessian (HessianOperator layout: 144 per local tet,
// row-major, corner order = the tet's 4 vertices x xyz) and each dof's vertex
// curvature and right-hand side exactly once. Global dof 3 v + i for global
// vertex v, axis i. Held dofs (and ids no tet uses) get an identity row and
// column and right-hand side 0, so dq = 0 there, as in the masked CG. Only
// the lower triangle is stored: it is all SimplicialLDLT reads.
//
// Collectives, through EnergyReduction (counted as root gathers/scatters,
// never as MPI_Allreduce):
//   set-up (constructor): 1 MPI_Gather (counts) + 2 MPI_Gatherv (vertex ids,
//     held masks and tets; vertex curvature); rank 0 fixes the sparsity
//     pattern and runs the symbolic analysis once;
//   per solve: 1 MPI_Gatherv (element Hessians, -g of owned dofs) + 1
//     MPI_Scatterv (dq on each rank's local vertices, shared ones identical
//     on every sharer, plus the positive-definite flag); rank 0 refactors.
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <vector>

#include "solver/local_problem.hpp"
#include "solver/methods/hessian_operator.hpp"

namespace descent {

template <class Real>
class NewtonLdlt {
 public:
  // Collective over the problem's ranks (set-up above).
  NewtonLdlt(LocalProblem<Real>& problem, const HessianOperator<Real>& hessian);

  // dq = -H^-1 g with H the element Hessians last stored by
  // hessian.assemble plus the vertex curvature; g and dq 3 reals per local
  // vertex. Returns whether H is positive definite: the factorization
  // succeeded and every entry of D is > 0 (Sylvester: D has H's inertia).
  // On a zero pivot dq is the Jacobi step -g / diag(H), flagged not positive.
  // Collective (per solve above).
  bool solve(const Real* g, Real* dq);

 private:
  using Matrix = Eigen::SparseMatrix<double>;  // column-major, lower triangle

  LocalProblem<Real>& problem_;
  const HessianOperator<Real>& hessian_;
  bool root_;
  std::vector<int> solve_counts_;    // per rank: 144 tets + 3 owned vertices (root)
  std::vector<int> scatter_counts_;  // per rank: 3 local vertices + 1 flag (root)
  std::vector<double> send_, received_, scattered_;

  // Rank 0 only, rank blocks in rank order.
  std::vector<index_t> tets_per_rank_, owned_per_rank_, vertices_per_rank_;
  std::vector<index_t> owned_vertex_;  // global ids of owned vertices
  std::vector<index_t> local_vertex_;  // global ids of local vertices (per rank block)
  std::vector<int> entry_slot_;        // per element-Hessian entry: index in A's values, or -1
  std::vector<int> diagonal_slot_;     // per global dof: index of (d, d) in A's values
  std::vector<double> base_diagonal_;  // per global dof: curvature, or 1 on held dofs
  std::vector<std::uint8_t> held_;     // per global dof
  Matrix matrix_;
  Eigen::SimplicialLDLT<Matrix, Eigen::Lower> ldlt_;
  Eigen::VectorXd rhs_, solution_;
};

}  // namespace descent
