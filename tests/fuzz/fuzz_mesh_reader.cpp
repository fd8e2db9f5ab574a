// Fuzz target for descent::read_mesh. Bad files must end in descent::Error;
// any other exception, a crash, a sanitizer report or a mesh that breaks the
// readers' promises is a finding.
//
// Input: byte 0 picks the format and how read_mesh is called, the rest is
// the file text. Byte 0 % 4: 0 Gmsh .msh, 1 MEDIT .mesh, 2 TetGen, whose
// text is split at the first "@@" into the .node and the .ele (no "@@": an
// empty .ele), 3 VTK: .vtu, or legacy .vtk where (byte 0 / 72) is odd. So a
// corpus file starts with the digit '0', '1', '2' or '3', or 'K' for .vtk.
// Higher bits vary what does not change the parse: which TetGen name is
// passed, an upper-case extension, with or without a report.
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <string_view>

#include "common/error.hpp"
#include "io/mesh_io.hpp"
#include "tests/fuzz/fuzz_common.hpp"

namespace {

namespace fs = std::filesystem;

// One directory per process, reused for every input: libFuzzer runs
// millions of inputs, and parallel jobs (-jobs=N) must not share files.
// Memory-backed /dev/shm where there is one: on a disk file system the
// rewrite of each input costs far more than the read being tested.
class ScratchDir {
 public:
  ScratchDir() {
    const std::string name = "descent-fuzz-mesh-" + std::to_string(::getpid());
    std::error_code error;
    dir_ = fs::path("/dev/shm") / name;
    fs::create_directories(dir_, error);
    if (!error) return;
    dir_ = fs::temp_directory_path() / name;
    fs::create_directories(dir_);
  }
  ~ScratchDir() {
    std::error_code ignored;
    fs::remove_all(dir_, ignored);
  }
  const fs::path& path() const { return dir_; }

 private:
  fs::path dir_;
};

const fs::path& scratch_dir() {
  static const ScratchDir dir;
  return dir.path();
}

// A failed write would test the harness, not the reader: stop loudly.
void write_file(const fs::path& path, std::string_view text) {
  std::FILE* file = std::fopen(path.c_str(), "wb");
  // fwrite of nothing is skipped: an empty view's data() may be null.
  if (!file || (!text.empty() && std::fwrite(text.data(), 1, text.size(), file) != text.size()) ||
      std::fclose(file) != 0) {
    std::perror(path.c_str());
    std::abort();
  }
}

double signed_volume6(const descent::Mesh& mesh, descent::index_t t) {
  const double* x[4];
  for (int k = 0; k < 4; ++k)
    x[k] = &mesh.positions[3 * static_cast<std::size_t>(
                                   mesh.tets[4 * static_cast<std::size_t>(t) + k])];
  double e[3][3];
  for (int k = 0; k < 3; ++k)
    for (int d = 0; d < 3; ++d) e[k][d] = x[k + 1][d] - x[0][d];
  return e[0][0] * (e[1][1] * e[2][2] - e[1][2] * e[2][1]) -
         e[0][1] * (e[1][0] * e[2][2] - e[1][2] * e[2][0]) +
         e[0][2] * (e[1][0] * e[2][1] - e[1][1] * e[2][0]);
}

// What mesh_io.hpp promises of every mesh a reader returns.
void check_mesh(const descent::Mesh& mesh) {
  using descent::fuzz::broken_promise;
  if (mesh.positions.size() % 3 != 0 || mesh.tets.size() % 4 != 0 || mesh.tets.empty())
    broken_promise("the mesh layout is wrong or it has no tets");
  for (const double x : mesh.positions)
    if (!std::isfinite(x)) broken_promise("a coordinate is not finite");
  for (const descent::index_t v : mesh.tets)
    if (v < 0 || v >= mesh.num_vertices()) broken_promise("a tet index is out of range");
  for (descent::index_t t = 0; t < mesh.num_tets(); ++t) {
    const double volume6 = signed_volume6(mesh, t);
    if (!(volume6 > 0)) {  // also catches NaN
      std::fprintf(stderr, "tet %d (0-based): 6 x signed volume = %g\n", t, volume6);
      broken_promise("a tet is not positively oriented, or its volume is NaN");
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const unsigned selector = data[0];
  const std::string_view text(reinterpret_cast<const char*>(data) + 1, size - 1);
  const bool upper_case = (selector / 9) % 2 == 1;
  const bool with_report = (selector / 18) % 2 == 0;

  const fs::path base = scratch_dir() / "input";
  std::string path;
  switch (selector % 4) {
    case 0:
      path = base.string() + (upper_case ? ".MSH" : ".msh");
      write_file(path, text);
      break;
    case 1:
      path = base.string() + (upper_case ? ".MESH" : ".mesh");
      write_file(path, text);
      break;
    case 3:
      if ((selector / 72) % 2 == 1)
        path = base.string() + (upper_case ? ".VTK" : ".vtk");
      else
        path = base.string() + (upper_case ? ".VTU" : ".vtu");
      write_file(path, text);
      break;
    default: {
      // TetGen pairs are found by name, so both files are always written
      // lower case; the name passed is .node, .ele or the base name.
      const std::size_t separator = text.find("@@");
      write_file(base.string() + ".node", text.substr(0, separator));
      write_file(base.string() + ".ele", separator == std::string_view::npos
                                             ? std::string_view()
                                             : text.substr(separator + 2));
      const char* const names[] = {".node", ".ele", ""};
      path = base.string() + names[(selector / 3) % 3];
      break;
    }
  }

  descent::MeshReadReport report;
  try {
    const descent::Mesh mesh = descent::read_mesh(path, with_report ? &report : nullptr);
    check_mesh(mesh);
    ++descent::fuzz::accepted_inputs;
  } catch (const descent::Error&) {
    // Expected: bad input is reported, not crashed on.
  }
  return 0;
}
