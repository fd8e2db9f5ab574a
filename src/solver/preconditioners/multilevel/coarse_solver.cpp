#include "solver/preconditioners/multilevel/coarse_solver.hpp"

#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "comm/mpi_check.hpp"
#include "common/error.hpp"

namespace descent {

struct CoarseSolver::Factor {
  Eigen::SimplicialLLT<Eigen::SparseMatrix<double>, Eigen::Lower, Eigen::AMDOrdering<int>> llt;
  Eigen::VectorXd rhs, solution;
};

namespace {

struct Entry {
  std::int32_t row, col;
  double value;
};

}  // namespace

CoarseSolver::CoarseSolver(MPI_Comm comm, const LevelLayout& level, double epsilon)
    : comm_(comm),
      block_(level.block),
      first_shift_(std::sqrt(epsilon)),
      factor_(std::make_unique<Factor>()) {
  int size = 1;
  MPI_Comm_size(comm, &size);
  std::vector<long long> owned(level.global.begin(), level.global.begin() + level.num_owned);
  int count = static_cast<int>(owned.size());
  std::vector<int> counts(size), offsets(size + 1, 0);
  DESCENT_MPI_CHECK(MPI_Allgather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, comm));
  for (int r = 0; r < size; ++r) offsets[r + 1] = offsets[r] + counts[r];
  std::vector<long long> all(offsets[size]);
  DESCENT_MPI_CHECK(MPI_Allgatherv(owned.data(), count, MPI_LONG_LONG, all.data(), counts.data(),
                                   offsets.data(), MPI_LONG_LONG, comm));
  std::sort(all.begin(), all.end());
  for (global_index_t id : level.global)
    index_.push_back(std::lower_bound(all.begin(), all.end(), id) - all.begin());
  unknowns_ = static_cast<long long>(all.size()) * block_;
  DESCENT_VERIFY(unknowns_ < (1LL << 31), "coarsest level of ", unknowns_, " unknowns");
  for (index_t v = 0; v < level.num_owned; ++v)
    for (int j = 0; j < block_; ++j)
      owned_inactive_.push_back(level.active[static_cast<std::size_t>(block_) * v + j] ? 0 : 1);
  rhs_.assign(unknowns_, 0.0);
  const int local = static_cast<int>(index_.size());
  std::vector<int> node_counts(size), node_offsets(size + 1, 0);
  DESCENT_MPI_CHECK(MPI_Allgather(&local, 1, MPI_INT, node_counts.data(), 1, MPI_INT, comm));
  for (int r = 0; r < size; ++r) node_offsets[r + 1] = node_offsets[r] + node_counts[r];
  gathered_index_.resize(node_offsets[size]);
  DESCENT_MPI_CHECK(MPI_Allgatherv(index_.data(), local, MPI_LONG_LONG, gathered_index_.data(),
                                   node_counts.data(), node_offsets.data(), MPI_LONG_LONG, comm));
  for (int r = 0; r <= size; ++r) {
    if (r < size) gathered_counts_.push_back(node_counts[r] * block_);
    gathered_offsets_.push_back(node_offsets[r] * block_);
  }
  gathered_.resize(static_cast<std::size_t>(node_offsets[size]) * block_);
}

CoarseSolver::~CoarseSolver() = default;

