#pragma once
// Block-sparse matrices over one rank's nodes of a multilevel level, on the
// host (set-up and refresh). Layout: block CSR. Row r's blocks are slots
// [offsets[r], offsets[r + 1]), their column nodes in `columns`, ascending;
// block s holds row_block x col_block values, row-major, at
// values[s * row_block * col_block]. Rows and columns are local node ids of
// the level (LocalMesh order for the finest level).
#include <algorithm>
#include <cstddef>
#include <vector>

#include "common/mesh.hpp"

namespace descent {

struct BlockPattern {
  index_t rows = 0, cols = 0;
  std::vector<index_t> offsets{0};  // rows + 1
  std::vector<index_t> columns;     // one per block, ascending within a row

  std::size_t num_blocks() const { return columns.size(); }
  // The slot of block (row, col), or -1 where the pattern has none.
  index_t find(index_t row, index_t col) const {
    const auto first = columns.begin() + offsets[row], last = columns.begin() + offsets[row + 1];
    const auto it = std::lower_bound(first, last, col);
    return it != last && *it == col ? static_cast<index_t>(it - columns.begin()) : -1;
  }
};

// The pattern of the transpose: for each column c, the rows holding a block
// in it (ascending) and each such block's slot in the original pattern.
struct TransposedPattern {
  std::vector<index_t> offsets;  // cols + 1
  std::vector<index_t> rows;
  std::vector<index_t> slots;
};
TransposedPattern transpose(const BlockPattern& pattern);

// A pattern from per-row column lists (sorted and made unique here).
BlockPattern pattern_from_rows(index_t cols, std::vector<std::vector<index_t>>& rows);

template <class T>
struct BlockMatrix {
  BlockPattern pattern;
  int row_block = 0, col_block = 0;
  std::vector<T> values;  // row_block * col_block per slot

  std::size_t block_size() const { return static_cast<std::size_t>(row_block) * col_block; }
  T* block(std::size_t slot) { return values.data() + slot * block_size(); }
  const T* block(std::size_t slot) const { return values.data() + slot * block_size(); }
};

// A square block matrix held elsewhere, read only: `block` x `block` values
// per slot of `pattern`.
struct BlockView {
  const BlockPattern* pattern = nullptr;
  const double* values = nullptr;
  int block = 0;

  const double* slot(std::size_t s) const {
    return values + s * static_cast<std::size_t>(block) * block;
  }
};

}  // namespace descent
