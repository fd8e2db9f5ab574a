#pragma once
// Recursive coordinate bisection of tet centroids (partition.method =
// "rcb"): a partition that needs no dual graph. The tets are split in two
// across the longest side of their centroids' bounding box, each half is
// split again, and so on until there are nparts parts.
//
// Every split is exact: part p gets BlockRange(num_tets, nparts).size(p)
// tets (parts differ by at most one). The split point is the k-th tet in
// the order of (centroid coordinate along the axis, global tet id), found
// by a parallel radix select on those 128-bit keys: byte by byte, a
// histogram per group of tets summed over the ranks. Bounding boxes are
// MPI_MIN / MPI_MAX of the centroids and centroids are computed from the
// input's positions in corner order, so the part of every tet depends only
// on the mesh and nparts: not on the ranks that compute it.
#include <mpi.h>

#include <vector>

#include "common/mesh_slice.hpp"

namespace descent {

// Collective: the centroid (xyz) of each tet of the slice; the positions of
// corners outside this rank's vertex block are asked from their blocks'
// ranks.
std::vector<double> tet_centroids(MPI_Comm comm, const MeshSlice& slice);

// Collective: the part in [0, nparts) of each tet of the slice (nparts >=
// 1); fewer tets than parts is a PartitionError.
std::vector<int> partition_by_coordinates(MPI_Comm comm, const MeshSlice& slice, int nparts);

}  // namespace descent
