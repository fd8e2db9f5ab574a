// FrameWriter and StatsWriter under 1 to 4 ranks. Ranks own interleaved,
// non-contiguous rows given in descending order, or rows of a shuffled
// numbering, and some vertices belong to no tet; rank 0 then reopens the files
// serially and checks every value. Each test ends by agreeing across ranks on
// pass or fail, so a failure seen on one rank fails the test on all of them.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <mpi.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <functional>
#include <numeric>
#include <random>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "common/error.hpp"
#include "io/frame_writer.hpp"
#include "meshes/generators.hpp"
#include "shared_test_directory.hpp"
#include "world_rank.hpp"

namespace descent {
namespace {

namespace fs = std::filesystem;

constexpr global_index_t kNumVertices = 20;
constexpr global_index_t kNumTets = 10;
const std::vector<int> kFrames = {0, 7, 12};  // 000012 checks the zero padding

using testing::world_rank;
using testing::world_size;

// Known values of the synthetic mesh, as functions of global ids.
double rest_position(global_index_t vertex, int axis) { return vertex + 0.1 * axis; }

double frame_position(global_index_t vertex, int axis, int frame) {
  return 1000.0 * frame + vertex + 0.01 * axis + 1.0 / 3.0;
}

double frame_velocity(global_index_t vertex, int axis, int frame) {
  return -0.5 * frame + 0.25 * vertex - axis / 7.0;
}

double frame_time(int frame) { return 0.1 * frame + 1e-7; }

global_index_t tet_vertex(global_index_t tet, int corner) {
  const global_index_t offsets[4] = {0, 3, 7, 11};
  return (tet + offsets[corner]) % kNumVertices;
}

// A fresh directory per test, shared by the ranks.
class TestDirectory : public SharedTestDirectory {
 public:
  explicit TestDirectory(const std::string& test_name)
      : SharedTestDirectory("descent_test_frame_writer_" + test_name) {}
};

// The rows one rank writes, in descending id order to exercise the sorting.
struct OwnedPart {
  std::vector<global_index_t> vertex_ids;
  std::vector<double> rest_positions;
  std::vector<global_index_t> tet_ids;
  std::vector<global_index_t> tet_vertices;

