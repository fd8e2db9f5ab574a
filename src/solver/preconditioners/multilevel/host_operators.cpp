#include "solver/preconditioners/multilevel/host_operators.hpp"

#include <cmath>
#include <cstdint>

#include "comm/mpi_check.hpp"
#include "common/error.hpp"
#include "common/splitmix.hpp"
#include "solver/spectrum.hpp"

namespace descent {

namespace {

template <int B, class T>
void product_of_blocks(const BlockPattern& pattern, const T* values, const double* x, double* y) {
#pragma omp parallel for schedule(static)
  for (index_t r = 0; r < pattern.rows; ++r) {
    double out[B] = {};
    for (index_t s = pattern.offsets[r]; s < pattern.offsets[r + 1]; ++s) {
      const T* a = values + B * B * static_cast<std::size_t>(s);
      const double* in = x + B * static_cast<std::size_t>(pattern.columns[s]);
      for (int i = 0; i < B; ++i)
        for (int j = 0; j < B; ++j) out[i] += static_cast<double>(a[B * i + j]) * in[j];
    }
    for (int i = 0; i < B; ++i) y[B * static_cast<std::size_t>(r) + i] = out[i];
  }
}

}  // namespace

template <class T>
void partial_product(const BlockPattern& pattern, const T* values, int block, const double* x,
                     double* y) {
  DESCENT_VERIFY(block == 3 || block == 6, "blocks of ", block);
  if (block == 3)
    product_of_blocks<3>(pattern, values, x, y);
  else
    product_of_blocks<6>(pattern, values, x, y);
}

template <class T>
std::vector<double> partial_diagonal(const BlockPattern& pattern, const T* values, int block) {
  const std::size_t bb = static_cast<std::size_t>(block) * block;
  std::vector<double> d(static_cast<std::size_t>(block) * pattern.rows, 0.0);
  for (index_t r = 0; r < pattern.rows; ++r) {
    const index_t s = pattern.find(r, r);
    if (s < 0) continue;
    for (int i = 0; i < block; ++i)
      d[static_cast<std::size_t>(block) * r + i] =
          static_cast<double>(values[bb * s + (block + 1) * i]);
  }
  return d;
}

std::vector<double> inverse_diagonal(const std::vector<double>& diagonal,
                                     const std::vector<std::uint8_t>& active) {
  std::vector<double> inv(diagonal.size(), 0.0);
  for (std::size_t k = 0; k < diagonal.size(); ++k)
    if (active[k] && diagonal[k] > 0) inv[k] = 1 / diagonal[k];
  return inv;
}

void rank_ordered_sum(MPI_Comm comm, double* values, int count) {
  int size = 1;
  MPI_Comm_size(comm, &size);
  std::vector<double> all(static_cast<std::size_t>(size) * count);
  DESCENT_MPI_CHECK(MPI_Allgather(values, count, MPI_DOUBLE, all.data(), count, MPI_DOUBLE, comm));
  for (int i = 0; i < count; ++i) {
    double sum = 0;
    for (int r = 0; r < size; ++r) sum += all[static_cast<std::size_t>(r) * count + i];
    values[i] = sum;
  }
}

std::vector<double> largest_eigenvalues(MPI_Comm comm, const std::vector<LanczosTarget>& targets,
                                        int steps, long& collectives) {
  const std::size_t count = targets.size();
  struct State {
    std::vector<double> v, v_prev, w, y;
    std::vector<double> alpha, beta;
    double scale = 0, beta_prev = 0;
    bool done = false;
  };
  std::vector<State> state(count);
  // w . D w over owned unknowns (D = 1 / inv_diagonal on active ones).
  auto weighted = [](const LanczosTarget& t, const std::vector<double>& w) {
    double sum = 0;
    for (index_t k = 0; k < t.owned; ++k)
      if (t.inv_diagonal[k] > 0) sum += w[k] * w[k] / t.inv_diagonal[k];
    return sum;
  };
  std::vector<double> sums(count);
  for (std::size_t i = 0; i < count; ++i) {
    const LanczosTarget& t = targets[i];
    State& s = state[i];
    for (auto* a : {&s.v, &s.v_prev, &s.w, &s.y}) a->assign(t.size, 0.0);
    for (index_t k = 0; k < t.size; ++k) {
      const std::uint64_t id =
          static_cast<std::uint64_t>(t.global[k / t.block]) * t.block + k % t.block;
      s.w[k] = t.inv_diagonal[k] > 0 ? unit_noise(id) : 0.0;
    }
    sums[i] = weighted(t, s.w);
  }
  rank_ordered_sum(comm, sums.data(), static_cast<int>(count));
  ++collectives;
  for (std::size_t i = 0; i < count; ++i) {
    state[i].scale = std::sqrt(sums[i]);
    state[i].done = !(sums[i] > 0);
  }
  for (int j = 0; j < steps; ++j) {
    for (std::size_t i = 0; i < count; ++i) {
      const LanczosTarget& t = targets[i];
      State& s = state[i];
      sums[i] = 0;
      if (s.done) continue;
      for (index_t k = 0; k < t.size; ++k) {
        s.v_prev[k] = s.v[k];
        s.v[k] = s.w[k] / s.scale;
      }
      t.product(s.v.data(), s.y.data());
      for (index_t k = 0; k < t.owned; ++k) sums[i] += s.v[k] * s.y[k];
    }
    rank_ordered_sum(comm, sums.data(), static_cast<int>(count));
    ++collectives;
    for (std::size_t i = 0; i < count; ++i) {
      const LanczosTarget& t = targets[i];
      State& s = state[i];
      if (s.done) {
        sums[i] = 0;
        continue;
      }
      const double a = sums[i];
      s.alpha.push_back(a);
      for (index_t k = 0; k < t.size; ++k)
        s.w[k] = s.y[k] * t.inv_diagonal[k] - a * s.v[k] - s.beta_prev * s.v_prev[k];
      sums[i] = weighted(t, s.w);
    }
    rank_ordered_sum(comm, sums.data(), static_cast<int>(count));
    ++collectives;
    for (std::size_t i = 0; i < count; ++i) {
      State& s = state[i];
      if (s.done) continue;
      const double b = std::sqrt(std::max(sums[i], 0.0));
      // An invariant subspace: the tridiagonal is exact there.
      if (!(b > 1e-12 * std::abs(s.alpha.back()))) {
        s.done = true;
        continue;
      }
      s.beta.push_back(b);
      s.beta_prev = s.scale = b;
    }
  }
  std::vector<double> largest(count, 0.0);
  for (std::size_t i = 0; i < count; ++i) {
    State& s = state[i];
    if (s.alpha.empty()) continue;
    s.beta.resize(s.alpha.size() - 1);
    largest[i] = tridiagonal_extremes(s.alpha, s.beta).highest;
  }
  return largest;
}

template void partial_product(const BlockPattern&, const double*, int, const double*, double*);
template void partial_product(const BlockPattern&, const float*, int, const double*, double*);
template std::vector<double> partial_diagonal(const BlockPattern&, const double*, int);
template std::vector<double> partial_diagonal(const BlockPattern&, const float*, int);

}  // namespace descent
