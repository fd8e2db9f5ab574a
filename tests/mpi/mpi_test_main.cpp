// GoogleTest main for tests run under mpiexec: MPI is initialised around the
// whole run, only rank 0 prints (every rank with DESCENT_TEST_ALL_RANKS=1 in
// the environment, to see another rank's failure), and every rank's failures
// count toward the exit code so mpiexec reports a failure seen on any rank.
#include <gtest/gtest.h>
#include <mpi.h>

#include <cstdlib>
#include <string>

#include "solver/petsc/petsc_session.hpp"

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  ::testing::InitGoogleTest(&argc, argv);
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  const char* all = std::getenv("DESCENT_TEST_ALL_RANKS");
  if (rank != 0 && !(all && std::string(all) == "1")) {
    auto& listeners = ::testing::UnitTest::GetInstance()->listeners();
    delete listeners.Release(listeners.default_result_printer());
  }
  int failed = RUN_ALL_TESTS();
  int any_failed = 0;
  MPI_Allreduce(&failed, &any_failed, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  descent::finish_petsc();  // when a test started PETSc
  MPI_Finalize();
  return any_failed;
}
