#include "io/checkpoint.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <system_error>

#include "common/error.hpp"
#include "common/xxhash64.hpp"

namespace descent {

namespace {

namespace fs = std::filesystem;
constexpr char kMagic[] = "descent-checkpoint-4\n";
constexpr char kMagicStem[] = "descent-checkpoint-";  // every format's magic starts so
constexpr std::size_t kMagicBytes = sizeof kMagic - 1;
constexpr std::size_t kHeaderBytes = kMagicBytes + 3 * sizeof(std::int32_t) + sizeof(std::int64_t);
constexpr std::size_t kDigestBytes = sizeof(std::uint64_t);
// Fixed part of the payload: 4 int64 counts, 5 doubles, 2 int32, the identity length.
constexpr std::size_t kFixedPayloadBytes =
    4 * sizeof(std::int64_t) + 5 * sizeof(double) + 2 * sizeof(std::int32_t) + sizeof(std::int64_t);

std::string system_error_text(int code) { return std::generic_category().message(code); }

// A file written with write(2) and made durable with fsync(2).
class OutputFile {
 public:
  explicit OutputFile(const std::string& path) : path_(path) {
    fd_ = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd_ < 0) fail(errno);
  }
  ~OutputFile() {
    if (fd_ >= 0) ::close(fd_);  // only after a failure: sync_and_close() closes
  }
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;

  void write(const void* data, std::size_t size) {
    const auto* bytes = static_cast<const char*>(data);
    while (size > 0) {
      const ssize_t written = ::write(fd_, bytes, size);
      if (written < 0 && errno == EINTR) continue;
      if (written <= 0) fail(written < 0 ? errno : EIO);
      bytes += written;
      size -= static_cast<std::size_t>(written);
    }
  }
  // Asks the kernel to start writing what was written so far to the device
  // and returns at once (Linux; elsewhere fsync alone does the work).
  void start_writeback() {
#ifdef __linux__
    ::sync_file_range(fd_, 0, 0, SYNC_FILE_RANGE_WRITE);  // a hint: fsync checks
#endif
  }
  void sync_and_close() {
    if (::fsync(fd_) != 0) fail(errno);
    const int closed = ::close(fd_);
    fd_ = -1;
    if (closed != 0) fail(errno);
  }

 private:
  [[noreturn]] void fail(int code) const {
    throw InputError(
        detail::concat("cannot write checkpoint ", path_, ": ", system_error_text(code)));
  }
  std::string path_;
  int fd_ = -1;
};

// A stretch of the file's bytes, where it lies in memory.
struct ByteRun {
  const void* data;
  std::size_t size;
};

// The header and the fixed part of the payload, identity included, as the
// file holds them (layout in checkpoint.hpp); the arrays follow as they lie
// in memory.
std::vector<char> serialise_head(const Checkpoint& c) {
  std::vector<char> head;
  auto put_bytes = [&](const void* data, std::size_t size) {
    head.insert(head.end(), static_cast<const char*>(data), static_cast<const char*>(data) + size);
  };
  auto put = [&](const auto& value) { put_bytes(&value, sizeof value); };
  const std::size_t array_bytes =
      (3 * c.q.size() + c.interpolants.size()) * sizeof(double);  // v, v_prev as large as q
  put_bytes(kMagic, kMagicBytes);
  put(std::int32_t(c.rank));
  put(std::int32_t(c.num_ranks));
  put(std::int32_t(c.frame));
  put(static_cast<std::int64_t>(kFixedPayloadBytes + c.identity.size() + array_bytes));
  put(std::int64_t(c.num_global_vertices));
  put(std::int64_t(c.num_global_tets));
  put(std::int64_t(c.q.size()));
  put(std::int64_t(c.interpolants.size()));
  put(c.time);
  put(c.alpha);
  put(c.lambda_min);
  put(c.lambda_max);
  put(c.widening);
  put(std::int32_t(c.steps_since_estimate));
  put(std::int32_t(c.reestimate ? 1 : 0));
  put(std::int64_t(c.identity.size()));
  put_bytes(c.identity.data(), c.identity.size());
  return head;
}

// The directory's entry changes (the renames) reach the disk.
void sync_directory(const fs::path& dir, const std::string& path) {
  const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  const bool synced = fd >= 0 && ::fsync(fd) == 0;
  const int code = errno;
  if (fd >= 0) ::close(fd);
  if (!synced)
    throw InputError(detail::concat("cannot write checkpoint ", path, ": fsync of ", dir.string(),
                                    ": ", system_error_text(code)));
}

// Reads values from a verified file's bytes; a read past the end means the
// declared sizes and the payload disagree.
class PayloadReader {
 public:
  PayloadReader(const std::vector<char>& bytes, std::size_t begin, std::size_t end,
                const std::string& path)
      : bytes_(bytes), at_(begin), end_(end), path_(path) {}

