#include "contact/spatial_hash.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "common/error.hpp"

namespace descent {

namespace {

// Cells are hashed into 21 bits per axis (a grid of 2 million cells along
// each axis before two cells share a key; sharing one only adds candidates).
constexpr std::uint64_t kAxisMask = (std::uint64_t{1} << 21) - 1;

}  // namespace

std::uint64_t SpatialHash::key(const std::array<std::int64_t, 3>& cell) {
  return (static_cast<std::uint64_t>(cell[0]) & kAxisMask) |
         ((static_cast<std::uint64_t>(cell[1]) & kAxisMask) << 21) |
         ((static_cast<std::uint64_t>(cell[2]) & kAxisMask) << 42);
}

std::array<std::int64_t, 3> SpatialHash::cell_of(const double* p) const {
  std::array<std::int64_t, 3> cell;
  for (int i = 0; i < 3; ++i) cell[i] = static_cast<std::int64_t>(std::floor(p[i] / cell_size_));
  return cell;
}

double SpatialHash::cell_size_for(const std::vector<Aabb>& boxes, double query_growth) {
  double sum = 0;
  for (const Aabb& box : boxes)
    sum += std::max({box.hi[0] - box.lo[0], box.hi[1] - box.lo[1], box.hi[2] - box.lo[2]});
  const double size = (boxes.empty() ? 0 : sum / static_cast<double>(boxes.size())) + query_growth;
  return size > 0 ? size : 1.0;
}

SpatialHash::SpatialHash(const std::vector<Aabb>& boxes, double cell_size)
    : cell_size_(cell_size), boxes_(boxes) {
  DESCENT_VERIFY(cell_size > 0 && std::isfinite(cell_size), "spatial hash cell size ", cell_size);
  std::vector<std::pair<std::uint64_t, index_t>> entries;
  for (std::size_t id = 0; id < boxes.size(); ++id) {
    const auto lo = cell_of(boxes[id].lo.data()), hi = cell_of(boxes[id].hi.data());
    const std::int64_t cells = (hi[0] - lo[0] + 1) * (hi[1] - lo[1] + 1) * (hi[2] - lo[2] + 1);
    if (cells > kMaxCellsPerBox) {
      large_.push_back(static_cast<index_t>(id));
      continue;
    }
    for (std::int64_t i = lo[0]; i <= hi[0]; ++i)
      for (std::int64_t j = lo[1]; j <= hi[1]; ++j)
        for (std::int64_t k = lo[2]; k <= hi[2]; ++k)
          entries.emplace_back(key({i, j, k}), static_cast<index_t>(id));
  }
  std::sort(entries.begin(), entries.end());
  for (std::size_t e = 0; e < entries.size(); ++e) {
    if (e == 0 || entries[e].first != entries[e - 1].first) {
      keys_.push_back(entries[e].first);
      offsets_.push_back(static_cast<index_t>(e));
    }
    ids_.push_back(entries[e].second);
  }
  offsets_.push_back(static_cast<index_t>(ids_.size()));
}

void SpatialHash::candidates(const Aabb& query, std::vector<index_t>& out) const {
  out.assign(large_.begin(), large_.end());
  const auto lo = cell_of(query.lo.data()), hi = cell_of(query.hi.data());
  const std::int64_t cells = (hi[0] - lo[0] + 1) * (hi[1] - lo[1] + 1) * (hi[2] - lo[2] + 1);
  if (cells > kMaxCellsPerBox) {
    // A query far larger than the cells: every listed box is a candidate.
    out.insert(out.end(), ids_.begin(), ids_.end());
  } else {
    for (std::int64_t i = lo[0]; i <= hi[0]; ++i)
      for (std::int64_t j = lo[1]; j <= hi[1]; ++j)
        for (std::int64_t k = lo[2]; k <= hi[2]; ++k) {
          const auto at = std::lower_bound(keys_.begin(), keys_.end(), key({i, j, k}));
          if (at == keys_.end() || *at != key({i, j, k})) continue;
          const std::size_t c = static_cast<std::size_t>(at - keys_.begin());
          out.insert(out.end(), ids_.begin() + offsets_[c], ids_.begin() + offsets_[c + 1]);
        }
  }
  // The overlap test first: a box listed in several cells the query covers
  // comes once per cell, and sorting those repeats cost more than the test.
  out.erase(std::remove_if(out.begin(), out.end(),
                           [&](index_t id) { return !boxes_[id].overlaps(query); }),
            out.end());
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
}

}  // namespace descent
