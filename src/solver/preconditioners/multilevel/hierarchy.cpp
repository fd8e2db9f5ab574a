#include "solver/preconditioners/multilevel/hierarchy.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numeric>
#include <unordered_map>

#include "comm/exchange.hpp"
#include "comm/mpi_check.hpp"
#include "common/error.hpp"
#include "common/splitmix.hpp"
#include "solver/preconditioners/multilevel/aggregation.hpp"
#include "solver/preconditioners/multilevel/galerkin.hpp"
#include "solver/preconditioners/multilevel/host_operators.hpp"

namespace descent {

namespace {

constexpr int kModes = 6;  // rigid motions: translation xyz, rotation about xyz
// A mode whose part independent of the modes before it is below this share
// of its squared norm carries nothing new on the aggregate: dropped.
constexpr double kDropShare = 1e-8;
// Lanczos steps for the smoothing weight's lambda_max, at set-up.
constexpr int kSmoothingSteps = 15;
// A level that keeps more than this share of the finer one's unknowns ends
// the coarsening (the finer one is then the coarsest).
constexpr double kMinShrink = 0.85;
constexpr int kRowTag = 7202;

int home_of(global_index_t key, int size) {
  return static_cast<int>(splitmix64(static_cast<std::uint64_t>(key)) %
                          static_cast<std::uint64_t>(size));
}

// out (rows x 6) = n (rows x 6) T(d): the rigid motions a node's near-null
// block n expresses about its own position p, re-expressed about the centre
// c = p - d. A motion (t, w) about c is (t + w x (p - c), w) about p, and
// w x d = W(d) w with W(d) = [[0, dz, -dy], [-dz, 0, dx], [dy, -dx, 0]].
void recentre(const double* n, int rows, const double* d, double* out) {
  const double w[3][3] = {{0, d[2], -d[1]}, {-d[2], 0, d[0]}, {d[1], -d[0], 0}};
  for (int r = 0; r < rows; ++r) {
    const double* in = n + kModes * r;
    double* o = out + kModes * r;
    for (int j = 0; j < 3; ++j) o[j] = in[j];
    for (int j = 0; j < 3; ++j)
      o[3 + j] = in[3 + j] + in[0] * w[0][j] + in[1] * w[1][j] + in[2] * w[2][j];
  }
}

// R with R^T R = G (6x6, row-major, upper triangular), column by column;
// a column whose remaining part is below kDropShare of G_jj is dropped (its
// row of R stays 0). Returns the kept columns as bits.
std::uint8_t cholesky_qr(const double* g, double* r) {
  std::fill(r, r + kModes * kModes, 0.0);
  std::uint8_t kept = 0;
  for (int j = 0; j < kModes; ++j) {
    double s = g[kModes * j + j];
    for (int i = 0; i < j; ++i) s -= r[kModes * i + j] * r[kModes * i + j];
    if (!(g[kModes * j + j] > 0) || !(s > kDropShare * g[kModes * j + j])) continue;
    const double rjj = std::sqrt(s);
    r[kModes * j + j] = rjj;
    for (int k = j + 1; k < kModes; ++k) {
      double t = g[kModes * j + k];
      for (int i = 0; i < j; ++i) t -= r[kModes * i + j] * r[kModes * i + k];
      r[kModes * j + k] = t / rjj;
    }
    kept |= static_cast<std::uint8_t>(1u << j);
  }
  return kept;
}

// x (rows x 6) = b R^-1 on the kept columns, 0 on the dropped ones.
void solve_right(const double* b, int rows, const double* r, std::uint8_t kept, double* x) {
  for (int row = 0; row < rows; ++row)
    for (int j = 0; j < kModes; ++j) {
      double& out = x[kModes * row + j];
      out = 0;
      if (!(kept >> j & 1u)) continue;
      double s = b[kModes * row + j];
      for (int i = 0; i < j; ++i) s -= x[kModes * row + i] * r[kModes * i + j];
      out = s / r[kModes * j + j];
    }
}

// One aggregate as its home computes it and returns it.
struct AggregateRecord {
  global_index_t id;
  double centre[3];
  double r[kModes * kModes];  // Gram on the way in, R on the way back
  std::uint8_t kept;
  int holder;  // on the way back from the holders' round: a rank holding it
};

// Sparse rows keyed by global coarse id: per local node, sorted keys and
// `width` values per key.
struct KeyedRows {
  int width = 0;
  std::vector<std::vector<global_index_t>> keys;
  std::vector<std::vector<double>> values;
};

// Adds `width` values under `key` into row (keys sorted).
void add_to_row(std::vector<global_index_t>& keys, std::vector<double>& values, int width,
                global_index_t key, const double* add) {
  const auto it = std::lower_bound(keys.begin(), keys.end(), key);
  const std::size_t at = static_cast<std::size_t>(it - keys.begin());
  if (it == keys.end() || *it != key) {
    keys.insert(it, key);
    values.insert(values.begin() + at * width, add, add + width);
    return;
  }
  for (int k = 0; k < width; ++k) values[at * width + k] += add[k];
}

// Completes the rows of shared nodes: every sharer sends its partial rows,
// and each row's total is the sum of all sharers' rows in ascending rank
// order (bitwise equal on every sharer). Point to point, set-up only.
void complete_shared_rows(MPI_Comm comm, const HaloPattern& halo, KeyedRows& rows) {
  const std::size_t neighbours = halo.neighbours.size();
  if (neighbours == 0) return;
  const int width = rows.width;
  std::vector<std::vector<double>> send(neighbours);
  std::vector<MPI_Request> requests(neighbours);
  for (std::size_t n = 0; n < neighbours; ++n) {
    std::vector<double>& buf = send[n];
    for (index_t v : halo.shared_with[n]) {
      buf.push_back(static_cast<double>(rows.keys[v].size()));
      for (global_index_t key : rows.keys[v]) buf.push_back(static_cast<double>(key));
      buf.insert(buf.end(), rows.values[v].begin(), rows.values[v].end());
    }
    DESCENT_MPI_CHECK(MPI_Isend(buf.data(), static_cast<int>(buf.size()), MPI_DOUBLE,
                                halo.neighbours[n], kRowTag, comm, &requests[n]));
  }
  // Terms of each shared node as (rank, keys, values), summed in rank order.
  struct Term {
    int rank;
    std::vector<global_index_t> keys;
    std::vector<double> values;
  };
  const index_t first = halo.first_shared;
  std::vector<std::vector<Term>> terms(halo.num_entries - first);
  for (index_t v = first; v < halo.num_entries; ++v)
    terms[v - first].push_back({halo.rank, rows.keys[v], rows.values[v]});
  for (std::size_t n = 0; n < neighbours; ++n) {
    MPI_Status status;
    DESCENT_MPI_CHECK(MPI_Probe(halo.neighbours[n], kRowTag, comm, &status));
    int count = 0;
    DESCENT_MPI_CHECK(MPI_Get_count(&status, MPI_DOUBLE, &count));
    std::vector<double> buf(count);
    DESCENT_MPI_CHECK(MPI_Recv(buf.data(), count, MPI_DOUBLE, halo.neighbours[n], kRowTag, comm,
                               MPI_STATUS_IGNORE));
    std::size_t at = 0;
    for (index_t v : halo.shared_with[n]) {
      Term t{halo.neighbours[n], {}, {}};
      const std::size_t keys = static_cast<std::size_t>(buf[at++]);
      for (std::size_t k = 0; k < keys; ++k)
        t.keys.push_back(static_cast<global_index_t>(buf[at++]));
      t.values.assign(buf.begin() + at, buf.begin() + at + keys * width);
      at += keys * width;
      terms[v - first].push_back(std::move(t));
    }
  }
  DESCENT_MPI_CHECK(
      MPI_Waitall(static_cast<int>(neighbours), requests.data(), MPI_STATUSES_IGNORE));
  for (index_t v = first; v < halo.num_entries; ++v) {
    auto& list = terms[v - first];
    std::sort(list.begin(), list.end(),
              [](const Term& a, const Term& b) { return a.rank < b.rank; });
    rows.keys[v].clear();
    rows.values[v].clear();
    for (const Term& t : list)
      for (std::size_t k = 0; k < t.keys.size(); ++k)
        add_to_row(rows.keys[v], rows.values[v], width, t.keys[k], &t.values[k * width]);
  }
}

// y = A x completed through the level's halo.
struct LevelProduct {
  BlockView a;
  Halo<double>* halo;
  void operator()(const double* x, double* y) const {
    partial_product(*a.pattern, a.values, a.block, x, y);
    halo->sum(y, a.block);
  }
};

struct Coarsening {
  LevelLayout layout;
  BlockMatrix<double> prolongation;
  std::vector<double> near_null;  // 6 x 6 per coarse node
  double omega = 0;
};

Coarsening coarsen(MPI_Comm comm, const LevelLayout& fine, const BlockView& rest,
                   const std::vector<double>& near_null, double cell) {
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  const int k = fine.block;
  const index_t n = fine.num_nodes();
  const Aggregates agg = aggregate_by_cells(comm, fine.global, fine.position, *rest.pattern, cell);

  // The rigid motions about each node's aggregate root, restricted to it.
  std::vector<double> motions(static_cast<std::size_t>(n) * k * kModes);
  for (index_t v = 0; v < n; ++v) {
    double d[3];
    for (int i = 0; i < 3; ++i) d[i] = fine.position[3 * v + i] - agg.root_position[3 * v + i];
    recentre(&near_null[static_cast<std::size_t>(v) * k * kModes], k, d,
             &motions[static_cast<std::size_t>(v) * k * kModes]);
  }

  // Gram matrices: owned nodes' parts to each aggregate's home, which
  // orthonormalises and answers every rank holding a node of it.
  std::map<global_index_t, AggregateRecord> mine;  // by aggregate, ascending
  for (index_t v = 0; v < n; ++v) {
    auto [it, fresh] = mine.try_emplace(agg.root[v]);
    AggregateRecord& a = it->second;
    if (fresh) {
      a = AggregateRecord{agg.root[v], {}, {}, 0, rank};
      std::copy(&agg.root_position[3 * v], &agg.root_position[3 * v] + 3, a.centre);
    }
    if (v >= fine.num_owned) continue;
    const double* b = &motions[static_cast<std::size_t>(v) * k * kModes];
    for (int i = 0; i < kModes; ++i)
      for (int j = 0; j < kModes; ++j)
        for (int row = 0; row < k; ++row)
          a.r[kModes * i + j] += b[kModes * row + i] * b[kModes * row + j];
  }
  Outbox<AggregateRecord> out(size);
  for (const auto& [id, a] : mine) out.count(home_of(id, size));
  out.allocate();
  for (const auto& [id, a] : mine) out.place(home_of(id, size), a);
  const Inbox<AggregateRecord> at_home = exchange(comm, out);
  // The home's table: records arrive in rank order, so each Gram is summed
  // in rank order.
  std::map<global_index_t, AggregateRecord> table;
  for (const AggregateRecord& r : at_home.records) {
    auto [it, fresh] = table.try_emplace(r.id, r);
    if (!fresh)
      for (int i = 0; i < kModes * kModes; ++i) it->second.r[i] += r.r[i];
  }
  for (auto& [id, a] : table) {
    double g[kModes * kModes];
    std::copy(a.r, a.r + kModes * kModes, g);
    a.kept = cholesky_qr(g, a.r);
  }
  Outbox<AggregateRecord> answer(size);
  for (int r = 0; r < size; ++r)
    for (std::size_t i = at_home.from_offsets[r]; i < at_home.from_offsets[r + 1]; ++i)
      answer.count(r);
  answer.allocate();
  for (int r = 0; r < size; ++r)
    for (std::size_t i = at_home.from_offsets[r]; i < at_home.from_offsets[r + 1]; ++i)
      answer.place(r, table.at(at_home.records[i].id));
  for (const AggregateRecord& a : exchange(comm, answer).records) mine[a.id] = a;

  // Tentative prolongation P_t: row v = (motions of v) R^-1, one block in
  // the column of v's aggregate.
  std::vector<double> tentative(motions.size());
  for (index_t v = 0; v < n; ++v) {
    const AggregateRecord& a = mine.at(agg.root[v]);
    solve_right(&motions[static_cast<std::size_t>(v) * k * kModes], k, a.r, a.kept,
                &tentative[static_cast<std::size_t>(v) * k * kModes]);
  }

  // Smoothing: P = P_t - omega D^-1 (A P_t), A the level's operator at rest.
  Halo<double> halo(comm, fine.halo);
  std::vector<double> diagonal = partial_diagonal(*rest.pattern, rest.values, k);
  halo.sum(diagonal.data(), k);
  const std::vector<double> inv = inverse_diagonal(diagonal, fine.active);
  LanczosTarget target;
  target.size = k * n;
  target.owned = k * fine.num_owned;
  target.inv_diagonal = inv.data();
  target.global = fine.global.data();
  target.block = k;
  target.product = LevelProduct{rest, &halo};
  long collectives = 0;
  const double lambda = largest_eigenvalues(comm, {target}, kSmoothingSteps, collectives)[0];
  Coarsening result;
  result.omega = lambda > 0 ? 4.0 / (3.0 * lambda) : 0.0;

  KeyedRows rows;
  rows.width = k * kModes;
  rows.keys.resize(n);
  rows.values.resize(n);
  std::vector<double> product(static_cast<std::size_t>(k) * kModes);
  for (index_t v = 0; v < n; ++v)
    for (index_t s = rest.pattern->offsets[v]; s < rest.pattern->offsets[v + 1]; ++s) {
      const index_t u = rest.pattern->columns[s];
      const double* a = rest.slot(s);
      const double* pt = &tentative[static_cast<std::size_t>(u) * k * kModes];
      std::fill(product.begin(), product.end(), 0.0);
      for (int r = 0; r < k; ++r)
        for (int c = 0; c < k; ++c)
          for (int j = 0; j < kModes; ++j)
            product[kModes * r + j] += a[k * r + c] * pt[kModes * c + j];
      add_to_row(rows.keys[v], rows.values[v], rows.width, agg.root[u], product.data());
    }
  complete_shared_rows(comm, fine.halo, rows);
  for (index_t v = 0; v < n; ++v) {
    std::vector<double>& values = rows.values[v];
    for (std::size_t e = 0; e < rows.keys[v].size(); ++e)
      for (int r = 0; r < k; ++r)
        for (int j = 0; j < kModes; ++j)
          values[e * rows.width + kModes * r + j] *= -result.omega * inv[k * v + r];
    add_to_row(rows.keys[v], values, rows.width, agg.root[v],
               &tentative[static_cast<std::size_t>(v) * k * kModes]);
  }

  // The coarse nodes: every aggregate P's rows reach here. Their homes say
  // who else holds each, with its R and centre.
  std::vector<global_index_t> coarse;
  for (const auto& keys : rows.keys) coarse.insert(coarse.end(), keys.begin(), keys.end());
  std::sort(coarse.begin(), coarse.end());
  coarse.erase(std::unique(coarse.begin(), coarse.end()), coarse.end());
  Outbox<AggregateRecord> ask(size);
  for (global_index_t id : coarse) ask.count(home_of(id, size));
  ask.allocate();
  for (global_index_t id : coarse)
    ask.place(home_of(id, size), AggregateRecord{id, {}, {}, 0, rank});
  const Inbox<AggregateRecord> asked = exchange(comm, ask);
  std::map<global_index_t, std::vector<int>> holders;  // at the home: ranks asking, ascending
  for (int r = 0; r < size; ++r)
    for (std::size_t i = asked.from_offsets[r]; i < asked.from_offsets[r + 1]; ++i)
      holders[asked.records[i].id].push_back(r);
  Outbox<AggregateRecord> tell(size);
  // Each holder hears of every holder (itself included).
  for (const auto& [id, ranks] : holders)
    for (int to : ranks)
      for (std::size_t i = 0; i < ranks.size(); ++i) tell.count(to);
  tell.allocate();
  for (const auto& [id, ranks] : holders)
    for (int to : ranks)
      for (int holder : ranks) {
        AggregateRecord a = table.at(id);
        a.holder = holder;
        tell.place(to, a);
      }
  const Inbox<AggregateRecord> told = exchange(comm, tell);

  // The coarse layout: [interior | shared owned | shared not owned], each
  // by id; a node's owner is the lowest rank holding it.
  std::map<global_index_t, std::vector<int>> sharers;  // other ranks holding each
  std::map<global_index_t, const AggregateRecord*> about;
  for (const AggregateRecord& a : told.records) {
    about[a.id] = &a;
    if (a.holder != rank) sharers[a.id].push_back(a.holder);
  }
  auto owner_of = [&](global_index_t id) {
    const auto it = sharers.find(id);
    if (it == sharers.end()) return rank;
    return std::min(rank, *std::min_element(it->second.begin(), it->second.end()));
  };
  std::vector<global_index_t> interior, owned_shared, other_shared;
  for (global_index_t id : coarse) {
    if (!sharers.count(id))
      interior.push_back(id);
    else if (owner_of(id) == rank)
      owned_shared.push_back(id);
    else
      other_shared.push_back(id);
  }
  LevelLayout& layout = result.layout;
  layout.block = kModes;
  layout.global = interior;
  layout.global.insert(layout.global.end(), owned_shared.begin(), owned_shared.end());
  layout.global.insert(layout.global.end(), other_shared.begin(), other_shared.end());
  layout.num_interior = static_cast<index_t>(interior.size());
  layout.num_owned = static_cast<index_t>(interior.size() + owned_shared.size());
  const index_t nc = layout.num_nodes();
  std::unordered_map<global_index_t, index_t> local;
  for (index_t c = 0; c < nc; ++c) local[layout.global[c]] = c;
  layout.position.resize(3 * static_cast<std::size_t>(nc));
  layout.active.resize(static_cast<std::size_t>(kModes) * nc);
  result.near_null.resize(static_cast<std::size_t>(kModes) * kModes * nc);
  for (index_t c = 0; c < nc; ++c) {
    const AggregateRecord& a = *about.at(layout.global[c]);
    std::copy(a.centre, a.centre + 3, &layout.position[3 * c]);
    for (int j = 0; j < kModes; ++j) layout.active[kModes * c + j] = a.kept >> j & 1u;
    std::copy(a.r, a.r + kModes * kModes,
              &result.near_null[static_cast<std::size_t>(kModes) * kModes * c]);
  }
  layout.halo.rank = rank;
  layout.halo.first_shared = layout.num_interior;
  layout.halo.num_entries = nc;
  std::map<int, std::vector<index_t>> with;  // neighbour -> shared nodes, ascending id
  for (index_t c = layout.num_interior; c < nc; ++c)
    for (int r : sharers.at(layout.global[c])) with[r].push_back(c);
  for (auto& [r, list] : with) {
    std::sort(list.begin(), list.end(),
              [&](index_t x, index_t y) { return layout.global[x] < layout.global[y]; });
    layout.halo.neighbours.push_back(r);
    layout.halo.shared_with.push_back(std::move(list));
  }

  // P with local columns.
  BlockMatrix<double>& p = result.prolongation;
  p.row_block = k;
  p.col_block = kModes;
  p.pattern.rows = n;
  p.pattern.cols = nc;
  p.pattern.offsets.assign(static_cast<std::size_t>(n) + 1, 0);
  for (index_t v = 0; v < n; ++v) {
    // In ascending global id of the coarse node, not local index: the
    // prolongation sums a row in this order, and every sharer of a node
    // must add the same terms in the same order.
    for (std::size_t e = 0; e < rows.keys[v].size(); ++e)
      p.pattern.columns.push_back(local.at(rows.keys[v][e]));
    p.values.insert(p.values.end(), rows.values[v].begin(), rows.values[v].end());
    p.pattern.offsets[v + 1] = static_cast<index_t>(p.pattern.columns.size());
    // The row now lives in P: release it (P and the rows would double the peak).
    std::vector<global_index_t>().swap(rows.keys[v]);
    std::vector<double>().swap(rows.values[v]);
  }
  return result;
}

long long global_sum(MPI_Comm comm, long long value) {
  DESCENT_MPI_CHECK(MPI_Allreduce(MPI_IN_PLACE, &value, 1, MPI_LONG_LONG, MPI_SUM, comm));
  return value;
}

}  // namespace

Hierarchy build_hierarchy(MPI_Comm comm, const LocalMesh& mesh, const BlockView& fine_rest,
                          const std::vector<std::uint8_t>& fixed_axes,
                          const HierarchyOptions& options) {
  DESCENT_VERIFY(options.cell > 0, "multilevel aggregation cell ", options.cell);
  Hierarchy h;
  LevelLayout finest;
  finest.block = 3;
  finest.global = mesh.global_vertex;
  finest.num_interior = mesh.num_interior;
  finest.num_owned = mesh.num_owned;
  finest.position = mesh.rest_positions;
  finest.active.resize(3 * static_cast<std::size_t>(mesh.num_vertices()));
  for (std::size_t k = 0; k < finest.active.size(); ++k)
    finest.active[k] = (fixed_axes[k / 3] >> (k % 3) & 1u) ? 0 : 1;
  finest.halo = halo_pattern(mesh);
  // A vertex's near-null block about itself: translations move it, the
  // rotations about it do not; held axes carry nothing.
  std::vector<double> near_null(3 * kModes * static_cast<std::size_t>(mesh.num_vertices()), 0.0);
  for (std::size_t k = 0; k < finest.active.size(); ++k)
    near_null[kModes * k + k % 3] = finest.active[k] ? 1.0 : 0.0;

  h.operator_pattern.push_back(*fine_rest.pattern);
  h.global_unknowns.push_back(global_sum(comm, 3LL * mesh.num_owned));
  h.levels.push_back(std::move(finest));
  // The current level's operator at rest: the finest read in place, the
  // coarser ones made here.
  BlockView rest = fine_rest;
  BlockMatrix<double> coarser;
  double cell = options.cell;
  while (h.global_unknowns.back() > options.coarse_size &&
         static_cast<int>(h.levels.size()) < options.max_levels) {
    Coarsening next = coarsen(comm, h.levels.back(), rest, near_null, cell);
    const long long unknowns =
        global_sum(comm, static_cast<long long>(kModes) * next.layout.num_owned);
    if (unknowns > kMinShrink * static_cast<double>(h.global_unknowns.back())) break;
    BlockMatrix<double> coarse_rest;
    coarse_rest.row_block = coarse_rest.col_block = kModes;
    coarse_rest.pattern = galerkin_pattern(*rest.pattern, next.prolongation.pattern);
    galerkin_product(*rest.pattern, rest.values, next.prolongation, coarse_rest.pattern,
                     coarse_rest.values);
    h.operator_pattern.push_back(coarse_rest.pattern);
    h.global_unknowns.push_back(unknowns);
    h.smoothing_weight.push_back(next.omega);
    h.prolongation.push_back(std::move(next.prolongation));
    h.levels.push_back(std::move(next.layout));
    near_null = std::move(next.near_null);
    coarser = std::move(coarse_rest);
    rest = BlockView{&coarser.pattern, coarser.values.data(), kModes};
    cell *= 2;
  }
  return h;
}

}  // namespace descent
