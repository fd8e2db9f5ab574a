#pragma once
// One rank's contact between its body and the scene's rigid obstacles
// ([[obstacle]], docs/contact.md). The terms are per surface vertex, local
// like the inertia terms: no message beyond the ones eps already needs.
//
// Data (host; an iteration engine copies what it reads):
//   vertices: the local ids of the rank's surface vertices, ascending, so the
//     owned ones are a prefix; a vertex on the surface on any rank is one on
//     every rank that holds it (the flags are summed through the halo), so
//     every sharer updates it alike.
//   kappa: barrier stiffness per surface vertex.
//   lags: FrictionLag per surface vertex and obstacle ([num_obstacles s + k]),
//     set at each step's start.
//   geometry: each obstacle where it is at the end of the step.
#include <cstdint>
#include <vector>

#include "comm/halo.hpp"
#include "comm/reduction.hpp"
#include "io/scene.hpp"
#include "kernels/obstacle_contact.hpp"
#include "partition/local_mesh.hpp"

namespace descent {

template <class Real>
class ObstacleContact {
 public:
  // `mass` (per local vertex) and `rest_diagonal` (the elastic Hessian
  // diagonal at rest, 3 per local vertex) are complete on every sharer;
  // `inv_h2` is 0 in a quasi-static solve. Collective: the activation
  // distance from the body's extent, and the check that no obstacle cuts the
  // body at its start (an InputError naming the obstacle, on every rank).
  ObstacleContact(const LocalMesh& mesh, const Scene& scene, Halo<Real>& halo,
                  EnergyReduction& reduction, const std::vector<Real>& mass,
                  const std::vector<Real>& rest_diagonal, double inv_h2);

  bool energy_method() const { return energy_; }
  double activation_distance() const { return static_cast<double>(dh_); }

  // A step from time t (positions qt) to t + h: the obstacles moved to
  // t + h, the friction lags from qt, and with "energy" the guess q made to
  // keep every surface vertex outside every obstacle (each body's whole move
  // from qt scaled by one factor). Collective with "energy" (each body's
  // factor's minimum over ranks: one allreduce per step). push_out() then
  // finishes the guess.
  void begin_step(double t, const Real* qt, Real* q);
  // With "energy": each surface vertex an obstacle moved onto in this step
  // (found by begin_step) put back at qt and pushed out along the normal.
  // Apart from begin_step so that moves scaled in between (pairs between
  // bodies) do not undo the push.
  void push_out(const Real* qt, Real* q) const;

  // "projection": moves each surface vertex inside an obstacle at the end of
  // the step to its surface (the obstacle is rigid and immovable, so the
  // vertex takes the whole correction), and cuts its slip by mu times that
  // correction (Coulomb on the impulse); the caller's velocity update
  // then sees the corrected positions. Records the corrections for the
  // stats. Does nothing with "energy".
  void project(Real* q, const Real* qt);

  // Per obstacle, this rank's sums over its owned surface vertices at the end
  // of the step (q): the force the body exerts on the
  // obstacle (xyz; with "energy" the gradient of the contact terms, with
  // "projection" m times the correction over h^2) and the vertices in
  // contact (gap below the activation distance, or corrected); 4 values per
  // obstacle.
  std::vector<double> local_sums(const Real* q) const;
  // The deepest penetration of an owned surface vertex into an obstacle
  // (m, >= 0): of the step's result before any projection.
  double local_penetration(const Real* q) const;

  // This rank's contact energy over its owned surface vertices at q.
  Energy local_energy(const Real* q, const Real* qt) const;

  // Host views of the data above (an engine copies them once, the lags and
  // geometry at every step start).
  ContactView<Real> view() const;
  const std::vector<index_t>& vertices() const { return vertices_; }
  const std::vector<Real>& kappa() const { return kappa_; }
  // Per surface vertex and axis, m/h^2 plus the elastic Hessian diagonal at
  // rest: the stiffness that holds it without contact (ContactView::base).
  const std::vector<Real>& base() const { return base_; }
  const std::vector<FrictionLag<Real>>& lags() const { return lags_; }
  const std::vector<ObstacleGeometry<Real>>& geometry() const { return geometry_; }

 private:
  const LocalMesh& mesh_;
  const std::vector<int> vertex_body_;  // per local vertex
  EnergyReduction& reduction_;
  std::vector<Obstacle> obstacles_;
  bool energy_ = true;
  Real dh_ = 0, eps_h_ = 0, h_ = 0;
  index_t num_owned_ = 0;
  std::vector<index_t> vertices_;
  std::vector<Real> kappa_, base_;
  std::vector<Real> mass_;  // per surface vertex
  std::vector<FrictionLag<Real>> lags_;
  std::vector<ObstacleGeometry<Real>> start_, geometry_;  // at the step's start and end
  std::vector<Real> start_positions_;                     // 3 per surface vertex
  std::vector<std::uint8_t> inside_;  // per surface vertex: an obstacle moved onto it
  // "projection": per obstacle the last step's correction force (xyz) and
  // corrected vertices over owned surface vertices, and the deepest
  // penetration before it.
  std::vector<double> projected_;
  double projected_depth_ = 0;
};

// Where obstacle `obstacle` is at time t (its motion applied).
template <class Real>
ObstacleGeometry<Real> obstacle_geometry(const Obstacle& obstacle, double t);

}  // namespace descent
