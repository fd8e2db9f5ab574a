// Gmsh .msh ASCII reader, versions 2.2 and 4.1. Layout read here:
//   $MeshFormat  version file-type(0 = ASCII) data-size  $EndMeshFormat
//   2.2 $Nodes:    N, then N lines "tag x y z"
//   2.2 $Elements: N, then N lines "tag type num-tags <tags> <node tags>"
//   4.1 $Nodes:    "blocks N min-tag max-tag"; per block "dim entity parametric n",
//                  then n lines of one tag, then n lines "x y z [u v w]"
//   4.1 $Elements: "blocks N min-tag max-tag"; per block "dim entity type n",
//                  then n lines "tag <node tags>"
// Only type 4 (4-node tet) is kept. Node tags may be sparse and in any order;
// they map to dense 0-based vertex indices in file order. Any other section
// ($PhysicalNames, $Entities, IPC's $Surface, ...) is skipped to its $End line.
#include <algorithm>
#include <map>
#include <optional>
#include <string_view>
#include <utility>

#include "io/mesh_io_detail.hpp"

namespace descent::mesh_io_detail {

namespace {

constexpr std::int64_t kTet4 = 4;

// Gmsh types of volume elements other than the 4-node tet, which are worth a
// warning when skipped: hexahedra, prisms, pyramids and higher-order tets.
bool is_other_volume_type(std::int64_t type) {
  constexpr std::int64_t kTypes[] = {5, 6, 7, 11, 12, 13, 14, 17, 18, 19, 29, 30, 31};
  return std::find(std::begin(kTypes), std::end(kTypes), type) != std::end(kTypes);
}

// Node tag -> 0-based vertex index. Tags within a few times the node count of
// each other use a dense table; scattered tags a sorted list.
class NodeTagMap {
 public:
  // `lines` are the lines the tags were read on, to name both of a duplicate.
  NodeTagMap(const std::vector<std::int64_t>& tags, const std::vector<std::int64_t>& lines,
             const LineScanner& scanner) {
    if (tags.empty()) return;
    const auto [min, max] = std::minmax_element(tags.begin(), tags.end());
    min_tag_ = *min;
    max_tag_ = *max;
    const auto duplicate = [&](index_t first, index_t second) {
      scanner.fail_at(lines[second], detail::concat("node tag ", tags[second],
                                                    " appears twice in $Nodes (first on line ",
                                                    lines[first], ")"));
    };
    const std::uint64_t span = static_cast<std::uint64_t>(max_tag_) - min_tag_;
    if (span < 4 * tags.size() + 1024) {
      dense_.assign(span + 1, -1);
      for (index_t v = 0; v < static_cast<index_t>(tags.size()); ++v) {
        index_t& slot = dense_[tags[v] - min_tag_];
        if (slot >= 0) duplicate(slot, v);
        slot = v;
      }
    } else {
      sorted_.reserve(tags.size());
      for (index_t v = 0; v < static_cast<index_t>(tags.size()); ++v)
        sorted_.emplace_back(tags[v], v);
      std::sort(sorted_.begin(), sorted_.end());
      for (std::size_t i = 1; i < sorted_.size(); ++i)
        if (sorted_[i].first == sorted_[i - 1].first)
          duplicate(sorted_[i - 1].second, sorted_[i].second);  // in file order
    }
  }

  // -1 when no node has this tag.
  index_t find(std::int64_t tag) const {
    if (tag < min_tag_ || tag > max_tag_) return -1;
    if (!dense_.empty()) return dense_[tag - min_tag_];
    const auto it =
        std::lower_bound(sorted_.begin(), sorted_.end(), std::make_pair(tag, index_t{0}));
    return it != sorted_.end() && it->first == tag ? it->second : -1;
  }

  std::int64_t min_tag() const { return min_tag_; }
  std::int64_t max_tag() const { return max_tag_; }

 private:
  std::int64_t min_tag_ = 0;
  std::int64_t max_tag_ = -1;
  std::vector<index_t> dense_;                            // by tag - min_tag_
  std::vector<std::pair<std::int64_t, index_t>> sorted_;  // (tag, index) by tag
};

class GmshReader {
 public:
  explicit GmshReader(const std::string& path)
      : text_(read_whole_file(path)), scanner_(text_, path, '\0') {}

