#include "app/partition_command.hpp"

#include <CLI/CLI.hpp>
#include <chrono>
#include <fstream>

#include "app/agree.hpp"
#include "app/console.hpp"
#include "app/count_option.hpp"
#include "app/memory_report.hpp"
#include "app/scene_mesh.hpp"
#include "comm/collective_error.hpp"
#include "comm/mpi_check.hpp"
#include "partition/face_matching.hpp"
#include "partition/geometric_partition.hpp"
#include "partition/partition_file.hpp"

namespace descent {
namespace {

void write_stats(const std::string& path, const PartitionQuality& q) {
  std::ofstream out(path);
  out << "part,tets,shared_vertices,neighbours,shared_pairs\n";
  for (std::size_t p = 0; p < q.tets_per_part.size(); ++p)
    out << p << ',' << q.tets_per_part[p] << ',' << q.shared_vertices_per_part[p] << ','
        << q.neighbours_per_part[p] << ',' << q.shared_pairs_per_part[p] << '\n';
  if (!out) throw InputError("cannot write " + path);
}

}  // namespace

CLI::App* add_partition_subcommand(CLI::App& app, PartitionOptions& options) {
  CLI::App* partition = app.add_subcommand(
      "partition", "Partition a scene's mesh once, for runs with --partition on as many ranks");
  partition->add_option("-n,--parts", options.parts, "Number of parts (the ranks of later runs)")
      ->required()
      ->check(at_least(1));
  partition->add_option("-o,--output", options.out_file,
                        "Partition file (.h5) for descent run --partition; none: report only");
  partition->add_option("--stats", options.stats_file,
                        "CSV of tets, shared vertices, neighbours and shared pairs per part");
  partition->add_flag("--quiet", options.quiet, "No progress output");
  return partition;
}

int run_partition(MPI_Comm comm, const Scene& scene, const PartitionOptions& options) {
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  const bool talk = rank == 0 && !options.quiet;
  const int parts = options.parts;
  const auto start = std::chrono::steady_clock::now();

  if (!scene.bodies.empty() && !options.out_file.empty())
    throw InputError(
        detail::concat(scene.source,
                       ": a scene of several bodies ([[body]]) is partitioned inside each run: a "
                       "partition file does not record its bodies (drop --output to see the "
                       "partition's quality)"));
  MeshReadReport report;
  MeshSlice slice = agree(comm, [&] { return build_scene_mesh_slice(comm, scene, &report); });
  if (rank == 0)
    for (const std::string& w : report.warnings) warn("%s", w.c_str());
  const PartitionMethod method = agree(
      comm, [&] { return choose_partition_method(scene.partition.method, slice.num_global_tets); });
  // RCB needs no dual graph: the surface faces and the cut are found from
  // the parts' tets once they have moved (partition/face_matching.hpp).
  const bool graph_free = method == PartitionMethod::rcb;
  GraphPartition partition;
  std::vector<std::uint8_t> surface_faces;
  if (graph_free) {
    partition.part = agree(comm, [&] { return partition_by_coordinates(comm, slice, parts); });
    surface_faces.assign(slice.num_tets(), 0);
  } else {
    DualGraph graph = agree(comm, [&] { return build_dual_graph(comm, slice); });
    partition = agree(comm, [&] {
      return partition_dual_graph(comm, graph, parts, method, scene.partition.tries);
    });
    surface_faces = std::move(graph.surface_faces);
  }
  std::vector<PartTets> held =
      agree(comm, [&] { return migrate_tets(comm, slice, surface_faces, partition.part, parts); });

  // Each part's local mesh, for its quality and to validate it (flat tets)
  // as a run would.
  PartitionQuality quality = agree(comm, [&] {
    const std::vector<PartVertices> vertices = gather_part_vertices(
        comm, held, slice.num_global_vertices, slice.first_vertex, slice.positions, nullptr);
    if (graph_free)
      partition.cut_faces =
          match_part_faces(comm, held, vertices, slice.num_global_vertices, parts, slice.source);
    std::vector<LocalMesh> locals;
    std::string error;
    try {
      for (std::size_t i = 0; i < held.size(); ++i)
        locals.push_back(build_local_mesh(held[i], vertices[i], parts, slice.num_global_vertices,
                                          slice.num_global_tets, slice.source, nullptr));
    } catch (const InputError& e) {
      error = e.what();
    }
    throw_if_any_failed(comm, error);
    return partition_quality(comm, locals, parts, partition.cut_faces);
  });
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (talk) {
    inform("%s: %lld vertices, %lld tets", slice.source.c_str(),
           static_cast<long long>(slice.num_global_vertices),
           static_cast<long long>(slice.num_global_tets));
    inform("partition (%s) on %d rank(s) in %.2f s: %s", to_string(method), size, seconds,
           describe(quality).c_str());
  }
  if (!options.out_file.empty()) {
    agree(comm, [&] {
      write_partition_file(comm, options.out_file, slice, held, parts, method, quality);
      return 0;
    });
    if (talk)
      inform("wrote %s: run it with mpirun -n %d descent run SCENE --partition %s",
             options.out_file.c_str(), parts, options.out_file.c_str());
  }
  const std::string memory = peak_memory_report(comm);
  if (talk) inform("%s", memory.c_str());
  if (!options.stats_file.empty())
    agree(comm, [&] {
      if (rank == 0) write_stats(options.stats_file, quality);
      return 0;
    });
  return 0;
}

}  // namespace descent
