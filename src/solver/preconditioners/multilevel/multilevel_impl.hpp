#pragma once
// MultilevelPreconditioner over an execution (HostExec or CudaExec):
// instantiated in multilevel_host.cpp and in the CUDA engine, nowhere else.
// What it computes and where: multilevel_preconditioner.hpp.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

#include "comm/halo.hpp"
#include "common/error.hpp"
#include "kernels/contact_loops.hpp"
#include "kernels/exec_array.hpp"
#include "kernels/multilevel_loops.hpp"
#include "solver/local_problem.hpp"
#include "solver/preconditioners/multilevel/coarse_solver.hpp"
#include "solver/preconditioners/multilevel/fine_structure.hpp"
#include "solver/preconditioners/multilevel/galerkin.hpp"
#include "solver/preconditioners/multilevel/hierarchy.hpp"
#include "solver/preconditioners/multilevel/host_operators.hpp"
#include "solver/preconditioners/preconditioner.hpp"

namespace descent {

namespace multilevel_detail {
// The smoother's interval is [upper / kSmootherRange, upper], upper =
// kUpperMargin x the largest Ritz value of kBoundSteps Lanczos steps: the
// Ritz value lies below lambda_max, and a bound below it would make the
// smoother (and P^-1) indefinite on the modes above.
constexpr double kUpperMargin = 1.1;
constexpr double kSmootherRange = 30;
constexpr int kBoundSteps = 10;
}  // namespace multilevel_detail

template <class Exec, class Real>
class MultilevelPreconditioner final : public Preconditioner<Real> {
 public:
  MultilevelPreconditioner(Exec& exec, LocalProblem<Real>& problem, const SolverSpec& spec)
      : exec_(exec),
        problem_(problem),
        model_(problem.model()),
        conversion_(problem.conversion()),
        converting_(problem.energy_changes_within_step()),
        terms_(problem.vertex_terms()),
        degree_(spec.multilevel_smoother_degree) {
    const auto start = Clock::now();
    const LocalMesh& mesh = problem.mesh();
    comm_ = problem.halo().comm();
    serial_ = exec_.serial();
    fine_ = make_fine_structure(mesh, !serial_);
    tets_ = constant(mesh.tets.data(), mesh.tets.size());
    rest_ = constant(problem.rest().data(), problem.rest().size());
    mass_ = constant(problem.mass().data(), problem.mass().size());
    fixed_ = constant(problem.fixed_axes().data(), problem.fixed_axes().size());
    tet_slots_ = upload(fine_.tet_slots);
    tet_order_ = upload(fine_.colour_order);
    diagonal_slots_ = upload(fine_.diagonal_slots);
    if (converting_) interpolant_ = make<Real>(mesh.num_tets());

    // The hierarchy from the operator at rest (interpolants 0: no conversion).
    levels_.resize(1);
    Level& finest = levels_[0];
    finest.block = 3;
    finest.nodes = mesh.num_vertices();
    finest.offsets = upload(fine_.pattern.offsets);
    finest.columns = upload(fine_.pattern.columns);
    finest.values = make<Real>(9 * fine_.pattern.num_blocks());
    std::vector<Real> rest_positions(mesh.rest_positions.begin(), mesh.rest_positions.end());
    ExecArray<Exec, Real> x0 = upload(rest_positions);
    assemble_finest(x0.data(), false);
    // Read in place where the host holds it in double; else a double copy
    // for the set-up (at 1M tets on 2 ranks a copy was 150 MB of each rank's
    // peak).
    const Real* host_fine = finest_on_host();
    std::vector<double> fine_copy;
    const double* fine_values = nullptr;
    if constexpr (Exec::kHostMemory && std::is_same_v<Real, double>) {
      fine_values = host_fine;
    } else {
      fine_copy.assign(host_fine, host_fine + 9 * fine_.pattern.num_blocks());
      fine_values = fine_copy.data();
    }
    HierarchyOptions options;
    options.cell = spec.multilevel_cell * mean_edge_length(mesh);
    options.coarse_size = spec.multilevel_coarse_size;
    hierarchy_ = build_hierarchy(comm_, mesh, BlockView{&fine_.pattern, fine_values, 3},
                                 problem.fixed_axes(), options);
    fine_copy = {};

    const std::size_t num_levels = hierarchy_.levels.size();
    levels_.resize(num_levels);
    host_values_.resize(num_levels);
    for (std::size_t l = 1; l < num_levels; ++l)
      host_values_[l].assign(36 * hierarchy_.operator_pattern[l].num_blocks(), 0.0);
    for (std::size_t l = 0; l < num_levels; ++l) {
      const LevelLayout& layout = hierarchy_.levels[l];
      Level& level = levels_[l];
      level.block = layout.block;
      level.nodes = layout.num_nodes();
      level.owned = layout.num_owned;
      level.first_shared = layout.num_interior;
      const std::size_t n = static_cast<std::size_t>(level.block) * level.nodes;
      for (ExecArray<Exec, Real>* a : {&level.x, &level.b, &level.r, &level.d, &level.y})
        *a = make<Real>(n);
      level.inv = make<Real>(n);
      level.halo = std::make_unique<Halo<Real>>(comm_, layout.halo);
      host_halos_.push_back(std::make_unique<Halo<double>>(comm_, layout.halo));
      if (!Exec::kHostMemory && !layout.halo.neighbours.empty()) level.stage = make_pinned<Real>(n);
      if (l > 0 && l + 1 < num_levels) {
        const BlockPattern& pattern = hierarchy_.operator_pattern[l];
        level.offsets = upload(pattern.offsets);
        level.columns = upload(pattern.columns);
        level.values = mirror(host_values_[l]);
      }
    }
    for (std::size_t l = 0; l + 1 < num_levels; ++l) {
      const BlockMatrix<double>& p = hierarchy_.prolongation[l];
      Transfer t;
      t.offsets = upload(p.pattern.offsets);
      t.columns = upload(p.pattern.columns);
      t.values = mirror(hierarchy_.prolongation[l].values);
      if (!views(t.values, p.values)) upload_into(t.values, p.values);
      if (!serial_) {  // the parallel restriction gathers through the transpose
        const TransposedPattern pt = transpose(p.pattern);
        t.t_offsets = upload(pt.offsets);
        t.t_rows = upload(pt.rows);
        t.t_slots = upload(pt.slots);
      }
      transfers_.push_back(std::move(t));
    }
    coarse_ = std::make_unique<CoarseSolver>(comm_, hierarchy_.levels.back(),
                                             std::numeric_limits<Real>::epsilon());
    coarse_b_.assign(static_cast<std::size_t>(levels_.back().block) * levels_.back().nodes, 0.0);
    coarse_x_ = coarse_b_;
    if (!Exec::kHostMemory) coarse_stage_ = make_pinned<Real>(coarse_b_.size());
    setup_seconds_ = std::chrono::duration<double>(Clock::now() - start).count();
  }

