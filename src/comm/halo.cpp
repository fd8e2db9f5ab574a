#include "comm/halo.hpp"

#include <algorithm>

#include "comm/mpi_check.hpp"
#include "comm/mpi_type.hpp"
#include "common/error.hpp"
#include "partition/local_mesh.hpp"

namespace descent {

namespace {

constexpr int kHaloTag = 7101;

}  // namespace

HaloPattern halo_pattern(const LocalMesh& mesh) {
  return {mesh.rank, mesh.num_interior, mesh.num_vertices(), mesh.neighbours, mesh.shared_with};
}

template <class Real>
Halo<Real>::Halo(MPI_Comm comm, const HaloPattern& pattern)
    : comm_(comm),
      first_shared_(pattern.first_shared),
      neighbours_(pattern.neighbours),
      shared_with_(pattern.shared_with) {
  const index_t num_shared = pattern.num_entries - pattern.first_shared;
  // Terms of each shared vertex as (rank, source), sorted by rank.
  std::vector<std::vector<std::pair<int, Source>>> terms(num_shared);
  for (index_t s = 0; s < num_shared; ++s) terms[s].push_back({pattern.rank, Source{-1, 0}});
  for (std::size_t n = 0; n < neighbours_.size(); ++n) {
    for (std::size_t slot = 0; slot < shared_with_[n].size(); ++slot) {
      const index_t v = shared_with_[n][slot];
      DESCENT_VERIFY(v >= first_shared_, "vertex ", v, " shared with rank ", neighbours_[n],
                     " is not in the shared range");
      terms[v - first_shared_].push_back(
          {neighbours_[n], Source{static_cast<int>(n), static_cast<index_t>(slot)}});
    }
  }
  plan_offsets_.assign(num_shared + 1, 0);
  for (index_t s = 0; s < num_shared; ++s) {
    auto& t = terms[s];
    std::sort(t.begin(), t.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    for (const auto& [rank, source] : t) plan_.push_back(source);
    plan_offsets_[s + 1] = static_cast<index_t>(plan_.size());
  }
  send_.resize(neighbours_.size());
  recv_.resize(neighbours_.size());
  requests_.resize(2 * neighbours_.size());
}

template <class Real>
void Halo<Real>::begin(const Real* values, int width) {
  const double start = MPI_Wtime();
  width_ = width;
  const int count = static_cast<int>(neighbours_.size());
  for (int n = 0; n < count; ++n) {
    const auto& ids = shared_with_[n];
    recv_[n].resize(ids.size() * width);
    send_[n].resize(ids.size() * width);
    DESCENT_MPI_CHECK(MPI_Irecv(recv_[n].data(), static_cast<int>(recv_[n].size()),
                                mpi_type<Real>(), neighbours_[n], kHaloTag, comm_, &requests_[n]));
  }
  for (int n = 0; n < count; ++n) {
    const auto& ids = shared_with_[n];
    Real* out = send_[n].data();
    for (std::size_t k = 0; k < ids.size(); ++k)
      for (int c = 0; c < width; ++c)
        out[k * width + c] = values[static_cast<std::size_t>(ids[k]) * width + c];
    DESCENT_MPI_CHECK(MPI_Isend(send_[n].data(), static_cast<int>(send_[n].size()),
                                mpi_type<Real>(), neighbours_[n], kHaloTag, comm_,
                                &requests_[count + n]));
    counters_.bytes_sent += static_cast<long>(send_[n].size() * sizeof(Real));
  }
  counters_.messages_sent += count;
  ++counters_.exchanges;
  counters_.seconds += MPI_Wtime() - start;
}

template <class Real>
void Halo<Real>::finish(Real* values, int width) {
  DESCENT_VERIFY(width == width_, "finish(width ", width, ") after begin(width ", width_, ")");
  const double start = MPI_Wtime();
  DESCENT_MPI_CHECK(
      MPI_Waitall(static_cast<int>(requests_.size()), requests_.data(), MPI_STATUSES_IGNORE));
  const index_t num_shared = static_cast<index_t>(plan_offsets_.size()) - 1;
  Real total[kMaxWidth];
  DESCENT_VERIFY(width <= kMaxWidth, "halo width ", width, " > ", kMaxWidth);
  for (index_t s = 0; s < num_shared; ++s) {
    Real* own = values + static_cast<std::size_t>(first_shared_ + s) * width;
    for (int c = 0; c < width; ++c) total[c] = 0;
    for (index_t k = plan_offsets_[s]; k < plan_offsets_[s + 1]; ++k) {
      const Source& src = plan_[k];
      const Real* term = src.neighbour < 0 ? own
                                           : recv_[src.neighbour].data() +
                                                 static_cast<std::size_t>(src.slot) * width;
      for (int c = 0; c < width; ++c) total[c] += term[c];
    }
    for (int c = 0; c < width; ++c) own[c] = total[c];
  }
  counters_.seconds += MPI_Wtime() - start;
}

template <class Real>
void Halo<Real>::sum(Real* values, int width) {
  begin(values, width);
  finish(values, width);
}

template class Halo<double>;
template class Halo<float>;

}  // namespace descent
