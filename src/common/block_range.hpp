#pragma once
// The block distribution of `total` items over `parts` ranks: rank r holds
// [begin(r), end(r)), with begin(r) = floor(total * r / parts), so blocks
// differ in size by at most one and every rank computes every block without
// communication. Mesh input (MeshSlice), the vertex directory and the frame
// writer all split tets and vertices this way.
#include "common/mesh.hpp"

namespace descent {

class BlockRange {
 public:
  BlockRange(global_index_t total, int parts) : total_(total), parts_(parts) {}

  global_index_t total() const { return total_; }
  int parts() const { return parts_; }
  // floor(total * part / parts) without forming total * part: with
  // total = q parts + r it is q part + floor(r part / parts), r < parts.
  global_index_t begin(int part) const {
    const global_index_t q = total_ / parts_, r = total_ % parts_;
    return q * part + r * part / parts_;
  }
  global_index_t end(int part) const { return begin(part + 1); }
  global_index_t size(int part) const { return end(part) - begin(part); }
  // The part whose block holds `id`, for 0 <= id < total.
  int owner(global_index_t id) const {
    // id * parts / total is within a part or two of the owner (rounding
    // of the blocks and of the double); the loops settle it.
    int part = static_cast<int>(static_cast<double>(id) / static_cast<double>(total_) * parts_);
    part = part < 0 ? 0 : (part >= parts_ ? parts_ - 1 : part);
    while (begin(part) > id) --part;
    while (end(part) <= id) ++part;
    return part;
  }

 private:
  global_index_t total_;
  int parts_;
};

}  // namespace descent
