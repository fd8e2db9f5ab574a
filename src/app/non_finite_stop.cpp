#include "app/non_finite_stop.hpp"

#include "app/console.hpp"
#include "comm/mpi_check.hpp"

namespace descent {

const char* step_status(const StepStats& step) {
  if (!step.finite) return "failed_non_finite";
  if (step.retried_from_start) return "retried_from_start";
  if (step.stalled) return "stalled";
  if (step.nonfinite_rollbacks > 0) return "rolled_back_non_finite";
  return "ok";
}

namespace {

std::string describe_site(const NonFiniteSite& site) {
  if (site.kind == NonFiniteSite::Kind::sum)
    return detail::concat("the ", describe(site.kind), " is ", site.value);
  return detail::concat("the ", describe(site.kind), " ", site.id, " is ", site.value);
}

}  // namespace

void warn_rolled_back(int frame, int rank, const NonFiniteSite& site) {
  warn("frame %d, rank %d: a trial state was not finite (%s); rolled back", frame, rank,
       describe_site(site).c_str());
}

void report_failed_step(MPI_Comm comm, int frame, const StepStats& step,
                        const std::string& last_good) {
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  const int offer = step.failed_at.found() ? rank : size;
  int reporter = size;
  DESCENT_MPI_CHECK(MPI_Allreduce(&offer, &reporter, 1, MPI_INT, MPI_MIN, comm));
  if (reporter == size) reporter = 0;
  if (rank != reporter) return;
  const std::string culprit =
      step.failed_at.found()
          ? detail::concat("on rank ", rank, " ", describe_site(step.failed_at))
          : std::string("no single term is non-finite on any rank: the total overflowed");
  throw NonFiniteError(detail::concat(
      "frame ", frame, ": no state with finite energy was reached in the step (", step.rollbacks,
      " rollbacks, ", step.nonfinite_rollbacks, " of them non-finite trials); ", culprit,
      ". The run stops; the last good state, frame ", frame - 1, ", is in ", last_good));
}

}  // namespace descent
