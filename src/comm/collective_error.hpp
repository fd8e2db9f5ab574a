#pragma once
// Errors found inside a collective phase: a rank that fails must not leave
// the others waiting in the next collective call, so every rank learns of the
// failure and throws.
//  - throw_if_any_failed: local checks on every rank. The failing ranks throw
//    their own error, the others a PeerFailure, which the caller's agree()
//    (app/agree.hpp) counts as no error of theirs.
//  - throw_if_rank0_failed: a step that rank 0 alone does (reading a file,
//    touching the file system). Every rank throws rank 0's message.
#include <mpi.h>

#include <string>
#include <system_error>

#include "comm/broadcast_string.hpp"
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

// `error_on_rank0`: what failed on rank 0, empty for nothing (other ranks'
// values are not read).
template <class ErrorType = InputError>
void throw_if_rank0_failed(MPI_Comm comm, std::string error_on_rank0) {
  const std::string error = broadcast_string(comm, std::move(error_on_rank0));
  if (!error.empty()) throw ErrorType(error);
}

// The same for an errno value (0: success): "`what`: <the errno's text>".
inline void throw_if_rank0_failed(MPI_Comm comm, int errno_on_rank0, const std::string& what) {
  throw_if_rank0_failed(comm, errno_on_rank0 == 0
                                  ? std::string()
                                  : what + ": " + std::generic_category().message(errno_on_rank0));
}

}  // namespace descent
