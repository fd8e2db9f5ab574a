#pragma once
// Checkpoints for restarting a killed run: one file per rank,
// DIR/checkpoint/rank-R-of-P.bin, holding that rank's whole solver state, so
// a restart on the same rank count continues bit for bit.
//
// File layout (native byte order, doubles IEEE 754):
//   "descent-checkpoint-3\n"        magic and version
//   int32  num_ranks, rank, frame
//   int64  num_global_vertices, num_global_tets, local dofs, local tets
//   double time, alpha, lambda_min, lambda_max, widening
//   int32  steps_since_estimate, reestimate (0 or 1)
//   int64  identity length, then that many bytes of text
//   double q[dofs], v[dofs], v_prev[dofs], interpolants[tets or 0]
// Versions 1 (no spectrum fields: its run estimates the spectrum anew at the
// first step) and 2 (no identity: nothing to check a restart against) are
// still read.
// Written to a temporary file and renamed, so a kill never leaves half a file;
// the previous checkpoint is kept as PATH.prev, because ranks write theirs
// one after another and a kill between two ranks' writes leaves some ranks a
// checkpoint newer than the others.
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
  // What defines the run (app/run_identity.hpp), for --restart to check;
  // empty in checkpoints of version 1 and 2.
  std::string identity;
  std::vector<double> q, v, v_prev;  // 3 per local vertex
  std::vector<double> interpolants;  // per local tet; empty without conversion
};

std::string checkpoint_path(const std::string& dir, int rank, int num_ranks);

// Throws InputError naming the path when it cannot be written.
void write_checkpoint(const std::string& path, const Checkpoint& checkpoint);

// Throws InputError naming the path when it is missing, truncated or not a
// checkpoint.
Checkpoint read_checkpoint(const std::string& path);

// The checkpoints of PATH and PATH.prev that exist, newest first; an
// InputError when neither does.
std::vector<Checkpoint> read_checkpoint_generations(const std::string& path);

}  // namespace descent
