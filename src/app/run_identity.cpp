#include "app/run_identity.hpp"

#include <algorithm>
#include <cstring>
#include <map>
#include <sstream>
#include <string_view>
#include <type_traits>
#include <vector>

#include "comm/mpi_check.hpp"
#include "io/number_text.hpp"
#include "io/scene_schema.hpp"

namespace descent {

namespace {

// FNV-1a over the bytes of an item, then a final mix (splitmix64), so items
// summed over ranks in any order give one digest.
class ItemHash {
 public:
  template <class T>
  void add(const T& value) {
    unsigned char bytes[sizeof(T)];
    std::memcpy(bytes, &value, sizeof(T));
    for (unsigned char b : bytes) state_ = (state_ ^ b) * 0x100000001b3ull;
  }
  std::uint64_t value() const {
    std::uint64_t z = state_ + 0x9e3779b97f4a7c15ull;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
  }

 private:
  std::uint64_t state_ = 0xcbf29ce484222325ull;
};

template <class T>
std::string as_text(const T& value) {
  if constexpr (std::is_same_v<T, bool>) {
    return value ? "true" : "false";
  } else if constexpr (std::is_floating_point_v<T>) {
    return format_double(value);
  } else if constexpr (std::is_integral_v<T>) {
    return std::to_string(value);
  } else if constexpr (std::is_same_v<T, std::string>) {
    return "\"" + value + "\"";
  } else {  // a fixed or variable list of numbers
    std::string text = "[";
    for (const auto& item : value) text += (text.size() > 1 ? ", " : "") + as_text(item);
    return text + "]";
  }
}

bool restart_may_change(const std::string& key) {
  return std::any_of(std::begin(kRestartMayChange), std::end(kRestartMayChange),
                     [&](const char* k) { return key == k; });
}

// key -> value of identity text, and the keys in their order.
std::map<std::string, std::string> entries(const std::string& identity,
                                           std::vector<std::string>* order = nullptr) {
  std::map<std::string, std::string> found;
  std::istringstream lines(identity);
  for (std::string line; std::getline(lines, line);) {
    const std::size_t at = line.find(" = ");
    if (at == std::string::npos) continue;
    found[line.substr(0, at)] = line.substr(at + 3);
    if (order) order->push_back(line.substr(0, at));
  }
  return found;
}

}  // namespace

std::uint64_t mesh_digest(MPI_Comm comm, const LocalMesh& local) {
  std::uint64_t sum = 0;
  for (index_t v = 0; v < local.num_owned; ++v) {
    ItemHash h;
    h.add(local.global_vertex[v]);
    for (int i = 0; i < 3; ++i) h.add(local.rest_positions[3 * static_cast<std::size_t>(v) + i]);
    sum += h.value();
  }
  for (index_t t = 0; t < local.num_tets(); ++t) {
    ItemHash h;
    h.add(~local.global_tet[t]);  // apart from the vertex ids
    for (int c = 0; c < 4; ++c)
      h.add(local.global_vertex[local.tets[4 * static_cast<std::size_t>(t) + c]]);
    sum += h.value();
  }
  DESCENT_MPI_CHECK(MPI_Allreduce(MPI_IN_PLACE, &sum, 1, MPI_UINT64_T, MPI_SUM, comm));
  return sum;
}

std::uint64_t partition_digest(MPI_Comm comm, const LocalMesh& local) {
  std::uint64_t sum = 0;
  for (const global_index_t id : local.global_tet) {
    ItemHash h;
    h.add(std::int64_t{local.rank});
    h.add(std::int64_t{id});
    sum += h.value();
  }
  DESCENT_MPI_CHECK(MPI_Allreduce(MPI_IN_PLACE, &sum, 1, MPI_UINT64_T, MPI_SUM, comm));
  return sum;
}

std::string run_identity(const Scene& scene, const MeshDigests& digests,
                         const std::string& precision) {
  std::string text;
  auto line = [&](const std::string& key, const auto& value) {
    if (!restart_may_change(key)) text += key + " = " + as_text(value) + "\n";
  };
  SceneFields fields{scene, {}};
  // A helix preset only names a resolution, which is listed itself.
  auto names_a_resolution = [](std::string_view key) { return key.ends_with("helix.preset"); };
  visit_scene_keys(fields, [&](std::string_view key, const auto& value) {
    if (!names_a_resolution(key)) line(std::string(key), value);
  });
  visit_scene_arrays(fields.scene, [&](std::string_view name, auto& list) {
    for (std::size_t e = 0; e < list.size(); ++e)
      visit_entry_keys(list[e], [&](std::string_view key, const auto& value) {
        if (!names_a_resolution(key))
          line(std::string(name) + "." + std::to_string(e) + "." + std::string(key), value);
      });
  });
  line("mesh.digest", digests.mesh);
  line("partition.digest", digests.partition);
  line("precision", precision);
  return text;
}

std::string identity_difference(const std::string& saved, const std::string& now) {
  std::vector<std::string> order;
  const auto then = entries(saved);
  const auto current = entries(now, &order);
  for (const std::string& key : order) {
    const auto it = then.find(key);
    if (it == then.end() && key == "partition.digest")
      return "the checkpoint's run predates partition digests: this version partitions "
             "differently and cannot continue it (run it again from the start)";
    if (it == then.end())
      return key + " = " + current.at(key) + " is new (the checkpoint's run had no such entry)";
    if (it->second == current.at(key)) continue;
    if (key == "partition.digest")
      return "the partition differs (partition.digest, a hash of which rank holds which tet, is " +
             current.at(key) + " now but was " + it->second +
             " in the checkpoint's run): restart with the partition.method and --partition "
             "file the run was made with";
    if (key == "mesh.digest")
      return "the mesh differs (mesh.digest, a hash of its vertex ids, coordinates and tets, is " +
             current.at(key) + " now but was " + it->second + " in the checkpoint's run)";
    return key + " is " + current.at(key) + " now but was " + it->second +
           " in the checkpoint's run";
  }
  for (const auto& [key, value] : then)
    if (!current.count(key)) return key + " = " + value + " of the checkpoint's run is gone";
  return "";
}

}  // namespace descent
