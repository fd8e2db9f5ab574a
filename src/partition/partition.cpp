#include "partition/partition.hpp"

#include <metis.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <numeric>
#include <sstream>
#include <unordered_map>

#include "common/error.hpp"

namespace descent {

namespace {

const char* metis_status_name(int status) {
  switch (status) {
    case METIS_ERROR_INPUT:
      return "METIS_ERROR_INPUT";
    case METIS_ERROR_MEMORY:
      return "METIS_ERROR_MEMORY";
    default:
      return "METIS_ERROR";
  }
}

}  // namespace

std::vector<std::pair<index_t, int>> vertex_users(const Mesh& mesh, std::span<const int> tet_part) {
  std::vector<std::pair<index_t, int>> users;
  users.reserve(mesh.tets.size());
  for (index_t t = 0; t < mesh.num_tets(); ++t)
    for (int a = 0; a < 4; ++a) users.emplace_back(mesh.tets[4 * t + a], tet_part[t]);
  std::sort(users.begin(), users.end());
  users.erase(std::unique(users.begin(), users.end()), users.end());
  return users;
}

std::vector<int> partition_tets(const Mesh& mesh, int nparts) {
  DESCENT_VERIFY(nparts >= 1, "nparts = ", nparts);
  const index_t num_tets = mesh.num_tets();
  if (nparts == 1) return std::vector<int>(num_tets, 0);
  if (num_tets < nparts) {
    throw MetisError(detail::concat("cannot split ", mesh.source, " (", num_tets, " tets) across ",
                                    nparts, " ranks: fewer tets than ranks"));
  }
  idx_t ne = num_tets;
  idx_t nn = mesh.num_vertices();
  std::vector<idx_t> eptr(num_tets + 1);
  for (index_t t = 0; t <= num_tets; ++t) eptr[t] = 4 * t;
  std::vector<idx_t> eind(mesh.tets.begin(), mesh.tets.end());
  idx_t ncommon = 3;  // tets are neighbours when they share a face
  idx_t np = nparts;
  idx_t options[METIS_NOPTIONS];
  METIS_SetDefaultOptions(options);
  options[METIS_OPTION_SEED] = 1;  // the same partition on every run
  idx_t objval = 0;
  std::vector<idx_t> epart(num_tets), npart(nn);
  const int status =
      METIS_PartMeshDual(&ne, &nn, eptr.data(), eind.data(), nullptr, nullptr, &ncommon, &np,
                         nullptr, options, &objval, epart.data(), npart.data());
  if (status != METIS_OK) {
    throw MetisError(detail::concat("METIS_PartMeshDual failed with ", metis_status_name(status),
                                    " on ", mesh.source, " (", num_tets, " tets, ", nparts,
                                    " parts)"));
  }
  std::vector<int> part(epart.begin(), epart.end());
  // METIS may leave a part empty on tiny meshes; every rank needs work.
  std::vector<index_t> count(nparts, 0);
  for (int p : part) ++count[p];
  for (int p = 0; p < nparts; ++p) {
    if (count[p] == 0) {
      throw MetisError(detail::concat("METIS left rank ", p, " without tets for ", mesh.source,
                                      " (", num_tets, " tets, ", nparts,
                                      " ranks): use fewer ranks"));
    }
  }
  return part;
}

PartitionQuality partition_quality(const Mesh& mesh, std::span<const int> tet_part, int nparts) {
  PartitionQuality q;
  q.tets_per_rank.assign(nparts, 0);
  for (int p : tet_part) ++q.tets_per_rank[p];
  // Faces: sorted vertex triple -> first tet's part; a second tet with another
  // part makes the face cut.
  std::unordered_map<std::uint64_t, int> face_part;
  face_part.reserve(mesh.tets.size());
  const index_t nv = mesh.num_vertices();
  for (index_t t = 0; t < mesh.num_tets(); ++t) {
    for (const auto& f : kTetFaces) {
      std::array<std::uint64_t, 3> v{};
      for (int k = 0; k < 3; ++k) v[k] = static_cast<std::uint64_t>(mesh.tets[4 * t + f[k]]);
      std::sort(v.begin(), v.end());
      const std::uint64_t key = (v[0] * nv + v[1]) * nv + v[2];
      auto [it, inserted] = face_part.try_emplace(key, tet_part[t]);
      if (!inserted && it->second != tet_part[t]) ++q.cut_faces;
    }
  }
  // Shared vertices: used by more than one part; counted for each sharer.
  const std::vector<std::pair<index_t, int>> users = vertex_users(mesh, tet_part);
  q.shared_vertices_per_rank.assign(nparts, 0);
  for (std::size_t k = 0; k < users.size();) {
    std::size_t end = k;
    while (end < users.size() && users[end].first == users[k].first) ++end;
    if (end - k > 1)
      for (std::size_t u = k; u < end; ++u) ++q.shared_vertices_per_rank[users[u].second];
    k = end;
  }
  const double mean = static_cast<double>(mesh.num_tets()) / nparts;
  q.imbalance = *std::max_element(q.tets_per_rank.begin(), q.tets_per_rank.end()) / mean;
  return q;
}

std::string describe(const PartitionQuality& q) {
  std::ostringstream os;
  os << "partition: " << q.tets_per_rank.size() << " ranks, imbalance " << q.imbalance
     << ", cut faces " << q.cut_faces << "; tets/shared vertices per rank:";
  for (std::size_t p = 0; p < q.tets_per_rank.size(); ++p)
    os << ' ' << q.tets_per_rank[p] << '/' << q.shared_vertices_per_rank[p];
  return os.str();
}

}  // namespace descent
