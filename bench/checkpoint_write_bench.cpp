// bench/checkpoint_write.sh's driver: what the checksum adds to writing a
// checkpoint. On a checkpoint of the 1M-tet helix's sizes held by one rank
// (the largest file a rank of that run writes: 200,480 vertices, 1,031,208
// tets with their interpolants), it times, alternating:
//  - checkpoint: write_checkpoint (write, writeback started, XXH64 of the
//    bytes meanwhile, fsync, rotation by rename, fsync of the directory);
//  - plain: the same bytes with the same calls (writeback started early
//    too) and no checksum: the digest's 8 bytes written as zeros;
// and XXH64 alone over the bytes. The checksum adds (checkpoint - plain) /
// plain, from the medians.
//
//   checkpoint_write_bench [--vertices V] [--tets T] [--runs N] [--out DIR]
// Prints one line per run and a summary line with the medians.
#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "common/xxhash64.hpp"
#include "io/checkpoint.hpp"

namespace {

namespace fs = std::filesystem;

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

// The arrays of a checkpoint in file order (the head is under 3 KB here).
std::vector<const std::vector<double>*> arrays_of(const descent::Checkpoint& c) {
  return {&c.q, &c.v, &c.v_prev, &c.interpolants};
}

void write_all(int fd, const void* data, std::size_t size) {
  const char* bytes = static_cast<const char*>(data);
  while (size > 0) {
    const ssize_t written = ::write(fd, bytes, size);
    if (written <= 0) std::exit(1);
    bytes += written;
    size -= static_cast<std::size_t>(written);
  }
}

// The same I/O as write_checkpoint, without the checksum.
void write_plain(const std::string& path, const descent::Checkpoint& c) {
  const std::string temporary = path + ".tmp";
  const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  const std::vector<char> head(41 + 88 + c.identity.size(), 'h');  // header + fixed payload
  write_all(fd, head.data(), head.size());
  for (const auto* array : arrays_of(c))
    write_all(fd, array->data(), array->size() * sizeof(double));
  const std::uint64_t digest = 0;
  write_all(fd, &digest, sizeof digest);
  if (::fsync(fd) != 0 || ::close(fd) != 0) std::exit(1);
  if (fs::exists(path)) fs::rename(path, path + ".prev");
  fs::rename(temporary, path);
  const int dir = ::open(fs::path(path).parent_path().c_str(), O_RDONLY | O_DIRECTORY);
  if (::fsync(dir) != 0) std::exit(1);
  ::close(dir);
}

}  // namespace

int main(int argc, char** argv) {
  long long vertices = 200480, tets = 1031208;
  int runs = 41;
  std::string out = "/tmp/descent_checkpoint_bench";
  for (int k = 1; k + 1 < argc; k += 2) {
    const std::string key = argv[k], value = argv[k + 1];
    if (key == "--vertices")
      vertices = std::atoll(value.c_str());
    else if (key == "--tets")
      tets = std::atoll(value.c_str());
    else if (key == "--runs")
      runs = std::atoi(value.c_str());
    else if (key == "--out")
      out = value;
  }
  descent::Checkpoint c;
  c.num_global_vertices = vertices;
  c.num_global_tets = tets;
  c.identity = std::string(2000, 'k');  // about the size of a real run identity
  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  for (auto* array : {&c.q, &c.v, &c.v_prev}) {
    array->resize(3 * static_cast<std::size_t>(vertices));
    for (double& x : *array) x = value(random);
  }
  c.interpolants.resize(static_cast<std::size_t>(tets));
  for (double& x : c.interpolants) x = value(random);
  const double megabytes = (3 * c.q.size() + c.interpolants.size()) * sizeof(double) / 1e6;

  fs::create_directories(fs::path(out) / "checkpoint");
  const std::string checked = descent::checkpoint_path(out, 0, 1);
  const std::string plain = (fs::path(out) / "checkpoint" / "plain.bin").string();
  std::vector<double> checkpoints, plains, hashes;
  for (int run = 0; run < runs; ++run) {
    // In turn first and second, so that neither always follows the other's fsync.
    for (int turn = 0; turn < 2; ++turn) {
      const auto start = std::chrono::steady_clock::now();
      if ((run + turn) % 2 == 0) {
        write_plain(plain, c);
        plains.push_back(seconds_since(start));
      } else {
        descent::write_checkpoint(checked, c);
        checkpoints.push_back(seconds_since(start));
      }
    }
    auto start = std::chrono::steady_clock::now();
    descent::XxHash64 hash;
    for (const auto* array : arrays_of(c))
      hash.update(array->data(), array->size() * sizeof(double));
    volatile std::uint64_t digest = hash.digest();
    (void)digest;
    hashes.push_back(seconds_since(start));
    std::printf("run %2d: plain %.4f s, checkpoint %.4f s, XXH64 alone %.5f s\n", run,
                plains.back(), checkpoints.back(), hashes.back());
  }
  const double checkpoint = median(checkpoints), without = median(plains), hash = median(hashes);
  std::printf(
      "checkpoint %.1f MB (%lld vertices, %lld tets), %d runs, medians: plain write+sync %.4f s, "
      "checkpoint %.4f s, XXH64 alone %.5f s (%.1f GB/s): the checksum adds %+.2f%%\n",
      megabytes, vertices, tets, runs, without, checkpoint, hash, megabytes / 1e3 / hash,
      100.0 * (checkpoint - without) / without);
  fs::remove_all(out);
  return 0;
}
