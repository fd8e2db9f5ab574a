// bench/mesh_read.sh's driver: reading a mesh into every rank's MeshSlice,
// wall time (slowest rank) and peak resident memory per rank.
//
//   mesh_read_bench prepare RESOLUTION DIR   (one rank) writes the double helix
//       at RESOLUTION as DIR/helix.msh (Gmsh 2.2, write_mesh) and DIR/helix.h5
//       (write_mesh_h5, with DIR/helix.xdmf)
//   mpiexec -n P mesh_read_bench read FILE   read_mesh_slice(FILE): .h5 goes
//       to read_mesh_h5 (each rank reads its blocks), .msh is parsed and
//       validated on rank 0 and scattered
// Peak memory is getrusage's ru_maxrss of each rank's process, before the
// read (MPI and the program) and after it; one read per process, so the
// peak is this read's.
#include <mpi.h>
#include <sys/resource.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "common/mesh_slice.hpp"
#include "io/mesh_h5.hpp"
#include "io/mesh_io.hpp"
#include "meshes/generators.hpp"

namespace {

double peak_rss_mb() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss / 1024.0;  // Linux reports KiB
}

int prepare(double resolution, const std::filesystem::path& dir) {
  descent::DoubleHelixParams params;
  params.resolution = resolution;
  const descent::Mesh mesh = descent::make_double_helix(params);
  std::filesystem::create_directories(dir);
  descent::write_mesh(mesh, (dir / "helix.msh").string());
  descent::write_mesh_h5(MPI_COMM_SELF, descent::slice_of(mesh, 0, 1), (dir / "helix.h5").string());
  std::printf("helix resolution %g: %d vertices, %d tets -> %s/helix.{msh,h5}\n", resolution,
              mesh.num_vertices(), mesh.num_tets(), dir.c_str());
  return 0;
}

int read(const std::string& path) {
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  const double before_mb = peak_rss_mb();
  MPI_Barrier(MPI_COMM_WORLD);
  const double start = MPI_Wtime();
  const descent::MeshSlice slice = descent::read_mesh_slice(MPI_COMM_WORLD, path, nullptr);
  double seconds = MPI_Wtime() - start;
  MPI_Allreduce(MPI_IN_PLACE, &seconds, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
  // Per rank: peak before, peak after, tets and vertices read.
  const double mine[4] = {before_mb, peak_rss_mb(), static_cast<double>(slice.num_tets()),
                          static_cast<double>(slice.num_vertices())};
  std::vector<double> all(4 * static_cast<std::size_t>(size));
  MPI_Gather(mine, 4, MPI_DOUBLE, all.data(), 4, MPI_DOUBLE, 0, MPI_COMM_WORLD);
  if (rank == 0) {
    std::printf("file=%s ranks=%d tets=%lld read_s=%.3f\n", path.c_str(), size,
                static_cast<long long>(slice.num_global_tets), seconds);
    for (int r = 0; r < size; ++r)
      std::printf(
          "  rank %d: peak_rss_before_mb=%.1f peak_rss_after_mb=%.1f tets=%.0f "
          "vertices=%.0f\n",
          r, all[4 * r], all[4 * r + 1], all[4 * r + 2], all[4 * r + 3]);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  const std::string mode = argc > 1 ? argv[1] : "";
  int code = 2;
  if (mode == "prepare" && argc == 4)
    code = prepare(std::atof(argv[2]), argv[3]);
  else if (mode == "read" && argc == 3)
    code = read(argv[2]);
  else
    std::fprintf(stderr, "usage: mesh_read_bench prepare RESOLUTION DIR | read FILE\n");
  MPI_Finalize();
  return code;
}