  template <class T>
  T get() {
    T value{};
    std::memcpy(&value, take(sizeof value), sizeof value);
    return value;
  }
  std::vector<double> get_array(std::int64_t count) {
    if (count < 0 || static_cast<std::uint64_t>(count) > (end_ - at_) / sizeof(double))
      throw inconsistent();
    std::vector<double> values(static_cast<std::size_t>(count));
    if (count == 0) return values;  // data() may be null: no memcpy from or to it
    std::memcpy(values.data(), take(values.size() * sizeof(double)),
                values.size() * sizeof(double));
    return values;
  }
  std::string get_text(std::int64_t length) {
    if (length < 0 || static_cast<std::uint64_t>(length) > end_ - at_) throw inconsistent();
    const char* text = take(static_cast<std::size_t>(length));
    return std::string(text, static_cast<std::size_t>(length));
  }
  bool at_end() const { return at_ == end_; }
  InputError inconsistent() const {
    return InputError(detail::concat("checkpoint ", path_,
                                     ": the payload does not match the sizes it declares "
                                     "(written by a faulty program?)"));
  }

 private:
  const char* take(std::size_t size) {
    if (size > end_ - at_) throw inconsistent();
    const char* where = bytes_.data() + at_;
    at_ += size;
    return where;
  }
  const std::vector<char>& bytes_;
  std::size_t at_, end_;
  const std::string& path_;
};

// The whole file, or an InputError saying why not.
std::vector<char> read_whole_file(const std::string& path) {
  std::error_code error;
  if (!fs::exists(path, error))
    throw InputError(detail::concat("checkpoint ", path, " is missing"));
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(detail::concat("checkpoint ", path, " cannot be opened"));
  std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw InputError(detail::concat("checkpoint ", path, " cannot be read"));
  return bytes;
}

// The header's magic: ours, an older format's (named), or none.
void verify_magic(const std::vector<char>& bytes, const std::string& path) {
  if (bytes.empty()) throw InputError(detail::concat("checkpoint ", path, " is empty"));
  const std::size_t stem = sizeof kMagicStem - 1;
  if (bytes.size() < stem || std::memcmp(bytes.data(), kMagicStem, stem) != 0)
    throw InputError(detail::concat(path, " is not a descent checkpoint"));
  if (bytes.size() < kHeaderBytes + kDigestBytes)
    throw InputError(detail::concat("checkpoint ", path, " is truncated: ", bytes.size(),
                                    " bytes, shorter than a header"));
  if (std::memcmp(bytes.data(), kMagic, kMagicBytes) != 0) {
    const std::string line(bytes.data() + stem,
                           std::find(bytes.data() + stem, bytes.data() + kMagicBytes, '\n'));
    throw InputError(detail::concat("checkpoint ", path, " is of format '", line,
                                    "', which has no checksum; this descent restarts only from "
                                    "format 4: rerun from the start"));
  }
}

}  // namespace

std::string checkpoint_path(const std::string& dir, int rank, int num_ranks) {
  return (fs::path(dir) / "checkpoint" /
          ("rank-" + std::to_string(rank) + "-of-" + std::to_string(num_ranks) + ".bin"))
      .string();
}

