#include "solver/local_problem.hpp"

#include <cmath>
#include <limits>
#include <type_traits>
#include <variant>

#include "common/error.hpp"
#include "kernels/contact_loops.hpp"
#include "kernels/cpu/host_exec.hpp"
#include "kernels/loops.hpp"
#include "solver/loads.hpp"

namespace descent {

namespace {

// Epsilon x mu per unit volume, with room: the round-off of an elastic term
// at rest, a difference of O(mu) quantities (the neo-Hookean boxes of
// tests/mpi/test_recovery.cpp settle at energies of -0.3 to -1 mu V eps that
// rise and fall between checks).
constexpr double kRestRoundoff = 64;

// Per body: its density and the factor its Young's modulus puts on the
// scene's energy density (Body: young scales every modulus alike). One entry
// for a scene without [[body]].
struct BodyMaterial {
  double density;
  double stiffness;
};

std::vector<BodyMaterial> body_materials(const Scene& scene) {
  const MaterialSpec& m = scene.material;
  if (scene.bodies.empty()) return {{m.density, 1.0}};
  std::vector<BodyMaterial> out;
  for (const Body& body : scene.bodies)
    out.push_back(
        {body.density > 0 ? body.density : m.density, body.young > 0 ? body.young / m.young : 1.0});
  return out;
}

std::uint8_t axes_mask(const std::string& axes) {
  std::uint8_t mask = 0;
  for (char c : axes) mask |= static_cast<std::uint8_t>(1u << (c - 'x'));
  return mask;
}

}  // namespace

template <class Real>
LocalProblem<Real>::LocalProblem(const LocalMesh& mesh, const Scene& scene, Halo<Real>& halo,
                                 EnergyReduction& reduction)
    : mesh_(mesh),
      halo_(halo),
      reduction_(reduction),
      model_(make_elastic_model<Real>(scene.material)),
      converting_(scene.material.conversion.enabled),
      dt_(static_cast<Real>(scene.time.dt)),
      fixed_regions_(scene.fixed),
      load_regions_(scene.loads) {
  const double h = scene.time.dt;
  // A quasi-static solve has no inertia and no damping.
  const bool dynamic = !scene.time.quasistatic;
  terms_.inv_h2 = static_cast<Real>(dynamic ? 1.0 / (h * h) : 0.0);
  terms_.damping_over_h = static_cast<Real>(dynamic ? scene.solver.damping / h : 0.0);
  for (int i = 0; i < 3; ++i) terms_.gravity[i] = static_cast<Real>(scene.gravity[i]);

  const index_t nt = mesh.num_tets(), nv = mesh.num_vertices();
  if (converting_) {
    const ConversionSpec& c = scene.material.conversion;
    conversion_ = {static_cast<Real>(c.lambda_minus), static_cast<Real>(c.lambda_plus),
                   static_cast<Real>(c.decay),
                   Arap<Real>::from_young_poisson(static_cast<Real>(scene.material.young),
                                                  static_cast<Real>(scene.material.poisson))};
    interpolant_.assign(nt, Real(0));
  }
  rest_.resize(nt);
  // Lumped masses: each tet gives rho V / 4 to its corners; shared vertices
  // are completed through the halo like any other partial sum. A body of its
  // own Young's modulus scales its tets' rest volume in rest_ (after the
  // mass), which every elastic term multiplies.
  std::vector<Real> corner_mass(12 * static_cast<std::size_t>(nt));
  const auto& x = mesh.rest_positions;
  const std::vector<BodyMaterial> materials = body_materials(scene);
  const std::vector<int> body = vertex_bodies(mesh);
  for (index_t t = 0; t < nt; ++t) {
    Vec3<Real> c[4];
    for (int a = 0; a < 4; ++a) {
      const double* p = &x[3 * static_cast<std::size_t>(mesh.tets[4 * t + a])];
      c[a] = {static_cast<Real>(p[0]), static_cast<Real>(p[1]), static_cast<Real>(p[2])};
    }
    rest_[t] = tet_rest(c[0], c[1], c[2], c[3]);
    DESCENT_VERIFY(rest_[t].volume > 0, "tet ", mesh.global_tet[t],
                   " has non-positive rest volume ", rest_[t].volume);
    const BodyMaterial& material = materials[body[mesh.tets[4 * t]]];
    const Real m = static_cast<Real>(material.density) * rest_[t].volume / Real(4);
    for (int k = 0; k < 12; ++k) corner_mass[12 * static_cast<std::size_t>(t) + k] = m;
    rest_[t].volume *= static_cast<Real>(material.stiffness);
  }
  // The bodies' volume (each tet lies on one rank; a stiffer body's counted
  // as its moduli scale it), for the noise floor.
  std::vector<double> volume(1, 0.0);
  for (index_t t = 0; t < nt; ++t) volume[0] += rest_[t].volume;
  reduction_.sum_in_place(volume);
  const double mu = scene.material.young / (2 * (1 + scene.material.poisson));
  // The elastic terms are evaluated in double (loops::local_energy).
  energy_noise_floor_ = kRestRoundoff * std::numeric_limits<double>::epsilon() * mu * volume[0];
  std::vector<Real> mass3(3 * static_cast<std::size_t>(nv));
  HostExec host;
  loops::gather_corners(host, 0, mesh.corner_offsets.data(), mesh.vertex_corners.data(), 0, nv,
                        corner_mass.data(), mass3.data(), 3, 0);
  halo_.sum(mass3.data(), 3);
  mass_.resize(nv);
  for (index_t v = 0; v < nv; ++v) mass_[v] = mass3[3 * static_cast<std::size_t>(v)];

  // A vertex in several fixed regions is held on the union of their axes and
  // moved by the last of them that moves.
  fixed_.assign(nv, 0);
  motion_region_.assign(nv, -1);
  for (std::size_t r = 0; r < scene.fixed.size(); ++r) {
    const FixedRegion& region = scene.fixed[r];
    const std::uint8_t mask = axes_mask(region.axes);
    for (index_t v = 0; v < nv; ++v) {
      if (!region.contains(&x[3 * static_cast<std::size_t>(v)])) continue;
      fixed_[v] |= mask;
      if (region.motion.kind != "none") motion_region_[v] = static_cast<int>(r);
    }
  }

  // Each load region's share of its force per vertex: the area of the
  // surface faces around the vertex over the region's whole area.
  load_weights_.resize(load_regions_.size());
  std::vector<double> region_area(load_regions_.size());
  for (std::size_t r = 0; r < load_regions_.size(); ++r) {
    const std::vector<double> share = local_load_areas(mesh, load_regions_[r], &region_area[r]);
    std::vector<Real> summed(share.begin(), share.end());
    halo_.sum(summed.data(), 1);
    load_weights_[r].assign(summed.begin(), summed.end());
  }
  reduction_.sum_in_place(region_area);
  for (std::size_t r = 0; r < load_regions_.size(); ++r) {
    const LoadRegion& region = load_regions_[r];
    if (!(region_area[r] > 0))
      throw InputError(detail::concat("load.", r, ": no boundary face of the mesh lies in [",
                                      region.box_min[0], ", ", region.box_min[1], ", ",
                                      region.box_min[2], "] - [", region.box_max[0], ", ",
                                      region.box_max[1], ", ", region.box_max[2], "]"));
    for (double& w : load_weights_[r]) w /= region_area[r];
  }
  external_force_.assign(3 * static_cast<std::size_t>(nv), Real(0));

  partial_.resize(6 * static_cast<std::size_t>(nv));

  // Floor of the diagonal: the mass term in dynamics; without inertia, a
  // small fraction of the rest stiffness, so d stays positive where a model's
  // curvature is not.
  const std::size_t n3 = 3 * static_cast<std::size_t>(nv);
  diagonal_floor_.resize(n3);
  rest_curvature_.resize(n3);
  // The elastic diagonal at rest: statics and contact need it; a double run
  // in dynamics does not (its states resolve far below the round-off of its
  // terms, so the inertia alone bounds rest_curvature_ well enough) and skips
  // the pass and its corner memory.
  std::vector<Real> rest_diagonal(n3, Real(0));  // elastic only
  if (!dynamic || !scene.obstacles.empty() || has_body_contact(scene) ||
      !std::is_same_v<Real, double>) {
    const std::vector<Real> rest(x.begin(), x.end());
    const Assembled at_rest = elastic_gradient(rest.data(), true);
    for (index_t v = 0; v < nv; ++v)
      for (int i = 0; i < 3; ++i)
        rest_diagonal[3 * v + i] = at_rest.values[at_rest.width * v + 3 + i];
    // The pass's corner values (with threads) go: a method that needs them
    // allocates them again (elastic_gradient); a run on the engine never does.
    std::vector<Real>().swap(corner_grad_);
    std::vector<Real>().swap(corner_diag_);
  }
  constexpr Real kRestStiffnessFraction = Real(1e-3);
  for (index_t v = 0; v < nv; ++v) {
    const Real inertia = dynamic ? mass_[v] * (terms_.inv_h2 + terms_.damping_over_h) : Real(0);
    for (int i = 0; i < 3; ++i) {
      const std::size_t k = 3 * static_cast<std::size_t>(v) + i;
      diagonal_floor_[k] = dynamic ? inertia : kRestStiffnessFraction * rest_diagonal[k];
      rest_curvature_[k] = inertia + rest_diagonal[k];
    }
  }
  if (!scene.obstacles.empty())
    contact_ = std::make_unique<ObstacleContact<Real>>(mesh, scene, halo_, reduction_, mass_,
                                                       rest_diagonal, terms_.inv_h2);
  if (has_body_contact(scene) && scene.contact.method == "energy")
    body_contact_ = std::make_unique<BodyContact<Real>>(mesh, scene, halo_, reduction_, mass_,
                                                        rest_diagonal, terms_.inv_h2);
  if (has_body_contact(scene) && scene.contact.method == "projection")
    body_projection_ =
        std::make_unique<BodyProjection<Real>>(mesh, scene, halo_, reduction_, mass_, fixed_);
}

template <class Real>
void LocalProblem<Real>::element_pass(const Real* q, index_t begin, index_t end, bool with_diagonal,
                                      const loops::ElementOut<Real>& out) {
  HostExec host;
  std::visit(
      [&](const auto& model) {
        if (converting_)
          loops::element_pass<true>(host, 0, model, conversion_, interpolant_.data(), q,
                                    mesh_.tets.data(), rest_.data(), begin, end, with_diagonal,
                                    out);
        else
          loops::element_pass<false>(host, 0, model, conversion_, interpolant_.data(), q,
                                     mesh_.tets.data(), rest_.data(), begin, end, with_diagonal,
                                     out);
      },
      model_);
}

template <class Real>
void LocalProblem<Real>::begin_step(double t) {
  const index_t nv = mesh_.num_vertices();
  std::fill(external_force_.begin(), external_force_.end(), Real(0));
  for (std::size_t r = 0; r < load_regions_.size(); ++r) {
    const std::array<double, 3> force = load_force(load_regions_[r], t);
    for (index_t v = 0; v < nv; ++v)
      for (int i = 0; i < 3; ++i)
        external_force_[3 * v + i] += static_cast<Real>(load_weights_[r][v] * force[i]);
  }
}

template <class Real>
void LocalProblem<Real>::hold_fixed(double t, Real* q) const {
  const index_t nv = mesh_.num_vertices();
  for (index_t v = 0; v < nv; ++v) {
    if (!fixed_[v]) continue;
    const double* rest = &mesh_.rest_positions[3 * static_cast<std::size_t>(v)];
    const std::array<double, 3> at =
        motion_region_[v] < 0 ? std::array<double, 3>{rest[0], rest[1], rest[2]}
                              : moved_position(fixed_regions_[motion_region_[v]].motion, rest, t);
    for (int i = 0; i < 3; ++i)
      if (fixed_[v] & (1u << i)) q[3 * v + i] = static_cast<Real>(at[i]);
  }
}

template <class Real>
std::vector<double> LocalProblem<Real>::local_region_sums(const Real* q, const Real* y,
                                                          const Real* qt) {
  const Assembled g = elastic_gradient(q, false);
  const std::size_t nf = fixed_regions_.size();
  std::vector<double> sums(7 * nf + 4 * load_regions_.size(), 0.0);
  const auto& x = mesh_.rest_positions;
  for (index_t v = 0; v < mesh_.num_owned; ++v) {
    const double* rest = &x[3 * static_cast<std::size_t>(v)];
    auto add_displacement = [&](double* s) {
      for (int i = 0; i < 3; ++i) s[i] += q[3 * v + i] - rest[i];
      s[3] += 1;
    };
    for (std::size_t r = 0; r < nf; ++r) {
      if (!fixed_regions_[r].contains(rest)) continue;
      double* s = &sums[7 * r];
      add_displacement(s);
      const std::uint8_t mask = axes_mask(fixed_regions_[r].axes);
      for (int i = 0; i < 3; ++i) {
        if (!(mask & (1u << i))) continue;
        const std::size_t k = 3 * static_cast<std::size_t>(v) + i;
        s[4 + i] += dof_gradient(terms_, mass_[v], g.values[g.width * v + i], q[k], y[k], qt[k],
                                 external_force_[k], i);
      }
    }
    for (std::size_t r = 0; r < load_regions_.size(); ++r)
      if (load_regions_[r].contains(rest)) add_displacement(&sums[7 * nf + 4 * r]);
  }
  return sums;
}

template <class Real>
typename LocalProblem<Real>::Assembled LocalProblem<Real>::elastic_gradient(const Real* q,
                                                                            bool with_diagonal) {
  const index_t nb = mesh_.num_boundary_tets, nt = mesh_.num_tets();
  const index_t ni = mesh_.num_interior, nv = mesh_.num_vertices();
  const index_t* offsets = mesh_.corner_offsets.data();
  const index_t* corners = mesh_.vertex_corners.data();
  const int width = with_diagonal ? 6 : 3;
  Real* partial = partial_.data();
  HostExec host;
  loops::ElementOut<Real> out;
  out.width = width;
  // One thread adds the results to the partials in tet order, bitwise the
  // gather's sums (kernels/element_out.hpp); threads gather through the
  // corner arrays, made at the first use: a run that never comes here (the
  // Chebyshev engine keeps its own) saves 24 reals per tet.
  const bool in_order = host.serial();
  if (in_order) {
    std::fill(partial, partial + static_cast<std::size_t>(width) * nv, Real(0));
    out.partial = partial;
    out.in_order = true;
  } else {
    if (corner_grad_.empty()) {
      corner_grad_.resize(12 * static_cast<std::size_t>(nt));
      corner_diag_.resize(12 * static_cast<std::size_t>(nt));
    }
    out.corner_grad = corner_grad_.data();
    out.corner_diag = with_diagonal ? corner_diag_.data() : nullptr;
  }
  auto gather = [&](index_t begin, index_t end) {
    if (in_order) return;
    loops::gather_corners(host, 0, offsets, corners, begin, end, corner_grad_.data(), partial,
                          width, 0);
    if (with_diagonal)
      loops::gather_corners(host, 0, offsets, corners, begin, end, corner_diag_.data(), partial,
                            width, 3);
  };

  // Boundary tets, then their (shared) vertices, then the exchange in flight
  // while the interior is computed (in order, the interior tets touch no
  // shared vertex).
  element_pass(q, 0, nb, with_diagonal, out);
  gather(ni, nv);
  halo_.begin(partial, width);
  element_pass(q, nb, nt, with_diagonal, out);
  gather(0, ni);
  halo_.finish(partial, width);

  return {partial, width};
}

template <class Real>
void LocalProblem<Real>::assemble_corners(const Real* corner_values, Real* out) {
  HostExec host;
  loops::gather_corners(host, 0, mesh_.corner_offsets.data(), mesh_.vertex_corners.data(), 0,
                        mesh_.num_vertices(), corner_values, out, 3, 0);
  halo_.sum(out, 3);
}

template <class Real>
Energy LocalProblem<Real>::local_energy(const Real* q, const Real* y, const Real* qt) const {
  HostExec host;
  const loops::VertexData<Real> vd{
      mass_.data(), fixed_.data(), diagonal_floor_.data(), external_force_.data(), y, qt, terms_};
  tet_energy_.resize(static_cast<std::size_t>(mesh_.num_tets()));
  const Sum2 s = std::visit(
      [&](const auto& model) {
        return converting_
                   ? loops::local_energy<true>(host, 0, model, conversion_, interpolant_.data(), q,
                                               mesh_.tets.data(), rest_.data(), mesh_.num_tets(),
                                               vd, rest_curvature_.data(), mesh_.num_owned,
                                               tet_energy_.data())
                   : loops::local_energy<false>(host, 0, model, conversion_, interpolant_.data(), q,
                                                mesh_.tets.data(), rest_.data(), mesh_.num_tets(),
                                                vd, rest_curvature_.data(), mesh_.num_owned,
                                                tet_energy_.data());
      },
      model_);
  if (!contact_) return {s.value, s.magnitude};
  const Energy contact = contact_->local_energy(q, qt);
  return {s.value + contact.value, s.magnitude + contact.magnitude};
}

template <class Real>
void LocalProblem<Real>::begin_contact_step(double t, const Real* qt, Real* q) {
  // The obstacles pull each body's guess back first, then the pairs between
  // bodies each contact island's (along the path left, so closing no
  // obstacle's gap more); vertices a moving obstacle ran into are pushed
  // out last, so no scaling undoes it; the pairs are then found about the
  // guess the iterations start at.
  if (contact_) contact_->begin_step(t, qt, q);
  if (body_contact_) body_contact_->pull_back(qt, q);
  if (contact_) contact_->push_out(qt, q);
  if (body_contact_) body_contact_->rebuild_here(q);
}

template <class Real>
bool LocalProblem<Real>::has_contact_barrier() const {
  return body_contact_ || (contact_ && contact_->energy_method());
}

template <class Real>
void LocalProblem<Real>::add_contact_gradient(const Real* q, const Real* qt, int width,
                                              Real* diag) {
  if (contact_ && contact_->energy_method()) {
    HostExec host;
    const loops::VertexData<Real> vd{
        mass_.data(), fixed_.data(), diagonal_floor_.data(), external_force_.data(), nullptr,
        qt,           terms_};
    loops::add_contact_gradient(host, 0, contact_->view(), vd, q, partial_.data(), width, diag);
  }
  if (body_contact_)
    body_contact_->add_gradient(q, partial_.data(), width, diag, terms_, mass_.data());
}

template <class Real>
void LocalProblem<Real>::guard_contact_moves(const Real* q, Real* q_next) {
  if (contact_ && contact_->energy_method()) {
    HostExec host;
    loops::guard_moves(host, 0, contact_->view(), fixed_.data(), q, q_next);
  }
  if (body_contact_) body_contact_->guard_proven(q, q_next, fixed_.data());
}

template <class Real>
void LocalProblem<Real>::end_contact_step(Real* q, const Real* qt) {
  // Bodies first: the obstacles are rigid and have the last word.
  if (body_projection_) body_projection_->project(q, qt);
  if (contact_) contact_->project(q, qt);
}

template class LocalProblem<double>;
template class LocalProblem<float>;

}  // namespace descent
