// Writes the seed corpora of the fuzz targets into OUT_DIR/mesh and
// OUT_DIR/scene: the handwritten seeds of SEED_DIR (tests/fuzz/corpus) plus
// small boxes in every format the project writes, made by make_box and
// write_mesh, so the seeds follow the writers if those change.
//
//   make_corpus SEED_DIR OUT_DIR
#include <unistd.h>

#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "common/error.hpp"
#include "io/mesh_io.hpp"
#include "meshes/generators.hpp"

namespace {

namespace fs = std::filesystem;

std::string read_file(const fs::path& path) {
  std::ifstream file(path, std::ios::binary);
  if (!file) throw descent::InputError("cannot read " + path.string());
  return {std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>()};
}

void write_file(const fs::path& path, const std::string& text) {
  std::ofstream file(path, std::ios::binary);
  file << text;
  if (!file.flush()) throw descent::InputError("cannot write " + path.string());
}

// Fresh copies of the handwritten seeds: a seed deleted from the source tree
// must not linger in the build tree.
void copy_seeds(const fs::path& from, const fs::path& to) {
  fs::remove_all(to);
  fs::create_directories(to);
  for (const auto& entry : fs::directory_iterator(from))
    if (entry.is_regular_file()) fs::copy_file(entry.path(), to / entry.path().filename());
}

// One box in each written format, as mesh-target inputs: the format digit
// (see fuzz_mesh_reader.cpp), then the text; TetGen's .node and .ele joined
// by "@@".
void write_box_seeds(const descent::BoxParams& params, const std::string& name,
                     const fs::path& scratch, const fs::path& out) {
  const descent::Mesh mesh = descent::make_box(params);
  descent::write_mesh(mesh, (scratch / "box.msh").string());
  descent::write_mesh(mesh, (scratch / "box.mesh").string());
  descent::write_mesh(mesh, (scratch / "box.node").string());
  write_file(out / ("gen_" + name + "_msh"), "0" + read_file(scratch / "box.msh"));
  write_file(out / ("gen_" + name + "_mesh"), "1" + read_file(scratch / "box.mesh"));
  write_file(out / ("gen_" + name + "_tetgen"),
             "2" + read_file(scratch / "box.node") + "@@\n" + read_file(scratch / "box.ele"));
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: %s SEED_DIR OUT_DIR\n", argv[0]);
    return 2;
  }
  try {
    const fs::path seeds = argv[1], out = argv[2];
    copy_seeds(seeds / "mesh", out / "mesh");
    copy_seeds(seeds / "scene", out / "scene");

    const fs::path scratch = out / ("scratch-" + std::to_string(::getpid()));
    fs::create_directories(scratch);
    // Small on purpose: the replay runs thousands of mutations of each.
    descent::BoxParams one_cell;
    one_cell.cells = {1, 1, 1};
    one_cell.tets_per_cell = 5;
    write_box_seeds(one_cell, "1x1x1_5", scratch, out / "mesh");
    descent::BoxParams slab;
    slab.cells = {2, 1, 1};
    slab.size = {2.0, 0.5, 1e-3};
    slab.origin = {-1.0, 3.0, -7.5};
    write_box_seeds(slab, "2x1x1_6", scratch, out / "mesh");
    descent::BoxParams cube;
    cube.cells = {2, 2, 2};
    write_box_seeds(cube, "2x2x2_6", scratch, out / "mesh");
    fs::remove_all(scratch);
  } catch (const std::exception& error) {
    std::fprintf(stderr, "make_corpus: %s\n", error.what());
    return 1;
  }
  return 0;
}
