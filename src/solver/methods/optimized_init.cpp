#include "solver/methods/optimized_init.hpp"

#include <vector>

#include "kernels/vertex.hpp"
#include "solver/methods/hessian_operator.hpp"

namespace descent {

template <class Real>
double optimized_step_weight(LocalProblem<Real>& problem, const Real* qt, const Real* y,
                             const Real* hv) {
  const std::size_t n = 3 * static_cast<std::size_t>(problem.num_vertices());
  const auto& fixed = problem.fixed_axes();
  const auto& mass = problem.mass();
  const VertexTerms<Real> terms = problem.vertex_terms();
  const Real* force = problem.external_force().data();
  std::vector<Real> p(n), hp(n);
  for (std::size_t dof = 0; dof < n; ++dof)
    p[dof] = fixed[dof / 3] & (1u << (dof % 3)) ? Real(0) : hv[dof];
  const auto g = problem.elastic_gradient(qt, false);
  // Owned dofs only, so that each counts once over all ranks.
  const std::size_t owned = 3 * static_cast<std::size_t>(problem.mesh().num_owned);
  double dots[2] = {0, 0};  // [p . grad eps(q_t), p . H p]
  for (std::size_t dof = 0; dof < owned; ++dof) {
    const int axis = static_cast<int>(dof % 3);
    const Real grad = dof_gradient(terms, mass[dof / 3], g.values[g.width * (dof / 3) + axis],
                                   qt[dof], y[dof], qt[dof], force[dof], axis);
    dots[0] += static_cast<double>(p[dof]) * grad;
  }
  HessianOperator<Real> hessian(problem);
  hessian.product(qt, p.data(), hp.data());
  for (std::size_t dof = 0; dof < owned; ++dof) dots[1] += static_cast<double>(p[dof]) * hp[dof];
  problem.global_dots(dots, 2);
  return dots[1] > 0 ? -dots[0] / dots[1] : 1.0;
}

template double optimized_step_weight(LocalProblem<double>&, const double*, const double*,
                                      const double*);
template double optimized_step_weight(LocalProblem<float>&, const float*, const float*,
                                      const float*);

}  // namespace descent
