#pragma once
// Contact islands: the bodies linked, directly or through others, by pairs
// of primitives near each other on any rank. The guess's pull-back
// (BodyContact::pull_back) scales each island's move by its own fraction,
// so a stack held by the floor does not slow a body falling beside it.
#include <utility>
#include <vector>

#include "comm/reduction.hpp"

namespace descent {

// Collective: each body's island, named by its least body id (the same
// vector on every rank), from this rank's links (pairs of body ids, either
// order, repeats allowed). Rounds of relaxing the links to a fixed point on
// each rank, then one allreduce of the labels, until a round changes none:
// at most (bodies in the largest island) rounds, about 2 in practice.
std::vector<int> contact_islands(int num_bodies, const std::vector<std::pair<int, int>>& links,
                                 EnergyReduction& reduction);

}  // namespace descent
