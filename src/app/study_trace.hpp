#pragma once
// One time step of any method from a simulation's current state, observed
// iteration by iteration: eps(q_k), wall time and collectives spent by the
// method up to iteration k. The measurement's own energy reduction and its
// time are kept out of both (a separate EnergyReduction, the clock paused).
// The simulation's state is left untouched. Collective over comm.
#include <mpi.h>

#include <string>
#include <vector>

#include "app/simulation.hpp"

namespace descent {

struct IterationRecord {
  int k = 0;                  // iteration (0: the initial guess)
  double energy = 0;          // eps(q_k), all ranks
  double seconds = 0;         // the method's wall time since the step began (rank 0's clock)
  long collectives = 0;       // the method's MPI_Allreduce calls since the step began
  double reduce_seconds = 0;  // of which time inside those collectives
  // Rank 0's processor time over the same span: on a machine shared with
  // other jobs the wall time measures the load too, this much less so.
  double cpu_seconds = 0;
  // Kinetic energy sum m |v_k|^2 / 2 of the iterate's velocity v_k = (q_k - q_t)/h
  // (paper 2, Fig. 3), all ranks.
  double kinetic = 0;
};

struct StepTrace {
  SolverSpec spec;
  StepStats stats;
  std::vector<IterationRecord> records;
};

// `twin`: a double simulation of the same partition holding the same state,
// whose problem the records evaluate (the simulation's own when null). A
// float study measures so, with the twin's held positions, q_t and y, so e_k
// shows the float iterates' accuracy in the double problem, not float's
// evaluation of eps nor float's rounding of the problem's data.
template <class Real>
StepTrace trace_step(MPI_Comm comm, Simulation<Real>& sim, const SolverSpec& spec,
                     const Simulation<double>* twin = nullptr);

// e_k = (eps(q_k) - eps*) / (eps(q_0) - eps*) per record.
std::vector<double> relative_errors(const StepTrace& trace, double energy_star);

}  // namespace descent
