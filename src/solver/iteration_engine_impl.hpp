#pragma once
// IterationEngine over an execution (HostExec or CudaExec): instantiated in
// solver/host_engine.cpp and kernels/cuda/cuda_engine.cu, nowhere else.
//
// One iteration (or Hessian product), as DESIGN §3 orders it, on two streams:
//   main: boundary tets [0, nb) -> (gather: shared vertices [ni, nv)) ->
//         shared partials to the host (one contiguous copy: the shared
//         vertices are the last nv - ni) -> exchange on the host -> back
//   side: interior tets [nb, nt) -> (gather: interior vertices [0, ni))
//   main: waits for side, then the fused vertex update over all dofs.
// Without neighbours there is no exchange, and the iterations between two
// energy checks are captured once per shape and replayed (run_graph).
// On the host (Exec::kHostMemory) the mesh data the problem holds is used
// in place: the engine allocates only what it writes.
#include <algorithm>
#include <chrono>
#include <string>
#include <variant>
#include <vector>

#include "common/error.hpp"
#include "kernels/contact_loops.hpp"
#include "kernels/exec_array.hpp"
#include "kernels/loops.hpp"
#include "solver/iteration_engine.hpp"
#include "solver/preconditioners/make_preconditioner.hpp"
#include "solver/preconditioners/multilevel/multilevel_impl.hpp"

namespace descent {

template <class Exec, class Real>
class EngineImpl final : public IterationEngine<Real> {
 public:
  EngineImpl(LocalProblem<Real>& problem, Halo<Real>& halo, const EngineOptions& options)
      : exec_(options.device),
        problem_(problem),
        halo_(halo),
        options_(options),
        model_(problem.model()),
        conversion_(problem.conversion()),
        converting_(problem.energy_changes_within_step()),
        terms_(problem.vertex_terms()) {
    const LocalMesh& mesh = problem.mesh();
    nt_ = mesh.num_tets();
    nb_ = mesh.num_boundary_tets;
    nv_ = mesh.num_vertices();
    ni_ = mesh.num_interior;
    owned_ = mesh.num_owned;
    n3_ = 3 * static_cast<std::size_t>(nv_);
    // A host with one thread adds the element results to the vertex partials
    // in tet order: bitwise the gather's sums, without the corner arrays'
    // round trip through memory (kernels/element_out.hpp).
    in_order_ = options.assembly == Assembly::gather && exec_.serial();
    const bool gather = options.assembly == Assembly::gather && !in_order_;

    tets_ = constant(mesh.tets.data(), mesh.tets.size(), memory_.tet_bytes);
    rest_ = constant(problem.rest().data(), problem.rest().size(), memory_.tet_bytes);
    if (converting_) interpolant_ = make<Real>(nt_, memory_.tet_bytes);
    if (gather) {
      corner_ids_ =
          constant(mesh.vertex_corners.data(), mesh.vertex_corners.size(), memory_.tet_bytes);
      offsets_ =
          constant(mesh.corner_offsets.data(), mesh.corner_offsets.size(), memory_.vertex_bytes);
      corner_grad_ = make<Real>(12 * static_cast<std::size_t>(nt_), memory_.tet_bytes);
      corner_diag_ = make<Real>(12 * static_cast<std::size_t>(nt_), memory_.tet_bytes);
    }
    mass_ = constant(problem.mass().data(), problem.mass().size(), memory_.vertex_bytes);
    fixed_ =
        constant(problem.fixed_axes().data(), problem.fixed_axes().size(), memory_.vertex_bytes);
    floor_ = constant(problem.diagonal_floor().data(), n3_, memory_.vertex_bytes);
    rest_curvature_ = constant(problem.rest_curvature().data(), n3_, memory_.vertex_bytes);
    for (Array<Real>* a : {&force_, &y_, &qt_, &checked_, &diag_, &q_[0], &q_[1], &q_[2]})
      *a = make<Real>(n3_, memory_.vertex_bytes);
    partial_ = make<Real>(2 * n3_, memory_.vertex_bytes);
    // Staging for the exchange: the host buffer is indexed like partial_, but
    // only the shared range [width ni, width nv) is ever copied.
    if (halo_.num_neighbours() > 0) stage_ = make_pinned<Real>(2 * n3_);
    for (Array<Real>* a : {&stage_q_, &stage_y_, &stage_qt_, &stage_force_, &stage_vector_})
      *a = make_pinned<Real>(n3_);
    if (problem.contact() && problem.contact()->energy_method()) {
      const ObstacleContact<Real>& c = *problem.contact();
      contact_ = c.view();
      contact_vertices_ = constant(c.vertices().data(), c.vertices().size(), memory_.vertex_bytes);
      contact_kappa_ = constant(c.kappa().data(), c.kappa().size(), memory_.vertex_bytes);
      contact_lags_ = constant(c.lags().data(), c.lags().size(), memory_.vertex_bytes);
      contact_geometry_ = constant(c.geometry().data(), c.geometry().size(), memory_.other_bytes);
      contact_.vertices = contact_vertices_.data();
      contact_.kappa = contact_kappa_.data();
      contact_.lags = contact_lags_.data();
      contact_.obstacles = contact_geometry_.data();
    }
    if (problem.body_contact()) {
      if constexpr (!Exec::kHostMemory)
        throw InputError(
            "contact between bodies (several bodies, or contact.self) runs on the cpu backend "
            "only: use --backend cpu");
      bodies_ = problem.body_contact();
    }
    reserve_params(64);
  }

