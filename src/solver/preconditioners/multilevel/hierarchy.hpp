#pragma once
// The multilevel hierarchy's structure (DESIGN §1 and §3, "Multilevel"),
// built once at set-up from the rest mesh: which nodes each level has on
// this rank, how its nodes are shared with other ranks, and the fixed
// prolongation P from each level to the next finer one. The operators
// themselves change with the state (multilevel_preconditioner.hpp).
//
// Smoothed aggregation (Vanek, Mandel, Brezina 1996), built so that P ranks
// make the hierarchy of 1 rank (to round-off):
//   - aggregates: the nodes of a level grouped by the cells of a grid over
//     their positions, split into connected pieces (aggregation.hpp);
//     the grid's edge is solver.multilevel_cell mean edge lengths at the
//     finest level, doubled at each coarser one;
//   - coarse space: each aggregate's six rigid motions about its root,
//     orthonormalised over the aggregate by a Cholesky QR that drops modes
//     its nodes cannot carry (one node: no rotations; nodes on a line: no
//     rotation about it) and held dofs (their rows are 0): the tentative
//     prolongation P_t, and the aggregate's near-null block R for the next
//     level;
//   - smoothing: P = (I - omega D^-1 A) P_t with A the level's operator at
//     rest (the finest: the Hessian of eps at the rest state, held dofs
//     removed) and omega = 4 / (3 lambda_max(D^-1 A));
//   - the next level's operator at rest is the Galerkin product P^T A P.
// Coarsening stops at solver.multilevel_coarse_size unknowns (or when a
// level no longer shrinks), the coarsest level being solved exactly. Its
// size depends neither on the mesh nor on the rank count; the number of
// levels grows with log(mesh size).
//
// Distribution: every rank holds a level's operator as the partial sum of
// its own tets' contributions (P^T A_r P over its part A_r of the finer
// operator), over its local nodes: the level-l+1 nodes that P's rows of its
// level-l nodes reach. A node several ranks hold is shared like a shared
// vertex: owned by the lowest of them, its partial sums completed through
// the level's halo in rank order, so all sharers hold bitwise equal totals.
// Each rank holds P's complete rows for all its local nodes (set-up
// exchanges the partial rows of shared ones).
#include <mpi.h>

#include <cstdint>
#include <vector>

#include "comm/halo.hpp"
#include "partition/local_mesh.hpp"
#include "solver/preconditioners/multilevel/block_sparse.hpp"

namespace descent {

// One level's nodes on this rank. Local order: [interior | shared owned |
// shared not owned], each by ascending global id (the finest level is the
// LocalMesh's own order). Vectors of the level hold `block` reals per node.
struct LevelLayout {
  int block = 3;  // unknowns per node: 3 at the finest level, 6 (rigid motions) above
  std::vector<global_index_t> global;  // global id per local node (finest: the vertex's)
  index_t num_interior = 0, num_owned = 0;
  std::vector<double> position;      // 3 per node: the vertex's, or its aggregate root's
  std::vector<std::uint8_t> active;  // per unknown: 0 for held dofs and dropped modes
  HaloPattern halo;

  index_t num_nodes() const { return static_cast<index_t>(global.size()); }
};

struct HierarchyOptions {
  double cell = 0;               // the finest level's aggregation cell (metres)
  long long coarse_size = 2000;  // unknowns at most of the coarsest level
  int max_levels = 16;
};

struct Hierarchy {
  std::vector<LevelLayout> levels;  // finest first
  // prolongation[l]: rows level l's nodes, columns level l+1's, blocks
  // levels[l].block x levels[l+1].block; a row's blocks in ascending global
  // id of their coarse node (not local index, unlike an operator's), so that
  // every rank holding a node sums its row in the same order.
  std::vector<BlockMatrix<double>> prolongation;
  // operator_pattern[l]: the pattern of this rank's partial operator of
  // level l (the finest: the vertex pairs of its tets).
  std::vector<BlockPattern> operator_pattern;
  std::vector<long long> global_unknowns;  // per level, over all ranks
  std::vector<double> smoothing_weight;    // omega per prolongation
};

// Collective. `fine_rest`: this rank's partial Hessian of eps at the rest
// state over its local vertices (3x3 blocks, held dofs' rows and columns 0,
// vertex terms on owned vertices only), read in place.
Hierarchy build_hierarchy(MPI_Comm comm, const LocalMesh& mesh, const BlockView& fine_rest,
                          const std::vector<std::uint8_t>& fixed_axes,
                          const HierarchyOptions& options);

}  // namespace descent
