#pragma once
// Host-side operations on a level's partial operator (block CSR, layout of
// block_sparse.hpp) that the set-up and each refresh need: its product and
// diagonal, and the largest eigenvalue of D^-1 A for several levels at once.
#include <mpi.h>

#include <functional>
#include <vector>

#include "comm/halo.hpp"
#include "solver/preconditioners/multilevel/block_sparse.hpp"

namespace descent {

// y = A_r x over every local row (this rank's partial sum; complete it with
// the level's halo). `values`: block * block per slot.
template <class T>
void partial_product(const BlockPattern& pattern, const T* values, int block, const double* x,
                     double* y);

// The diagonal of A_r (block per node), partial like A_r.
template <class T>
std::vector<double> partial_diagonal(const BlockPattern& pattern, const T* values, int block);

// 1/d where d > 0 and the unknown is active, else 0: the Jacobi inverse that
// leaves held dofs and dropped modes at 0.
std::vector<double> inverse_diagonal(const std::vector<double>& diagonal,
                                     const std::vector<std::uint8_t>& active);

// One operator whose largest eigenvalue of D^-1 A is wanted.
struct LanczosTarget {
  index_t size = 0;   // local unknowns
  index_t owned = 0;  // unknowns [0, owned) counted in inner products
  const double* inv_diagonal = nullptr;
  const global_index_t* global = nullptr;  // per node, for the start vector
  int block = 1;
  // y = A x, complete on every local unknown (halo included).
  std::function<void(const double* x, double* y)> product;
};

// lambda_max(D^-1 A) of every target: `steps` Lanczos steps in the D inner
// product from a start vector drawn by global id (the same on every rank
// count), the inner products of all targets fused: 1 + 2 steps collectives
// in all (rank_ordered_sum), added to `collectives`. The largest Ritz
// value, which lies below lambda_max; 0 for a target with nothing active.
std::vector<double> largest_eigenvalues(MPI_Comm comm, const std::vector<LanczosTarget>& targets,
                                        int steps, long& collectives);

// Sums `count` values over all ranks in place, adding the ranks' values in
// rank order (one MPI_Allgather): every rank gets the same bits, which the
// smoother's coefficients need, as sharers of a node must update it alike.
void rank_ordered_sum(MPI_Comm comm, double* values, int count);

}  // namespace descent
