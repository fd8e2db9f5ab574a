// MEDIT .mesh ASCII reader. Layout: keywords (any case), each followed by its
// value or by a count and that many records, one per line; `#` comments.
//   MeshVersionFormatted v      Dimension 3
//   Vertices    N, then N lines "x y z ref"
//   Tetrahedra  N, then N lines "a b c d ref" (1-based vertex numbers)
//   End
// Every other section (Triangles, Edges, Corners, Ridges, Normals, ...) is
// skipped line by line up to the next keyword, so its arity need not be known.
#include <algorithm>
#include <cctype>
#include <string_view>

#include "io/mesh_io_detail.hpp"

namespace descent::mesh_io_detail {

namespace {

bool is_keyword(std::string_view token) {
  return !token.empty() && std::isalpha(static_cast<unsigned char>(token[0]));
}

bool same_keyword(std::string_view a, std::string_view b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
           return std::tolower(static_cast<unsigned char>(x)) ==
                  std::tolower(static_cast<unsigned char>(y));
         });
}

class MeditReader {
 public:
  explicit MeditReader(const std::string& path)
      : text_(read_whole_file(path)), scanner_(text_, path, '#') {}

  ReadResult read() {
    bool more = scanner_.next_line();
    while (more) {
      const std::string_view keyword = scanner_.token("a keyword");
      if (!is_keyword(keyword))
        scanner_.fail(detail::concat("expected a keyword such as Vertices or Tetrahedra, found '",
                                     keyword,
                                     "' (does the count of the section above match its lines?)"));
      if (same_keyword(keyword, "End")) return finish();
      if (same_keyword(keyword, "Dimension")) {
        const std::int64_t dimension =
            scanner_.count_here_or_on_next_line("the dimension", 1 << 20);
        if (dimension != 3)
          scanner_.fail(detail::concat("the mesh has dimension ", dimension,
                                       "; only 3-dimensional meshes are supported"));
      } else if (same_keyword(keyword, "Vertices")) {
        read_vertices();
      } else if (same_keyword(keyword, "Tetrahedra")) {
        read_tets();
      } else {
        more = skip_to_next_keyword();
        continue;
      }
      more = scanner_.next_line();
    }
    scanner_.fail("the file ended without End (truncated file)");
  }

 private:
  void read_vertices() {
    if (vertices_line_ != 0)
      scanner_.fail(
          detail::concat("a second Vertices section (the first is on line ", vertices_line_, ")"));
    vertices_line_ = scanner_.line();
    const std::int64_t count =
        scanner_.count_here_or_on_next_line("the number of vertices", kMaxIndexCount);
    constexpr std::size_t kMinVertexBytes = 8;  // "0 0 0 0\n"
    result_.mesh.positions.reserve(3 * bounded_reserve(count, scanner_, kMinVertexBytes));
    for (std::int64_t i = 0; i < count; ++i) {
      next_record(scanner_, i, count, "vertices", "Vertices");
      read_vertex(scanner_, i + 1, result_.mesh.positions);  // the reference is dropped
    }
  }

  void read_tets() {
    if (vertices_line_ == 0) scanner_.fail("Tetrahedra comes before Vertices");
    if (tets_line_ != 0)
      scanner_.fail(
          detail::concat("a second Tetrahedra section (the first is on line ", tets_line_, ")"));
    tets_line_ = scanner_.line();
    const std::int64_t count =
        scanner_.count_here_or_on_next_line("the number of tets", kMaxIndexCount);
    if (count == 0) scanner_.fail("Tetrahedra declares 0 tets");
    constexpr std::size_t kMinTetBytes = 10;  // "1 2 3 4 0\n"
    const std::size_t reserved = bounded_reserve(count, scanner_, kMinTetBytes);
    result_.mesh.tets.reserve(4 * reserved);
    result_.origin.tet_lines.reserve(reserved);
    const std::int64_t num_vertices = result_.mesh.num_vertices();
    for (std::int64_t i = 0; i < count; ++i) {
      next_record(scanner_, i, count, "tets", "Tetrahedra");
      for (int k = 0; k < 4; ++k) {
        const std::int64_t vertex = scanner_.integer("a vertex number of the tet");
        if (vertex < 1 || vertex > num_vertices)
          scanner_.fail(detail::concat("tet ", i + 1, " refers to vertex ", vertex,
                                       ", but the file has ", num_vertices,
                                       " vertices (numbered from 1)"));
        result_.mesh.tets.push_back(static_cast<index_t>(vertex - 1));
      }
      result_.origin.tet_lines.push_back(scanner_.line());
    }
  }

  // Leaves the scanner on the next line that starts with a keyword; false at
  // the end of the file.
  bool skip_to_next_keyword() {
    while (scanner_.next_line())
      if (is_keyword(scanner_.peek_token())) return true;
    return false;
  }

  ReadResult finish() {
    if (tets_line_ == 0) scanner_.fail("the file has no Tetrahedra section");
    result_.origin.name = scanner_.path();
    result_.origin.first_vertex_number = 1;
    result_.origin.first_tet_number = 1;
    return std::move(result_);
  }

  std::string text_;
  LineScanner scanner_;
  ReadResult result_;
  std::int64_t vertices_line_ = 0;  // where each section started; 0 until then
  std::int64_t tets_line_ = 0;
};

}  // namespace

ReadResult read_medit(const std::string& path) { return MeditReader(path).read(); }

}  // namespace descent::mesh_io_detail