  ReadResult read() {
    read_format();
    std::int64_t elements_line = 0;
    while (scanner_.next_line()) {
      const std::string_view name = scanner_.token("a section name");
      if (name == "$Nodes") {
        if (node_map_) scanner_.fail("a second $Nodes section; only one is supported");
        is_v2_ ? read_nodes_v2() : read_nodes_v41();
        node_map_.emplace(result_.origin.vertex_numbers, node_lines_, scanner_);
        node_lines_ = {};
      } else if (name == "$Elements") {
        if (!node_map_) scanner_.fail("$Elements comes before $Nodes");
        if (elements_line != 0) scanner_.fail("a second $Elements section; only one is supported");
        elements_line = scanner_.line();
        is_v2_ ? read_elements_v2() : read_elements_v41();
      } else if (name.starts_with('$')) {
        skip_section(name);
      } else {
        scanner_.fail(
            detail::concat("expected a section such as $Nodes or $Elements, found '", name, "'"));
      }
    }
    if (!node_map_) scanner_.fail("the file has no $Nodes section (truncated file?)");
    if (elements_line == 0) scanner_.fail("the file has no $Elements section (truncated file?)");
    if (result_.mesh.tets.empty())
      scanner_.fail_at(elements_line,
                       "$Elements holds no 4-node tets (type 4)" +
                           (skipped_volume_types_.empty() ? "" : "; " + skipped_note()));
    if (!skipped_volume_types_.empty())
      result_.warnings.push_back(scanner_.path() + ": " + skipped_note());
    result_.origin.name = scanner_.path();
    return std::move(result_);
  }

 private:
  void read_format() {
    if (!scanner_.next_line() || scanner_.token("$MeshFormat") != "$MeshFormat")
      scanner_.fail("expected $MeshFormat first: not a Gmsh .msh file");
    if (!scanner_.next_line()) scanner_.fail("expected the format line after $MeshFormat");
    const std::string_view version = scanner_.token("the format version");
    const std::int64_t file_type = scanner_.integer("the file type");
    if (file_type != 0)
      scanner_.fail(
          "binary .msh files are not supported; save the mesh as ASCII (e.g. "
          "`gmsh in.msh -save -format msh41 -o out.msh`)");
    is_v2_ = version == "2" || version.starts_with("2.");
    if (!is_v2_ && version != "4.1")
      scanner_.fail(detail::concat("Gmsh format version ", version,
                                   " is not supported; supported are 2.2 and 4.1 (ASCII)"));
    expect_end("$EndMeshFormat", "after the format line");
  }

  void read_nodes_v2() {
    start_section("$Nodes");
    const std::int64_t count = scanner_.count("the number of nodes", kMaxIndexCount);
    reserve_nodes(count);
    for (std::int64_t i = 0; i < count; ++i) {
      next_record(scanner_, i, count, "nodes", "$Nodes");
      add_node_tag(scanner_.integer("a node tag"));
      read_vertex(scanner_, result_.origin.vertex_numbers.back(), result_.mesh.positions);
    }
    expect_end("$EndNodes", detail::concat("after the ", count, " nodes that $Nodes declares"));
  }

  void read_nodes_v41() {
    start_section("$Nodes");
    const std::int64_t blocks = scanner_.count("the number of node blocks", INT64_MAX);
    const std::int64_t count = scanner_.count("the number of nodes", kMaxIndexCount);
    reserve_nodes(count);
    std::vector<std::int64_t>& tags = result_.origin.vertex_numbers;
    for (std::int64_t block = 0; block < blocks; ++block) {
      const std::int64_t done = static_cast<std::int64_t>(tags.size());
      next_record(scanner_, block, blocks, "node blocks", "$Nodes");
      scanner_.integer("the entity dimension");
      scanner_.integer("the entity tag");
      scanner_.integer("the parametric flag");
      const std::int64_t in_block =
          scanner_.count("the number of nodes in the block", count - done);
      for (std::int64_t i = 0; i < in_block; ++i) {
        next_record(scanner_, done + i, count, "nodes", "$Nodes");
        add_node_tag(scanner_.integer("a node tag"));
      }
      // Parametric coordinates, if any, follow x y z on the line and are dropped.
      for (std::int64_t i = 0; i < in_block; ++i) {
        next_record(scanner_, done + i, count, "node coordinates", "$Nodes");
        read_vertex(scanner_, tags[done + i], result_.mesh.positions);
      }
    }
    if (static_cast<std::int64_t>(tags.size()) != count)
      scanner_.fail(detail::concat("the node blocks hold ", tags.size(),
                                   " nodes, but $Nodes declares ", count));
    expect_end("$EndNodes",
               detail::concat("after the ", blocks, " node blocks that $Nodes declares"));
  }

  void read_elements_v2() {
    start_section("$Elements");
    const std::int64_t count = scanner_.count("the number of elements", INT64_MAX);
    reserve_tets(count);
    for (std::int64_t i = 0; i < count; ++i) {
      next_record(scanner_, i, count, "elements", "$Elements");
      const std::int64_t tag = scanner_.integer("an element number");
      const std::int64_t type = scanner_.integer("an element type");
      if (type != kTet4) {
        note_skipped(type);
        continue;
      }
      const std::int64_t num_tags = scanner_.count("the number of tags", 1024);
      for (std::int64_t k = 0; k < num_tags; ++k) scanner_.integer("a tag");
      add_tet(tag);
    }
    expect_end("$EndElements",
               detail::concat("after the ", count, " elements that $Elements declares"));
  }

