// P ranks equal 1 rank with every way a mesh comes in: generated slices, a
// Gmsh file (parsed on rank 0, blocks sent out), an HDF5 file (every rank
// reads its blocks), and a partition file made once by `descent partition`.
// After a few frames the positions by global id (the input's order) agree
// with a 1-rank run of the generated mesh to 1e-9 of the bounding-box
// diagonal, and shared vertices are bitwise equal on all their sharers. The
// partition file gives the very partition, and so the very positions, of
// partitioning in the run itself; made for P parts, it refuses Q != P ranks.
#include <gtest/gtest.h>
#include <mpi.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "app/agree.hpp"
#include "app/mesh_setup.hpp"
#include "app/partition_command.hpp"
#include "app/scene_mesh.hpp"
#include "app/simulation.hpp"
#include "gather_positions.hpp"
#include "io/mesh_h5.hpp"
#include "mesh_extent.hpp"
#include "partition/partition_file.hpp"
#include "shared_vertices.hpp"
#include "small_scenes.hpp"
#include "world_rank.hpp"

namespace descent {
namespace {

using testing::world_rank;
using testing::world_size;
namespace fs = std::filesystem;

constexpr int kFrames = 6;

// A directory every rank sees, made by rank 0 and removed at the end.
class SharedDirectory {
 public:
  SharedDirectory() {
    path_ = (fs::temp_directory_path() / "descent_input_paths").string();
    if (world_rank() == 0) fs::create_directories(path_);
    MPI_Barrier(MPI_COMM_WORLD);
  }
  ~SharedDirectory() {
    MPI_Barrier(MPI_COMM_WORLD);
    if (world_rank() == 0) fs::remove_all(path_);
  }
  std::string file(const std::string& name) const { return path_ + "/" + name; }

 private:
  std::string path_;
};

Scene from_file(Scene scene, const std::string& path) {
  scene.mesh.generator.clear();
  scene.mesh.file = path;
  return scene;
}

// Positions by global id on rank 0 after kFrames frames; empty elsewhere.
std::vector<double> run(MPI_Comm comm, const Scene& scene, const MeshSetupOptions& options,
                        int* mismatches) {
  DistributedMesh mesh = set_up_mesh(comm, scene, options);
  const global_index_t num_vertices = mesh.local.num_global_vertices;
  Simulation<double> sim(comm, scene, std::move(mesh));
  for (int frame = 0; frame < kFrames; ++frame) sim.step();
  if (mismatches) *mismatches = testing::shared_mismatches(comm, sim);
  return testing::gather_positions(comm, sim, num_vertices);
}

class InputPaths : public ::testing::TestWithParam<std::string> {};

TEST_P(InputPaths, PRanksEqualOneRankWithEveryInputPath) {
  Scene scene = testing::small_helix_scene();
  scene.partition.method = GetParam();
  const SharedDirectory dir;
  const Mesh mesh = build_scene_mesh(scene.mesh);
  if (world_rank() == 0) write_mesh(mesh, dir.file("helix.msh"));
  write_mesh_h5(MPI_COMM_WORLD, build_scene_mesh_slice(MPI_COMM_WORLD, scene.mesh),
                dir.file("helix.h5"));
  PartitionOptions pieces;
  pieces.parts = world_size();
  pieces.out_file = dir.file("pieces.h5");
  pieces.quiet = true;
  run_partition(MPI_COMM_WORLD, scene, pieces);
  MPI_Barrier(MPI_COMM_WORLD);
  if (world_rank() == 0) {
    // The file is a mesh ParaView opens: its index names the file itself.
    std::ifstream index(dir.file("pieces.xdmf"));
    const std::string text((std::istreambuf_iterator<char>(index)), {});
    EXPECT_NE(text.find(">pieces.h5:/mesh/tets<"), std::string::npos) << text;
    EXPECT_FALSE(fs::exists(dir.file("pieces.h5.partial"))) << "the staging directory stays";
  }

  std::vector<double> reference;
  if (world_rank() == 0) reference = run(MPI_COMM_SELF, scene, {}, nullptr);
  const double diagonal = testing::bounding_box_diagonal(mesh);

  struct Path {
    const char* name;
    Scene scene;
    MeshSetupOptions options;
  };
  MeshSetupOptions with_pieces;
  with_pieces.partition_file = pieces.out_file;
  const Path paths[] = {{"generator", scene, {}},
                        {"msh", from_file(scene, dir.file("helix.msh")), {}},
                        {"h5", from_file(scene, dir.file("helix.h5")), {}},
                        {"pieces", scene, with_pieces}};
  std::vector<double> generated;
  for (const Path& path : paths) {
    int mismatches = -1;
    const std::vector<double> got = run(MPI_COMM_WORLD, path.scene, path.options, &mismatches);
    EXPECT_EQ(mismatches, 0) << path.name << ": shared vertices differ between sharers";
    if (world_rank() != 0) continue;
    ASSERT_EQ(got.size(), reference.size()) << path.name;
    double worst = 0, moved = 0;
    for (std::size_t k = 0; k < got.size(); ++k) {
      worst = std::max(worst, std::abs(got[k] - reference[k]));
      moved = std::max(moved, std::abs(reference[k] - mesh.positions[k]));
    }
    EXPECT_GT(moved, 1e-3 * diagonal) << "the helix should sag under gravity";
    EXPECT_LE(worst, 1e-9 * diagonal) << path.name << ": " << world_size() << " ranks vs 1";
    std::printf("[ %s, %s ] %d ranks: max |q_P - q_1| = %.3g (diagonal %.3g)\n", path.name,
                GetParam().c_str(), world_size(), worst, diagonal);
    // Partitioned now or once beforehand: the same partition, bit for bit.
    if (std::string(path.name) == "generator") generated = got;
    if (std::string(path.name) == "pieces") {
      EXPECT_EQ(got, generated);
    }
  }
}

TEST(InputPaths, APartitionFileRefusesAnotherRankCount) {
  const Scene scene = testing::small_helix_scene();
  const SharedDirectory dir;
  PartitionOptions pieces;
  pieces.parts = world_size() + 1;
  pieces.out_file = dir.file("other.h5");
  pieces.quiet = true;
  run_partition(MPI_COMM_WORLD, scene, pieces);
  MeshSetupOptions options;
  options.partition_file = pieces.out_file;
  try {
    set_up_mesh(MPI_COMM_WORLD, scene, options);
    ADD_FAILURE() << "a partition into " << pieces.parts << " parts ran on " << world_size();
  } catch (const ReportedFailure&) {
    // The message went to stderr on rank 0; the check itself is tested
    // below without the set-up's printing.
  }
  try {
    read_partition_piece(MPI_COMM_WORLD, pieces.out_file);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(detail::concat("into ", world_size() + 1, " parts")), std::string::npos)
        << message;
    EXPECT_NE(message.find(detail::concat("this run has ", world_size(), " rank(s)")),
              std::string::npos)
        << message;
  }
}

std::vector<std::string> methods() {
  std::vector<std::string> m{"metis"};
  if (have_ptscotch()) m.push_back("ptscotch");
  return m;
}

INSTANTIATE_TEST_SUITE_P(Methods, InputPaths, ::testing::ValuesIn(methods()),
                         [](const ::testing::TestParamInfo<std::string>& method) {
                           return method.param;
                         });

}  // namespace
}  // namespace descent
