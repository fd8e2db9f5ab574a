// bench/frame_write.sh's driver: the time FrameWriter::write_frame takes per
// frame, slowest rank, on a synthetic vertex set of about --vertices
// vertices: an n x n x n grid numbered in grid order (x fastest, z slowest).
//   --numbering helix: ranks own slabs across z cut by a tilted plane, as a
//     partitioner cuts the helix across its axis: each rank owns long runs of
//     ids, with interleaved runs near the cut.
//   --numbering shuffled: the same ownership with the ids randomly permuted,
//     as a mesh file with scattered numbering gives: each rank's ids spread
//     over the whole range.
// Frames need only the owned vertices; each rank gives a small block of
// --tets-per-rank made-up tets for the mesh written at open.
//
// Built twice by bench/frame_write.sh: against this tree's writer, and with
// DESCENT_BENCH_OLD_WRITER against the point-selection writer of commit
// 6865353 (32-bit id spans, no unused vertices).
//
//   mpiexec -n 2 frame_write_bench --vertices 1000000 --numbering shuffled
//       --frames 7 --out /tmp/frames
// Prints one line per frame and a summary line with the median.
#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numeric>
#include <random>
#include <string>
#include <vector>

#include "io/frame_writer.hpp"

namespace {

using descent::FrameWriter;
using descent::FrameWriterLayout;
using descent::global_index_t;
#ifdef DESCENT_BENCH_OLD_WRITER
using IdVector = std::vector<descent::index_t>;  // the old layout's 32-bit ids
constexpr const char* kWriter = "old";
#else
using IdVector = std::vector<global_index_t>;
constexpr const char* kWriter = "new";
#endif

struct Options {
  global_index_t vertices = 1000000;
  std::string numbering = "helix";
  int frames = 7;
  int tets_per_rank = 1000;
  std::string out = "frame_write_bench_out";
};

Options parse(int argc, char** argv) {
  Options options;
  for (int k = 1; k + 1 < argc; k += 2) {
    const std::string key = argv[k], value = argv[k + 1];
    if (key == "--vertices")
      options.vertices = std::atoll(value.c_str());
    else if (key == "--numbering")
      options.numbering = value;
    else if (key == "--frames")
      options.frames = std::atoi(value.c_str());
    else if (key == "--tets-per-rank")
      options.tets_per_rank = std::atoi(value.c_str());
    else if (key == "--out")
      options.out = value;
    else {
      std::fprintf(stderr, "unknown option %s\n", key.c_str());
      std::exit(2);
    }
  }
  if (options.numbering != "helix" && options.numbering != "shuffled") {
    std::fprintf(stderr, "--numbering is helix or shuffled\n");
    std::exit(2);
  }
  return options;
}

// This rank's vertices: ids and rest positions (grid spacing 1 mm).
struct Owned {
  IdVector ids;
  std::vector<double> rest;
};

Owned owned_vertices(int n, const std::string& numbering, int rank, int size) {
  const global_index_t total = global_index_t{n} * n * n;
  std::vector<global_index_t> id_of(0);
  if (numbering == "shuffled") {
    // The same permutation on every rank: same seed, same library.
    id_of.resize(total);
    std::iota(id_of.begin(), id_of.end(), global_index_t{0});
    std::shuffle(id_of.begin(), id_of.end(), std::mt19937_64(12345));
  }
  Owned owned;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        // Slabs across z, the cut tilted by a quarter of the height over x.
        const double across = k + 0.25 * (i - 0.5 * n);
        const int owner = std::clamp(static_cast<int>(std::floor(across * size / n)), 0, size - 1);
        if (owner != rank) continue;
        const global_index_t grid_id = (global_index_t{k} * n + j) * n + i;
        owned.ids.push_back(
            static_cast<IdVector::value_type>(id_of.empty() ? grid_id : id_of[grid_id]));
        owned.rest.insert(owned.rest.end(), {1e-3 * i, 1e-3 * j, 1e-3 * k});
      }
  return owned;
}

double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  const std::size_t m = values.size() / 2;
  return values.size() % 2 ? values[m] : 0.5 * (values[m - 1] + values[m]);
}

}  // namespace

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  const Options options = parse(argc, argv);
  const int n = static_cast<int>(std::lround(std::cbrt(static_cast<double>(options.vertices))));
  const global_index_t num_vertices = global_index_t{n} * n * n;
  const global_index_t num_tets = global_index_t{options.tets_per_rank} * size;
  {
    const Owned owned = owned_vertices(n, options.numbering, rank, size);
    IdVector tet_ids, tet_vertices;
    for (global_index_t t = global_index_t{options.tets_per_rank} * rank;
         t < global_index_t{options.tets_per_rank} * (rank + 1); ++t) {
      tet_ids.push_back(static_cast<IdVector::value_type>(t));
      for (int corner = 0; corner < 4; ++corner)
        tet_vertices.push_back(static_cast<IdVector::value_type>((t * 4 + corner) % num_vertices));
    }

    FrameWriterLayout layout;
    layout.num_global_vertices = static_cast<decltype(layout.num_global_vertices)>(num_vertices);
    layout.num_global_tets = static_cast<decltype(layout.num_global_tets)>(num_tets);
    layout.owned_vertex_ids = owned.ids;
    layout.tet_ids = tet_ids;
    layout.tet_vertices = tet_vertices;
    layout.owned_rest_positions = owned.rest;

    MPI_Barrier(MPI_COMM_WORLD);
    double start = MPI_Wtime();
    FrameWriter writer(MPI_COMM_WORLD, options.out, layout);
    double open_s = MPI_Wtime() - start;
    MPI_Allreduce(MPI_IN_PLACE, &open_s, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);

    std::vector<double> positions(owned.rest.size()), velocities(owned.rest.size());
    std::vector<double> frame_s;
    for (int frame = 0; frame < options.frames; ++frame) {
      for (std::size_t k = 0; k < positions.size(); ++k) {
        velocities[k] = 1e-3 * std::sin(0.001 * static_cast<double>(k) + frame);
        positions[k] = owned.rest[k] + 0.01 * frame * velocities[k];
      }
      MPI_Barrier(MPI_COMM_WORLD);
      start = MPI_Wtime();
      writer.write_frame(frame, 0.01 * frame, positions, velocities);
      double seconds = MPI_Wtime() - start;
      MPI_Allreduce(MPI_IN_PLACE, &seconds, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
      frame_s.push_back(seconds);
      if (rank == 0) std::printf("frame %d: %.4f s\n", frame, seconds);
    }
    if (rank == 0)
      std::printf(
          "writer=%s numbering=%s vertices=%lld ranks=%d frames=%d open_s=%.4f "
          "median_frame_s=%.4f\n",
          kWriter, options.numbering.c_str(), static_cast<long long>(num_vertices), size,
          options.frames, open_s, median(frame_s));
  }
  MPI_Finalize();
  return 0;
}
