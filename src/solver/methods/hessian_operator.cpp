#include "solver/methods/hessian_operator.hpp"

#include <algorithm>
#include <variant>

#include "kernels/contact_loops.hpp"
#include "kernels/cpu/host_exec.hpp"
#include "kernels/element_hessian.hpp"
#include "kernels/loops.hpp"
#include "kernels/vertex.hpp"

namespace descent {

template <class Real>
HessianOperator<Real>::HessianOperator(LocalProblem<Real>& problem) : problem_(problem) {
  const std::size_t nt = static_cast<std::size_t>(problem.mesh().num_tets());
  const std::size_t n = 3 * static_cast<std::size_t>(problem.num_vertices());
  // Corner values only for threads: one thread adds in tet order
  // (LocalProblem::assemble_elements).
  if (!HostExec().serial()) corners_.resize(12 * nt);
  diagonal_.resize(n);
  vertex_curvature_.resize(n);
  const VertexTerms<Real> terms = problem.vertex_terms();
  // The vertex terms are quadratic: their curvature is the diagonal with no
  // elastic part and no floor.
  for (std::size_t dof = 0; dof < n; ++dof)
    vertex_curvature_[dof] = dof_diagonal(terms, problem.mass()[dof / 3], Real(0), Real(0));
}

template <class Real>
void HessianOperator<Real>::finish(const Real* p, Real* out) const {
  const auto& fixed = problem_.fixed_axes();
  const std::size_t n = diagonal_.size();
#pragma omp parallel for schedule(static)
  for (std::size_t dof = 0; dof < n; ++dof)
    out[dof] =
        fixed[dof / 3] & (1u << (dof % 3)) ? Real(0) : out[dof] + vertex_curvature_[dof] * p[dof];
}

template <class Real>
void HessianOperator<Real>::product(const Real* q, const Real* p, Real* out, const Real* qt) {
  HostExec host;
  const LocalMesh& mesh = problem_.mesh();
  problem_.assemble_elements(corners_.data(), out, [&](const loops::ElementOut<Real>& o) {
    std::visit(
        [&](const auto& model) {
          loops::hessian_product_pass<false>(
              host, 0, model, problem_.conversion(), static_cast<const Real*>(nullptr), q, p,
              mesh.tets.data(), problem_.rest().data(), 0, mesh.num_tets(), o);
        },
        problem_.model());
  });
  // The pairs exist only as a barrier (contact.method = "energy").
  if (qt) {
    if (BodyContact<Real>* bodies = problem_.body_contact())
      bodies->add_hessian_product(q, p, out, PairHessian::exact);
    const ObstacleContact<Real>* contact = problem_.contact();
    if (contact && contact->energy_method()) {
      loops::VertexData<Real> vd{};  // the product reads the held axes and q_t only
      vd.fixed = problem_.fixed_axes().data();
      vd.qt = qt;
      loops::add_contact_hessian_product(host, 0, contact->view(), vd, q, p, out);
    }
  }
  finish(p, out);
}

template <class Real>
void HessianOperator<Real>::assemble(const Real* q, bool project) {
  const index_t nt = problem_.mesh().num_tets();
  const index_t* tets = problem_.mesh().tets.data();
  const TetRest<Real>* rest = problem_.rest().data();
  hessians_.resize(144 * static_cast<std::size_t>(nt));
  Real* h = hessians_.data();
  problem_.assemble_elements(
      corners_.data(), diagonal_.data(), [&](const loops::ElementOut<Real>& o) {
        std::visit(
            [&](const auto& model) {
#pragma omp parallel for schedule(static)
              for (index_t t = 0; t < nt; ++t) {
                const TetCorners<Real> x = loops::tet_corners(q, tets, t);
                Real* ht = &h[144 * static_cast<std::size_t>(t)];
                if (project)
                  element_hessian_psd(model, rest[t], x, ht);
                else
                  element_hessian(model, rest[t], x, ht);
                const Vec3<Real> diagonal[4] = {{ht[0], ht[13], ht[26]},
                                                {ht[39], ht[52], ht[65]},
                                                {ht[78], ht[91], ht[104]},
                                                {ht[117], ht[130], ht[143]}};
                loops::put_corners(o, tets, t, diagonal, static_cast<const Vec3<Real>*>(nullptr));
              }
            },
            problem_.model());
      });
  const auto& fixed = problem_.fixed_axes();
  for (std::size_t dof = 0; dof < diagonal_.size(); ++dof)
    diagonal_[dof] =
        fixed[dof / 3] & (1u << (dof % 3)) ? Real(1) : diagonal_[dof] + vertex_curvature_[dof];
  contact_blocks_.clear();
  pair_hessian_ = PairHessian::none;
}

template <class Real>
void HessianOperator<Real>::assemble_contact(const Real* q, const Real* qt, bool project) {
  pair_hessian_ = PairHessian::none;
  BodyContact<Real>* bodies = problem_.body_contact();
  if (bodies && problem_.has_contact_barrier()) {
    pair_hessian_ = project ? PairHessian::psd : PairHessian::exact;
    pairs_at_.assign(q, q + diagonal_.size());
    bodies->add_hessian_diagonal(q, diagonal_.data(), problem_.fixed_axes().data());
  }
  const ObstacleContact<Real>* contact = problem_.contact();
  if (!contact || !contact->energy_method()) return;
  const ContactView<Real> view = contact->view();
  const auto& fixed = problem_.fixed_axes();
  contact_blocks_.resize(9 * static_cast<std::size_t>(view.num_vertices));
  for (index_t s = 0; s < view.num_vertices; ++s) {
    const ContactTerms<Real> t = loops::contact_terms(view, s, q, qt, !project);
    std::copy(t.hess, t.hess + 9, contact_blocks_.begin() + 9 * s);
    // The Jacobi diagonal of the linear solve stays positive: an exact
    // block's diagonal may be negative (a curved obstacle's barrier).
    const std::size_t v = static_cast<std::size_t>(view.vertices[s]);
    for (int i = 0; i < 3; ++i)
      if (!(fixed[v] & (1u << i)) && t.hess[4 * i] > Real(0)) diagonal_[3 * v + i] += t.hess[4 * i];
  }
}

template <class Real>
void HessianOperator<Real>::apply(const Real* p, Real* out) {
  const index_t nt = problem_.mesh().num_tets();
  const index_t* tets = problem_.mesh().tets.data();
  const Real* h = hessians_.data();
  problem_.assemble_elements(corners_.data(), out, [&](const loops::ElementOut<Real>& o) {
#pragma omp parallel for schedule(static)
    for (index_t t = 0; t < nt; ++t) {
      const TetCorners<Real> pc = loops::tet_corners(p, tets, t);
      const Real v[12] = {pc.x[0].x, pc.x[0].y, pc.x[0].z, pc.x[1].x, pc.x[1].y, pc.x[1].z,
                          pc.x[2].x, pc.x[2].y, pc.x[2].z, pc.x[3].x, pc.x[3].y, pc.x[3].z};
      const Real* ht = &h[144 * static_cast<std::size_t>(t)];
      Real c[12];
      for (int r = 0; r < 12; ++r) {
        Real sum = 0;
        for (int s = 0; s < 12; ++s) sum += ht[12 * r + s] * v[s];
        c[r] = sum;
      }
      const Vec3<Real> values[4] = {
          {c[0], c[1], c[2]}, {c[3], c[4], c[5]}, {c[6], c[7], c[8]}, {c[9], c[10], c[11]}};
      loops::put_corners(o, tets, t, values, static_cast<const Vec3<Real>*>(nullptr));
    }
  });
  if (pair_hessian_ != PairHessian::none)
    problem_.body_contact()->add_hessian_product(pairs_at_.data(), p, out, pair_hessian_);
  if (!contact_blocks_.empty()) {
    const index_t* vertices = problem_.contact()->vertices().data();
    const index_t count = static_cast<index_t>(contact_blocks_.size() / 9);
    for (index_t s = 0; s < count; ++s) {
      const std::size_t v = static_cast<std::size_t>(vertices[s]);
      const Real* block = &contact_blocks_[9 * static_cast<std::size_t>(s)];
      for (int i = 0; i < 3; ++i)
        out[3 * v + i] += block[3 * i] * p[3 * v] + block[3 * i + 1] * p[3 * v + 1] +
                          block[3 * i + 2] * p[3 * v + 2];
    }
  }
  finish(p, out);
}

template class HessianOperator<double>;
template class HessianOperator<float>;

}  // namespace descent
