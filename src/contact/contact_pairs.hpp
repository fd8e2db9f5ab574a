#pragma once
// The contact pairs one rank evaluates (issue 21, step 3): among the
// primitives of its ContactHalo, every vertex-triangle and edge-edge pair
// closer than `reach` whose primitives share no vertex and belong to
// different bodies (or, with contact.self, to any), and which touches a
// local contact vertex: each rank adds the terms of the pairs around its own
// vertices, as every sharer adds a shared vertex's obstacle terms. A pair's
// energy is counted by one rank only: the owner of its vertex of least
// global id (counted_here).
//
// Order: ascending by the global ids of (p, a, b, c) and of (p0, p1, q0, q1),
// edges ordered within and between by their (lesser, greater) global ids, so
// the pairs and their sums do not depend on the rank count.
#include <array>
#include <vector>

#include "contact/contact_halo.hpp"

namespace descent {

struct ContactPairs {
  std::vector<std::array<index_t, 4>> vertex_triangle;  // contact indices (p, a, b, c)
  std::vector<std::array<index_t, 4>> edge_edge;        // (p0, p1, q0, q1)
};

// With `to` (3 per contact vertex): the pairs that may come closer than
// `reach` somewhere along the straight paths from the halo's positions to
// `to`, each vertex's scaled by any fraction in [0, 1] (their boxes over
// both ends meet, and their distance less their vertices' summed moves is
// below reach).
template <class Real>
ContactPairs find_contact_pairs(const ContactHalo<Real>& halo, double reach, bool self,
                                const std::vector<Real>* to = nullptr);

// Whether this rank counts the energy of the pair with contact vertices `v`.
template <class Real>
bool counted_here(const ContactHalo<Real>& halo, const std::array<index_t, 4>& v) {
  index_t least = v[0];
  for (index_t c : v)
    if (halo.global_id()[c] < halo.global_id()[least]) least = c;
  return halo.owned(least);
}

}  // namespace descent
