// The `descent` command line: run a scene, write a generated mesh, report the
// build. Every subcommand has --help.
//
// Exit status: 0 success, 1 a runtime or input error, 2 a usage error (an
// unknown command, option or value), kStoppedExitCode (75) a run stopped by
// a signal that --restart continues.
#include <mpi.h>
#include <omp.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdlib>
#include <optional>
#include <string>

#include "app/agree.hpp"
#include "app/console.hpp"
#include "app/count_option.hpp"
#include "app/default_scene.hpp"
#include "app/partition_command.hpp"
#include "app/run_command.hpp"
#include "app/scene_mesh.hpp"
#include "app/study_command.hpp"
#include "app/tune_command.hpp"
#include "common/closest_name.hpp"
#include "io/mesh_h5.hpp"
#include "io/mesh_io.hpp"
#include "io/scene.hpp"
#include "solver/petsc/petsc_session.hpp"

namespace {

using namespace descent;

Scene read_scene(const std::string& path, const std::vector<std::string>& overrides) {
  if (path.empty()) return parse_scene(kDefaultScene, "<built-in double helix scene>", overrides);
  return load_scene(path, overrides);
}

constexpr int kUsageExitCode = 2;

// `descent mesh`: .h5 files are written by every rank, each its slice (so a
// mesh too large for one rank is generated and written in parallel); the
// ASCII formats by rank 0 from the whole mesh.
int write_scene_mesh(MPI_Comm comm, const Scene& scene, const std::string& path) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  global_index_t counts[2] = {0, 0};
  if (is_hdf5_mesh_path(path)) {
    const MeshSlice slice = build_scene_mesh_slice(comm, scene);
    write_mesh_h5(comm, slice, path);
    counts[0] = slice.num_global_vertices;
    counts[1] = slice.num_global_tets;
  } else if (rank == 0) {
    const Mesh m = build_scene_mesh(scene);
    write_mesh(m, path);
    counts[0] = m.num_vertices();
    counts[1] = m.num_tets();
  }
  if (rank == 0)
    inform("wrote %s (%lld vertices, %lld tets)", path.c_str(), static_cast<long long>(counts[0]),
           static_cast<long long>(counts[1]));
  return 0;
}

// The subcommand named by the first argument that is not an option, when it
// names none: CLI11 would only say that a subcommand is required.
std::string unknown_subcommand(const CLI::App& app, int argc, char** argv) {
  if (argc < 2 || argv[1][0] == '-') return "";
  std::vector<std::string> names;
  for (const CLI::App* sub : app.get_subcommands({})) names.push_back(sub->get_name());
  const std::string given = argv[1];
  if (std::find(names.begin(), names.end(), given) != names.end()) return "";
  std::string list;
  for (const std::string& n : names) list += (list.empty() ? "" : ", ") + n;
  const std::optional<std::string> close = closest_name(given, names);
  return "unknown command '" + given + "'" + (close ? "; did you mean '" + *close + "'?" : "") +
         " (commands: " + list + "; descent --help)";
}

