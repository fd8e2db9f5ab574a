#include "solver/preconditioners/multilevel/block_sparse.hpp"

namespace descent {

TransposedPattern transpose(const BlockPattern& pattern) {
  TransposedPattern t;
  t.offsets.assign(static_cast<std::size_t>(pattern.cols) + 1, 0);
  for (index_t c : pattern.columns) ++t.offsets[c + 1];
  for (index_t c = 0; c < pattern.cols; ++c) t.offsets[c + 1] += t.offsets[c];
  t.rows.resize(pattern.num_blocks());
  t.slots.resize(pattern.num_blocks());
  std::vector<index_t> next(t.offsets.begin(), t.offsets.end() - 1);
  // Rows in ascending order, so each column's list is ascending too.
  for (index_t r = 0; r < pattern.rows; ++r)
    for (index_t s = pattern.offsets[r]; s < pattern.offsets[r + 1]; ++s) {
      const index_t k = next[pattern.columns[s]]++;
      t.rows[k] = r;
      t.slots[k] = s;
    }
  return t;
}

BlockPattern pattern_from_rows(index_t cols, std::vector<std::vector<index_t>>& rows) {
  BlockPattern p;
  p.rows = static_cast<index_t>(rows.size());
  p.cols = cols;
  p.offsets.assign(rows.size() + 1, 0);
  for (std::size_t r = 0; r < rows.size(); ++r) {
    std::vector<index_t>& row = rows[r];
    std::sort(row.begin(), row.end());
    row.erase(std::unique(row.begin(), row.end()), row.end());
    p.offsets[r + 1] = p.offsets[r] + static_cast<index_t>(row.size());
  }
  p.columns.reserve(p.offsets.back());
  for (const auto& row : rows) p.columns.insert(p.columns.end(), row.begin(), row.end());
  return p;
}

}  // namespace descent