  void read_interpolants_from(const Real* interpolants) override {
    interpolant_source_ = interpolants;
  }

  // The finest operator gains the projected contact Hessian blocks at each
  // refresh (kernels/contact_loops.hpp): `contact` and the step-start
  // positions `qt` in this execution's memory, owned by the caller.
  void use_contact(ContactView<Real> contact, const Real* qt) {
    contact_ = contact;
    contact_qt_ = qt;
  }

  void refresh(const Real* q) override { refresh(q, nullptr); }
  // With `extra_diagonal` (3 per local vertex, this execution's memory, the
  // same on every sharer): added to the finest operator's diagonal too.
  void refresh(const Real* q, const Real* extra_diagonal) {
    const auto start = Clock::now();
    if (converting_ && !interpolant_source_) {
      const std::vector<Real>& l = problem_.interpolants();
      exec_.copy(kStream, interpolant_.data(), l.data(), interpolant_.bytes());
    }
    assemble_finest(q, converting_);
    if (extra_diagonal) {
      loops::add_owned_diagonal(exec_, kStream, problem_.mesh().num_owned, extra_diagonal,
                                fixed_.data(), diagonal_slots_.data(), levels_[0].values.data());
      exec_.sync(kStream);
    }
    rebuild(finest_on_host());
    ++stats_.refreshes;
    stats_.refresh_seconds += std::chrono::duration<double>(Clock::now() - start).count();
  }

