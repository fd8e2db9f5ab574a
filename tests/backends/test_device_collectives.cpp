// Collectives of the device stepper (emulated backend), counted at the MPI
// boundary through PMPI (this file replaces MPI_Allreduce & co. for this test
// executable): exactly one MPI_Allreduce per energy check (12 per 96-iteration
// step) and no other collective inside a step, as on the CPU
// (tests/mpi/test_collectives.cpp), for gather and scatter assembly.
#include <gtest/gtest.h>
#include <mpi.h>

#include "app/scene_mesh.hpp"
#include "tests/backends/compare_runs.hpp"
#include "tests/mpi/small_scenes.hpp"

namespace {
long g_allreduce = 0;
long g_other_collectives = 0;
}  // namespace

extern "C" {
int MPI_Allreduce(const void* send, void* recv, int count, MPI_Datatype type, MPI_Op op,
                  MPI_Comm comm) {
  ++g_allreduce;
  return PMPI_Allreduce(send, recv, count, type, op, comm);
}
int MPI_Bcast(void* buffer, int count, MPI_Datatype type, int root, MPI_Comm comm) {
  ++g_other_collectives;
  return PMPI_Bcast(buffer, count, type, root, comm);
}
int MPI_Barrier(MPI_Comm comm) {
  ++g_other_collectives;
  return PMPI_Barrier(comm);
}
int MPI_Reduce(const void* send, void* recv, int count, MPI_Datatype type, MPI_Op op, int root,
               MPI_Comm comm) {
  ++g_other_collectives;
  return PMPI_Reduce(send, recv, count, type, op, root, comm);
}
int MPI_Allgather(const void* send, int scount, MPI_Datatype stype, void* recv, int rcount,
                  MPI_Datatype rtype, MPI_Comm comm) {
  ++g_other_collectives;
  return PMPI_Allgather(send, scount, stype, recv, rcount, rtype, comm);
}
int MPI_Gather(const void* send, int scount, MPI_Datatype stype, void* recv, int rcount,
               MPI_Datatype rtype, int root, MPI_Comm comm) {
  ++g_other_collectives;
  return PMPI_Gather(send, scount, stype, recv, rcount, rtype, root, comm);
}
}

namespace descent {
namespace {

TEST(DeviceCollectives, OneAllreducePerCheckAndNothingElse) {
  Scene scene = testing::small_helix_scene();
  scene.solver.iterations = 96;
  scene.solver.check_interval = 8;
  const Mesh mesh = build_scene_mesh(scene.mesh);
  for (Assembly assembly : {Assembly::gather, Assembly::scatter}) {
    Simulation<float> sim(MPI_COMM_WORLD, scene, mesh,
                          testing::backend_of(BackendKind::emulated, assembly));
    for (int frame = 0; frame < 3; ++frame) {
      const long allreduce_before = g_allreduce;
      const long other_before = g_other_collectives;
      const StepStats step = sim.step();
      ASSERT_EQ(step.iterations, 96) << "the step ended early; the count below assumes a full step";
      EXPECT_EQ(g_allreduce - allreduce_before, 96 / 8)
          << to_string(assembly) << ", frame " << frame;
      EXPECT_EQ(g_other_collectives - other_before, 0)
          << to_string(assembly) << ", frame " << frame;
    }
  }
}

}  // namespace
}  // namespace descent