void write_checkpoint(const std::string& path, const Checkpoint& c) {
  const fs::path dir = fs::path(path).parent_path();
  std::error_code made;
  fs::create_directories(dir, made);
  const std::string temporary = path + ".tmp";
  const std::vector<char> head = serialise_head(c);
  const ByteRun runs[] = {{head.data(), head.size()},
                          {c.q.data(), c.q.size() * sizeof(double)},
                          {c.v.data(), c.v.size() * sizeof(double)},
                          {c.v_prev.data(), c.v_prev.size() * sizeof(double)},
                          {c.interpolants.data(), c.interpolants.size() * sizeof(double)}};
  // The checksum of the very bytes written, computed once they are written
  // and their writeback to the device has begun: hashing (about 12 GB/s)
  // then overlaps the device's work, which fsync would wait for anyway,
  // instead of adding to it (bench/results/checkpoint_write).
  {
    OutputFile out(temporary);
    for (const ByteRun& run : runs) out.write(run.data, run.size);
    out.start_writeback();
    XxHash64 hash;
    for (const ByteRun& run : runs) hash.update(run.data, run.size);
    const std::uint64_t digest = hash.digest();
    out.write(&digest, sizeof digest);
    out.sync_and_close();
  }
  std::error_code renamed;
  if (fs::exists(path)) fs::rename(path, path + ".prev", renamed);
  if (!renamed) fs::rename(temporary, path, renamed);
  if (renamed) throw InputError("cannot write checkpoint " + path + ": " + renamed.message());
  sync_directory(dir, path);
}

Checkpoint read_checkpoint(const std::string& path, int rank, int num_ranks) {
  const std::vector<char> bytes = read_whole_file(path);
  verify_magic(bytes, path);
  PayloadReader header(bytes, kMagicBytes, kHeaderBytes, path);
  Checkpoint c;
  c.rank = header.get<std::int32_t>();
  c.num_ranks = header.get<std::int32_t>();
  c.frame = header.get<std::int32_t>();
  const auto payload_bytes = header.get<std::int64_t>();
  const std::uint64_t expected_size =
      kHeaderBytes + static_cast<std::uint64_t>(payload_bytes) + kDigestBytes;
  if (payload_bytes < 0 || bytes.size() < expected_size)
    throw InputError(detail::concat("checkpoint ", path, " is truncated: ", bytes.size(),
                                    " bytes, its header declares ", expected_size));
  if (bytes.size() > expected_size)
    throw InputError(detail::concat("checkpoint ", path, " has ", bytes.size() - expected_size,
                                    " bytes after its end (", expected_size, " declared)"));
  XxHash64 hash;
  hash.update(bytes.data(), bytes.size() - kDigestBytes);
  std::uint64_t stored = 0;
  std::memcpy(&stored, bytes.data() + bytes.size() - kDigestBytes, kDigestBytes);
  if (hash.digest() != stored)
    throw InputError(detail::concat("checkpoint ", path,
                                    " is damaged: its checksum does not match its contents"));
  if (c.rank != rank || c.num_ranks != num_ranks)
    throw InputError(detail::concat("checkpoint ", path, " holds the state of rank ", c.rank,
                                    " of ", c.num_ranks, ", not of rank ", rank, " of ", num_ranks,
                                    ": another rank's file in its place"));

  PayloadReader in(bytes, kHeaderBytes, bytes.size() - kDigestBytes, path);
  c.num_global_vertices = in.get<std::int64_t>();
  c.num_global_tets = in.get<std::int64_t>();
  const auto dofs = in.get<std::int64_t>();
  const auto tets = in.get<std::int64_t>();
  // Only a faulty writer (or a forged checksum) gets past the checks above
  // with these wrong.
  if (c.frame < 0 || dofs % 3 != 0) throw in.inconsistent();
  c.time = in.get<double>();
  c.alpha = in.get<double>();
  c.lambda_min = in.get<double>();
  c.lambda_max = in.get<double>();
  c.widening = in.get<double>();
  c.steps_since_estimate = in.get<std::int32_t>();
  c.reestimate = in.get<std::int32_t>() != 0;
  c.identity = in.get_text(in.get<std::int64_t>());
  c.q = in.get_array(dofs);
  c.v = in.get_array(dofs);
  c.v_prev = in.get_array(dofs);
  c.interpolants = in.get_array(tets);
  if (!in.at_end()) throw in.inconsistent();
  return c;
}

}  // namespace descent