  typename IterationEngine<Real>::Staging staging() override {
    return {stage_q_.data(), stage_y_.data(), stage_qt_.data(), stage_force_.data(),
            stage_vector_.data()};
  }

  void begin_step(bool upload_force, const Real* interpolants) override {
    const std::size_t bytes = checked_.bytes();
    cur_ = 0;
    exec_.copy(kMain, q_[cur_].data(), stage_q_.data(), bytes);
    exec_.copy(kMain, q_[prev_index()].data(), q_[cur_].data(), bytes);
    exec_.copy(kMain, checked_.data(), q_[cur_].data(), bytes);
    exec_.copy(kMain, y_.data(), stage_y_.data(), bytes);
    exec_.copy(kMain, qt_.data(), stage_qt_.data(), bytes);
    if (upload_force) exec_.copy(kMain, force_.data(), stage_force_.data(), bytes);
    if (converting_) exec_.copy(kMain, interpolant_.data(), interpolants, interpolant_.bytes());
    // The obstacles where the step ends and the friction lags of its start
    // (on the host the engine reads the problem's own).
    if (contact_.num_vertices > 0 && !Exec::kHostMemory) {
      const ObstacleContact<Real>& c = *problem_.contact();
      exec_.copy(kMain, contact_lags_.data(), c.lags().data(), contact_lags_.bytes());
      exec_.copy(kMain, contact_geometry_.data(), c.geometry().data(), contact_geometry_.bytes());
    }
    // The host may change its buffers as soon as this returns.
    exec_.sync(kMain);
  }

  void iterate(int count, const std::uint8_t* refresh, const Real* alpha,
               const Real* omega) override {
    DESCENT_VERIFY(count > 0, "iteration block of ", count);
    exec_.sync(kMain);  // the previous block's parameter upload is done with params_host_
    reserve_params(static_cast<std::size_t>(count));
    for (int i = 0; i < count; ++i) params_host_.data()[i] = {alpha[i], omega[i]};
    exec_.copy(kMain, params_.data(), params_host_.data(), count * sizeof(params_host_.data()[0]));
    const int first = cur_;
    auto enqueue = [&, first] {
      for (int i = 0; i < count; ++i)
        iteration(refresh[i] != 0, params_.data() + i, (first + i) % 3);
    };
    if (preconditioner_) {
      // The V-cycle synchronises with the host (its coarsest solve): no
      // sequence to capture.
      for (int i = 0; i < count; ++i) preconditioned_iteration(params_.data() + i, (first + i) % 3);
    } else if (options_.graphs && halo_.num_neighbours() == 0) {
      // A captured sequence bakes in its buffers: the key names the rotation
      // phase and which iterations refresh the diagonal.
      std::string key = std::to_string(first) + ":";
      for (int i = 0; i < count; ++i) key += refresh[i] ? '1' : '0';
      exec_.run_graph(key, enqueue);
    } else {
      enqueue();
    }
    cur_ = (first + count) % 3;
  }

