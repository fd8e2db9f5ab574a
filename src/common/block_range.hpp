#pragma once
// The block distribution of `total` items over `parts` ranks: rank r holds
// [begin(r), end(r)), with begin(r) = floor(total * r / parts), so blocks
// differ in size by at most one and every rank computes every block without
// communication. Mesh input (MeshSlice), the vertex directory and the frame
// writer all split tets and vertices this way.
#include <vector>

#include "common/mesh.hpp"

namespace descent {

class BlockRange {
 public:
  BlockRange(global_index_t total, int parts)
      : total_(total), parts_(parts), per_item_(total > 0 ? double(parts) / double(total) : 0.0) {
    // floor(total * r / parts) without forming total * r: with total =
    // q parts + rest it is q r + floor(rest r / parts), rest < parts.
    const global_index_t q = total / parts, rest = total % parts;
    begins_.resize(static_cast<std::size_t>(parts) + 1);
    for (int r = 0; r <= parts; ++r) begins_[r] = q * r + rest * r / parts;
  }

  global_index_t total() const { return total_; }
  int parts() const { return parts_; }
  global_index_t begin(int part) const { return begins_[part]; }
  global_index_t end(int part) const { return begins_[part + 1]; }
  global_index_t size(int part) const { return end(part) - begin(part); }
  // The part whose block holds `id`, for 0 <= id < total. Called for every
  // face and vertex of the set-up: a multiplication and a comparison or two.
  int owner(global_index_t id) const {
    // id * parts / total is within a part or two of the owner (rounding of
    // the blocks and of the double); the loops settle it.
    int part = static_cast<int>(static_cast<double>(id) * per_item_);
    part = part < 0 ? 0 : (part >= parts_ ? parts_ - 1 : part);
    while (begins_[part] > id) --part;
    while (begins_[part + 1] <= id) ++part;
    return part;
  }

 private:
  global_index_t total_;
  int parts_;
  double per_item_;
  std::vector<global_index_t> begins_;
};

}  // namespace descent
