// VTK XML UnstructuredGrid (.vtu) reader, ASCII data arrays (ParaView's and
// meshio's ascii output, SOFA's meshes). Layout read:
//   <VTKFile type="UnstructuredGrid" ...> <UnstructuredGrid>
//     <Piece NumberOfPoints="N" NumberOfCells="M">
//       <Points> <DataArray NumberOfComponents="3" format="ascii"> x y z ... </DataArray>
//       <Cells>  <DataArray Name="connectivity" ...> 0-based point ids of every cell
//                <DataArray Name="offsets" ...>      end of each cell in connectivity
//                <DataArray Name="types" ...>        VTK cell type of each cell
// Values may wrap lines freely. PointData, CellData and FieldData are
// skipped. Cells of type 10 (VTK_TETRA) are the mesh; lower-dimensional
// cells are skipped silently and other volume cells with a warning, as the
// Gmsh reader does. Binary and appended arrays (base64 or raw, perhaps
// compressed) and files of several pieces are refused by name.
#include <charconv>
#include <map>
#include <string_view>

#include "io/mesh_io_detail.hpp"

namespace descent::mesh_io_detail {

namespace {

bool is_blank(char c) { return c == ' ' || c == '\n' || c == '\t' || c == '\r'; }

class VtuReader {
 public:
  explicit VtuReader(const std::string& path) : path_(path), text_(read_whole_file(path)) {}

  ReadResult read() {
    const Tag file = open_tag("VTKFile", 0, text_.size());
    if (attribute(file, "type") != "UnstructuredGrid")
      fail_at(file.begin, detail::concat("a VTK file of type '", attribute(file, "type"),
                                         "'; only UnstructuredGrid (.vtu) holds tets"));
    const Tag piece = open_tag("Piece", file.end, text_.size());
    if (find_tag("Piece", piece.end, text_.size()) != std::string_view::npos)
      fail_at(piece.begin, "the file has several Pieces; only one is read (merge them first)");
    const std::int64_t num_points = count_attribute(piece, "NumberOfPoints");
    const std::int64_t num_cells = count_attribute(piece, "NumberOfCells");

    const Range points = element("Points", piece.end);
    const Tag coordinates = open_tag("DataArray", points.begin, points.end);
    if (attribute(coordinates, "NumberOfComponents") != "3")
      fail_at(coordinates.begin, "the Points DataArray must have NumberOfComponents=\"3\"");
    read_points(coordinates, num_points);

    const Range cells = element("Cells", piece.end);
    const std::vector<std::int64_t> offsets =
        integers(named_array("offsets", cells), num_cells, "offsets");
    const std::vector<std::int64_t> types =
        integers(named_array("types", cells), num_cells, "types");
    read_tets(named_array("connectivity", cells), offsets, types, num_points);

    if (result_.mesh.tets.empty())
      fail_at(cells.begin, "the Cells hold no tets (VTK type 10)" +
                               (skipped_.empty() ? "" : "; " + skipped_note()));
    if (!skipped_.empty()) result_.warnings.push_back(path_ + ": " + skipped_note());
    result_.origin.name = path_;
    return std::move(result_);
  }

 private:
  struct Tag {  // "<name attributes>": [begin, end) of the whole tag
    std::size_t begin = 0, end = 0;
    std::string_view attributes;
  };
  struct Range {  // an element's content, between its tags
    std::size_t begin = 0, end = 0;
  };

  // The 1-based line of text position `at`.
  std::int64_t line_at(std::size_t at) const {
    return 1 + std::count(text_.begin(), text_.begin() + static_cast<std::ptrdiff_t>(at), '\n');
  }
  [[noreturn]] void fail_at(std::size_t at, const std::string& message) const {
    throw InputError(detail::concat(path_, ":", line_at(at), ": ", message));
  }

  // Position of "<name" followed by a blank, '>' or '/', in [from, until).
  std::size_t find_tag(std::string_view name, std::size_t from, std::size_t until) const {
    std::string opening(1, '<');
    opening += name;
    for (std::size_t at = text_.find(opening, from); at != std::string::npos && at < until;
         at = text_.find(opening, at + 1)) {
      const char next = at + opening.size() < text_.size() ? text_[at + opening.size()] : '\0';
      if (is_blank(next) || next == '>' || next == '/') return at;
    }
    return std::string_view::npos;
  }

