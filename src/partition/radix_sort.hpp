#pragma once
// Least-significant-digit radix sort of (key, value) records by key, for the
// set-up's large sorts by global id (tens of millions of records per rank),
// where it runs several times faster than a comparison sort. Stable: records
// of equal keys keep their order.
#include <array>
#include <cstdint>
#include <vector>

#include "common/mesh.hpp"

namespace descent {

struct KeyedIndex {
  global_index_t key;  // >= 0
  index_t value;
};

// Sorts by key, where every key is < key_bound.
inline void radix_sort(std::vector<KeyedIndex>& records, global_index_t key_bound) {
  constexpr int kDigitBits = 11;
  constexpr std::size_t kBuckets = std::size_t{1} << kDigitBits;
  std::vector<KeyedIndex> scratch(records.size());
  for (int shift = 0; shift < 63 && (global_index_t{1} << shift) < key_bound; shift += kDigitBits) {
    std::array<std::size_t, kBuckets + 1> start{};
    for (const KeyedIndex& r : records) ++start[((r.key >> shift) & (kBuckets - 1)) + 1];
    for (std::size_t b = 0; b < kBuckets; ++b) start[b + 1] += start[b];
    for (const KeyedIndex& r : records) scratch[start[(r.key >> shift) & (kBuckets - 1)]++] = r;
    records.swap(scratch);
  }
}

}  // namespace descent
