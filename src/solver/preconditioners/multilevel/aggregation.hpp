#pragma once
// The aggregates of one level (smoothed aggregation's first step): the
// level's nodes grouped by the cells of a grid over their positions, each
// cell's nodes split into the connected pieces of the level's graph inside
// the cell, so an aggregate never joins two bodies or two strands that only
// pass near each other. Independent of the partition: the cell of a node
// depends on its position alone, and each cell's pieces are found whole on
// one rank (the cell's home), from the nodes and edges every rank sends it.
//
// An aggregate is named by its root, the node of smallest global id in it;
// the root's position stands for the aggregate's (exact, so the next level's
// cells do not depend on round-off).
#include <mpi.h>

#include <vector>

#include "common/mesh.hpp"
#include "solver/preconditioners/multilevel/block_sparse.hpp"

namespace descent {

struct Aggregates {
  std::vector<global_index_t> root;   // per local node: its aggregate's root (global id)
  std::vector<double> root_position;  // 3 per local node: the root's position
};

// Collective. `global`: global id per local node; `position`: 3 per local
// node; `graph`: the level's couplings between local nodes (a square pattern;
// the union over ranks is the whole level's graph); `cell`: the grid's edge.
Aggregates aggregate_by_cells(MPI_Comm comm, const std::vector<global_index_t>& global,
                              const std::vector<double>& position, const BlockPattern& graph,
                              double cell);

}  // namespace descent
