// Checkpoints that prove themselves (io/checkpoint.hpp) and the restart's
// choice among them (app/restart_checkpoint.hpp): every way a file can be
// wrong is named, and --restart takes the newest frame that verifies on
// every rank, or refuses on every rank with one message.
#include <gtest/gtest.h>
#include <mpi.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <string>
#include <vector>

#include "app/restart_checkpoint.hpp"
#include "common/error.hpp"
#include "file_bytes.hpp"
#include "io/checkpoint.hpp"
#include "shared_test_directory.hpp"
#include "world_rank.hpp"

namespace descent {
namespace {

namespace fs = std::filesystem;
using testing::world_rank;
using testing::world_size;

const std::string kIdentity = "material.young = 100000\nprecision = double\n";

// This rank's checkpoint of `frame`, with values that differ by rank and frame.
Checkpoint sample(int frame) {
  Checkpoint c;
  c.rank = world_rank();
  c.num_ranks = world_size();
  c.frame = frame;
  c.num_global_vertices = 40;
  c.num_global_tets = 90;
  c.time = 0.01 * frame;
  c.alpha = 0.5 + c.rank;
  c.lambda_min = 1e-3;
  c.lambda_max = 2.5;
  c.widening = 1.1;
  c.steps_since_estimate = frame;
  c.reestimate = frame % 2 == 1;
  c.identity = kIdentity;
  for (int k = 0; k < 30; ++k) {
    c.q.push_back(frame + 0.001 * k + c.rank);
    c.v.push_back(-0.5 * k);
    c.v_prev.push_back(0.25 * k);
  }
  c.interpolants = {0.0, 0.5, 1.0};
  return c;
}

void expect_same(const Checkpoint& a, const Checkpoint& b) {
  EXPECT_EQ(a.rank, b.rank);
  EXPECT_EQ(a.num_ranks, b.num_ranks);
  EXPECT_EQ(a.frame, b.frame);
  EXPECT_EQ(a.num_global_vertices, b.num_global_vertices);
  EXPECT_EQ(a.num_global_tets, b.num_global_tets);
  EXPECT_EQ(a.time, b.time);
  EXPECT_EQ(a.alpha, b.alpha);
  EXPECT_EQ(a.lambda_min, b.lambda_min);
  EXPECT_EQ(a.lambda_max, b.lambda_max);
  EXPECT_EQ(a.widening, b.widening);
  EXPECT_EQ(a.steps_since_estimate, b.steps_since_estimate);
  EXPECT_EQ(a.reestimate, b.reestimate);
  EXPECT_EQ(a.identity, b.identity);
  EXPECT_EQ(a.q, b.q);
  EXPECT_EQ(a.v, b.v);
  EXPECT_EQ(a.v_prev, b.v_prev);
  EXPECT_EQ(a.interpolants, b.interpolants);
}

using testing::read_bytes;
using testing::write_bytes;

// The message read_checkpoint throws for `path`, or "" when it reads.
std::string read_error(const std::string& path, int rank, int size) {
  try {
    read_checkpoint(path, rank, size);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

void expect_error(const std::string& path, const std::string& part) {
  const std::string message = read_error(path, world_rank(), world_size());
  EXPECT_NE(message.find(path), std::string::npos) << message;
  EXPECT_NE(message.find(part), std::string::npos) << "expected '" << part << "' in: " << message;
}

TEST(Checkpoint, WrittenAndReadBackWhole) {
  SharedTestDirectory dir("descent_test_checkpoint_round_trip");
  const std::string path = checkpoint_path(dir.path().string(), world_rank(), world_size());
  write_checkpoint(path, sample(3));
  write_checkpoint(path, sample(4));
  expect_same(read_checkpoint(path, world_rank(), world_size()), sample(4));
  expect_same(read_checkpoint(path + ".prev", world_rank(), world_size()), sample(3));
  EXPECT_FALSE(fs::exists(path + ".tmp"));
  expect_all_ranks_passed();
}

TEST(Checkpoint, EveryDamageIsNamed) {
  SharedTestDirectory dir("descent_test_checkpoint_damage");
  const std::string path = checkpoint_path(dir.path().string(), world_rank(), world_size());
  write_checkpoint(path, sample(2));
  const std::vector<char> good = read_bytes(path);
  const std::string bad = path + ".bad";

  expect_error(path + ".none", "is missing");
  write_bytes(bad, {});
  expect_error(bad, "is empty");
  write_bytes(bad, std::vector<char>(good.begin(), good.begin() + 30));
  expect_error(bad, "is truncated");
  write_bytes(bad, std::vector<char>(good.begin(), good.end() - 9));
  expect_error(bad, "is truncated");
  std::vector<char> longer = good;
  longer.push_back('x');
  write_bytes(bad, longer);
  expect_error(bad, "1 bytes after its end");
  // Two bytes flipped anywhere: the header, the payload, the checksum.
  for (const std::size_t at : {std::size_t{22}, good.size() / 2, good.size() - 2}) {
    std::vector<char> flipped = good;
    flipped[at] ^= 0x10;
    flipped[at + 1] ^= 0x01;
    write_bytes(bad, flipped);
    const std::string message = read_error(bad, world_rank(), world_size());
    EXPECT_TRUE(message.find("is damaged") != std::string::npos ||
                message.find("truncated") != std::string::npos ||
                message.find("after its end") != std::string::npos)
        << "byte " << at << ": " << message;
  }
  std::vector<char> old = good;
  old[19] = '3';
  write_bytes(bad, old);
  expect_error(bad, "of format '3', which has no checksum");
  write_bytes(bad, {'h', 'e', 'l', 'l', 'o', '\n'});
  expect_error(bad, "is not a descent checkpoint");
  // Another rank's (or rank count's) intact file in this one's place.
  const std::string message = read_error(path, world_rank() + 1, world_size() + 1);
  EXPECT_NE(message.find(detail::concat("holds the state of rank ", world_rank(), " of ",
                                        world_size(), ", not of rank ", world_rank() + 1)),
            std::string::npos)
      << message;
  expect_all_ranks_passed();
}

// restart_checkpoint on every rank: the frame it chose, or "" for a refusal
// (then `message` holds the reporting rank's error, others' stay empty).
int chosen_frame(const std::string& dir, std::string& message) {
  try {
    return restart_checkpoint(MPI_COMM_WORLD, dir, kIdentity).frame;
  } catch (const PeerFailure&) {
  } catch (const InputError& e) {
    message = e.what();
  }
  return -1;
}

// The message of the one rank that reports a refusal, on rank 0.
std::string refusal(const std::string& dir) {
  std::string mine;
  EXPECT_EQ(chosen_frame(dir, mine), -1);
  int reporters = mine.empty() ? 0 : 1;
  MPI_Allreduce(MPI_IN_PLACE, &reporters, 1, MPI_INT, MPI_SUM, MPI_COMM_WORLD);
  EXPECT_EQ(reporters, 1);
  // Rank 0 learns the reporter's text.
  int length = static_cast<int>(mine.size()), from = mine.empty() ? -1 : world_rank();
  MPI_Allreduce(MPI_IN_PLACE, &from, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  if (from < 0) return "";
  MPI_Bcast(&length, 1, MPI_INT, from, MPI_COMM_WORLD);
  mine.resize(length);
  MPI_Bcast(mine.data(), length, MPI_CHAR, from, MPI_COMM_WORLD);
  return mine;
}

TEST(Restart, TakesTheNewestFrameThatVerifiesOnEveryRank) {
  SharedTestDirectory dir("descent_test_restart_choice");
  const std::string out = dir.path().string();
  const int last = world_size() - 1;
  const std::string path = checkpoint_path(out, world_rank(), world_size());
  write_checkpoint(path, sample(5));
  write_checkpoint(path, sample(10));
  std::string message;
  EXPECT_EQ(chosen_frame(out, message), 10) << message;

  // The last rank's newer file damaged: every rank goes back to frame 5.
  MPI_Barrier(MPI_COMM_WORLD);
  if (world_rank() == last) {
    std::vector<char> bytes = read_bytes(path);
    bytes[bytes.size() / 2] ^= 0x20;
    bytes[bytes.size() / 2 + 1] ^= 0x02;
    write_bytes(path, bytes);
  }
  MPI_Barrier(MPI_COMM_WORLD);
  EXPECT_EQ(chosen_frame(out, message), 5) << message;

  // A kill between two ranks' rotations: rank 0 has frames 15 and 10, the
  // others 10 (and 10, damaged on the last rank): frame 10 is on every rank.
  write_checkpoint(path, sample(10));
  if (world_rank() == 0) write_checkpoint(path, sample(15));
  MPI_Barrier(MPI_COMM_WORLD);
  EXPECT_EQ(chosen_frame(out, message), world_size() > 1 ? 10 : 15) << message;

  // No frame on every rank: both of the last rank's files damaged.
  MPI_Barrier(MPI_COMM_WORLD);
  if (world_rank() == last) {
    for (const std::string& file : {path, path + ".prev"}) {
      std::vector<char> bytes = read_bytes(file);
      bytes[bytes.size() / 2] ^= 0x01;
      write_bytes(file, bytes);
    }
  }
  MPI_Barrier(MPI_COMM_WORLD);
  std::string text = refusal(out);
  if (world_rank() == 0) {
    EXPECT_NE(text.find("no frame has a verified checkpoint on every rank"), std::string::npos)
        << text;
    EXPECT_NE(text.find(checkpoint_path(out, last, world_size()) + " is damaged"),
              std::string::npos)
        << text;
  }

  // A missing rank: the last rank's files removed.
  if (world_rank() == last) {
    fs::remove(path);
    fs::remove(path + ".prev");
  }
  MPI_Barrier(MPI_COMM_WORLD);
  text = refusal(out);
  const std::string missing = world_size() > 1
                                  ? checkpoint_path(out, last, world_size()) + " is missing"
                                  : "holds no checkpoint";
  if (world_rank() == 0) {
    EXPECT_NE(text.find(missing), std::string::npos) << text;
  }

  // Another run's checkpoint: refused naming what differs.
  write_checkpoint(path, sample(20));
  MPI_Barrier(MPI_COMM_WORLD);
  try {
    restart_checkpoint(MPI_COMM_WORLD, out, "material.young = 250000\nprecision = double\n");
    ADD_FAILURE() << "another run's checkpoint was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("belongs to another run"), std::string::npos) << e.what();
  } catch (const PeerFailure&) {
  }
  expect_all_ranks_passed();
}

TEST(Restart, NoCheckpointsAtAllSaysSo) {
  SharedTestDirectory dir("descent_test_restart_none");
  const std::string text = refusal(dir.path().string());
  if (world_rank() == 0) {
    EXPECT_NE(text.find("does not exist"), std::string::npos) << text;
  }
  expect_all_ranks_passed();
}

}  // namespace
}  // namespace descent
