#include "contact/body_contact.hpp"

#include <algorithm>
#include <cmath>

#include "common/timed.hpp"
#include "contact/contact_islands.hpp"
#include "contact/contact_scale.hpp"
#include "kernels/pair_contact.hpp"

namespace descent {

namespace {

double length(const double* d) { return std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]); }

}  // namespace

template <class Real>
BodyContact<Real>::BodyContact(const LocalMesh& mesh, const Scene& scene, Halo<Real>& halo,
                               EnergyReduction& reduction, const std::vector<Real>& mass,
                               const std::vector<Real>& rest_diagonal, double inv_h2)
    : mesh_(mesh),
      vertex_body_(vertex_bodies(mesh)),
      reduction_(reduction),
      halo_(mesh, halo),
      self_(scene.contact.self),
      mu_(scene.contact.friction),
      eps_h_(scene.contact.smoothing_velocity * scene.time.dt) {
  dh_ = descent::activation_distance(mesh, scene, reduction);
  kappa_.assign(mesh.num_vertices(), Real(0));
  for (index_t v = 0; v < mesh.num_vertices(); ++v)
    kappa_[v] =
        vertex_stiffness(scene, mass[v], inv_h2, &rest_diagonal[3 * static_cast<std::size_t>(v)]);
  // The mollifier's threshold of nearly parallel edges, IPC's 1e-3 |u|^2
  // |v|^2 with the mean surface edge for both (the same on every rank).
  const double mean_edge = mean_surface_edge(mesh, reduction);
  eps_ = 1e-3 * std::pow(mean_edge, 4);
  cap_max_ = dh_ + 0.5 * mean_edge;
  drift_seen_.assign(halo_.num_local(), 0.0);

  // Bodies may start closer than dh, never touching.
  std::vector<Real> rest(mesh.rest_positions.begin(), mesh.rest_positions.end());
  halo_.rebuild(rest.data(), dh_, kappa_);
  pairs_ = find_contact_pairs(halo_, dh_, self_);
  track_from_here();
  require_bodies_apart(-reduction.max_of(-local_pair_stats(rest.data()).least), dh_);
}

template <class Real>
void BodyContact<Real>::pull_back(const Real* qt, Real* q) {
  const Timed timed(seconds_.search);
  const index_t nv = mesh_.num_vertices();
  qt_.assign(qt, qt + 3 * static_cast<std::size_t>(nv));
  // A new step starts with the relative guard.
  safe_ = false;
  verify_paths_ = crossing_ = false;
  // The pairs that may come within dh along the moves q - q_t, each scaled
  // by any fraction: a pair not among them keeps beyond dh (no barrier,
  // no crossing) however the bodies' moves are scaled.
  halo_.rebuild(qt, dh_, kappa_, q);
  std::vector<Real> guess;
  halo_.gather(q, guess);
  pairs_ = find_contact_pairs(halo_, dh_, self_, &guess);
  const std::vector<Real>& start = halo_.positions();
  const std::vector<int>& body = halo_.body();
  const int num_bodies = mesh_.num_bodies();
  // Per body the least share of its pairs' paths that keeps half their gap
  // (negated, to go through the maximum), and the bodies the pairs link.
  std::vector<double> least(static_cast<std::size_t>(num_bodies), -1.0);
  std::vector<std::pair<int, int>> links;
  for_each_path(
      start, guess, [](std::size_t, const std::array<index_t, 4>&) { return false; },
      [&](PairKind kind, const std::array<index_t, 4>& v, const Real* x0, const Real* x1) {
        const double d = std::sqrt(static_cast<double>(pair_distance(kind, x0, false).d2));
        const double f = pair_path_fraction(kind, x0, x1, d, 0.5 * d);
        for (int j = 0; j < 4; ++j) {
          least[body[v[j]]] = std::max(least[body[v[j]]], -f);
          if (body[v[j]] != body[v[0]]) links.emplace_back(body[v[0]], body[v[j]]);
        }
      });
  const std::vector<int> island = contact_islands(num_bodies, links, reduction_);
  reduction_.max_in_place(least.data(), num_bodies);
  // Each island's move is scaled by its bodies' least fraction: every pair
  // then travels its own path cut short, keeping half its gap.
  std::vector<double> fraction(static_cast<std::size_t>(num_bodies), 1.0);
  for (int b = 0; b < num_bodies; ++b)
    fraction[island[b]] = std::min(fraction[island[b]], -least[b]);
  for (index_t v = 0; v < nv; ++v) {
    const Real f = static_cast<Real>(fraction[island[vertex_body_[v]]]);
    if (f < Real(1))
      for (int i = 0; i < 3; ++i) {
        const std::size_t k = 3 * static_cast<std::size_t>(v) + i;
        q[k] = qt[k] + f * (q[k] - qt[k]);
      }
  }
}

