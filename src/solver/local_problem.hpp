#pragma once
// One rank's share of the incremental potential eps(q) of implicit Euler
// (DESIGN §1): element terms over its tets, vertex terms over its vertices,
// shared-vertex partial sums completed through the halo, the total energy
// through the one reduction. Methods call only this interface, never MPI.
//
// Layout: every per-vertex array is xyz-interleaved over local vertices
// (LocalMesh order: interior, shared owned, shared not owned).
#include <cstdint>
#include <vector>

#include "comm/halo.hpp"
#include "comm/reduction.hpp"
#include "io/scene.hpp"
#include "kernels/neo_hookean.hpp"
#include "kernels/tet.hpp"
#include "kernels/vertex.hpp"
#include "partition/partition.hpp"

namespace descent {

template <class Real>
class LocalProblem {
 public:
  LocalProblem(const LocalMesh& mesh, const Scene& scene, Halo<Real>& halo,
               EnergyReduction& reduction);

  index_t num_vertices() const { return mesh_.num_vertices(); }
  const LocalMesh& mesh() const { return mesh_; }
  Real dt() const { return dt_; }

  // Lumped mass per local vertex (sum over all ranks' tets, bitwise equal on
  // every sharer) and fixed-axis mask (bit i set: axis i held).
  const std::vector<Real>& mass() const { return mass_; }
  const std::vector<std::uint8_t>& fixed_axes() const { return fixed_; }
  const VertexTerms<Real>& vertex_terms() const { return terms_; }

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
  // positions qt: element terms of its tets plus vertex terms of its owned
  // vertices (each vertex counted by one rank). No communication.
  Energy local_energy(const Real* q, const Real* y, const Real* qt) const;

  // Sums of `count` (1 or 2) local energies over all ranks: the one collective.
  EnergySums global_energies(const Energy* local, int count) {
    return reduction_.sum(local, count);
  }

 private:
  const LocalMesh& mesh_;
  Halo<Real>& halo_;
  EnergyReduction& reduction_;
  NeoHookean<Real> model_;
  Real dt_;
  VertexTerms<Real> terms_;
  std::vector<TetRest<Real>> rest_;
  std::vector<Real> mass_;
  std::vector<std::uint8_t> fixed_;
  std::vector<Real> corner_grad_, corner_diag_;  // 12 per tet
  std::vector<Real> partial_;                    // 3 or 6 per vertex: gradient [, diagonal]
};

}  // namespace descent