  Tag open_tag(std::string_view name, std::size_t from, std::size_t until) const {
    const std::size_t at = find_tag(name, from, until);
    if (at == std::string_view::npos)
      fail_at(from, detail::concat("expected a <", name, "> element (truncated file?)"));
    const std::size_t close = text_.find('>', at);
    if (close == std::string::npos) fail_at(at, detail::concat("<", name, " is never closed"));
    Tag tag;
    tag.begin = at;
    tag.end = close + 1;
    tag.attributes =
        std::string_view(text_).substr(at + 1 + name.size(), close - at - 1 - name.size());
    return tag;
  }

  // The content of the first <name> element after `from`.
  Range element(std::string_view name, std::size_t from) const {
    const Tag tag = open_tag(name, from, text_.size());
    std::string closing = "</";
    closing += name;
    closing += '>';
    const std::size_t end = text_.find(closing, tag.end);
    if (end == std::string::npos)
      fail_at(tag.begin, detail::concat("<", name, "> is never closed"));
    return {tag.end, end};
  }

  // The value of attribute `name` (double or single quotes); empty if absent.
  static std::string_view attribute(const Tag& tag, std::string_view name) {
    const std::string_view a = tag.attributes;
    for (std::size_t at = a.find(name); at != std::string_view::npos; at = a.find(name, at + 1)) {
      const bool starts = at == 0 || is_blank(a[at - 1]);
      std::size_t k = at + name.size();
      while (k < a.size() && a[k] == ' ') ++k;
      if (!starts || k >= a.size() || a[k] != '=') continue;
      ++k;
      while (k < a.size() && a[k] == ' ') ++k;
      if (k >= a.size() || (a[k] != '"' && a[k] != '\'')) continue;
      const std::size_t end = a.find(a[k], k + 1);
      if (end == std::string_view::npos) return {};
      return a.substr(k + 1, end - k - 1);
    }
    return {};
  }

  std::int64_t count_attribute(const Tag& tag, std::string_view name) const {
    const std::string_view value = attribute(tag, name);
    std::int64_t count = -1;
    const auto [end, error] = std::from_chars(value.data(), value.data() + value.size(), count);
    if (value.empty() || error != std::errc() || end != value.data() + value.size() || count < 0 ||
        count > kMaxIndexCount)
      fail_at(tag.begin, detail::concat("the Piece's ", name, " must be a count from 0 to ",
                                        kMaxIndexCount, ", found '", value, "'"));
    return count;
  }

  // The DataArray of <Cells> whose Name is `name`; its content must be ascii.
  Range named_array(std::string_view name, const Range& cells) const {
    for (std::size_t at = cells.begin;;) {
      const std::size_t found = find_tag("DataArray", at, cells.end);
      if (found == std::string_view::npos)
        fail_at(cells.begin, detail::concat("the Cells have no DataArray Name=\"", name, "\""));
      const Tag tag = open_tag("DataArray", found, cells.end);
      if (attribute(tag, "Name") == name) return ascii_content(tag);
      at = tag.end;
    }
  }

  Range ascii_content(const Tag& tag) const {
    const std::string_view format = attribute(tag, "format");
    if (format != "ascii")
      fail_at(tag.begin,
              detail::concat("a DataArray in format \"", format.empty() ? "(none)" : format,
                             "\"; only format=\"ascii\" is read (ParaView: Save Data, Data Mode "
                             "Ascii; meshio: write with binary=False)"));
    const std::size_t end = text_.find("</DataArray>", tag.end);
    if (end == std::string::npos) fail_at(tag.begin, "a <DataArray> is never closed");
    return {tag.end, end};
  }

  // Walks the numbers of an ascii DataArray, counting lines as it goes.
  class Numbers {
   public:
    Numbers(const VtuReader& reader, const Range& range)
        : reader_(reader), at_(range.begin), end_(range.end), line_(reader.line_at(range.begin)) {}

    // False at the end of the array.
    bool next() {
      while (at_ < end_ && is_blank(reader_.text_[at_])) {
        if (reader_.text_[at_] == '\n') ++line_;
        ++at_;
      }
      return at_ < end_;
    }
    template <class T>
    T value(std::string_view what) {
      const char* first = reader_.text_.data() + at_;
      const char* last = reader_.text_.data() + end_;
      const char* stop = first;
      while (stop < last && !is_blank(*stop)) ++stop;
      T v{};
      const auto [end, error] = std::from_chars(first, stop, v);
      if (error != std::errc() || end != stop)
        throw InputError(detail::concat(reader_.path_, ":", line_, ": expected ", what, ", found '",
                                        std::string_view(first, stop - first), "'"));
      at_ = static_cast<std::size_t>(stop - reader_.text_.data());
      return v;
    }
    std::int64_t line() const { return line_; }

   private:
    const VtuReader& reader_;
    std::size_t at_, end_;
    std::int64_t line_;
  };

