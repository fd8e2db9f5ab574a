#pragma once
// One run's distributed set-up and time stepping, for the command line, the
// tests and the benchmarks alike: from its piece of the partitioned mesh
// (partition/distribute.hpp) each rank builds its halo, problem and solver,
// and step() advances every rank by one time step.
#include <mpi.h>

#include <memory>
#include <string>
#include <vector>

#include "backends/backend.hpp"
#include "comm/halo.hpp"
#include "comm/reduction.hpp"
#include "common/mesh.hpp"
#include "io/checkpoint.hpp"
#include "io/scene.hpp"
#include "partition/distribute.hpp"
#include "solver/local_problem.hpp"
#include "solver/stepper.hpp"

namespace descent {

template <class Real>
class Simulation {
 public:
  // Collective over comm. Every rank passes its own piece of the mesh.
  // `backend` picks the stepper's backend (backends/backend.hpp; default:
  // the CPU).
  Simulation(MPI_Comm comm, const Scene& scene, DistributedMesh mesh,
             const BackendChoice& backend = {});
  // The same from a whole mesh every rank holds (tests, small meshes): each
  // rank takes its slice, and the set-up partitions it as scene.partition says.
  Simulation(MPI_Comm comm, const Scene& scene, const Mesh& mesh,
             const BackendChoice& backend = {});

  // One time step. A step whose predicted initial guess leads to no finite
  // state (e.g. a tet inverted by the extrapolation, where no shorter step
  // gets back) is taken again once from the step start q_t, with the step
  // length it began with; StepStats::retried_from_start says so.
  StepStats step();

  // Starts from positions other than the rest shape (xyz by global vertex id,
  // at rest velocity): for recovery tests and restarts.
  void set_positions(const std::vector<double>& global_xyz);

  // This rank's whole solver state after `frame`, and back (a checkpoint of
  // another mesh, rank or rank count is an InputError).
  Checkpoint checkpoint(int frame) const;
  void restore(const Checkpoint& checkpoint);

  const LocalMesh& local_mesh() const { return local_; }
  // The solver keys the simulation's own stepper runs with.
  const SolverSpec& solver_spec() const { return scene_.solver; }
  const LocalProblem<Real>& problem() const { return problem_; }
  // For `descent study` and method tests: other methods over the same
  // problem, started from this state.
  LocalProblem<Real>& problem() { return problem_; }
  const BodyState<Real>& state() const { return state_; }
  const PartitionQuality& partition_quality() const { return quality_; }
  const HaloCounters& halo_counters() const { return halo_.counters(); }
  const ReductionCounters& reduction_counters() const { return reduction_.counters(); }
  const Stepper<Real>& stepper() const { return *solver_; }
  Stepper<Real>& stepper() { return *solver_; }
  std::string stepper_timing_report() const { return descent::stepper_timing_report(*solver_); }
  std::string preconditioner_report(bool used) const {
    return descent::preconditioner_report(*solver_, local_.num_tets(), used);
  }
  // Where contact between bodies spent its time on this rank (pair search,
  // ghosts, terms, guard) as a share of `step_ms`; empty without it.
  std::string body_contact_report(double step_ms);
  // Device memory of a device stepper, per tet and per vertex; empty on the CPU.
  std::string device_memory_report() const {
    return descent::device_memory_report(*solver_, local_.num_tets(), local_.num_vertices());
  }

  // Positions and velocities of owned vertices (3 per vertex, in local order
  // [0, num_owned)), after the last step.
  std::vector<double> owned_positions() const;
  std::vector<double> owned_velocities() const;

  // Per-region measurements after the last step, for the stats: names and
  // values in the same order (none when the scene has no load, no moving
  // fixed region and is not quasi-static). Collective (one allreduce).
  const std::vector<std::string>& measurement_names() const { return measurement_names_; }
  std::vector<double> measure();

 private:
  Scene scene_;
  long long num_global_vertices_;
  long long num_global_tets_;
  std::vector<std::string> measurement_names_;
  PartitionQuality quality_;
  LocalMesh local_;
  Halo<Real> halo_;
  EnergyReduction reduction_;
  LocalProblem<Real> problem_;
  std::unique_ptr<Stepper<Real>> solver_;
  BodyState<Real> state_;
};

}  // namespace descent
