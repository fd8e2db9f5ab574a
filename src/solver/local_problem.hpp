#pragma once
// One rank's share of the incremental potential eps(q) of implicit Euler
// (DESIGN §1): element terms over its tets, vertex terms over its vertices,
// shared-vertex partial sums completed through the halo, the total energy
// through the one reduction. Methods call only this interface, never MPI.
//
// Layout: every per-vertex array is xyz-interleaved over local vertices
// (LocalMesh order: interior, shared owned, shared not owned).
#include <algorithm>
#include <cstdint>
#include <memory>
#include <vector>

#include "comm/halo.hpp"
#include "comm/reduction.hpp"
#include "contact/body_contact.hpp"
#include "contact/body_projection.hpp"
#include "contact/obstacle_contact.hpp"
#include "io/scene.hpp"
#include "kernels/conversion.hpp"
#include "kernels/cpu/host_exec.hpp"
#include "kernels/element_out.hpp"
#include "kernels/tet.hpp"
#include "kernels/vertex.hpp"
#include "partition/local_mesh.hpp"
#include "solver/material.hpp"
#include "solver/stepper.hpp"

namespace descent {

template <class Real>
class LocalProblem {
 public:
  // Collective (masses and load weights are completed through the halo and
  // the reduction). A [[load]] region that holds no surface face of the
  // whole mesh is an InputError naming it, on every rank.
  LocalProblem(const LocalMesh& mesh, const Scene& scene, Halo<Real>& halo,
               EnergyReduction& reduction);

  index_t num_vertices() const { return mesh_.num_vertices(); }
  const LocalMesh& mesh() const { return mesh_; }
  // The rank's exchange of shared-vertex partial sums (for an iteration
  // engine, which assembles its own).
  Halo<Real>& halo() { return halo_; }
  Real dt() const { return dt_; }

  // Lumped mass per local vertex (sum over all ranks' tets, bitwise equal on
  // every sharer) and fixed-axis mask (bit i set: axis i held).
  const std::vector<Real>& mass() const { return mass_; }
  const std::vector<std::uint8_t>& fixed_axes() const { return fixed_; }
  const VertexTerms<Real>& vertex_terms() const { return terms_; }
  // Lower bound of the diagonal per dof (kernels/vertex.hpp, dof_diagonal).
  const std::vector<Real>& diagonal_floor() const { return diagonal_floor_; }
  // The Hessian diagonal at rest per dof (elastic plus, in dynamics, the
  // inertia's): weights the resolution of states in Real in the energy's
  // magnitude (loops::local_energy).
  const std::vector<Real>& rest_curvature() const { return rest_curvature_; }
  // External (surface-load) force per dof at the time of the current step.
  const std::vector<Real>& external_force() const { return external_force_; }

