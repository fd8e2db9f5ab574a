// HDF5 meshes moved block by block: every rank writes or reads its slice as
// one hyperslab per dataset, then checks the rows it read on its own.
#include "io/mesh_h5.hpp"

#include <hdf5.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <vector>

#include "comm/collective_error.hpp"
#include "common/block_range.hpp"
#include "common/error.hpp"
#include "io/hdf5_blocks.hpp"
#include "io/hdf5_handle.hpp"
#include "io/hdf5_rows.hpp"

namespace descent {
namespace {

namespace fs = std::filesystem;
using hdf5::check;
using hdf5::Hid;
using hdf5::owned;

constexpr const char* kTets = "/mesh/tets";
constexpr const char* kPositions = "/mesh/positions";

// The slices tile [0, T) and [0, V) in blocks of whole rows, with the same
// totals on every rank; LogicError on every rank otherwise.
void verify_slices_tile(MPI_Comm comm, const MeshSlice& slice, const std::string& path) {
  int size = 0;
  MPI_Comm_size(comm, &size);
  // Per rank: T, first tet, tet count, V, first vertex, vertex count (-1: not whole rows).
  const std::array<global_index_t, 6> mine = {
      slice.num_global_tets,
      slice.first_tet,
      slice.tets.size() % 4 == 0 ? static_cast<global_index_t>(slice.tets.size() / 4) : -1,
      slice.num_global_vertices,
      slice.first_vertex,
      slice.positions.size() % 3 == 0 ? static_cast<global_index_t>(slice.positions.size() / 3)
                                      : -1};
  std::vector<global_index_t> all(6 * static_cast<std::size_t>(size));
  MPI_Allgather(mine.data(), 6, MPI_INT64_T, all.data(), 6, MPI_INT64_T, comm);
  // Blocks of one kind, at `column` of each rank's six, tile [0, total).
  auto tiles = [&](int column) {
    std::vector<std::array<global_index_t, 2>> blocks;  // first, count
    for (int r = 0; r < size; ++r) {
      const global_index_t* row = &all[6 * static_cast<std::size_t>(r) + column];
      if (row[0] != all[column] || row[2] < 0) return false;
      if (row[2] > 0) blocks.push_back({row[1], row[2]});
    }
    std::sort(blocks.begin(), blocks.end());
    global_index_t next = 0;
    for (const auto& [first, count] : blocks) {
      if (first != next) return false;
      next += count;
    }
    return next == all[column];
  };
  if (!tiles(0) || !tiles(3))
    throw LogicError(detail::concat("write_mesh_h5(", path,
                                    "): the ranks' slices must hold whole rows and cover the tets "
                                    "and the vertices once each, with the same totals"));
}

std::string xdmf_text(const std::string& h5_name, global_index_t num_vertices,
                      global_index_t num_tets) {
  std::ostringstream xdmf;
  xdmf << "<?xml version=\"1.0\" ?>\n"
       << "<Xdmf Version=\"3.0\">\n"
       << "  <Domain>\n"
       << "    <Grid Name=\"mesh\" GridType=\"Uniform\">\n"
       << "      <Topology TopologyType=\"Tetrahedron\" NumberOfElements=\"" << num_tets << "\">\n"
       << "        <DataItem Dimensions=\"" << num_tets
       << " 4\" NumberType=\"Int\" Precision=\"8\" Format=\"HDF\">" << h5_name << ":" << kTets
       << "</DataItem>\n"
       << "      </Topology>\n"
       << "      <Geometry GeometryType=\"XYZ\">\n"
       << "        <DataItem Dimensions=\"" << num_vertices
       << " 3\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">" << h5_name << ":"
       << kPositions << "</DataItem>\n"
       << "      </Geometry>\n"
       << "    </Grid>\n"
       << "  </Domain>\n"
       << "</Xdmf>\n";
  return xdmf.str();
}

// Rank 0 writes FILE.xdmf beside FILE.h5; an error there throws on every rank.
void write_xdmf(MPI_Comm comm, const MeshSlice& slice, const std::string& path) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  std::string error;
  if (rank == 0) {
    const fs::path xdmf = fs::path(path).replace_extension(".xdmf");
    const std::string text = xdmf_text(fs::path(path).filename().string(),
                                       slice.num_global_vertices, slice.num_global_tets);
    std::FILE* file = std::fopen(xdmf.c_str(), "w");
    const bool written =
        file != nullptr && std::fwrite(text.data(), 1, text.size(), file) == text.size();
    const bool closed = file != nullptr && std::fclose(file) == 0;
    if (!written || !closed) error = detail::concat("cannot write ", xdmf.string());
  }
  throw_if_rank0_failed(comm, error);
}

// Rank 0 checks that `path` is an HDF5 file with both datasets; each problem
// is thrown on every rank. (Ranks share the file system, so they would all
// find the same; asking once keeps the message single and the ranks in step.)
void verify_file_on_rank0(MPI_Comm comm, const std::string& path) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  std::string error;
  if (rank == 0) {
    hdf5::quiet_errors();
    std::error_code ignored;
    if (!fs::is_regular_file(path, ignored)) {
      error = detail::concat(path, ": no such file");
    } else if (H5Fis_hdf5(path.c_str()) <= 0) {
      error = detail::concat(path, ": not an HDF5 file");
    } else {
      const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
      if (file < 0) {
        error = detail::concat(path, ": HDF5 cannot open it: ", hdf5::innermost_error());
      } else {
        for (const char* dataset : {kTets, kPositions}) {
          if (H5Lexists(file, "/mesh", H5P_DEFAULT) <= 0 ||
              H5Lexists(file, dataset, H5P_DEFAULT) <= 0) {
            error = detail::concat(path, ": no dataset ", dataset,
                                   " (a mesh file holds /mesh/positions float64 [V, 3] and "
                                   "/mesh/tets int64 [T, 4])");
            break;
          }
        }
        H5Fclose(file);
      }
    }
  }
  throw_if_rank0_failed(comm, error);
}

