#include "app/memory_report.hpp"

#include <sys/resource.h>

#include <algorithm>
#include <numeric>
#include <sstream>
#include <vector>

namespace descent {

std::string peak_memory_report(MPI_Comm comm) {
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  const double mine = static_cast<double>(usage.ru_maxrss) / 1024.0;  // Linux: KiB
  std::vector<double> all(rank == 0 ? size : 0);
  MPI_Gather(&mine, 1, MPI_DOUBLE, all.data(), 1, MPI_DOUBLE, 0, comm);
  if (rank != 0) return "";
  const double mean = std::accumulate(all.begin(), all.end(), 0.0) / size;
  std::ostringstream line;
  line.precision(0);
  line << std::fixed << "peak RSS per rank:";
  constexpr int kListed = 16;
  if (size <= kListed) {
    for (double mb : all) line << ' ' << mb;
    line << " MiB";
  } else {
    const auto [lo, hi] = std::minmax_element(all.begin(), all.end());
    line << " min " << *lo << ", max " << *hi << " MiB";
  }
  line << " (mean " << mean << ", rank 0 " << std::showpos << 100 * (all[0] / mean - 1)
       << std::noshowpos << "%)";
  return line.str();
}

}  // namespace descent
