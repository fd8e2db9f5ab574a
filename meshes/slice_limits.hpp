#pragma once
// The one limit the slice generators share: MeshSlice counts a rank's tets
// and vertices in index_t, so the largest block of either must fit one.
#include <algorithm>
#include <limits>
#include <string>

#include "common/error.hpp"
#include "common/mesh.hpp"

namespace descent {

// Throws InputError starting with `culprit` (the key and its value) when a
// block of num_tets or num_vertices over num_ranks ranks exceeds index_t.
inline void require_blocks_fit_index(const std::string& culprit, global_index_t num_tets,
                                     global_index_t num_vertices, int num_ranks) {
  const global_index_t largest = std::max(num_tets, num_vertices);
  if ((largest + num_ranks - 1) / num_ranks > std::numeric_limits<index_t>::max())
    throw InputError(detail::concat(culprit, " gives ", num_tets, " tets and ", num_vertices,
                                    " vertices: more per rank than a 32-bit index holds on ",
                                    num_ranks, num_ranks == 1 ? " rank" : " ranks",
                                    "; run on more ranks"));
}

}  // namespace descent