  void apply(const Real* r, Real* z) override {
    const auto start = Clock::now();
    if (levels_.size() == 1) {
      solve_coarsest(r, z, true);
    } else {
      vcycle(0, r, z);
    }
    exec_.sync(kStream);
    ++stats_.applications;
    stats_.apply_seconds += std::chrono::duration<double>(Clock::now() - start).count();
  }

  PreconditionerStats stats() const override {
    PreconditionerStats s = stats_;
    s.gathers = lanczos_gathers_ + coarse_->solves() + coarse_->gathers();
    for (const Level& level : levels_) s.messages += level.halo->counters().messages_sent;
    for (const auto& halo : host_halos_) s.messages += halo->counters().messages_sent;
    s.memory_bytes = memory_bytes_ + host_bytes();
    s.level_dofs = hierarchy_.global_unknowns;
    return s;
  }

  std::string describe() const override {
    std::string s = "multilevel: " + std::to_string(levels_.size()) + " levels of";
    for (std::size_t l = 0; l < hierarchy_.global_unknowns.size(); ++l)
      s += (l ? " / " : " ") + std::to_string(hierarchy_.global_unknowns[l]);
    return s + " unknowns (the coarsest solved exactly), Chebyshev-Jacobi smoothing of degree " +
           std::to_string(degree_) + ", set up in " + format_seconds(setup_seconds_);
  }

  const Hierarchy& hierarchy() const { return hierarchy_; }
  // The smoother's interval of level l at the last refresh.
  std::pair<double, double> smoother_interval(std::size_t l) const {
    return {levels_[l].lower, levels_[l].upper};
  }

 private:
  using Clock = std::chrono::steady_clock;
  static constexpr int kStream = 0;
  template <class T>
  using Array = ExecArray<Exec, T>;

  struct Level {
    int block = 3;
    index_t nodes = 0, owned = 0, first_shared = 0;
    Array<index_t> offsets, columns;  // the operator's pattern (finest and middle levels)
    Array<Real> values, inv;
    Array<Real> x, b, r, d, y;
    Array<Real> stage;  // a device's halo staging (pinned host)
    std::unique_ptr<Halo<Real>> halo;
    double lower = 0, upper = 0;  // the smoother's interval
  };
  struct Transfer {  // P from level l + 1 to level l, and its transpose
    Array<index_t> offsets, columns;
    Array<Real> values;
    Array<index_t> t_offsets, t_rows, t_slots;
  };

  static std::string format_seconds(double s) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.2f s", s);
    return buf;
  }

  template <class T>
  Array<T> make(std::size_t n) {
    memory_bytes_ += n * sizeof(T);
    return Array<T>(&exec_, n, false);
  }
  template <class T>
  Array<T> make_pinned(std::size_t n) {
    return Array<T>(&exec_, n, true);
  }
  template <class T>
  Array<T> upload(const std::vector<T>& host) {
    Array<T> a = make<T>(host.size());
    exec_.copy(kStream, a.data(), host.data(), a.bytes());
    exec_.sync(kStream);
    return a;
  }
  // Data the problem holds: used in place on the host, copied to a device.
  template <class T>
  Array<T> constant(const T* host, std::size_t n) {
    if constexpr (Exec::kHostMemory) {
      return Array<T>::view(host, n);
    } else {
      Array<T> a = make<T>(n);
      exec_.copy(kStream, a.data(), host, a.bytes());
      exec_.sync(kStream);
      return a;
    }
  }

