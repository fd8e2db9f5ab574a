#include "contact/body_contact.hpp"

#include <algorithm>
#include <cmath>

#include "common/error.hpp"
#include "contact/contact_scale.hpp"
#include "kernels/contact_loops.hpp"
#include "kernels/pair_contact.hpp"

namespace descent {

namespace {

// A vertex's move per iteration, as a fraction of its nearest pair's
// distance: two sides closing at once keep 1 - 2 x 0.4 = 0.2 of the gap,
// the share kGapKept keeps from an obstacle.
constexpr double kMoveFraction = 0.5 * (1.0 - kGapKept<double>);

double length(const double* d) { return std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]); }

}  // namespace

template <class Real>
BodyContact<Real>::BodyContact(const LocalMesh& mesh, const Scene& scene, Halo<Real>& halo,
                               EnergyReduction& reduction, const std::vector<Real>& mass,
                               const std::vector<Real>& rest_diagonal, double inv_h2)
    : mesh_(mesh), reduction_(reduction), halo_(mesh, halo), self_(scene.contact.self) {
  dh_ = descent::activation_distance(mesh, scene, reduction);
  kappa_.assign(mesh.num_vertices(), Real(0));
  for (index_t v = 0; v < mesh.num_vertices(); ++v)
    kappa_[v] =
        vertex_stiffness(scene, mass[v], inv_h2, &rest_diagonal[3 * static_cast<std::size_t>(v)]);
  // The mollifier's threshold of nearly parallel edges, IPC's 1e-3 |u|^2
  // |v|^2 with the mean surface edge for both (the same on every rank).
  std::vector<double> edges(2, 0.0);
  const auto& x = mesh.rest_positions;
  for (index_t t = 0; t < mesh.num_tets(); ++t)
    for (int f = 0; f < 4; ++f) {
      if (!(mesh.surface_faces[t] & (1u << f))) continue;
      for (int k = 0; k < 3; ++k) {
        const std::size_t a = mesh.tets[4 * static_cast<std::size_t>(t) + kTetFaces[f][k]];
        const std::size_t b =
            mesh.tets[4 * static_cast<std::size_t>(t) + kTetFaces[f][(k + 1) % 3]];
        const double d[3] = {x[3 * b] - x[3 * a], x[3 * b + 1] - x[3 * a + 1],
                             x[3 * b + 2] - x[3 * a + 2]};
        edges[0] += length(d);
        edges[1] += 1;
      }
    }
  reduction.sum_in_place(edges);
  const double mean_edge = edges[1] > 0 ? edges[0] / edges[1] : 0.0;
  eps_ = 1e-3 * std::pow(mean_edge, 4);

  // Bodies may start closer than dh, never touching.
  std::vector<Real> rest(x.begin(), x.end());
  halo_.rebuild(rest.data(), dh_, kappa_);
  pairs_ = find_contact_pairs(halo_, dh_, self_);
  const double least = reduction.max_of(-local_least_distance(rest.data()));
  if (-least <= 0)
    throw InputError(
        "bodies touch at the start (a vertex on another body's surface, or two edges "
        "meeting), where the contact barrier is infinite: leave a gap, below contact.distance = " +
        std::to_string(dh_) + " m if they should rest on each other");
}

template <class Real>
void BodyContact<Real>::begin_step(const Real* qt, Real* q) {
  const index_t nv = mesh_.num_vertices();
  // D: the guess's largest move (one allreduce); the reach covers the step.
  double moved = 0;
  for (index_t v = 0; v < nv; ++v) {
    const double d[3] = {static_cast<double>(q[3 * v] - qt[3 * v]),
                         static_cast<double>(q[3 * v + 1] - qt[3 * v + 1]),
                         static_cast<double>(q[3 * v + 2] - qt[3 * v + 2])};
    moved = std::max(moved, length(d));
  }
  moved = reduction_.max_of(moved);
  cap_ = dh_ + moved;
  const double reach = dh_ + 2 * (moved + cap_);
  halo_.rebuild(qt, reach, kappa_);
  pairs_ = find_contact_pairs(halo_, reach, self_);

  // The guess pulled back: no pair closes by more than half its gap at q_t
  // (its closing is at most the sum of its two sides' largest moves).
  std::vector<Real> guess;
  halo_.gather(q, guess);
  const std::vector<Real>& start = halo_.positions();
  std::vector<double> move(halo_.num_vertices());
  for (index_t c = 0; c < halo_.num_vertices(); ++c) {
    const double d[3] = {static_cast<double>(guess[3 * c] - start[3 * c]),
                         static_cast<double>(guess[3 * c + 1] - start[3 * c + 1]),
                         static_cast<double>(guess[3 * c + 2] - start[3 * c + 2])};
    move[c] = length(d);
  }
  double fraction = 1;
  Real x[12];
  for (int kind = 0; kind < 2; ++kind)
    for (const auto& v : kind == 0 ? pairs_.vertex_triangle : pairs_.edge_edge) {
      for (int k = 0; k < 4; ++k)
        for (int i = 0; i < 3; ++i) x[3 * k + i] = start[3 * static_cast<std::size_t>(v[k]) + i];
      const double d = std::sqrt(static_cast<double>(
          kind == 0 ? point_triangle_distance(x, false).d2 : edge_edge_distance(x, false).d2));
      // Side A: the vertex, or the first edge; side B the rest.
      const double a = kind == 0 ? move[v[0]] : std::max(move[v[0]], move[v[1]]);
      const double b = kind == 0 ? std::max({move[v[1]], move[v[2]], move[v[3]]})
                                 : std::max(move[v[2]], move[v[3]]);
      if (a + b > 0.5 * d) fraction = std::min(fraction, 0.5 * d / (a + b));
    }
  fraction = -reduction_.max_of(-fraction);
  if (fraction < 1)
    for (std::size_t k = 0; k < 3 * static_cast<std::size_t>(nv); ++k)
      q[k] = qt[k] + static_cast<Real>(fraction) * (q[k] - qt[k]);
  halo_.update_ghosts(q);
  anchor_ = halo_.positions();
  nearest_.assign(halo_.num_vertices(), Real(0));
}

