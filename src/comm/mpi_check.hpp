#pragma once
// Every MPI call's return code is checked; a failure names the call and the
// MPI error string.
#include <mpi.h>

#include "common/error.hpp"

namespace descent::detail {

inline void check_mpi(int code, const char* call, const char* file, int line) {
  if (code == MPI_SUCCESS) return;
  char text[MPI_MAX_ERROR_STRING];
  int length = 0;
  MPI_Error_string(code, text, &length);
  throw MpiError(concat(file, ":", line, ": ", call, " failed: ", std::string(text, length)));
}

}  // namespace descent::detail

#define DESCENT_MPI_CHECK(call) ::descent::detail::check_mpi((call), #call, __FILE__, __LINE__)
