#include "solver/step_control.hpp"

#include <vector>

#include "solver/methods/optimized_init.hpp"

namespace descent {

template <class Real>
void predict_positions(const SolverSpec& spec, LocalProblem<Real>& problem,
                       const BodyState<Real>& state, Real* qt, Real* y, Real* q, bool from_start) {
  const Real h = problem.dt();
  const std::string& init = from_start ? std::string("position") : spec.init;
  // Weights of h v and of h (v - v_prev) in the guess q_t + ... .
  const Real w_velocity = init == "position" ? Real(0) : Real(1);
  const Real w_acceleration =
      init == "constant_acceleration" ? static_cast<Real>(spec.eta) : Real(0);
  const std::size_t n = state.q.size();
#pragma omp parallel for schedule(static)
  for (std::size_t k = 0; k < n; ++k) {
    const Real q_start = state.q[k], v = state.v[k];
    qt[k] = q_start;
    y[k] = q_start + h * v;
    q[k] = q_start + h * (w_velocity * v + w_acceleration * (v - state.v_prev[k]));
  }
  // Eq. 10 (solver/methods/optimized_init.hpp): q_t + d h v, d from y and q_t.
  if (init == "optimized") {
    std::vector<Real> hv(n);
    for (std::size_t k = 0; k < n; ++k) hv[k] = h * state.v[k];
    const Real d = static_cast<Real>(optimized_step_weight(problem, qt, y, hv.data()));
    for (std::size_t k = 0; k < n; ++k) q[k] = qt[k] + d * hv[k];
  }
  problem.begin_contact_step(state.time, qt, q);
}

template void predict_positions(const SolverSpec&, LocalProblem<double>&, const BodyState<double>&,
                                double*, double*, double*, bool);
template void predict_positions(const SolverSpec&, LocalProblem<float>&, const BodyState<float>&,
                                float*, float*, float*, bool);

}  // namespace descent
