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

template <class T>
void galerkin_product(const BlockPattern& a, const T* a_values, const BlockMatrix<double>& p,
                      const BlockPattern& c, std::vector<double>& c_values) {
  const int fb = p.row_block, cb = p.col_block;
  const std::size_t fbfb = static_cast<std::size_t>(fb) * fb, fbcb = static_cast<std::size_t>(fb) * cb,
                    cbcb = static_cast<std::size_t>(cb) * cb;
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
        const double* puj = p.block(t);
        for (int r = 0; r < fb; ++r)
          for (int k = 0; k < fb; ++k) {
            const double x = static_cast<double>(avu[fb * r + k]);
            if (x == 0) continue;
            for (int col = 0; col < cb; ++col) out[cb * r + col] += x * puj[cb * k + col];
          }
      }
    }
    std::sort(touched.begin(), touched.end());
    for (index_t t = pp.offsets[v]; t < pp.offsets[v + 1]; ++t) {
      const index_t i = pp.columns[t];
      const double* pvi = p.block(t);
      // Row i's slots in ascending column order, met as `touched` ascends.
      index_t slot = c.offsets[i];
      for (index_t j : touched) {
        while (slot < c.offsets[i + 1] && c.columns[slot] < j) ++slot;
        DESCENT_VERIFY(slot < c.offsets[i + 1] && c.columns[slot] == j,
                       "Galerkin block outside its pattern");
        double* cij = c_values.data() + cbcb * slot;
        const double* apj = acc.data() + fbcb * j;
        for (int k = 0; k < fb; ++k)
          for (int r = 0; r < cb; ++r) {
            const double x = pvi[cb * k + r];
            if (x == 0) continue;
            for (int col = 0; col < cb; ++col) cij[cb * r + col] += x * apj[cb * k + col];
          }
      }
    }
  }
}

template void galerkin_product(const BlockPattern&, const double*, const BlockMatrix<double>&,
                               const BlockPattern&, std::vector<double>&);
template void galerkin_product(const BlockPattern&, const float*, const BlockMatrix<double>&,
                               const BlockPattern&, std::vector<double>&);

}  // namespace descent
