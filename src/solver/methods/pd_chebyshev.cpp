#include "solver/methods/pd_chebyshev.hpp"

#include <variant>

#include "common/error.hpp"
#include "kernels/projective_dynamics.hpp"
#include "kernels/vertex.hpp"
#include "solver/spectrum.hpp"
#include "solver/step_control.hpp"

namespace descent {

template <class Real>
PdChebyshev<Real>::PdChebyshev(LocalProblem<Real>& problem, const SolverSpec& spec)
    : MethodBase<Real>(problem, spec) {
  for (auto* v : {&g_, &d_, &q_prev_}) v->assign(this->size(), Real(0));
  // diag(A): the elastic part from every tet's corners, completed through
  // the halo, then the vertex terms and floor as for the Hessian diagonal.
  const Arap<Real>* arap = std::get_if<Arap<Real>>(&problem.model());
  DESCENT_VERIFY(arap, "pd_chebyshev needs material.model = \"arap\"");
  const index_t nt = problem.mesh().num_tets();
  std::vector<Real> corners(12 * static_cast<std::size_t>(nt));
  for (index_t t = 0; t < nt; ++t) {
    Vec3<Real> diag[4];
    pd_element_diagonal(*arap, problem.rest()[t], diag);
    for (int a = 0; a < 4; ++a) {
      Real* c = &corners[12 * static_cast<std::size_t>(t) + 3 * a];
      c[0] = diag[a].x;
      c[1] = diag[a].y;
      c[2] = diag[a].z;
    }
  }
  std::vector<Real> elastic(this->size());
  problem.assemble_corners(corners.data(), elastic.data());
  const VertexTerms<Real> terms = problem.vertex_terms();
  for (std::size_t dof = 0; dof < this->size(); ++dof)
    d_[dof] =
        dof_diagonal(terms, problem.mass()[dof / 3], elastic[dof], problem.diagonal_floor()[dof]);
}

template <class Real>
void PdChebyshev<Real>::iterate(StepStats& stats) {
  const std::size_t n = this->size();
  const Real rho2 = static_cast<Real>(this->spec_.rho * this->spec_.rho);
  q_prev_ = this->q_;
  Real omega = 1;
  int chebyshev_k = 0;
  for (int k = 0; k < this->spec_.iterations; ++k) {
    this->gradient(this->q_.data(), g_.data(), nullptr, false);
    omega = chebyshev_omega(chebyshev_k, this->spec_.chebyshev_delay, rho2, omega);
    const Real alpha = static_cast<Real>(this->alpha_);
    Real* q = this->q_.data();
#pragma omp parallel for schedule(static)
    for (std::size_t dof = 0; dof < n; ++dof) {
      const Real next = chebyshev_dof(q[dof], q_prev_[dof], g_[dof], d_[dof], alpha, omega);
      q_prev_[dof] = q[dof];
      q[dof] = next;
    }
    ++chebyshev_k;
    stats.iterations = k + 1;
    this->report(k + 1);
    const auto outcome = this->check(k, stats);
    if (MethodBase<Real>::ends_step(outcome)) break;
    if (outcome == MethodBase<Real>::Check::rolled_back) {
      q_prev_ = this->q_;
      chebyshev_k = 0;
    }
  }
}

template <class Real>
double PdChebyshev<Real>::bound_rate() const {
  const double rho = this->spec_.rho;
  return rho > 0 && rho < 1 ? chebyshev_rate(rho) : 0.0;
}

template class PdChebyshev<double>;
template class PdChebyshev<float>;

}  // namespace descent
