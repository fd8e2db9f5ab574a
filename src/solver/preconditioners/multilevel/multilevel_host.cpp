// The multilevel preconditioner on the host execution: the methods' and the
// CPU engine's.
#include "contact/body_contact.hpp"
#include "contact/obstacle_contact.hpp"
#include "kernels/cpu/host_exec.hpp"
#include "solver/preconditioners/multilevel/multilevel_impl.hpp"
#include "solver/preconditioners/multilevel/multilevel_preconditioner.hpp"

namespace descent {

namespace {

// The host execution holds no state; this one lives beside its user.
template <class Real>
class HostMultilevel final : public Preconditioner<Real> {
 public:
  HostMultilevel(LocalProblem<Real>& problem, const SolverSpec& spec, const Real* contact_qt)
      : problem_(problem), impl_(exec_, problem, spec) {
    const ObstacleContact<Real>* contact = problem.contact();
    if (contact_qt && contact && contact->energy_method() && !contact->vertices().empty())
      impl_.use_contact(contact->view(), contact_qt);
  }
  // With pairs between bodies in eps, the diagonal of their positive
  // semi-definite Hessians at q joins the finest operator (collective with
  // the contact neighbours): only newton takes it, refreshing P^-1 at each
  // iterate, where the pairs' couplings, which the hierarchy's operators do
  // not hold, stay with the CG's products.
  void refresh(const Real* q) override {
    BodyContact<Real>* pairs = problem_.body_contact();
    if (!pairs || !problem_.has_contact_barrier()) {
      impl_.refresh(q);
      return;
    }
    pair_diagonal_.assign(3 * static_cast<std::size_t>(problem_.num_vertices()), Real(0));
    pairs->add_hessian_diagonal(q, pair_diagonal_.data(), problem_.fixed_axes().data());
    impl_.refresh(q, pair_diagonal_.data());
  }
  void read_interpolants_from(const Real* l) override { impl_.read_interpolants_from(l); }
  void apply(const Real* r, Real* z) override { impl_.apply(r, z); }
  PreconditionerStats stats() const override { return impl_.stats(); }
  std::string describe() const override { return impl_.describe(); }

 private:
  LocalProblem<Real>& problem_;
  HostExec exec_;
  MultilevelPreconditioner<HostExec, Real> impl_;
  std::vector<Real> pair_diagonal_;  // 3 per local vertex
};

}  // namespace

template <class Real>
std::unique_ptr<Preconditioner<Real>> make_host_multilevel(LocalProblem<Real>& problem,
                                                           const SolverSpec& spec,
                                                           const Real* contact_qt) {
  return std::make_unique<HostMultilevel<Real>>(problem, spec, contact_qt);
}

template class MultilevelPreconditioner<HostExec, double>;
template class MultilevelPreconditioner<HostExec, float>;
template std::unique_ptr<Preconditioner<double>> make_host_multilevel(LocalProblem<double>&,
                                                                      const SolverSpec&,
                                                                      const double*);
template std::unique_ptr<Preconditioner<float>> make_host_multilevel(LocalProblem<float>&,
                                                                     const SolverSpec&,
                                                                     const float*);

}  // namespace descent
