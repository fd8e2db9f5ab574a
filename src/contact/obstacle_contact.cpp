#include "contact/obstacle_contact.hpp"

#include <algorithm>
#include <cmath>

#include "common/error.hpp"
#include "contact/contact_scale.hpp"
#include "contact/surface_vertices.hpp"
#include "kernels/contact_loops.hpp"
#include "kernels/cpu/host_exec.hpp"

namespace descent {

namespace {

// Rigid motion x = R x0 + c of `motion` at time t (kernels/obstacle_contact.hpp).
void motion_transform(const Motion& motion, double t, double* rotation, double* shift) {
  for (int i = 0; i < 9; ++i) rotation[i] = i % 4 == 0 ? 1.0 : 0.0;
  for (int i = 0; i < 3; ++i) shift[i] = 0;
  const double tm = std::min(t, motion.until);
  if (motion.kind == "translate") {
    for (int i = 0; i < 3; ++i) shift[i] = motion.velocity[i] * tm;
  } else if (motion.kind == "rotate") {
    // Rodrigues: R = cos a I + sin a [k]x + (1 - cos a) k k^T; c = p - R p.
    const auto& ax = motion.axis;
    const double len = std::sqrt(ax[0] * ax[0] + ax[1] * ax[1] + ax[2] * ax[2]);
    const double k[3] = {ax[0] / len, ax[1] / len, ax[2] / len};
    const double a = motion.angular_velocity * tm, co = std::cos(a), si = std::sin(a);
    const double cross[9] = {0, -k[2], k[1], k[2], 0, -k[0], -k[1], k[0], 0};
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        rotation[3 * i + j] = (i == j ? co : 0.0) + si * cross[3 * i + j] + (1 - co) * k[i] * k[j];
    const auto& p = motion.centre;
    for (int i = 0; i < 3; ++i)
      shift[i] =
          p[i] - (rotation[3 * i] * p[0] + rotation[3 * i + 1] * p[1] + rotation[3 * i + 2] * p[2]);
  }
}

// Where the material point of obstacle `o` at x (at the time of `from`) is
// at the time of `to`: to.R from.R^T (x - from.c) + to.c.
template <class Real>
void carried(const ObstacleGeometry<Real>& from, const ObstacleGeometry<Real>& to, const Real* x,
             Real* out) {
  Real d[3], x0[3];
  for (int i = 0; i < 3; ++i) d[i] = x[i] - from.shift[i];
  for (int i = 0; i < 3; ++i)
    x0[i] = from.rotation[i] * d[0] + from.rotation[3 + i] * d[1] + from.rotation[6 + i] * d[2];
  for (int i = 0; i < 3; ++i)
    out[i] = to.rotation[3 * i] * x0[0] + to.rotation[3 * i + 1] * x0[1] +
             to.rotation[3 * i + 2] * x0[2] + to.shift[i];
}

}  // namespace

template <class Real>
ObstacleGeometry<Real> obstacle_geometry(const Obstacle& obstacle, double t) {
  ObstacleGeometry<Real> o{};
  if (obstacle.kind == "plane") {
    o.kind = kObstaclePlane;
    const auto& n = obstacle.normal;
    const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    for (int i = 0; i < 3; ++i) {
      o.a[i] = static_cast<Real>(obstacle.point[i]);
      o.b[i] = static_cast<Real>(n[i] / len);
    }
  } else if (obstacle.kind == "sphere") {
    o.kind = kObstacleSphere;
    for (int i = 0; i < 3; ++i) o.a[i] = static_cast<Real>(obstacle.centre[i]);
    o.radius = static_cast<Real>(obstacle.radius);
  } else {
    o.kind = kObstacleBox;
    for (int i = 0; i < 3; ++i) {
      o.a[i] = static_cast<Real>(obstacle.box_min[i]);
      o.b[i] = static_cast<Real>(obstacle.box_max[i]);
    }
  }
  double rotation[9], shift[3];
  motion_transform(obstacle.motion, t, rotation, shift);
  for (int i = 0; i < 9; ++i) o.rotation[i] = static_cast<Real>(rotation[i]);
  for (int i = 0; i < 3; ++i) o.shift[i] = static_cast<Real>(shift[i]);
  return o;
}

template <class Real>
ObstacleContact<Real>::ObstacleContact(const LocalMesh& mesh, const Scene& scene, Halo<Real>& halo,
                                       EnergyReduction& reduction, const std::vector<Real>& mass,
                                       const std::vector<Real>& rest_diagonal, double inv_h2)
    : mesh_(mesh),
      vertex_body_(vertex_bodies(mesh)),
      reduction_(reduction),
      obstacles_(scene.obstacles),
      energy_(scene.contact.method == "energy"),
      eps_h_(static_cast<Real>(scene.contact.smoothing_velocity * scene.time.dt)),
      h_(static_cast<Real>(scene.time.dt)),
      projected_(4 * scene.obstacles.size(), 0.0) {
  const index_t nv = mesh.num_vertices();
  vertices_ = surface_vertices(mesh, halo);
  num_owned_ = static_cast<index_t>(
      std::lower_bound(vertices_.begin(), vertices_.end(), mesh.num_owned) - vertices_.begin());

  dh_ = static_cast<Real>(descent::activation_distance(mesh, scene, reduction));
  for (index_t v : vertices_) {
    const Real* d = &rest_diagonal[3 * static_cast<std::size_t>(v)];
    kappa_.push_back(vertex_stiffness(scene, mass[v], inv_h2, d));
    mass_.push_back(mass[v]);
    for (int i = 0; i < 3; ++i) base_.push_back(static_cast<Real>(mass[v] * inv_h2) + d[i]);
  }

  // No obstacle may cut the body at its start, nor touch it where the
  // barrier (infinite at a zero gap) would hold it.
  const auto& x = mesh.rest_positions;
  for (std::size_t k = 0; k < obstacles_.size(); ++k) {
    const ObstacleGeometry<Real> o = obstacle_geometry<Real>(obstacles_[k], 0.0);
    double depth = -1e300;
    for (index_t v = 0; v < nv; ++v) {
      const Real p[3] = {static_cast<Real>(x[3 * static_cast<std::size_t>(v)]),
                         static_cast<Real>(x[3 * static_cast<std::size_t>(v) + 1]),
                         static_cast<Real>(x[3 * static_cast<std::size_t>(v) + 2])};
      depth = std::max(depth, -static_cast<double>(obstacle_gap(o, p).g));
    }
    depth = reduction.max_of(depth);
    const std::string name = detail::concat("obstacle.", k, " (", obstacles_[k].kind, ")");
    if (depth > 0)
      throw InputError(detail::concat(
          name, " cuts the body at its start: a vertex lies ", depth,
          " m inside it (move the obstacle or the body; a gap below contact.distance = ",
          static_cast<double>(dh_), " m is allowed)"));
    if (depth == 0 && energy_)
      throw InputError(
          detail::concat(name,
                         " touches the body at its start: a vertex lies on its surface, where the "
                         "barrier of contact.method = \"energy\" is infinite (leave a gap, below "
                         "contact.distance = ",
                         static_cast<double>(dh_), " m if it should rest there)"));
  }
  lags_.assign(vertices_.size() * obstacles_.size(), FrictionLag<Real>{});
  start_positions_.assign(3 * vertices_.size(), Real(0));
  start_.resize(obstacles_.size());
  geometry_.resize(obstacles_.size());
  for (std::size_t k = 0; k < obstacles_.size(); ++k)
    geometry_[k] = obstacle_geometry<Real>(obstacles_[k], 0.0);
}

template <class Real>
void ObstacleContact<Real>::begin_step(double t, const Real* qt, Real* q) {
  const std::size_t no = obstacles_.size();
  for (std::size_t k = 0; k < no; ++k) {
    start_[k] = obstacle_geometry<Real>(obstacles_[k], t);
    geometry_[k] = obstacle_geometry<Real>(obstacles_[k], t + static_cast<double>(h_));
  }
  std::fill(projected_.begin(), projected_.end(), 0.0);
  projected_depth_ = 0;
  const index_t ns = static_cast<index_t>(vertices_.size());
  for (index_t s = 0; s < ns; ++s)
    for (int i = 0; i < 3; ++i)
      start_positions_[3 * static_cast<std::size_t>(s) + i] =
          qt[3 * static_cast<std::size_t>(vertices_[s]) + i];
  if (!energy_) return;
#pragma omp parallel for schedule(static)
  for (index_t s = 0; s < ns; ++s) {
    const std::size_t v = static_cast<std::size_t>(vertices_[s]);
    const Real* xt = qt + 3 * v;
    for (std::size_t k = 0; k < no; ++k) {
      FrictionLag<Real>& lag = lags_[no * s + k];
      lag = FrictionLag<Real>{};
      const Gap<Real> gap = obstacle_gap(start_[k], xt);
      if (obstacles_[k].friction <= 0 || !(gap.g > Real(0)) || gap.g >= dh_) continue;
      lag.mu_lambda =
          static_cast<Real>(obstacles_[k].friction) * -kappa_[s] * barrier(gap.g, dh_).first;
      Real moved[3];
      carried(start_[k], geometry_[k], xt, moved);
      for (int i = 0; i < 3; ++i) {
        lag.n[i] = gap.n[i];
        lag.w[i] = moved[i] - xt[i];
      }
    }
  }
  // The guess: each body's whole move from qt scaled by the largest
  // fraction that keeps every surface vertex of it at least dh/2 from every
  // obstacle (or where it is, if nearer): one scale per body, so the guess
  // keeps its shape (cutting each vertex alone crushes the layer that meets
  // an obstacle first), a body thrown at an obstacle starts the step
  // touching it, inside the barrier's reach, where P^-1 and the spectrum
  // estimate made at the guess see the barrier, and a body resting on the
  // floor does not hold back one falling beside it.
  const int nb = mesh_.num_bodies();
  std::vector<double> least_scale(static_cast<std::size_t>(nb), 1.0);
  inside_.assign(vertices_.size(), 0);
  for (index_t s = 0; s < ns; ++s) {
    const std::size_t v = static_cast<std::size_t>(vertices_[s]);
    const Real* xt = qt + 3 * v;
    for (std::size_t k = 0; k < no; ++k)
      if (!(obstacle_gap(geometry_[k], xt).g > 0)) inside_[s] = 1;
    if (inside_[s]) continue;
    const Real d[3] = {q[3 * v] - xt[0], q[3 * v + 1] - xt[1], q[3 * v + 2] - xt[2]};
    const Real scale =
        move_fraction(geometry_.data(), static_cast<int>(no), xt, d, Real(0), dh_ / 2);
    double& least = least_scale[vertex_body_[v]];
    least = std::min(least, static_cast<double>(scale));
  }
  // The minimum over ranks, through the maximum of the negations.
  for (double& l : least_scale) l = -l;
  reduction_.max_in_place(least_scale.data(), nb);
  const std::size_t nv = static_cast<std::size_t>(mesh_.num_vertices());
  for (std::size_t v = 0; v < nv; ++v) {
    const Real scale = static_cast<Real>(-least_scale[vertex_body_[v]]);
    if (scale < Real(1))
      for (std::size_t k = 3 * v; k < 3 * v + 3; ++k) q[k] = qt[k] + scale * (q[k] - qt[k]);
  }
}

template <class Real>
void ObstacleContact<Real>::push_out(const Real* qt, Real* q) const {
  if (!energy_) return;
  // Vertices an obstacle has moved onto are pushed out along its normal, to
  // half the activation distance (a few passes settle corners).
  const std::size_t no = obstacles_.size();
  for (std::size_t s = 0; s < vertices_.size(); ++s) {
    if (!inside_[s]) continue;
    const std::size_t v = static_cast<std::size_t>(vertices_[s]);
    Real* x = q + 3 * v;
    for (int i = 0; i < 3; ++i) x[i] = qt[3 * v + i];
    for (int pass = 0; pass < 4; ++pass)
      for (std::size_t k = 0; k < no; ++k) {
        const Gap<Real> gap = obstacle_gap(geometry_[k], x);
        if (gap.g < dh_ / 2)
          for (int i = 0; i < 3; ++i) x[i] += (dh_ / 2 - gap.g) * gap.n[i];
      }
  }
}

template <class Real>
void ObstacleContact<Real>::project(Real* q, const Real* qt) {
  if (energy_) return;
  const std::size_t no = obstacles_.size();
  const double inv_h2 = 1.0 / (static_cast<double>(h_) * static_cast<double>(h_));
  for (std::size_t s = 0; s < vertices_.size(); ++s) {
    const std::size_t v = static_cast<std::size_t>(vertices_[s]);
    const bool owned = s < static_cast<std::size_t>(num_owned_);
    Real* x = q + 3 * v;
    const Real* xt = qt + 3 * v;
    for (std::size_t k = 0; k < no; ++k) {
      const Gap<Real> gap = obstacle_gap(geometry_[k], x);
      if (!(gap.g < Real(0))) continue;
      const Real depth = -gap.g;
      Real before[3] = {x[0], x[1], x[2]};
      for (int i = 0; i < 3; ++i) x[i] += depth * gap.n[i];
      // Coulomb on the impulse: the slip (relative to the obstacle, whose
      // motion over the step is that of its material point at qt) is cut by
      // mu times the normal correction, to zero at most.
      const Real mu = static_cast<Real>(obstacles_[k].friction);
      if (mu > 0) {
        Real moved[3], slip[3];
        carried(start_[k], geometry_[k], xt, moved);
        for (int i = 0; i < 3; ++i) slip[i] = x[i] - moved[i];
        const Real sn = slip[0] * gap.n[0] + slip[1] * gap.n[1] + slip[2] * gap.n[2];
        Real u[3];
        for (int i = 0; i < 3; ++i) u[i] = slip[i] - sn * gap.n[i];
        const Real len = std::sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
        if (len > 0) {
          const Real cut = std::min(Real(1), mu * depth / len);
          for (int i = 0; i < 3; ++i) x[i] -= cut * u[i];
        }
      }
      if (!owned) continue;
      double* sums = &projected_[4 * k];
      for (int i = 0; i < 3; ++i)
        sums[i] -= static_cast<double>(mass_[s]) * static_cast<double>(x[i] - before[i]) * inv_h2;
      sums[3] += 1;
      projected_depth_ = std::max(projected_depth_, static_cast<double>(depth));
    }
  }
}

template <class Real>
std::vector<double> ObstacleContact<Real>::local_sums(const Real* q) const {
  if (!energy_) return projected_;
  const std::size_t no = obstacles_.size();
  std::vector<double> sums(4 * no, 0.0);
  for (index_t s = 0; s < num_owned_; ++s) {
    const std::size_t v = static_cast<std::size_t>(vertices_[s]);
    for (std::size_t k = 0; k < no; ++k) {
      ContactTerms<Real> terms;
      const Real g = add_barrier(geometry_[k], kappa_[s], dh_, q + 3 * v, false, terms);
      add_friction(lags_[no * s + k], eps_h_, q + 3 * v,
                   &start_positions_[3 * static_cast<std::size_t>(s)], false, terms);
      for (int i = 0; i < 3; ++i) sums[4 * k + i] += static_cast<double>(terms.grad[i]);
      if (g < dh_) sums[4 * k + 3] += 1;
    }
  }
  return sums;
}

template <class Real>
double ObstacleContact<Real>::local_penetration(const Real* q) const {
  if (!energy_) return projected_depth_;
  double depth = 0;
  for (index_t s = 0; s < num_owned_; ++s)
    for (const ObstacleGeometry<Real>& o : geometry_)
      depth = std::max(
          depth,
          -static_cast<double>(obstacle_gap(o, q + 3 * static_cast<std::size_t>(vertices_[s])).g));
  return depth;
}

template <class Real>
Energy ObstacleContact<Real>::local_energy(const Real* q, const Real* qt) const {
  if (!energy_) return {};
  HostExec host;
  const Sum2 s = loops::contact_energy(host, 0, view(), q, qt);
  return {s.value, s.magnitude};
}

template <class Real>
ContactView<Real> ObstacleContact<Real>::view() const {
  ContactView<Real> c;
  c.num_obstacles = static_cast<int>(geometry_.size());
  c.obstacles = geometry_.data();
  c.num_vertices = static_cast<index_t>(vertices_.size());
  c.num_owned = num_owned_;
  c.vertices = vertices_.data();
  c.kappa = kappa_.data();
  c.lags = lags_.data();
  c.dh = dh_;
  c.eps_h = eps_h_;
  return c;
}

template ObstacleGeometry<double> obstacle_geometry(const Obstacle&, double);
template ObstacleGeometry<float> obstacle_geometry(const Obstacle&, double);
template class ObstacleContact<double>;
template class ObstacleContact<float>;

}  // namespace descent
