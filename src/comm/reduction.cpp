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
  const double start = MPI_Wtime();
  double global = value;
  DESCENT_MPI_CHECK(MPI_Allreduce(&value, &global, 1, MPI_DOUBLE, MPI_MAX, comm_));
  ++counters_.dot_allreduces;
  counters_.seconds += MPI_Wtime() - start;
  return global;
}

void EnergyReduction::sum_in_place(std::vector<double>& values) {
  if (values.empty()) return;
  DESCENT_MPI_CHECK(MPI_Allreduce(MPI_IN_PLACE, values.data(), static_cast<int>(values.size()),
                                  MPI_DOUBLE, MPI_SUM, comm_));
  ++counters_.other_allreduces;
}

}  // namespace descent
