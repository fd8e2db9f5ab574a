#include "app/restart_checkpoint.hpp"

#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <vector>

#include "app/console.hpp"
#include "app/run_identity.hpp"
#include "comm/collective_error.hpp"
#include "comm/mpi_check.hpp"
#include "common/error.hpp"

namespace descent {
namespace {

namespace fs = std::filesystem;

// Why a restart finds no checkpoint of this rank count on any rank: a run on
// another rank count (named), no checkpoints at all, or no such directory.
std::string missing_checkpoint(const std::string& dir, int size) {
  const fs::path where = fs::path(dir) / "checkpoint";
  std::error_code listed;
  std::vector<int> counts;
  for (const auto& entry : fs::directory_iterator(where, listed)) {
    int ranks = 0;
    if (std::sscanf(entry.path().filename().c_str(), "rank-0-of-%d.bin", &ranks) == 1 &&
        entry.path().extension() == ".bin")
      counts.push_back(ranks);
  }
  if (listed)
    return detail::concat("--restart: ", where.string(), " does not exist: is ", dir,
                          " the output directory of the run to continue?");
  if (counts.empty())
    return detail::concat("--restart: ", where.string(),
                          " holds no checkpoint (the run wrote none: output.checkpoint_every = 0, "
                          "or it stopped before its first)");
  std::sort(counts.begin(), counts.end());
  std::string found;
  for (int c : counts) found += (found.empty() ? "" : ", ") + std::to_string(c);
  return detail::concat("--restart: ", where.string(), " holds checkpoints of a run on ", found,
                        " rank(s), not ", size, ": restart it on ", counts.front(), " rank(s)");
}

// One generation of this rank's checkpoint: verified, or why not.
struct Generation {
  std::string path;
  std::optional<Checkpoint> checkpoint;
  std::string error;  // empty when verified
  int frame() const { return checkpoint ? checkpoint->frame : -1; }
};

Generation read_generation(const std::string& path, int rank, int size) {
  Generation g;
  g.path = path;
  try {
    g.checkpoint = read_checkpoint(path, rank, size);
  } catch (const Error& e) {
    g.error = e.what();
  }
  return g;
}

// Per rank, as gathered: the frames of its two generations (-1: none
// verified) and whether it has a checkpoint file at all.
constexpr int kFields = 3;

// The newest frame that every rank has a verified generation of; -1 if none.
int newest_common_frame(const std::vector<int>& all, int size) {
  int best = -1;
  for (int k = 0; k < kFields * size; ++k) {
    if (k % kFields == 2) continue;
    const int f = all[k];
    bool everywhere = f > best;
    for (int r = 0; r < size && everywhere; ++r)
      everywhere = all[kFields * r] == f || all[kFields * r + 1] == f;
    if (everywhere) best = f;
  }
  return best;
}

}  // namespace

Checkpoint restart_checkpoint(MPI_Comm comm, const std::string& dir, const std::string& identity) {
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  const std::string path = checkpoint_path(dir, rank, size);
  const std::array<Generation, 2> generations = {read_generation(path, rank, size),
                                                 read_generation(path + ".prev", rank, size)};
  std::error_code ignored;
  const bool has_file = fs::exists(path, ignored) || fs::exists(path + ".prev", ignored);
  const std::array<int, kFields> mine = {generations[0].frame(), generations[1].frame(),
                                         has_file ? 1 : 0};
  std::vector<int> all(kFields * static_cast<std::size_t>(size));
  DESCENT_MPI_CHECK(
      MPI_Allgather(mine.data(), kFields, MPI_INT, all.data(), kFields, MPI_INT, comm));
  const int frame = newest_common_frame(all, size);

  if (frame < 0) {
    // Reported by one rank: rank 0 when no rank has a file, else the first
    // rank whose newer file failed, else rank 0 (intact files, no common frame).
    bool any_file = false;
    int reporter = -1;
    for (int r = 0; r < size; ++r) {
      any_file = any_file || all[kFields * r + 2] == 1;
      if (reporter < 0 && all[kFields * r] < 0) reporter = r;
    }
    std::string error;
    if (rank == std::max(reporter, 0)) {
      if (!any_file) {
        error = missing_checkpoint(dir, size);
      } else if (reporter < 0) {
        error = "--restart: the ranks' checkpoints share no frame:";
        for (int r = 0; r < size; ++r)
          error += detail::concat(r ? "," : "", " rank ", r, " has frames ", all[kFields * r],
                                  " and ", all[kFields * r + 1]);
      } else {
        error =
            "--restart: no frame has a verified checkpoint on every rank: " + generations[0].error;
        if (fs::exists(generations[1].path, ignored)) error += "; " + generations[1].error;
      }
    }
    throw_if_any_failed(comm, error);
  }

  const Generation& used = generations[0].frame() == frame ? generations[0] : generations[1];
  // Said by one rank, which files and why: the first whose newer file
  // failed, else the first whose newer file holds a frame others lack.
  int reporter = size, first_on_prev = size, on_prev = 0;
  for (int r = size - 1; r >= 0; --r) {
    if (all[kFields * r] < 0) reporter = r;
    if (all[kFields * r] != frame) {
      first_on_prev = r;
      ++on_prev;
    }
  }
  if (reporter == size) reporter = first_on_prev;
  if (rank == reporter) {
    const std::string why =
        generations[0].checkpoint
            ? detail::concat(generations[0].path, " holds frame ", generations[0].frame(),
                             ", which not every rank has")
            : generations[0].error;
    warn(
        "--restart: %s; continuing after frame %d, the newest that verifies on every rank "
        "(from the .prev checkpoint on %d of %d rank(s))",
        why.c_str(), frame, on_prev, size);
  }

  std::string error;
  if (const std::string differs = identity_difference(used.checkpoint->identity, identity);
      !differs.empty())
    error = detail::concat(
        "--restart: ", used.path, " belongs to another run: ", differs,
        ". Restart with the scene, mesh and precision that made it (a restart may change "
        "time.frames, output.every and output.checkpoint_every)");
  throw_if_any_failed(comm, error);
  return *used.checkpoint;
}

}  // namespace descent
