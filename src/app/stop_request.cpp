#include "app/stop_request.hpp"

#include <csignal>

#include "comm/mpi_check.hpp"

namespace descent {

namespace {

constexpr int kStopSignals[] = {SIGTERM, SIGINT, SIGUSR1};
struct sigaction previous[sizeof(kStopSignals) / sizeof(kStopSignals[0])];

volatile std::sig_atomic_t caught = 0;

extern "C" void record_stop(int signal) {
  if (caught != 0 && signal == SIGINT) {
    // Asked twice: the user wants out now (async-signal-safe calls only).
    std::signal(SIGINT, SIG_DFL);
    std::raise(SIGINT);
    return;
  }
  if (caught == 0) caught = signal;
}

}  // namespace

StopRequest::StopRequest() {
  caught = 0;
  struct sigaction action = {};
  action.sa_handler = record_stop;
  sigemptyset(&action.sa_mask);
  // Restarted, not failed: a signal must not break the MPI or file call it
  // lands in.
  action.sa_flags = SA_RESTART;
  for (std::size_t s = 0; s < std::size(kStopSignals); ++s)
    sigaction(kStopSignals[s], &action, &previous[s]);
}

StopRequest::~StopRequest() {
  // After a stop (caught or agreed) the handlers stay until the process
  // ends: once the first rank exits with kStoppedExitCode, mpiexec sends
  // SIGTERM to the ranks still in MPI_Finalize, which would die of it
  // (status 143) after their checkpoints were written.
  if (caught != 0) return;
  for (std::size_t s = 0; s < std::size(kStopSignals); ++s)
    sigaction(kStopSignals[s], &previous[s], nullptr);
}

int StopRequest::agreed(MPI_Comm comm) const {
  int signal = caught;
  DESCENT_MPI_CHECK(MPI_Allreduce(MPI_IN_PLACE, &signal, 1, MPI_INT, MPI_MAX, comm));
  // A rank that caught nothing stops too: it keeps its handlers as well.
  if (caught == 0) caught = signal;
  return signal;
}

const char* signal_name(int signal) {
  switch (signal) {
    case SIGTERM:
      return "SIGTERM";
    case SIGINT:
      return "SIGINT";
    case SIGUSR1:
      return "SIGUSR1";
    default:
      return "an unexpected signal";
  }
}

}  // namespace descent