  Energy local_energy(bool checked) override {
    const Real* q = checked ? checked_.data() : q_[cur_].data();
    const loops::VertexData<Real> vd = vertex_data();
    // The lanes' tet energies on the host (loops::local_energy).
    double* tet_energy = nullptr;
    if constexpr (Exec::kHostMemory) {
      tet_energy_.resize(static_cast<std::size_t>(nt_));
      tet_energy = tet_energy_.data();
    }
    const Sum2 s = std::visit(
        [&](const auto& model) {
          return converting_
                     ? loops::local_energy<true>(
                           exec_, kMain, model, conversion_, interpolant_.data(), q, tets_.data(),
                           rest_.data(), nt_, vd, rest_curvature_.data(), owned_, tet_energy)
                     : loops::local_energy<false>(
                           exec_, kMain, model, conversion_, interpolant_.data(), q, tets_.data(),
                           rest_.data(), nt_, vd, rest_curvature_.data(), owned_, tet_energy);
        },
        model_);
    Energy e{s.value, s.magnitude};
    if (contact_.num_vertices > 0) {
      const Sum2 c = loops::contact_energy(exec_, kMain, contact_, q, qt_.data());
      e = {e.value + c.value, e.magnitude + c.magnitude};
    }
    if (bodies_) {
      exec_.sync(kMain);
      const double pairs = bodies_->local_energy(q);
      e = {e.value + pairs, e.magnitude + in_double_units<Real>(std::abs(pairs))};
    }
    return e;
  }

  void accept() override { exec_.copy(kMain, checked_.data(), q_[cur_].data(), checked_.bytes()); }

  bool contact_pairs_drifted() override {
    if (!bodies_) return false;
    exec_.sync(kMain);
    return bodies_->needs_rebuild(q_[cur_].data());
  }

  void refresh_contact_pairs() override {
    if (!bodies_) return;
    exec_.sync(kMain);
    bodies_->rebuild_here(q_[cur_].data());
  }

  void rollback() override {
    exec_.copy(kMain, q_[cur_].data(), checked_.data(), checked_.bytes());
    exec_.copy(kMain, q_[prev_index()].data(), checked_.data(), checked_.bytes());
  }

  void download(bool checked) override {
    exec_.copy(kMain, stage_q_.data(), checked ? checked_.data() : q_[cur_].data(),
               checked_.bytes());
    exec_.sync(kMain);
  }

  void download_interpolants(Real* interpolants) override {
    if (!converting_) return;
    exec_.copy(kMain, interpolants, interpolant_.data(), interpolant_.bytes());
    exec_.sync(kMain);
  }

  void refresh_diagonal() override {
    assemble([&](int stream, index_t begin,
                 index_t end) { element_pass(stream, q_[cur_].data(), begin, end, true, 6); },
             true, 6);
    add_contact(q_[cur_].data(), 6, nullptr);
    loops::diagonal_update(exec_, kMain, 3 * nv_, vertex_data(), partial_.data(), diag_.data());
    exec_.sync(kMain);
  }

