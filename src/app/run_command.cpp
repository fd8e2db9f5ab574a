#include "app/run_command.hpp"

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <string>

#include "app/agree.hpp"
#include "app/console.hpp"
#include "app/memory_report.hpp"
#include "app/mesh_setup.hpp"
#include "app/non_finite_stop.hpp"
#include "app/precision_choice.hpp"
#include "app/restart_checkpoint.hpp"
#include "app/run_identity.hpp"
#include "app/simulation.hpp"
#include "app/stop_request.hpp"
#include "comm/broadcast_string.hpp"
#include "common/error.hpp"
#include "io/checkpoint.hpp"
#include "io/frame_writer.hpp"

namespace descent {

namespace {

// Global ids of the tets this rank writes and their global vertex ids.
struct TetOutput {
  std::vector<global_index_t> vertices;
};

TetOutput tet_output(const LocalMesh& local) {
  TetOutput out;
  out.vertices.resize(local.tets.size());
  for (std::size_t k = 0; k < local.tets.size(); ++k)
    out.vertices[k] = local.global_vertex[local.tets[k]];
  return out;
}

// One line per fixed region with the number of vertices it holds (each
// counted by its owner, summed over ranks); a region that holds none is
// almost always a mistake in its box, so it is a warning (on stderr, even
// with --quiet). Collective.
void report_fixed_regions(MPI_Comm comm, const Scene& scene, const LocalMesh& local, bool talk) {
  if (scene.fixed.empty()) return;
  std::vector<long long> count(scene.fixed.size(), 0);
  for (std::size_t r = 0; r < scene.fixed.size(); ++r)
    for (index_t v = 0; v < local.num_owned; ++v)
      count[r] += scene.fixed[r].contains(&local.rest_positions[3 * static_cast<std::size_t>(v)]);
  MPI_Allreduce(MPI_IN_PLACE, count.data(), static_cast<int>(count.size()), MPI_LONG_LONG, MPI_SUM,
                comm);
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  if (rank != 0) return;
  for (std::size_t r = 0; r < scene.fixed.size(); ++r) {
    const FixedRegion& region = scene.fixed[r];
    const auto& lo = region.box_min;
    const auto& hi = region.box_max;
    if (count[r] == 0)
      warn("fixed.%zu holds no vertex: [%g, %g, %g] - [%g, %g, %g] misses the mesh", r, lo[0],
           lo[1], lo[2], hi[0], hi[1], hi[2]);
    else if (talk)
      inform("fixed.%zu: %lld vertices in [%g, %g, %g] - [%g, %g, %g], axes %s", r, count[r], lo[0],
             lo[1], lo[2], hi[0], hi[1], hi[2], region.axes.c_str());
  }
}

// The directory this run writes to: `dir` unless it already holds a run
// (frames or stats) and overwriting was not asked for, then the first free
// DIR.N. Decided on rank 0 and broadcast, so every rank writes to the same.
std::string output_directory(MPI_Comm comm, const std::string& dir, bool overwrite) {
  namespace fs = std::filesystem;
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  std::string chosen = dir;
  if (rank == 0 && !overwrite) {
    auto holds_run = [](const fs::path& d) {
      return fs::exists(d / "frames.h5") || fs::exists(d / "stats.csv");
    };
    for (int n = 1; holds_run(chosen); ++n) chosen = dir + "." + std::to_string(n);
  }
  return broadcast_string(comm, chosen);
}

template <class Real>
int run_scene_in(MPI_Comm comm, const Scene& scene, const RunOptions& options,
                 const BackendChoice& backend);

}  // namespace

int run_scene(MPI_Comm comm, const Scene& scene, const RunOptions& options) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  std::string note;
  const BackendChoice backend = choose_backend(comm, options.backend, &note);
  // Which GPU is used; why none is, only to those who asked for CUDA or for
  // detail (a CPU-only machine is not news).
  const bool asked_for_cuda = options.backend.backend == "cuda" || options.verbose;
  const bool tell_note = backend.kind == BackendKind::cuda || asked_for_cuda;
  if (rank == 0 && !note.empty() && !options.quiet && tell_note) inform("%s", note.c_str());
  const bool on_gpu = backend.kind == BackendKind::cuda;
  const PrecisionChoice precision =
      choose_precision(options.precision, on_gpu, scene.solver.accuracy);
  // On a GPU auto's choice depends on the target: say which it made.
  const bool tell_precision = options.verbose || (on_gpu && options.precision == "auto");
  if (rank == 0 && !options.quiet && tell_precision) inform("precision: %s", precision.why.c_str());
  return precision.use_float ? run_scene_in<float>(comm, scene, options, backend)
                             : run_scene_in<double>(comm, scene, options, backend);
}

