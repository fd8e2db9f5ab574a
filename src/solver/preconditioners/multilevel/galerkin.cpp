#include "solver/preconditioners/multilevel/galerkin.hpp"

#include <algorithm>

#include "common/error.hpp"

namespace descent {

BlockPattern galerkin_pattern(const BlockPattern& a, const BlockPattern& p) {
  std::vector<std::vector<index_t>> rows(p.cols);
  std::vector<index_t> reach;  // coarse nodes of (A P)_v
  for (index_t v = 0; v < a.rows; ++v) {
    reach.clear();
    for (index_t s = a.offsets[v]; s < a.offsets[v + 1]; ++s) {
      const index_t u = a.columns[s];
      reach.insert(reach.end(), p.columns.begin() + p.offsets[u],
                   p.columns.begin() + p.offsets[u + 1]);
    }
    std::sort(reach.begin(), reach.end());
    reach.erase(std::unique(reach.begin(), reach.end()), reach.end());
    for (index_t t = p.offsets[v]; t < p.offsets[v + 1]; ++t) {
      auto& row = rows[p.columns[t]];
      row.insert(row.end(), reach.begin(), reach.end());
      // Keep rows short while they grow: most entries repeat.
      if (row.size() > 4 * reach.size() + 64) {
        std::sort(row.begin(), row.end());
        row.erase(std::unique(row.begin(), row.end()), row.end());
      }
    }
  }
  return pattern_from_rows(p.cols, rows);
}

namespace {

// out (R x C) += a (R x K) b (K x C), fixed sizes so the compiler keeps the
// sums in registers; row-major.
template <int R, int K, int C, class TA, class TB>
inline void add_product(const TA* a, const TB* b, double* out) {
  for (int r = 0; r < R; ++r)
    for (int c = 0; c < C; ++c) {
      double sum = 0;
      for (int k = 0; k < K; ++k) sum += static_cast<double>(a[K * r + k]) * b[C * k + c];
      out[C * r + c] += sum;
    }
}

// out (R x C) += a^T b with a (K x R) and b (K x C).
template <int R, int K, int C>
inline void add_transposed_product(const double* a, const double* b, double* out) {
  for (int r = 0; r < R; ++r)
    for (int c = 0; c < C; ++c) {
      double sum = 0;
      for (int k = 0; k < K; ++k) sum += a[R * k + r] * b[C * k + c];
      out[C * r + c] += sum;
    }
}

template <int FB, int CB, class T>
void galerkin_blocks(const BlockPattern& a, const T* a_values, const BlockMatrix<double>& p,
                     const BlockPattern& c, std::vector<double>& c_values) {
  constexpr std::size_t fbfb = FB * FB, fbcb = FB * CB, cbcb = CB * CB;
  c_values.assign(c.num_blocks() * cbcb, 0.0);
  std::vector<double> acc(static_cast<std::size_t>(p.pattern.cols) * fbcb);
  std::vector<index_t> mark(p.pattern.cols, -1), touched;
  const BlockPattern& pp = p.pattern;
  for (index_t v = 0; v < a.rows; ++v) {
    if (pp.offsets[v] == pp.offsets[v + 1]) continue;  // a row P does not reach
    touched.clear();
    for (index_t s = a.offsets[v]; s < a.offsets[v + 1]; ++s) {
      const T* avu = a_values + fbfb * s;
      const index_t u = a.columns[s];
      for (index_t t = pp.offsets[u]; t < pp.offsets[u + 1]; ++t) {
        const index_t j = pp.columns[t];
        double* out = acc.data() + fbcb * j;
        if (mark[j] != v) {
          mark[j] = v;
          std::fill(out, out + fbcb, 0.0);
          touched.push_back(j);
        }
        add_product<FB, FB, CB>(avu, p.block(t), out);
      }
    }
    std::sort(touched.begin(), touched.end());
    for (index_t t = pp.offsets[v]; t < pp.offsets[v + 1]; ++t) {
      const index_t i = pp.columns[t];
      const double* pvi = p.block(t);
      // C is symmetric: the blocks right of the diagonal only (mirrored
      // below). Row i's slots in ascending column order, met as `touched`
      // ascends.
      index_t slot = c.offsets[i];
      for (auto it = std::lower_bound(touched.begin(), touched.end(), i); it != touched.end();
           ++it) {
        const index_t j = *it;
        while (slot < c.offsets[i + 1] && c.columns[slot] < j) ++slot;
        DESCENT_VERIFY(slot < c.offsets[i + 1] && c.columns[slot] == j,
                       "Galerkin block outside its pattern");
        add_transposed_product<CB, FB, CB>(pvi, acc.data() + fbcb * j,
                                           c_values.data() + cbcb * slot);
      }
    }
  }
  // C_ji = C_ij^T for the blocks left of the diagonal.
  for (index_t i = 0; i < c.rows; ++i)
    for (index_t s = c.offsets[i]; s < c.offsets[i + 1] && c.columns[s] < i; ++s) {
      const index_t mirror = c.find(c.columns[s], i);
      DESCENT_VERIFY(mirror >= 0, "Galerkin pattern not symmetric");
      double* lower = c_values.data() + cbcb * s;
      const double* upper = c_values.data() + cbcb * mirror;
      for (int r = 0; r < CB; ++r)
        for (int col = 0; col < CB; ++col) lower[CB * r + col] = upper[CB * col + r];
    }
}

}  // namespace

template <class T>
void galerkin_product(const BlockPattern& a, const T* a_values, const BlockMatrix<double>& p,
                      const BlockPattern& c, std::vector<double>& c_values) {
  DESCENT_VERIFY(p.col_block == 6 && (p.row_block == 3 || p.row_block == 6), "Galerkin product of ",
                 p.row_block, " x ", p.col_block, " blocks");
  if (p.row_block == 3)
    galerkin_blocks<3, 6>(a, a_values, p, c, c_values);
  else
    galerkin_blocks<6, 6>(a, a_values, p, c, c_values);
}

template void galerkin_product(const BlockPattern&, const double*, const BlockMatrix<double>&,
                               const BlockPattern&, std::vector<double>&);
template void galerkin_product(const BlockPattern&, const float*, const BlockMatrix<double>&,
                               const BlockPattern&, std::vector<double>&);

}  // namespace descent