  void use_preconditioner(const SolverSpec& spec) override {
    // The iterations refresh no diagonal now: its corner values go (before
    // the preconditioner's set-up, the run's peak of memory).
    if (corner_diag_.size() > 0) {
      memory_.tet_bytes -= corner_diag_.bytes();
      corner_diag_ = {};
    }
    const std::string kind = preconditioner_of(spec);
    if (kind == "multilevel") {
      auto multilevel =
          std::make_unique<MultilevelPreconditioner<Exec, Real>>(exec_, problem_, spec);
      if (contact_.num_vertices > 0) multilevel->use_contact(contact_, qt_.data());
      preconditioner_ = std::move(multilevel);
    } else if constexpr (Exec::kHostMemory) {
      preconditioner_ = make_host_preconditioner(problem_, spec);
    } else {
      throw InputError(detail::concat("solver.preconditioner = \"", kind,
                                      "\" runs on the cpu backend only; use --backend cpu, or "
                                      "solver.preconditioner = \"multilevel\""));
    }
    DESCENT_VERIFY(preconditioner_, "no preconditioner for ", kind);
    if (contact_.num_vertices > 0) {
      const std::size_t n = 3 * static_cast<std::size_t>(contact_.num_vertices);
      contact_base_ = constant(problem_.contact()->base().data(), n, memory_.vertex_bytes);
      contact_reference_ = make<Real>(n, memory_.vertex_bytes);
      contact_scale_ = make<Real>(n, memory_.vertex_bytes);
      contact_.base = contact_base_.data();
      contact_.reference = contact_reference_.data();
      contact_.scale = contact_scale_.data();
    }
    if (converting_) preconditioner_->read_interpolants_from(interpolant_.data());
    gradient_ = make<Real>(n3_, memory_.vertex_bytes);
    direction_ = make<Real>(n3_, memory_.vertex_bytes);
  }
  const Preconditioner<Real>* preconditioner() const override { return preconditioner_.get(); }
  void refresh_preconditioner() override {
    exec_.sync(kMain);
    preconditioner_->refresh(q_[cur_].data());
    if (contact_.num_vertices > 0)
      loops::contact_reference(exec_, kMain, contact_, q_[cur_].data(), qt_.data());
  }

  std::array<double, 6> translation_sums() override {
    std::array<double, 6> sums{};
    if (preconditioner_) return sums;
    for (int axis = 0; axis < 3; ++axis) {
      const Sum2 s =
          loops::translation_sums(exec_, kMain, owned_, vertex_data(), diag_.data(), axis);
      sums[2 * axis] = s.value;
      sums[2 * axis + 1] = s.magnitude;
    }
    return sums;
  }

  double lanczos_begin() override {
    if (lanczos_[0].size() == 0)
      for (Array<Real>& a : lanczos_) a = make<Real>(n3_, memory_.vertex_bytes);
    if (preconditioner_) {
      if (lanczos_residual_[0].size() == 0)
        for (Array<Real>& a : lanczos_residual_) a = make<Real>(n3_, memory_.vertex_bytes);
      for (Array<Real>& a : lanczos_residual_) exec_.zero(kMain, a.data(), a.bytes());
      Real* s = lanczos_residual_[kS].data();
      exec_.copy(kMain, s, stage_vector_.data(), lanczos_residual_[kS].bytes());
      loops::zero_held(exec_, kMain, 3 * nv_, fixed_.data(), s);
      return precondition_residual();
    }
    Real* w = lanczos_[kW].data();
    exec_.copy(kMain, w, stage_vector_.data(), lanczos_[kW].bytes());
    exec_.zero(kMain, lanczos_[kV].data(), lanczos_[kV].bytes());
    exec_.zero(kMain, lanczos_[kVPrev].data(), lanczos_[kVPrev].bytes());
    loops::zero_held(exec_, kMain, 3 * nv_, fixed_.data(), w);
    return loops::weighted_norm2(exec_, kMain, 3 * owned_, diag_.data(), w);
  }