template <class Real>
void BodyContact<Real>::rebuild_here(const Real* q) {
  const Timed timed(seconds_.search);
  // Each surface vertex's drift cap. Between bodies, dh plus half the mean
  // surface edge: pairs lie only where bodies come near each other, and a
  // wide cap means few searches. With contact.self, four times the largest
  // drift the checks saw of the vertex since the last search (its next
  // search is then due at twice that), within [dh, dh plus half the mean
  // surface edge]: the wide cap for all gave every pair of a finely meshed
  // surface's second ring (1.7M pairs, 107 per surface vertex, on the
  // shared bunny and dragon) to every iteration.
  // The wide cap, the same everywhere, costs no message; the adaptive
  // ones one allreduce (the halo's reach) and one gather (the ghosts').
  std::vector<Real> caps;  // with contact.self: 3 per local vertex, the cap in each
  cap_ = cap_max_;
  if (self_) {
    caps.assign(3 * static_cast<std::size_t>(mesh_.num_vertices()), Real(0));
    double largest = dh_;
    for (index_t c = 0; c < halo_.num_local(); ++c) {
      const double cap = std::clamp(4 * drift_seen_[c], dh_, cap_max_);
      largest = std::max(largest, cap);
      for (int i = 0; i < 3; ++i)
        caps[3 * static_cast<std::size_t>(halo_.local_vertex()[c]) + i] = static_cast<Real>(cap);
    }
    cap_ = reduction_.max_of(largest);
  }
  std::fill(drift_seen_.begin(), drift_seen_.end(), 0.0);
  halo_.rebuild(q, dh_ + 2 * cap_, kappa_);
  if (self_) {
    // Each ghost's cap from its holder, which guards its drift by it.
    std::vector<Real> gathered;
    halo_.gather(caps.data(), gathered);
    caps_.resize(halo_.num_vertices());
    for (std::size_t c = 0; c < caps_.size(); ++c) caps_[c] = static_cast<double>(gathered[3 * c]);
  } else {
    caps_.assign(halo_.num_vertices(), cap_max_);
  }
  pairs_ = find_contact_pairs<Real>(halo_, dh_, self_, nullptr, &caps_);
  // Without a pair on any rank no gap can close below dh before the next
  // search (the drift cap), so the iterations skip the guard's exchange.
  const bool here = !pairs_.vertex_triangle.empty() || !pairs_.edge_edge.empty();
  any_pairs_ = reduction_.max_of(here ? 1.0 : 0.0) > 0;
  track_from_here();
  if (!(mu_ > 0)) return;
  // Friction lags from the step start (the ghosts' too).
  halo_.gather(qt_.data(), start_);
  const std::vector<Real>& kappa = halo_.carried();
  std::size_t pair = 0;
  Real xt[12];
  for (int kind = 0; kind < 2; ++kind)
    for (const auto& v : kind == 0 ? pairs_.vertex_triangle : pairs_.edge_edge) {
      Real k = 0;
      for (int j = 0; j < 4; ++j) {
        k += kappa[v[j]] / Real(4);
        for (int i = 0; i < 3; ++i) xt[3 * j + i] = start_[3 * static_cast<std::size_t>(v[j]) + i];
      }
      lags_[pair++] = pair_friction_lag(kind == 0 ? PairKind::vertex_triangle : PairKind::edge_edge,
                                        xt, k, static_cast<Real>(dh_), static_cast<Real>(mu_));
    }
}

