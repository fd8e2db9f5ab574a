#include "solver/methods/newton_ldlt.hpp"

#include <algorithm>
#include <climits>

#include "common/error.hpp"

namespace descent {

namespace {

// MPI counts are int: a rank's block must stay below 2^31 values.
int checked_count(std::size_t count, const char* what) {
  DESCENT_VERIFY(count < static_cast<std::size_t>(INT_MAX), "newton_solver = \"ldlt\": ", what,
                 " of one rank has ", count, " values, more than an MPI count holds");
  return static_cast<int>(count);
}

}  // namespace

template <class Real>
NewtonLdlt<Real>::NewtonLdlt(LocalProblem<Real>& problem, const HessianOperator<Real>& hessian)
    : problem_(problem), hessian_(hessian), root_(problem.mesh().rank == 0) {
  const LocalMesh& mesh = problem.mesh();
  // The whole structure travels to rank 0 in 32-bit ids: a direct solve of
  // a mesh that needs more is far beyond one rank anyway.
  if (mesh.num_global_vertices > INT_MAX / 3)
    throw InputError(
        detail::concat("solver.newton_solver = \"ldlt\" factors the whole mesh on rank "
                       "0 and takes at most ",
                       INT_MAX / 3, " vertices, not ", mesh.num_global_vertices,
                       ": use newton_solver = \"petsc\""));
  const index_t nt = mesh.num_tets(), no = mesh.num_owned, nv = mesh.num_vertices();
  EnergyReduction& reduction = problem.reduction();

  // Structure of this rank, in global vertex ids: [nt, no, nv | fixed-axis
  // mask of the owned vertices (no) | ids of the local vertices (nv) | tets
  // (4 nt)]. Owned vertices are the first no local ones (LocalMesh order).
  std::vector<index_t> structure = {nt, no, nv};
  for (index_t v = 0; v < no; ++v) structure.push_back(problem.fixed_axes()[v]);
  for (index_t v = 0; v < nv; ++v) structure.push_back(static_cast<index_t>(mesh.global_vertex[v]));
  for (index_t k = 0; k < 4 * nt; ++k)
    structure.push_back(static_cast<index_t>(mesh.global_vertex[mesh.tets[k]]));
  const int structure_size = checked_count(structure.size(), "the mesh structure");
  const std::vector<int> structure_counts = reduction.gather_counts(structure_size);
  std::vector<index_t> all;
  reduction.gather_to_root(structure.data(), structure_size, structure_counts, all);

  // Rank 0 reads the blocks; the others learn nothing and need nothing.
  std::vector<int> curvature_counts;
  std::vector<std::uint8_t> owned_fixed;
  std::vector<index_t> tet_vertices;  // 4 global ids per tet, rank blocks in rank order
  index_t num_global = 0;             // 1 + the largest global vertex id
  if (root_) {
    std::size_t at = 0;
    for (std::size_t r = 0; r < structure_counts.size(); ++r) {
      const index_t t = all[at], o = all[at + 1], v = all[at + 2];
      at += 3;
      tets_per_rank_.push_back(t);
      owned_per_rank_.push_back(o);
      vertices_per_rank_.push_back(v);
      solve_counts_.push_back(checked_count(144 * std::size_t(t) + 3 * std::size_t(o), "Hessian"));
      scatter_counts_.push_back(checked_count(3 * std::size_t(v) + 1, "dq"));
      curvature_counts.push_back(3 * o);
      for (index_t k = 0; k < o; ++k) owned_fixed.push_back(static_cast<std::uint8_t>(all[at + k]));
      at += o;
      for (index_t k = 0; k < v; ++k) {
        local_vertex_.push_back(all[at + k]);
        if (k < o) owned_vertex_.push_back(all[at + k]);
        num_global = std::max(num_global, all[at + k] + 1);
      }
      at += v;
      tet_vertices.insert(tet_vertices.end(), all.begin() + at, all.begin() + at + 4 * t);
      at += 4 * t;
    }
  }

  // The vertex curvature is fixed for the run (HessianOperator computes it
  // once), so it travels once.
  std::vector<double> curvature(hessian.vertex_curvature().begin(),
                                hessian.vertex_curvature().begin() + 3 * std::size_t(no));
  std::vector<double> all_curvature;
  reduction.gather_to_root(curvature.data(), 3 * no, curvature_counts, all_curvature);
  send_.resize(144 * std::size_t(nt) + 3 * std::size_t(no));
  scattered_.resize(3 * std::size_t(nv) + 1);
  if (!root_) return;

  // Dofs of vertices no tet uses stay held (identity, dq = 0).
  const std::size_t n = 3 * std::size_t(num_global);
  held_.assign(n, 1);
  base_diagonal_.assign(n, 1.0);
  for (std::size_t k = 0; k < owned_vertex_.size(); ++k)
    for (int i = 0; i < 3; ++i) {
      const std::size_t dof = 3 * std::size_t(owned_vertex_[k]) + i;
      held_[dof] = owned_fixed[k] & (1u << i) ? 1 : 0;
      if (!held_[dof]) base_diagonal_[dof] = all_curvature[3 * k + i];
    }

  // The pattern: every diagonal entry and the lower-triangle entries between
  // free dofs of one tet; explicit zeros are kept by setFromTriplets.
  const std::size_t num_tets = tet_vertices.size() / 4;
  auto dof_of = [&](std::size_t t, int corner_axis) {
    return 3 * int(tet_vertices[4 * t + corner_axis / 3]) + corner_axis % 3;
  };
  std::vector<Eigen::Triplet<double>> pattern;
  pattern.reserve(n + 78 * num_tets);
  for (std::size_t d = 0; d < n; ++d) pattern.emplace_back(int(d), int(d), 0.0);
  for (std::size_t t = 0; t < num_tets; ++t)
    for (int r = 0; r < 12; ++r)
      for (int c = 0; c < 12; ++c) {
        const int row = dof_of(t, r), col = dof_of(t, c);
        if (row >= col && !held_[row] && !held_[col]) pattern.emplace_back(row, col, 0.0);
      }
  matrix_.resize(int(n), int(n));
  matrix_.setFromTriplets(pattern.begin(), pattern.end());
  matrix_.makeCompressed();

  // Where each element-Hessian entry and each diagonal entry adds in A's
  // values (column-major: the rows of column c are sorted).
  auto slot = [&](int row, int col) {
    const int* rows = matrix_.innerIndexPtr();
    const int* begin = rows + matrix_.outerIndexPtr()[col];
    const int* end = rows + matrix_.outerIndexPtr()[col + 1];
    const int* it = std::lower_bound(begin, end, row);
    DESCENT_VERIFY(it != end && *it == row, "entry (", row, ", ", col, ") not in the pattern");
    return int(it - rows);
  };
  diagonal_slot_.resize(n);
  for (std::size_t d = 0; d < n; ++d) diagonal_slot_[d] = slot(int(d), int(d));
  entry_slot_.assign(144 * num_tets, -1);
  for (std::size_t t = 0; t < num_tets; ++t)
    for (int r = 0; r < 12; ++r)
      for (int c = 0; c < 12; ++c) {
        const int row = dof_of(t, r), col = dof_of(t, c);
        if (row >= col && !held_[row] && !held_[col])
          entry_slot_[144 * t + 12 * r + c] = slot(row, col);
      }
  ldlt_.analyzePattern(matrix_);
  rhs_.resize(int(n));
  solution_.resize(int(n));
}

template <class Real>
bool NewtonLdlt<Real>::solve(const Real* g, Real* dq) {
  const LocalMesh& mesh = problem_.mesh();
  const std::size_t nt = mesh.num_tets(), no = mesh.num_owned, nv = mesh.num_vertices();
  const Real* h = hessian_.element_hessians().data();
  for (std::size_t k = 0; k < 144 * nt; ++k) send_[k] = h[k];
  for (std::size_t k = 0; k < 3 * no; ++k) send_[144 * nt + k] = -static_cast<double>(g[k]);
  problem_.reduction().gather_to_root(send_.data(), int(send_.size()), solve_counts_, received_);

  std::vector<double> out;  // per rank: dq of its local vertices, then the flag
  if (root_) {
    double* values = matrix_.valuePtr();
    std::fill(values, values + matrix_.nonZeros(), 0.0);
    for (std::size_t d = 0; d < diagonal_slot_.size(); ++d)
      values[diagonal_slot_[d]] = base_diagonal_[d];
    rhs_.setZero();
    // received_: per rank [144 per tet | 3 per owned vertex].
    std::size_t at = 0, entry = 0, owned = 0;
    for (std::size_t r = 0; r < tets_per_rank_.size(); ++r) {
      const std::size_t m = 144 * std::size_t(tets_per_rank_[r]);
      for (std::size_t k = 0; k < m; ++k)
        if (entry_slot_[entry + k] >= 0) values[entry_slot_[entry + k]] += received_[at + k];
      entry += m;
      at += m;
      for (std::size_t k = 0; k < 3 * std::size_t(owned_per_rank_[r]); ++k) {
        const std::size_t dof = 3 * std::size_t(owned_vertex_[owned + k / 3]) + k % 3;
        if (!held_[dof]) rhs_[dof] = received_[at + k];
      }
      at += 3 * std::size_t(owned_per_rank_[r]);
      owned += owned_per_rank_[r];
    }
    ldlt_.factorize(matrix_);
    bool positive = ldlt_.info() == Eigen::Success;
    if (positive) {
      solution_ = ldlt_.solve(rhs_);
      positive = (ldlt_.vectorD().array() > 0.0).all();
    } else {
      for (std::size_t d = 0; d < diagonal_slot_.size(); ++d)
        solution_[d] = rhs_[d] / values[diagonal_slot_[d]];
    }
    std::size_t local = 0;
    for (std::size_t r = 0; r < vertices_per_rank_.size(); ++r) {
      for (index_t k = 0; k < vertices_per_rank_[r]; ++k)
        for (int i = 0; i < 3; ++i) out.push_back(solution_[3 * local_vertex_[local + k] + i]);
      out.push_back(positive ? 1.0 : 0.0);
      local += vertices_per_rank_[r];
    }
  }
  problem_.reduction().scatter_from_root(out, scatter_counts_, scattered_.data(),
                                         int(scattered_.size()));
  for (std::size_t k = 0; k < 3 * nv; ++k) dq[k] = static_cast<Real>(scattered_[k]);
  return scattered_[3 * nv] > 0.5;
}

template class NewtonLdlt<double>;
template class NewtonLdlt<float>;

}  // namespace descent