  void lanczos_next(double beta) override {
    if (preconditioner_) {
      loops::lanczos_advance_preconditioned(exec_, kMain, 3 * nv_, static_cast<Real>(1.0 / beta),
                                            lanczos_residual_[kS].data(), lanczos_[kW].data(),
                                            lanczos_residual_[kU].data(),
                                            lanczos_residual_[kUPrev].data(), lanczos_[kV].data());
      return;
    }
    loops::lanczos_advance(exec_, kMain, 3 * nv_, static_cast<Real>(1.0 / beta),
                           lanczos_[kW].data(), lanczos_[kV].data(), lanczos_[kVPrev].data());
  }

  double lanczos_product() override {
    const Real* q = q_[cur_].data();
    const Real* v = lanczos_[kV].data();
    assemble([&](int stream, index_t begin,
                 index_t end) { hessian_product_pass(stream, q, v, begin, end); },
             false, 3);
    // partial_ holds the elastic part, 3 per vertex; the contact Hessian's
    // product joins it.
    if (contact_.num_vertices > 0)
      loops::add_contact_hessian_product(exec_, kMain, contact_, vertex_data(), q, v,
                                         partial_.data());
    if (bodies_) {
      exec_.sync(kMain);
      bodies_->add_hessian_product(q, v, partial_.data());
    }
    return loops::hessian_vertex_terms(exec_, kMain, 3 * nv_, 3 * owned_, vertex_data(),
                                       partial_.data(), v, lanczos_[kY].data());
  }

  double lanczos_orthogonalize(double alpha, double beta_prev) override {
    if (preconditioner_) {
      loops::lanczos_residual_preconditioned(
          exec_, kMain, 3 * nv_, lanczos_[kY].data(), lanczos_residual_[kU].data(),
          lanczos_residual_[kUPrev].data(), static_cast<Real>(alpha), static_cast<Real>(beta_prev),
          lanczos_residual_[kS].data());
      return precondition_residual();
    }
    Real* w = lanczos_[kW].data();
    loops::lanczos_residual(exec_, kMain, 3 * nv_, lanczos_[kY].data(), diag_.data(),
                            lanczos_[kV].data(), lanczos_[kVPrev].data(), static_cast<Real>(alpha),
                            static_cast<Real>(beta_prev), w);
    return loops::weighted_norm2(exec_, kMain, 3 * owned_, diag_.data(), w);
  }

  void synchronize() override {
    exec_.sync(kSide);
    exec_.sync(kMain);
  }

  typename IterationEngine<Real>::KernelTiming time_element_pass(bool with_diag,
                                                                 int repeats) override {
    const int width = with_diag ? 6 : 3;
    const Real* q = q_[cur_].data();
    synchronize();
    const auto start = std::chrono::steady_clock::now();
    for (int r = 0; r < repeats; ++r) {
      if (!gathers())
        exec_.zero(kMain, partial_.data(), static_cast<std::size_t>(width) * nv_ * sizeof(Real));
      element_pass(kMain, q, 0, nt_, with_diag, width);
    }
    synchronize();
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() / repeats;
    // Per tet: 4 ids, the rest data, 12 position reals, 12 output reals per
    // output (added to the partials: each a read-modify-write, counted twice).
    const double outputs = (with_diag ? 24.0 : 12.0) * (gathers() ? 1.0 : 2.0) * sizeof(Real);
    const double per_tet =
        4.0 * sizeof(index_t) + sizeof(TetRest<Real>) + 12.0 * sizeof(Real) + outputs;
    return {seconds, per_tet * nt_};
  }

  EngineMemory memory() const override { return memory_; }
  std::string describe() const override {
    return exec_.describe() + ", " + to_string(options_.assembly) + " assembly" +
           (in_order_ ? " (in tet order)" : "");
  }
  bool on_device() const override { return !Exec::kHostMemory; }
  long graph_launches() const override { return exec_.graph_launches(); }

 private:
  static constexpr int kMain = 0, kSide = 1;                              // streams
  static constexpr int kStart = 0, kBoundaryDone = 1, kInteriorDone = 2;  // events
  static constexpr int kV = 0, kVPrev = 1, kW = 2, kY = 3;                // Lanczos vectors
  static constexpr int kS = 0, kU = 1, kUPrev = 2;  // their residual-space partners (P^-1)