  void read_points(const Tag& tag, std::int64_t num_points) {
    const Range content = ascii_content(tag);
    Numbers numbers(*this, content);
    std::vector<double>& positions = result_.mesh.positions;
    // No more than the text can hold ("0 0 0 "), whatever a corrupt count says.
    const std::size_t fits = (content.end - content.begin) / 6 + 1;
    positions.reserve(3 * std::min(static_cast<std::size_t>(num_points), fits));
    for (std::int64_t p = 0; p < num_points; ++p) {
      double x[3];
      for (double& c : x) {
        if (!numbers.next())
          fail_at(content.end,
                  detail::concat("the Points hold ", positions.size() / 3,
                                 " whole points; NumberOfPoints declares ", num_points));
        c = numbers.value<double>("a coordinate");
      }
      if (!std::isfinite(x[0]) || !std::isfinite(x[1]) || !std::isfinite(x[2]))
        throw InputError(detail::concat(path_, ":", numbers.line(), ": vertex ", p,
                                        " has a non-finite coordinate (", x[0], " ", x[1], " ",
                                        x[2], ")"));
      positions.insert(positions.end(), {x[0], x[1], x[2]});
    }
    if (numbers.next())
      fail_at(content.end, detail::concat("the Points hold more than the ", num_points,
                                          " points NumberOfPoints declares"));
  }

  std::vector<std::int64_t> integers(const Range& content, std::int64_t count,
                                     std::string_view name) const {
    Numbers numbers(*this, content);
    std::vector<std::int64_t> values;
    values.reserve(
        std::min(static_cast<std::size_t>(count), (content.end - content.begin) / 2 + 1));
    while (numbers.next()) {
      if (static_cast<std::int64_t>(values.size()) == count)
        fail_at(content.end, detail::concat("the ", name, " array holds more than the ", count,
                                            " values NumberOfCells declares"));
      values.push_back(numbers.value<std::int64_t>(detail::concat("an integer of ", name)));
    }
    if (static_cast<std::int64_t>(values.size()) != count)
      fail_at(content.end, detail::concat("the ", name, " array holds ", values.size(),
                                          " values; NumberOfCells declares ", count));
    return values;
  }

  void read_tets(const Range& content, const std::vector<std::int64_t>& offsets,
                 const std::vector<std::int64_t>& types, std::int64_t num_points) {
    Numbers numbers(*this, content);
    std::int64_t read = 0;  // connectivity entries read
    for (std::size_t cell = 0; cell < offsets.size(); ++cell) {
      const std::int64_t size = offsets[cell] - read;
      if (size < 0)
        fail_at(content.begin, detail::concat("offsets decrease at cell ", cell, " (",
                                              offsets[cell], " after ", read, ")"));
      const bool tet = types[cell] == kVtkTetraType;
      if (tet && size != 4)
        fail_at(content.begin,
                detail::concat("cell ", cell, " is a tet (type 10) with ", size, " points"));
      if (!tet && is_other_vtk_volume_type(types[cell])) ++skipped_[types[cell]];
      std::int64_t line = 0;
      for (std::int64_t k = 0; k < size; ++k) {
        if (!numbers.next())
          fail_at(content.end, detail::concat("the connectivity ends at entry ", read + k,
                                              "; the offsets reach ", offsets.back()));
        if (k == 0) line = numbers.line();
        const std::int64_t point = numbers.value<std::int64_t>("a point id of the connectivity");
        if (!tet) continue;
        if (point < 0 || point >= num_points)
          throw InputError(detail::concat(path_, ":", numbers.line(), ": tet (cell ", cell,
                                          ") refers to point ", point, ", but the file has ",
                                          num_points, " points (numbered from 0)"));
        result_.mesh.tets.push_back(static_cast<index_t>(point));
      }
      read += size;
      if (tet) {
        result_.origin.tet_numbers.push_back(static_cast<std::int64_t>(cell));
        result_.origin.tet_lines.push_back(line);
      }
    }
    if (numbers.next())
      fail_at(content.end, detail::concat("the connectivity holds more than the ", read,
                                          " entries the offsets reach"));
  }

  std::string skipped_note() const {
    return skipped_volume_note(skipped_, "cells of VTK", "linear tets (type 10)");
  }

  std::string path_;
  std::string text_;
  ReadResult result_;
  std::map<std::int64_t, std::int64_t> skipped_;  // volume cell type -> how many
};

}  // namespace

ReadResult read_vtu(const std::string& path) { return VtuReader(path).read(); }

}  // namespace descent::mesh_io_detail
