#pragma once
// The Galerkin product C = P^T A P of a level's partial operator A (this
// rank's part, over its local nodes) and the prolongation P to the next
// level (complete rows for every local node): this rank's part of the next
// level's operator. No communication: the parts of all ranks sum to the
// whole, since A's do and P is the same on every rank.
//
// The pattern is fixed at set-up (galerkin_pattern); a refresh recomputes
// the values only. One pass over A's rows on one thread: for each row v,
// (A P)_v = sum_u A_vu P_u into a dense accumulator over coarse nodes, then
// C_IJ += P_vI^T (A P)_vJ for every block I of P's row v and J >= I (a fixed
// order, so the result does not depend on the thread count); C is
// symmetric, the blocks left of its diagonal are the mirror images.
#include <vector>

#include "solver/preconditioners/multilevel/block_sparse.hpp"

namespace descent {

BlockPattern galerkin_pattern(const BlockPattern& a, const BlockPattern& p);

// C's values (zeroed first) for the pattern `c` from galerkin_pattern;
// `a_values`: a_block^2 per slot of `a`; P's blocks a_block x p.col_block.
template <class T>
void galerkin_product(const BlockPattern& a, const T* a_values, const BlockMatrix<double>& p,
                      const BlockPattern& c, std::vector<double>& c_values);

}  // namespace descent
