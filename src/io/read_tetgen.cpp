// TetGen .node/.ele reader. Layout, with `#` comments anywhere:
//   .node: "N dim nattr nbound", then N lines "id x y z [attributes] [marker]"
//   .ele:  "T corners nattr",    then T lines "id a b c d [more corners] [attribute]"
// Node ids are consecutive from the first one, 0 or 1, which sets the base of
// the .ele's node references. 10-node tets keep their first 4 corners.
#include "io/mesh_io_detail.hpp"

namespace descent::mesh_io_detail {

namespace {

void expect_end_of_file(LineScanner& scanner, std::int64_t count, const char* records) {
  if (scanner.next_line())
    scanner.fail(detail::concat("unexpected data after the ", count, " ", records,
                                " that the header declares"));
}

// Reads the .node file into `result` and returns the number of the first node.
std::int64_t read_nodes(const std::string& path, ReadResult& result) {
  const std::string text = read_whole_file(path);
  LineScanner scanner(text, path, '#');
  if (!scanner.next_line())
    scanner.fail("expected the header 'N dim nattr nbound'; the file is empty");
  const std::int64_t count = scanner.count("the number of nodes", kMaxIndexCount);
  if (scanner.has_token()) {
    const std::int64_t dimension = scanner.integer("the dimension");
    if (dimension != 3)
      scanner.fail(detail::concat("the nodes have dimension ", dimension,
                                  "; only 3-dimensional meshes are supported"));
  }
  constexpr std::size_t kMinNodeBytes = 8;  // "1 0 0 0\n"
  result.mesh.positions.reserve(3 * bounded_reserve(count, scanner, kMinNodeBytes));
  std::int64_t first = 0;
  for (std::int64_t i = 0; i < count; ++i) {
    next_record(scanner, i, count, "nodes", "the header");
    const std::int64_t id = scanner.integer("a node id");
    if (i == 0) {
      if (id != 0 && id != 1)
        scanner.fail(
            detail::concat("the first node id is ", id, "; TetGen numbers nodes from 0 or 1"));
      first = id;
    } else if (id != first + i) {
      scanner.fail(detail::concat("node id ", id, " is out of sequence; expected ", first + i));
    }
    read_vertex(scanner, id, result.mesh.positions);  // attributes and marker are dropped
  }
  expect_end_of_file(scanner, count, "nodes");
  return first;
}

void read_tets(const std::string& path, std::int64_t first_node, ReadResult& result) {
  const std::string text = read_whole_file(path);
  LineScanner scanner(text, path, '#');
  if (!scanner.next_line())
    scanner.fail("expected the header 'T corners nattr'; the file is empty");
  const std::int64_t count = scanner.count("the number of tets", kMaxIndexCount);
  if (count == 0) scanner.fail("the header declares 0 tets");
  if (scanner.has_token()) {
    const std::int64_t corners = scanner.integer("the number of nodes per tet");
    if (corners != 4 && corners != 10)
      scanner.fail(detail::concat("tets have ", corners, " nodes; supported are 4 and 10"));
  }
  constexpr std::size_t kMinTetBytes = 10;  // "1 1 2 3 4\n"
  const std::size_t reserved = bounded_reserve(count, scanner, kMinTetBytes);
  result.mesh.tets.reserve(4 * reserved);
  result.origin.tet_numbers.reserve(reserved);
  result.origin.tet_lines.reserve(reserved);
  const std::int64_t num_nodes = result.mesh.num_vertices();
  for (std::int64_t i = 0; i < count; ++i) {
    next_record(scanner, i, count, "tets", "the header");
    const std::int64_t id = scanner.integer("a tet id");
    for (int k = 0; k < 4; ++k) {
      const std::int64_t node = scanner.integer("a node id of the tet");
      if (node < first_node || node - first_node >= num_nodes)
        scanner.fail(detail::concat("tet ", id, " refers to node ", node,
                                    ", but the .node file has ", num_nodes,
                                    " nodes (numbered from ", first_node, ")"));
      result.mesh.tets.push_back(static_cast<index_t>(node - first_node));
    }
    result.origin.tet_numbers.push_back(id);
    result.origin.tet_lines.push_back(scanner.line());
  }
  expect_end_of_file(scanner, count, "tets");
}

}  // namespace

ReadResult read_tetgen(const std::string& node_path, const std::string& ele_path) {
  ReadResult result;
  result.origin.first_vertex_number = read_nodes(node_path, result);
  read_tets(ele_path, result.origin.first_vertex_number, result);
  result.origin.name = ele_path;
  return result;
}

}  // namespace descent::mesh_io_detail
