#include "run_case.hpp"

#include <algorithm>
#include <cmath>

#include "app/simulation.hpp"
#include "common/error.hpp"
#include "gather_positions.hpp"
#include "kernels/svd3.hpp"
#include "kernels/tet.hpp"
#include "mesh_extent.hpp"

namespace descent::extremes {
namespace {

template <class Real>
bool all_finite(const std::vector<Real>& values) {
  return std::all_of(values.begin(), values.end(), [](Real x) { return std::isfinite(x); });
}

// The prediction ChebyshevDescent starts a step from (paper 1, §4.4),
// written again here so the energy check below does not trust the solver:
// q_t + h (w_v v + w_a (v - v_prev)), held dofs where their motion puts them.
template <class Real>
std::vector<Real> initial_guess(const LocalProblem<Real>& problem, const SolverSpec& spec,
                                const BodyState<Real>& s, double t_next) {
  const Real h = problem.dt();
  const Real w_velocity = spec.init == "position" ? Real(0) : Real(1);
  const Real w_acceleration =
      spec.init == "constant_acceleration" ? static_cast<Real>(spec.eta) : Real(0);
  std::vector<Real> q(s.q.size());
  for (std::size_t k = 0; k < q.size(); ++k)
    q[k] = s.q[k] + h * (w_velocity * s.v[k] + w_acceleration * (s.v[k] - s.v_prev[k]));
  problem.hold_fixed(t_next, q.data());
  return q;
}

struct Inversion {
  double min_det = std::numeric_limits<double>::infinity();
  double min_sigma = std::numeric_limits<double>::infinity();
  long inverted = 0;
};

// Over this rank's tets (each global tet lives on exactly one rank), in
// double whatever Real, from the rest positions of the local mesh.
template <class Real>
Inversion local_inversion(const LocalMesh& mesh, const std::vector<Real>& q) {
  Inversion inv;
  const auto& x = mesh.rest_positions;
  for (index_t t = 0; t < mesh.num_tets(); ++t) {
    Vec3<double> r[4], d[4];
    for (int a = 0; a < 4; ++a) {
      const std::size_t v = 3 * static_cast<std::size_t>(mesh.tets[4 * t + a]);
      r[a] = {x[v], x[v + 1], x[v + 2]};
      d[a] = {double(q[v]), double(q[v + 1]), double(q[v + 2])};
    }
    const TetRest<double> rest = tet_rest(r[0], r[1], r[2], r[3]);
    const Mat3<double> f = deformation_gradient(d[0], d[1], d[2], d[3], rest.dm_inv);
    const double j = det(f);
    inv.min_det = std::min(inv.min_det, j);
    inv.min_sigma = std::min(inv.min_sigma, svd3(f).sigma[2]);
    inv.inverted += j <= 0 ? 1 : 0;
  }
  return inv;
}

// Largest |sigma - 1| over all tets of `mesh` at global positions x.
double worst_stretch(const Mesh& mesh, const std::vector<double>& x) {
  double worst = 0;
  for (index_t t = 0; t < mesh.num_tets(); ++t) {
    Vec3<double> r[4], d[4];
    for (int a = 0; a < 4; ++a) {
      const std::size_t v = 3 * static_cast<std::size_t>(mesh.tets[4 * t + a]);
      r[a] = {mesh.positions[v], mesh.positions[v + 1], mesh.positions[v + 2]};
      d[a] = {x[v], x[v + 1], x[v + 2]};
    }
    const TetRest<double> rest = tet_rest(r[0], r[1], r[2], r[3]);
    const Svd3<double> s = svd3(deformation_gradient(d[0], d[1], d[2], d[3], rest.dm_inv));
    for (double sigma : s.sigma) worst = std::max(worst, std::abs(sigma - 1.0));
  }
  return worst;
}

// "rank R: <culprit> = value" from the lowest rank whose scan found one.
std::string gather_failure(MPI_Comm comm, const NonFiniteSite& site) {
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  // [reporting rank or size, kind, id, value] per rank
  const double mine[4] = {site.found() ? double(rank) : double(size), double(int(site.kind)),
                          double(site.id), site.value};
  std::vector<double> all(4 * static_cast<std::size_t>(size));
  MPI_Allgather(mine, 4, MPI_DOUBLE, all.data(), 4, MPI_DOUBLE, comm);
  for (int r = 0; r < size; ++r)
    if (all[4 * r] < size)
      return detail::concat("rank ", r, ": ", describe(NonFiniteSite::Kind(int(all[4 * r + 1]))),
                            " ", static_cast<long long>(all[4 * r + 2]), " = ", all[4 * r + 3]);
  return "no rank names a culprit (the sum overflowed)";
}

}  // namespace

template <class Real>
Result run_case(MPI_Comm comm, const Case& c, int iterations, const std::string& method) {
  Scene scene = c.scene;
  if (iterations > 0) scene.solver.iterations = iterations;
  if (!method.empty()) scene.solver.method = method;
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  Result result;
  result.bbox_diagonal = testing::bounding_box_diagonal(c.mesh);
  Simulation<Real> sim(comm, scene, c.mesh);
  const LocalProblem<Real>& problem = sim.problem();
  if (c.start != Start::rest) sim.set_positions(start_positions(c));
  if (c.velocity != std::array<double, 3>{0.0, 0.0, 0.0}) {
    // Through a checkpoint, the one way in for a velocity; held axes stay at rest.
    Checkpoint state = sim.checkpoint(0);
    for (std::size_t v = 0; v < state.v.size() / 3; ++v)
      for (int i = 0; i < 3; ++i) {
        const bool held = problem.fixed_axes()[v] & (1u << i);
        state.v[3 * v + i] = state.v_prev[3 * v + i] = held ? 0.0 : c.velocity[i];
      }
    sim.restore(state);
  }
  const bool check_energy = !problem.energy_changes_within_step();
  result.energy_checked = check_energy;

  const double start = MPI_Wtime();
  for (int frame = 1; frame <= c.frames; ++frame) {
    const BodyState<Real> before = sim.state();
    const double t_next = before.time + scene.time.dt;
    const StepStats step = sim.step();
    ++result.steps;
    result.iterations += step.iterations;
    result.rollbacks += step.rollbacks;
    result.nonfinite_rollbacks += step.nonfinite_rollbacks;
    result.stalled_steps += step.stalled ? 1 : 0;
    result.final_alpha = step.alpha;
    if (!step.finite) {
      result.finite = false;
      result.failed_frame = frame;
      result.failure = gather_failure(comm, step.failed_at);
      break;
    }
    if (check_energy) {
      const std::vector<Real> guess = initial_guess(problem, scene.solver, before, t_next);
      std::vector<Real> y(before.q.size());
      for (std::size_t k = 0; k < y.size(); ++k) y[k] = before.q[k] + problem.dt() * before.v[k];
      const Energy e_new = problem.local_energy(sim.state().q.data(), y.data(), before.q.data());
      const Energy e_guess = problem.local_energy(guess.data(), y.data(), before.q.data());
      // [new, |new|, guess, |guess|, non-finite new, non-finite guess]
      double sums[6] = {e_new.value,
                        e_new.magnitude,
                        e_guess.value,
                        e_guess.magnitude,
                        std::isfinite(e_new.value) ? 0.0 : 1.0,
                        std::isfinite(e_guess.value) ? 0.0 : 1.0};
      MPI_Allreduce(MPI_IN_PLACE, sums, 6, MPI_DOUBLE, MPI_SUM, comm);
      // A non-finite guess is beaten by any finite state.
      if (sums[5] == 0) {
        // The solver accepts a check whose energy exceeds the last accepted
        // one by at most the tolerance (its round-off, at least the noise
        // floor at rest), so over a step the bound is the sum over its
        // accepted checks (checks minus rollbacks).
        const int interval = scene.solver.check_interval;
        const int checks = (step.iterations + interval - 1) / interval;
        const int accepted = std::max(1, checks - step.rollbacks);
        const double tolerance =
            accepted * std::max(1024 * std::numeric_limits<Real>::epsilon() * sums[1],
                                problem.energy_noise_floor());
        const double rise =
            sums[4] > 0 ? std::numeric_limits<double>::infinity() : sums[0] - sums[2];
        const double ratio = tolerance > 0 ? rise / tolerance : (rise > 0 ? 1e300 : 0.0);
        result.worst_rise_ratio = std::max(result.worst_rise_ratio, ratio);
        result.energy_rises += ratio > 1 ? 1 : 0;
      }
    }
    Inversion inv = local_inversion(sim.local_mesh(), sim.state().q);
    double mins[2] = {inv.min_det, inv.min_sigma};
    long count = inv.inverted;
    MPI_Allreduce(MPI_IN_PLACE, mins, 2, MPI_DOUBLE, MPI_MIN, comm);
    MPI_Allreduce(MPI_IN_PLACE, &count, 1, MPI_LONG, MPI_SUM, comm);
    // NaN compares false: a NaN det leaves min_det as it was; finite says so.
    result.min_det = std::min(result.min_det, mins[0]);
    result.min_sigma = std::min(result.min_sigma, mins[1]);
    result.max_inverted = std::max(result.max_inverted, count);
    result.final_inverted = count;
  }
  result.wall_s = MPI_Wtime() - start;
  int finite = all_finite(sim.state().q) && all_finite(sim.state().v) ? 1 : 0;
  MPI_Allreduce(MPI_IN_PLACE, &finite, 1, MPI_INT, MPI_MIN, comm);
  result.state_finite = finite == 1;
  result.finite = result.finite && result.state_finite;
  result.positions = testing::gather_positions(comm, sim, c.mesh.num_vertices());
  if (rank == 0 && c.recovers && result.finite)
    result.worst_stretch = worst_stretch(c.mesh, result.positions);
  return result;
}

double relative_distance(const Result& a, const Result& reference) {
  double worst = 0;
  for (std::size_t k = 0; k < a.positions.size() && k < reference.positions.size(); ++k)
    worst = std::max(worst, std::abs(a.positions[k] - reference.positions[k]));
  return worst / a.bbox_diagonal;
}

template Result run_case<double>(MPI_Comm, const Case&, int, const std::string&);
template Result run_case<float>(MPI_Comm, const Case&, int, const std::string&);

}  // namespace descent::extremes