  // Sets the loads to their values at time t (the end of the step).
  void begin_step(double t);
  // Contact with the scene's obstacles (null without [[obstacle]]): its
  // terms join eps (contact.method = "energy"), or it corrects each step's
  // result ("projection").
  ObstacleContact<Real>* contact() { return contact_.get(); }
  const ObstacleContact<Real>* contact() const { return contact_.get(); }
  // Contact between bodies (null without several bodies or contact.self):
  // pair terms of eps that the Chebyshev engine adds on the CPU
  // (contact.method = "energy"), or the pass that corrects each step's
  // result ("projection"); one of them at most.
  BodyContact<Real>* body_contact() { return body_contact_.get(); }
  const BodyContact<Real>* body_contact() const { return body_contact_.get(); }
  BodyProjection<Real>* body_projection() { return body_projection_.get(); }
  // A step from time t (step-start positions qt) with guess q: the
  // obstacles placed for it and q kept outside them (ObstacleContact::
  // begin_step), the pairs between bodies found and q pulled back so none
  // closes too far (BodyContact::begin_step); nothing without contact.
  // Called after the guess is made; collective with contact.
  void begin_contact_step(double t, const Real* qt, Real* q);
  // Whether eps holds contact barriers: obstacles or pairs between bodies
  // with contact.method = "energy".
  bool has_contact_barrier() const;
  // For methods beyond chebyshev (gd, jacobi_gd, nesterov, ncg, lbfgs) with
  // contact barriers: their gradient at q (step start qt), and with width 6
  // their dominant diagonal, added to the partials the last elastic_gradient
  // assembled (`width` per vertex); `diag` (may be null; 3 per vertex)
  // raised to the vertex curvature plus that diagonal, as chebyshev's
  // iterations between refreshes raise theirs. Records each surface
  // vertex's nearest pair for guard_contact_moves().
  void add_contact_gradient(const Real* q, const Real* qt, int width, Real* diag);
  // The Chebyshev engine's guard for those methods: each surface vertex's
  // move from q (the last add_contact_gradient's) to q_next cut so that it
  // enters no obstacle and crosses no surface of the bodies. Unlike
  // chebyshev, which lets its next energy check roll back a move whose
  // pair paths could not be proven, each move is proven at once (one more
  // neighbour message and one allreduce per iteration with pairs) and,
  // where it is not, cut again by the safe guard for the rest of the step
  // (BodyContact::guard_proven), so no iterate crosses.
  // Collective with the contact neighbours.
  void guard_contact_moves(const Real* q, Real* q_next);
  // The step's result q corrected by the projection pass (contact.method =
  // "projection"), before the velocity is formed from it.
  void end_contact_step(Real* q, const Real* qt);

  // Writes the prescribed positions at time t into the held dofs of q.
  void hold_fixed(double t, Real* q) const;

  // Per region, this rank's sums over its owned vertices, for the stats:
  // fixed region r: [displacement xyz, vertex count, reaction xyz] (the
  // reaction is grad eps on the held dofs: the force the support exerts);
  // load region r: [displacement xyz, vertex count]. Fixed regions first.
  // Evaluates the gradient (one halo exchange), no collective.
  std::vector<double> local_region_sums(const Real* q, const Real* y, const Real* qt);

  // Elastic gradient, and the elastic Hessian diagonal when `with_diagonal`,
  // complete on every local vertex (shared ones summed over all sharers).
  // Boundary tets first, the exchange overlapped with the interior.
  // Result: `width` reals per vertex, gradient xyz at [width v, +3) and, with
  // the diagonal (width 6), its xyz at [width v + 3, +3). Valid until the next call.
  struct Assembled {
    const Real* values;
    int width;
  };
  Assembled elastic_gradient(const Real* q, bool with_diagonal);

  // This rank's share of eps(q) with inertial target y and step-start
  // positions qt: element terms of its tets plus vertex terms (and contact
  // terms) of its owned vertices (each vertex counted by one rank). No
  // communication.
  Energy local_energy(const Real* q, const Real* y, const Real* qt) const;

  // The first non-finite value of this rank's share of eps(q) (positions,
  // inertial targets, element terms, vertex terms, in that order), for a
  // message naming it; Kind::none when every local term is finite. A serial
  // scan without communication (solver/non_finite_scan.cpp): called only
  // after the reduction reported a non-finite energy, never per iteration.
  NonFiniteSite find_non_finite(const Real* q, const Real* y, const Real* qt) const;

  // The energy change below which a check sees no change: the round-off of
  // the elastic terms at rest, where each is a difference of O(mu)
  // quantities (mu/2 (I1bar - 3), ...) whose value, and so the magnitude
  // the round-off of a check is scaled by, is 0: 64 eps mu V with V the
  // body's volume (quasi-static equilibria, near-rest states). The same on
  // every rank.
  double energy_noise_floor() const { return energy_noise_floor_; }

  // Whether eps itself changes between iterations of one step (model
  // conversion updates its interpolants at every gradient evaluation).
  bool energy_changes_within_step() const { return converting_; }