template <class Real>
bool BodyContact<Real>::needs_rebuild(const Real* q) {
  bool drifted = false;
  for (index_t c = 0; c < halo_.num_local(); ++c) {
    const Real* x = q + 3 * static_cast<std::size_t>(halo_.local_vertex()[c]);
    double d[3];
    for (int i = 0; i < 3; ++i) d[i] = static_cast<double>(x[i] - anchor_[3 * c + i]);
    const double drift = length(d);
    drift_seen_[c] = std::max(drift_seen_[c], drift);
    drifted = drifted || drift > 0.5 * caps_[c];
  }
  return drifted;
}

template <class Real>
void BodyContact<Real>::track_from_here() {
  anchor_ = halo_.positions();
  last_ = anchor_;
  nearest_.assign(halo_.num_vertices(), Real(0));
  travel_.assign(halo_.num_vertices(), 0.0);
  const std::size_t np = pairs_.vertex_triangle.size() + pairs_.edge_edge.size();
  checked_distance_.assign(np, 0.0);
  checked_travel_.assign(np, -1.0);  // never evaluated
  lags_.assign(np, PairFrictionLag<Real>{});
}

template <class Real>
PairTerms<Real> BodyContact<Real>::terms_of(PairKind kind, std::size_t pair,
                                            const std::array<index_t, 4>& v, const Real* x,
                                            Real kappa, PairHessian hessian) const {
  PairTerms<Real> t =
      pair_barrier(kind, x, kappa, static_cast<Real>(dh_), static_cast<Real>(eps_), hessian);
  if (lags_[pair].mu_lambda > Real(0)) {
    Real xt[12];
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 3; ++i) xt[3 * j + i] = start_[3 * static_cast<std::size_t>(v[j]) + i];
    add_pair_friction(lags_[pair], static_cast<Real>(eps_h_), x, xt, hessian, t);
  }
  return t;
}

template <class Real>
Real BodyContact<Real>::gather_pair_with_stiffness(const std::vector<Real>& p,
                                                   const std::array<index_t, 4>& v, Real* x) const {
  gather_pair(p, v, x);
  const std::vector<Real>& kappa = halo_.carried();
  Real k = 0;
  for (int j = 0; j < 4; ++j) k += kappa[v[j]] / Real(4);
  return k;
}

template <class Real>
template <class Visit>
void BodyContact<Real>::for_each_pair(bool skip_far, Visit&& visit) {
  const std::vector<Real>& p = halo_.positions();
  Real x[12];
  std::size_t index = 0;
  for (int kind = 0; kind < 2; ++kind)
    for (const auto& v : kind == 0 ? pairs_.vertex_triangle : pairs_.edge_edge) {
      const std::size_t pair = index++;
      double travel = 0;
      for (int j = 0; j < 4; ++j) travel += travel_[v[j]];
      if (skip_far && checked_travel_[pair] >= 0 && !(lags_[pair].mu_lambda > Real(0))) {
        // Its distance has fallen by at most its vertices' travel since it
        // was evaluated: still beyond dh, it has no term.
        const double bound = checked_distance_[pair] - (travel - checked_travel_[pair]);
        if (bound > dh_) {
          for (index_t c : v)
            if (c < halo_.num_local())
              nearest_[c] = std::min(nearest_[c], static_cast<Real>(bound));
          continue;
        }
      }
      const Real k = gather_pair_with_stiffness(p, v, x);
      const PairKind pair_kind = kind == 0 ? PairKind::vertex_triangle : PairKind::edge_edge;
      const double distance = visit(pair_kind, v, x, k, pair);
      if (distance >= 0) {
        checked_distance_[pair] = distance;
        checked_travel_[pair] = travel;
      }
    }
}