namespace {

template <class Real>
int run_scene_in(MPI_Comm comm, const Scene& scene, const RunOptions& options,
                 const BackendChoice& backend) {
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  const bool talk = rank == 0 && !options.quiet;
  const char* precision = sizeof(Real) == 4 ? "float" : "double";
  // Set-up is timed to the first iteration: mesh, solver, output opened.
  const auto setup_start = std::chrono::steady_clock::now();
  auto seconds_since_start = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - setup_start).count();
  };

  MeshSetupOptions setup;
  setup.partition_file = options.partition_file;
  setup.talk = talk;
  DistributedMesh mesh = set_up_mesh(comm, scene, setup);
  const double mesh_seconds = seconds_since_start();
  const UnusedVertices unused = std::move(mesh.unused);
  if (talk) inform("%d rank(s) x %d thread(s), %s", size, omp_get_max_threads(), precision);
  report_fixed_regions(comm, scene, mesh.local, talk);

  Simulation<Real> sim(comm, scene, std::move(mesh), backend);
  const double solver_seconds = seconds_since_start() - mesh_seconds;
  if (talk && backend.kind != BackendKind::cpu)
    inform("backend %s: %s", to_string(backend.kind), sim.device_memory_report().c_str());
  if (talk && sim.stepper().preconditioner())
    inform("%s", sim.preconditioner_report(false).c_str());

  const LocalMesh& local = sim.local_mesh();
  const std::string identity =
      run_identity(scene, {mesh_digest(comm, local), partition_digest(comm, local)}, precision);
  auto checkpoint_of = [&](int frame) {
    Checkpoint c = sim.checkpoint(frame);
    c.identity = identity;
    return c;
  };
  const TetOutput tets = tet_output(local);
  const std::vector<double> rest(local.rest_positions.begin(),
                                 local.rest_positions.begin() + 3 * local.num_owned);
  FrameWriterLayout layout;
  layout.num_global_vertices = local.num_global_vertices;
  layout.num_global_tets = local.num_global_tets;
  layout.owned_vertex_ids = std::span(local.global_vertex.data(), local.num_owned);
  layout.tet_ids = local.global_tet;
  layout.tet_vertices = tets.vertices;
  layout.owned_rest_positions = rest;
  layout.unused_vertex_ids = unused.ids;
  layout.unused_rest_positions = unused.positions;
  // A restart continues in place.
  int first_frame = 1;
  if (options.restart) {
    const Checkpoint chosen = restart_checkpoint(comm, scene.output.dir, identity);
    sim.restore(chosen);
    first_frame = chosen.frame + 1;
    if (talk) inform("restarting after frame %d", chosen.frame);
  }
  const std::string out_dir = options.restart
                                  ? scene.output.dir
                                  : output_directory(comm, scene.output.dir, options.overwrite);
  // Said even with --quiet: the output is not where it was asked for.
  if (rank == 0 && out_dir != scene.output.dir)
    warn("%s holds an earlier run; writing to %s (--overwrite reuses it)", scene.output.dir.c_str(),
         out_dir.c_str());
  const int resume_after = options.restart ? first_frame - 1 : -1;
  FrameWriter frames(comm, out_dir, layout, resume_after);
  StatsWriter stats(comm, out_dir, sim.measurement_names(), resume_after);
  if (!options.restart) frames.write_frame(0, 0.0, sim.owned_positions(), sim.owned_velocities());
  const std::string setup_memory = peak_memory_report(comm);
  if (talk) {
    const double total = seconds_since_start();
    inform("set-up %.2f s to the first step: mesh %.2f s, solver %.2f s, output %.2f s", total,
           mesh_seconds, solver_seconds, total - mesh_seconds - solver_seconds);
    inform("after set-up, %s", setup_memory.c_str());
  }
  // The newest frame in frames.h5 (-1: none known), so a stop can add the
  // last good one without writing a frame twice.
  int last_written =
      options.restart ? (resume_after % scene.output.every == 0 ? resume_after : -1) : 0;

  // The newest checkpoint on disk (-1: none of this process), so a stop
  // writes one only where it lacks.
  int last_checkpoint = -1;

  const double h = scene.time.dt;
  int frames_run = 0;
  double total_ms = 0;
  long total_iterations = 0;
  int stalled_steps = 0, retried_steps = 0, resolution_limited_steps = 0;
  int capped_steps = 0;  // ran to solver.iterations short of solver.accuracy
  constexpr int kStallWarnings = 5;
  int nonfinite_steps = 0, nonfinite_warnings = 0;  // the latter on this rank
  const int checkpoint_every = scene.output.checkpoint_every;
  const StopRequest stop;
  for (int frame = first_frame; frame <= scene.time.frames; ++frame) {
    // Before the step, so a signal during set-up stops before any work.
    if (const int signal = stop.agreed(comm)) {
      // Frames and stats are flushed as they are written; what --restart
      // needs is the last finished frame's checkpoint.
      if (last_checkpoint != frame - 1)
        write_checkpoint(checkpoint_path(out_dir, rank, size), checkpoint_of(frame - 1));
      if (rank == 0)
        std::fprintf(stderr,
                     "descent: %s: stopped after frame %d of %d, checkpoint in %s/checkpoint; "
                     "continue with the same command plus --restart --out %s\n",
                     signal_name(signal), frame - 1, scene.time.frames, out_dir.c_str(),
                     out_dir.c_str());
      return kStoppedExitCode;
    }
    const double halo_before = sim.halo_counters().seconds;
    const double reduce_before = sim.reduction_counters().seconds;
    const auto start = std::chrono::steady_clock::now();
    const StepStats step = sim.step();
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    ++frames_run;
    total_ms += ms;
    total_iterations += step.iterations;

    FrameStats row;
    row.frame = frame;
    row.sim_time = frame * h;
    row.iterations = step.iterations;
    row.rollbacks = step.rollbacks;
    row.alpha = step.alpha;
    row.energy = step.energy;
    row.wall_ms = ms;
    row.halo_ms = 1e3 * (sim.halo_counters().seconds - halo_before);
    row.allreduce_ms = 1e3 * (sim.reduction_counters().seconds - reduce_before);
    row.stalled = step.stalled ? 1 : 0;
    row.nonfinite_rollbacks = step.nonfinite_rollbacks;
    row.status = step_status(step);
    row.lambda_min = step.lambda_min;
    row.lambda_max = step.lambda_max;
    row.rho = step.rho;
    row.spectrum_steps = step.spectrum_steps;
    row.error_estimate = step.error_estimate;
    // A failed step has nothing to measure (and measuring is collective, so
    // every rank skips it alike: all know from the reduction).
    row.extra = step.finite ? sim.measure()
                            : std::vector<double>(sim.measurement_names().size(),
                                                  std::numeric_limits<double>::quiet_NaN());
    // The energy of a failed step is not a number anyone can use.
    if (!step.finite) row.energy = std::numeric_limits<double>::quiet_NaN();
    stats.write(row);
    // A failed step says more below; a warning would only repeat it. A
    // trial that inverted a tet of a model undefined there met the model's
    // barrier (infinite energy by design): counted in the stats, not warned.
    const bool warn_rollback = step.finite && step.rejected_at.found() &&
                               step.rejected_at.kind != NonFiniteSite::Kind::inverted_element;
    if (warn_rollback && ++nonfinite_warnings <= kStallWarnings)
      warn_rolled_back(frame, rank, step.rejected_at);
    nonfinite_steps += step.nonfinite_rollbacks > 0 ? 1 : 0;
    // A float step that ends at round-off above its target could reach it in
    // double: warned once. In double it is a body that barely moved this
    // step (the target is relative to the step's decrease): counted below.
    resolution_limited_steps += step.at_resolution ? 1 : 0;
    capped_steps += scene.solver.accuracy > 0 && step.finite && !step.stalled &&
                            step.iterations >= scene.solver.iterations &&
                            !(step.error_estimate <= scene.solver.accuracy)
                        ? 1
                        : 0;
    if (rank == 0 && sizeof(Real) == 4 && step.at_resolution && resolution_limited_steps == 1)
      warn(
          "frame %d: the step's energy changes fell within float's round-off with its error "
          "estimate at %.1e, short of solver.accuracy = %g (a step ends below half of it); "
          "--precision double resolves more (counted at the end)",
          frame, step.error_estimate, scene.solver.accuracy);
    if (rank == 0 && step.finite && step.retried_from_start && ++retried_steps <= kStallWarnings)
      warn(
          "frame %d: the predicted initial guess (solver.init = \"%s\") led to no finite "
          "state; the step was retaken from its start%s",
          frame, scene.solver.init.c_str(),
          retried_steps == kStallWarnings ? " (further such warnings suppressed)" : "");
    if (!step.finite) {
      // The body still holds the last good state (the step left it alone):
      // make sure it is on disk, then stop every rank with one message.
      if (last_written != frame - 1)
        frames.write_frame(frame - 1, (frame - 1) * h, sim.owned_positions(),
                           sim.owned_velocities());
      report_failed_step(comm, frame, step, frames.h5_path());
      return 3;  // the ranks that do not report; main's agree() ends them all
    }
    if (frame % scene.output.every == 0) {
      frames.write_frame(frame, frame * h, sim.owned_positions(), sim.owned_velocities());
      last_written = frame;
    }
    // After the frame's output, so a restart never lacks a frame it skips.
    if (checkpoint_every > 0 && (frame % checkpoint_every == 0 || frame == scene.time.frames)) {
      write_checkpoint(checkpoint_path(out_dir, rank, size), checkpoint_of(frame));
      last_checkpoint = frame;
    }
    stalled_steps += row.stalled;
    if (rank == 0 && step.stalled && stalled_steps <= kStallWarnings)
      warn(
          "frame %d: alpha fell below solver.alpha_min = %g after %d iterations; the step "
          "ended unconverged%s",
          frame, scene.solver.alpha_min, step.iterations,
          stalled_steps == kStallWarnings ? " (further such warnings suppressed)" : "");
    if (talk) {
      std::printf("frame %4d/%d  %8.1f ms  alpha %.3g  rollbacks %d%s\n", frame, scene.time.frames,
                  ms, step.alpha, step.rollbacks,
                  step.stalled ? "  (alpha at minimum: step ended early)" : "");
      std::fflush(stdout);
    }
  }
  // The counts are of the frames this process ran (after a restart, not
  // those before it).
  if (talk && resolution_limited_steps > 0)
    inform(
        "%d of %d steps ended with their energy changes within %s's round-off, their error "
        "estimates short of solver.accuracy = %g (a step whose body barely moves has little "
        "decrease to resolve its target against)",
        resolution_limited_steps, frames_run, precision, scene.solver.accuracy);
  // Pressed contact (a resting stack, an impact between large bodies)
  // spreads the spectrum Chebyshev's rate follows with Jacobi's D; lbfgs
  // took 3.6-16x less time there (bench/results/contact/README.md).
  if (talk && capped_steps > 0)
    inform(
        "%d of %d steps ran to solver.iterations = %d with their error estimates short of "
        "solver.accuracy = %g%s",
        capped_steps, frames_run, scene.solver.iterations, scene.solver.accuracy,
        has_contact_barrier(scene) && scene.solver.method == "chebyshev"
            ? "; where contact presses, solver.method = \"lbfgs\" often converges in far fewer "
              "iterations (docs/contact.md, Which to choose)"
            : "");
  if (rank == 0 && stalled_steps > 0)
    warn("%d of %d steps ended at alpha_min (column `stalled` in stats.csv)", stalled_steps,
         frames_run);
  // Mostly trials that inverted a tet of the neo-Hookean family (infinite
  // energy by design), so a note, not a warning; NaNs were warned above.
  if (talk && nonfinite_steps > 0)
    inform(
        "%d of %d steps rolled back trial states of non-finite energy (column "
        "`nonfinite_rollbacks` in stats.csv)",
        nonfinite_steps, frames_run);
  const std::string run_memory = peak_memory_report(comm);
  if (talk && frames_run == 0)
    inform("nothing to run: the run already has all %d frames (raise time.frames to go on)",
           scene.time.frames);
  if (talk && frames_run > 0) {
    const double ns_per_tet_iteration =
        total_iterations > 0
            ? 1e6 * total_ms / (static_cast<double>(local.num_global_tets) * total_iterations)
            : 0.0;
    inform("%d frames in %.1f s, %.1f ms/frame, %.1f ns per tet-iteration", frames_run,
           total_ms / 1e3, total_ms / frames_run, ns_per_tet_iteration);
    inform("%s", run_memory.c_str());
    const std::string timing = sim.stepper_timing_report();
    if (!timing.empty()) inform("%s", timing.c_str());
    const std::string preconditioning = sim.preconditioner_report(true);
    if (!preconditioning.empty()) inform("%s", preconditioning.c_str());
    const std::string contact = sim.body_contact_report(total_ms);
    if (!contact.empty()) inform("%s", contact.c_str());
    inform("wrote %s, %s and %s", frames.h5_path().c_str(), frames.xdmf_path().c_str(),
           stats.path().c_str());
  }
  return 0;
}

}  // namespace

}  // namespace descent