  // Conversion interpolants per local tet (empty without conversion).
  const std::vector<Real>& interpolants() const { return interpolant_; }
  void set_interpolants(std::vector<Real> values) { interpolant_ = std::move(values); }

  // For methods beyond chebyshev (solver/methods/): the rest data and model
  // the element terms use, corner values (12 per tet, layout of
  // kernels/cpu/element_loops.hpp) summed to vertices with shared vertices
  // completed through the halo (3 per vertex, out), and fused global sums of
  // inner products and a global maximum (each one counted MPI_Allreduce).
  const std::vector<TetRest<Real>>& rest() const { return rest_; }
  const ElasticModel<Real>& model() const { return model_; }
  // The conversion parameters (meaningful when energy_changes_within_step()).
  const Conversion<Real>& conversion() const { return conversion_; }
  void assemble_corners(const Real* corner_values, Real* out);
  // The same sums from an element pass: pass(o) puts each tet's 12 values
  // to the loops::ElementOut o. With one thread they are added to out in tet
  // order (zeroed first; kernels/element_out.hpp), bitwise the gather's sums
  // without the corner arrays; with threads through corner_values and
  // assemble_corners.
  template <class Pass>
  void assemble_elements(Real* corner_values, Real* out, const Pass& pass) {
    loops::ElementOut<Real> o;
    if (HostExec().serial()) {
      std::fill(out, out + 3 * static_cast<std::size_t>(mesh_.num_vertices()), Real(0));
      o.partial = out;
      o.in_order = true;
      pass(o);
      halo_.sum(out, 3);
      return;
    }
    o.corner_grad = corner_values;
    pass(o);
    assemble_corners(corner_values, out);
  }
  void global_dots(double* values, int count) { reduction_.sum_dots(values, count); }
  double global_max(double value) { return reduction_.max_of(value); }

  // Sums of `count` (1 or 2) local energies over all ranks: the one collective.
  EnergySums global_energies(const Energy* local, int count) {
    return reduction_.sum(local, count);
  }

  // The gathers to rank 0 and scatters from it of Newton's direct solver
  // (solver/methods/newton_ldlt.hpp); no other method uses them.
  EnergyReduction& reduction() { return reduction_; }

 private:
  const LocalMesh& mesh_;
  Halo<Real>& halo_;
  EnergyReduction& reduction_;
  // Runs the element pass (the gradient and, when with_diagonal, the
  // diagonal to `out`) over tets [begin, end) with the scene's model and
  // conversion.
  void element_pass(const Real* q, index_t begin, index_t end, bool with_diagonal,
                    const loops::ElementOut<Real>& out);

  ElasticModel<Real> model_;
  double energy_noise_floor_ = 0;
  bool converting_ = false;
  Conversion<Real> conversion_{};
  std::vector<Real> interpolant_;  // conversion l per tet (Eq. 17), when converting
  Real dt_;
  VertexTerms<Real> terms_;
  std::vector<FixedRegion> fixed_regions_;
  std::vector<LoadRegion> load_regions_;
  std::vector<std::vector<double>> load_weights_;  // per load region, per local vertex
  std::vector<int> motion_region_;    // per local vertex: fixed region moving it, or -1
  std::vector<Real> external_force_;  // 3 per local vertex
  std::vector<Real> diagonal_floor_;  // 3 per local vertex
  std::vector<Real> rest_curvature_;  // 3 per local vertex
  std::vector<TetRest<Real>> rest_;
  std::vector<Real> mass_;
  std::vector<std::uint8_t> fixed_;
  std::vector<Real> corner_grad_, corner_diag_;  // 12 per tet
  std::vector<Real> partial_;                    // 3 or 6 per vertex: gradient [, diagonal]
  mutable std::vector<double> tet_energy_;       // one per tet: local_energy's scratch
  std::unique_ptr<ObstacleContact<Real>> contact_;
  std::unique_ptr<BodyContact<Real>> body_contact_;
  std::unique_ptr<BodyProjection<Real>> body_projection_;
};

}  // namespace descent
