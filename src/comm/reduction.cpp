#include "comm/reduction.hpp"

#include <cmath>

#include "comm/mpi_check.hpp"

namespace descent {

EnergySums EnergyReduction::sum(const Energy* local, int count) {
  const double start = MPI_Wtime();
  // [value0, magnitude0, value1, magnitude1, non-finite count 0, 1]
  double send[6] = {0, 0, 0, 0, 0, 0};
  for (int k = 0; k < count; ++k) {
    if (std::isfinite(local[k].value) && std::isfinite(local[k].magnitude)) {
      send[2 * k] = local[k].value;
      send[2 * k + 1] = local[k].magnitude;
    } else {
      send[4 + k] = 1;
    }
  }
  double global[6] = {0, 0, 0, 0, 0, 0};
  DESCENT_MPI_CHECK(MPI_Allreduce(send, global, 6, MPI_DOUBLE, MPI_SUM, comm_));
  ++counters_.allreduces;
  counters_.seconds += MPI_Wtime() - start;
  EnergySums sums;
  for (int k = 0; k < 2; ++k) {
    sums.energy[k] = {global[2 * k], global[2 * k + 1]};
    sums.finite[k] = global[4 + k] == 0.0;
  }
  return sums;
}

void EnergyReduction::sum_dots(double* values, int count) {
  const double start = MPI_Wtime();
  DESCENT_MPI_CHECK(MPI_Allreduce(MPI_IN_PLACE, values, count, MPI_DOUBLE, MPI_SUM, comm_));
  ++counters_.dot_allreduces;
  counters_.seconds += MPI_Wtime() - start;
}

double EnergyReduction::max_of(double value) {
  max_in_place(&value, 1);
  return value;
}

void EnergyReduction::max_in_place(double* values, int count) {
  const double start = MPI_Wtime();
  DESCENT_MPI_CHECK(MPI_Allreduce(MPI_IN_PLACE, values, count, MPI_DOUBLE, MPI_MAX, comm_));
  ++counters_.dot_allreduces;
  counters_.seconds += MPI_Wtime() - start;
}

namespace {

// Displacements of blocks of `counts` values laid end to end.
std::vector<int> block_offsets(const std::vector<int>& counts) {
  std::vector<int> offsets(counts.size(), 0);
  for (std::size_t r = 1; r < counts.size(); ++r) offsets[r] = offsets[r - 1] + counts[r - 1];
  return offsets;
}

template <class T>
void gatherv_to_root(MPI_Comm comm, MPI_Datatype type, const T* send, int count,
                     const std::vector<int>& counts, std::vector<T>& recv) {
  int rank = 0;
  DESCENT_MPI_CHECK(MPI_Comm_rank(comm, &rank));
  std::vector<int> offsets;
  if (rank == 0) {
    offsets = block_offsets(counts);
    recv.resize(counts.empty() ? 0 : static_cast<std::size_t>(offsets.back()) + counts.back());
  }
  DESCENT_MPI_CHECK(
      MPI_Gatherv(send, count, type, recv.data(), counts.data(), offsets.data(), type, 0, comm));
}

}  // namespace

std::vector<int> EnergyReduction::gather_counts(int count) {
  int rank = 0, size = 1;
  DESCENT_MPI_CHECK(MPI_Comm_rank(comm_, &rank));
  DESCENT_MPI_CHECK(MPI_Comm_size(comm_, &size));
  std::vector<int> counts(rank == 0 ? size : 0);
  DESCENT_MPI_CHECK(MPI_Gather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, comm_));
  ++counters_.root_gathers;
  return counts;
}

void EnergyReduction::gather_to_root(const double* send, int count, const std::vector<int>& counts,
                                     std::vector<double>& recv) {
  gatherv_to_root(comm_, MPI_DOUBLE, send, count, counts, recv);
  ++counters_.root_gathers;
}

void EnergyReduction::gather_to_root(const std::int32_t* send, int count,
                                     const std::vector<int>& counts,
                                     std::vector<std::int32_t>& recv) {
  gatherv_to_root(comm_, MPI_INT32_T, send, count, counts, recv);
  ++counters_.root_gathers;
}

void EnergyReduction::scatter_from_root(const std::vector<double>& send,
                                        const std::vector<int>& counts, double* recv, int count) {
  int rank = 0;
  DESCENT_MPI_CHECK(MPI_Comm_rank(comm_, &rank));
  const std::vector<int> offsets = rank == 0 ? block_offsets(counts) : std::vector<int>{};
  DESCENT_MPI_CHECK(MPI_Scatterv(send.data(), counts.data(), offsets.data(), MPI_DOUBLE, recv,
                                 count, MPI_DOUBLE, 0, comm_));
  ++counters_.root_scatters;
}

void EnergyReduction::sum_in_place(std::vector<double>& values) {
  if (values.empty()) return;
  DESCENT_MPI_CHECK(MPI_Allreduce(MPI_IN_PLACE, values.data(), static_cast<int>(values.size()),
                                  MPI_DOUBLE, MPI_SUM, comm_));
  ++counters_.other_allreduces;
}

}  // namespace descent
