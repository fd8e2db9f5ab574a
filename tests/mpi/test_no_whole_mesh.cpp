// No rank touches the whole mesh: on 3 ranks, each rank reads or generates
// only its block of tets and vertices, and the heap the whole mesh set-up
// takes on any rank (every vector of slices, dual graph, parts and local
// mesh) stays well under what one rank takes for the same mesh alone.
#include <gtest/gtest.h>
#include <malloc.h>
#include <mpi.h>

#include <atomic>
#include <cstdlib>
#include <filesystem>
#include <new>

#include "app/mesh_setup.hpp"
#include "app/scene_mesh.hpp"
#include "io/mesh_h5.hpp"
#include "small_scenes.hpp"
#include "world_rank.hpp"

// Heap bytes this process holds through operator new (every std::vector),
// and the most it has held since the last reset.
namespace {
std::atomic<long long> g_held{0}, g_peak{0};

void note_allocation(void* p) {
  const long long held = g_held += static_cast<long long>(malloc_usable_size(p));
  long long peak = g_peak.load();
  while (held > peak && !g_peak.compare_exchange_weak(peak, held)) {
  }
}
}  // namespace

void* operator new(std::size_t size) {
  void* p = std::malloc(size == 0 ? 1 : size);
  if (!p) throw std::bad_alloc();
  note_allocation(p);
  return p;
}
void operator delete(void* p) noexcept {
  if (!p) return;
  g_held -= static_cast<long long>(malloc_usable_size(p));
  std::free(p);
}
void operator delete(void* p, std::size_t) noexcept { operator delete(p); }

namespace descent {
namespace {

using testing::world_rank;
using testing::world_size;

// Peak heap bytes above what was held before, while `set_up` runs.
template <class SetUp>
long long peak_heap_of(SetUp&& set_up) {
  const long long before = g_held.load();
  g_peak = before;
  set_up();
  return g_peak.load() - before;
}

Scene helix_scene() {
  Scene scene = testing::small_helix_scene();
  scene.mesh.helix.resolution = 3.075;  // the 82K helix
  return scene;
}

void expect_blocks_only(const MeshSlice& slice) {
  const BlockRange tets(slice.num_global_tets, world_size());
  const BlockRange vertices(slice.num_global_vertices, world_size());
  EXPECT_EQ(slice.num_tets(), tets.size(world_rank()));
  EXPECT_EQ(slice.num_vertices(), vertices.size(world_rank()));
  EXPECT_LE(slice.num_tets(), slice.num_global_tets / world_size() + 1);
}

TEST(NoWholeMesh, EachRankGeneratesOrReadsOnlyItsBlocks) {
  const Scene scene = helix_scene();
  const MeshSlice generated = build_scene_mesh_slice(MPI_COMM_WORLD, scene.mesh);
  expect_blocks_only(generated);
  const std::string path = (std::filesystem::temp_directory_path() / "no_whole_mesh.h5").string();
  write_mesh_h5(MPI_COMM_WORLD, generated, path);
  Scene from_file = scene;
  from_file.mesh.generator.clear();
  from_file.mesh.file = path;
  const MeshSlice read = build_scene_mesh_slice(MPI_COMM_WORLD, from_file.mesh);
  expect_blocks_only(read);
  EXPECT_EQ(read.tets, generated.tets);
  MPI_Barrier(MPI_COMM_WORLD);
  if (world_rank() == 0) std::filesystem::remove(path);
}

TEST(NoWholeMesh, NoRankAllocatesTheWholeSetUp) {
  if (world_size() < 3) GTEST_SKIP() << "the heap of 3 ranks against 1";
  const Scene scene = helix_scene();
  long long on_p = peak_heap_of([&] { set_up_mesh(MPI_COMM_WORLD, scene, {}); });
  long long most = 0;
  MPI_Allreduce(&on_p, &most, 1, MPI_LONG_LONG, MPI_MAX, MPI_COMM_WORLD);
  if (world_rank() == 0) {
    const long long alone = peak_heap_of([&] { set_up_mesh(MPI_COMM_SELF, scene, {}); });
    std::printf("[ heap ] set-up peak: %lld bytes on one rank, at most %lld on each of %d\n", alone,
                most, world_size());
    // 1/P of it plus the halo's share; a rank that held the whole mesh
    // at any moment would be near 1.
    EXPECT_LT(static_cast<double>(most), 0.5 * static_cast<double>(alone));
  }
}

}  // namespace
}  // namespace descent