void CoarseSolver::factor(const BlockPattern& pattern, const std::vector<double>& values) {
  int size = 1;
  MPI_Comm_size(comm_, &size);
  const int bb = block_ * block_;
  std::vector<Entry> mine;
  for (index_t r = 0; r < pattern.rows; ++r)
    for (index_t s = pattern.offsets[r]; s < pattern.offsets[r + 1]; ++s)
      for (int i = 0; i < block_; ++i)
        for (int j = 0; j < block_; ++j) {
          const double value = values[static_cast<std::size_t>(bb) * s + block_ * i + j];
          const long long row = index_[r] * block_ + i,
                          col = index_[pattern.columns[s]] * block_ + j;
          if (value != 0 && row >= col)
            mine.push_back({static_cast<std::int32_t>(row), static_cast<std::int32_t>(col), value});
        }
  // Identity rows of unknowns that carry nothing, once (by their owner).
  for (std::size_t k = 0; k < owned_inactive_.size(); ++k)
    if (owned_inactive_[k]) {
      const auto row = static_cast<std::int32_t>(index_[k / block_] * block_ + k % block_);
      mine.push_back({row, row, 1.0});
    }
  const int bytes = static_cast<int>(mine.size() * sizeof(Entry));
  DESCENT_VERIFY(mine.size() * sizeof(Entry) < (1u << 31), "coarsest operator too large to gather");
  std::vector<int> counts(size), offsets(size + 1, 0);
  DESCENT_MPI_CHECK(MPI_Allgather(&bytes, 1, MPI_INT, counts.data(), 1, MPI_INT, comm_));
  for (int r = 0; r < size; ++r) offsets[r + 1] = offsets[r] + counts[r];
  std::vector<Entry> all(offsets[size] / sizeof(Entry));
  DESCENT_MPI_CHECK(MPI_Allgatherv(mine.data(), bytes, MPI_BYTE, all.data(), counts.data(),
                                   offsets.data(), MPI_BYTE, comm_));
  gathers_ += 2;
  // setFromTriplets sums duplicates in the order given: rank order.
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(all.size());
  for (const Entry& e : all) triplets.emplace_back(e.row, e.col, e.value);
  const Eigen::Index n = static_cast<Eigen::Index>(unknowns_);
  Eigen::SparseMatrix<double> a(n, n);
  a.setFromTriplets(triplets.begin(), triplets.end());
  factor_->llt.compute(a);
  // Semi-definite where nothing holds a body still (a quasi-static solve
  // without held vertices: its rigid motions cost nothing): factor
  // A + shift diag(A), the shift growing from round-off, which keeps the
  // V-cycle SPD and leaves the motions A does not see to the smoother.
  // The shift starts at sqrt(epsilon) of the V-cycle's precision: 1/shift
  // is how far P^-1 amplifies the motions A does not see, and the round-off
  // of a right-hand side in them (epsilon) must stay small after it (in
  // float, 1e-8 let a collapsed box's rigid motions grow to NaN); an entry
  // with no curvature at all shifts by the operator's largest scale.
  shift_ = 0;
  if (factor_->llt.info() != Eigen::Success) {
    const Eigen::VectorXd diagonal = a.diagonal().cwiseAbs();
    const double floor = 1e-3 * std::max(diagonal.maxCoeff(), 1e-300);
    for (double shift = first_shift_; shift <= 1e-1 && factor_->llt.info() != Eigen::Success;
         shift *= 10) {
      Eigen::SparseMatrix<double> shifted = a;
      for (Eigen::Index k = 0; k < n; ++k)
        shifted.coeffRef(k, k) += shift * std::max(diagonal[k], floor);
      factor_->llt.compute(shifted);
      shift_ = shift;
    }
  }
  if (factor_->llt.info() != Eigen::Success)
    throw Error(detail::concat("multilevel: the coarsest operator (", unknowns_,
                               " unknowns) is not positive semi-definite"));
  factor_->rhs.resize(n);
}

void CoarseSolver::solve(const double* b, double* x) {
  int rank = 0;
  MPI_Comm_rank(comm_, &rank);
  DESCENT_MPI_CHECK(MPI_Allgatherv(b, gathered_counts_[rank], MPI_DOUBLE, gathered_.data(),
                                   gathered_counts_.data(), gathered_offsets_.data(), MPI_DOUBLE,
                                   comm_));
  ++solves_;
  // Rank by rank, so every rank adds the same terms in the same order.
  std::fill(rhs_.begin(), rhs_.end(), 0.0);
  for (std::size_t e = 0; e < gathered_index_.size(); ++e)
    for (int j = 0; j < block_; ++j)
      rhs_[gathered_index_[e] * block_ + j] += gathered_[block_ * e + j];
  Factor& f = *factor_;
  for (long long k = 0; k < unknowns_; ++k) f.rhs[k] = rhs_[k];
  f.solution = f.llt.solve(f.rhs);
  for (std::size_t v = 0; v < index_.size(); ++v)
    for (int j = 0; j < block_; ++j) x[block_ * v + j] = f.solution[index_[v] * block_ + j];
}

}  // namespace descent