  // The mean edge length of the whole mesh (one allreduce), rounded to four
  // significant digits so that the aggregation cells do not depend on the
  // round-off of the sum's order, which changes with the rank count.
  double mean_edge_length(const LocalMesh& mesh) const {
    double sums[2] = {0, 0};
    const auto& x = mesh.rest_positions;
    for (index_t t = 0; t < mesh.num_tets(); ++t)
      for (int a = 0; a < 4; ++a)
        for (int b = a + 1; b < 4; ++b) {
          const double* p = &x[3 * static_cast<std::size_t>(mesh.tets[4 * t + a])];
          const double* q = &x[3 * static_cast<std::size_t>(mesh.tets[4 * t + b])];
          sums[0] += std::sqrt((p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) +
                               (p[2] - q[2]) * (p[2] - q[2]));
          sums[1] += 1;
        }
    rank_ordered_sum(comm_, sums, 2);
    DESCENT_VERIFY(sums[1] > 0 && sums[0] > 0, "multilevel: a mesh without edges");
    const double mean = sums[0] / sums[1];
    const double unit = std::pow(10.0, std::floor(std::log10(mean)) - 3);
    return std::round(mean / unit) * unit;
  }

  // The finest operator at x: PSD-projected element Hessians colour by
  // colour, then the vertex curvature of owned vertices.
  void assemble_finest(const Real* x, bool converting) {
    Level& f = levels_[0];
    exec_.zero(kStream, f.values.data(), f.values.bytes());
    const auto& colours = fine_.colour_offsets;
    std::visit(
        [&](const auto& model) {
          for (std::size_t c = 0; c + 1 < colours.size(); ++c) {
            if (converting)
              loops::add_element_hessians<true>(exec_, kStream, model, conversion_, interpolants(),
                                                x, tets_.data(), rest_.data(), tet_order_.data(),
                                                colours[c], colours[c + 1], tet_slots_.data(),
                                                fixed_.data(), f.values.data());
            else
              loops::add_element_hessians<false>(exec_, kStream, model, conversion_,
                                                 interpolant_.data(), x, tets_.data(), rest_.data(),
                                                 tet_order_.data(), colours[c], colours[c + 1],
                                                 tet_slots_.data(), fixed_.data(), f.values.data());
          }
        },
        model_);
    loops::add_vertex_curvature(exec_, kStream, problem_.mesh().num_owned, terms_, mass_.data(),
                                fixed_.data(), diagonal_slots_.data(), f.values.data());
    if (contact_.num_owned > 0)
      loops::add_contact_blocks(exec_, kStream, contact_, fixed_.data(), x, contact_qt_,
                                diagonal_slots_.data(), f.values.data());
    exec_.sync(kStream);
  }

  // Each tet's interpolant: where the method keeps them, else the copy of
  // the problem's refresh made.
  const Real* interpolants() const {
    return interpolant_source_ ? interpolant_source_ : interpolant_.data();
  }

  // The finest operator's values where the host can read them.
  const Real* finest_on_host() {
    const Array<Real>& values = levels_[0].values;
    if constexpr (Exec::kHostMemory) {
      return values.data();
    } else {
      host_fine_.resize(values.size());
      exec_.copy(kStream, host_fine_.data(), values.data(), values.bytes());
      exec_.sync(kStream);
      return host_fine_.data();
    }
  }

