#pragma once
// The exact solve of the coarsest level, redundantly on every rank: its
// operator is gathered whole at each refresh (every rank's partial blocks,
// MPI_Allgatherv, summed in rank order) and factored by a sparse Cholesky
// (Eigen's SimplicialLLT, AMD ordering), the same factor on every rank. A
// solve takes the right-hand side as partial sums over each rank's local
// nodes and completes it with one MPI_Allreduce of the coarsest level's
// size (at most solver.multilevel_coarse_size unknowns): the V-cycle's one
// collective. Unknowns that carry nothing (dropped modes) get an identity
// row, so the solution is 0 there.
#include <mpi.h>

#include <memory>
#include <vector>

#include "solver/preconditioners/multilevel/hierarchy.hpp"

namespace descent {

class CoarseSolver {
 public:
  // Collective: numbers the level's nodes globally (ascending id).
  CoarseSolver(MPI_Comm comm, const LevelLayout& level);
  ~CoarseSolver();
  CoarseSolver(const CoarseSolver&) = delete;
  CoarseSolver& operator=(const CoarseSolver&) = delete;

  // Collective. `values`: this rank's partial operator on `pattern`.
  void factor(const BlockPattern& pattern, const std::vector<double>& values);
  // Collective (one MPI_Allreduce). b: this rank's partial sums, block per
  // local node; x: the solution on every local node.
  void solve(const double* b, double* x);

  long long unknowns() const { return unknowns_; }
  long allreduces() const { return allreduces_; }
  long gathers() const { return gathers_; }

 private:
  struct Factor;
  MPI_Comm comm_;
  int block_;
  std::vector<std::uint8_t> owned_inactive_;  // per local unknown of an owned node
  std::vector<long long> index_;  // per local node: its global index
  long long unknowns_ = 0;
  std::vector<double> rhs_;
  std::unique_ptr<Factor> factor_;
  long allreduces_ = 0, gathers_ = 0;
};

}  // namespace descent
