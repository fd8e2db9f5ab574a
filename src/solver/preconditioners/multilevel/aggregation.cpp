#include "solver/preconditioners/multilevel/aggregation.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <unordered_map>

#include "comm/exchange.hpp"
#include "common/splitmix.hpp"

namespace descent {

namespace {

using Cell = std::array<std::int64_t, 3>;

// The grid is offset by irrational fractions of a cell, so the vertices of a
// voxel mesh (integer multiples of its spacing) never lie on a cell face.
constexpr double kOffset[3] = {0.3819660112501051, 0.2360679774997897, 0.1458980337503155};

Cell cell_of(const double* x, double cell) {
  Cell c;
  for (int i = 0; i < 3; ++i)
    c[i] = static_cast<std::int64_t>(std::floor(x[i] / cell + kOffset[i]));
  return c;
}

int home_of(const Cell& c, int size) {
  std::uint64_t z = 0;
  for (std::int64_t v : c) z = splitmix64(z ^ static_cast<std::uint64_t>(v));
  return static_cast<int>(z % static_cast<std::uint64_t>(size));
}

// A node (b < 0) or an edge between nodes a and b of one cell, sent to the
// cell's home.
struct CellRecord {
  Cell cell;
  std::int64_t a, b;
  double position[3];  // a node's
};

// A node's aggregate, back from the home of its cell.
struct RootRecord {
  std::int64_t node, root;
  double position[3];
};

// The smallest-id representative, with path halving.
std::size_t find(std::vector<std::size_t>& parent, std::size_t i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

}  // namespace

Aggregates aggregate_by_cells(MPI_Comm comm, const std::vector<global_index_t>& global,
                              const std::vector<double>& position, const BlockPattern& graph,
                              double cell) {
  int size = 1;
  MPI_Comm_size(comm, &size);
  const std::size_t n = global.size();
  std::vector<Cell> cells(n);
  for (std::size_t v = 0; v < n; ++v) cells[v] = cell_of(&position[3 * v], cell);

  // Every local node, and every local edge inside one cell, to the cell's home.
  std::vector<CellRecord> records;
  std::vector<int> homes;
  for (std::size_t v = 0; v < n; ++v) {
    records.push_back(
        {cells[v], global[v], -1, {position[3 * v], position[3 * v + 1], position[3 * v + 2]}});
    homes.push_back(home_of(cells[v], size));
  }
  for (index_t r = 0; r < graph.rows; ++r)
    for (index_t s = graph.offsets[r]; s < graph.offsets[r + 1]; ++s) {
      const index_t c = graph.columns[s];
      if (c <= r || cells[c] != cells[r]) continue;
      records.push_back({cells[r], global[r], global[c], {0, 0, 0}});
      homes.push_back(home_of(cells[r], size));
    }
  Outbox<CellRecord> out(size);
  for (int h : homes) out.count(h);
  out.allocate();
  for (std::size_t k = 0; k < records.size(); ++k) out.place(homes[k], records[k]);
  records.clear();
  const Inbox<CellRecord> in = exchange(comm, out);

  // At the home: per cell, the pieces of its graph, each named by its
  // smallest node id. Records grouped by cell, nodes before edges.
  const std::vector<CellRecord>& got = in.records;
  std::vector<std::size_t> order(got.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) {
    if (got[x].cell != got[y].cell) return got[x].cell < got[y].cell;
    return (got[x].b < 0) > (got[y].b < 0);
  });
  std::unordered_map<std::int64_t, RootRecord> answer;  // node id -> its root
  for (std::size_t first = 0; first < order.size();) {
    std::size_t last = first;
    while (last < order.size() && got[order[last]].cell == got[order[first]].cell) ++last;
    // The cell's distinct nodes, by id, with a position each.
    std::vector<std::pair<std::int64_t, const double*>> nodes;
    for (std::size_t k = first; k < last && got[order[k]].b < 0; ++k)
      nodes.push_back({got[order[k]].a, got[order[k]].position});
    std::sort(nodes.begin(), nodes.end(),
              [](const auto& x, const auto& y) { return x.first < y.first; });
    nodes.erase(std::unique(nodes.begin(), nodes.end(),
                            [](const auto& x, const auto& y) { return x.first == y.first; }),
                nodes.end());
    auto index_of = [&](std::int64_t id) {
      return static_cast<std::size_t>(
          std::lower_bound(nodes.begin(), nodes.end(), id,
                           [](const auto& x, std::int64_t key) { return x.first < key; }) -
          nodes.begin());
    };
    std::vector<std::size_t> parent(nodes.size());
    std::iota(parent.begin(), parent.end(), std::size_t{0});
    for (std::size_t k = first; k < last; ++k) {
      const CellRecord& r = got[order[k]];
      if (r.b < 0) continue;
      const std::size_t a = find(parent, index_of(r.a)), b = find(parent, index_of(r.b));
      // The smaller index (smaller id) stays the representative.
      if (a < b) parent[b] = a;
      if (b < a) parent[a] = b;
    }
    for (std::size_t i = 0; i < nodes.size(); ++i) {
      const std::size_t root = find(parent, i);
      const double* p = nodes[root].second;
      answer[nodes[i].first] = {nodes[i].first, nodes[root].first, {p[0], p[1], p[2]}};
    }
    first = last;
  }

  // Each node's answer to every rank that sent it.
  Outbox<RootRecord> back(size);
  auto for_each_node_record = [&](auto&& f) {
    for (int r = 0; r < size; ++r)
      for (std::size_t k = in.from_offsets[r]; k < in.from_offsets[r + 1]; ++k)
        if (got[k].b < 0) f(r, got[k].a);
  };
  for_each_node_record([&](int r, std::int64_t) { back.count(r); });
  back.allocate();
  for_each_node_record([&](int r, std::int64_t node) { back.place(r, answer.at(node)); });
  const Inbox<RootRecord> roots = exchange(comm, back);

  std::unordered_map<std::int64_t, const RootRecord*> by_node;
  for (const RootRecord& r : roots.records) by_node[r.node] = &r;
  Aggregates result;
  result.root.resize(n);
  result.root_position.resize(3 * n);
  for (std::size_t v = 0; v < n; ++v) {
    const RootRecord& r = *by_node.at(global[v]);
    result.root[v] = r.root;
    std::copy(r.position, r.position + 3, &result.root_position[3 * v]);
  }
  return result;
}

}  // namespace descent
