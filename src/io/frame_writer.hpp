#pragma once
// Frames of one run, written by all ranks into one HDF5 file with parallel
// HDF5 (no gather to rank 0), plus an XDMF index that ParaView and meshio open
// as a time series. Vertices and tets are stored in the input mesh's order,
// whatever the rank count.
//
// How: rank r of P writes its block of rows, [begin(r), end(r)) of
// BlockRange(num_vertices, P), of every vertex array, and its block of
// BlockRange(num_tets, P) of /mesh/tets, each as one contiguous hyperslab.
// The rows a rank owns, in any numbering, travel to the rank whose block
// holds them: the plan is made at construction, and each frame moves
// positions and velocities together in one MPI_Alltoallv.
//
// File layout (DIR/frames.h5), every vertex array float64 [num_vertices, 3]
// in input vertex order:
//   /mesh/tets                  int32 [num_tets, 4]  global vertex ids, input order
//                               (int64 where an id passes 2^31 - 1)
//   /mesh/rest_positions
//   /frames/NNNNNN/positions    one group per written frame, NNNNNN its number
//   /frames/NNNNNN/displacement positions - rest_positions
//   /frames/NNNNNN/velocity
//   attribute "time" (float64) on each frame group
// Vertices no tet uses stay at rest: zero displacement and velocity.
// DIR/frames.xdmf: one temporal collection with one Uniform grid per frame,
// all data by reference into frames.h5 (relative paths, so DIR can move).
// Each grid has its Time, the frame's positions as Geometry (ParaView shows
// the deformed body) and node Attributes "displacement" and "velocity"
// (vectors). The first grid holds the Topology (NumberType Int, Precision 4
// or 8 as /mesh/tets);
// the others include it by xpointer. meshio's TimeSeriesReader takes its
// points and cells from that first grid: for a run, frame 0, written before
// the first step, at rest. So read_points_cells() is the rest mesh, and
// read_data(k) gives frame k's time and point data "displacement" and
// "velocity" (it skips the Geometry).
// frames.xdmf is rewritten after every frame and the HDF5 file flushed, so a
// run killed mid-way leaves a readable series of every completed frame.
#include <mpi.h>

#include <memory>
#include <span>
#include <string>
#include <vector>

#include "common/mesh.hpp"

namespace descent {

// Bytes per vertex id in /mesh/tets for a mesh of num_vertices: 4 where
// every id fits in int32, else 8.
int frame_tet_id_bytes(global_index_t num_vertices);

struct FrameWriterLayout {
  global_index_t num_global_vertices = 0;
  global_index_t num_global_tets = 0;
  // Vertices this rank writes each frame: their global ids, in any order.
  // Each vertex a tet uses is owned by exactly one rank.
  std::span<const global_index_t> owned_vertex_ids;
  // Tets this rank writes at open (each global tet by exactly one rank): their
  // global tet ids and their 4 global vertex ids each (4 * size entries).
  std::span<const global_index_t> tet_ids;
  std::span<const global_index_t> tet_vertices;
  // Rest positions of the owned vertices, 3 per vertex in owned_vertex_ids order.
  std::span<const double> owned_rest_positions;
  // Vertices no tet uses (a mesh file may have them): kept, and written at
  // rest in every frame. Each is listed by exactly one rank, with 3 rest
  // positions per vertex in unused_vertex_ids order.
  std::span<const global_index_t> unused_vertex_ids;
  std::span<const double> unused_rest_positions;
};

class FrameWriter {
 public:
  // Collective over `comm`, which must outlive the writer; destroy the writer
  // before MPI_Finalize, which shuts HDF5 down. Creates DIR (and parents) if
  // needed; the caller decides beforehand whether an existing DIR may be reused
  // (its frames.h5 is truncated, its frames.xdmf removed).
  // With resume_after >= 0 the existing DIR/frames.h5 is reopened instead:
  // frames after resume_after are dropped (a killed run may have written past
  // its checkpoint) and the XDMF index is rebuilt; the mesh must be the same.
  FrameWriter(MPI_Comm comm, const std::string& dir, const FrameWriterLayout& layout,
              int resume_after = -1);
  ~FrameWriter();
  FrameWriter(const FrameWriter&) = delete;
  FrameWriter& operator=(const FrameWriter&) = delete;

  // Collective. `owned_positions` and `owned_velocities` hold 3 doubles per
  // owned vertex, in the order of layout.owned_vertex_ids; `frame` in
  // [0, 999999], each written once, and `time` the same on every rank. Returns
  // once the frame is flushed to frames.h5 and listed in frames.xdmf.
  void write_frame(int frame, double time, std::span<const double> owned_positions,
                   std::span<const double> owned_velocities);

  std::string h5_path() const;
  std::string xdmf_path() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// One row per simulated frame, written by rank 0 to DIR/stats.csv and flushed
// per row.
struct FrameStats {
  int frame = 0;
  double sim_time = 0;
  int iterations = 0;
  int rollbacks = 0;
  double alpha = 0;
  double energy = 0;  // at the last accepted energy check
  double wall_ms = 0;
  double halo_ms = 0;
  double allreduce_ms = 0;
  int stalled = 0;            // 1: alpha fell below alpha_min and the step ended early
  std::vector<double> extra;  // values of the writer's extra columns, in order
  // Written after `stalled`, before the extra columns (declared last so
  // positional initialisers written before they existed still compile).
  // Checks rolled back because the trial state's energy was not finite:
  int nonfinite_rollbacks = 0;
  // How the step ended, worst first: "failed_non_finite" (no finite state
  // reached: the run stops after this row), "retried_from_start" (the
  // predicted guess reached no finite state; the step was retaken from q_t),
  // "stalled", "rolled_back_non_finite" (a non-finite trial was rejected, the
  // step went on), "ok".
  std::string status = "ok";
  // Chebyshev (0 for other methods): the spectrum bounds [lambda_min,
  // lambda_max] of D^-1 H the step used, its rho, the Lanczos steps it spent
  // estimating them (0: reused), and the relative error its last check
  // estimates (NaN: none).
  double lambda_min = 0, lambda_max = 0, rho = 0;
  int spectrum_steps = 0;
  double error_estimate = 0;
};

class StatsWriter {
 public:
  // Collective over `comm`. Creates DIR if needed and opens DIR/stats.csv on
  // rank 0 of comm (other ranks hold nothing); throws on every rank if rank 0 cannot.
  // `extra_columns` follow the fixed ones (per-region measurements); each row
  // then carries one value per extra column in FrameStats::extra.
  // With resume_after >= 0 the existing DIR/stats.csv is kept up to that
  // frame and appended to (its columns must be the same).
  StatsWriter(MPI_Comm comm, const std::string& dir,
              const std::vector<std::string>& extra_columns = {}, int resume_after = -1);
  ~StatsWriter();
  StatsWriter(const StatsWriter&) = delete;
  StatsWriter& operator=(const StatsWriter&) = delete;
  void write(const FrameStats& row);  // rank 0 writes; others ignore (not collective)
  std::string path() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace descent
