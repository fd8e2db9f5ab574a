#pragma once
// Checkpoints for restarting a killed run: one file per rank,
// DIR/checkpoint/rank-R-of-P.bin, holding that rank's whole solver state, so
// a restart on the same rank count continues bit for bit.
//
// File layout, format 4 (native byte order, doubles IEEE 754):
//   header   "descent-checkpoint-4\n"   magic and format version (21 bytes)
//            int32 rank, num_ranks, frame  whose file it is, and its step
//            int64 payload_bytes           the length of the payload
//   payload  int64 num_global_vertices, num_global_tets, local dofs, local tets
//            double time, alpha, lambda_min, lambda_max, widening
//            int32 steps_since_estimate, reestimate (0 or 1)
//            int64 identity length, then that many bytes of text
//            double q[dofs], v[dofs], v_prev[dofs], interpolants[tets or 0]
//   trailer  uint64 XXH64 (common/xxhash64.hpp says why) of header and payload
// The checksum is computed over the bytes as written, while the device writes
// them back (so it hides behind the fsync: bench/results/checkpoint_write),
// and a file is read
// only whole: its length, checksum, rank and rank count are verified before
// any value is used. Whatever later joins the solver's state goes into the
// payload, with the format version raised. Files of formats 1-3 (no
// checksum) are refused: nothing could tell whether they are intact.
//
// Written to PATH.tmp, fsynced, then PATH (if any) is renamed to PATH.prev,
// PATH.tmp to PATH, and the directory fsynced: a kill or a crash of the node
// leaves either generation whole. Ranks write theirs one after another, so a
// kill between two ranks' writes leaves some ranks a checkpoint newer than the
// others; the restart (app/restart_checkpoint.hpp) picks the newest frame
// that verifies on every rank.
#include <string>
#include <vector>

#include "common/mesh.hpp"

namespace descent {

struct Checkpoint {
  int num_ranks = 1;
  int rank = 0;
  int frame = 0;  // the last completed frame
  long long num_global_vertices = 0;
  long long num_global_tets = 0;
  double time = 0;
  // The stepper's StepMemory (solver/stepper.hpp).
  double alpha = 0;
  double lambda_min = 0, lambda_max = 0, widening = 1;
  int steps_since_estimate = 0;
  bool reestimate = false;
  // What defines the run (app/run_identity.hpp), for --restart to check.
  std::string identity;
  std::vector<double> q, v, v_prev;  // 3 per local vertex
  std::vector<double> interpolants;  // per local tet; empty without conversion
};

std::string checkpoint_path(const std::string& dir, int rank, int num_ranks);

// Throws InputError naming the path when it cannot be written.
void write_checkpoint(const std::string& path, const Checkpoint& checkpoint);

// Reads and verifies the checkpoint of `rank` of `num_ranks` at `path`;
// throws InputError naming the path and what failed: missing, empty,
// truncated, not a checkpoint, of another format, damaged (checksum), or
// another rank's or rank count's file.
Checkpoint read_checkpoint(const std::string& path, int rank, int num_ranks);

}  // namespace descent
