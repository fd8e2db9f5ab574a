// read_mesh picks the reader by extension and validates what it read;
// validate_mesh applies the same checks to a mesh built in memory.
#include "io/mesh_io.hpp"

#include <filesystem>

#include "io/mesh_io_detail.hpp"

namespace descent {

namespace {

using mesh_io_detail::ReadResult;

using mesh_io_detail::lowercase_extension;

ReadResult read_by_format(const std::string& path) {
  const std::string extension = lowercase_extension(path);
  if (extension == ".msh") return mesh_io_detail::read_gmsh(path);
  if (extension == ".mesh") return mesh_io_detail::read_medit(path);
  if (extension == ".vtu") return mesh_io_detail::read_vtu(path);
  if (extension == ".vtk") return mesh_io_detail::read_vtk(path);
  const std::string base = path.substr(0, path.size() - extension.size());
  if (extension == ".node") return mesh_io_detail::read_tetgen(path, base + ".ele");
  if (extension == ".ele") return mesh_io_detail::read_tetgen(base + ".node", path);
  // The base name of a TetGen pair, which may itself hold a dot ("bunny.1").
  std::error_code error;
  if (std::filesystem::exists(path + ".node", error) ||
      (extension.empty() && !std::filesystem::exists(path, error)))
    return mesh_io_detail::read_tetgen(path + ".node", path + ".ele");
  throw InputError(detail::concat(
      path, ": unknown mesh format '", extension.empty() ? "(no extension)" : extension,
      "'; supported are .msh (Gmsh 2.2 and 4.1, ASCII), .mesh (MEDIT, ASCII), .vtu (VTK "
      "UnstructuredGrid, ascii arrays), .vtk (legacy VTK, ASCII) and .node/.ele (TetGen, or the "
      "base name of the pair)"));
}

}  // namespace

Mesh read_mesh(const std::string& path, MeshReadReport* report) {
  ReadResult result = read_by_format(path);
  if (report) {
    *report = MeshReadReport{};
    report->warnings = std::move(result.warnings);
  }
  result.mesh.source = path;
  mesh_io_detail::validate(result.mesh, result.origin, report);
  return std::move(result.mesh);
}

void validate_mesh(Mesh& mesh, const std::string& what, MeshReadReport* report) {
  mesh_io_detail::MeshOrigin origin;
  origin.name = what;
  mesh_io_detail::validate(mesh, origin, report);
}

}  // namespace descent