// The two datasets of a mesh file.
const hdf5::RowsShape kTetsShape{4, H5T_INTEGER, "T", "4 vertex ids per tet",
                                 "vertex ids must be integers"};
const hdf5::RowsShape kPositionsShape{3, H5T_FLOAT, "V", "3 coordinates per vertex",
                                      "coordinates must be one of these"};

// The checks of the rows a rank read; a failure throws on this rank alone.
void verify_rows(const MeshSlice& slice, const std::string& path) {
  for (index_t t = 0; t < slice.num_tets(); ++t) {
    const global_index_t row = slice.first_tet + t;
    const global_index_t* v = &slice.tets[4 * static_cast<std::size_t>(t)];
    for (int k = 0; k < 4; ++k)
      if (v[k] < 0 || v[k] >= slice.num_global_vertices)
        throw InputError(detail::concat(path, ": ", kTets, " row ", row, " (tet ", row,
                                        ") refers to vertex ", v[k], ", but the mesh has ",
                                        slice.num_global_vertices, " vertices"));
    for (int a = 0; a < 4; ++a)
      for (int b = a + 1; b < 4; ++b)
        if (v[a] == v[b])
          throw InputError(detail::concat(path, ": ", kTets, " row ", row, " (tet ", row,
                                          ") uses vertex ", v[a], " twice (vertices ", v[0], " ",
                                          v[1], " ", v[2], " ", v[3], ")"));
  }
  for (index_t k = 0; k < slice.num_vertices(); ++k) {
    const global_index_t row = slice.first_vertex + k;
    const double* x = &slice.positions[3 * static_cast<std::size_t>(k)];
    if (!std::isfinite(x[0]) || !std::isfinite(x[1]) || !std::isfinite(x[2]))
      throw InputError(detail::concat(path, ": ", kPositions, " row ", row, " (vertex ", row,
                                      ") has a non-finite coordinate (", x[0], " ", x[1], " ", x[2],
                                      ")"));
  }
}

}  // namespace