template <class Real>
void BodyContact<Real>::add_gradient(const Real* q, Real* partial, int width, Real* diag,
                                     const VertexTerms<Real>& terms, const Real* mass) {
  update_ghosts(q);
  const Timed timed(seconds_.terms);
  const index_t local = halo_.num_local();
  const auto& local_vertex = halo_.local_vertex();
  std::vector<Real>& contact_diag = contact_diagonal_;
  contact_diag.assign(3 * static_cast<std::size_t>(local), Real(0));
  std::fill(nearest_.begin(), nearest_.end(), Real(INFINITY));
  for_each_pair(true, [&](PairKind kind, const std::array<index_t, 4>& v, const Real* x, Real kappa,
                          std::size_t pair) {
    const PairTerms<Real> t = terms_of(kind, pair, v, x, kappa, PairHessian::psd);
    for (int j = 0; j < 4; ++j) {
      const index_t c = v[j];
      if (c >= local) continue;
      nearest_[c] = std::min(nearest_[c], t.distance);
      if (t.energy == Real(0)) continue;
      Real* out = partial + width * static_cast<std::size_t>(local_vertex[c]);
      for (int i = 0; i < 3; ++i) {
        out[i] += t.grad[3 * j + i];
        // Gershgorin: the row's absolute sum dominates the pair's block.
        Real row = 0;
        for (int col = 0; col < 12; ++col) row += std::abs(t.hess[12 * (3 * j + i) + col]);
        contact_diag[3 * c + i] += row;
      }
    }
    return static_cast<double>(t.distance);
  });
  for (index_t c = 0; c < local; ++c) {
    const index_t v = local_vertex[c];
    for (int i = 0; i < 3; ++i) {
      const Real d = contact_diag[3 * c + i];
      if (width == 6) partial[6 * static_cast<std::size_t>(v) + 3 + i] += d;
      if (diag && d > Real(0)) {
        const Real least = dof_diagonal(terms, mass[v], d, Real(0));
        if (diag[3 * v + i] < least) diag[3 * v + i] = least;
      }
    }
  }
}

template <class Real>
double BodyContact<Real>::local_energy(const Real* q) {
  update_ghosts(q);
  if (crossing_) {
    // A path since the last check may have crossed: an energy no check
    // accepts, so the check rolls back (the sum is not finite on any rank).
    crossing_ = false;
    return INFINITY;
  }
  const Timed timed(seconds_.terms);
  double sum = 0;
  for_each_pair(true, [&](PairKind kind, const std::array<index_t, 4>& v, const Real* x, Real kappa,
                          std::size_t pair) {
    if (counted_here(halo_, v))
      sum += static_cast<double>(terms_of(kind, pair, v, x, kappa, PairHessian::none).energy);
    return -1.0;
  });
  return sum;
}

template <class Real>
double BodyContact<Real>::measured_energy(const Real* q) const {
  std::vector<Real> p;
  halo_.gather(q, p);
  double sum = 0;
  Real x[12];
  std::size_t pair = 0;
  for_each_contact_pair(pairs_, [&](PairKind kind, const std::array<index_t, 4>& v) {
    const std::size_t index = pair++;
    if (!counted_here(halo_, v)) return;
    const Real k = gather_pair_with_stiffness(p, v, x);
    sum += static_cast<double>(terms_of(kind, index, v, x, k, PairHessian::none).energy);
  });
  return sum;
}

template <class Real>
void BodyContact<Real>::add_hessian_product(const Real* q, const Real* v, Real* out,
                                            PairHessian hessian) {
  update_ghosts(q);
  {
    const Timed timed(seconds_.ghosts);
    halo_.gather(v, gathered_);
  }
  const Timed timed(seconds_.terms);
  const index_t local = halo_.num_local();
  for_each_pair(true, [&](PairKind kind, const std::array<index_t, 4>& c, const Real* x, Real kappa,
                          std::size_t pair) {
    const PairTerms<Real> t = terms_of(kind, pair, c, x, kappa, hessian);
    if (t.energy == Real(0)) return -1.0;
    for (int j = 0; j < 4; ++j) {
      if (c[j] >= local) continue;
      Real* o = out + 3 * static_cast<std::size_t>(halo_.local_vertex()[c[j]]);
      for (int i = 0; i < 3; ++i) {
        Real s = 0;
        for (int l = 0; l < 4; ++l)
          for (int m = 0; m < 3; ++m)
            s += t.hess[12 * (3 * j + i) + 3 * l + m] *
                 gathered_[3 * static_cast<std::size_t>(c[l]) + m];
        o[i] += s;
      }
    }
    return -1.0;
  });
}

