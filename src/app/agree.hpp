#pragma once
// Set-up phases that may fail on some ranks only (a file one rank cannot
// read, METIS on rank 0): every rank runs the phase, then all agree, so an
// error on any rank ends every rank cleanly, never a hang, and the message is
// printed once, by the lowest failing rank.
#include <mpi.h>

#include <string>

#include "app/console.hpp"
#include "common/error.hpp"

namespace descent {

// Thrown on every rank once the failure has been printed.
struct ReportedFailure : Error {
  ReportedFailure() : Error("failure already reported") {}
};

template <class Phase>
auto agree(MPI_Comm comm, Phase&& phase) -> decltype(phase()) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  std::string error;
  using Result = decltype(phase());
  Result result{};
  try {
    result = phase();
  } catch (const ReportedFailure&) {
    throw;  // an inner agree() has already made every rank throw this
  } catch (const PeerFailure&) {
    // Another rank failed and reports its own error below.
  } catch (const Error& e) {
    error = e.what();
  } catch (const std::exception& e) {
    error = std::string("unexpected error: ") + e.what();
  }
  const int mine = error.empty() ? -1 : rank;
  int reporter = -1;
  MPI_Allreduce(&mine, &reporter, 1, MPI_INT, MPI_MAX, comm);
  if (reporter < 0) return result;
  // The lowest failing rank reports: failing ranks offer their rank, others a
  // rank past the end.
  int size = 1;
  MPI_Comm_size(comm, &size);
  const int offer = error.empty() ? size : rank;
  MPI_Allreduce(&offer, &reporter, 1, MPI_INT, MPI_MIN, comm);
  if (rank == reporter) {
    if (size > 1)
      report_error("rank %d: %s", rank, error.c_str());
    else
      report_error("%s", error.c_str());
  }
  throw ReportedFailure();
}

}  // namespace descent