template <class Real>
template <class Visit>
void BodyContact<Real>::for_each_pair(Visit&& visit) const {
  const std::vector<Real>& p = halo_.positions();
  const std::vector<Real>& kappa = halo_.carried();
  Real x[12];
  for (int kind = 0; kind < 2; ++kind)
    for (const auto& v : kind == 0 ? pairs_.vertex_triangle : pairs_.edge_edge) {
      Real k = 0;
      for (int j = 0; j < 4; ++j) {
        k += kappa[v[j]] / Real(4);
        for (int i = 0; i < 3; ++i) x[3 * j + i] = p[3 * static_cast<std::size_t>(v[j]) + i];
      }
      visit(kind == 0 ? PairKind::vertex_triangle : PairKind::edge_edge, v, x, k);
    }
}

template <class Real>
void BodyContact<Real>::add_gradient(const Real* q, Real* partial, int width, Real* diag,
                                     const VertexTerms<Real>& terms, const Real* mass) {
  halo_.update_ghosts(q);
  const index_t local = halo_.num_local();
  const auto& local_vertex = halo_.local_vertex();
  std::vector<Real> contact_diag(3 * static_cast<std::size_t>(local), Real(0));
  std::fill(nearest_.begin(), nearest_.end(), Real(INFINITY));
  const Real dh = static_cast<Real>(dh_), eps = static_cast<Real>(eps_);
  for_each_pair([&](PairKind kind, const std::array<index_t, 4>& v, const Real* x, Real kappa) {
    const PairTerms<Real> t = pair_barrier(kind, x, kappa, dh, eps, PairHessian::psd);
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
  halo_.update_ghosts(q);
  double sum = 0;
  const Real dh = static_cast<Real>(dh_), eps = static_cast<Real>(eps_);
  for_each_pair([&](PairKind kind, const std::array<index_t, 4>& v, const Real* x, Real kappa) {
    if (counted_here(halo_, v))
      sum += static_cast<double>(pair_barrier(kind, x, kappa, dh, eps, PairHessian::none).energy);
  });
  return sum;
}

template <class Real>
void BodyContact<Real>::add_hessian_product(const Real* q, const Real* v, Real* out) {
  halo_.update_ghosts(q);
  halo_.gather(v, gathered_);
  const index_t local = halo_.num_local();
  const Real dh = static_cast<Real>(dh_), eps = static_cast<Real>(eps_);
  for_each_pair([&](PairKind kind, const std::array<index_t, 4>& c, const Real* x, Real kappa) {
    const PairTerms<Real> t = pair_barrier(kind, x, kappa, dh, eps, PairHessian::exact);
    if (t.energy == Real(0)) return;
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
  });
}

template <class Real>
void BodyContact<Real>::guard(const Real* q, Real* q_next, const std::uint8_t* fixed) const {
  for (index_t c = 0; c < halo_.num_local(); ++c) {
    const std::size_t v = static_cast<std::size_t>(halo_.local_vertex()[c]);
    if (fixed[v]) continue;  // held vertices follow their motion
    double m[3];
    for (int i = 0; i < 3; ++i) m[i] = static_cast<double>(q_next[3 * v + i] - q[3 * v + i]);
    const double move = length(m);
    const double allowed = kMoveFraction * static_cast<double>(nearest_[c]);
    // A non-finite move is none (the energy check rejects the iterate).
    const double scale = !std::isfinite(move) ? 0.0 : (move > allowed ? allowed / move : 1.0);
    double to[3];
    for (int i = 0; i < 3; ++i)
      to[i] = static_cast<double>(q[3 * v + i]) + scale * m[i] - anchor_[3 * c + i];
    const double drift = length(to);
    const double pull = drift > cap_ ? cap_ / drift : 1.0;
    for (int i = 0; i < 3; ++i)
      q_next[3 * v + i] = static_cast<Real>(anchor_[3 * c + i] + pull * to[i]);
  }
}

template <class Real>
double BodyContact<Real>::local_active_pairs(const Real* q) {
  halo_.update_ghosts(q);
  double count = 0;
  for_each_pair([&](PairKind kind, const std::array<index_t, 4>& v, const Real* x, Real) {
    const PairDistance<Real> d = kind == PairKind::vertex_triangle
                                     ? point_triangle_distance(x, false)
                                     : edge_edge_distance(x, false);
    if (counted_here(halo_, v) && std::sqrt(static_cast<double>(d.d2)) < dh_) count += 1;
  });
  return count;
}

template <class Real>
double BodyContact<Real>::local_least_distance(const Real* q) {
  halo_.update_ghosts(q);
  double least = 1e300;
  for_each_pair([&](PairKind kind, const std::array<index_t, 4>&, const Real* x, Real) {
    const PairDistance<Real> d = kind == PairKind::vertex_triangle
                                     ? point_triangle_distance(x, false)
                                     : edge_edge_distance(x, false);
    least = std::min(least, std::sqrt(static_cast<double>(d.d2)));
  });
  return least;
}

template class BodyContact<double>;
template class BodyContact<float>;

}  // namespace descent