template <class Real>
void BodyContact<Real>::add_hessian_diagonal(const Real* q, Real* diag, const std::uint8_t* fixed) {
  update_ghosts(q);
  const Timed timed(seconds_.terms);
  const index_t local = halo_.num_local();
  for_each_pair(true, [&](PairKind kind, const std::array<index_t, 4>& c, const Real* x, Real kappa,
                          std::size_t pair) {
    const PairTerms<Real> t = terms_of(kind, pair, c, x, kappa, PairHessian::psd);
    if (t.energy == Real(0)) return -1.0;
    for (int j = 0; j < 4; ++j) {
      if (c[j] >= local) continue;
      const std::size_t v = static_cast<std::size_t>(halo_.local_vertex()[c[j]]);
      for (int i = 0; i < 3; ++i)
        if (!(fixed[v] & (1u << i))) diag[3 * v + i] += t.hess[13 * (3 * j + i)];
    }
    return -1.0;
  });
}

template <class Real>
double BodyContact<Real>::path_fraction(const Real* q, const Real* dq) {
  update_ghosts(q);
  std::vector<Real> moves;
  {
    const Timed timed(seconds_.ghosts);
    halo_.gather(dq, moves);
  }
  const Timed timed(seconds_.guard);
  const std::vector<Real>& p = halo_.positions();
  double fraction = 1;
  Real x0[12], x1[12], d[12];
  for_each_contact_pair(pairs_, [&](PairKind kind, const std::array<index_t, 4>& v) {
    gather_pair(p, v, x0);
    gather_pair(moves, v, d);
    for (int k = 0; k < 12; ++k) x1[k] = x0[k] + d[k];
    const double d0 = std::sqrt(static_cast<double>(pair_distance(kind, x0, false).d2));
    fraction =
        std::min(fraction, pair_path_fraction(kind, x0, x1, d0, pair_kept_gap<Real>(d0, dh_)));
  });
  // The drift cap, by the triangle inequality: |q + s dq - anchor| <= cap.
  for (index_t c = 0; c < halo_.num_local(); ++c) {
    double from[3], move[3];
    for (int i = 0; i < 3; ++i) {
      from[i] = static_cast<double>(p[3 * c + i] - anchor_[3 * c + i]);
      move[i] = static_cast<double>(moves[3 * c + i]);
    }
    const double room = caps_[c] - length(from), travel = length(move);
    if (travel > room) fraction = std::min(fraction, room > 0 ? room / travel : 0.0);
  }
  return fraction;
}

template <class Real>
void BodyContact<Real>::guard(Real* q, Real* q_next, const std::uint8_t* fixed) {
  cut_move(q, q_next, fixed);
  for (index_t c = 0; c < halo_.num_local(); ++c) {
    const std::size_t v = static_cast<std::size_t>(halo_.local_vertex()[c]);
    if (!fixed[v] && cut_[c] < 1)
      for (int i = 0; i < 3; ++i) q[3 * v + i] = q_next[3 * v + i];
  }
}

template <class Real>
void BodyContact<Real>::guard_proven(const Real* q, Real* q_next, const std::uint8_t* fixed) {
  cut_move(q, q_next, fixed);
  update_ghosts(q_next);
  // One allreduce for both: 2 where a path is not proven, 1 where a move
  // was cut.
  const bool cut_here = std::any_of(cut_.begin(), cut_.end(), [](double f) { return f < 1; });
  const double worst = reduction_.max_of(crossing_ ? 2.0 : cut_here ? 1.0 : 0.0);
  crossing_ = false;
  moves_cut_ = worst > 0;
  if (worst < 2) return;
  // Only the path guard leaves a move unproven, and it kept each contact
  // vertex's proposal in proposed_: the move is made again from there.
  for (index_t c = 0; c < halo_.num_local(); ++c) {
    const std::size_t v = static_cast<std::size_t>(halo_.local_vertex()[c]);
    for (int i = 0; i < 3; ++i) q_next[3 * v + i] = proposed_[3 * c + i];
  }
  safe_ = true;
  cut_move(q, q_next, fixed);
}