int main_with_mpi(int argc, char** argv) {
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);

  CLI::App app{"descent: distributed Jacobi-Chebyshev descent for elastic bodies"};
  // Asked at run time: the devices visible now, not at build time.
  app.set_version_flag("--version", [] {
    return std::string("descent ") + DESCENT_VERSION + " (OpenMP " + std::to_string(_OPENMP) +
           ")\n" + backend_report();
  });
  app.require_subcommand(1);

  std::string scene_path, out_dir, mesh_out;
  std::vector<std::string> overrides;
  bool quiet = false;
  bool verbose = false;
  bool overwrite = false;
  bool restart = false;
  int threads = 0;
  std::string petsc_options;
  std::string precision = "auto";
  BackendRequest backend;
  bool no_graphs = false;

  CLI::App* run =
      app.add_subcommand("run", "Simulate a scene (default: the built-in double helix)");
  run->add_option("scene", scene_path, "Scene file (TOML); none: the built-in double helix");
  run->add_option("--set", overrides, "Override a scene key, e.g. --set solver.iterations=64")
      ->type_name("KEY=VALUE");
  run->add_option("--out", out_dir, "Output directory (overrides output.dir)");
  run->add_flag("--quiet", quiet, "No progress output (warnings and errors still go to stderr)");
  run->add_flag("--verbose", verbose, "Also report details, e.g. why no GPU is used");
  run->add_flag("--overwrite", overwrite,
                "Reuse an output directory holding an earlier run (default: write to DIR.1, ...)");
  run->add_flag("--restart", restart,
                "Continue the run in the output directory from its last checkpoint");
  run->add_option("--precision", precision,
                  "Real type of the solver (default auto: double on the CPU; on a GPU float where "
                  "solver.accuracy is 1e-3 or looser or 0, else double)")
      ->check(CLI::IsMember({"auto", "float", "double"}));
  run->add_option("--backend", backend.backend, "auto (cuda when a device is visible), cpu or cuda")
      ->check(CLI::IsMember({"auto", "cpu", "cuda"}));
  run->add_option("--assembly", backend.assembly,
                  "Chebyshev engine: element results to vertices by gather (deterministic, "
                  "default; one thread per rank adds them in tet order, the same sums) or "
                  "scatter (atomics)")
      ->check(CLI::IsMember({"gather", "scatter"}));
  run->add_flag("--share-device", backend.share_device,
                "Let more ranks per node than visible GPUs share them");
  run->add_flag("--no-graphs", no_graphs,
                "CUDA engine: launch every kernel instead of replaying captured graphs");
  run->add_option("--threads", threads, "OpenMP threads per rank (default: OMP_NUM_THREADS)")
      ->check(at_least(1));
  run->add_option("--petsc-options", petsc_options,
                  "Options for the PETSc solvers, e.g. \"-ksp_monitor -pc_type hypre\"");
  std::string partition_file;
  run->add_option("--partition", partition_file,
                  "This rank's piece of a partition file made by descent partition (as many "
                  "parts as ranks); the file's mesh replaces the scene's");

  TuneOptions tune_options;
  CLI::App* tune = add_tune_subcommand(app, tune_options);
  tune->add_option("scene", scene_path, "Scene file (TOML); none: the built-in double helix");
  tune->add_option("--set", overrides, "Override a scene key")->type_name("KEY=VALUE");

  StudyOptions study_options;
  CLI::App* study = add_study_subcommand(app, study_options);
  study->add_option("scene", scene_path, "Scene file (TOML); none: the built-in double helix");
  study->add_option("--set", overrides, "Override a scene key for every case")
      ->type_name("KEY=VALUE");
  study->add_option("--threads", threads, "OpenMP threads per rank (default: OMP_NUM_THREADS)")
      ->check(at_least(1));
  study->add_option("--petsc-options", petsc_options,
                    "Options for the PETSc solvers, e.g. \"-ksp_monitor -log_view\"");

  PartitionOptions partition_options;
  CLI::App* partition = add_partition_subcommand(app, partition_options);
  partition->add_option("scene", scene_path, "Scene file (TOML); none: the built-in double helix");
  partition->add_option("--set", overrides, "Override a scene key")->type_name("KEY=VALUE");

  CLI::App* mesh = app.add_subcommand("mesh", "Write the mesh of a scene to a file");
  mesh->add_option("scene", scene_path, "Scene file (TOML); none: the built-in double helix");
  mesh->add_option("--set", overrides,
                   "Override a scene key, e.g. --set mesh.helix.preset=\"316k\"")
      ->type_name("KEY=VALUE");
  mesh->add_option("-o,--output", mesh_out,
                   "Output file: .h5 (written by all ranks), .mesh (MEDIT), .msh (Gmsh 2.2), "
                   ".node (TetGen)")
      ->required();

  if (const std::string unknown = unknown_subcommand(app, argc, argv); !unknown.empty()) {
    if (rank == 0) report_error("%s", unknown.c_str());
    return kUsageExitCode;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version end here too, with exit 0 and their text.
    if (e.get_exit_code() == 0) return rank == 0 ? app.exit(e) : 0;
    if (rank == 0) report_error("%s (descent --help lists the commands and options)", e.what());
    return kUsageExitCode;
  }
  if (threads > 0) omp_set_num_threads(threads);
  // Read when PETSc starts (solver/petsc/petsc_session.hpp), after PETSc's
  // own environment variable.
  if (!petsc_options.empty()) {
    const char* earlier = std::getenv("PETSC_OPTIONS");
    const std::string all = (earlier ? std::string(earlier) + " " : std::string()) + petsc_options;
    setenv("PETSC_OPTIONS", all.c_str(), 1);
  }

  try {
    Scene scene = agree(MPI_COMM_WORLD, [&] { return read_scene(scene_path, overrides); });
    if (!out_dir.empty()) scene.output.dir = out_dir;
    if (*partition)
      return agree(MPI_COMM_WORLD,
                   [&] { return run_partition(MPI_COMM_WORLD, scene, partition_options); });
    if (*tune)
      return agree(MPI_COMM_WORLD, [&] { return run_tune(MPI_COMM_WORLD, scene, tune_options); });
    if (*study) {
      auto read = [&](const std::vector<std::string>& extra) {
        std::vector<std::string> all = overrides;
        all.insert(all.end(), extra.begin(), extra.end());
        return read_scene(scene_path, all);
      };
      return agree(MPI_COMM_WORLD, [&] { return run_study(MPI_COMM_WORLD, read, study_options); });
    }
    if (*run) {
      RunOptions options;
      options.quiet = quiet;
      options.verbose = verbose;
      options.overwrite = overwrite;
      options.restart = restart;
      options.precision = precision;
      options.backend = backend;
      options.backend.graphs = !no_graphs;
      options.partition_file = partition_file;
      return agree(MPI_COMM_WORLD, [&] { return run_scene(MPI_COMM_WORLD, scene, options); });
    }
    return agree(MPI_COMM_WORLD, [&] { return write_scene_mesh(MPI_COMM_WORLD, scene, mesh_out); });
  } catch (const ReportedFailure&) {
    return 1;
  }
}

}  // namespace

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  const int code = main_with_mpi(argc, argv);
  descent::finish_petsc();  // prints -log_view, when PETSc ran
  MPI_Finalize();
  return code;
}
