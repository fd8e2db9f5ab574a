#pragma once
// Contact between bodies with contact.method = "projection" (issue 21, step
// 4; docs/contact.md): the step is solved without contact, by any method
// and preconditioner, and its result is then corrected so that the pairs
// whose straight path over the step came within reach end apart
// (kernels/pair_projection.hpp: one plane per pair, mass-weighted moves that
// keep momentum, Coulomb friction on the impulse).
//
// A pass: the contact halo and pairs are found over the paths from q_t to
// the result (contact_halo.hpp, contact_pairs.hpp: one allgather and one
// all-to-all), each rank forms the constraints of the pairs around its
// vertices and relaxes them Jacobi-fashion: every sweep computes all moves
// from the same positions, each vertex takes the sum of its pairs' moves,
// each pair's scaled by 1 / (the most constraints any of its vertices is in)
// so a vertex pressed by many pairs does not overshoot. A sweep costs a
// neighbour message (the ghosts' new positions) and one allreduce (the
// largest violation left, which ends the sweeps). The moves of a shared
// vertex are summed in the pairs' global order on every sharer, so sharers
// stay bitwise alike and P ranks give one rank's result. Corrections can
// bring other pairs within reach: the pass is repeated, over the paths from
// q_t to the corrected result, until no constraint is violated.
#include <array>
#include <vector>

#include "comm/halo.hpp"
#include "comm/reduction.hpp"
#include "contact/contact_halo.hpp"
#include "contact/contact_pairs.hpp"
#include "io/scene.hpp"
#include "kernels/pair_projection.hpp"

namespace descent {

template <class Real>
class BodyProjection {
 public:
  // Collective. `mass` per local vertex; `fixed_axes` per local vertex (any
  // bit set: the vertex is held and takes no correction). Bodies that touch
  // at the start are an InputError on every rank (the overlap check before
  // the scatter refuses overlapping ones).
  BodyProjection(const LocalMesh& mesh, const Scene& scene, Halo<Real>& halo,
                 EnergyReduction& reduction, const std::vector<Real>& mass,
                 const std::vector<std::uint8_t>& fixed_axes);

  // Collective: the step's result q (3 per local vertex) corrected, from the
  // step start qt.
  void project(Real* q, const Real* qt);

  // Wall seconds on this rank so far: finding the pairs (search), the
  // sweeps with their messages (sweeps).
  struct Seconds {
    double search = 0, sweeps = 0;
  };
  const Seconds& seconds() const { return seconds_; }
  double activation_distance() const { return dh_; }
  // For the stats, of the last pass: this rank's counted pairs whose
  // constraint the solve's result violated, the least distance after it of
  // the pairs that came within dh along the step (1e300: none), and per body
  // (xyz each) the correction force m dx / h^2 on the vertices this rank
  // owns.
  PairStats local_pair_stats() const;
  // The deepest a side went behind its pair's plane in the solve's result
  // (0: none), on this rank.
  double local_penetration() const { return penetration_; }
  // Steps whose pass ended with a constraint violated by more than a tenth
  // of dh (on any rank) after the most passes and sweeps, so far.
  long unresolved_steps() const { return unresolved_steps_; }

 private:
  struct Constraint {
    PairKind kind;
    std::array<index_t, 4> v;  // contact indices
    PairConstraint<Real> plane;
  };
  // The constraints of the pairs found over the paths qt -> q, with their
  // relaxations; the first pass of a step also measures the penetration and
  // counts the violated pairs. Returns the largest violation on any rank
  // (collective).
  double find_constraints(const Real* qt, const Real* q, bool first);
  // One Jacobi sweep over the constraints into q; returns the largest
  // violation left on any rank (collective).
  double sweep(Real* q);
  // Collective: where a constraint is violated by more than deep_, its
  // contact island's relative motion over the step is cut to the least
  // share of its pairs' paths that keeps them dh apart (or half their gap
  // if nearer), its free vertices' common (mass-weighted) move kept: the
  // island keeps its momentum and the sweeps are left gaps they can close
  // without crushing elements.
  void cut_deep_islands(Real* q, const Real* qt);
  // The least distance of `pairs` at x (3 per contact vertex; 1e300: none).
  double least_distance(const ContactPairs& pairs, const std::vector<Real>& x) const;

  const LocalMesh& mesh_;
  const std::vector<int> vertex_body_;  // per local vertex
  EnergyReduction& reduction_;
  ContactHalo<Real> halo_;
  bool self_ = false;
  double dh_ = 0, mu_ = 0, inv_h2_ = 0;
  double deep_ = 0;  // a violation beyond it cuts its island (kDeep of the mean surface edge)
  std::vector<Real> mass_;      // per local vertex
  std::vector<Real> inv_mass_;  // per local vertex: 1 / m, 0 where held
  ContactPairs pairs_;          // the last search's, over the paths q_t -> q
  std::vector<Constraint> constraints_;
  std::vector<double> relaxation_;  // per constraint
  // Per contact vertex: q_t, and the positions the sweeps are at.
  std::vector<Real> start_, current_;
  std::vector<double> force_;  // per body, xyz
  double penetration_ = 0;
  long violated_pairs_ = 0;
  long unresolved_steps_ = 0;
  Seconds seconds_;
};

}  // namespace descent