  FrameWriterLayout layout() const {
    return {kNumVertices, kNumTets, vertex_ids, tet_ids, tet_vertices, rest_positions, {}, {}};
  }
  std::vector<double> positions(int frame) const {
    std::vector<double> positions;
    for (global_index_t vertex : vertex_ids)
      for (int axis = 0; axis < 3; ++axis) positions.push_back(frame_position(vertex, axis, frame));
    return positions;
  }
  std::vector<double> velocities(int frame) const {
    std::vector<double> velocities;
    for (global_index_t vertex : vertex_ids)
      for (int axis = 0; axis < 3; ++axis)
        velocities.push_back(frame_velocity(vertex, axis, frame));
    return velocities;
  }
  void write(FrameWriter& writer, int frame) const {
    writer.write_frame(frame, frame_time(frame), positions(frame), velocities(frame));
  }
};

OwnedPart owned_part(const std::function<int(global_index_t)>& vertex_owner,
                     const std::function<int(global_index_t)>& tet_owner) {
  OwnedPart part;
  const int rank = world_rank();
  for (global_index_t vertex = kNumVertices - 1; vertex >= 0; --vertex) {
    if (vertex_owner(vertex) != rank) continue;
    part.vertex_ids.push_back(vertex);
    for (int axis = 0; axis < 3; ++axis) part.rest_positions.push_back(rest_position(vertex, axis));
  }
  for (global_index_t tet = kNumTets - 1; tet >= 0; --tet) {
    if (tet_owner(tet) != rank) continue;
    part.tet_ids.push_back(tet);
    for (int corner = 0; corner < 4; ++corner) part.tet_vertices.push_back(tet_vertex(tet, corner));
  }
  return part;
}

// Serial reads for rank 0's checks. Each closes what it opens before returning.
std::vector<hsize_t> dataset_dims(hid_t file, const std::string& path) {
  std::vector<hsize_t> dims;
  const hid_t dataset = H5Dopen2(file, path.c_str(), H5P_DEFAULT);
  if (dataset < 0) return dims;
  const hid_t space = H5Dget_space(dataset);
  dims.resize(H5Sget_simple_extent_ndims(space));
  H5Sget_simple_extent_dims(space, dims.data(), nullptr);
  H5Sclose(space);
  H5Dclose(dataset);
  return dims;
}

bool dataset_type_is(hid_t file, const std::string& path, hid_t expected) {
  const hid_t dataset = H5Dopen2(file, path.c_str(), H5P_DEFAULT);
  if (dataset < 0) return false;
  const hid_t type = H5Dget_type(dataset);
  const bool equal = H5Tequal(type, expected) > 0;
  H5Tclose(type);
  H5Dclose(dataset);
  return equal;
}

template <class T>
std::vector<T> read_dataset(hid_t file, const std::string& path, hid_t memory_type,
                            std::size_t size) {
  std::vector<T> values(size);
  const hid_t dataset = H5Dopen2(file, path.c_str(), H5P_DEFAULT);
  if (dataset < 0 ||
      H5Dread(dataset, memory_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()) < 0)
    values.clear();
  if (dataset >= 0) H5Dclose(dataset);
  return values;
}

double read_time_attribute(hid_t file, const std::string& group) {
  double time = -1;
  const hid_t attribute = H5Aopen_by_name(file, group.c_str(), "time", H5P_DEFAULT, H5P_DEFAULT);
  if (attribute >= 0) {
    H5Aread(attribute, H5T_NATIVE_DOUBLE, &time);
    H5Aclose(attribute);
  }
  return time;
}

hsize_t count_links(hid_t file, const std::string& group) {
  H5G_info_t info{};
  if (H5Gget_info_by_name(file, group.c_str(), &info, H5P_DEFAULT) < 0) return 0;
  return info.nlinks;
}

std::string frame_name(int frame) {
  char name[16];
  std::snprintf(name, sizeof name, "%06d", frame);
  return name;
}

// `tet_type`: the file type of /mesh/tets (int32 for this small mesh; int64
// in a file an earlier build wrote).
void check_h5(const fs::path& h5_path, hid_t tet_type = H5T_STD_I32LE) {
  const hid_t file = H5Fopen(h5_path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(file, 0) << h5_path;

  const std::vector<hsize_t> tets_dims = {kNumTets, 4};
  EXPECT_EQ(dataset_dims(file, "/mesh/tets"), tets_dims);
  EXPECT_TRUE(dataset_type_is(file, "/mesh/tets", tet_type)) << "ids below 2^31 take 4 bytes";
  const auto tets =
      read_dataset<global_index_t>(file, "/mesh/tets", H5T_NATIVE_INT64, 4 * kNumTets);
  ASSERT_EQ(tets.size(), std::size_t{4 * kNumTets});
  for (global_index_t tet = 0; tet < kNumTets; ++tet)
    for (int corner = 0; corner < 4; ++corner)
      EXPECT_EQ(tets[4 * tet + corner], tet_vertex(tet, corner)) << "tet " << tet;

  const std::vector<hsize_t> vertex_dims = {kNumVertices, 3};
  EXPECT_EQ(dataset_dims(file, "/mesh/rest_positions"), vertex_dims);
  const auto rest =
      read_dataset<double>(file, "/mesh/rest_positions", H5T_NATIVE_DOUBLE, 3 * kNumVertices);
  ASSERT_EQ(rest.size(), std::size_t{3 * kNumVertices});
  for (global_index_t vertex = 0; vertex < kNumVertices; ++vertex)
    for (int axis = 0; axis < 3; ++axis)
      EXPECT_EQ(rest[3 * vertex + axis], rest_position(vertex, axis)) << "vertex " << vertex;

  EXPECT_EQ(count_links(file, "/frames"), kFrames.size());
  for (int frame : kFrames) {
    const std::string group = "/frames/" + frame_name(frame);
    EXPECT_EQ(read_time_attribute(file, group), frame_time(frame)) << group;
    // Each vertex array of the frame, by name, and its value at (vertex, axis).
    const std::vector<std::pair<std::string, std::function<double(global_index_t, int)>>> arrays = {
        {"positions", [&](global_index_t v, int a) { return frame_position(v, a, frame); }},
        {"displacement", [&](global_index_t v,
                             int a) { return frame_position(v, a, frame) - rest_position(v, a); }},
        {"velocity", [&](global_index_t v, int a) { return frame_velocity(v, a, frame); }}};
    for (const auto& [name, expected] : arrays) {
      const std::string path = group + "/" + name;
      EXPECT_EQ(dataset_dims(file, path), vertex_dims) << path;
      const auto values = read_dataset<double>(file, path, H5T_NATIVE_DOUBLE, 3 * kNumVertices);
      ASSERT_EQ(values.size(), std::size_t{3 * kNumVertices}) << path;
      for (global_index_t vertex = 0; vertex < kNumVertices; ++vertex)
        for (int axis = 0; axis < 3; ++axis)
          EXPECT_EQ(values[3 * vertex + axis], expected(vertex, axis))
              << path << " vertex " << vertex << " axis " << axis;
    }
  }
  H5Fclose(file);
}

std::string read_text(const fs::path& path) {
  std::ifstream in(path);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

std::size_t count_occurrences(const std::string& text, const std::string& pattern) {
  std::size_t count = 0;
  for (auto at = text.find(pattern); at != std::string::npos; at = text.find(pattern, at + 1))
    ++count;
  return count;
}

// The values of <Time Value="..."/>, in file order.
std::vector<double> time_values(const std::string& xdmf) {
  const std::string tag = "<Time Value=\"";
  std::vector<double> times;
  for (auto at = xdmf.find(tag); at != std::string::npos; at = xdmf.find(tag, at + 1))
    times.push_back(std::stod(xdmf.substr(at + tag.size())));
  return times;
}

// The XDMF index as text: one Uniform grid per frame, the topology in the
// first and included by the others, three vertex arrays per frame, relative
// paths, right sizes.
void check_xdmf(const fs::path& xdmf_path, std::size_t frames_written, int tet_id_bytes = 4) {
  const std::string xdmf = read_text(xdmf_path);
  EXPECT_EQ(count_occurrences(xdmf, "CollectionType=\"Temporal\""), 1u) << xdmf;
  EXPECT_EQ(count_occurrences(xdmf, "GridType=\"Uniform\""), frames_written) << xdmf;
  EXPECT_EQ(count_occurrences(xdmf, "<Time Value="), frames_written) << xdmf;
  EXPECT_EQ(count_occurrences(xdmf, "TopologyType=\"Tetrahedron\" NumberOfElements=\"10\""), 1u);
  EXPECT_EQ(count_occurrences(xdmf, "Dimensions=\"10 4\" NumberType=\"Int\" Precision=\"" +
                                        std::to_string(tet_id_bytes) + "\""),
            1u)
      << "the index gives /mesh/tets' own width";
  EXPECT_EQ(count_occurrences(xdmf, ">frames.h5:/mesh/tets</DataItem>"), 1u);
  EXPECT_EQ(count_occurrences(xdmf, "xmlns:xi=\"http://www.w3.org/2001/XInclude\""), 1u);
  EXPECT_EQ(count_occurrences(
                xdmf, "<xi:include xpointer=\"xpointer(/Xdmf/Domain/Grid/Grid[1]/Topology)\"/>"),
            frames_written - 1);
  EXPECT_LT(xdmf.find("<Topology"), xdmf.find("<xi:include")) << "the first grid holds it";
  EXPECT_EQ(count_occurrences(xdmf, "GeometryType=\"XYZ\""), frames_written);
  EXPECT_EQ(count_occurrences(xdmf, "AttributeType=\"Vector\" Center=\"Node\""),
            2 * frames_written);
  EXPECT_EQ(count_occurrences(xdmf, "Dimensions=\"20 3\" NumberType=\"Float\" Precision=\"8\""),
            3 * frames_written);
  std::vector<double> expected_times;
  for (std::size_t k = 0; k < frames_written; ++k) {
    const std::string group = "frames.h5:/frames/" + frame_name(kFrames[k]);
    EXPECT_EQ(count_occurrences(xdmf, ">" + group + "/positions</DataItem>"), 1u) << group;
    for (const char* name : {"displacement", "velocity"}) {
      EXPECT_EQ(count_occurrences(xdmf, "<Attribute Name=\"" + std::string(name) +
                                            "\" AttributeType=\"Vector\" Center=\"Node\">\n"
                                            "          <DataItem Dimensions=\"20 3\" "
                                            "NumberType=\"Float\" Precision=\"8\" "
                                            "Format=\"HDF\">" +
                                            group + "/" + name + "</DataItem>"),
                1u)
          << group << " " << name;
    }
    expected_times.push_back(frame_time(kFrames[k]));
  }
  EXPECT_EQ(time_values(xdmf), expected_times) << "times in frame order, exact";
  EXPECT_EQ(xdmf.find(xdmf_path.parent_path().string()), std::string::npos)
      << "the index must name frames.h5 relatively";
  EXPECT_FALSE(fs::exists(xdmf_path.string() + ".tmp"));
}

// Writes kFrames with the given ownership, then checks the files on rank 0.
void write_and_check(const std::string& test_name,
                     const std::function<int(global_index_t)>& vertex_owner,
                     const std::function<int(global_index_t)>& tet_owner) {
  TestDirectory dir(test_name);
  const fs::path output = dir.path() / "nested" / "frames";  // parents are created too
  const OwnedPart part = owned_part(vertex_owner, tet_owner);
  {
    FrameWriter writer(MPI_COMM_WORLD, output.string(), part.layout());
    EXPECT_EQ(writer.h5_path(), (output / "frames.h5").string());
    EXPECT_EQ(writer.xdmf_path(), (output / "frames.xdmf").string());
    for (std::size_t k = 0; k < kFrames.size(); ++k) {
      part.write(writer, kFrames[k]);
      // Each completed frame is listed at once (what a killed run leaves).
      if (world_rank() == 0) check_xdmf(output / "frames.xdmf", k + 1);
    }
  }
  if (world_rank() == 0) check_h5(output / "frames.h5");
  expect_all_ranks_passed();
}

TEST(FrameWriter, InterleavedOwnershipWritesEveryRowAtItsGlobalId) {
  const int size = world_size();
  write_and_check(
      "interleaved", [size](global_index_t vertex) { return vertex % size; },
      [size](global_index_t tet) { return (tet * 7) % size; });
}

TEST(FrameWriter, RanksWithoutRowsStillTakePart) {
  write_and_check(
      "rank0_owns_all", [](global_index_t) { return 0; }, [](global_index_t) { return 0; });
}

// Ids up to 2^31 - 1 fit in int32; one more vertex needs int64.
TEST(FrameWriter, VertexIdsTakeFourBytesWhileTheyFitInt32) {
  const global_index_t int32_ids = global_index_t{1} << 31;  // ids 0 .. 2^31 - 1
  EXPECT_EQ(frame_tet_id_bytes(kNumVertices), 4);
  EXPECT_EQ(frame_tet_id_bytes(int32_ids), 4);
  EXPECT_EQ(frame_tet_id_bytes(int32_ids + 1), 8);
}

// A run killed after frame 12 but checkpointed at frame 7 resumes after 7:
// frame 12 is dropped, the index lists frames 0 and 7 in full again, and
// frame 12 can be written anew.
TEST(FrameWriter, ResumingDropsLaterFramesAndRebuildsTheIndex) {
  TestDirectory dir("resume");
  const int size = world_size();
  const OwnedPart part = owned_part([size](global_index_t vertex) { return (vertex / 3) % size; },
                                    [size](global_index_t tet) { return tet % size; });
  {
    FrameWriter writer(MPI_COMM_WORLD, dir.path().string(), part.layout());
    for (int frame : kFrames) part.write(writer, frame);
  }
  {
    FrameWriter resumed(MPI_COMM_WORLD, dir.path().string(), part.layout(), kFrames[1]);
    if (world_rank() == 0) {
      check_xdmf(dir.path() / "frames.xdmf", 2);
      const hid_t file = H5Fopen((dir.path() / "frames.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
      EXPECT_EQ(count_links(file, "/frames"), 2u);
      H5Fclose(file);
    }
    part.write(resumed, kFrames[2]);
  }
  if (world_rank() == 0) {
    check_xdmf(dir.path() / "frames.xdmf", kFrames.size());
    check_h5(dir.path() / "frames.h5");
  }
  expect_all_ranks_passed();
}

// A file whose /mesh/tets an earlier build wrote in int64 resumes, and the
// rebuilt index names that width (an index saying 4 would misread them).
TEST(FrameWriter, ResumingAFileWithInt64TetsKeepsTheirWidthInTheIndex) {
  TestDirectory dir("resume_int64");
  const int size = world_size();
  const OwnedPart part = owned_part([size](global_index_t vertex) { return vertex % size; },
                                    [size](global_index_t tet) { return tet % size; });
  {
    FrameWriter writer(MPI_COMM_WORLD, dir.path().string(), part.layout());
    for (int frame : kFrames) part.write(writer, frame);
  }
  if (world_rank() == 0) {  // /mesh/tets rewritten as int64, the same ids
    const fs::path h5 = dir.path() / "frames.h5";
    const auto ids = [&] {
      const hid_t file = H5Fopen(h5.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
      auto read = read_dataset<global_index_t>(file, "/mesh/tets", H5T_NATIVE_INT64, 4 * kNumTets);
      H5Fclose(file);
      return read;
    }();
    const hid_t file = H5Fopen(h5.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    ASSERT_GE(H5Ldelete(file, "/mesh/tets", H5P_DEFAULT), 0);
    const hsize_t dims[2] = {kNumTets, 4};
    const hid_t space = H5Screate_simple(2, dims, nullptr);
    const hid_t set =
        H5Dcreate2(file, "/mesh/tets", H5T_STD_I64LE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    EXPECT_GE(H5Dwrite(set, H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, ids.data()), 0);
    H5Dclose(set);
    H5Sclose(space);
    H5Fclose(file);
  }
  MPI_Barrier(MPI_COMM_WORLD);
  {
    FrameWriter resumed(MPI_COMM_WORLD, dir.path().string(), part.layout(), kFrames[1]);
    if (world_rank() == 0) check_xdmf(dir.path() / "frames.xdmf", 2, 8);
    part.write(resumed, kFrames[2]);
  }
  if (world_rank() == 0) {
    check_xdmf(dir.path() / "frames.xdmf", kFrames.size(), 8);
    check_h5(dir.path() / "frames.h5", H5T_STD_I64LE);
  }
  expect_all_ranks_passed();
}

TEST(FrameWriter, WritingAFrameTwiceThrowsHdf5ErrorOnEveryRank) {
  TestDirectory dir("duplicate_frame");
  const int size = world_size();
  const OwnedPart part = owned_part([size](global_index_t vertex) { return vertex % size; },
                                    [size](global_index_t tet) { return tet % size; });
  FrameWriter writer(MPI_COMM_WORLD, dir.path().string(), part.layout());
  part.write(writer, 3);
  H5E_auto2_t print_errors = nullptr;
  void* print_errors_data = nullptr;
  H5Eget_auto2(H5E_DEFAULT, &print_errors, &print_errors_data);
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);  // the HDF5 error stack is expected here
  try {
    part.write(writer, 3);
    ADD_FAILURE() << "no error for a frame written twice";
  } catch (const Hdf5Error& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("H5Gcreate2"), std::string::npos) << message;
    EXPECT_NE(message.find((dir.path() / "frames.h5").string() + ":/frames/000003"),
              std::string::npos)
        << message;
  }
  H5Eset_auto2(H5E_DEFAULT, print_errors, print_errors_data);
  expect_all_ranks_passed();
}

TEST(FrameWriter, DirectoryThatCannotBeCreatedThrowsOnEveryRank) {
  TestDirectory dir("blocked");
  const fs::path blocker = dir.path() / "regular_file";
  if (world_rank() == 0) {
    fs::create_directories(dir.path());
    std::ofstream(blocker) << "not a directory\n";
  }
  MPI_Barrier(MPI_COMM_WORLD);
  const int size = world_size();
  const OwnedPart part = owned_part([size](global_index_t vertex) { return vertex % size; },
                                    [size](global_index_t tet) { return tet % size; });
  const std::string output = (blocker / "frames").string();
  EXPECT_THROW(FrameWriter(MPI_COMM_WORLD, output, part.layout()), InputError);
  EXPECT_THROW(StatsWriter(MPI_COMM_WORLD, output), InputError);
  expect_all_ranks_passed();
}

TEST(FrameWriter, LayoutThatMissesAVertexThrowsOnEveryRank) {
  TestDirectory dir("bad_layout");
  const int size = world_size();
  OwnedPart part = owned_part([size](global_index_t vertex) { return vertex % size; },
                              [size](global_index_t tet) { return tet % size; });
  if (world_rank() == 0) {  // vertex 0 is rank 0's last
    part.vertex_ids.pop_back();
    part.rest_positions.resize(3 * part.vertex_ids.size());
  }
  EXPECT_THROW(FrameWriter(MPI_COMM_WORLD, dir.path().string(), part.layout()), LogicError);
  expect_all_ranks_passed();
}

// The old check only summed counts per rank; a vertex listed twice (on two
// ranks, or twice on one) while another is missing passes that, and must not.
TEST(FrameWriter, LayoutThatGivesAVertexOrTetTwiceThrowsOnEveryRank) {
  TestDirectory dir("duplicate_rows");
  const int size = world_size();
  const int last = size - 1;
  OwnedPart vertices_twice = owned_part([size](global_index_t vertex) { return vertex % size; },
                                        [size](global_index_t tet) { return tet % size; });
  OwnedPart tets_twice = vertices_twice;
  if (world_rank() == last) {
    // Replace its first vertex / tet with one rank 0 owns: the counts still add up.
    vertices_twice.vertex_ids.front() = 0;
    tets_twice.tet_ids.front() = 0;
  }
  EXPECT_THROW(FrameWriter(MPI_COMM_WORLD, dir.path().string(), vertices_twice.layout()),
               LogicError);
  EXPECT_THROW(FrameWriter(MPI_COMM_WORLD, dir.path().string(), tets_twice.layout()), LogicError);
  expect_all_ranks_passed();
}

// A mesh as a user's file may number it: a box whose vertex and tet ids are
// shuffled, so that the vertices a rank owns are scattered over the whole id
// range, plus vertices that no tet uses, at shuffled ids too.
struct ShuffledMesh {
  global_index_t num_vertices = 0, num_tets = 0;
  std::vector<double> positions;             // 3 per vertex, by input id
  std::vector<global_index_t> tets;          // 4 per tet, by input id
  std::vector<char> unused;                  // per vertex: no tet uses it
  std::vector<int> tet_owner, vertex_owner;  // rank of each tet and vertex
};

constexpr int kUnusedVertices = 5;

ShuffledMesh shuffled_mesh(int size) {
  BoxParams params;
  params.cells = {4, 3, 3};
  const Mesh box = make_box(params);
  ShuffledMesh mesh;
  mesh.num_vertices = box.num_vertices() + kUnusedVertices;
  mesh.num_tets = box.num_tets();
  // Every rank draws the same permutations: same seed, same library.
  std::mt19937_64 random(2024);
  std::vector<global_index_t> vertex_id(mesh.num_vertices), tet_id(mesh.num_tets);
  std::iota(vertex_id.begin(), vertex_id.end(), 0);
  std::iota(tet_id.begin(), tet_id.end(), 0);
  std::shuffle(vertex_id.begin(), vertex_id.end(), random);
  std::shuffle(tet_id.begin(), tet_id.end(), random);

  mesh.positions.resize(3 * mesh.num_vertices);
  mesh.unused.assign(mesh.num_vertices, 0);
  for (global_index_t v = 0; v < mesh.num_vertices; ++v)
    for (int axis = 0; axis < 3; ++axis)
      mesh.positions[3 * vertex_id[v] + axis] =
          v < box.num_vertices() ? box.positions[3 * v + axis] : 10.0 + v + axis;
  for (global_index_t v = box.num_vertices(); v < mesh.num_vertices; ++v)
    mesh.unused[vertex_id[v]] = 1;

  // Tets by slabs of x (a partitioner's geometric split), vertices to the
  // lowest rank of a tet using them, unused vertices round robin.
  mesh.tets.resize(4 * mesh.num_tets);
  mesh.tet_owner.resize(mesh.num_tets);
  mesh.vertex_owner.assign(mesh.num_vertices, size);
  for (global_index_t t = 0; t < mesh.num_tets; ++t) {
    double centroid_x = 0;
    for (int corner = 0; corner < 4; ++corner)
      centroid_x += 0.25 * box.positions[3 * box.tets[4 * t + corner]];
    const int owner = std::min(size - 1, static_cast<int>(centroid_x * size));
    mesh.tet_owner[tet_id[t]] = owner;
    for (int corner = 0; corner < 4; ++corner) {
      const global_index_t v = vertex_id[box.tets[4 * t + corner]];
      mesh.tets[4 * tet_id[t] + corner] = v;
      mesh.vertex_owner[v] = std::min(mesh.vertex_owner[v], owner);
    }
  }
  for (global_index_t v = 0; v < mesh.num_vertices; ++v)
    if (mesh.unused[v]) mesh.vertex_owner[v] = static_cast<int>(v % size);
  return mesh;
}

TEST(FrameWriter, ShuffledNumberingAndUnusedVerticesRoundTripInInputOrder) {
  TestDirectory dir("shuffled");
  const int rank = world_rank();
  const ShuffledMesh mesh = shuffled_mesh(world_size());
  std::vector<global_index_t> owned, unused, tet_ids, tet_vertices;
  std::vector<double> owned_rest, unused_rest;
  for (global_index_t v = 0; v < mesh.num_vertices; ++v) {
    if (mesh.vertex_owner[v] != rank) continue;
    (mesh.unused[v] ? unused : owned).push_back(v);
    auto& rest = mesh.unused[v] ? unused_rest : owned_rest;
    rest.insert(rest.end(), &mesh.positions[3 * v], &mesh.positions[3 * v + 3]);
  }
  for (global_index_t t = 0; t < mesh.num_tets; ++t) {
    if (mesh.tet_owner[t] != rank) continue;
    tet_ids.push_back(t);
    tet_vertices.insert(tet_vertices.end(), &mesh.tets[4 * t], &mesh.tets[4 * t + 4]);
  }
  if (world_size() > 1 && !owned.empty()) {
    // The point of the test: each rank's ids spread over the whole range.
    EXPECT_LT(owned.front(), mesh.num_vertices / 4);
    EXPECT_GT(owned.back(), 3 * mesh.num_vertices / 4);
  }

  const FrameWriterLayout layout{mesh.num_vertices, mesh.num_tets, owned,  tet_ids,
                                 tet_vertices,      owned_rest,    unused, unused_rest};
  const std::vector<int> frames = {0, 4};
  {
    FrameWriter writer(MPI_COMM_WORLD, dir.path().string(), layout);
    for (int frame : frames) {
      std::vector<double> positions, velocities;
      for (std::size_t k = 0; k < owned.size(); ++k)
        for (int axis = 0; axis < 3; ++axis) {
          positions.push_back(owned_rest[3 * k + axis] + frame_position(owned[k], axis, frame));
          velocities.push_back(frame_velocity(owned[k], axis, frame));
        }
      writer.write_frame(frame, frame_time(frame), positions, velocities);
    }
  }

  if (rank == 0) {
    const hid_t file = H5Fopen((dir.path() / "frames.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    ASSERT_GE(file, 0);
    EXPECT_EQ(read_dataset<double>(file, "/mesh/rest_positions", H5T_NATIVE_DOUBLE,
                                   3 * mesh.num_vertices),
              mesh.positions);
    EXPECT_EQ(read_dataset<global_index_t>(file, "/mesh/tets", H5T_NATIVE_INT64, 4 * mesh.num_tets),
              mesh.tets);
    for (int frame : frames) {
      const std::string group = "/frames/" + frame_name(frame);
      const auto positions = read_dataset<double>(file, group + "/positions", H5T_NATIVE_DOUBLE,
                                                  3 * mesh.num_vertices);
      const auto displacement = read_dataset<double>(file, group + "/displacement",
                                                     H5T_NATIVE_DOUBLE, 3 * mesh.num_vertices);
      const auto velocity =
          read_dataset<double>(file, group + "/velocity", H5T_NATIVE_DOUBLE, 3 * mesh.num_vertices);
      ASSERT_EQ(positions.size(), mesh.positions.size());
      ASSERT_EQ(displacement.size(), mesh.positions.size());
      ASSERT_EQ(velocity.size(), mesh.positions.size());
      for (global_index_t v = 0; v < mesh.num_vertices; ++v)
        for (int axis = 0; axis < 3; ++axis) {
          const std::size_t at = 3 * v + axis;
          const double rest = mesh.positions[at];
          if (mesh.unused[v]) {  // at rest in every frame
            EXPECT_EQ(positions[at], rest) << group << " unused vertex " << v;
            EXPECT_EQ(displacement[at], 0.0) << group << " unused vertex " << v;
            EXPECT_EQ(velocity[at], 0.0) << group << " unused vertex " << v;
            continue;
          }
          const double expected = rest + frame_position(v, axis, frame);
          EXPECT_EQ(positions[at], expected) << group << " vertex " << v;
          EXPECT_EQ(displacement[at], expected - rest) << group << " vertex " << v;
          EXPECT_EQ(velocity[at], frame_velocity(v, axis, frame)) << group << " vertex " << v;
        }
    }
    H5Fclose(file);
  }
  expect_all_ranks_passed();
}

std::vector<std::string> split(const std::string& line, char separator) {
  std::vector<std::string> fields;
  std::istringstream in(line);
  for (std::string field; std::getline(in, field, separator);) fields.push_back(field);
  return fields;
}

TEST(StatsWriter, WritesHeaderAndOneRowPerFrame) {
  TestDirectory dir("stats");
  const std::vector<FrameStats> rows = {
      {0, 0.0, 12, 0, 1.0, -1.0 / 3.0, 10.25, 1.5, 0.125, 0, {0.5, -2.0}},
      {1,
       1.0 / 60.0,
       30,
       2,
       0.123456789012345678,
       6.02214076e23,
       2000.0,
       0.0004,
       3.0,
       1,
       {1e-300, 7.0},
       3,
       "stalled",
       2.3e-4,
       2.86,
       0.99983922,
       20,
       0.0125}};
  std::string path;
  {
    StatsWriter stats(MPI_COMM_WORLD, dir.path().string(), {"load0_disp_y", "converted"});
    path = stats.path();
    for (const FrameStats& row : rows) stats.write(row);
  }
  EXPECT_EQ(path, (dir.path() / "stats.csv").string());
  if (world_rank() == 0) {
    std::istringstream csv(read_text(path));
    std::string line;
    std::getline(csv, line);
    EXPECT_EQ(line,
              "frame,sim_time,iterations,rollbacks,alpha,energy,wall_ms,halo_ms,allreduce_ms,"
              "stalled,nonfinite_rollbacks,status,lambda_min,lambda_max,rho,spectrum_steps,"
              "error_estimate,load0_disp_y,converted");
    for (const FrameStats& row : rows) {
      ASSERT_TRUE(std::getline(csv, line));
      const auto fields = split(line, ',');
      ASSERT_EQ(fields.size(), 19u) << line;
      EXPECT_EQ(std::stoi(fields[0]), row.frame);
      EXPECT_EQ(std::stod(fields[1]), row.sim_time) << "exact round trip";
      EXPECT_EQ(std::stoi(fields[2]), row.iterations);
      EXPECT_EQ(std::stoi(fields[3]), row.rollbacks);
      EXPECT_EQ(std::stod(fields[4]), row.alpha) << "exact round trip";
      EXPECT_EQ(std::stod(fields[5]), row.energy) << "exact round trip";
      EXPECT_NEAR(std::stod(fields[6]), row.wall_ms, 5e-4);
      EXPECT_NEAR(std::stod(fields[7]), row.halo_ms, 5e-4);
      EXPECT_NEAR(std::stod(fields[8]), row.allreduce_ms, 5e-4);
      EXPECT_EQ(std::stoi(fields[9]), row.stalled);
      EXPECT_EQ(std::stoi(fields[10]), row.nonfinite_rollbacks);
      EXPECT_EQ(fields[11], row.status);
      EXPECT_EQ(std::stod(fields[12]), row.lambda_min) << "exact round trip";
      EXPECT_EQ(std::stod(fields[13]), row.lambda_max) << "exact round trip";
      EXPECT_EQ(std::stod(fields[14]), row.rho) << "exact round trip";
      EXPECT_EQ(std::stoi(fields[15]), row.spectrum_steps);
      EXPECT_EQ(std::stod(fields[16]), row.error_estimate) << "exact round trip";
      EXPECT_EQ(std::stod(fields[17]), row.extra[0]) << "exact round trip";
      EXPECT_EQ(std::stod(fields[18]), row.extra[1]) << "exact round trip";
    }
    EXPECT_FALSE(std::getline(csv, line)) << "one row per write: " << line;
  }
  expect_all_ranks_passed();
}

}  // namespace
}  // namespace descent