  template <class T>
  using Array = ExecArray<Exec, T>;

  template <class T>
  Array<T> make(std::size_t n, std::size_t& counter) {
    counter += n * sizeof(T);
    return Array<T>(&exec_, n, false);
  }
  template <class T>
  Array<T> make_pinned(std::size_t n) {
    return Array<T>(&exec_, n, true);
  }
  // Data that stays as the problem holds it: used in place on the host,
  // copied to a device once.
  template <class T>
  Array<T> constant(const T* host, std::size_t n, std::size_t& counter) {
    if constexpr (Exec::kHostMemory) {
      return Array<T>::view(host, n);
    } else {
      Array<T> a = make<T>(n, counter);
      exec_.copy(kMain, a.data(), host, a.bytes());
      exec_.sync(kMain);
      return a;
    }
  }

  int prev_index() const { return (cur_ + 2) % 3; }

  // Room for the parameters of `count` iterations. Growing moves the device
  // array, so captured graphs (which name it) are dropped with it.
  void reserve_params(std::size_t count) {
    if (count <= params_.size()) return;
    memory_.other_bytes -= params_.bytes();
    params_ = make<loops::IterationParams<Real>>(count, memory_.other_bytes);
    params_host_ = make_pinned<loops::IterationParams<Real>>(count);
    exec_.clear_graphs();
  }

  // Whether the element results go through the corner arrays and the gather.
  bool gathers() const { return options_.assembly == Assembly::gather && !in_order_; }

  loops::VertexData<Real> vertex_data() const {
    return {mass_.data(), fixed_.data(), floor_.data(), force_.data(),
            y_.data(),    qt_.data(),    terms_};
  }

  loops::ElementOut<Real> element_out(int width) {
    loops::ElementOut<Real> out;
    if (gathers()) {
      out.corner_grad = corner_grad_.data();
      out.corner_diag = corner_diag_.data();
    } else {
      out.partial = partial_.data();
      out.in_order = in_order_;
    }
    out.width = width;
    return out;
  }

  void element_pass(int stream, const Real* q, index_t begin, index_t end, bool with_diag,
                    int width) {
    if (end <= begin) return;
    const loops::ElementOut<Real> out = element_out(width);
    std::visit(
        [&](const auto& model) {
          if (converting_)
            loops::element_pass<true>(exec_, stream, model, conversion_, interpolant_.data(), q,
                                      tets_.data(), rest_.data(), begin, end, with_diag, out);
          else
            loops::element_pass<false>(exec_, stream, model, conversion_, interpolant_.data(), q,
                                       tets_.data(), rest_.data(), begin, end, with_diag, out);
        },
        model_);
  }

  void hessian_product_pass(int stream, const Real* q, const Real* p, index_t begin, index_t end) {
    if (end <= begin) return;
    const loops::ElementOut<Real> out = element_out(3);
    std::visit(
        [&](const auto& model) {
          if (converting_)
            loops::hessian_product_pass<true>(exec_, stream, model, conversion_,
                                              static_cast<const Real*>(interpolant_.data()), q, p,
                                              tets_.data(), rest_.data(), begin, end, out);
          else
            loops::hessian_product_pass<false>(exec_, stream, model, conversion_,
                                               static_cast<const Real*>(interpolant_.data()), q, p,
                                               tets_.data(), rest_.data(), begin, end, out);
        },
        model_);
  }

  void gather(int stream, index_t begin, index_t end, bool with_diag, int width) {
    if (end <= begin) return;
    loops::gather_corners(exec_, stream, offsets_.data(), corner_ids_.data(), begin, end,
                          corner_grad_.data(), partial_.data(), width, 0);
    if (with_diag)
      loops::gather_corners(exec_, stream, offsets_.data(), corner_ids_.data(), begin, end,
                            corner_diag_.data(), partial_.data(), width, 3);
  }

