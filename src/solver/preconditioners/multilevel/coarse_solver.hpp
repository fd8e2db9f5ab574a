#pragma once
// The exact solve of the coarsest level, redundantly on every rank: its
// operator is gathered whole at each refresh (every rank's partial blocks,
// MPI_Allgatherv, summed in rank order) and factored by a sparse Cholesky
// (Eigen's SimplicialLLT, AMD ordering), the same factor on every rank. A
// solve takes the right-hand side as partial sums over each rank's local
// nodes and completes it with one MPI_Allgatherv of every rank's partial
// sums (about the coarsest level's size, at most
// solver.multilevel_coarse_size unknowns, times the ranks sharing a node),
// the V-cycle's one collective, each rank then adding them in rank order:
// an MPI_Allreduce need not give every rank the same bits (Open MPI's on 3
// ranks did not), and sharers of a vertex must hold bitwise equal values.
// Unknowns that carry nothing (dropped modes) get an identity row, so the
// solution is 0 there. A semi-definite operator (a quasi-static body that
// nothing holds) is factored with a shift of its diagonal, at least
// sqrt(epsilon) of it.
#include <mpi.h>

#include <memory>
#include <vector>

#include "solver/preconditioners/multilevel/hierarchy.hpp"

namespace descent {

class CoarseSolver {
 public:
  // Collective: numbers the level's nodes globally (ascending id).
  // `epsilon`: the machine epsilon of the V-cycle's arithmetic.
  CoarseSolver(MPI_Comm comm, const LevelLayout& level, double epsilon);
  ~CoarseSolver();
  CoarseSolver(const CoarseSolver&) = delete;
  CoarseSolver& operator=(const CoarseSolver&) = delete;

  // Collective. `values`: this rank's partial operator on `pattern`.
  void factor(const BlockPattern& pattern, const std::vector<double>& values);
  // Collective (one MPI_Allgatherv). b: this rank's partial sums, block per
  // local node; x: the solution on every local node.
  void solve(const double* b, double* x);

  long long unknowns() const { return unknowns_; }
  // The relative shift of the diagonal the last factorisation needed (0:
  // none, the operator was positive definite).
  double shift() const { return shift_; }
  // The collectives of the solves (one each) and of the factorisations.
  long solves() const { return solves_; }
  long gathers() const { return gathers_; }

 private:
  struct Factor;
  MPI_Comm comm_;
  int block_;
  double first_shift_;
  std::vector<std::uint8_t> owned_inactive_;  // per local unknown of an owned node
  std::vector<long long> index_;              // per local node: its global index
  long long unknowns_ = 0;
  std::vector<double> rhs_;
  // Every rank's local nodes' global indices, rank after rank (set-up), and
  // the gathered partial sums, block per entry.
  std::vector<long long> gathered_index_;
  std::vector<int> gathered_counts_, gathered_offsets_;
  std::vector<double> gathered_;
  std::unique_ptr<Factor> factor_;
  long solves_ = 0, gathers_ = 0;
  double shift_ = 0;
};

}  // namespace descent
