#pragma once
// Helpers of MPI tests that write files: a directory every rank names alike,
// and a test verdict every rank shares.
#include <gtest/gtest.h>
#include <mpi.h>

#include <filesystem>
#include <random>
#include <string>

namespace descent {

// A directory under the system temp directory, named by rank 0 (prefix and a
// random suffix), the same on every rank of MPI_COMM_WORLD, and removed by
// rank 0 once every rank is done with it.
class SharedTestDirectory {
 public:
  explicit SharedTestDirectory(const std::string& prefix) {
    int rank = 0;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    std::string name;
    if (rank == 0) {
      std::random_device random;
      name = prefix + "_" + std::to_string(random()) + std::to_string(random());
    }
    int length = static_cast<int>(name.size());
    MPI_Bcast(&length, 1, MPI_INT, 0, MPI_COMM_WORLD);
    name.resize(length);
    MPI_Bcast(name.data(), length, MPI_CHAR, 0, MPI_COMM_WORLD);
    path_ = std::filesystem::temp_directory_path() / name;
  }
  ~SharedTestDirectory() {
    MPI_Barrier(MPI_COMM_WORLD);
    int rank = 0;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    std::error_code ignored;
    if (rank == 0) std::filesystem::remove_all(path_, ignored);
  }
  SharedTestDirectory(const SharedTestDirectory&) = delete;
  SharedTestDirectory& operator=(const SharedTestDirectory&) = delete;
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

// Fails the current test on every rank when it failed on any.
inline void expect_all_ranks_passed() {
  int failed = ::testing::Test::HasFailure() ? 1 : 0;
  MPI_Allreduce(MPI_IN_PLACE, &failed, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  EXPECT_EQ(failed, 0) << "some rank failed this test";
}

}  // namespace descent
