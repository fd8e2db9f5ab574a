#pragma once
// Private parts of mesh_io: the per-format readers and the validation that
// every reader and validate_mesh share.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <iterator>
#include <limits>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "common/error.hpp"
#include "io/line_scanner.hpp"
#include "io/mesh_io.hpp"

namespace descent::mesh_io_detail {

// Most vertices or tets a mesh can hold with 32-bit indices.
constexpr std::int64_t kMaxIndexCount = std::numeric_limits<index_t>::max();

// Where each vertex and tet came from, so that messages use the file's own
// numbers and lines. An in-memory mesh has a name only and 0-based numbers.
struct MeshOrigin {
  std::string name;  // path of the file the tets came from, or what the mesh is
  // Number of vertex v: vertex_numbers[v] when set (sparse file tags), else
  // first_vertex_number + v. Likewise for tets.
  std::int64_t first_vertex_number = 0;
  std::vector<std::int64_t> vertex_numbers;
  std::int64_t first_tet_number = 0;
  std::vector<std::int64_t> tet_numbers;
  std::vector<std::int64_t> tet_lines;  // 1-based line of each tet; empty in memory

  std::int64_t vertex_number(index_t v) const;
  std::int64_t tet_number(index_t t) const;
  // "path:line" of tet t, or the name for an in-memory mesh.
  std::string tet_location(index_t t) const;
};

struct ReadResult {
  Mesh mesh;
  MeshOrigin origin;
  std::vector<std::string> warnings;  // the reader's own, e.g. skipped element types
};

// Parse one format into a mesh, without validation beyond index ranges and
// finite coordinates (which need the line being read).
ReadResult read_gmsh(const std::string& path);
ReadResult read_medit(const std::string& path);
ReadResult read_tetgen(const std::string& node_path, const std::string& ele_path);
ReadResult read_vtu(const std::string& path);
ReadResult read_vtk(const std::string& path);

// VTK's cell type of the linear tet (VTK_TETRA), in .vtu and legacy .vtk.
constexpr std::int64_t kVtkTetraType = 10;

// VTK volume cell types other than the linear tet (voxel, hexahedron,
// wedge, pyramid, pentagonal and hexagonal prisms, the quadratic and
// Lagrange families, polyhedron): skipped with a warning, not silently.
inline bool is_other_vtk_volume_type(std::int64_t type) {
  constexpr std::int64_t kTypes[] = {11, 12, 13, 14, 15, 16, 24, 25, 26, 27,
                                     29, 32, 33, 42, 71, 72, 73, 74, 79};
  return std::find(std::begin(kTypes), std::end(kTypes), type) != std::end(kTypes);
}

// The rules of validate_mesh, with messages naming elements as `origin` says.
// Sets the report's counts and appends its warnings.
void validate(Mesh& mesh, const MeshOrigin& origin, MeshReadReport* report);

// What a reader skipped, for its warning: "skipped volume elements of Gmsh
// type 11 (120), 5 (3); only 4-node tets (type 4) are read", from the count
// of each skipped type.
inline std::string skipped_volume_note(const std::map<std::int64_t, std::int64_t>& skipped,
                                       std::string_view kinds, std::string_view read) {
  std::string note = detail::concat("skipped volume ", kinds, " type");
  const char* separator = " ";
  for (const auto& [type, how_many] : skipped) {
    note += detail::concat(separator, type, " (", how_many, ")");
    separator = ", ";
  }
  return detail::concat(note, "; only ", read, " are read");
}

// The extension of a path in lower case, with its dot: ".msh"; empty if none.
inline std::string lowercase_extension(const std::string& path) {
  std::string extension = std::filesystem::path(path).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return extension;
}

// Reads "x y z" from the scanner's line and appends them; `number` names the
// vertex when a coordinate is not finite.
inline void read_vertex(LineScanner& scanner, std::int64_t number, std::vector<double>& positions) {
  const double x = scanner.real("x coordinate");
  const double y = scanner.real("y coordinate");
  const double z = scanner.real("z coordinate");
  if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z))
    scanner.fail(detail::concat("vertex ", number, " has a non-finite coordinate (", x, " ", y, " ",
                                z, ")"));
  positions.insert(positions.end(), {x, y, z});
}

// Moves the scanner to the next record line; at the end of the file, fails
// saying which record of how many was missing.
inline void next_record(LineScanner& scanner, std::int64_t done, std::int64_t declared,
                        const char* records, const char* section) {
  if (!scanner.next_line())
    scanner.fail(detail::concat("the file ended after ", done, " of the ", declared, " ", records,
                                " that ", section, " declares (truncated file)"));
}

}  // namespace descent::mesh_io_detail
