// Mesh writers: MEDIT .mesh, Gmsh 2.2 ASCII .msh, TetGen .node + .ele. All
// number vertices and tets from 1, and write coordinates as %.17g, which
// reads back to the same double.
#include <cerrno>
#include <charconv>
#include <cstdio>
#include <cstring>
#include <string_view>
#include <utility>

#include "io/mesh_io_detail.hpp"

namespace descent {

namespace {

// Buffered text output to one file; every failure is an InputError naming it.
class TextFile {
 public:
  explicit TextFile(std::string path)
      : path_(std::move(path)), file_(std::fopen(path_.c_str(), "wb")) {
    if (!file_) fail();
    buffer_.reserve(kFlushBytes + kMaxItemBytes);
  }
  ~TextFile() {
    if (file_) std::fclose(file_);
  }
  TextFile(const TextFile&) = delete;
  TextFile& operator=(const TextFile&) = delete;

  TextFile& operator<<(std::string_view text) {
    buffer_ += text;
    flush_if_full();
    return *this;
  }
  TextFile& operator<<(std::int64_t value) {
    char digits[kMaxItemBytes];
    const auto end = std::to_chars(digits, digits + sizeof digits, value).ptr;
    return *this << std::string_view(digits, end - digits);
  }
  TextFile& operator<<(double value) {
    char digits[kMaxItemBytes];
    const auto end =
        std::to_chars(digits, digits + sizeof digits, value, std::chars_format::general, 17).ptr;
    return *this << std::string_view(digits, end - digits);
  }

  // Writes what is buffered and closes; a failure here (disk full) is reported.
  void close() {
    flush();
    std::FILE* file = std::exchange(file_, nullptr);
    if (std::fclose(file) != 0) fail();
  }

 private:
  static constexpr std::size_t kFlushBytes = 1 << 20;
  static constexpr std::size_t kMaxItemBytes = 32;  // "-1.2345678901234567e-308" fits

  void flush_if_full() {
    if (buffer_.size() >= kFlushBytes) flush();
  }
  void flush() {
    if (std::fwrite(buffer_.data(), 1, buffer_.size(), file_) != buffer_.size()) fail();
    buffer_.clear();
  }
  [[noreturn]] void fail() const {
    throw InputError(detail::concat(path_, ": cannot write: ", std::strerror(errno)));
  }

  std::string path_;
  std::FILE* file_;
  std::string buffer_;
};

void write_vertex_lines(const Mesh& mesh, TextFile& out, bool with_number, bool with_reference) {
  for (index_t v = 0; v < mesh.num_vertices(); ++v) {
    const double* x = &mesh.positions[3 * static_cast<std::size_t>(v)];
    if (with_number) out << std::int64_t{v + 1} << " ";
    out << x[0] << " " << x[1] << " " << x[2] << (with_reference ? " 0\n" : "\n");
  }
}

// Each tet line: [number] [`prefix`] a b c d [" 0" reference], 1-based.
void write_tet_lines(const Mesh& mesh, TextFile& out, bool with_number, std::string_view prefix,
                     bool with_reference) {
  for (index_t t = 0; t < mesh.num_tets(); ++t) {
    const index_t* v = &mesh.tets[4 * static_cast<std::size_t>(t)];
    if (with_number) out << std::int64_t{t + 1} << " ";
    out << prefix;
    for (int k = 0; k < 4; ++k) out << std::int64_t{v[k] + 1} << (k < 3 ? " " : "");
    out << (with_reference ? " 0\n" : "\n");
  }
}

void write_medit(const Mesh& mesh, const std::string& path) {
  TextFile out(path);
  // Version 2: coordinates in double precision.
  out << "MeshVersionFormatted 2\nDimension 3\nVertices\n"
      << std::int64_t{mesh.num_vertices()} << "\n";
  write_vertex_lines(mesh, out, false, true);
  out << "Tetrahedra\n" << std::int64_t{mesh.num_tets()} << "\n";
  write_tet_lines(mesh, out, false, "", true);
  out << "End\n";
  out.close();
}

void write_gmsh22(const Mesh& mesh, const std::string& path) {
  TextFile out(path);
  out << "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n"
      << std::int64_t{mesh.num_vertices()} << "\n";
  write_vertex_lines(mesh, out, true, false);
  out << "$EndNodes\n$Elements\n" << std::int64_t{mesh.num_tets()} << "\n";
  // Type 4 (4-node tet), 2 tags: physical group 0, elementary entity 1.
  write_tet_lines(mesh, out, true, "4 2 0 1 ", false);
  out << "$EndElements\n";
  out.close();
}

void write_tetgen(const Mesh& mesh, const std::string& node_path, const std::string& ele_path) {
  TextFile nodes(node_path);
  nodes << std::int64_t{mesh.num_vertices()} << " 3 0 0\n";
  write_vertex_lines(mesh, nodes, true, false);
  nodes.close();
  TextFile tets(ele_path);
  tets << std::int64_t{mesh.num_tets()} << " 4 0\n";
  write_tet_lines(mesh, tets, true, "", false);
  tets.close();
}

}  // namespace

void write_mesh(const Mesh& mesh, const std::string& path) {
  const std::string extension = mesh_io_detail::lowercase_extension(path);
  if (extension == ".mesh") return write_medit(mesh, path);
  if (extension == ".msh") return write_gmsh22(mesh, path);
  if (extension == ".node")
    return write_tetgen(mesh, path, path.substr(0, path.size() - extension.size()) + ".ele");
  throw InputError(detail::concat(path, ": cannot write mesh format '", extension,
                                  "'; supported are .mesh (MEDIT), .msh (Gmsh 2.2 ASCII) and "
                                  ".node (TetGen .node + .ele)"));
}

}  // namespace descent