  void read_elements_v41() {
    start_section("$Elements");
    const std::int64_t blocks = scanner_.count("the number of element blocks", INT64_MAX);
    const std::int64_t count = scanner_.count("the number of elements", INT64_MAX);
    std::int64_t done = 0;
    for (std::int64_t block = 0; block < blocks; ++block) {
      next_record(scanner_, block, blocks, "element blocks", "$Elements");
      scanner_.integer("the entity dimension");
      scanner_.integer("the entity tag");
      const std::int64_t type = scanner_.integer("the element type");
      const std::int64_t in_block =
          scanner_.count("the number of elements in the block", count - done);
      if (type == kTet4) reserve_tets(in_block);
      for (std::int64_t i = 0; i < in_block; ++i, ++done) {
        next_record(scanner_, done, count, "elements", "$Elements");
        const std::int64_t tag = scanner_.integer("an element tag");
        if (type == kTet4) add_tet(tag);
      }
      if (type != kTet4) note_skipped(type, in_block);
    }
    if (done != count)
      scanner_.fail(detail::concat("the element blocks hold ", done,
                                   " elements, but $Elements declares ", count));
    expect_end("$EndElements",
               detail::concat("after the ", blocks, " element blocks that $Elements declares"));
  }

  // Reads the 4 node tags of the tet numbered `tag` from the current line.
  void add_tet(std::int64_t tag) {
    if (result_.mesh.tets.size() / 4 >= static_cast<std::size_t>(kMaxIndexCount))
      scanner_.fail(detail::concat("more than ", kMaxIndexCount, " tets; indices are 32-bit"));
    for (int k = 0; k < 4; ++k) {
      const std::int64_t node = scanner_.integer("a node tag of the tet");
      const index_t v = node_map_->find(node);
      if (v < 0)
        scanner_.fail(detail::concat("tet ", tag, " refers to node ", node,
                                     ", which $Nodes does not define (the file has ",
                                     result_.mesh.num_vertices(), " nodes, tags ",
                                     node_map_->min_tag(), " to ", node_map_->max_tag(), ")"));
      result_.mesh.tets.push_back(v);
    }
    result_.origin.tet_numbers.push_back(tag);
    result_.origin.tet_lines.push_back(scanner_.line());
  }

  void add_node_tag(std::int64_t tag) {
    result_.origin.vertex_numbers.push_back(tag);
    node_lines_.push_back(scanner_.line());
  }

  void reserve_nodes(std::int64_t count) {
    constexpr std::size_t kMinNodeBytes = 8;  // "1 0 0 0\n"
    const std::size_t n = bounded_reserve(count, scanner_, kMinNodeBytes);
    result_.mesh.positions.reserve(3 * n);
    result_.origin.vertex_numbers.reserve(n);
    node_lines_.reserve(n);
  }

  void reserve_tets(std::int64_t count) {
    constexpr std::size_t kMinTetBytes = 10;  // "1 1 2 3 4\n"
    const std::size_t n =
        result_.origin.tet_numbers.size() + bounded_reserve(count, scanner_, kMinTetBytes);
    result_.mesh.tets.reserve(4 * n);
    result_.origin.tet_numbers.reserve(n);
    result_.origin.tet_lines.reserve(n);
  }

  void note_skipped(std::int64_t type, std::int64_t how_many = 1) {
    if (is_other_volume_type(type)) skipped_volume_types_[type] += how_many;
  }

  std::string skipped_note() const {
    return skipped_volume_note(skipped_volume_types_, "elements of Gmsh", "4-node tets (type 4)");
  }

  // The line after a section name holds its header.
  void start_section(std::string_view name) {
    if (!scanner_.next_line())
      scanner_.fail(detail::concat("the file ended right after ", name, " (truncated file)"));
  }

  void expect_end(std::string_view end, const std::string& where) {
    if (!scanner_.next_line())
      scanner_.fail(
          detail::concat("expected ", end, " ", where, ", but the file ended (truncated file)"));
    const std::string_view found = scanner_.token(end);
    if (found != end)
      scanner_.fail(detail::concat("expected ", end, " ", where, ", found '", found, "'"));
  }

  void skip_section(std::string_view name) {
    const std::int64_t start = scanner_.line();
    const std::string end = detail::concat("$End", name.substr(1));
    while (scanner_.next_line())
      if (scanner_.token(end) == end) return;
    scanner_.fail(
        detail::concat("section ", name, " (line ", start, ") has no ", end, " (truncated file)"));
  }

  std::string text_;
  LineScanner scanner_;
  bool is_v2_ = false;
  ReadResult result_;
  std::vector<std::int64_t> node_lines_;  // line of each node's tag, until the tag map is built
  std::optional<NodeTagMap> node_map_;
  std::map<std::int64_t, std::int64_t> skipped_volume_types_;  // type -> count
};

}  // namespace

ReadResult read_gmsh(const std::string& path) { return GmshReader(path).read(); }

}  // namespace descent::mesh_io_detail
