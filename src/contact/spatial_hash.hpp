#pragma once
// A uniform grid over axis-aligned boxes, hashed by cell: which of a set of
// boxes (triangles', tets', edges' bounds) may touch a query box. Broad
// phase of the searches between surface primitives (body_overlap.hpp).
//
// Layout: cell (i, j, k) = floor(x / cell_size); a box is listed in every
// cell it overlaps, ids by cell in CSR (cells sorted by key).
#include <array>
#include <cstdint>
#include <vector>

#include "common/mesh.hpp"

namespace descent {

struct Aabb {
  std::array<double, 3> lo{1e300, 1e300, 1e300};
  std::array<double, 3> hi{-1e300, -1e300, -1e300};

  void add(const double* p) {
    for (int i = 0; i < 3; ++i) {
      lo[i] = p[i] < lo[i] ? p[i] : lo[i];
      hi[i] = p[i] > hi[i] ? p[i] : hi[i];
    }
  }
  bool overlaps(const Aabb& other) const {
    for (int i = 0; i < 3; ++i)
      if (hi[i] < other.lo[i] || other.hi[i] < lo[i]) return false;
    return true;
  }
};

class SpatialHash {
 public:
  // `cell_size` > 0; boxes[i] is listed under id i. A box spanning more than
  // kMaxCellsPerBox cells (far larger than the cells) is kept aside and
  // offered to every query instead, so one huge primitive cannot fill memory.
  static constexpr std::int64_t kMaxCellsPerBox = 4096;
  SpatialHash(const std::vector<Aabb>& boxes, double cell_size);

  // Ids of the boxes that overlap `query` (each once, ascending): exactly
  // those, whatever the cell size, so what a search finds does not depend
  // on the boxes a rank happens to hold; the caller tests the primitives.
  void candidates(const Aabb& query, std::vector<index_t>& out) const;

  // A cell edge for boxes about this size queried by boxes grown by
  // `query_growth` beyond theirs: the mean largest extent plus the growth,
  // so a query covers a few cells along each axis, not the growth over the
  // extent (a pair search's reach can be many primitives wide).
  static double cell_size_for(const std::vector<Aabb>& boxes, double query_growth = 0);

 private:
  std::array<std::int64_t, 3> cell_of(const double* p) const;
  static std::uint64_t key(const std::array<std::int64_t, 3>& cell);

  double cell_size_;
  std::vector<Aabb> boxes_;
  std::vector<std::uint64_t> keys_;  // sorted distinct cell keys
  std::vector<index_t> offsets_;     // ids of keys_[c] at ids_[offsets_[c] .. offsets_[c + 1])
  std::vector<index_t> ids_;
  std::vector<index_t> large_;  // boxes offered to every query
};

}  // namespace descent