  // Diagonals, Galerkin products, smoother bounds and the coarsest factor
  // from the finest operator (host memory).
  void rebuild(const Real* fine) {
    using namespace multilevel_detail;
    const std::size_t last = levels_.size() - 1;
    std::vector<std::vector<double>> inverse(last);
    for (std::size_t l = 0; l < last; ++l) {
      const LevelLayout& layout = hierarchy_.levels[l];
      const BlockPattern& pattern = hierarchy_.operator_pattern[l];
      std::vector<double> diagonal =
          l == 0 ? partial_diagonal(pattern, fine, 3)
                 : partial_diagonal(pattern, host_values_[l].data(), layout.block);
      host_halos_[l]->sum(diagonal.data(), layout.block);
      inverse[l] = inverse_diagonal(diagonal, layout.active);
      if (l == 0)
        galerkin_product(pattern, fine, hierarchy_.prolongation[l],
                         hierarchy_.operator_pattern[l + 1], host_values_[l + 1]);
      else
        galerkin_product(pattern, host_values_[l].data(), hierarchy_.prolongation[l],
                         hierarchy_.operator_pattern[l + 1], host_values_[l + 1]);
    }
    std::vector<LanczosTarget> targets(last);
    for (std::size_t l = 0; l < last; ++l) {
      const LevelLayout& layout = hierarchy_.levels[l];
      LanczosTarget& t = targets[l];
      t.size = layout.block * layout.num_nodes();
      t.owned = layout.block * layout.num_owned;
      t.inv_diagonal = inverse[l].data();
      t.global = layout.global.data();
      t.block = layout.block;
      const BlockPattern* pattern = &hierarchy_.operator_pattern[l];
      Halo<double>* halo = host_halos_[l].get();
      const int block = layout.block;
      if (l == 0)
        t.product = [pattern, fine, halo](const double* x, double* y) {
          partial_product(*pattern, fine, 3, x, y);
          halo->sum(y, 3);
        };
      else
        t.product = [pattern, values = host_values_[l].data(), halo, block](const double* x,
                                                                            double* y) {
          partial_product(*pattern, values, block, x, y);
          halo->sum(y, block);
        };
    }
    const std::vector<double> largest =
        last > 0 ? largest_eigenvalues(comm_, targets, kBoundSteps, lanczos_gathers_)
                 : std::vector<double>{};
    for (std::size_t l = 0; l < last; ++l) {
      Level& level = levels_[l];
      level.upper = kUpperMargin * largest[l];
      level.lower = level.upper / kSmootherRange;
      upload_into(level.inv, inverse[l]);
      if (l > 0 && !views(level.values, host_values_[l]))
        upload_into(level.values, host_values_[l]);
    }
    if (last == 0) {
      const std::size_t n = 9 * fine_.pattern.num_blocks();
      coarse_->factor(fine_.pattern, std::vector<double>(fine, fine + n));
    } else {
      coarse_->factor(hierarchy_.operator_pattern[last], host_values_[last]);
    }
  }

  // The execution's copy of host values kept in double: the host data
  // itself where the execution is the host's and Real is double (no second
  // copy), else an array the caller fills with upload_into.
  Array<Real> mirror(std::vector<double>& host) {
    if constexpr (Exec::kHostMemory && std::is_same_v<Real, double>)
      return Array<Real>::view(host.data(), host.size());
    else
      return make<Real>(host.size());
  }

  static bool views(const Array<Real>& a, const std::vector<double>& host) {
    return static_cast<const void*>(a.data()) == static_cast<const void*>(host.data());
  }

  void upload_into(Array<Real>& target, const std::vector<double>& host) {
    staging_.assign(host.begin(), host.end());
    exec_.copy(kStream, target.data(), staging_.data(), target.bytes());
    exec_.sync(kStream);
  }

  // Completes partial sums of level l's shared nodes through its halo.
  void complete(std::size_t l, Real* values) {
    Level& level = levels_[l];
    if (level.halo->num_neighbours() == 0) return;
    if constexpr (Exec::kHostMemory) {
      level.halo->sum(values, level.block);
    } else {
      const std::size_t offset = static_cast<std::size_t>(level.block) * level.first_shared;
      const std::size_t bytes =
          static_cast<std::size_t>(level.block) * (level.nodes - level.first_shared) * sizeof(Real);
      exec_.copy(kStream, level.stage.data() + offset, values + offset, bytes);
      exec_.sync(kStream);
      level.halo->sum(level.stage.data(), level.block);
      exec_.copy(kStream, values + offset, level.stage.data() + offset, bytes);
    }
  }

