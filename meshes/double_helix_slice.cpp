// The double helix generated block by block: rank r of P returns
// slice_of(make_double_helix(params), r, P), bit for bit, while no rank
// voxelizes, numbers or stores more than its share and a few cell layers.
//
// 1. Each rank voxelizes its slab of cell layers (slabs.hpp) with the serial
//    generator's arithmetic (double_helix_grid.hpp).
// 2. The body's largest component is kept, found over all slabs
//    (slab_components.hpp).
// 3. Per-layer counts of body cells and of used nodes, gathered on every
//    rank, give each cell layer its first tet (6 per body cell, cell order)
//    and each node layer its first vertex (used nodes, node order).
// 4. Each rank fetches the kept cells of the layers its tet and vertex blocks
//    touch (fetched_layers.hpp) and emits those blocks.
#include "meshes/double_helix_slice.hpp"

#include <algorithm>
#include <vector>

#include "comm/mpi_check.hpp"
#include "common/block_range.hpp"
#include "common/error.hpp"
#include "meshes/all_gather.hpp"
#include "meshes/double_helix_grid.hpp"
#include "meshes/fetched_layers.hpp"
#include "meshes/hex_split.hpp"
#include "meshes/slab_components.hpp"
#include "meshes/slabs.hpp"
#include "meshes/slice_limits.hpp"

namespace descent {
namespace helix {
namespace {

constexpr global_index_t kUnusedNode = -1;

// 1 for each node of a node layer that a body cell of the cell layer below or
// above uses, else 0 (layout k * (nx + 1) + i); a null cell layer has none.
void mark_used_nodes(const Grid& grid, const std::uint8_t* below, const std::uint8_t* above,
                     std::vector<std::uint8_t>& used) {
  used.assign(grid.nodes_per_layer(), 0);
  const index_t row = grid.nx + 1;
  for (const std::uint8_t* cells : {below, above}) {
    if (!cells) continue;
    for (index_t k = 0; k < grid.nz; ++k)
      for (index_t i = 0; i < grid.nx; ++i)
        if (cells[k * grid.nx + i]) {
          const index_t node = k * row + i;
          used[node] = used[node + 1] = used[node + row] = used[node + row + 1] = 1;
        }
  }
}

// Where the global numbering gives each layer its tets and vertices: cell
// layer j holds tets [tet_first[j], tet_first[j + 1]) and node layer j
// vertices [vertex_first[j], vertex_first[j + 1]).
struct LayerOffsets {
  std::vector<global_index_t> tet_first;     // ny + 1 entries
  std::vector<global_index_t> vertex_first;  // ny + 2 entries

