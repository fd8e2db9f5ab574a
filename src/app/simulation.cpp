#include "app/simulation.hpp"

#include <algorithm>
#include <cstdio>

#include "comm/mpi_check.hpp"
#include "common/error.hpp"
#include "solver/loads.hpp"

namespace descent {

namespace {

bool scene_needs_measurements(const Scene& scene) {
  bool moving = false;
  for (const FixedRegion& region : scene.fixed) moving = moving || region.motion.kind != "none";
  return moving || !scene.loads.empty() || scene.time.quasistatic ||
         scene.material.conversion.enabled || !scene.obstacles.empty() || !scene.bodies.empty() ||
         scene.contact.self;
}

std::vector<std::string> scene_measurement_names(const Scene& scene) {
  std::vector<std::string> names;
  if (!scene_needs_measurements(scene)) return names;
  const char* xyz[3] = {"x", "y", "z"};
  for (std::size_t r = 0; r < scene.fixed.size(); ++r) {
    for (const char* a : xyz) names.push_back(detail::concat("fixed", r, "_disp_", a));
    for (const char* a : xyz) names.push_back(detail::concat("fixed", r, "_reaction_", a));
  }
  for (std::size_t r = 0; r < scene.loads.size(); ++r) {
    for (const char* a : xyz) names.push_back(detail::concat("load", r, "_disp_", a));
    for (const char* a : xyz) names.push_back(detail::concat("load", r, "_force_", a));
  }
  if (scene.material.conversion.enabled) names.push_back("converted_elements");
  for (std::size_t k = 0; k < scene.obstacles.size(); ++k) {
    for (const char* a : xyz) names.push_back(detail::concat("obstacle", k, "_force_", a));
    names.push_back(detail::concat("obstacle", k, "_contacts"));
  }
  if (!scene.obstacles.empty()) names.push_back("contact_penetration");
  if (has_body_contact(scene)) {
    names.push_back("body_contact_pairs");
    names.push_back("body_contact_least_distance");
    if (scene.contact.method == "projection") names.push_back("body_contact_penetration");
  }
  for (std::size_t b = 0; b < scene.bodies.size(); ++b) {
    for (const char* a : xyz) names.push_back(detail::concat("body", b, "_com_", a));
    for (const char* a : xyz) names.push_back(detail::concat("body", b, "_velocity_", a));
    for (const char* a : xyz) names.push_back(detail::concat("body", b, "_momentum_", a));
    names.push_back(detail::concat("body", b, "_kinetic"));
    if (has_body_contact(scene))
      for (const char* a : xyz) names.push_back(detail::concat("body", b, "_contact_force_", a));
  }
  return names;
}

// Per body, sums over this rank's owned vertices of q and v: [m, m x (3),
// m v (3), m |v|^2 / 2] (kBodySums each).
constexpr int kBodySums = 8;

template <class Real>
std::vector<double> local_body_sums(const LocalMesh& mesh, const std::vector<int>& body,
                                    const std::vector<Real>& mass, const Real* q, const Real* v) {
  std::vector<double> sums(kBodySums * static_cast<std::size_t>(mesh.num_bodies()), 0.0);
  for (index_t i = 0; i < mesh.num_owned; ++i) {
    double* s = &sums[kBodySums * static_cast<std::size_t>(body[i])];
    const double m = mass[i];
    s[0] += m;
    for (int d = 0; d < 3; ++d) {
      s[1 + d] += m * q[3 * i + d];
      s[4 + d] += m * v[3 * i + d];
      s[7] += 0.5 * m * v[3 * i + d] * v[3 * i + d];
    }
  }
  return sums;
}

// Each body's initial rigid velocity v = velocity + angular_velocity x
// (x - c), c its centre of mass (one allreduce); held axes stay at rest.
template <class Real>
void set_body_velocities(const Scene& scene, const LocalMesh& mesh,
                         const LocalProblem<Real>& problem, EnergyReduction& reduction,
                         BodyState<Real>& state) {
  if (scene.bodies.empty()) return;
  const std::vector<int> body = vertex_bodies(mesh);
  std::vector<double> sums =
      local_body_sums(mesh, body, problem.mass(), state.q.data(), state.v.data());
  reduction.sum_in_place(sums);
  const std::vector<std::uint8_t>& held = problem.fixed_axes();
  for (index_t i = 0; i < mesh.num_vertices(); ++i) {
    const Body& b = scene.bodies[body[i]];
    const double* s = &sums[kBodySums * static_cast<std::size_t>(body[i])];
    double r[3];
    for (int d = 0; d < 3; ++d) r[d] = static_cast<double>(state.q[3 * i + d]) - s[1 + d] / s[0];
    const auto& w = b.angular_velocity;
    const double spin[3] = {w[1] * r[2] - w[2] * r[1], w[2] * r[0] - w[0] * r[2],
                            w[0] * r[1] - w[1] * r[0]};
    for (int d = 0; d < 3; ++d) {
      const Real velocity =
          (held[i] & (1u << d)) ? Real(0) : static_cast<Real>(b.velocity[d] + spin[d]);
      state.v[3 * i + d] = velocity;
      state.v_prev[3 * i + d] = velocity;
    }
  }
}

}  // namespace

template <class Real>
Simulation<Real>::Simulation(MPI_Comm comm, const Scene& scene, DistributedMesh mesh,
                             const BackendChoice& backend)
    : scene_(scene),
      num_global_vertices_(mesh.local.num_global_vertices),
      num_global_tets_(mesh.local.num_global_tets),
      measurement_names_(scene_measurement_names(scene)),
      quality_(std::move(mesh.quality)),
      local_(std::move(mesh.local)),
      halo_(comm, local_),
      reduction_(comm),
      problem_(local_, scene, halo_, reduction_),
      solver_(make_backend_stepper(problem_, halo_, scene.solver, backend)),
      state_(rest_state<Real>(local_)) {
  set_body_velocities(scene_, local_, problem_, reduction_, state_);
}

template <class Real>
Simulation<Real>::Simulation(MPI_Comm comm, const Scene& scene, const Mesh& mesh,
                             const BackendChoice& backend)
    : Simulation(comm, scene, distribute_mesh(comm, mesh, scene.partition), backend) {}

template <class Real>
void Simulation<Real>::set_positions(const std::vector<double>& global_xyz) {
  for (index_t v = 0; v < local_.num_vertices(); ++v)
    for (int i = 0; i < 3; ++i)
      state_.q[3 * v + i] = static_cast<Real>(global_xyz[3 * local_.global_vertex[v] + i]);
  std::fill(state_.v.begin(), state_.v.end(), Real(0));
  std::fill(state_.v_prev.begin(), state_.v_prev.end(), Real(0));
}

namespace {

// The counts of an earlier attempt at the same step, added to the one that
// stands.
void add_attempt(StepStats& stands, const StepStats& earlier) {
  stands.rollbacks += earlier.rollbacks;
  stands.nonfinite_rollbacks += earlier.nonfinite_rollbacks;
  stands.spectrum_steps += earlier.spectrum_steps;
}

}  // namespace

template <class Real>
StepStats Simulation<Real>::step() {
  const StepMemory memory = solver_->memory();
  solver_->abandon_non_finite_guess_next_step();
  StepStats first = solver_->step(state_);
  if (first.finite) return first;
  // The failed step left the body at its start, which is finite; only the
  // guess was not. Every rank knows (the reduction), so all retry alike.
  solver_->set_memory(memory);
  solver_->guess_next_step_from_start();
  StepStats retry = solver_->step(state_);
  if (!retry.finite && first.abandoned_guess) {
    // The step start led nowhere either: back to the guess, shrinking the
    // step as far as it takes this time (from a guess of non-finite energy
    // a short enough step can still reach a finite state).
    solver_->set_memory(memory);
    StepStats persisted = solver_->step(state_);
    add_attempt(persisted, retry);
    retry = persisted;
  }
  retry.retried_from_start = true;
  add_attempt(retry, first);
  if (!retry.rejected_at.found()) retry.rejected_at = first.rejected_at;
  return retry;
}

template <class Real>
Checkpoint Simulation<Real>::checkpoint(int frame) const {
  Checkpoint c;
  c.num_ranks = local_.num_ranks;
  c.rank = local_.rank;
  c.frame = frame;
  c.num_global_vertices = num_global_vertices_;
  c.num_global_tets = num_global_tets_;
  c.time = state_.time;
  const StepMemory memory = solver_->memory();
  c.alpha = memory.alpha;
  c.lambda_min = memory.lambda_min;
  c.lambda_max = memory.lambda_max;
  c.widening = memory.widening;
  c.steps_since_estimate = memory.steps_since_estimate;
  c.reestimate = memory.reestimate;
  c.q.assign(state_.q.begin(), state_.q.end());
  c.v.assign(state_.v.begin(), state_.v.end());
  c.v_prev.assign(state_.v_prev.begin(), state_.v_prev.end());
  c.interpolants.assign(problem_.interpolants().begin(), problem_.interpolants().end());
  return c;
}

template <class Real>
void Simulation<Real>::restore(const Checkpoint& c) {
  const bool same_run = c.num_ranks == local_.num_ranks && c.rank == local_.rank &&
                        c.num_global_vertices == num_global_vertices_ &&
                        c.num_global_tets == num_global_tets_ && c.q.size() == state_.q.size() &&
                        c.interpolants.size() == problem_.interpolants().size();
  if (!same_run) {
    throw InputError(detail::concat(
        "the checkpoint of rank ", c.rank, " of ", c.num_ranks, " (", c.num_global_vertices,
        " vertices, ", c.num_global_tets, " tets) does not belong to this run (rank ", local_.rank,
        " of ", local_.num_ranks, ", ", num_global_vertices_, " vertices, ", num_global_tets_,
        " tets): restart with the same scene and rank count"));
  }
  state_.q.assign(c.q.begin(), c.q.end());
  state_.v.assign(c.v.begin(), c.v.end());
  state_.v_prev.assign(c.v_prev.begin(), c.v_prev.end());
  state_.time = c.time;
  solver_->set_memory(
      {c.alpha, c.lambda_min, c.lambda_max, c.steps_since_estimate, c.reestimate, c.widening});
  problem_.set_interpolants(std::vector<Real>(c.interpolants.begin(), c.interpolants.end()));
}

template <class Real>
std::vector<double> Simulation<Real>::measure() {
  if (measurement_names_.empty()) return {};
  std::vector<double> sums = solver_->local_region_sums();
  // Elements blending toward arap (l > 0), summed in the same allreduce.
  const auto& interpolants = problem_.interpolants();
  sums.push_back(static_cast<double>(
      std::count_if(interpolants.begin(), interpolants.end(), [](Real l) { return l > 0; })));
  // Per obstacle: the force on it and the vertices touching it (4 sums).
  const ObstacleContact<Real>* contact = problem_.contact();
  const std::size_t contact_at = sums.size();
  if (contact) {
    const std::vector<double> c = contact->local_sums(state_.q.data());
    sums.insert(sums.end(), c.begin(), c.end());
  }
  BodyContact<Real>* barrier = problem_.body_contact();
  const BodyProjection<Real>* projection = problem_.body_projection();
  const bool pairs = barrier || projection;
  const std::size_t pairs_at = sums.size();
  const PairStats pair_stats = barrier      ? barrier->local_pair_stats(state_.q.data())
                               : projection ? projection->local_pair_stats()
                                            : PairStats{};
  if (pairs) sums.push_back(pair_stats.pairs);
  sums.insert(sums.end(), pair_stats.force.begin(), pair_stats.force.end());
  const std::size_t bodies_at = sums.size();
  if (!scene_.bodies.empty()) {
    const std::vector<double> b = local_body_sums(local_, vertex_bodies(local_), problem_.mass(),
                                                  state_.q.data(), state_.v.data());
    sums.insert(sums.end(), b.begin(), b.end());
  }
  reduction_.sum_in_place(sums);
  // Sums -> means and totals, in the order of measurement_names_.
  std::vector<double> values;
  const std::size_t nf = scene_.fixed.size();
  for (std::size_t r = 0; r < nf; ++r) {
    const double* s = &sums[7 * r];
    for (int i = 0; i < 3; ++i) values.push_back(s[3] > 0 ? s[i] / s[3] : 0.0);
    for (int i = 0; i < 3; ++i) values.push_back(s[4 + i]);
  }
  for (std::size_t r = 0; r < scene_.loads.size(); ++r) {
    const double* s = &sums[7 * nf + 4 * r];
    for (int i = 0; i < 3; ++i) values.push_back(s[3] > 0 ? s[i] / s[3] : 0.0);
    const std::array<double, 3> force = load_force(scene_.loads[r], state_.time);
    for (int i = 0; i < 3; ++i) values.push_back(force[i]);
  }
  if (scene_.material.conversion.enabled) values.push_back(sums[contact_at - 1]);
  if (contact) {
    values.insert(values.end(), sums.begin() + contact_at, sums.begin() + pairs_at);
    values.push_back(reduction_.max_of(contact->local_penetration(state_.q.data())));
  }
  if (pairs) {
    values.push_back(sums[pairs_at]);
    values.push_back(-reduction_.max_of(-pair_stats.least));
    if (projection) values.push_back(reduction_.max_of(projection->local_penetration()));
  }
  for (std::size_t b = 0; b < scene_.bodies.size(); ++b) {
    const double* s = &sums[bodies_at + kBodySums * b];
    for (int d = 0; d < 3; ++d) values.push_back(s[1 + d] / s[0]);  // centre of mass
    for (int d = 0; d < 3; ++d) values.push_back(s[4 + d] / s[0]);  // its velocity
    for (int d = 0; d < 3; ++d) values.push_back(s[4 + d]);         // momentum
    values.push_back(s[7]);
    if (pairs)
      for (int d = 0; d < 3; ++d) values.push_back(sums[pairs_at + 1 + 3 * b + d]);
  }
  return values;
}

template <class Real>
std::string Simulation<Real>::body_contact_report(double step_ms) {
  if (const BodyProjection<Real>* projection = problem_.body_projection()) {
    const auto& s = projection->seconds();
    const double total = s.search + s.sweeps;
    char text[256];
    std::snprintf(text, sizeof text,
                  "contact between bodies (projection) %.1f%% of step time on rank 0 (%.1f ms of "
                  "%.1f ms): pair search %.1f ms, sweeps %.1f ms; %ld step(s) ended with a pair "
                  "not separated",
                  step_ms > 0 ? 100 * 1e3 * total / step_ms : 0.0, 1e3 * total, step_ms,
                  1e3 * s.search, 1e3 * s.sweeps, projection->unresolved_steps());
    return text;
  }
  const BodyContact<Real>* contact = problem_.body_contact();
  if (!contact) return {};
  const auto& s = contact->seconds();
  const double total = s.search + s.ghosts + s.terms + s.guard;
  char text[256];
  std::snprintf(text, sizeof text,
                "contact between bodies %.1f%% of step time on rank 0 (%.1f ms of %.1f ms): pair "
                "search %.1f ms, ghosts %.1f ms, terms %.1f ms, guard %.1f ms; %ld path(s) not "
                "proven free of crossings, rolled back",
                step_ms > 0 ? 100 * 1e3 * total / step_ms : 0.0, 1e3 * total, step_ms,
                1e3 * s.search, 1e3 * s.ghosts, 1e3 * s.terms, 1e3 * s.guard,
                contact->paths_caught());
  return text;
}

template <class Real>
std::vector<double> Simulation<Real>::owned_positions() const {
  return std::vector<double>(state_.q.begin(), state_.q.begin() + 3 * local_.num_owned);
}

template <class Real>
std::vector<double> Simulation<Real>::owned_velocities() const {
  return std::vector<double>(state_.v.begin(), state_.v.begin() + 3 * local_.num_owned);
}

template class Simulation<double>;
template class Simulation<float>;

}  // namespace descent