  // Element results assembled into partial_ (`width` per vertex) on every
  // local vertex, shared ones completed through the halo: pass(stream, begin,
  // end) runs the element kernel over tets [begin, end); with_diag: its
  // second output (the diagonal) is gathered too. Queued on the streams; the
  // main stream holds the result when this returns.
  template <class ElementPass>
  void assemble(const ElementPass& pass, bool with_diag, int width) {
    const bool gather_mode = gathers();
    const bool exchange = halo_.num_neighbours() > 0;
    const std::size_t shared_offset = static_cast<std::size_t>(width) * ni_;
    const std::size_t shared_bytes = static_cast<std::size_t>(width) * (nv_ - ni_) * sizeof(Real);

    if (!gather_mode)
      exec_.zero(kMain, partial_.data(), static_cast<std::size_t>(width) * nv_ * sizeof(Real));
    exec_.record(kMain, kStart);
    exec_.wait(kSide, kStart);
    pass(kMain, 0, nb_);
    if (gather_mode) gather(kMain, ni_, nv_, with_diag, width);
    exec_.record(kMain, kBoundaryDone);
    if (exchange)
      exec_.copy(kMain, stage_.data() + shared_offset, partial_.data() + shared_offset,
                 shared_bytes);
    auto interior = [&] {
      pass(kSide, nb_, nt_);
      if (gather_mode) {
        exec_.wait(kSide, kBoundaryDone);  // interior vertices have boundary-tet corners too
        gather(kSide, 0, ni_, with_diag, width);
      }
      exec_.record(kSide, kInteriorDone);
    };
    // An asynchronous execution queues the interior before the host blocks
    // on the exchange, so the two overlap; the host one runs it in between.
    if constexpr (Exec::kAsync) interior();
    if (exchange) {
      exec_.sync(kMain);
      halo_.begin(stage_.data(), width);
    }
    if constexpr (!Exec::kAsync) interior();
    if (exchange) {
      halo_.finish(stage_.data(), width);
      exec_.copy(kMain, partial_.data() + shared_offset, stage_.data() + shared_offset,
                 shared_bytes);
    }
    exec_.wait(kMain, kInteriorDone);
  }

  // z (the Lanczos w) <- P^-1 s; returns s . z over owned dofs.
  double precondition_residual() {
    const Real* s = lanczos_residual_[kS].data();
    Real* z = lanczos_[kW].data();
    preconditioner_->apply(s, z);
    return loops::inner_product(exec_, kMain, 3 * owned_, s, z);
  }

  // One iteration with P^-1: the gradient assembled (no diagonal), P^-1
  // applied to it, the Chebyshev update along it.
  void preconditioned_iteration(const loops::IterationParams<Real>* params, int c) {
    const Real* q = q_[c].data();
    assemble([&](int stream, index_t begin,
                 index_t end) { element_pass(stream, q, begin, end, false, 3); },
             false, 3);
    add_contact(q, 3, nullptr);
    loops::gradient_dofs(exec_, kMain, 3 * nv_, vertex_data(), partial_.data(), q,
                         gradient_.data());
    if (contact_.num_vertices > 0)
      loops::apply_contact_scale(exec_, kMain, contact_, gradient_.data());
    preconditioner_->apply(gradient_.data(), direction_.data());
    if (contact_.num_vertices > 0)
      loops::apply_contact_scale(exec_, kMain, contact_, direction_.data());
    loops::preconditioned_update(exec_, kMain, 3 * nv_, fixed_.data(), direction_.data(), q,
                                 q_[(c + 2) % 3].data(), q_[(c + 1) % 3].data(), params);
    guard(c);
  }

