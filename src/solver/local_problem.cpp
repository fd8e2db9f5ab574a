#include "solver/local_problem.hpp"

#include <cmath>

#include "common/error.hpp"
#include "kernels/cpu/element_loops.hpp"

namespace descent {

namespace {

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
      model_(NeoHookean<Real>::from_young_poisson(static_cast<Real>(scene.material.young),
                                                  static_cast<Real>(scene.material.poisson))),
      dt_(static_cast<Real>(scene.time.dt)) {
  const double h = scene.time.dt;
  terms_.inv_h2 = static_cast<Real>(1.0 / (h * h));
  terms_.damping_over_h = static_cast<Real>(scene.solver.damping / h);
  for (int i = 0; i < 3; ++i) terms_.gravity[i] = static_cast<Real>(scene.gravity[i]);

  const index_t nt = mesh.num_tets(), nv = mesh.num_vertices();
  rest_.resize(nt);
  // Lumped masses: each tet gives rho V / 4 to its corners; shared vertices
  // are completed through the halo like any other partial sum.
  std::vector<Real> corner_mass(12 * static_cast<std::size_t>(nt));
  const auto& x = mesh.rest_positions;
  for (index_t t = 0; t < nt; ++t) {
    Vec3<Real> c[4];
    for (int a = 0; a < 4; ++a) {
      const double* p = &x[3 * static_cast<std::size_t>(mesh.tets[4 * t + a])];
      c[a] = {static_cast<Real>(p[0]), static_cast<Real>(p[1]), static_cast<Real>(p[2])};
    }
    rest_[t] = tet_rest(c[0], c[1], c[2], c[3]);
    DESCENT_VERIFY(rest_[t].volume > 0, "tet ", mesh.global_tet[t],
                   " has non-positive rest volume ", rest_[t].volume);
    const Real m = static_cast<Real>(scene.material.density) * rest_[t].volume / Real(4);
    for (int k = 0; k < 12; ++k) corner_mass[12 * static_cast<std::size_t>(t) + k] = m;
  }
  std::vector<Real> mass3(3 * static_cast<std::size_t>(nv));
  cpu::gather_corners(mesh.corner_offsets.data(), mesh.vertex_corners.data(), 0, nv,
                      corner_mass.data(), mass3.data(), 3);
  halo_.sum(mass3.data(), 3);
  mass_.resize(nv);
  for (index_t v = 0; v < nv; ++v) mass_[v] = mass3[3 * static_cast<std::size_t>(v)];

  fixed_.assign(nv, 0);
  for (const FixedRegion& region : scene.fixed) {
    const std::uint8_t mask = axes_mask(region.axes);
    for (index_t v = 0; v < nv; ++v)
      if (region.contains(&x[3 * static_cast<std::size_t>(v)])) fixed_[v] |= mask;
  }

  corner_grad_.resize(12 * static_cast<std::size_t>(nt));
  corner_diag_.resize(12 * static_cast<std::size_t>(nt));
  partial_.resize(6 * static_cast<std::size_t>(nv));
}

template <class Real>
typename LocalProblem<Real>::Assembled LocalProblem<Real>::elastic_gradient(const Real* q,
                                                                            bool with_diagonal) {
  const index_t nb = mesh_.num_boundary_tets, nt = mesh_.num_tets();
  const index_t ni = mesh_.num_interior, nv = mesh_.num_vertices();
  const index_t* tets = mesh_.tets.data();
  const index_t* offsets = mesh_.corner_offsets.data();
  const index_t* corners = mesh_.vertex_corners.data();
  Real* diag_corners = with_diagonal ? corner_diag_.data() : nullptr;
  const int width = with_diagonal ? 6 : 3;
  Real* partial = partial_.data();

  // Boundary tets, then their (shared) vertices, then the exchange in flight
  // while the interior is computed.
  cpu::element_gradients(model_, q, tets, rest_.data(), 0, nb, corner_grad_.data(), diag_corners);
  cpu::gather_corners(offsets, corners, ni, nv, corner_grad_.data(), partial, width);
  if (with_diagonal)
    cpu::gather_corners(offsets, corners, ni, nv, corner_diag_.data(), partial + 3, width);
  halo_.begin(partial, width);
  cpu::element_gradients(model_, q, tets, rest_.data(), nb, nt, corner_grad_.data(), diag_corners);
  cpu::gather_corners(offsets, corners, 0, ni, corner_grad_.data(), partial, width);
  if (with_diagonal)
    cpu::gather_corners(offsets, corners, 0, ni, corner_diag_.data(), partial + 3, width);
  halo_.finish(partial, width);

  return {partial, width};
}

template <class Real>
Energy LocalProblem<Real>::local_energy(const Real* q, const Real* y, const Real* qt) const {
  const cpu::EnergySum elastic =
      cpu::element_energy_sum(model_, q, mesh_.tets.data(), rest_.data(), 0, mesh_.num_tets());
  const index_t owned = mesh_.num_owned;
  double value = 0, magnitude = 0;
#pragma omp parallel for schedule(static) reduction(+ : value, magnitude)
  for (index_t v = 0; v < owned; ++v) {
    for (int i = 0; i < 3; ++i) {
      const std::size_t k = 3 * static_cast<std::size_t>(v) + i;
      const double term = dof_energy(terms_, mass_[v], q[k], y[k], qt[k], i);
      value += term;
      magnitude += std::abs(term);
    }
  }
  Energy e{elastic.value + value, elastic.magnitude + magnitude};
  return e;
}

template class LocalProblem<double>;
template class LocalProblem<float>;

}  // namespace descent
