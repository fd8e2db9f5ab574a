#pragma once
// Contact between bodies, and within one with contact.self (issue 21, step
// 3; docs/contact.md): barrier and lagged friction terms (contact.friction)
// of vertex-triangle and edge-edge pairs (kernels/pair_contact.hpp) over the contact halo
// (contact_halo.hpp), as part of eps for the Chebyshev iteration on the CPU.
//
// The pairs are found (one allgather and one all-to-all) about where the
// surface vertices are, each vertex with its own drift cap: a pair is
// found when its distance is below dh plus the largest cap of each side,
// and the guard keeps every surface vertex within its cap of that place, so
// no pair outside the set comes within dh. A vertex's cap is dh plus half
// the mean surface edge, or with contact.self four times the largest drift
// the checks saw of it since the last search, within [dh, that]; a ghost's
// comes from its holder. They are found again at each step's start, and
// after an accepted energy check where a vertex has drifted half its cap
// (the flag costs one allreduce per check).
// At the step's start the guess is first pulled back along q - q_t so that
// no pair closes by more than half its gap along that path (pull_back();
// moves both sides share close nothing), each contact island (bodies linked
// by pairs that may come within dh along the path, contact_islands.hpp) by
// its own fraction. Per iteration: the ghosts'
// positions (neighbour messages only), the terms of the pairs around this
// rank's vertices (each sharer adds the same, as for obstacles), and the
// guard. The guard sends each iteration's proposed moves to the ghosts'
// holders (one more neighbour message, 3 reals per ghost) and cuts each
// surface vertex's move to the least fraction any of its pairs allows:
// the share of the path along which the pair keeps pair_kept_gap() of its
// gap (kernels/pair_path.hpp). Vertices cut by different fractions may
// still close a pair, so at the next exchange every pair's path is proven
// free of crossings; one that is not makes the step's next energy check
// infinite (no extra collective): the check rolls back, and the rest of
// the step runs the safe guard on every rank (use_safe_guard()), which cuts
// every vertex's own move to half of what its nearest pair may close, so no
// two sides can cross.
#include <array>
#include <chrono>
#include <vector>

#include "comm/halo.hpp"
#include "comm/reduction.hpp"
#include "contact/contact_halo.hpp"
#include "contact/contact_pairs.hpp"
#include "io/scene.hpp"
#include "kernels/pair_contact.hpp"
#include "kernels/pair_path.hpp"
#include "kernels/vertex.hpp"