  // The contact terms at q joined to the assembled partials (`width` per
  // vertex) and `diag` raised to them (kernels/contact_loops.hpp); nothing
  // without contact.
  void add_contact(const Real* q, int width, Real* diag) {
    if (contact_.num_vertices > 0)
      loops::add_contact_gradient(exec_, kMain, contact_, vertex_data(), q, partial_.data(), width,
                                  diag);
    if (bodies_) {
      exec_.sync(kMain);
      bodies_->add_gradient(q, partial_.data(), width, diag, terms_, mass_.data());
    }
  }

  // No surface vertex's move from buffer c to (c + 1) % 3 enters an
  // obstacle or crosses a surface of the bodies. A vertex the bodies' guard
  // cuts loses its momentum: buffer c is only the next iteration's previous
  // iterate now.
  void guard(int c) {
    Real* q_next = q_[(c + 1) % 3].data();
    if (contact_.num_vertices > 0)
      loops::guard_moves(exec_, kMain, contact_, fixed_.data(), q_[c].data(), q_next);
    if (bodies_) {
      exec_.sync(kMain);
      bodies_->guard(q_[c].data(), q_next, fixed_.data());
    }
  }

  // One iteration from buffer `c` (current), (c + 2) % 3 (previous) into
  // (c + 1) % 3 (next).
  void iteration(bool refresh, const loops::IterationParams<Real>* params, int c) {
    const Real* q = q_[c].data();
    const int width = refresh ? 6 : 3;
    assemble([&](int stream, index_t begin,
                 index_t end) { element_pass(stream, q, begin, end, refresh, width); },
             refresh, width);
    add_contact(q, width, refresh ? nullptr : diag_.data());
    loops::vertex_update(exec_, kMain, 3 * nv_, vertex_data(), partial_.data(), width, refresh,
                         diag_.data(), q, q_[(c + 2) % 3].data(), q_[(c + 1) % 3].data(), params);
    guard(c);
  }

  Exec exec_;
  LocalProblem<Real>& problem_;
  Halo<Real>& halo_;
  EngineOptions options_;
  ElasticModel<Real> model_;
  Conversion<Real> conversion_;
  bool converting_;
  VertexTerms<Real> terms_;
  index_t nt_ = 0, nb_ = 0, nv_ = 0, ni_ = 0, owned_ = 0;
  bool in_order_ = false;
  std::size_t n3_ = 0;
  int cur_ = 0;
  EngineMemory memory_;

  Array<index_t> tets_, corner_ids_, offsets_;
  Array<TetRest<Real>> rest_;
  Array<Real> interpolant_, corner_grad_, corner_diag_;
  Array<Real> mass_, floor_, rest_curvature_, force_, y_, qt_, checked_, diag_, partial_;
  Array<std::uint8_t> fixed_;
  Array<Real> q_[3];
  Array<Real> lanczos_[4];           // v, v_prev, w, y: made at the first estimate
  Array<Real> lanczos_residual_[3];  // s, u, u_prev: with a preconditioner other than D^-1
  std::unique_ptr<Preconditioner<Real>> preconditioner_;
  Array<Real> gradient_, direction_;  // g and P^-1 g, with that preconditioner
  Array<Real> stage_;                 // exchange (pinned host)
  Array<Real> stage_q_, stage_y_, stage_qt_, stage_force_, stage_vector_;  // (pinned host)
  Array<loops::IterationParams<Real>> params_, params_host_;
  // Obstacle contact with contact.method = "energy" (num_vertices 0 without).
  ContactView<Real> contact_;
  // Contact between bodies (null without; the CPU only): its pairs' terms
  // and guard, with the ghosts' positions exchanged at each use.
  BodyContact<Real>* bodies_ = nullptr;
  Array<index_t> contact_vertices_;
  Array<Real> contact_kappa_;
  Array<FrictionLag<Real>> contact_lags_;
  Array<ObstacleGeometry<Real>> contact_geometry_;
  Array<Real> contact_base_, contact_reference_, contact_scale_;  // with a preconditioner
  std::vector<double> tet_energy_;  // one per tet: local_energy's scratch on the host
};

}  // namespace descent
