// The box generated block by block: rank r of P returns
// slice_of(make_box(params), r, P) from closed forms, without communication:
// tet t is tet t % tets_per_cell of cell t / tets_per_cell, and a vertex id is
// its node index (layout in box_grid.hpp).
#include <cstdint>
#include <vector>

#include "comm/mpi_check.hpp"
#include "common/block_range.hpp"
#include "common/error.hpp"
#include "meshes/box_grid.hpp"
#include "meshes/generators.hpp"
#include "meshes/slice_limits.hpp"

namespace descent {
namespace {

// Global counts in 64 bits: the slice path has no 32-bit limit on the whole
// box, only on a rank's block.
void require_counts_fit(const BoxParams& params, int num_ranks) {
  const global_index_t nx = params.cells[0], ny = params.cells[1], nz = params.cells[2];
  const std::string culprit = detail::concat("mesh.box.cells ", nx, " x ", ny, " x ", nz);
  // Well below 2^63, so that the exact counts below cannot overflow.
  constexpr double kMaxCount = 0x1p62;
  if (double(nx + 1) * double(ny + 1) * double(nz + 1) > kMaxCount ||
      double(nx) * double(ny) * double(nz) * params.tets_per_cell > kMaxCount)
    throw InputError(culprit + " gives more tets or vertices than a 64-bit index holds");
  require_blocks_fit_index(culprit, nx * ny * nz * params.tets_per_cell,
                           (nx + 1) * (ny + 1) * (nz + 1), num_ranks);
}

}  // namespace

MeshSlice make_box_slice(MPI_Comm comm, const BoxParams& params) {
  box::validate_values(params);
  int rank = 0, num_ranks = 1;
  DESCENT_MPI_CHECK(MPI_Comm_rank(comm, &rank));
  DESCENT_MPI_CHECK(MPI_Comm_size(comm, &num_ranks));
  require_counts_fit(params, num_ranks);
  const global_index_t nx = params.cells[0], ny = params.cells[1], nz = params.cells[2];
  const global_index_t tets_per_cell = params.tets_per_cell;
  auto node_index = [&](global_index_t i, global_index_t j, global_index_t k) {
    return (k * (ny + 1) + j) * (nx + 1) + i;
  };

  MeshSlice slice;
  slice.source = box::source_of(params);
  slice.num_global_tets = nx * ny * nz * tets_per_cell;
  slice.num_global_vertices = (nx + 1) * (ny + 1) * (nz + 1);
  const BlockRange tets(slice.num_global_tets, num_ranks);
  const BlockRange vertices(slice.num_global_vertices, num_ranks);

  slice.first_tet = tets.begin(rank);
  slice.tets.reserve(4 * std::size_t(tets.size(rank)));
  for (global_index_t tet = tets.begin(rank); tet < tets.end(rank); ++tet) {
    const global_index_t cell = tet / tets_per_cell;
    const global_index_t i = cell % nx, j = cell / nx % ny, k = cell / (nx * ny);
    const hex_split::TetCorners& corners = box::split_of(params, i, j, k)[tet % tets_per_cell];
    for (int corner : corners)
      slice.tets.push_back(
          node_index(i + (corner & 1), j + ((corner >> 1) & 1), k + ((corner >> 2) & 1)));
  }

  slice.first_vertex = vertices.begin(rank);
  slice.positions.reserve(3 * std::size_t(vertices.size(rank)));
  for (global_index_t node = vertices.begin(rank); node < vertices.end(rank); ++node) {
    const global_index_t i = node % (nx + 1), j = node / (nx + 1) % (ny + 1),
                         k = node / ((nx + 1) * (ny + 1));
    slice.positions.insert(slice.positions.end(),
                           {box::coordinate(params, 0, i), box::coordinate(params, 1, j),
                            box::coordinate(params, 2, k)});
  }
  return slice;
}

}  // namespace descent
