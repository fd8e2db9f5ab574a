#pragma once
// Contact between bodies, and within one with contact.self (issue 21, step
// 3; docs/contact.md): barrier terms of vertex-triangle and edge-edge pairs
// (kernels/pair_contact.hpp) over the contact halo (contact_halo.hpp),
// as part of eps for the Chebyshev iteration on the CPU.
//
// Per step: the pair set is rebuilt at the step start q_t (one allgather
// and one all-to-all) to a reach that covers every pair the step can bring
// within dh: dh + 2 (D + cap), D the guess's largest move from q_t and cap
// the most any surface vertex may then drift from the guess (dh + D), which
// the guard enforces. The guess is pulled back along q - q_t so that no
// pair closes by more than half its gap at q_t (one allreduce). Per
// iteration: the ghosts' positions (neighbour messages only), the terms of
// the pairs around this rank's vertices (each sharer adds the same, as for
// obstacles), and the guard: every surface vertex moves at most
// 0.4 times its nearest pair's distance, so no pair closes by more than
// 0.8 of its gap in one iteration, and no iterate crosses.
#include <array>
#include <vector>

#include "comm/halo.hpp"
#include "comm/reduction.hpp"
#include "contact/contact_halo.hpp"
#include "contact/contact_pairs.hpp"
#include "io/scene.hpp"
#include "kernels/vertex.hpp"

namespace descent {

// Whether a scene has contact between bodies: several bodies, or one with
// contact.self.
inline bool has_body_contact(const Scene& scene) {
  return scene.bodies.size() > 1 || scene.contact.self;
}

template <class Real>
class BodyContact {
 public:
  // Collective. `mass` and `rest_diagonal` as ObstacleContact takes them.
  // Bodies that touch at the start (a pair at distance 0, where the barrier
  // is infinite) are an InputError on every rank.
  BodyContact(const LocalMesh& mesh, const Scene& scene, Halo<Real>& halo,
              EnergyReduction& reduction, const std::vector<Real>& mass,
              const std::vector<Real>& rest_diagonal, double inv_h2);

  // Collective: the pairs for the step from qt, and the guess q (3 per
  // local vertex) pulled back as the header says.
  void begin_step(const Real* qt, Real* q);

  // At q: the gradient of the pairs around this rank's vertices into
  // `partial` (`width` per vertex) and, with width 6, the dominant diagonal
  // of their positive semi-definite Hessians into its diagonal slots;
  // `diag` (may be null) raised to the vertex curvature plus that diagonal.
  // Records each surface vertex's nearest pair for guard().
  void add_gradient(const Real* q, Real* partial, int width, Real* diag,
                    const VertexTerms<Real>& terms, const Real* mass);
  // This rank's share of the pairs' energy at q (each pair counted once).
  double local_energy(const Real* q);
  // The exact Hessian of the pairs at q times v, added to out (3 per vertex).
  void add_hessian_product(const Real* q, const Real* v, Real* out);
  // The move q -> q_next of each free surface vertex cut to 0.4 times its
  // nearest pair's distance at q (the last add_gradient) and to the step's
  // drift cap about the guess.
  void guard(const Real* q, Real* q_next, const std::uint8_t* fixed) const;

  double activation_distance() const { return dh_; }
  // For the stats, at q: this rank's counted pairs within dh, and the least
  // distance of its pairs (1e300 without pairs).
  double local_active_pairs(const Real* q);
  double local_least_distance(const Real* q);

 private:
  // Each pair's barrier terms at the halo's current positions.
  template <class Visit>
  void for_each_pair(Visit&& visit) const;

  const LocalMesh& mesh_;
  EnergyReduction& reduction_;
  ContactHalo<Real> halo_;
  ContactPairs pairs_;
  std::vector<Real> kappa_;  // per local vertex (surface ones meaningful)
  bool self_ = false;
  double dh_ = 0, eps_ = 0, cap_ = 0;
  std::vector<Real> anchor_;   // per contact vertex: the guess (local ones used)
  std::vector<Real> nearest_;  // per contact vertex: its nearest pair's distance
  std::vector<Real> gathered_;
};

}  // namespace descent
