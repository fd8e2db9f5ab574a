// Legacy VTK (.vtk) reader, ASCII, DATASET UNSTRUCTURED_GRID (ParaView's,
// meshio's, SOFA's and TetGen's -k output). Layout read:
//   # vtk DataFile Version v      line 1
//   any title                     line 2
//   ASCII
//   DATASET UNSTRUCTURED_GRID
//   POINTS N type                 then 3N coordinates
//   CELLS M S                     before 5.0: M records "k i1 .. ik" (S numbers in all)
//   CELLS M+1 S, OFFSETS type, CONNECTIVITY type    5.0 and later: M + 1 offsets, S ids
//   CELL_TYPES M                  then M VTK cell types
// Values may wrap lines freely. FIELD blocks before POINTS and METADATA
// blocks are skipped; reading ends at CELL_TYPES, so POINT_DATA and
// CELL_DATA after it are never parsed. Cells as in the .vtu reader: type 10
// (VTK_TETRA) is the mesh, lower-dimensional cells are skipped silently and
// other volume cells with a warning. BINARY files and other datasets are
// refused by name.
#include <map>
#include <string_view>

#include "io/mesh_io_detail.hpp"

namespace descent::mesh_io_detail {

namespace {

class VtkReader {
 public:
  explicit VtkReader(const std::string& path)
      : text_(blank_title(read_whole_file(path), path)), scanner_(text_, path, '\0') {}

  ReadResult read() {
    expect_word("ASCII",
                "a legacy VTK file in ASCII (BINARY files are not read: ParaView's Save "
                "Data with File Type Ascii, or meshio with binary=False, writes one)");
    expect_word("DATASET", "DATASET UNSTRUCTURED_GRID");
    const std::string_view dataset = scanner_.token("the dataset type");
    if (dataset != "UNSTRUCTURED_GRID")
      scanner_.fail(detail::concat("DATASET ", dataset, "; only UNSTRUCTURED_GRID holds tets"));
    std::int64_t types_line = 0;
    while (types_line == 0) {
      const std::string_view keyword = word("a section keyword such as POINTS or CELLS");
      if (keyword == "POINTS") {
        read_points();
      } else if (keyword == "CELLS") {
        read_cells();
      } else if (keyword == "CELL_TYPES") {
        types_line = scanner_.line();
        read_types();
      } else if (keyword == "FIELD") {
        skip_field();
      } else if (keyword == "METADATA") {
        skip_metadata();
      } else {
        scanner_.fail(detail::concat("expected POINTS, CELLS or CELL_TYPES, found '", keyword,
                                     "' (does a count above match its values?)"));
      }
    }
    keep_tets();
    if (result_.mesh.tets.empty())
      scanner_.fail_at(types_line, "the cells hold no tets (VTK type 10)" +
                                       (skipped_.empty() ? "" : "; " + skipped_note()));
    if (!skipped_.empty()) result_.warnings.push_back(scanner_.path() + ": " + skipped_note());
    result_.origin.name = scanner_.path();
    return std::move(result_);
  }

 private:
  // The file with its title (line 2, free text, perhaps empty) blanked, so
  // that the scanner, which skips blank lines, keeps the file's line numbers.
  static std::string blank_title(std::string text, const std::string& path) {
    if (text.rfind("# vtk DataFile Version", 0) != 0)
      throw InputError(path +
                       ":1: not a legacy VTK file (it must start with "
                       "'# vtk DataFile Version')");
    const std::size_t first = text.find('\n');
    const std::size_t second = first == std::string::npos ? first : text.find('\n', first + 1);
    if (second == std::string::npos)
      throw InputError(path + ": the file ends within its header (truncated file)");
    for (std::size_t k = 0; k < second; ++k)
      if (text[k] != '\n') text[k] = ' ';
    return text;
  }

  // Moves to the next token, on this line or a later one.
  void word_is_next(std::string_view what) {
    while (!scanner_.has_token())
      if (!scanner_.next_line())
        scanner_.fail(
            detail::concat("the file ended where ", what, " was expected (truncated file)"));
  }
  std::string_view word(std::string_view what) {
    word_is_next(what);
    return scanner_.token(what);
  }
  std::int64_t integer(std::string_view what) {
    word_is_next(what);
    return scanner_.integer(what);
  }
  double real(std::string_view what) {
    word_is_next(what);
    return scanner_.real(what);
  }
  std::int64_t count(std::string_view what) {
    word_is_next(what);
    return scanner_.count(what, kMaxIndexCount);
  }
  void expect_word(std::string_view expected, std::string_view what) {
    const std::string_view found = word(what);
    if (found != expected)
      scanner_.fail(detail::concat("expected ", what, ", found '", found, "'"));
  }

  void read_points() {
    if (!result_.mesh.positions.empty()) scanner_.fail("a second POINTS section");
    const std::int64_t n = count("the number of points");
    word("the points' data type");
    constexpr std::size_t kMinPointBytes = 6;  // "0 0 0 "
    result_.mesh.positions.reserve(3 * bounded_reserve(n, scanner_, kMinPointBytes));
    for (std::int64_t p = 0; p < n; ++p) {
      const double x = real("an x coordinate"), y = real("a y coordinate"),
                   z = real("a z coordinate");
      if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z))
        scanner_.fail(
            detail::concat("point ", p, " has a non-finite coordinate (", x, " ", y, " ", z, ")"));
      result_.mesh.positions.insert(result_.mesh.positions.end(), {x, y, z});
    }
  }

