#include "io/checkpoint.hpp"

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "common/error.hpp"

namespace descent {

namespace {

namespace fs = std::filesystem;
constexpr char kMagic[] = "descent-checkpoint-3\n";
constexpr char kMagicVersion2[] = "descent-checkpoint-2\n";
constexpr char kMagicVersion1[] = "descent-checkpoint-1\n";

template <class T>
void put(std::ofstream& out, const T& value) {
  out.write(reinterpret_cast<const char*>(&value), sizeof value);
}

void put_array(std::ofstream& out, const std::vector<double>& values) {
  out.write(reinterpret_cast<const char*>(values.data()),
            static_cast<std::streamsize>(values.size() * sizeof(double)));
}

template <class T>
T get(std::ifstream& in, const std::string& path) {
  T value{};
  if (!in.read(reinterpret_cast<char*>(&value), sizeof value))
    throw InputError("checkpoint " + path + " is truncated");
  return value;
}

std::vector<double> get_array(std::ifstream& in, std::int64_t count, const std::string& path) {
  if (count < 0 || count > (std::int64_t{1} << 40))
    throw InputError("checkpoint " + path + " declares an impossible array size");
  std::vector<double> values(static_cast<std::size_t>(count));
  if (!in.read(reinterpret_cast<char*>(values.data()),
               static_cast<std::streamsize>(values.size() * sizeof(double))))
    throw InputError("checkpoint " + path + " is truncated");
  return values;
}

}  // namespace

std::string checkpoint_path(const std::string& dir, int rank, int num_ranks) {
  return (fs::path(dir) / "checkpoint" /
          ("rank-" + std::to_string(rank) + "-of-" + std::to_string(num_ranks) + ".bin"))
      .string();
}

void write_checkpoint(const std::string& path, const Checkpoint& c) {
  std::error_code made;
  fs::create_directories(fs::path(path).parent_path(), made);
  const std::string temporary = path + ".tmp";
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    out.write(kMagic, sizeof kMagic - 1);
    put(out, std::int32_t(c.num_ranks));
    put(out, std::int32_t(c.rank));
    put(out, std::int32_t(c.frame));
    put(out, std::int64_t(c.num_global_vertices));
    put(out, std::int64_t(c.num_global_tets));
    put(out, std::int64_t(c.q.size()));
    put(out, std::int64_t(c.interpolants.size()));
    put(out, c.time);
    put(out, c.alpha);
    put(out, c.lambda_min);
    put(out, c.lambda_max);
    put(out, c.widening);
    put(out, std::int32_t(c.steps_since_estimate));
    put(out, std::int32_t(c.reestimate ? 1 : 0));
    put(out, std::int64_t(c.identity.size()));
    out.write(c.identity.data(), static_cast<std::streamsize>(c.identity.size()));
    put_array(out, c.q);
    put_array(out, c.v);
    put_array(out, c.v_prev);
    put_array(out, c.interpolants);
    out.close();
    if (!out) throw InputError("cannot write checkpoint " + temporary);
  }
  std::error_code renamed;
  if (fs::exists(path)) fs::rename(path, path + ".prev", renamed);
  if (!renamed) fs::rename(temporary, path, renamed);
  if (renamed) throw InputError("cannot write checkpoint " + path + ": " + renamed.message());
}

Checkpoint read_checkpoint(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError("no checkpoint " + path + " (was the run started with checkpoints?)");
  char magic[sizeof kMagic - 1];
  if (!in.read(magic, sizeof magic)) throw InputError(path + " is not a descent checkpoint");
  const bool version1 = std::memcmp(magic, kMagicVersion1, sizeof magic) == 0;
  const bool version2 = std::memcmp(magic, kMagicVersion2, sizeof magic) == 0;
  if (!version1 && !version2 && std::memcmp(magic, kMagic, sizeof magic) != 0)
    throw InputError(path + " is not a descent checkpoint");
  Checkpoint c;
  c.num_ranks = get<std::int32_t>(in, path);
  c.rank = get<std::int32_t>(in, path);
  c.frame = get<std::int32_t>(in, path);
  c.num_global_vertices = get<std::int64_t>(in, path);
  c.num_global_tets = get<std::int64_t>(in, path);
  const auto dofs = get<std::int64_t>(in, path);
  const auto tets = get<std::int64_t>(in, path);
  c.time = get<double>(in, path);
  c.alpha = get<double>(in, path);
  if (!version1) {
    c.lambda_min = get<double>(in, path);
    c.lambda_max = get<double>(in, path);
    c.widening = get<double>(in, path);
    c.steps_since_estimate = get<std::int32_t>(in, path);
    c.reestimate = get<std::int32_t>(in, path) != 0;
  }
  if (!version1 && !version2) {
    const auto length = get<std::int64_t>(in, path);
    if (length < 0 || length > (std::int64_t{1} << 24))
      throw InputError("checkpoint " + path + " declares an impossible identity length");
    c.identity.resize(static_cast<std::size_t>(length));
    if (!in.read(c.identity.data(), length))
      throw InputError("checkpoint " + path + " is truncated");
  }
  c.q = get_array(in, dofs, path);
  c.v = get_array(in, dofs, path);
  c.v_prev = get_array(in, dofs, path);
  c.interpolants = get_array(in, tets, path);
  return c;
}

std::vector<Checkpoint> read_checkpoint_generations(const std::string& path) {
  std::vector<Checkpoint> found;
  for (const std::string& candidate : {path, path + ".prev"})
    if (fs::exists(candidate)) found.push_back(read_checkpoint(candidate));
  if (found.empty()) return {read_checkpoint(path)};  // throws, naming the path
  return found;
}

}  // namespace descent
