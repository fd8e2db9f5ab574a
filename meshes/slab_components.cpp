// The largest component over slabs: label within the slab, match across the
// face below, unite everywhere; see slab_components.hpp.
#include "meshes/slab_components.hpp"

#include <algorithm>
#include <array>
#include <limits>
#include <numeric>

#include "comm/mpi_check.hpp"
#include "common/error.hpp"
#include "meshes/all_gather.hpp"

namespace descent::helix {
namespace {

constexpr index_t kOutside = -1;  // the label of a cell outside the body

// A face-connected component of the body within one slab; the global table of
// them, rank by rank, numbers them all.
struct SlabComponent {
  std::int64_t size;        // cells
  std::int64_t first_cell;  // its smallest global cell index
};

struct SlabLabels {
  std::vector<index_t> label;             // per slab cell, layout as `inside`
  std::vector<SlabComponent> components;  // in the order found, i.e. by first_cell
};

// Flood fill of the slab's body, seeds in cell order.
SlabLabels label_slab(const Grid& grid, const Slabs& slabs,
                      const std::vector<std::uint8_t>& inside) {
  const std::size_t nx = grid.nx, nz = grid.nz, layer = grid.cells_per_layer();
  const std::size_t num_layers = slabs.size();
  const std::int64_t slab_first_cell = std::int64_t(slabs.first()) * grid.cells_per_layer();
  SlabLabels labels;
  labels.label.assign(inside.size(), kOutside);
  std::vector<std::size_t> stack;
  for (std::size_t seed = 0; seed < inside.size(); ++seed) {
    if (!inside[seed] || labels.label[seed] != kOutside) continue;
    if (labels.components.size() == std::size_t(std::numeric_limits<index_t>::max()))
      throw InputError(
          "mesh.helix.resolution is too high for the rank count: one rank's slab of the grid "
          "holds more components than a 32-bit index numbers; run on more ranks");
    const index_t id = index_t(labels.components.size());
    std::int64_t size = 0;
    labels.label[seed] = id;
    stack.push_back(seed);
    while (!stack.empty()) {
      const std::size_t cell = stack.back();
      stack.pop_back();
      ++size;
      const std::size_t i = cell % nx, k = (cell / nx) % nz, j = cell / layer;
      auto visit = [&](std::size_t neighbour) {
        if (inside[neighbour] && labels.label[neighbour] == kOutside) {
          labels.label[neighbour] = id;
          stack.push_back(neighbour);
        }
      };
      if (i > 0) visit(cell - 1);
      if (i + 1 < nx) visit(cell + 1);
      if (k > 0) visit(cell - nx);
      if (k + 1 < nz) visit(cell + nx);
      if (j > 0) visit(cell - layer);
      if (j + 1 < num_layers) visit(cell + layer);
    }
    labels.components.push_back({size, slab_first_cell + std::int64_t(seed)});
  }
  return labels;
}

// Pairs (global id below, global id here) of components that touch across the
// face between this slab and the one below, each pair once.
std::vector<std::array<std::int64_t, 2>> matches_with_slab_below(MPI_Comm comm, const Grid& grid,
                                                                 const Slabs& slabs,
                                                                 const SlabLabels& labels,
                                                                 std::int64_t first_id) {
  const index_t layer = grid.cells_per_layer();
  auto global_id = [&](index_t label) { return label == kOutside ? -1 : first_id + label; };
  std::vector<std::int64_t> top_ids;
  if (!slabs.empty()) {
    const std::size_t top = std::size_t(slabs.size() - 1) * layer;
    top_ids.resize(layer);
    for (index_t c = 0; c < layer; ++c) top_ids[c] = global_id(labels.label[top + c]);
  }
  const std::vector<std::int64_t> below_ids = layer_from_below(comm, slabs, top_ids.data(), layer);
  std::vector<std::array<std::int64_t, 2>> matches;
  for (std::size_t c = 0; c < below_ids.size(); ++c)
    if (below_ids[c] >= 0 && labels.label[c] != kOutside)
      matches.push_back({below_ids[c], global_id(labels.label[c])});
  std::sort(matches.begin(), matches.end());
  matches.erase(std::unique(matches.begin(), matches.end()), matches.end());
  return matches;
}

}  // namespace

ComponentCensus keep_largest_component(MPI_Comm comm, const Grid& grid, const Slabs& slabs,
                                       std::vector<std::uint8_t>& inside) {
  const SlabLabels labels = label_slab(grid, slabs, inside);
  // Global ids: the components of lower ranks first.
  std::int64_t num_mine = std::int64_t(labels.components.size()), first_id = 0;
  DESCENT_MPI_CHECK(MPI_Exscan(&num_mine, &first_id, 1, MPI_INT64_T, MPI_SUM, comm));
  if (slabs.rank() == 0) first_id = 0;  // MPI_Exscan leaves rank 0's undefined
  const auto matches = matches_with_slab_below(comm, grid, slabs, labels, first_id);

  const std::vector<SlabComponent> all = all_gather(comm, labels.components);
  const auto all_matches = all_gather(comm, matches);
  if (all.empty()) return {};

  std::vector<std::int64_t> parent(all.size());
  std::iota(parent.begin(), parent.end(), 0);
  auto root = [&](std::int64_t id) {
    while (parent[id] != id) id = parent[id] = parent[parent[id]];
    return id;
  };
  for (const auto& [a, b] : all_matches) {
    const std::int64_t root_a = root(a), root_b = root(b);
    parent[std::max(root_a, root_b)] = std::min(root_a, root_b);
  }
  // Whole components, accumulated on their root.
  std::vector<SlabComponent> whole(all.size(), {0, std::numeric_limits<std::int64_t>::max()});
  for (std::size_t id = 0; id < all.size(); ++id) {
    SlabComponent& sum = whole[root(std::int64_t(id))];
    sum.size += all[id].size;
    sum.first_cell = std::min(sum.first_cell, all[id].first_cell);
  }
  ComponentCensus census;
  std::int64_t largest = -1, num_body_cells = 0;
  for (std::size_t id = 0; id < all.size(); ++id) {
    if (root(std::int64_t(id)) != std::int64_t(id)) continue;
    ++census.num_components;
    num_body_cells += whole[id].size;
    if (largest < 0 || whole[id].size > whole[largest].size ||
        (whole[id].size == whole[largest].size && whole[id].first_cell < whole[largest].first_cell))
      largest = std::int64_t(id);
  }
  census.body_cells_dropped = num_body_cells - whole[largest].size;

  std::vector<std::uint8_t> keep(labels.components.size());
  for (std::size_t label = 0; label < keep.size(); ++label)
    keep[label] = root(first_id + std::int64_t(label)) == largest;
  for (std::size_t cell = 0; cell < inside.size(); ++cell)
    if (labels.label[cell] != kOutside && !keep[labels.label[cell]]) inside[cell] = 0;
  return census;
}

}  // namespace descent::helix
