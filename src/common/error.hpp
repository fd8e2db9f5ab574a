#pragma once
// Error families of descent. Every throw names the culprit: the file and line of
// an input, the scene key, the element, or the library call that failed.
#include <sstream>
#include <stdexcept>
#include <string>

namespace descent {

struct Error : std::runtime_error {
  using std::runtime_error::runtime_error;
};
// Bad user input: mesh files, scene files, command-line values.
struct InputError : Error {
  using Error::Error;
};
struct MpiError : Error {
  using Error::Error;
};
struct MetisError : Error {
  using Error::Error;
};
struct Hdf5Error : Error {
  using Error::Error;
};
// Partitioning failed (PT-Scotch, or a part left without tets).
struct PartitionError : Error {
  using Error::Error;
};
// Thrown, inside a collective phase, on the ranks whose own work succeeded
// when another rank failed: that rank's error is the one to report.
struct PeerFailure : Error {
  PeerFailure() : Error("another rank failed") {}
};
// An internal invariant broke: a bug in descent, not in the input.
struct LogicError : Error {
  using Error::Error;
};

namespace detail {
template <class... Args>
std::string concat(const Args&... args) {
  std::ostringstream os;
  (os << ... << args);
  return os.str();
}
}  // namespace detail

}  // namespace descent

// Always checked, in every build type.
#define DESCENT_VERIFY(cond, ...)                                                                 \
  do {                                                                                            \
    if (!(cond))                                                                                  \
      throw ::descent::LogicError(::descent::detail::concat(__FILE__, ":", __LINE__, ": check '", \
                                                            #cond, "' failed: ", __VA_ARGS__));   \
  } while (0)

// Checked in debug builds only (hot loops).
#ifdef NDEBUG
#define DESCENT_ASSERT(cond, ...) ((void)0)
#else
#define DESCENT_ASSERT(cond, ...) DESCENT_VERIFY(cond, __VA_ARGS__)
#endif