template <class Real>
void BodyContact<Real>::cut_move(const Real* q, Real* q_next, const std::uint8_t* fixed) {
  if (safe_) {
    cut_by_nearest_gap(q, q_next, fixed);
  } else if (any_pairs_) {
    cut_by_pair_paths(q_next, fixed);
  } else {
    cut_.assign(halo_.num_local(), 1.0);
  }
  const Timed timed(seconds_.guard);
  for (index_t c = 0; c < halo_.num_local(); ++c) {
    const std::size_t v = static_cast<std::size_t>(halo_.local_vertex()[c]);
    if (fixed[v]) continue;  // held vertices follow their motion
    // The drift cap about where the pairs were found.
    double to[3];
    for (int i = 0; i < 3; ++i) to[i] = static_cast<double>(q_next[3 * v + i] - anchor_[3 * c + i]);
    const double drift = length(to);
    if (drift > caps_[c]) {
      for (int i = 0; i < 3; ++i)
        q_next[3 * v + i] = static_cast<Real>(anchor_[3 * c + i] + caps_[c] / drift * to[i]);
      cut_[c] = 0;
    }
  }
}

template <class Real>
void BodyContact<Real>::cut_by_pair_paths(Real* q_next, const std::uint8_t* fixed) {
  {
    const Timed timed(seconds_.ghosts);
    halo_.gather(q_next, proposed_);
  }
  const Timed timed(seconds_.guard);
  const std::vector<Real>& p = halo_.positions();  // q's, as add_gradient left them
  const index_t local = halo_.num_local();
  cut_.assign(local, 1.0);
  for_each_path(
      p, proposed_,
      [&](std::size_t pair, const std::array<index_t, 4>& v) {
        const double bound = gap_bound(pair, v);
        return moved(v) < bound - pair_kept_gap<Real>(bound, dh_);
      },
      [&](PairKind kind, const std::array<index_t, 4>& v, const Real* x0, const Real* x1) {
        const double d = std::sqrt(static_cast<double>(pair_distance(kind, x0, false).d2));
        const double f = pair_path_fraction(kind, x0, x1, d, pair_kept_gap<Real>(d, dh_));
        for (index_t c : v)
          if (c < local) cut_[c] = std::min(cut_[c], f);
      });
  for (index_t c = 0; c < local; ++c) {
    const std::size_t v = static_cast<std::size_t>(halo_.local_vertex()[c]);
    if (fixed[v] || cut_[c] == 1.0) continue;
    for (int i = 0; i < 3; ++i)
      q_next[3 * v + i] =
          static_cast<Real>(p[3 * c + i] + cut_[c] * (proposed_[3 * c + i] - p[3 * c + i]));
  }
  verify_paths_ = true;
}

template <class Real>
void BodyContact<Real>::cut_by_nearest_gap(const Real* q, Real* q_next, const std::uint8_t* fixed) {
  const Timed timed(seconds_.guard);
  cut_.assign(halo_.num_local(), 1.0);
  for (index_t c = 0; c < halo_.num_local(); ++c) {
    const std::size_t v = static_cast<std::size_t>(halo_.local_vertex()[c]);
    if (fixed[v] || !std::isfinite(static_cast<double>(nearest_[c]))) continue;
    double m[3];
    for (int i = 0; i < 3; ++i) m[i] = static_cast<double>(q_next[3 * v + i] - q[3 * v + i]);
    const double move = length(m);
    // Each side closes at most half of what the pair may close.
    const double g = static_cast<double>(nearest_[c]);
    const double allowed = 0.5 * (g - pair_kept_gap<Real>(g, dh_));
    // A non-finite move is none (the energy check rejects the iterate).
    const double scale = !std::isfinite(move) ? 0.0 : (move > allowed ? allowed / move : 1.0);
    if (scale == 1.0) continue;
    cut_[c] = scale;
    for (int i = 0; i < 3; ++i) q_next[3 * v + i] = static_cast<Real>(q[3 * v + i] + scale * m[i]);
  }
}

