#pragma once
// The surface that contact between bodies sees on one rank (issue 21, step
// 3): this rank's surface vertices and the triangles its tets hold, plus the
// contact halo, the surface triangles of other ranks that lie near this
// rank's surface, with their vertices ("ghosts").
//
// Near: a triangle of rank s comes to rank r when its bounding box meets the
// box of r's surface vertices grown by `reach` + the longest surface edge
// of any rank (for paths, the boxes of both ends and the longest edge at
// either). So every pair of primitives closer than `reach` that touches
// a vertex of r is complete on r: the other primitive lies within reach of
// a primitive through that vertex, which lies within one edge of it.
//
// Rebuilt collectively (one MPI_Allgather of boxes, one all-to-all of
// triangles and vertices: rebuild()); between rebuilds, each iteration
// refreshes the ghosts' positions with messages to the contact neighbours
// only (update_ghosts(): no collective), 3 reals per ghost vertex.
//
// Contact vertex numbering: [local surface vertices (ascending local id) |
// ghosts (ascending global id)].
#include <mpi.h>

#include <array>
#include <unordered_map>
#include <vector>

#include "comm/halo.hpp"
#include "partition/local_mesh.hpp"

namespace descent {

template <class Real>
class ContactHalo {
 public:
  // Collective over the halo's communicator: marks the surface vertices on
  // every sharer (one halo sum). `mesh` must outlive the object.
  ContactHalo(const LocalMesh& mesh, Halo<Real>& halo);

  // Collective: the ghosts and triangles for positions q (3 per local
  // vertex) and this reach. `carried` (one per local vertex, or empty)
  // travels with the ghosts: carried() gives it per contact vertex. With
  // `to` (3 per local vertex), for the straight paths from q to `to`: a
  // triangle's box and a rank's surface box then cover both ends.
  void rebuild(const Real* q, double reach, const std::vector<Real>& carried = {},
               const Real* to = nullptr);
  // Neighbour messages only: `values` (3 per local vertex, the same on
  // every sharer) per contact vertex into `out`, the ghosts' from their
  // holders.
  void gather(const Real* values, std::vector<Real>& out) const;
  // gather() of positions q into positions().
  void update_ghosts(const Real* q) { gather(q, positions_); }

  index_t num_local() const { return num_local_; }
  index_t num_vertices() const { return static_cast<index_t>(global_id_.size()); }
  // Per contact vertex: its local vertex (local ones; -1 for ghosts), its
  // global id, its body, and whether this rank owns it.
  const std::vector<index_t>& local_vertex() const { return local_vertex_; }
  const std::vector<global_index_t>& global_id() const { return global_id_; }
  const std::vector<int>& body() const { return body_; }
  bool owned(index_t c) const { return c < num_local_ && local_vertex_[c] < mesh_.num_owned; }
  // Surface triangles (contact vertex indices, counter-clockwise seen from
  // outside): this rank's, then the halo's.
  const std::vector<std::array<index_t, 3>>& triangles() const { return triangles_; }
  // The triangles' vertices (ascending) and their edges, each once with the
  // lesser global id first, in global id order: what the pair search
  // queries. Derived again only where a rebuild changed the triangles.
  const std::vector<index_t>& triangle_vertices() const { return triangle_vertices_; }
  const std::vector<std::array<index_t, 2>>& edges() const { return edges_; }
  // xyz per contact vertex, as of the last rebuild or update_ghosts.
  const std::vector<Real>& positions() const { return positions_; }
  const std::vector<Real>& carried() const { return carried_; }
  // Ranks this one receives ghosts from and sends them to.
  const std::vector<int>& sources() const { return sources_; }
  const std::vector<int>& destinations() const { return destinations_; }

 private:
  const LocalMesh& mesh_;
  MPI_Comm comm_;
  std::vector<index_t> surface_;                       // local surface vertices, ascending
  std::vector<std::array<index_t, 3>> own_triangles_;  // local vertex ids
  index_t num_local_ = 0;
  std::vector<index_t> local_vertex_;
  std::vector<global_index_t> global_id_;
  std::vector<int> body_;
  // triangle_vertices_ and edges_ from triangles_ and global_id_.
  void derive_primitives();

  std::vector<std::array<index_t, 3>> triangles_;
  std::vector<index_t> triangle_vertices_;
  std::vector<std::array<index_t, 2>> edges_;
  // What the primitives were derived from, to skip a rebuild that kept them.
  std::vector<std::array<index_t, 3>> derived_triangles_;
  std::vector<global_index_t> derived_ids_;
  std::vector<Real> positions_;
  std::vector<Real> carried_;
  // Per destination: local vertices whose positions it gets; per source: the
  // contact index each received position goes to (-1: a vertex local here).
  std::vector<int> destinations_, sources_;
  std::vector<std::vector<index_t>> send_vertices_;
  std::vector<std::vector<index_t>> receive_slots_;
  // gather()'s message buffers, kept between its calls.
  mutable std::vector<std::vector<Real>> sending_, receiving_;
  mutable std::vector<MPI_Request> requests_;
};

}  // namespace descent
