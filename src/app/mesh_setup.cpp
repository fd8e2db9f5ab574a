#include "app/mesh_setup.hpp"

#include <chrono>

#include "app/agree.hpp"
#include "app/console.hpp"
#include "app/scene_mesh.hpp"
#include "common/error.hpp"
#include "partition/partition_file.hpp"

namespace descent {
namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

DistributedMesh set_up_mesh(MPI_Comm comm, const Scene& scene, const MeshSetupOptions& options) {
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  const auto start = std::chrono::steady_clock::now();
  DistributedMesh mesh;
  double read_seconds = 0;
  if (!options.partition_file.empty() && !scene.bodies.empty())
    throw InputError(detail::concat(options.partition_file, ": ", scene.source,
                                    " has several bodies ([[body]]), which a partition file does "
                                    "not record: run it without --partition"));
  if (!options.partition_file.empty()) {
    PartitionPiece piece =
        agree(comm, [&] { return read_partition_piece(comm, options.partition_file); });
    read_seconds = seconds_since(start);
    mesh = agree(comm, [&] {
      return distribute_piece(comm, std::move(piece), options.partition_file,
                              scene.partition.reorder);
    });
  } else {
    MeshReadReport report;
    MeshSlice slice = agree(comm, [&] { return build_scene_mesh_slice(comm, scene, &report); });
    if (rank == 0)
      for (const std::string& w : report.warnings) warn("%s", w.c_str());
    read_seconds = seconds_since(start);
    mesh = agree(comm, [&] { return distribute_mesh(comm, std::move(slice), scene.partition); });
  }
  const double partition_seconds = seconds_since(start) - read_seconds;
  const LocalMesh& local = mesh.local;
  if (rank == 0 && mesh.reoriented_tets > 0)
    warn("%s: re-oriented %lld of %lld tets that were negatively oriented", mesh.source.c_str(),
         static_cast<long long>(mesh.reoriented_tets),
         static_cast<long long>(local.num_global_tets));
  if (rank == 0 && mesh.unused_vertices > 0)
    warn("%s: %lld of %lld vertices belong to no tet (kept, written at rest)", mesh.source.c_str(),
         static_cast<long long>(mesh.unused_vertices),
         static_cast<long long>(local.num_global_vertices));
  if (options.talk) {
    inform("%s: %lld vertices, %lld tets", mesh.source.c_str(),
           static_cast<long long>(local.num_global_vertices),
           static_cast<long long>(local.num_global_tets));
    if (size > 1)
      inform("partition (%s): %s", to_string(mesh.method), describe(mesh.quality).c_str());
    const SetupSeconds& s = mesh.seconds;
    if (options.partition_file.empty())
      inform(
          "mesh set-up %.2f s on rank 0: slices %.2f s, dual graph %.2f s, partition %.2f s, "
          "tets moved %.2f s, vertices %.2f s, faces matched %.2f s, local mesh %.2f s, local "
          "order (%s) %.2f s",
          read_seconds + partition_seconds, read_seconds, s.dual_graph, s.partition, s.migration,
          s.vertices, s.face_matching, s.local_mesh, scene.partition.reorder.c_str(),
          s.local_order);
    else
      inform(
          "mesh set-up %.2f s on rank 0, partitioned beforehand: piece read %.2f s, vertices "
          "%.2f s, local mesh %.2f s, local order (%s) %.2f s",
          read_seconds + partition_seconds, read_seconds, s.vertices, s.local_mesh,
          scene.partition.reorder.c_str(), s.local_order);
  }
  return mesh;
}

}  // namespace descent