template <class Real>
void BodyContact<Real>::measure_moves(const std::vector<Real>& from, const std::vector<Real>& to) {
  moves_.resize(from.size() / 3);
  for (std::size_t c = 0; c < moves_.size(); ++c) {
    double d[3];
    for (int i = 0; i < 3; ++i) d[i] = static_cast<double>(to[3 * c + i] - from[3 * c + i]);
    moves_[c] = length(d);
  }
}

template <class Real>
double BodyContact<Real>::moved(const std::array<index_t, 4>& v) const {
  return moves_[v[0]] + moves_[v[1]] + moves_[v[2]] + moves_[v[3]];
}

template <class Real>
double BodyContact<Real>::gap_bound(std::size_t pair, const std::array<index_t, 4>& v) const {
  if (checked_travel_[pair] < 0) return 0;  // not evaluated since the pairs were found
  double travel = 0;
  for (index_t c : v) travel += travel_[c];
  return std::max(0.0, checked_distance_[pair] - (travel - checked_travel_[pair]));
}

template <class Real>
bool BodyContact<Real>::paths_clear() {
  bool clear = true;
  for_each_path(
      last_, halo_.positions(),
      [&](std::size_t pair, const std::array<index_t, 4>& v) {
        return !clear || moved(v) < gap_bound(pair, v);
      },
      [&](PairKind kind, const std::array<index_t, 4>&, const Real* x0, const Real* x1) {
        const double d = std::sqrt(static_cast<double>(pair_distance(kind, x0, false).d2));
        if (pair_path_fraction(kind, x0, x1, d, 0.0) < 1) clear = false;
      });
  return clear;
}

template <class Real>
template <class Skip, class Visit>
void BodyContact<Real>::for_each_path(const std::vector<Real>& from, const std::vector<Real>& to,
                                      Skip&& skip, Visit&& visit) {
  measure_moves(from, to);
  Real x0[12], x1[12];
  std::size_t pair = 0;
  for_each_contact_pair(pairs_, [&](PairKind kind, const std::array<index_t, 4>& v) {
    if (skip(pair++, v)) return;
    gather_pair(from, v, x0);
    gather_pair(to, v, x1);
    visit(kind, v, x0, x1);
  });
}

template <class Real>
PairStats BodyContact<Real>::local_pair_stats(const Real* q) {
  update_ghosts(q);
  PairStats stats;
  stats.force.assign(3 * static_cast<std::size_t>(mesh_.num_bodies()), 0.0);
  for_each_pair(false, [&](PairKind kind, const std::array<index_t, 4>& v, const Real* x,
                           Real kappa, std::size_t pair) {
    const PairTerms<Real> t = terms_of(kind, pair, v, x, kappa, PairHessian::none);
    const double d = static_cast<double>(t.distance);
    if (counted_here(halo_, v) && d < dh_) stats.pairs += 1;
    stats.least = std::min(stats.least, d);
    for (int j = 0; j < 4; ++j)
      if (halo_.owned(v[j]))
        for (int i = 0; i < 3; ++i)
          stats.force[3 * static_cast<std::size_t>(halo_.body()[v[j]]) + i] -=
              static_cast<double>(t.grad[3 * j + i]);
    return -1.0;
  });
  return stats;
}

template <class Real>
void BodyContact<Real>::update_ghosts(const Real* q) {
  const Timed timed(seconds_.ghosts);
  halo_.update_ghosts(q);
  if (verify_paths_) {
    // The guarded iteration's paths (their checks timed with the guard).
    const auto begin = std::chrono::steady_clock::now();
    verify_paths_ = false;
    if (!paths_clear()) {
      crossing_ = true;
      ++paths_caught_;
    }
    const double spent =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
    seconds_.guard += spent;
    seconds_.ghosts -= spent;
  }
  // Each contact vertex's path length since the pairs were found.
  const std::vector<Real>& p = halo_.positions();
  for (std::size_t c = 0; c < travel_.size(); ++c) {
    double d[3];
    for (int i = 0; i < 3; ++i) {
      d[i] = static_cast<double>(p[3 * c + i] - last_[3 * c + i]);
      last_[3 * c + i] = p[3 * c + i];
    }
    travel_[c] += length(d);
  }
}

template class BodyContact<double>;
template class BodyContact<float>;

}  // namespace descent
