// The partition file: written by every rank at once, each its parts' rows
// as one hyperslab per dataset; read back one part per rank.
#include "partition/partition_file.hpp"

#include <hdf5.h>

#include <array>
#include <cstdio>
#include <filesystem>

#include "comm/collective_error.hpp"
#include "comm/mpi_check.hpp"
#include "common/block_range.hpp"
#include "common/error.hpp"
#include "io/hdf5_blocks.hpp"
#include "io/mesh_h5.hpp"

namespace descent {
namespace {

using hdf5::check;
using hdf5::Hid;
using hdf5::owned;

const char* method_key(PartitionMethod method) {
  switch (method) {
    case PartitionMethod::metis:
      return "metis";
    case PartitionMethod::ptscotch:
      return "ptscotch";
    case PartitionMethod::rcb:
      return "rcb";
  }
  return "";
}

// Scalar attributes of /partition.
template <class T>
void write_attribute(hid_t group, const char* name, hid_t file_type, hid_t memory_type,
                     const T& value, const std::string& where) {
  Hid space = owned(H5Screate(H5S_SCALAR), H5Sclose, "H5Screate", where);
  Hid attribute = owned(H5Acreate2(group, name, file_type, space.get(), H5P_DEFAULT, H5P_DEFAULT),
                        H5Aclose, "H5Acreate2", where + " attribute " + name);
  check(H5Awrite(attribute.get(), memory_type, &value), "H5Awrite", where);
}

void write_text_attribute(hid_t group, const char* name, const std::string& text,
                          const std::string& where) {
  Hid type = owned(H5Tcopy(H5T_C_S1), H5Tclose, "H5Tcopy", where);
  check(H5Tset_size(type.get(), text.size()), "H5Tset_size", where);
  Hid space = owned(H5Screate(H5S_SCALAR), H5Sclose, "H5Screate", where);
  Hid attribute = owned(H5Acreate2(group, name, type.get(), space.get(), H5P_DEFAULT, H5P_DEFAULT),
                        H5Aclose, "H5Acreate2", where + " attribute " + name);
  check(H5Awrite(attribute.get(), type.get(), text.data()), "H5Awrite", where);
}

// Rows [first, first + count) of a [rows, cols] dataset of the partition group.
struct Rows {
  global_index_t first = 0, count = 0;
};

}  // namespace

void write_partition_file(MPI_Comm comm, const std::string& path, const MeshSlice& slice,
                          const std::vector<PartTets>& held, int num_parts, PartitionMethod method,
                          const PartitionQuality& quality) {
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  // Written in a directory of its own beside PATH, under PATH's own name, so
  // that the XDMF index written with it names the right file once both move.
  namespace fs = std::filesystem;
  const fs::path final_h5(path);
  const fs::path staging = fs::path(path + ".partial");
  const std::string temporary = (staging / final_h5.filename()).string();
  int made = 0;
  if (rank == 0) {
    std::error_code created;
    fs::create_directories(staging, created);
    made = created.value();
  }
  throw_if_rank0_failed(comm, made, "cannot make " + staging.string());
  write_mesh_h5(comm, slice, temporary);

  // Where this rank's parts go: the parts are blocks in rank order, so
  // the ranks' rows are too.
  std::vector<global_index_t> part_tets(num_parts, 0);
  for (const PartTets& p : held) part_tets[p.part] = p.num_tets();
  DESCENT_MPI_CHECK(
      MPI_Allreduce(MPI_IN_PLACE, part_tets.data(), num_parts, MPI_INT64_T, MPI_SUM, comm));
  std::vector<global_index_t> offsets(num_parts + 1, 0);
  for (int p = 0; p < num_parts; ++p) offsets[p + 1] = offsets[p] + part_tets[p];
  Rows mine;
  if (!held.empty()) {
    mine.first = offsets[held.front().part];
    mine.count = offsets[held.back().part + 1] - mine.first;
  }
  std::vector<global_index_t> ids, tets;
  std::vector<std::uint8_t> surface;
  for (const PartTets& p : held) {
    ids.insert(ids.end(), p.ids.begin(), p.ids.end());
    tets.insert(tets.end(), p.vertices.begin(), p.vertices.end());
    surface.insert(surface.end(), p.surface_faces.begin(), p.surface_faces.end());
  }
  std::vector<global_index_t> stats;
  for (int p = 0; p < num_parts; ++p)
    stats.insert(stats.end(), {quality.tets_per_part[p], quality.shared_vertices_per_part[p],
                               quality.neighbours_per_part[p], quality.shared_pairs_per_part[p]});

  {
    const std::string where = temporary + ":/partition";
    Hid access = hdf5::mpio_access(comm, temporary);
    Hid file = owned(H5Fopen(temporary.c_str(), H5F_ACC_RDWR, access.get()), H5Fclose, "H5Fopen",
                     temporary);
    Hid transfer = hdf5::collective_transfer(where);
    Hid group = owned(H5Gcreate2(file.get(), "/partition", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                      H5Gclose, "H5Gcreate2", where);
    const global_index_t parts = num_parts;
    write_attribute(group.get(), "num_parts", H5T_STD_I64LE, H5T_NATIVE_INT64, parts, where);
    write_attribute(group.get(), "cut_faces", H5T_STD_I64LE, H5T_NATIVE_INT64, quality.cut_faces,
                    where);
    write_attribute(group.get(), "imbalance", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, quality.imbalance,
                    where);
    write_text_attribute(group.get(), "method", method_key(method), where);

    // Small tables, written by rank 0 (the others select nothing).
    const bool root = rank == 0;
    Hid offsets_set = hdf5::create_rows_dataset(group.get(), "tet_offsets", H5T_STD_I64LE,
                                                num_parts + 1, 1, where + "/tet_offsets");
    hdf5::write_block(offsets_set.get(), transfer.get(), H5T_NATIVE_INT64, 0,
                      root ? num_parts + 1 : 0, 1, offsets.data(), where + "/tet_offsets");
    Hid stats_set = hdf5::create_rows_dataset(group.get(), "part_stats", H5T_STD_I64LE, num_parts,
                                              kPartStatsColumns, where + "/part_stats");
    hdf5::write_block(stats_set.get(), transfer.get(), H5T_NATIVE_INT64, 0, root ? num_parts : 0,
                      kPartStatsColumns, stats.data(), where + "/part_stats");

    const global_index_t total = offsets.back();
    Hid ids_set = hdf5::create_rows_dataset(group.get(), "tet_ids", H5T_STD_I64LE, total, 1,
                                            where + "/tet_ids");
    hdf5::write_block(ids_set.get(), transfer.get(), H5T_NATIVE_INT64, mine.first, mine.count, 1,
                      ids.data(), where + "/tet_ids");
    Hid tets_set =
        hdf5::create_rows_dataset(group.get(), "tets", H5T_STD_I64LE, total, 4, where + "/tets");
    hdf5::write_block(tets_set.get(), transfer.get(), H5T_NATIVE_INT64, mine.first, mine.count, 4,
                      tets.data(), where + "/tets");
    Hid surface_set = hdf5::create_rows_dataset(group.get(), "surface_faces", H5T_STD_U8LE, total,
                                                1, where + "/surface_faces");
    hdf5::write_block(surface_set.get(), transfer.get(), H5T_NATIVE_UINT8, mine.first, mine.count,
                      1, surface.data(), where + "/surface_faces");
  }
  DESCENT_MPI_CHECK(MPI_Barrier(comm));
  int error = 0;
  if (rank == 0) {
    std::error_code renamed, ignored;
    fs::rename(temporary, final_h5, renamed);
    if (!renamed) {
      fs::rename(fs::path(temporary).replace_extension(".xdmf"),
                 fs::path(final_h5).replace_extension(".xdmf"), renamed);
      fs::remove(staging, ignored);
    }
    error = renamed.value();
  }
  throw_if_rank0_failed(comm, error, detail::concat("cannot rename ", temporary, " to ", path));
}

DistributedMesh distribute_piece(MPI_Comm comm, PartitionPiece piece, const std::string& source,
                                 const std::string& reorder) {
  DistributedMesh mesh;
  mesh.source = source;
  // read_partition_piece has checked the name.
  mesh.method = piece.method == "metis"      ? PartitionMethod::metis
                : piece.method == "ptscotch" ? PartitionMethod::ptscotch
                                             : PartitionMethod::rcb;
  // read_partition_piece has checked every id.
  const global_index_t num_vertices = piece.num_global_vertices;
  assemble_local_mesh(comm, piece.tets, num_vertices, piece.num_global_tets, piece.first_vertex,
                      piece.block_positions, reorder, mesh);
  mesh.quality = std::move(piece.quality);
  return mesh;
}

}  // namespace descent