  template <int B>
  void product_rows(const Level& level, const Real* values, index_t begin, index_t end,
                    const Real* x, Real* y) {
    loops::block_product<B>(exec_, kStream, begin, end, level.offsets.data(), level.columns.data(),
                            values, x, y);
  }

  // y = A_l x, complete on every local node. On the host the shared rows go
  // first and their exchange overlaps the interior rows.
  void product(std::size_t l, const Real* x, Real* y) {
    Level& level = levels_[l];
    auto rows = [&](index_t begin, index_t end) {
      if (level.block == 3)
        product_rows<3>(level, level.values.data(), begin, end, x, y);
      else
        product_rows<6>(level, level.values.data(), begin, end, x, y);
    };
    if (Exec::kHostMemory && level.halo->num_neighbours() > 0) {
      rows(level.first_shared, level.nodes);
      level.halo->begin(y, level.block);
      rows(0, level.first_shared);
      level.halo->finish(y, level.block);
      return;
    }
    rows(0, level.nodes);
    complete(l, y);
  }

  // x = A_L^-1 b on the coarsest level. `complete_rhs`: b is complete on
  // every local node (the finest level as the coarsest), so only owned
  // nodes' values enter the partial sums; otherwise b is partial already.
  void solve_coarsest(const Real* b, Real* x, bool complete_rhs) {
    const Level& level = levels_.back();
    const std::size_t n = coarse_b_.size();
    const Real* host_b = b;
    if constexpr (!Exec::kHostMemory) {
      exec_.copy(kStream, coarse_stage_.data(), b, n * sizeof(Real));
      exec_.sync(kStream);
      host_b = coarse_stage_.data();
    } else {
      exec_.sync(kStream);
    }
    const std::size_t owned = static_cast<std::size_t>(level.block) * level.owned;
    for (std::size_t k = 0; k < n; ++k)
      coarse_b_[k] = complete_rhs && k >= owned ? 0.0 : static_cast<double>(host_b[k]);
    coarse_->solve(coarse_b_.data(), coarse_x_.data());
    if constexpr (Exec::kHostMemory) {
      for (std::size_t k = 0; k < n; ++k) x[k] = static_cast<Real>(coarse_x_[k]);
    } else {
      for (std::size_t k = 0; k < n; ++k) coarse_stage_.data()[k] = static_cast<Real>(coarse_x_[k]);
      exec_.copy(kStream, x, coarse_stage_.data(), n * sizeof(Real));
    }
  }

