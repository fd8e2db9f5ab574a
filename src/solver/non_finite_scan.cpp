// The rank-local search for the culprit of a non-finite energy. It runs only
// after the energy reduction reported a non-finite count, so it may be serial
// and slow; the normal path never calls it and it makes no collective.
#include <cmath>
#include <type_traits>
#include <utility>
#include <variant>

#include "kernels/loops.hpp"
#include "solver/local_problem.hpp"

namespace descent {

const char* describe(NonFiniteSite::Kind kind) {
  switch (kind) {
    case NonFiniteSite::Kind::none:
      return "nothing";
    case NonFiniteSite::Kind::position:
      return "position of vertex";
    case NonFiniteSite::Kind::velocity:
      return "velocity (inertial target) of vertex";
    case NonFiniteSite::Kind::element_energy:
      return "energy of tet";
    case NonFiniteSite::Kind::inverted_element:
      return "energy of inverted tet";
    case NonFiniteSite::Kind::vertex_energy:
      return "vertex energy term of vertex";
    case NonFiniteSite::Kind::sum:
      return "sum of finite terms (overflow) on this rank";
  }
  return "?";
}

template <class Real>
NonFiniteSite LocalProblem<Real>::find_non_finite(const Real* q, const Real* y,
                                                  const Real* qt) const {
  using Kind = NonFiniteSite::Kind;
  const index_t nv = mesh_.num_vertices(), nt = mesh_.num_tets();
  // Vertex values first, causes before effects: a NaN there spreads into
  // every term that touches the vertex. The step's start (qt) and its
  // inertial target (y = qt + h v) come before the trial positions q.
  for (const auto& [values, kind] :
       {std::pair{qt, Kind::position}, std::pair{y, Kind::velocity}, std::pair{q, Kind::position}})
    for (index_t v = 0; v < nv; ++v)
      for (int i = 0; i < 3; ++i)
        if (!std::isfinite(values[3 * v + i]))
          return {kind, mesh_.global_vertex[v], static_cast<double>(values[3 * v + i])};
  // One element at a time through the same inline math local_energy uses.
  NonFiniteSite site;
  std::visit(
      [&](const auto& model) {
        for (index_t t = 0; t < nt && !site.found(); ++t) {
          const TetCorners<Real> c = loops::tet_corners(q, &mesh_.tets[4 * std::size_t(t)]);
          const double e = converting_
                               ? converted_energy(model, conversion_, interpolant_[t], rest_[t], c)
                               : element_energy(model, rest_[t], c);
          if (std::isfinite(e)) continue;
          bool barrier = false;
          if constexpr (!std::decay_t<decltype(model)>::kInvertible) {
            const Mat3<Real> f =
                deformation_gradient(c.x[0], c.x[1], c.x[2], c.x[3], rest_[t].dm_inv);
            barrier = !converting_ && det(f) <= Real(0);
          }
          site = {barrier ? Kind::inverted_element : Kind::element_energy, mesh_.global_tet[t], e};
        }
      },
      model_);
  if (site.found()) return site;
  for (index_t v = 0; v < mesh_.num_owned; ++v) {
    for (int i = 0; i < 3; ++i) {
      const std::size_t k = 3 * static_cast<std::size_t>(v) + i;
      const double term = dof_energy(terms_, mass_[v], q[k], y[k], qt[k], external_force_[k], i);
      if (!std::isfinite(term)) return {Kind::vertex_energy, mesh_.global_vertex[v], term};
    }
  }
  const Energy total = local_energy(q, y, qt);
  if (!std::isfinite(total.value) || !std::isfinite(total.magnitude))
    return {Kind::sum, -1, total.value};
  return site;
}

template NonFiniteSite LocalProblem<double>::find_non_finite(const double*, const double*,
                                                             const double*) const;
template NonFiniteSite LocalProblem<float>::find_non_finite(const float*, const float*,
                                                            const float*) const;

}  // namespace descent
