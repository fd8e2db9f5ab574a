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
#include "kernels/pair_contact.hpp"

namespace descent {

struct ContactPairs {
  std::vector<std::array<index_t, 4>> vertex_triangle;  // contact indices (p, a, b, c)
  std::vector<std::array<index_t, 4>> edge_edge;        // (p0, p1, q0, q1)
};

// With `to` (3 per contact vertex): the pairs that may come closer than
// `reach` somewhere along the straight paths from the halo's positions to
// `to`, each vertex's scaled by any fraction in [0, 1] (their boxes over
// both ends meet, and their distance less their vertices' summed moves is
// below reach). With `caps` (one per contact vertex) instead: the pairs
// closer than reach plus the largest cap of each side, those that may come
// within reach while no vertex moves further than its cap (a point of a
// primitive moves by a convex combination of its vertices' moves).
template <class Real>
ContactPairs find_contact_pairs(const ContactHalo<Real>& halo, double reach, bool self,
                                const std::vector<Real>* to = nullptr,
                                const std::vector<double>* caps = nullptr);

// visit(kind, vertices) for every pair, in the pairs' order: the
// vertex-triangle ones, then the edge-edge ones.
template <class Visit>
void for_each_contact_pair(const ContactPairs& pairs, Visit&& visit) {
  for (const auto& v : pairs.vertex_triangle) visit(PairKind::vertex_triangle, v);
  for (const auto& v : pairs.edge_edge) visit(PairKind::edge_edge, v);
}

// A pair's 12 coordinates (its 4 vertices' xyz) from x (3 per contact
// vertex) into out.
template <class Real>
void gather_pair(const std::vector<Real>& x, const std::array<index_t, 4>& v, Real* out) {
  for (int k = 0; k < 4; ++k)
    for (int i = 0; i < 3; ++i) out[3 * k + i] = x[3 * static_cast<std::size_t>(v[k]) + i];
}

// What the stats report of the pairs on one rank (summed or reduced over
// ranks by the caller).
struct PairStats {
  double pairs = 0;           // counted pairs in contact
  double least = 1e300;       // the least distance of the pairs (1e300: none)
  std::vector<double> force;  // per body, xyz: the force the pairs put on owned vertices
};

// Throws InputError on every rank when `least_distance` (over all ranks) is
// not positive: bodies touching at the start, where the barrier is infinite
// and the projection's planes are not defined.
void require_bodies_apart(double least_distance, double dh);

// Whether this rank counts the energy of the pair with contact vertices `v`.
template <class Real>
bool counted_here(const ContactHalo<Real>& halo, const std::array<index_t, 4>& v) {
  index_t least = v[0];
  for (index_t c : v)
    if (halo.global_id()[c] < halo.global_id()[least]) least = c;
  return halo.owned(least);
}

}  // namespace descent
