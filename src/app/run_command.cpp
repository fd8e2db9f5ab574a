#include "app/run_command.hpp"

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <string>

#include "app/non_finite_stop.hpp"
#include "app/scene_mesh.hpp"
#include "app/simulation.hpp"
#include "common/error.hpp"
#include "io/checkpoint.hpp"
#include "io/frame_writer.hpp"

namespace descent {

namespace {

// Global ids of the tets this rank writes and their global vertex ids.
struct TetOutput {
  std::vector<index_t> ids, vertices;
};

TetOutput tet_output(const LocalMesh& local) {
  TetOutput out;
  out.ids = local.global_tet;
  out.vertices.resize(local.tets.size());
  for (std::size_t k = 0; k < local.tets.size(); ++k)
    out.vertices[k] = local.global_vertex[local.tets[k]];
  return out;
}

// One line per fixed region with the number of vertices it holds; a region
// that holds none is almost always a mistake in its box, so it is flagged.
void report_fixed_regions(const Scene& scene, const Mesh& mesh) {
  for (std::size_t r = 0; r < scene.fixed.size(); ++r) {
    const FixedRegion& region = scene.fixed[r];
    index_t count = 0;
    for (index_t v = 0; v < mesh.num_vertices(); ++v)
      count += region.contains(&mesh.positions[3 * static_cast<std::size_t>(v)]) ? 1 : 0;
    std::printf("%sfixed.%zu: %d vertices in [%g, %g, %g] - [%g, %g, %g], axes %s\n",
                count == 0 ? "warning: " : "", r, count, region.box_min[0], region.box_min[1],
                region.box_min[2], region.box_max[0], region.box_max[1], region.box_max[2],
                region.axes.c_str());
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
  int length = static_cast<int>(chosen.size());
  MPI_Bcast(&length, 1, MPI_INT, 0, comm);
  chosen.resize(length);
  MPI_Bcast(chosen.data(), length, MPI_CHAR, 0, comm);
  return chosen;
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
  // Why no GPU is used, or which one.
  if (rank == 0 && !note.empty() && !options.quiet) std::printf("descent: %s\n", note.c_str());
  const bool on_gpu = backend.kind == BackendKind::cuda;
  const bool use_float = options.precision == "float" || (options.precision == "auto" && on_gpu);
  return use_float ? run_scene_in<float>(comm, scene, options, backend)
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

  MeshReadReport report;
  const Mesh mesh = build_scene_mesh(scene.mesh, &report);
  if (talk) {
    for (const auto& w : report.warnings) std::printf("warning: %s\n", w.c_str());
    std::printf("descent: %s: %d vertices, %d tets on %d rank(s) x %d thread(s), %s\n",
                mesh.source.c_str(), mesh.num_vertices(), mesh.num_tets(), size,
                omp_get_max_threads(), sizeof(Real) == 4 ? "float" : "double");
  }

  if (talk) report_fixed_regions(scene, mesh);

  Simulation<Real> sim(comm, scene, mesh, backend);
  if (talk && backend.kind != BackendKind::cpu)
    std::printf("descent: backend %s: %s\n", to_string(backend.kind),
                sim.device_memory_report().c_str());
  if (talk && size > 1)
    std::printf("%s\n", describe(partition_quality(mesh, sim.tet_part(), size)).c_str());

  const LocalMesh& local = sim.local_mesh();
  const TetOutput tets = tet_output(local);
  const std::vector<double> rest(local.rest_positions.begin(),
                                 local.rest_positions.begin() + 3 * local.num_owned);
  FrameWriterLayout layout;
  layout.num_global_vertices = mesh.num_vertices();
  layout.num_global_tets = mesh.num_tets();
  layout.owned_vertex_ids = std::span(local.global_vertex.data(), local.num_owned);
  layout.tet_ids = tets.ids;
  layout.tet_vertices = tets.vertices;
  layout.owned_rest_positions = rest;
  // A restart continues in place from the newest frame every rank has a
  // checkpoint of (a kill between two ranks' writes leaves some one newer).
  int first_frame = 1;
  if (options.restart) {
    const std::vector<Checkpoint> generations =
        read_checkpoint_generations(checkpoint_path(scene.output.dir, rank, size));
    int frame = generations.front().frame;
    MPI_Allreduce(MPI_IN_PLACE, &frame, 1, MPI_INT, MPI_MIN, comm);
    const auto chosen = std::find_if(generations.begin(), generations.end(),
                                     [frame](const Checkpoint& c) { return c.frame == frame; });
    if (chosen == generations.end())
      throw InputError(detail::concat("rank ", rank, " has no checkpoint of frame ", frame, " in ",
                                      scene.output.dir, "/checkpoint"));
    sim.restore(*chosen);
    first_frame = frame + 1;
    if (talk) std::printf("descent: restarting after frame %d\n", frame);
  }
  const std::string out_dir = options.restart
                                  ? scene.output.dir
                                  : output_directory(comm, scene.output.dir, options.overwrite);
  if (talk && out_dir != scene.output.dir)
    std::printf("descent: %s holds an earlier run; writing to %s (--overwrite reuses it)\n",
                scene.output.dir.c_str(), out_dir.c_str());
  const int resume_after = options.restart ? first_frame - 1 : -1;
  FrameWriter frames(comm, out_dir, layout, resume_after);
  StatsWriter stats(comm, out_dir, sim.measurement_names(), resume_after);
  if (!options.restart) frames.write_frame(0, 0.0, sim.owned_positions(), sim.owned_velocities());
  // The newest frame in frames.h5 (-1: none known), so a stop can add the
  // last good one without writing a frame twice.
  int last_written =
      options.restart ? (resume_after % scene.output.every == 0 ? resume_after : -1) : 0;

  const double h = scene.time.dt;
  double total_ms = 0;
  long total_iterations = 0;
  int stalled_steps = 0, retried_steps = 0;
  constexpr int kStallWarnings = 5;
  int nonfinite_steps = 0, nonfinite_warnings = 0;  // the latter on this rank
  const int checkpoint_every = scene.output.checkpoint_every;
  for (int frame = first_frame; frame <= scene.time.frames; ++frame) {
    const double halo_before = sim.halo_counters().seconds;
    const double reduce_before = sim.reduction_counters().seconds;
    const auto start = std::chrono::steady_clock::now();
    const StepStats step = sim.step();
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
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
    const bool warn = step.finite && step.rejected_at.found() &&
                      step.rejected_at.kind != NonFiniteSite::Kind::inverted_element;
    if (warn && ++nonfinite_warnings <= kStallWarnings)
      warn_rolled_back(frame, rank, step.rejected_at);
    nonfinite_steps += step.nonfinite_rollbacks > 0 ? 1 : 0;
    if (rank == 0 && step.finite && step.retried_from_start && ++retried_steps <= kStallWarnings)
      std::fprintf(stderr,
                   "warning: frame %d: the predicted initial guess (solver.init = \"%s\") led to "
                   "no finite state; the step was retaken from its start%s\n",
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
    if (checkpoint_every > 0 && (frame % checkpoint_every == 0 || frame == scene.time.frames))
      write_checkpoint(checkpoint_path(out_dir, rank, size), sim.checkpoint(frame));
    stalled_steps += row.stalled;
    if (rank == 0 && step.stalled && stalled_steps <= kStallWarnings) {
      std::fprintf(stderr,
                   "warning: frame %d: alpha fell below solver.alpha_min = %g after %d "
                   "iterations; the step ended unconverged%s\n",
                   frame, scene.solver.alpha_min, step.iterations,
                   stalled_steps == kStallWarnings ? " (further such warnings suppressed)" : "");
    }
    if (talk) {
      std::printf("frame %4d/%d  %8.1f ms  alpha %.3g  rollbacks %d%s\n", frame, scene.time.frames,
                  ms, step.alpha, step.rollbacks,
                  step.stalled ? "  (alpha at minimum: step ended early)" : "");
      std::fflush(stdout);
    }
  }
  if (rank == 0 && stalled_steps > 0)
    std::fprintf(stderr,
                 "warning: %d of %d steps ended at alpha_min (column `stalled` in stats.csv)\n",
                 stalled_steps, scene.time.frames);
  // Mostly trials that inverted a tet of the neo-Hookean family (infinite
  // energy by design), so a note, not a warning; NaNs were warned above.
  if (talk && nonfinite_steps > 0)
    std::printf(
        "descent: %d of %d steps rolled back trial states of non-finite energy (column "
        "`nonfinite_rollbacks` in stats.csv)\n",
        nonfinite_steps, scene.time.frames);
  if (talk && scene.time.frames > 0) {
    const double ns_per_tet_iteration =
        total_iterations > 0
            ? 1e6 * total_ms / (static_cast<double>(mesh.num_tets()) * total_iterations)
            : 0.0;
    std::printf("descent: %d frames in %.1f s, %.1f ms/frame, %.1f ns per tet-iteration\n",
                scene.time.frames, total_ms / 1e3, total_ms / scene.time.frames,
                ns_per_tet_iteration);
    const std::string timing = sim.stepper_timing_report();
    if (!timing.empty()) std::printf("descent: %s\n", timing.c_str());
    std::printf("descent: wrote %s, %s and %s\n", frames.h5_path().c_str(),
                frames.xdmf_path().c_str(), stats.path().c_str());
  }
  return 0;
}

}  // namespace

}  // namespace descent
