#include "partition/geometric_partition.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <limits>
#include <utility>

#include "comm/exchange.hpp"
#include "comm/mpi_check.hpp"
#include "common/error.hpp"

namespace descent {
namespace {

struct Position {
  double xyz[3];
};

// An unsigned integer that orders as the double does (negative values
// reversed), so a split point is found digit by digit.
std::uint64_t ordered_key(double x) {
  std::uint64_t bits = 0;
  std::memcpy(&bits, &x, sizeof bits);
  return (bits >> 63) != 0 ? ~bits : bits | (std::uint64_t{1} << 63);
}

// The 128-bit key of a tet: its centroid's coordinate along the split's
// axis, then its global id, which makes every key distinct.
using Key = std::pair<std::uint64_t, std::uint64_t>;

constexpr int kDigitBits = 8;
constexpr int kBins = 1 << kDigitBits;
constexpr int kKeyDigits = 128 / kDigitBits;

// Digit `round` of a key, the most significant first.
int key_digit(const Key& key, int round) {
  const std::uint64_t word = round < kKeyDigits / 2 ? key.first : key.second;
  const int shift = 64 - kDigitBits * (round % (kKeyDigits / 2) + 1);
  return static_cast<int>((word >> shift) & (kBins - 1));
}

void set_digit(Key& key, int round, int digit) {
  std::uint64_t& word = round < kKeyDigits / 2 ? key.first : key.second;
  word |= static_cast<std::uint64_t>(digit) << (64 - kDigitBits * (round % (kKeyDigits / 2) + 1));
}

}  // namespace

std::vector<double> tet_centroids(MPI_Comm comm, const MeshSlice& slice) {
  int size = 1;
  MPI_Comm_size(comm, &size);
  const BlockRange vertex_blocks(slice.num_global_vertices, size);
  const global_index_t first = slice.first_vertex, last = first + slice.num_vertices();
  for (const global_index_t v : slice.tets)
    DESCENT_VERIFY(v >= 0 && v < slice.num_global_vertices, "vertex id ", v,
                   " out of range: slices are validated when read");

  // Corners in other blocks, each asked once; the answers come back by rank
  // in rank order, so they line up with the ascending list.
  std::vector<global_index_t> remote;
  for (const global_index_t v : slice.tets)
    if (v < first || v >= last) remote.push_back(v);
  std::sort(remote.begin(), remote.end());
  remote.erase(std::unique(remote.begin(), remote.end()), remote.end());
  Outbox<global_index_t> asks(size);
  for (const global_index_t v : remote) asks.count(vertex_blocks.owner(v));
  asks.allocate();
  for (const global_index_t v : remote) asks.place(vertex_blocks.owner(v), v);
  const Inbox<global_index_t> asked = exchange(comm, asks);
  Outbox<Position> answers(size);
  for (int source = 0; source < size; ++source)
    for (std::size_t k = asked.from_offsets[source]; k < asked.from_offsets[source + 1]; ++k)
      answers.count(source);
  answers.allocate();
  for (int source = 0; source < size; ++source)
    for (std::size_t k = asked.from_offsets[source]; k < asked.from_offsets[source + 1]; ++k) {
      Position p;
      std::copy_n(&slice.positions[3 * static_cast<std::size_t>(asked.records[k] - first)], 3,
                  p.xyz);
      answers.place(source, p);
    }
  const std::vector<Position> remote_positions = exchange(comm, answers).records;

  // Summed in corner order, so a tet's centroid is the same bits on any
  // number of ranks.
  std::vector<double> centroids(3 * static_cast<std::size_t>(slice.num_tets()), 0.0);
  for (index_t t = 0; t < slice.num_tets(); ++t)
    for (int a = 0; a < 4; ++a) {
      const global_index_t v = slice.tets[4 * static_cast<std::size_t>(t) + a];
      const double* p =
          v >= first && v < last
              ? &slice.positions[3 * static_cast<std::size_t>(v - first)]
              : remote_positions[std::lower_bound(remote.begin(), remote.end(), v) - remote.begin()]
                    .xyz;
      for (int k = 0; k < 3; ++k) centroids[3 * static_cast<std::size_t>(t) + k] += p[k];
    }
  for (double& c : centroids) c *= 0.25;
  return centroids;
}

std::vector<int> partition_by_coordinates(MPI_Comm comm, const MeshSlice& slice, int nparts) {
  DESCENT_VERIFY(nparts >= 1, "nparts = ", nparts);
  if (slice.num_global_tets < nparts)
    throw PartitionError(detail::concat("cannot split ", slice.num_global_tets, " tets into ",
                                        nparts, " parts: fewer tets than parts"));
  const std::vector<double> centroid = tet_centroids(comm, slice);
  const index_t nt = slice.num_tets();
  const BlockRange part_sizes(slice.num_global_tets, nparts);

  // Each tet's group is the parts [part[t], group_end[part[t]]) it is still
  // to be split among; a level splits every group of two or more parts.
  std::vector<int> part(nt, 0);
  std::vector<int> group_end(nparts, 0);
  group_end[0] = nparts;
  for (;;) {
    std::vector<int> group_first, group_of(nparts, -1);
    for (int p = 0; p < nparts; p = group_end[p])
      if (group_end[p] - p > 1) {
        group_of[p] = static_cast<int>(group_first.size());
        group_first.push_back(p);
      }
    const int groups = static_cast<int>(group_first.size());
    if (groups == 0) break;

    // Bounding boxes of the groups' centroids: minima and negated maxima,
    // in one MPI_MIN; the split is across the longest side (the first of
    // equal sides).
    std::vector<double> box(6 * static_cast<std::size_t>(groups),
                            std::numeric_limits<double>::infinity());
    for (index_t t = 0; t < nt; ++t) {
      const int g = group_of[part[t]];
      if (g < 0) continue;
      for (int k = 0; k < 3; ++k) {
        const double c = centroid[3 * static_cast<std::size_t>(t) + k];
        box[6 * g + k] = std::min(box[6 * g + k], c);
        box[6 * g + 3 + k] = std::min(box[6 * g + 3 + k], -c);
      }
    }
    DESCENT_MPI_CHECK(MPI_Allreduce(MPI_IN_PLACE, box.data(), static_cast<int>(box.size()),
                                    MPI_DOUBLE, MPI_MIN, comm));
    std::vector<int> axis(groups, 0), middle(groups);
    // Per group, how many of the tets still in the running go to the lower half.
    std::vector<global_index_t> remaining(groups);
    for (int g = 0; g < groups; ++g) {
      for (int k = 1; k < 3; ++k)
        if (-box[6 * g + 3 + k] - box[6 * g + k] > -box[6 * g + 3 + axis[g]] - box[6 * g + axis[g]])
          axis[g] = k;
      const int first = group_first[g];
      middle[g] = first + (group_end[first] - first) / 2;
      remaining[g] = part_sizes.begin(middle[g]) - part_sizes.begin(first);
    }
    auto key_of = [&](index_t t, int g) {
      return Key{ordered_key(centroid[3 * static_cast<std::size_t>(t) + axis[g]]),
                 static_cast<std::uint64_t>(slice.first_tet + t)};
    };

    // Radix select: digit by digit, the bin that holds each group's split
    // key, and only the tets of that bin stay candidates.
    std::vector<Key> split(groups, Key{0, 0});
    std::vector<index_t> candidates;
    for (index_t t = 0; t < nt; ++t)
      if (group_of[part[t]] >= 0) candidates.push_back(t);
    std::vector<global_index_t> histogram(static_cast<std::size_t>(groups) * kBins);
    std::vector<int> chosen(groups);
    for (int round = 0; round < kKeyDigits; ++round) {
      std::fill(histogram.begin(), histogram.end(), 0);
      for (const index_t t : candidates) {
        const int g = group_of[part[t]];
        ++histogram[static_cast<std::size_t>(g) * kBins + key_digit(key_of(t, g), round)];
      }
      DESCENT_MPI_CHECK(MPI_Allreduce(MPI_IN_PLACE, histogram.data(),
                                      static_cast<int>(histogram.size()), MPI_INT64_T, MPI_SUM,
                                      comm));
      for (int g = 0; g < groups; ++g) {
        // remaining[g] >= 1 and the group's candidates number at least that
        // many, so the bin is found.
        const global_index_t* bins = &histogram[static_cast<std::size_t>(g) * kBins];
        int d = 0;
        while (bins[d] < remaining[g]) remaining[g] -= bins[d++];
        chosen[g] = d;
        set_digit(split[g], round, d);
      }
      candidates.erase(std::remove_if(candidates.begin(), candidates.end(),
                                      [&](index_t t) {
                                        const int g = group_of[part[t]];
                                        return key_digit(key_of(t, g), round) != chosen[g];
                                      }),
                       candidates.end());
    }

    // Keys up to the split key (it is one tet's) make the lower half.
    for (index_t t = 0; t < nt; ++t) {
      const int g = group_of[part[t]];
      if (g >= 0 && key_of(t, g) > split[g]) part[t] = middle[g];
    }
    for (int g = 0; g < groups; ++g) {
      const int first = group_first[g];
      group_end[middle[g]] = group_end[first];
      group_end[first] = middle[g];
    }
  }
  return part;
}

}  // namespace descent
