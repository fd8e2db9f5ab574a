// HDF5 meshes written and read block by block, and read_mesh_slice of any
// format, under 1 to 4 ranks. A mesh written from slices reads back as the
// same slices on the same ranks and as the whole mesh on one rank; bad files
// fail with messages that name the file, the dataset and the row, on the rank
// that read the row or, for what every rank sees, on every rank.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <mpi.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "common/block_range.hpp"
#include "common/error.hpp"
#include "common/mesh_slice.hpp"
#include "io/mesh_h5.hpp"
#include "io/mesh_io.hpp"
#include "meshes/generators.hpp"
#include "shared_test_directory.hpp"
#include "world_rank.hpp"

namespace descent {
namespace {

namespace fs = std::filesystem;

using testing::world_rank;
using testing::world_size;

Mesh small_helix() {
  DoubleHelixParams params;
  params.resolution = 0.8;
  return make_double_helix(params);
}

// Coordinates on a grid of halves, exact in float32 too.
Mesh small_box() {
  BoxParams params;
  params.cells = {3, 2, 2};
  params.size = {1.5, 1.0, 1.0};
  return make_box(params);
}

void expect_same_slice(const MeshSlice& read, const MeshSlice& expected, const std::string& what) {
  EXPECT_EQ(read.num_global_vertices, expected.num_global_vertices) << what;
  EXPECT_EQ(read.num_global_tets, expected.num_global_tets) << what;
  EXPECT_EQ(read.first_tet, expected.first_tet) << what;
  EXPECT_EQ(read.first_vertex, expected.first_vertex) << what;
  EXPECT_EQ(read.tets, expected.tets) << what;
  EXPECT_EQ(read.positions, expected.positions) << what;  // bit for bit
}

std::string read_text(const fs::path& path) {
  std::ifstream in(path);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// Runs `read` on every rank and checks that exactly the ranks in
// `failing_rank` throw InputError with `message`, the others nothing.
void expect_read_error(const std::function<MeshSlice()>& read,
                       const std::function<bool(int)>& failing_rank, const std::string& message) {
  std::string thrown;
  bool threw = false;
  try {
    read();
  } catch (const InputError& error) {
    threw = true;
    thrown = error.what();
  }
  if (failing_rank(world_rank())) {
    EXPECT_TRUE(threw) << "rank " << world_rank() << " expected: " << message;
    EXPECT_EQ(thrown, message);
  } else {
    EXPECT_FALSE(threw) << "rank " << world_rank() << " threw: " << thrown;
  }
}

bool every_rank(int) { return true; }

// Serial HDF5 files for the reader's error cases, written by rank 0. A
// dataset is its name, file type, memory type, dims and values.
struct RawDataset {
  std::string name;
  hid_t file_type;
  hid_t memory_type;
  std::vector<hsize_t> dims;
  const void* values;
};

void write_raw_file(const fs::path& path, const std::vector<RawDataset>& datasets) {
  if (world_rank() == 0) {
    const hid_t file = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    const hid_t group = H5Gcreate2(file, "/mesh", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    for (const RawDataset& d : datasets) {
      const hid_t space = H5Screate_simple(static_cast<int>(d.dims.size()), d.dims.data(), nullptr);
      const hid_t set = H5Dcreate2(file, d.name.c_str(), d.file_type, space, H5P_DEFAULT,
                                   H5P_DEFAULT, H5P_DEFAULT);
      H5Dwrite(set, d.memory_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, d.values);
      H5Dclose(set);
      H5Sclose(space);
    }
    H5Gclose(group);
    H5Fclose(file);
  }
  MPI_Barrier(MPI_COMM_WORLD);
}

// A valid mesh as raw datasets: 64-bit tets and float64 positions of `mesh`.
struct RawMesh {
  std::vector<std::int64_t> tets;
  std::vector<double> positions;
  explicit RawMesh(const Mesh& mesh)
      : tets(mesh.tets.begin(), mesh.tets.end()), positions(mesh.positions) {}
  hsize_t num_tets() const { return tets.size() / 4; }
  hsize_t num_vertices() const { return positions.size() / 3; }
  RawDataset tets_dataset() const {
    return {"/mesh/tets", H5T_STD_I64LE, H5T_NATIVE_INT64, {num_tets(), 4}, tets.data()};
  }
  RawDataset positions_dataset() const {
    return {"/mesh/positions",
            H5T_IEEE_F64LE,
            H5T_NATIVE_DOUBLE,
            {num_vertices(), 3},
            positions.data()};
  }
};

// The rank whose block of `total` rows holds `row`.
int reader_of(global_index_t row, global_index_t total) {
  return BlockRange(total, world_size()).owner(row);
}

TEST(MeshH5, SlicesWrittenReadBackAsTheSameSlicesAndAsTheWholeMeshOnOneRank) {
  SharedTestDirectory dir("descent_test_mesh_h5_round_trip");
  const int rank = world_rank(), size = world_size();
  if (rank == 0) fs::create_directories(dir.path());
  MPI_Barrier(MPI_COMM_WORLD);
  for (const Mesh& mesh : {small_box(), small_helix()}) {
    const std::string path = (dir.path() / "mesh.h5").string();
    const MeshSlice mine = slice_of(mesh, rank, size);
    write_mesh_h5(MPI_COMM_WORLD, mine, path);
    expect_same_slice(read_mesh_h5(MPI_COMM_WORLD, path), mine, mesh.source + " on every rank");
    expect_same_slice(read_mesh_slice(MPI_COMM_WORLD, path, nullptr), mine,
                      mesh.source + " through read_mesh_slice");
    if (rank == 0) {
      expect_same_slice(read_mesh_h5(MPI_COMM_SELF, path), slice_of(mesh, 0, 1),
                        mesh.source + " whole on one rank");
      const std::string xdmf = read_text(dir.path() / "mesh.xdmf");
      const std::string tets_item = "<DataItem Dimensions=\"" + std::to_string(mesh.num_tets()) +
                                    " 4\" NumberType=\"Int\" Precision=\"8\" "
                                    "Format=\"HDF\">mesh.h5:/mesh/tets</DataItem>";
      const std::string positions_item = "<DataItem Dimensions=\"" +
                                         std::to_string(mesh.num_vertices()) +
                                         " 3\" NumberType=\"Float\" Precision=\"8\" "
                                         "Format=\"HDF\">mesh.h5:/mesh/positions</DataItem>";
      EXPECT_NE(xdmf.find("TopologyType=\"Tetrahedron\" NumberOfElements=\"" +
                          std::to_string(mesh.num_tets()) + "\""),
                std::string::npos)
          << xdmf;
      EXPECT_NE(xdmf.find(tets_item), std::string::npos) << xdmf;
      EXPECT_NE(xdmf.find("GeometryType=\"XYZ\""), std::string::npos) << xdmf;
      EXPECT_NE(xdmf.find(positions_item), std::string::npos) << xdmf;
    }
  }
  expect_all_ranks_passed();
}

TEST(MeshH5, SlicesThatDoNotCoverTheMeshOnceThrowOnEveryRank) {
  SharedTestDirectory dir("descent_test_mesh_h5_bad_slices");
  if (world_rank() == 0) fs::create_directories(dir.path());
  MPI_Barrier(MPI_COMM_WORLD);
  const Mesh mesh = small_box();
  // Every rank its block, but the last rank drops its last tet.
  MeshSlice mine = slice_of(mesh, world_rank(), world_size());
  if (world_rank() == world_size() - 1) mine.tets.resize(mine.tets.size() - 4);
  EXPECT_THROW(write_mesh_h5(MPI_COMM_WORLD, mine, (dir.path() / "mesh.h5").string()), LogicError);
  // Every rank the whole mesh: each row written by every rank.
  if (world_size() > 1) {
    EXPECT_THROW(
        write_mesh_h5(MPI_COMM_WORLD, slice_of(mesh, 0, 1), (dir.path() / "mesh.h5").string()),
        LogicError);
  }
  expect_all_ranks_passed();
}

TEST(MeshH5, Int32TetsAndFloat32PositionsAreAccepted) {
  SharedTestDirectory dir("descent_test_mesh_h5_narrow");
  if (world_rank() == 0) fs::create_directories(dir.path());
  const Mesh mesh = small_box();
  const std::vector<float> positions(mesh.positions.begin(), mesh.positions.end());
  const fs::path path = dir.path() / "narrow.h5";
  const hsize_t num_tets = mesh.num_tets(), num_vertices = mesh.num_vertices();
  write_raw_file(
      path,
      {{"/mesh/tets", H5T_STD_I32LE, H5T_NATIVE_INT32, {num_tets, 4}, mesh.tets.data()},
       {"/mesh/positions", H5T_IEEE_F32LE, H5T_NATIVE_FLOAT, {num_vertices, 3}, positions.data()}});
  expect_same_slice(read_mesh_h5(MPI_COMM_WORLD, path.string()),
                    slice_of(mesh, world_rank(), world_size()), "int32 tets, float32 positions");
  expect_all_ranks_passed();
}

TEST(MeshH5, FilesEveryRankSeesAsWrongThrowOnEveryRank) {
  SharedTestDirectory dir("descent_test_mesh_h5_wrong_files");
  if (world_rank() == 0) {
    fs::create_directories(dir.path());
    std::ofstream(dir.path() / "text.h5") << "not HDF5\n";
  }
  MPI_Barrier(MPI_COMM_WORLD);
  const RawMesh raw(small_box());
  auto read = [](const fs::path& path) {
    return [path] { return read_mesh_h5(MPI_COMM_WORLD, path.string()); };
  };

  const fs::path missing = dir.path() / "missing.h5";
  expect_read_error(read(missing), every_rank, missing.string() + ": no such file");
  const fs::path text = dir.path() / "text.h5";
  expect_read_error(read(text), every_rank, text.string() + ": not an HDF5 file");

  const std::string layout =
      " (a mesh file holds /mesh/positions float64 [V, 3] and /mesh/tets int64 [T, 4])";
  const fs::path no_tets = dir.path() / "no_tets.h5";
  write_raw_file(no_tets, {raw.positions_dataset()});
  expect_read_error(read(no_tets), every_rank,
                    no_tets.string() + ": no dataset /mesh/tets" + layout);
  const fs::path no_positions = dir.path() / "no_positions.h5";
  write_raw_file(no_positions, {raw.tets_dataset()});
  expect_read_error(read(no_positions), every_rank,
                    no_positions.string() + ": no dataset /mesh/positions" + layout);

  const fs::path three_columns = dir.path() / "three_columns.h5";
  write_raw_file(three_columns, {{"/mesh/tets",
                                  H5T_STD_I64LE,
                                  H5T_NATIVE_INT64,
                                  {raw.num_tets() * 4 / 3, 3},
                                  raw.tets.data()},
                                 raw.positions_dataset()});
  expect_read_error(read(three_columns), every_rank,
                    three_columns.string() + ": /mesh/tets has shape [" +
                        std::to_string(raw.num_tets() * 4 / 3) +
                        ", 3], expected [T, 4] (4 vertex ids per tet)");
  const fs::path flat = dir.path() / "flat.h5";
  write_raw_file(flat, {raw.tets_dataset(),
                        {"/mesh/positions",
                         H5T_IEEE_F64LE,
                         H5T_NATIVE_DOUBLE,
                         {raw.num_vertices() * 3},
                         raw.positions.data()}});
  expect_read_error(read(flat), every_rank,
                    flat.string() + ": /mesh/positions has shape [" +
                        std::to_string(raw.num_vertices() * 3) +
                        "], expected [V, 3] (3 coordinates per vertex)");

  const fs::path float_tets = dir.path() / "float_tets.h5";
  write_raw_file(float_tets, {{"/mesh/tets",
                               H5T_IEEE_F64LE,
                               H5T_NATIVE_DOUBLE,
                               {raw.num_vertices(), 3},
                               raw.positions.data()},
                              raw.positions_dataset()});
  expect_read_error(
      read(float_tets), every_rank,
      float_tets.string() + ": /mesh/tets does not hold integers; vertex ids must be integers");
  const fs::path integer_positions = dir.path() / "integer_positions.h5";
  write_raw_file(
      integer_positions,
      {raw.tets_dataset(),
       {"/mesh/positions", H5T_STD_I64LE, H5T_NATIVE_INT64, {raw.num_tets(), 4}, raw.tets.data()}});
  expect_read_error(read(integer_positions), every_rank,
                    integer_positions.string() +
                        ": /mesh/positions does not hold float32 or float64 values; coordinates "
                        "must be one of these");

  const fs::path empty = dir.path() / "empty.h5";
  write_raw_file(empty, {{"/mesh/tets", H5T_STD_I64LE, H5T_NATIVE_INT64, {0, 4}, nullptr},
                         raw.positions_dataset()});
  expect_read_error(read(empty), every_rank,
                    empty.string() + ": /mesh/tets has no rows; a mesh needs a tet");
  expect_all_ranks_passed();
}

// A bad row fails on the rank whose block holds it, and only there; the
// other ranks return, so none is left in a collective call.
TEST(MeshH5, BadRowsThrowOnTheRankThatReadThemNamingTheRow) {
  SharedTestDirectory dir("descent_test_mesh_h5_bad_rows");
  if (world_rank() == 0) fs::create_directories(dir.path());
  const RawMesh good(small_box());
  const global_index_t num_tets = good.num_tets(), num_vertices = good.num_vertices();
  auto read = [](const fs::path& path) {
    return [path] { return read_mesh_h5(MPI_COMM_WORLD, path.string()); };
  };
  auto read_by = [&](global_index_t row, global_index_t total) {
    return [row, total](int rank) { return rank == reader_of(row, total); };
  };

  RawMesh out_of_range = good;
  const global_index_t last_tet = num_tets - 1;
  out_of_range.tets[4 * last_tet + 2] = num_vertices;
  const fs::path range_path = dir.path() / "out_of_range.h5";
  write_raw_file(range_path, {out_of_range.tets_dataset(), out_of_range.positions_dataset()});
  expect_read_error(read(range_path), read_by(last_tet, num_tets),
                    range_path.string() + ": /mesh/tets row " + std::to_string(last_tet) +
                        " (tet " + std::to_string(last_tet) + ") refers to vertex " +
                        std::to_string(num_vertices) + ", but the mesh has " +
                        std::to_string(num_vertices) + " vertices");

  RawMesh negative = good;
  negative.tets[4 * 0 + 1] = -1;
  const fs::path negative_path = dir.path() / "negative.h5";
  write_raw_file(negative_path, {negative.tets_dataset(), negative.positions_dataset()});
  expect_read_error(read(negative_path), read_by(0, num_tets),
                    negative_path.string() +
                        ": /mesh/tets row 0 (tet 0) refers to vertex -1, but the mesh has " +
                        std::to_string(num_vertices) + " vertices");

  RawMesh twice = good;
  const global_index_t middle_tet = num_tets / 2;
  std::int64_t* v = &twice.tets[4 * middle_tet];
  v[3] = v[1];
  const fs::path twice_path = dir.path() / "twice.h5";
  write_raw_file(twice_path, {twice.tets_dataset(), twice.positions_dataset()});
  expect_read_error(read(twice_path), read_by(middle_tet, num_tets),
                    twice_path.string() + ": /mesh/tets row " + std::to_string(middle_tet) +
                        " (tet " + std::to_string(middle_tet) + ") uses vertex " +
                        std::to_string(v[1]) + " twice (vertices " + std::to_string(v[0]) + " " +
                        std::to_string(v[1]) + " " + std::to_string(v[2]) + " " +
                        std::to_string(v[3]) + ")");

  RawMesh not_finite = good;
  const global_index_t last_vertex = num_vertices - 1;
  not_finite.positions[3 * last_vertex + 1] = std::numeric_limits<double>::quiet_NaN();
  const fs::path nan_path = dir.path() / "nan.h5";
  write_raw_file(nan_path, {not_finite.tets_dataset(), not_finite.positions_dataset()});
  std::ostringstream coordinates;
  coordinates << not_finite.positions[3 * last_vertex] << " "
              << not_finite.positions[3 * last_vertex + 1] << " "
              << not_finite.positions[3 * last_vertex + 2];
  expect_read_error(read(nan_path), read_by(last_vertex, num_vertices),
                    nan_path.string() + ": /mesh/positions row " + std::to_string(last_vertex) +
                        " (vertex " + std::to_string(last_vertex) +
                        ") has a non-finite coordinate (" + coordinates.str() + ")");
  expect_all_ranks_passed();
}

// ASCII files are parsed on rank 0 with the serial reader's validation
// (re-orientation included) and scattered: the slices equal the serial
// read's, and rank 0's report carries its warnings.
TEST(MeshSlice, AsciiFileReadsAsTheSlicesOfTheSerialRead) {
  SharedTestDirectory dir("descent_test_mesh_slice_ascii");
  if (world_rank() == 0) fs::create_directories(dir.path());
  Mesh mesh = small_helix();
  std::swap(mesh.tets[2], mesh.tets[3]);  // tet 0 negatively oriented: re-oriented on reading
  mesh.positions.insert(mesh.positions.end(), {9.0, 9.0, 9.0});  // a vertex no tet uses
  for (const char* name : {"helix.msh", "helix.mesh", "helix.node"}) {
    const std::string path = (dir.path() / name).string();
    if (world_rank() == 0) write_mesh(mesh, path);
    MPI_Barrier(MPI_COMM_WORLD);
    MeshReadReport report;
    const MeshSlice mine = read_mesh_slice(MPI_COMM_WORLD, path, &report);
    const Mesh serial = read_mesh(path);
    expect_same_slice(mine, slice_of(serial, world_rank(), world_size()), path);
    EXPECT_EQ(mine.source, path);
    if (world_rank() == 0) {
      EXPECT_EQ(report.reoriented_tets, 1) << path;
      EXPECT_EQ(report.unreferenced_vertices, 1) << path;
      EXPECT_EQ(report.warnings.size(), 2u) << path;
    } else {
      EXPECT_TRUE(report.warnings.empty()) << "only rank 0 reads";
    }
  }
  expect_all_ranks_passed();
}

TEST(MeshSlice, AsciiErrorOnRankZeroIsThrownOnEveryRankWithItsMessage) {
  SharedTestDirectory dir("descent_test_mesh_slice_ascii_error");
  const fs::path path = dir.path() / "bad.mesh";
  if (world_rank() == 0) {
    fs::create_directories(dir.path());
    std::ofstream(path) << "MeshVersionFormatted 2\nDimension 3\nVertices\n4\n"
                           "0 0 0 0\n1 0 0 0\n0 1 0 0\n0 0 1 0\nTetrahedra\n1\n1 2 3 9 0\nEnd\n";
  }
  MPI_Barrier(MPI_COMM_WORLD);
  std::string serial_message;
  try {
    read_mesh(path.string());
  } catch (const InputError& error) {
    serial_message = error.what();
  }
  ASSERT_NE(serial_message.find(path.string() + ":11:"), std::string::npos) << serial_message;
  expect_read_error([&] { return read_mesh_slice(MPI_COMM_WORLD, path.string(), nullptr); },
                    every_rank, serial_message);
  const fs::path missing = dir.path() / "missing.msh";
  expect_read_error([&] { return read_mesh_slice(MPI_COMM_WORLD, missing.string(), nullptr); },
                    every_rank,
                    [&] {
                      try {
                        read_mesh(missing.string());
                      } catch (const InputError& error) {
                        return std::string(error.what());
                      }
                      return std::string("no error");
                    }());
  expect_all_ranks_passed();
}

}  // namespace
}  // namespace descent