  // x = V_l b: level l's V-cycle (the coarsest: its exact solve).
  void vcycle(std::size_t l, const Real* b, Real* x) {
    const std::size_t last = levels_.size() - 1;
    if (l == last) {
      solve_coarsest(b, x, false);
      return;
    }
    Level& level = levels_[l];
    const index_t n = level.block * level.nodes;
    // Chebyshev on [lower, upper]: theta the centre, delta the half width.
    const double theta = (level.upper + level.lower) / 2, delta = (level.upper - level.lower) / 2;
    const double sigma = theta / delta;
    Real* r = level.r.data();
    Real* d = level.d.data();
    Real* y = level.y.data();
    const Real* inv = level.inv.data();
    auto smooth = [&] {
      double rho = 1 / sigma;
      for (int k = 1; k < degree_; ++k) {
        product(l, d, y);
        const double next = 1 / (2 * sigma - rho);
        loops::smoother_step(exec_, kStream, n, y, inv, static_cast<Real>(next * rho),
                             static_cast<Real>(2 * next / delta), r, d, x);
        rho = next;
      }
    };
    loops::smoother_start(exec_, kStream, n, b, inv, static_cast<Real>(1 / theta), r, d, x);
    smooth();
    product(l, d, y);
    loops::subtract(exec_, kStream, n, y, r);

    Level& coarse = levels_[l + 1];
    const Transfer& t = transfers_[l];
    if (serial_ && level.block == 3)
      loops::restrict_owned_serial<3>(coarse.nodes, t.offsets.data(), t.columns.data(), level.owned,
                                      t.values.data(), r, coarse.b.data());
    else if (serial_)
      loops::restrict_owned_serial<6>(coarse.nodes, t.offsets.data(), t.columns.data(), level.owned,
                                      t.values.data(), r, coarse.b.data());
    else if (level.block == 3)
      loops::restrict_owned<3>(exec_, kStream, coarse.nodes, t.t_offsets.data(), t.t_rows.data(),
                               t.t_slots.data(), level.owned, t.values.data(), r, coarse.b.data());
    else
      loops::restrict_owned<6>(exec_, kStream, coarse.nodes, t.t_offsets.data(), t.t_rows.data(),
                               t.t_slots.data(), level.owned, t.values.data(), r, coarse.b.data());
    if (l + 1 < last) complete(l + 1, coarse.b.data());
    vcycle(l + 1, coarse.b.data(), coarse.x.data());
    if (level.block == 3)
      loops::prolong_add<3>(exec_, kStream, level.nodes, t.offsets.data(), t.columns.data(),
                            t.values.data(), coarse.x.data(), x);
    else
      loops::prolong_add<6>(exec_, kStream, level.nodes, t.offsets.data(), t.columns.data(),
                            t.values.data(), coarse.x.data(), x);

    product(l, x, y);
    loops::smoother_restart(exec_, kStream, n, b, y, inv, static_cast<Real>(1 / theta), r, d, x);
    smooth();
  }

  std::size_t host_bytes() const {
    std::size_t bytes = host_fine_.size() * sizeof(Real);
    for (const auto& v : host_values_) bytes += v.size() * sizeof(double);
    for (const auto& p : hierarchy_.prolongation)
      bytes += p.values.size() * sizeof(double) + p.pattern.columns.size() * sizeof(index_t);
    for (const auto& p : hierarchy_.operator_pattern) bytes += p.columns.size() * sizeof(index_t);
    return bytes;
  }

  Exec& exec_;
  LocalProblem<Real>& problem_;
  MPI_Comm comm_ = MPI_COMM_NULL;
  ElasticModel<Real> model_;
  Conversion<Real> conversion_;
  bool converting_;
  VertexTerms<Real> terms_;
  int degree_;
  // One host thread: the assembly takes the tets in their own order and the
  // restriction runs row by row (both faster there, and the same sums).
  bool serial_ = false;
  FineStructure fine_;
  Hierarchy hierarchy_;
  std::vector<Level> levels_;
  std::vector<Transfer> transfers_;
  Array<index_t> tets_, tet_slots_, tet_order_, diagonal_slots_;
  Array<TetRest<Real>> rest_;
  Array<Real> mass_, interpolant_;
  ContactView<Real> contact_;
  const Real* contact_qt_ = nullptr;
  const Real* interpolant_source_ = nullptr;
  Array<std::uint8_t> fixed_;
  Array<Real> coarse_stage_;     // a device's coarsest vectors, on the host (pinned)
  std::vector<Real> host_fine_;  // a device's finest operator, on the host
  std::vector<std::vector<double>> host_values_;  // [l >= 1]: the Galerkin products
  std::vector<std::unique_ptr<Halo<double>>> host_halos_;
  std::vector<Real> staging_;
  std::unique_ptr<CoarseSolver> coarse_;
  std::vector<double> coarse_b_, coarse_x_;
  PreconditionerStats stats_;
  long lanczos_gathers_ = 0;
  std::size_t memory_bytes_ = 0;
  double setup_seconds_ = 0;
};

}  // namespace descent