void write_mesh_h5(MPI_Comm comm, const MeshSlice& slice, const std::string& path) {
  verify_slices_tile(comm, slice, path);
  {
    Hid access = hdf5::mpio_access(comm, path);
    Hid file = owned(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, access.get()), H5Fclose,
                     "H5Fcreate", path);
    Hid transfer = hdf5::collective_transfer(path);
    Hid mesh = owned(H5Gcreate2(file.get(), "/mesh", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                     H5Gclose, "H5Gcreate2", path + ":/mesh");

    const std::string positions_where = path + ":" + kPositions;
    Hid positions = hdf5::create_rows_dataset(mesh.get(), "positions", H5T_IEEE_F64LE,
                                              slice.num_global_vertices, 3, positions_where);
    hdf5::write_block(positions.get(), transfer.get(), H5T_NATIVE_DOUBLE, slice.first_vertex,
                      slice.num_vertices(), 3, slice.positions.data(), positions_where);

    const std::string tets_where = path + ":" + kTets;
    Hid tets = hdf5::create_rows_dataset(mesh.get(), "tets", H5T_STD_I64LE, slice.num_global_tets,
                                         4, tets_where);
    hdf5::write_block(tets.get(), transfer.get(), H5T_NATIVE_INT64, slice.first_tet,
                      slice.num_tets(), 4, slice.tets.data(), tets_where);
  }
  write_xdmf(comm, slice, path);
}

MeshSlice read_mesh_h5(MPI_Comm comm, const std::string& path) {
  verify_file_on_rank0(comm, path);
  int rank = 0, size = 0;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  MeshSlice slice;
  slice.source = path;
  // Every collective call happens in this block, and every handle is closed
  // at its end, before any rank checks its rows and may throw.
  {
    Hid access = hdf5::mpio_access(comm, path);
    Hid file =
        owned(H5Fopen(path.c_str(), H5F_ACC_RDONLY, access.get()), H5Fclose, "H5Fopen", path);
    Hid transfer = hdf5::independent_transfer(path);
    const hdf5::RowsDataset tets = hdf5::open_rows_dataset(file.get(), path, kTets, kTetsShape);
    const hdf5::RowsDataset positions =
        hdf5::open_rows_dataset(file.get(), path, kPositions, kPositionsShape);
    if (tets.rows == 0)
      throw InputError(detail::concat(path, ": ", kTets, " has no rows; a mesh needs a tet"));
    slice.num_global_tets = tets.rows;
    slice.num_global_vertices = positions.rows;

    const BlockRange tet_blocks(tets.rows, size), vertex_blocks(positions.rows, size);
    slice.first_tet = tet_blocks.begin(rank);
    slice.tets.resize(4 * static_cast<std::size_t>(tet_blocks.size(rank)));
    slice.first_vertex = vertex_blocks.begin(rank);
    slice.positions.resize(3 * static_cast<std::size_t>(vertex_blocks.size(rank)));
    std::string read_error;  // this rank's, agreed on by every rank below
    try {
      hdf5::read_block(tets.dataset.get(), transfer.get(), H5T_NATIVE_INT64, slice.first_tet,
                       tet_blocks.size(rank), 4, slice.tets.data(), path + ":" + kTets);
      hdf5::read_block(positions.dataset.get(), transfer.get(), H5T_NATIVE_DOUBLE,
                       slice.first_vertex, vertex_blocks.size(rank), 3, slice.positions.data(),
                       path + ":" + kPositions);
    } catch (const Hdf5Error& e) {
      read_error = e.what();
    }
    throw_if_any_failed<Hdf5Error>(comm, read_error);
  }
  verify_rows(slice, path);
  return slice;
}

}  // namespace descent