  // Each cell's ids, and the line it starts on, as [offsets_[c], offsets_[c + 1]).
  void read_cells() {
    if (!offsets_.empty()) scanner_.fail("a second CELLS section");
    const std::int64_t first = count("the CELLS count");
    const std::int64_t size = count("the CELLS size");
    word_is_next("the cells");
    if (scanner_.peek_token() == "OFFSETS") {  // 5.0 and later: first = cells + 1
      word("OFFSETS");
      word("the offsets' data type");
      for (std::int64_t k = 0; k < first; ++k) {
        offsets_.push_back(integer("an offset"));
        cell_lines_.push_back(scanner_.line());
      }
      expect_word("CONNECTIVITY", "CONNECTIVITY after the offsets");
      word("the connectivity's data type");
      for (std::int64_t k = 0; k < size; ++k) ids_.push_back(integer("a point id"));
      if (offsets_.empty() || offsets_.front() != 0 || offsets_.back() != size)
        scanner_.fail(
            detail::concat("the OFFSETS must run from 0 to the CONNECTIVITY's ", size, " ids"));
      cell_lines_.pop_back();
      return;
    }
    offsets_.push_back(0);
    for (std::int64_t c = 0; c < first; ++c) {
      const std::int64_t k = integer("the number of points of a cell");
      cell_lines_.push_back(scanner_.line());
      if (k < 0 || static_cast<std::int64_t>(ids_.size()) + k + c + 1 > size)
        scanner_.fail(
            detail::concat("cell ", c, " has ", k, " points, beyond the CELLS size ", size));
      for (std::int64_t j = 0; j < k; ++j) ids_.push_back(integer("a point id"));
      offsets_.push_back(static_cast<std::int64_t>(ids_.size()));
    }
    if (static_cast<std::int64_t>(ids_.size()) + first != size)
      scanner_.fail(detail::concat("the cells hold ", ids_.size() + first,
                                   " numbers; CELLS declares ", size));
  }

  void read_types() {
    if (offsets_.empty()) scanner_.fail("CELL_TYPES comes before CELLS");
    const std::int64_t n = count("the number of cell types");
    if (n + 1 != static_cast<std::int64_t>(offsets_.size()))
      scanner_.fail(
          detail::concat("CELL_TYPES declares ", n, " cells; CELLS holds ", offsets_.size() - 1));
    for (std::int64_t c = 0; c < n; ++c) types_.push_back(integer("a cell type"));
  }

  void keep_tets() {
    const std::int64_t num_points = result_.mesh.num_vertices();
    for (std::size_t c = 0; c < types_.size(); ++c) {
      const std::int64_t begin = offsets_[c], end = offsets_[c + 1];
      if (end < begin)
        scanner_.fail_at(cell_lines_[c], detail::concat("the offsets decrease at cell ", c));
      if (types_[c] != kVtkTetraType) {
        if (is_other_vtk_volume_type(types_[c])) ++skipped_[types_[c]];
        continue;
      }
      if (end - begin != 4)
        scanner_.fail_at(cell_lines_[c], detail::concat("cell ", c, " is a tet (type 10) with ",
                                                        end - begin, " points"));
      for (std::int64_t k = begin; k < end; ++k) {
        if (ids_[k] < 0 || ids_[k] >= num_points)
          scanner_.fail_at(cell_lines_[c], detail::concat("tet (cell ", c, ") refers to point ",
                                                          ids_[k], ", but the file has ",
                                                          num_points, " points (numbered from 0)"));
        result_.mesh.tets.push_back(static_cast<index_t>(ids_[k]));
      }
      result_.origin.tet_numbers.push_back(static_cast<std::int64_t>(c));
      result_.origin.tet_lines.push_back(cell_lines_[c]);
    }
  }

  // FIELD name n, then n arrays "name components tuples type" and their
  // values (or a NULL_ARRAY).
  void skip_field() {
    word("the field's name");
    const std::int64_t arrays = count("the number of field arrays");
    for (std::int64_t a = 0; a < arrays; ++a) {
      if (word("a field array's name") == "NULL_ARRAY") continue;
      const std::int64_t components = count("its components"), tuples = count("its tuples");
      word("its data type");
      for (std::int64_t k = 0; k < components * tuples; ++k) word("a field value");
    }
  }

  // METADATA: information lines up to the next section keyword.
  void skip_metadata() {
    for (;;) {
      word_is_next("a section after METADATA");
      const std::string_view next = scanner_.peek_token();
      if (next == "CELLS" || next == "CELL_TYPES" || next == "POINTS") return;
      scanner_.token("metadata");
    }
  }

  std::string skipped_note() const {
    return skipped_volume_note(skipped_, "cells of VTK", "linear tets (type 10)");
  }

  std::string text_;
  LineScanner scanner_;
  ReadResult result_;
  std::vector<std::int64_t> offsets_, ids_, types_;
  std::vector<std::int64_t> cell_lines_;          // the line each cell starts on
  std::map<std::int64_t, std::int64_t> skipped_;  // volume cell type -> how many
};

}  // namespace

ReadResult read_vtk(const std::string& path) { return VtkReader(path).read(); }

}  // namespace descent::mesh_io_detail
