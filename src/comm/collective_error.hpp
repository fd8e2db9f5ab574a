#pragma once
// Local checks inside a collective set-up phase: a rank that finds an error
// must not leave the others waiting in the next collective call. Every
// rank learns whether any failed; the failing ranks throw their own error,
// the others a PeerFailure, which the caller's agree() (app/agree.hpp)
// counts as no error of theirs.
#include <mpi.h>

#include <string>

#include "comm/mpi_check.hpp"
#include "common/error.hpp"

namespace descent {

template <class ErrorType = InputError>
void throw_if_any_failed(MPI_Comm comm, const std::string& local_error) {
  int failed = local_error.empty() ? 0 : 1;
  DESCENT_MPI_CHECK(MPI_Allreduce(MPI_IN_PLACE, &failed, 1, MPI_INT, MPI_MAX, comm));
  if (!local_error.empty()) throw ErrorType(local_error);
  if (failed) throw PeerFailure();
}

}  // namespace descent