namespace descent {

// Whether a scene has contact between bodies: several bodies, or one with
// contact.self.
inline bool has_body_contact(const Scene& scene) {
  return scene.bodies.size() > 1 || scene.contact.self;
}

// Whether a scene's eps holds contact barriers: obstacles or contact between
// bodies with contact.method = "energy".
inline bool has_contact_barrier(const Scene& scene) {
  return scene.contact.method == "energy" && (!scene.obstacles.empty() || has_body_contact(scene));
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

  // Collective: the guess q (3 per local vertex) for the step from qt
  // pulled back as the header says. A step then calls rebuild_here(q).
  void pull_back(const Real* qt, Real* q);
  // Collective: the pairs about q (3 per local vertex), the guard's anchor
  // there.
  void rebuild_here(const Real* q);
  // Whether a local surface vertex of q (3 per local vertex) has drifted
  // half its cap from where the pairs were found; each drift is kept for
  // the next search's caps. No communication.
  bool needs_rebuild(const Real* q);

  // At q: the gradient of the pairs around this rank's vertices into
  // `partial` (`width` per vertex) and, with width 6, the dominant diagonal
  // of their positive semi-definite Hessians into its diagonal slots;
  // `diag` (may be null) raised to the vertex curvature plus that diagonal.
  // Records each surface vertex's nearest pair for guard().
  void add_gradient(const Real* q, Real* partial, int width, Real* diag,
                    const VertexTerms<Real>& terms, const Real* mass);
  // This rank's share of the pairs' energy at q (each pair counted once);
  // +inf when a path since the last energy was not proven free of crossings.
  double local_energy(const Real* q);
  // This rank's share of the pairs' energy at q, barrier and friction, each
  // pair counted once, leaving every state of the iteration as it is (the
  // guard's paths, the skip bounds, the timers): for a study's measurements
  // between iterations. Collective with the contact neighbours.
  double measured_energy(const Real* q) const;
  // The pairs' Hessian at q, exact or in the positive semi-definite form
  // (`hessian`), times v, added to out (3 per vertex). Collective with the
  // contact neighbours (v's ghosts).
  void add_hessian_product(const Real* q, const Real* v, Real* out,
                           PairHessian hessian = PairHessian::exact);
  // For Newton (solver/methods/newton.hpp), at q: the diagonal of the pairs'
  // positive semi-definite Hessians added to diag (3 per vertex) on the
  // dofs `fixed` leaves free; and, collective with the contact neighbours,
  // the largest s in [0, 1] (this rank's part: the caller takes the least
  // over ranks) for which the move s dq from q keeps every pair's distance
  // above pair_kept_gap() of it (kernels/pair_path.hpp, proven along the
  // path) and every local contact vertex within the drift cap of where the
  // pairs were found, so that no pair outside the set comes within dh.
  void add_hessian_diagonal(const Real* q, Real* diag, const std::uint8_t* fixed);
  double path_fraction(const Real* q, const Real* dq);
  // Collective with the contact neighbours: the move q -> q_next of each
  // free surface vertex cut as the header says (q: the last add_gradient's)
  // and to the step's drift cap about the guess. A vertex whose move is cut
  // gets q = q_next: the iteration's momentum (q_next - q next time) would
  // otherwise carry it on into the pair, closing the gap by the same share
  // every iteration however hard the barrier pushes back.
  void guard(Real* q, Real* q_next, const std::uint8_t* fixed);
  // For methods that take no momentum from one iterate to the next (gd,
  // jacobi_gd, lbfgs): the move q -> q_next cut as guard() cuts it (q left
  // as it is), then proven free of crossings at once on every rank (one more
  // neighbour message and one allreduce; guard() leaves that to the next
  // exchange). Where any rank cannot prove it, every rank switches to the
  // safe guard for the rest of the step and cuts the move again from its
  // proposal, so no iterate crosses. The ghosts then hold q_next's
  // positions (the unproven one's after a second cut).
  void guard_proven(const Real* q, Real* q_next, const std::uint8_t* fixed);
  // The safe guard for the rest of the step. Called on every rank after a
  // check whose energy was not finite, which an unproven path on any rank
  // makes it: switched on the detecting rank alone, its neighbours went on
  // waiting for the path guard's exchange (3 ranks deadlocked on two bodies
  // thrown at each other), and the ranks' iterates differed from one rank's.
  void use_safe_guard() { safe_ = true; }
  bool safe_guard_on() const { return safe_; }
  // Whether the last guard_proven() cut a move on any rank.
  bool moves_cut() const { return moves_cut_; }

  double activation_distance() const { return dh_; }

  // Wall seconds on this rank so far, by part: the pair search with its
  // rebuild of the halo and the guess's pull-back (search), the ghosts'
  // positions (ghosts), the pairs' terms (terms), the guard (guard).
  struct Seconds {
    double search = 0, ghosts = 0, terms = 0, guard = 0;
  };
  // Paths between iterates this rank could not prove free of crossings
  // (each made a check roll back), so far.
  long paths_caught() const { return paths_caught_; }
  const Seconds& seconds() const { return seconds_; }
  // For the stats, at q: this rank's counted pairs within dh, the least
  // distance of its pairs, and per body the force the pairs put on its
  // vertices that this rank owns.
  PairStats local_pair_stats(const Real* q);

 private:
  // The guard's anchor and the pairs' skip bounds from the halo's positions
  // now (after the pairs are found).
  void track_from_here();
  // The halo's positions at q, timed; after a guarded iteration, each
  // pair's path there checked.
  void update_ghosts(const Real* q);
  // Whether every pair's straight path from last_ to the halo's positions
  // is proven free of crossings.
  bool paths_clear();
  // moves_ <- each contact vertex's move from `from` to `to` (3 per contact
  // vertex); moved(v): the sum over a pair's vertices, which bounds its
  // closing rate (kernels/pair_path.hpp) without gathering its coordinates.
  void measure_moves(const std::vector<Real>& from, const std::vector<Real>& to);
  // visit(kind, vertices, x0, x1) with each pair's 12 coordinates in `from`
  // and `to` (3 per contact vertex), for the pairs skip(pair index,
  // vertices) does not settle from moves_ (measure_moves(from, to) first).
  template <class Skip, class Visit>
  void for_each_path(const std::vector<Real>& from, const std::vector<Real>& to, Skip&& skip,
                     Visit&& visit);
  double moved(const std::array<index_t, 4>& v) const;
  // A lower bound on pair's distance at last_.
  double gap_bound(std::size_t pair, const std::array<index_t, 4>& v) const;
  // The guards (guard()): cutting each vertex's move by the fractions of
  // its pairs' paths (relative), or to its nearest pair's gap (safe).
  void cut_by_pair_paths(Real* q_next, const std::uint8_t* fixed);
  // Either of those (the safe one once switched on, none without pairs),
  // then the drift cap about the guess; cut_ holds each local contact
  // vertex's fraction (< 1: cut).
  void cut_move(const Real* q, Real* q_next, const std::uint8_t* fixed);
  void cut_by_nearest_gap(const Real* q, Real* q_next, const std::uint8_t* fixed);
  // The pair's 12 coordinates from `p` (3 per contact vertex) into x; returns
  // its stiffness, the mean of its vertices'.
  Real gather_pair_with_stiffness(const std::vector<Real>& p, const std::array<index_t, 4>& v,
                                  Real* x) const;
  // The pair's barrier and friction terms at x (its 12 coordinates).
  PairTerms<Real> terms_of(PairKind kind, std::size_t pair, const std::array<index_t, 4>& v,
                           const Real* x, Real kappa, PairHessian hessian) const;
  // visit(kind, vertices, x, kappa, pair index) for each pair at the halo's current
  // positions, returning its distance (or < 0: not evaluated). With
  // skip_far, a pair whose last distance less its vertices' travel since
  // then exceeds dh is not visited (it has no barrier term, and no friction
  // if its lag has none), its bound only lowering its local vertices'
  // nearest distance.
  template <class Visit>
  void for_each_pair(bool skip_far, Visit&& visit);

  const LocalMesh& mesh_;
  const std::vector<int> vertex_body_;  // per local vertex
  EnergyReduction& reduction_;
  ContactHalo<Real> halo_;
  ContactPairs pairs_;
  std::vector<Real> kappa_;  // per local vertex (surface ones meaningful)
  bool self_ = false;
  double mu_ = 0, eps_h_ = 0;  // contact.friction; smoothing velocity x dt
  double dh_ = 0, eps_ = 0;
  double cap_max_ = 0;              // dh plus half the mean surface edge
  double cap_ = 0;                  // the largest cap of the last search
  std::vector<double> caps_;        // per contact vertex: its drift cap
  std::vector<double> drift_seen_;  // per local contact vertex: since the search
  std::vector<Real> anchor_;        // per contact vertex: the guess (local ones used)
  std::vector<Real> proposed_;      // per contact vertex: the guarded iteration's q_next
  std::vector<double> cut_;         // per local contact vertex: the guard's fraction (< 1: cut)
  std::vector<double> moves_;       // per contact vertex: measure_moves()
  bool safe_ = false;               // the safe guard, for the rest of the step
  bool moves_cut_ = false;          // the last guard_proven() cut a move somewhere
  bool any_pairs_ = true;           // a pair on some rank at the last search
  bool verify_paths_ = false;       // the next update_ghosts checks the pairs' paths
  bool crossing_ = false;           // a path was not proven; the next energy is infinite
  long paths_caught_ = 0;
  std::vector<Real> nearest_;  // per contact vertex: its nearest pair's distance
  std::vector<Real> gathered_;
  std::vector<Real> contact_diagonal_;  // add_gradient's, 3 per local contact vertex
  // Per contact vertex: path length since begin_step, and where it was.
  std::vector<double> travel_;
  std::vector<Real> last_;
  // Per pair (vertex-triangle, then edge-edge): its distance when last
  // evaluated and its vertices' summed travel then (< 0: not yet).
  std::vector<double> checked_distance_, checked_travel_;
  // The step start: q_t per local vertex, per contact vertex, and each
  // pair's friction lag from it.
  std::vector<Real> qt_, start_;
  std::vector<PairFrictionLag<Real>> lags_;
  mutable Seconds seconds_;
};

}  // namespace descent
