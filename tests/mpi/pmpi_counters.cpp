#include "pmpi_counters.hpp"

#include <mpi.h>

namespace {
long g_allreduce = 0;
long g_other_collectives = 0;
long g_allgatherv = 0;
}  // namespace

namespace descent::testing {
long pmpi_allreduces() { return g_allreduce; }
long pmpi_other_collectives() { return g_other_collectives; }
long pmpi_allgathervs() { return g_allgatherv; }
}  // namespace descent::testing

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
int MPI_Allgatherv(const void* send, int scount, MPI_Datatype stype, void* recv, const int* rcounts,
                   const int* displs, MPI_Datatype rtype, MPI_Comm comm) {
  ++g_allgatherv;
  return PMPI_Allgatherv(send, scount, stype, recv, rcounts, displs, rtype, comm);
}
int MPI_Gather(const void* send, int scount, MPI_Datatype stype, void* recv, int rcount,
               MPI_Datatype rtype, int root, MPI_Comm comm) {
  ++g_other_collectives;
  return PMPI_Gather(send, scount, stype, recv, rcount, rtype, root, comm);
}
}
