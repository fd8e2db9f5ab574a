#pragma once
// A stop asked of a run from outside: SIGTERM (scancel, a batch system's
// time limit), SIGINT (Ctrl-C) or SIGUSR1 (what a job script forwards of
// Slurm's --signal=B:USR1@T). The handler only records the signal; the run
// looks at frame boundaries, where every rank agrees on it with one
// MPI_Allreduce of an int per frame (none in the iteration loop), writes a
// checkpoint of the last finished frame and ends with kStoppedExitCode, so
// `--restart` continues it. A second Ctrl-C while stopping ends the process
// at once, as Ctrl-C usually does.
#include <mpi.h>

namespace descent {

// EX_TEMPFAIL of sysexits.h: the run did not fail, it can be continued.
constexpr int kStoppedExitCode = 75;

class StopRequest {
 public:
  // Installs the handlers; the destructor restores the previous ones unless
  // a stop was caught (then they stay until the process ends).
  StopRequest();
  ~StopRequest();
  StopRequest(const StopRequest&) = delete;
  StopRequest& operator=(const StopRequest&) = delete;

  // Collective: the signal any rank has caught so far (the largest number if
  // ranks caught different ones), 0 if none has.
  int agreed(MPI_Comm comm) const;
};

// "SIGTERM", "SIGINT", "SIGUSR1" (the signals it handles).
const char* signal_name(int signal);

}  // namespace descent