  // The cell layer holding tet t (0 <= t < number of tets).
  index_t cell_layer_of_tet(global_index_t t) const {
    return index_t(std::upper_bound(tet_first.begin(), tet_first.end(), t) - tet_first.begin() - 1);
  }
  // The node layer holding vertex v (0 <= v < number of vertices).
  index_t node_layer_of_vertex(global_index_t v) const {
    return index_t(std::upper_bound(vertex_first.begin(), vertex_first.end(), v) -
                   vertex_first.begin() - 1);
  }
};

// Collective. `kept` is the filtered slab, `kept_below` the cell layer just
// below it (empty if none). Each rank counts node layers first() .. end() - 1
// of its slab, and the last rank also the top node layer ny.
LayerOffsets layer_offsets(MPI_Comm comm, const Grid& grid, const Slabs& slabs,
                           const std::vector<std::uint8_t>& kept,
                           const std::vector<std::uint8_t>& kept_below) {
  const index_t layer = grid.cells_per_layer();
  std::vector<std::int64_t> body_cells, used_nodes;
  std::vector<std::uint8_t> used;
  const std::uint8_t* below = kept_below.empty() ? nullptr : kept_below.data();
  for (index_t j = 0; j < slabs.size(); ++j) {
    const std::uint8_t* cells = kept.data() + std::size_t(j) * layer;
    body_cells.push_back(std::count(cells, cells + layer, 1));
    mark_used_nodes(grid, below, cells, used);
    used_nodes.push_back(std::count(used.begin(), used.end(), 1));
    below = cells;
  }
  if (!slabs.empty() && slabs.end() == slabs.num_layers()) {
    mark_used_nodes(grid, below, nullptr, used);
    used_nodes.push_back(std::count(used.begin(), used.end(), 1));
  }
  const std::vector<std::int64_t> all_body_cells = all_gather(comm, body_cells);
  const std::vector<std::int64_t> all_used_nodes = all_gather(comm, used_nodes);

  LayerOffsets offsets;
  offsets.tet_first.assign(1, 0);
  for (std::int64_t count : all_body_cells)
    offsets.tet_first.push_back(offsets.tet_first.back() + 6 * count);
  offsets.vertex_first.assign(1, 0);
  for (std::int64_t count : all_used_nodes)
    offsets.vertex_first.push_back(offsets.vertex_first.back() + count);
  return offsets;
}

// The cell layers a rank needs for its blocks, as disjoint ascending spans:
// its tets' cell layers and one more each side (a tet's corners lie on node
// layers j and j + 1, numbered from cell layers j - 1 .. j + 1), and the two
// cell layers around each node layer of its vertices.
std::vector<LayerSpan> layers_needed(const LayerOffsets& offsets, const BlockRange& tets,
                                     const BlockRange& vertices, index_t ny, int rank) {
  std::vector<LayerSpan> spans;
  if (tets.size(rank) > 0) {
    const index_t first = offsets.cell_layer_of_tet(tets.begin(rank));
    const index_t last = offsets.cell_layer_of_tet(tets.end(rank) - 1);
    spans.push_back({std::max(0, first - 1), std::min(ny, last + 2)});
  }
  if (vertices.size(rank) > 0) {
    const index_t first = offsets.node_layer_of_vertex(vertices.begin(rank));
    const index_t last = offsets.node_layer_of_vertex(vertices.end(rank) - 1);
    spans.push_back({std::max(0, first - 1), std::min(ny, last + 1)});
  }
  if (spans.size() == 2) {
    if (spans[1].first < spans[0].first) std::swap(spans[0], spans[1]);
    if (spans[1].first <= spans[0].end) {
      spans[0].end = std::max(spans[0].end, spans[1].end);
      spans.pop_back();
    }
  }
  return spans;
}

// Global vertex id of each node of node layer j, or kUnusedNode (layout
// k * (nx + 1) + i).
void number_node_layer(const Grid& grid, const FetchedLayers& layers, const LayerOffsets& offsets,
                       index_t j, std::vector<global_index_t>& vertex_of_node) {
  std::vector<std::uint8_t> used;
  mark_used_nodes(grid, layers.layer(j - 1), layers.layer(j), used);
  vertex_of_node.resize(used.size());
  global_index_t next = offsets.vertex_first[j];
  for (std::size_t node = 0; node < used.size(); ++node)
    vertex_of_node[node] = used[node] ? next++ : kUnusedNode;
}

// Tets [first, end) of the global numbering, 4 vertex ids each.
std::vector<global_index_t> emit_tets(const Grid& grid, const FetchedLayers& layers,
                                      const LayerOffsets& offsets, global_index_t first,
                                      global_index_t end) {
  std::vector<global_index_t> tets;
  if (first == end) return tets;
  tets.reserve(4 * std::size_t(end - first));
  const index_t row = grid.nx + 1;
  const index_t first_layer = offsets.cell_layer_of_tet(first);
  const index_t last_layer = offsets.cell_layer_of_tet(end - 1);
  std::vector<global_index_t> lower, upper;  // vertex ids on node layers j and j + 1
  number_node_layer(grid, layers, offsets, first_layer, upper);
  for (index_t j = first_layer; j <= last_layer; ++j) {
    std::swap(lower, upper);
    number_node_layer(grid, layers, offsets, j + 1, upper);
    const std::uint8_t* cells = layers.layer(j);
    global_index_t tet = offsets.tet_first[j];
    for (index_t k = 0; k < grid.nz; ++k)
      for (index_t i = 0; i < grid.nx; ++i) {
        if (!cells[k * grid.nx + i]) continue;
        if (tet + 6 <= first) {
          tet += 6;
          continue;
        }
        global_index_t corner_vertex[8];
        for (int corner = 0; corner < 8; ++corner) {
          const index_t node = (k + ((corner >> 2) & 1)) * row + i + (corner & 1);
          corner_vertex[corner] = ((corner >> 1) & 1 ? upper : lower)[node];
        }
        for (const hex_split::TetCorners& corners : hex_split::kKuhnTets) {
          if (tet >= first && tet < end)
            for (int corner : corners) tets.push_back(corner_vertex[corner]);
          ++tet;
        }
      }
  }
  return tets;
}

// Positions of vertices [first, end) of the global numbering, xyz each.
std::vector<double> emit_positions(const Grid& grid, const FetchedLayers& layers,
                                   const LayerOffsets& offsets, global_index_t first,
                                   global_index_t end) {
  std::vector<double> positions;
  if (first == end) return positions;
  positions.reserve(3 * std::size_t(end - first));
  std::vector<global_index_t> vertex_of_node;
  for (index_t j = offsets.node_layer_of_vertex(first); j <= offsets.node_layer_of_vertex(end - 1);
       ++j) {
    number_node_layer(grid, layers, offsets, j, vertex_of_node);
    for (index_t k = 0; k <= grid.nz; ++k)
      for (index_t i = 0; i <= grid.nx; ++i) {
        const global_index_t vertex = vertex_of_node[k * (grid.nx + 1) + i];
        if (vertex >= first && vertex < end)
          positions.insert(positions.end(), {grid.node_x(i), grid.node_y(j), grid.node_x(k)});
      }
  }
  return positions;
}

}  // namespace

SliceAndWork make_slice_and_work(MPI_Comm comm, const DoubleHelixParams& params) {
  validate(params);
  const Geometry g = geometry_of(params);
  const Grid grid = make_grid(params, g, NodeIndexing::kOneLayer);
  int rank = 0, num_ranks = 1;
  DESCENT_MPI_CHECK(MPI_Comm_rank(comm, &rank));
  DESCENT_MPI_CHECK(MPI_Comm_size(comm, &num_ranks));
  const Slabs slabs(grid.ny, rank, num_ranks);
  const index_t layer = grid.cells_per_layer();

  SliceAndWork result;
  SliceWork& work = result.work;
  work.nx = grid.nx;
  work.ny = grid.ny;
  work.nz = grid.nz;

  // Layout as in slabs.hpp: 1 for a body cell, else 0.
  std::vector<std::uint8_t> kept(std::size_t(slabs.size()) * layer);
  if (!slabs.empty()) {
    const std::vector<Column> columns = columns_of(grid);
    for (index_t j = slabs.first(); j < slabs.end(); ++j)
      voxelize_layer(grid, g, columns, j, kept.data() + std::size_t(j - slabs.first()) * layer);
  }
  work.cells_voxelized = std::int64_t(kept.size());

  const ComponentCensus census = keep_largest_component(comm, grid, slabs, kept);
  if (census.num_components == 0) throw_no_cell_in_body(params);
  work.num_components = census.num_components;
  work.body_cells_dropped = census.body_cells_dropped;

  const std::uint8_t* top = slabs.empty() ? nullptr : kept.data() + kept.size() - layer;
  const LayerOffsets offsets =
      layer_offsets(comm, grid, slabs, kept, layer_from_below(comm, slabs, top, layer));
  const global_index_t num_tets = offsets.tet_first.back();
  const global_index_t num_vertices = offsets.vertex_first.back();
  require_blocks_fit_index(detail::concat("mesh.helix.resolution = ", params.resolution), num_tets,
                           num_vertices, num_ranks);
  const BlockRange tets(num_tets, num_ranks), vertices(num_vertices, num_ranks);

  std::vector<std::vector<LayerSpan>> needed(num_ranks);
  for (int r = 0; r < num_ranks; ++r)
    needed[r] = layers_needed(offsets, tets, vertices, grid.ny, r);
  const FetchedLayers layers(comm, slabs, layer, kept, needed);
  work.cell_layers_fetched = std::int64_t(layers.num_layers());

  MeshSlice& slice = result.slice;
  slice.source = source_of(params);
  slice.num_global_tets = num_tets;
  slice.num_global_vertices = num_vertices;
  slice.first_tet = tets.begin(rank);
  slice.tets = emit_tets(grid, layers, offsets, tets.begin(rank), tets.end(rank));
  slice.first_vertex = vertices.begin(rank);
  slice.positions = emit_positions(grid, layers, offsets, vertices.begin(rank), vertices.end(rank));
  return result;
}

}  // namespace helix

MeshSlice make_double_helix_slice(MPI_Comm comm, const DoubleHelixParams& params) {
  return helix::make_slice_and_work(comm, params).slice;
}

}  // namespace descent
