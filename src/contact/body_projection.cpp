#include "contact/body_projection.hpp"

#include <algorithm>
#include <cmath>

#include "common/timed.hpp"
#include "contact/contact_islands.hpp"
#include "contact/contact_scale.hpp"

namespace descent {

namespace {

// Passes over the paths q_t -> the corrected result (after the first), and
// sweeps per pass, at most; a constraint counts as met within kTolerance dh.
// The bounds only stop a pass that cannot converge (constraints that
// contradict each other, e.g. a vertex squeezed between two held bodies):
// unresolved_steps() counts them.
constexpr int kMaxPasses = 4;
constexpr int kMaxSweeps = 64;
constexpr double kTolerance = 0.1;
// A constraint violated by more than this share of the mean surface edge
// cannot be met by moving surface vertices alone without crushing the
// elements under them: its island's relative motion is cut first.
constexpr double kDeep = 0.25;

}  // namespace

template <class Real>
BodyProjection<Real>::BodyProjection(const LocalMesh& mesh, const Scene& scene, Halo<Real>& halo,
                                     EnergyReduction& reduction, const std::vector<Real>& mass,
                                     const std::vector<std::uint8_t>& fixed_axes)
    : mesh_(mesh),
      vertex_body_(vertex_bodies(mesh)),
      reduction_(reduction),
      halo_(mesh, halo),
      self_(scene.contact.self),
      mu_(scene.contact.friction),
      inv_h2_(1.0 / (scene.time.dt * scene.time.dt)),
      mass_(mass) {
  dh_ = descent::activation_distance(mesh, scene, reduction);
  deep_ = kDeep * mean_surface_edge(mesh, reduction);
  const index_t nv = mesh.num_vertices();
  inv_mass_.assign(nv, Real(0));
  for (index_t v = 0; v < nv; ++v)
    if (fixed_axes[v] == 0 && mass[v] > 0) inv_mass_[v] = Real(1) / mass[v];
  force_.assign(3 * static_cast<std::size_t>(mesh.num_bodies()), 0.0);
  // Bodies may start closer than dh, never touching.
  const std::vector<Real> rest(mesh.rest_positions.begin(), mesh.rest_positions.end());
  halo_.rebuild(rest.data(), dh_, inv_mass_);
  const ContactPairs pairs = find_contact_pairs(halo_, dh_, self_);
  require_bodies_apart(-reduction.max_of(-least_distance(pairs, halo_.positions())), dh_);
}

template <class Real>
double BodyProjection<Real>::least_distance(const ContactPairs& pairs,
                                            const std::vector<Real>& x) const {
  double least = 1e300;
  Real y[12];
  for_each_contact_pair(pairs, [&](PairKind kind, const std::array<index_t, 4>& v) {
    gather_pair(x, v, y);
    least = std::min(least, std::sqrt(static_cast<double>(pair_distance(kind, y, false).d2)));
  });
  return least;
}

template <class Real>
double BodyProjection<Real>::find_constraints(const Real* qt, const Real* q, bool first) {
  const Timed timed(seconds_.search);
  halo_.rebuild(qt, dh_, inv_mass_, q);
  start_ = halo_.positions();
  halo_.gather(q, current_);
  pairs_ = find_contact_pairs(halo_, dh_, self_, &current_);
  constraints_.clear();
  Real x0[12], x1[12];
  double violation = 0;
  for_each_contact_pair(pairs_, [&](PairKind kind, const std::array<index_t, 4>& v) {
    gather_pair(start_, v, x0);
    gather_pair(current_, v, x1);
    const PairConstraint<Real> plane = pair_constraint(kind, x0, x1, dh_);
    if (!plane.active) return;
    const double value = pair_constraint_value(plane, x1, dh_);
    violation = std::max(violation, -value);
    if (first) {
      // How far the solve took a side behind the pair's plane.
      penetration_ = std::max(penetration_, -(value + dh_));
      if (value < 0 && counted_here(halo_, v)) ++violated_pairs_;
    }
    constraints_.push_back({kind, v, plane});
  });
  // Per contact vertex the constraints it is in: complete for this rank's
  // vertices (every pair around them is here), the ghosts' from their
  // holders (3 per vertex, as gather() moves them).
  const index_t local = halo_.num_local();
  std::vector<Real> count(3 * static_cast<std::size_t>(mesh_.num_vertices()), Real(0));
  for (const Constraint& con : constraints_)
    for (index_t c : con.v)
      if (c < local) count[3 * static_cast<std::size_t>(halo_.local_vertex()[c])] += 1;
  std::vector<Real> counts;
  halo_.gather(count.data(), counts);
  relaxation_.clear();
  for (const Constraint& con : constraints_) {
    Real most = 1;
    for (index_t c : con.v) most = std::max(most, counts[3 * static_cast<std::size_t>(c)]);
    relaxation_.push_back(1.0 / static_cast<double>(most));
  }
  return reduction_.max_of(violation);
}

template <class Real>
double BodyProjection<Real>::sweep(Real* q) {
  const Timed timed(seconds_.sweeps);
  const index_t local = halo_.num_local();
  std::vector<double> moves(3 * static_cast<std::size_t>(local), 0.0);
  Real x[12], xt[12], inv_mass[4];
  double dx[12];
  // In the constraints' order, which is the pairs' global one: a shared
  // vertex sums the same moves in the same order on every sharer.
  for (std::size_t k = 0; k < constraints_.size(); ++k) {
    const Constraint& con = constraints_[k];
    gather_pair(current_, con.v, x);
    gather_pair(start_, con.v, xt);
    for (int j = 0; j < 4; ++j) inv_mass[j] = halo_.carried()[con.v[j]];
    project_pair(con.plane, x, xt, inv_mass, dh_, mu_, relaxation_[k], dx);
    for (int j = 0; j < 4; ++j)
      if (con.v[j] < local)
        for (int i = 0; i < 3; ++i) moves[3 * con.v[j] + i] += dx[3 * j + i];
  }
  for (index_t c = 0; c < local; ++c) {
    Real* y = q + 3 * static_cast<std::size_t>(halo_.local_vertex()[c]);
    for (int i = 0; i < 3; ++i) y[i] += static_cast<Real>(moves[3 * c + i]);
  }
  halo_.gather(q, current_);
  double violation = 0;
  for (const Constraint& con : constraints_) {
    gather_pair(current_, con.v, x);
    violation = std::max(violation, -pair_constraint_value(con.plane, x, dh_));
  }
  return reduction_.max_of(violation);
}

template <class Real>
void BodyProjection<Real>::cut_deep_islands(Real* q, const Real* qt) {
  const Timed timed(seconds_.search);
  const int num_bodies = mesh_.num_bodies();
  const std::vector<int>& body = halo_.body();
  // Per body: the deepest violation of its constraints and the least share
  // of its pairs' relative paths that keeps them dh apart, or half their
  // gap if they start nearer than 2 dh (negated, so both go through one
  // maximum), and the bodies the constraints link.
  std::vector<double> per_body(2 * static_cast<std::size_t>(num_bodies), -1.0);
  std::vector<std::pair<int, int>> links;
  Real x0[12], x1[12];
  for (const Constraint& con : constraints_) {
    gather_pair(start_, con.v, x0);
    gather_pair(current_, con.v, x1);
    const double violation = -pair_constraint_value(con.plane, x1, dh_);
    const double d0 = std::sqrt(static_cast<double>(pair_distance(con.kind, x0, false).d2));
    const double f = pair_path_fraction(con.kind, x0, x1, d0, d0 > 2 * dh_ ? dh_ : 0.5 * d0);
    for (index_t c : con.v) {
      per_body[2 * body[c]] = std::max(per_body[2 * body[c]], violation);
      per_body[2 * body[c] + 1] = std::max(per_body[2 * body[c] + 1], -f);
      if (body[c] != body[con.v[0]]) links.emplace_back(body[con.v[0]], body[c]);
    }
  }
  const std::vector<int> island = contact_islands(num_bodies, links, reduction_);
  reduction_.max_in_place(per_body.data(), 2 * num_bodies);
  // Per island: whether it is cut and by what fraction, and its mass and
  // the mass-weighted move of its free vertices (owned ones summed over
  // ranks).
  std::vector<double> fraction(static_cast<std::size_t>(num_bodies), 1.0);
  std::vector<char> deep(static_cast<std::size_t>(num_bodies), 0);
  for (int b = 0; b < num_bodies; ++b) {
    fraction[island[b]] = std::min(fraction[island[b]], -per_body[2 * b + 1]);
    if (per_body[2 * b] > deep_) deep[island[b]] = 1;
  }
  std::vector<double> moved(4 * static_cast<std::size_t>(num_bodies), 0.0);
  for (index_t v = 0; v < mesh_.num_owned; ++v) {
    if (inv_mass_[v] == Real(0)) continue;
    double* m = &moved[4 * static_cast<std::size_t>(island[vertex_body_[v]])];
    m[0] += static_cast<double>(mass_[v]);
    for (int i = 0; i < 3; ++i)
      m[1 + i] += static_cast<double>(mass_[v]) *
                  static_cast<double>(q[3 * static_cast<std::size_t>(v) + i] -
                                      qt[3 * static_cast<std::size_t>(v) + i]);
  }
  reduction_.sum_in_place(moved);
  for (index_t v = 0; v < mesh_.num_vertices(); ++v) {
    const int k = island[vertex_body_[v]];
    if (!deep[k] || inv_mass_[v] == Real(0) || !(moved[4 * k] > 0)) continue;
    for (int i = 0; i < 3; ++i) {
      const std::size_t j = 3 * static_cast<std::size_t>(v) + i;
      const double common = moved[4 * k + 1 + i] / moved[4 * k];
      const double d = static_cast<double>(q[j] - qt[j]);
      q[j] = static_cast<Real>(static_cast<double>(qt[j]) + common + fraction[k] * (d - common));
    }
  }
}

template <class Real>
void BodyProjection<Real>::project(Real* q, const Real* qt) {
  penetration_ = 0;
  violated_pairs_ = 0;
  std::fill(force_.begin(), force_.end(), 0.0);
  const double tolerance = kTolerance * dh_;
  // A step whose result violates nothing is left as it is.
  double violation = find_constraints(qt, q, true);
  if (violation <= tolerance) return;
  const index_t nv = mesh_.num_vertices();
  const std::vector<Real> before(q, q + 3 * static_cast<std::size_t>(nv));
  // Each pass finds the constraints over the paths to the result as it is
  // now, so the last one found checks the sweeps before it.
  for (int pass = 0;; ++pass) {
    if (pass > 0) violation = find_constraints(qt, q, false);
    if (violation <= tolerance) break;
    if (pass == 0 && violation > deep_) {
      cut_deep_islands(q, qt);
      violation = find_constraints(qt, q, false);
      if (violation <= tolerance) break;
    }
    if (pass == kMaxPasses) {
      ++unresolved_steps_;
      break;
    }
    for (int s = 0; s < kMaxSweeps && violation > tolerance; ++s) violation = sweep(q);
  }
  // The force the pairs put on each body: m dx / h^2 over its owned vertices.
  for (index_t v = 0; v < mesh_.num_owned; ++v)
    for (int i = 0; i < 3; ++i) {
      const std::size_t k = 3 * static_cast<std::size_t>(v) + i;
      force_[3 * static_cast<std::size_t>(vertex_body_[v]) + i] +=
          static_cast<double>(mass_[v]) * static_cast<double>(q[k] - before[k]) * inv_h2_;
    }
}

template <class Real>
PairStats BodyProjection<Real>::local_pair_stats() const {
  PairStats stats;
  stats.pairs = static_cast<double>(violated_pairs_);
  stats.least = least_distance(pairs_, current_);
  stats.force = force_;
  return stats;
}

template class BodyProjection<double>;
template class BodyProjection<float>;

}  // namespace descent
