#pragma once
// Exchange of shared-vertex partial sums among all sharers (DESIGN §3).
//
// Every rank computes partial sums (gradient, Hessian diagonal, mass) for its
// local vertices from its own tets. For a shared vertex, each sharer sends its
// partial to every other sharer; each then forms the total by adding all
// sharers' partials in ascending rank order, so every sharer holds the
// bitwise-identical total and updates the vertex redundantly. One exchange per
// iteration, no owner/ghost round trip.
//
// Split phase (overlap): begin() packs the shared vertices' partials and posts
// nonblocking sends and receives; finish() waits and writes the totals in
// place. Layout: `values` holds `width` reals per local vertex
// ([width * v + c]); shared vertices are local ids [first_shared, num_vertices).
// Widths up to kMaxWidth.
#include <mpi.h>

#include <vector>

#include "common/mesh.hpp"

namespace descent {

struct LocalMesh;

// Who shares which entries with whom: of a LocalMesh's vertices, or of the
// nodes of one level of a multilevel hierarchy. Entries [first_shared,
// num_entries) are shared; per neighbour rank (ascending) the local ids it
// shares in ascending global id, the same order on both sides.
struct HaloPattern {
  int rank = 0;
  index_t first_shared = 0;
  index_t num_entries = 0;
  std::vector<int> neighbours;
  std::vector<std::vector<index_t>> shared_with;
};
HaloPattern halo_pattern(const LocalMesh& mesh);

struct HaloCounters {
  long exchanges = 0;
  long messages_sent = 0;
  long bytes_sent = 0;
  double seconds = 0;  // wall time inside begin() and finish()
};

template <class Real>
class Halo {
 public:
  static constexpr int kMaxWidth = 8;
  Halo(MPI_Comm comm, const HaloPattern& pattern);
  Halo(MPI_Comm comm, const LocalMesh& mesh) : Halo(comm, halo_pattern(mesh)) {}

  void begin(const Real* values, int width);
  void finish(Real* values, int width);
  // begin() then finish(), for set-up sums (masses) with nothing to overlap.
  void sum(Real* values, int width);

  const HaloCounters& counters() const { return counters_; }
  int num_neighbours() const { return static_cast<int>(neighbours_.size()); }
  MPI_Comm comm() const { return comm_; }

 private:
  // Where one term of a shared vertex's total comes from: this rank's own
  // partial (neighbour == -1) or slot `slot` of neighbour `neighbour`'s buffer.
  struct Source {
    int neighbour;
    index_t slot;
  };

  MPI_Comm comm_;
  index_t first_shared_ = 0;
  std::vector<int> neighbours_;
  std::vector<std::vector<index_t>> shared_with_;
  std::vector<index_t> plan_offsets_;  // CSR over shared vertices, sources in rank order
  std::vector<Source> plan_;
  std::vector<std::vector<Real>> send_, recv_;
  std::vector<MPI_Request> requests_;
  int width_ = 0;
  HaloCounters counters_;
};

}  // namespace descent
