// Mesh readers, writers and validation: small hand-written files in every
// format, each kind of bad input, writer round trips, and the real meshes of
// DESCENT_SHARED_MESHES when present.
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "common/error.hpp"
#include "io/mesh_io.hpp"

namespace descent {
namespace {

namespace fs = std::filesystem;

// The text of a file whose line k is all[k - 1].
std::string join(const std::vector<std::string>& all) {
  std::string text;
  for (const std::string& line : all) (text += line) += '\n';
  return text;
}

double signed_volume(const Mesh& mesh, index_t t) {
  const double* x[4];
  for (int k = 0; k < 4; ++k) x[k] = &mesh.positions[3 * mesh.tets[4 * t + k]];
  double e[3][3];
  for (int k = 0; k < 3; ++k)
    for (int d = 0; d < 3; ++d) e[k][d] = x[k + 1][d] - x[0][d];
  return (e[0][0] * (e[1][1] * e[2][2] - e[1][2] * e[2][1]) -
          e[0][1] * (e[1][0] * e[2][2] - e[1][2] * e[2][0]) +
          e[0][2] * (e[1][0] * e[2][1] - e[1][1] * e[2][0])) /
         6;
}

double total_volume(const Mesh& mesh) {
  double volume = 0;
  for (index_t t = 0; t < mesh.num_tets(); ++t) volume += signed_volume(mesh, t);
  return volume;
}

// The mesh every small file below describes: the unit corner tet 1 2 3 4 and
// its neighbour 2 3 4 5 across the face 2 3 4, both positively oriented.
const std::vector<double> kTwoTetPositions = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 1};
const std::vector<index_t> kTwoTets = {0, 1, 2, 3, 1, 2, 3, 4};

// The two-tet mesh's nodes as a 1-based TetGen .node file.
const std::string kTetgenNodes = "5 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n5 1 1 1\n";

Mesh two_tet_mesh() {
  Mesh mesh;
  mesh.positions = kTwoTetPositions;
  mesh.tets = kTwoTets;
  return mesh;
}

// MEDIT text of the two-tet mesh with comments and skipped sections; tests
// replace single lines to make bad inputs (line numbers as in the comments).
std::vector<std::string> medit_lines() {
  return {
      "# a comment line",        // 1
      "meshversionformatted 2",  // 2
      "DIMENSION",               // 3
      "3",                       // 4
      "Vertices",                // 5
      "5",                       // 6
      "0 0 0 1",                 // 7
      "1 0 0 1  # trailing",     // 8
      "0 1 0 1",                 // 9
      "0 0 1 1",                 // 10
      "1 1 1 1",                 // 11
      "Edges",                   // 12
      "1",                       // 13
      "1 2 0",                   // 14
      "Corners 2",               // 15
      "1",                       // 16
      "2",                       // 17
      "Triangles",               // 18
      "1",                       // 19
      "1 2 3 0",                 // 20
      "Normals",                 // 21
      "1",                       // 22
      "0 0 1",                   // 23
      "Tetrahedra",              // 24
      "2",                       // 25
      "1 2 3 4 0",               // 26
      "2 3 4 5 0",               // 27
      "End",                     // 28
  };
}

// Gmsh 2.2 text of the two-tet mesh with sparse node tags 10..50, physical
// names, a point and a triangle element.
std::vector<std::string> gmsh22_lines() {
  return {
      "$MeshFormat",            // 1
      "2.2 0 8",                // 2
      "$EndMeshFormat",         // 3
      "$PhysicalNames",         // 4
      "1",                      // 5
      "3 1 \"body part\"",      // 6
      "$EndPhysicalNames",      // 7
      "$Nodes",                 // 8
      "5",                      // 9
      "10 0 0 0",               // 10
      "20 1 0 0",               // 11
      "30 0 1 0",               // 12
      "40 0 0 1",               // 13
      "50 1 1 1",               // 14
      "$EndNodes",              // 15
      "$Elements",              // 16
      "4",                      // 17
      "1 15 2 0 1 10",          // 18
      "2 2 2 0 1 10 20 30",     // 19
      "7 4 2 0 1 10 20 30 40",  // 20
      "9 4 2 0 1 20 30 40 50",  // 21
      "$EndElements",           // 22
  };
}

class MeshIoTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           (std::string("descent_mesh_io_") + info->name() + "_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string path(const std::string& name) const { return (dir_ / name).string(); }

  std::string write(const std::string& name, const std::string& text) const {
    std::ofstream(path(name), std::ios::binary) << text;
    return path(name);
  }

  // The message of the InputError that reading `name` throws, after checking
  // it names the file and the line ("name:line:").
  std::string read_error(const std::string& name, int line) const {
    try {
      read_mesh(path(name));
    } catch (const InputError& error) {
      const std::string message = error.what();
      EXPECT_NE(message.find(name + ":" + std::to_string(line) + ":"), std::string::npos)
          << message;
      return message;
    }
    ADD_FAILURE() << "no InputError reading " << name;
    return {};
  }

  fs::path dir_;
};

#define EXPECT_CONTAINS(text, part) \
  EXPECT_NE(std::string(text).find(part), std::string::npos) << "'" << (text) << "'"

// ---------------------------------------------------------------- reading

TEST_F(MeshIoTest, ReadsGmsh22WithSparseTagsAndSkippedElements) {
  MeshReadReport report;
  const Mesh mesh = read_mesh(write("two.msh", join(gmsh22_lines())), &report);
  EXPECT_EQ(mesh.positions, kTwoTetPositions);
  EXPECT_EQ(mesh.tets, kTwoTets);
  EXPECT_EQ(mesh.source, path("two.msh"));
  EXPECT_EQ(report.reoriented_tets, 0);
  EXPECT_EQ(report.unreferenced_vertices, 0);
  EXPECT_TRUE(report.warnings.empty());
}

// Two node blocks (the second on a surface, with parametric u v after x y z),
// a triangle block before the tet block, and $Entities and IPC's $Surface to skip.
TEST_F(MeshIoTest, ReadsGmsh41WithBlocksParametricNodesAndUnknownSections) {
  const char* text = R"($MeshFormat
4.1 0 8
$EndMeshFormat
$Entities
0 0 0 1
1 0 0 0 1 1 1 0 0
$EndEntities
$Nodes
2 5 3 105
3 1 0 2
105
3
1 1 1
0 0 0
2 1 1 3
7
9
4
1 0 0 0.5 0.5
0 1 0 0.1 0.2
0 0 1 0.3 0.4
$EndNodes
$Elements
2 3 11 30
2 1 2 1
30 3 7 9
3 1 4 2
11 3 7 9 4
20 7 9 4 105
$EndElements
$Surface
1
3 7 9
$EndSurface
)";
  const Mesh mesh = read_mesh(write("blocks.msh", text));
  EXPECT_EQ(mesh.positions, (std::vector<double>{1, 1, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1}));
  EXPECT_EQ(mesh.tets, (std::vector<index_t>{1, 2, 3, 4, 2, 3, 4, 0}));
}

// Tags too far apart for a dense table.
TEST_F(MeshIoTest, ReadsGmshWithScatteredNodeTags) {
  const char* text = R"($MeshFormat
2.2 0 8
$EndMeshFormat
$Nodes
5
1000000000000 0 0 0
5 1 0 0
7 0 1 0
3 0 0 1
1 1 1 1
$EndNodes
$Elements
2
1 4 0 1000000000000 5 7 3
2 4 0 5 7 3 1
$EndElements
)";
  const Mesh mesh = read_mesh(write("scattered.msh", text));
  EXPECT_EQ(mesh.positions, kTwoTetPositions);
  EXPECT_EQ(mesh.tets, kTwoTets);
}

TEST_F(MeshIoTest, ReadsMeditWithCommentsAnyCaseAndSkippedSections) {
  MeshReadReport report;
  const Mesh mesh = read_mesh(write("two.mesh", join(medit_lines())), &report);
  EXPECT_EQ(mesh.positions, kTwoTetPositions);
  EXPECT_EQ(mesh.tets, kTwoTets);
  EXPECT_TRUE(report.warnings.empty());
}

// The two-tet mesh as a .vtu: values wrapped across lines, a triangle
// (type 5, skipped silently) and a hexahedron (type 12, skipped with a
// warning) among the cells, point and cell data beside them. Line 11 holds
// the connectivity's first tet.
std::vector<std::string> vtu_lines() {
  return {"<?xml version=\"1.0\"?>",
          "<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">",
          "  <UnstructuredGrid>",
          "    <Piece NumberOfPoints=\"5\" NumberOfCells=\"4\">",
          "      <PointData><DataArray type=\"Float32\" Name=\"t\" format=\"ascii\">1 2 3 4 5"
          "</DataArray></PointData>",
          "      <Points>",
          "        <DataArray type=\"Float64\" NumberOfComponents='3' format=\"ascii\">",
          "          0 0 0 1 0 0 0",
          "          1 0 0 0 1 1 1 1",
          "        </DataArray></Points><Cells>",
          "        <DataArray type=\"Int32\" Name=\"connectivity\" format=\"ascii\">0 1 2 3",
          "          0 1 2  0 1 2 3 0 1 2 4",
          "          1 2 3 4</DataArray>",
          "        <DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">10 5 12 10"
          "</DataArray>",
          "        <DataArray type=\"Int32\" Name=\"offsets\" format=\"ascii\">4 7 15 19"
          "</DataArray>",
          "      </Cells>",
          "      <CellData><DataArray type=\"Int32\" Name=\"id\" format=\"ascii\">1 2 3 4"
          "</DataArray></CellData>",
          "    </Piece>",
          "  </UnstructuredGrid>",
          "</VTKFile>"};
}

TEST_F(MeshIoTest, ReadsVtuWithWrappedValuesSkippedCellsAndOtherArrays) {
  MeshReadReport report;
  const Mesh mesh = read_mesh(write("two.vtu", join(vtu_lines())), &report);
  EXPECT_EQ(mesh.positions, kTwoTetPositions);
  EXPECT_EQ(mesh.tets, kTwoTets);
  ASSERT_EQ(report.warnings.size(), 1u);
  EXPECT_CONTAINS(report.warnings[0], "two.vtu: skipped volume cells of VTK type 12 (1)");
}

TEST_F(MeshIoTest, BadVtuIsAnErrorNamingTheLine) {
  std::vector<std::string> lines = vtu_lines();
  lines[6] = "        <DataArray type=\"Float32\" NumberOfComponents=\"3\" format=\"binary\">";
  write("binary.vtu", join(lines));
  EXPECT_CONTAINS(read_error("binary.vtu", 7), "format \"binary\"; only format=\"ascii\"");

  lines = vtu_lines();
  lines[12] = "          1 2 3 5</DataArray>";  // the second tet's last point is out of range
  write("range.vtu", join(lines));
  EXPECT_CONTAINS(read_error("range.vtu", 13),
                  "tet (cell 3) refers to point 5, but the file has 5");

  lines = vtu_lines();
  lines[3] = "    <Piece NumberOfPoints=\"6\" NumberOfCells=\"4\">";
  write("points.vtu", join(lines));
  EXPECT_CONTAINS(read_error("points.vtu", 10), "the Points hold 5 whole points");

  lines = vtu_lines();
  lines[14] =
      "        <DataArray type=\"Int32\" Name=\"offsets\" format=\"ascii\">4 7 15 18"
      "</DataArray>";
  write("offsets.vtu", join(lines));
  EXPECT_CONTAINS(read_error("offsets.vtu", 11), "cell 3 is a tet (type 10) with 3 points");

  lines = vtu_lines();
  lines[13] =
      "        <DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">5 5 12 12"
      "</DataArray>";
  write("no_tets.vtu", join(lines));
  EXPECT_CONTAINS(read_error("no_tets.vtu", 10),
                  "no tets (VTK type 10); skipped volume cells of VTK type 12 (2)");

  lines = vtu_lines();
  lines.insert(lines.end() - 2, "    <Piece NumberOfPoints=\"0\" NumberOfCells=\"0\"></Piece>");
  write("pieces.vtu", join(lines));
  EXPECT_CONTAINS(read_error("pieces.vtu", 4), "several Pieces");

  lines = vtu_lines();
  lines[1] = "<VTKFile type=\"PolyData\" version=\"0.1\">";
  write("poly.vtu", join(lines));
  EXPECT_CONTAINS(read_error("poly.vtu", 2), "only UnstructuredGrid");
}

// The two-tet mesh as a legacy .vtk before version 5: an empty title, a
// FIELD block before the points, values wrapped across lines, a triangle
// and a hexahedron among the cells, point data after them. Line 12 holds
// the first tet.
std::vector<std::string> vtk_lines() {
  return {"# vtk DataFile Version 3.0",
          "",
          "ASCII",
          "DATASET UNSTRUCTURED_GRID",
          "FIELD FieldData 2",
          "TIME 1 1 double",
          "0.5",
          "CYCLE 1 2 int 7 8",
          "POINTS 5 float",
          "0 0 0 1 0 0 0",
          "1 0 0 0 1 1 1 1",
          "CELLS 4 23",
          "4 0 1 2 3",
          "3 0 1 2  8 0 1 2 3 0 1 2 4",
          "4 1 2 3 4",
          "CELL_TYPES 4",
          "10 5 12",
          "10",
          "POINT_DATA 5",
          "SCALARS t float 1",
          "LOOKUP_TABLE default",
          "1 2 3 4 5"};
}

// The same as a legacy .vtk of version 5.1 (offsets and connectivity, a
// METADATA block).
std::vector<std::string> vtk51_lines() {
  return {"# vtk DataFile Version 5.1",
          "two tets",
          "ASCII",
          "DATASET UNSTRUCTURED_GRID",
          "POINTS 5 double",
          "0 0 0 1 0 0 0 1 0 0 0 1 1 1 1",
          "METADATA",
          "INFORMATION 0",
          "",
          "CELLS 3 8",
          "OFFSETS vtktypeint64",
          "0 4 8",
          "CONNECTIVITY vtktypeint64",
          "0 1 2 3 1 2 3 4",
          "CELL_TYPES 2",
          "10 10"};
}

TEST_F(MeshIoTest, ReadsLegacyVtkOfBothLayouts) {
  MeshReadReport report;
  const Mesh mesh = read_mesh(write("two.vtk", join(vtk_lines())), &report);
  EXPECT_EQ(mesh.positions, kTwoTetPositions);
  EXPECT_EQ(mesh.tets, kTwoTets);
  ASSERT_EQ(report.warnings.size(), 1u);
  EXPECT_CONTAINS(report.warnings[0], "two.vtk: skipped volume cells of VTK type 12 (1)");

  const Mesh v51 = read_mesh(write("two51.vtk", join(vtk51_lines())));
  EXPECT_EQ(v51.positions, kTwoTetPositions);
  EXPECT_EQ(v51.tets, kTwoTets);
}

TEST_F(MeshIoTest, BadLegacyVtkIsAnErrorNamingTheLine) {
  std::vector<std::string> lines = vtk_lines();
  lines[2] = "BINARY";
  write("binary.vtk", join(lines));
  EXPECT_CONTAINS(read_error("binary.vtk", 3), "BINARY files are not read");

  lines = vtk_lines();
  lines[14] = "4 1 2 3 5";
  write("range.vtk", join(lines));
  EXPECT_CONTAINS(read_error("range.vtk", 15),
                  "tet (cell 3) refers to point 5, but the file has 5");

  lines = vtk_lines();
  lines[11] = "CELLS 4 24";
  write("size.vtk", join(lines));
  EXPECT_CONTAINS(read_error("size.vtk", 15), "the cells hold 23 numbers; CELLS declares 24");

  lines = vtk_lines();
  lines[3] = "DATASET POLYDATA";
  write("poly.vtk", join(lines));
  EXPECT_CONTAINS(read_error("poly.vtk", 4), "only UNSTRUCTURED_GRID");

  lines = vtk_lines();
  lines.resize(13);
  write("short.vtk", join(lines));
  EXPECT_CONTAINS(read_error("short.vtk", 13), "truncated file");

  lines = vtk51_lines();
  lines[11] = "0 4 9";
  write("offsets.vtk", join(lines));
  EXPECT_CONTAINS(read_error("offsets.vtk", 14), "OFFSETS must run from 0");

  write("header.vtk", "vtk output\n\nASCII\n");
  EXPECT_CONTAINS(read_error("header.vtk", 1), "not a legacy VTK file");
}

TEST_F(MeshIoTest, ReadsTetgenByEitherNameOrBaseWithAttributesAndMarkers) {
  write("pair.node",
        join({"# nodes", "5 3 1 1", "1 0 0 0 7.5 1", "2 1 0 0 7.5 1", "3 0 1 0 7.5 0  # interior",
              "", "4 0 0 1 7.5 1", "5 1 1 1 7.5 1", "# Generated by hand"}));
  write("pair.ele", join({"2 4 1", "1 1 2 3 4 3.0", "# between", "2 2 3 4 5 3.0"}));
  for (const char* name : {"pair.node", "pair.ele", "pair"}) {
    const Mesh mesh = read_mesh(path(name));
    EXPECT_EQ(mesh.positions, kTwoTetPositions) << name;
    EXPECT_EQ(mesh.tets, kTwoTets) << name;
  }
}

TEST_F(MeshIoTest, ReadsZeroBasedTetgenWithTenNodeTetsAndCountsUnusedVertices) {
  // Node 5 is a mid-edge node, used only by the dropped corners 5..10.
  write("quadratic.1.node",
        join({"6 3 0 0", "0 0 0 0", "1 1 0 0", "2 0 1 0", "3 0 0 1", "4 1 1 1", "5 0.5 0 0"}));
  write("quadratic.1.ele", join({"2 10 0", "0 0 1 2 3 5 5 5 5 5 5", "1 1 2 3 4 5 5 5 5 5 5"}));
  MeshReadReport report;
  const Mesh mesh = read_mesh(path("quadratic.1"), &report);
  EXPECT_EQ(mesh.num_vertices(), 6);
  EXPECT_EQ(mesh.tets, kTwoTets);
  EXPECT_EQ(report.unreferenced_vertices, 1);
  ASSERT_EQ(report.warnings.size(), 1u);
  EXPECT_CONTAINS(report.warnings[0], "1 of 6 vertices belong to no tet");
}

TEST_F(MeshIoTest, ReorientsNegativeTetsAndCountsThem) {
  std::vector<std::string> text = medit_lines();
  text[25] = "1 3 2 4 0";  // line 26: tet 1 with two vertices swapped
  MeshReadReport report;
  const Mesh mesh = read_mesh(write("flipped.mesh", join(text)), &report);
  EXPECT_EQ(report.reoriented_tets, 1);
  ASSERT_EQ(report.warnings.size(), 1u);
  EXPECT_CONTAINS(report.warnings[0], "re-oriented 1 of 2 tets");
  for (index_t t = 0; t < mesh.num_tets(); ++t) EXPECT_GT(signed_volume(mesh, t), 0);
  EXPECT_EQ(std::vector<index_t>(mesh.tets.begin(), mesh.tets.begin() + 4),
            (std::vector<index_t>{0, 2, 3, 1}));
}

// The message of the InputError that validating `mesh` as "test box" throws.
std::string validation_error(Mesh mesh) {
  try {
    validate_mesh(mesh, "test box");
  } catch (const InputError& error) {
    return error.what();
  }
  ADD_FAILURE() << "no InputError";
  return {};
}

TEST_F(MeshIoTest, ValidatesInMemoryMeshesWithZeroBasedNames) {
  Mesh mesh = two_tet_mesh();
  std::swap(mesh.tets[4], mesh.tets[5]);
  MeshReadReport report;
  validate_mesh(mesh, "test box", &report);
  EXPECT_EQ(report.reoriented_tets, 1);
  EXPECT_GT(signed_volume(mesh, 1), 0);

  Mesh bad = two_tet_mesh();
  bad.tets[7] = 5;
  EXPECT_CONTAINS(validation_error(bad), "test box: tet 1 refers to vertex 5, but the mesh has 5");
  bad = two_tet_mesh();
  bad.tets[1] = 3;
  EXPECT_CONTAINS(validation_error(bad), "test box: tet 0 uses vertex 3 twice");
  bad = two_tet_mesh();
  bad.positions[4] = std::nan("");
  EXPECT_CONTAINS(validation_error(bad), "test box: vertex 1 has a non-finite coordinate");
  bad = two_tet_mesh();
  bad.tets.insert(bad.tets.end(), {4, 3, 1, 2});
  EXPECT_CONTAINS(validation_error(bad), "test box: tet 2 has the same vertices as tet 1");
  bad.tets.clear();
  EXPECT_CONTAINS(validation_error(bad), "test box: the mesh has no tets");
}

// ---------------------------------------------------------------- bad input

TEST_F(MeshIoTest, TruncatedGmshNodesAreAnError) {
  std::vector<std::string> text = gmsh22_lines();
  text.resize(12);  // EOF after 3 of 5 nodes
  write("truncated.msh", join(text));
  const std::string message = read_error("truncated.msh", 12);
  EXPECT_CONTAINS(message, "after 3 of the 5 nodes");
  EXPECT_CONTAINS(message, "truncated");
}

TEST_F(MeshIoTest, MissingEndNodesIsAnError) {
  std::vector<std::string> text = gmsh22_lines();
  text.erase(text.begin() + 14);  // line 15 is now $Elements
  write("no_end.msh", join(text));
  EXPECT_CONTAINS(read_error("no_end.msh", 15), "expected $EndNodes after the 5 nodes");
}

TEST_F(MeshIoTest, UnterminatedUnknownSectionIsAnError) {
  write("open.msh", join(gmsh22_lines()) + "$Surface\n1\n1 2 3\n");
  EXPECT_CONTAINS(read_error("open.msh", 25), "section $Surface (line 23) has no $EndSurface");
}

TEST_F(MeshIoTest, OutOfRangeNodeIsAnErrorInEachFormat) {
  std::vector<std::string> gmsh = gmsh22_lines();
  gmsh[20] = "9 4 2 0 1 20 30 40 99999";
  write("range.msh", join(gmsh));
  EXPECT_CONTAINS(read_error("range.msh", 21), "tet 9 refers to node 99999");

  std::vector<std::string> medit = medit_lines();
  medit[26] = "2 3 4 6 0";
  write("range.mesh", join(medit));
  EXPECT_CONTAINS(read_error("range.mesh", 27), "tet 2 refers to vertex 6, but the file has 5");

  write("range.node", kTetgenNodes);
  write("range.ele", join({"2 4 0", "1 1 2 3 4", "2 2 3 4 0"}));
  EXPECT_CONTAINS(read_error("range.ele", 3), "tet 2 refers to node 0, but the .node file has 5");
}

TEST_F(MeshIoTest, NonFiniteCoordinateIsAnErrorNamingTheVertex) {
  std::vector<std::string> medit = medit_lines();
  medit[8] = "nan 1 0 1";
  write("nan.mesh", join(medit));
  EXPECT_CONTAINS(read_error("nan.mesh", 9), "vertex 3 has a non-finite coordinate");

  std::vector<std::string> gmsh = gmsh22_lines();
  gmsh[12] = "40 0 inf 1";
  write("inf.msh", join(gmsh));
  EXPECT_CONTAINS(read_error("inf.msh", 13), "vertex 40 has a non-finite coordinate");
}

TEST_F(MeshIoTest, NonNumericAndShortLinesAreErrors) {
  std::vector<std::string> medit = medit_lines();
  medit[9] = "0 zero 1 1";
  write("word.mesh", join(medit));
  EXPECT_CONTAINS(read_error("word.mesh", 10), "expected y coordinate (a number), found 'zero'");

  write("short.node", kTetgenNodes);
  write("short.ele", join({"2 4 0", "1 1 2 3", "2 2 3 4 5"}));
  EXPECT_CONTAINS(read_error("short.ele", 2), "expected a node id of the tet, but the line ends");
}

TEST_F(MeshIoTest, DuplicateTetInAnyOrderIsAnError) {
  std::vector<std::string> medit = medit_lines();
  medit[26] = "4 2 1 3 0";  // the vertices of tet 1, negatively ordered
  write("duplicate.mesh", join(medit));
  EXPECT_CONTAINS(read_error("duplicate.mesh", 27),
                  "tet 2 has the same vertices as tet 1 (line 26)");
}

TEST_F(MeshIoTest, RepeatedVertexIsAnError) {
  std::vector<std::string> gmsh = gmsh22_lines();
  gmsh[19] = "7 4 2 0 1 10 20 20 40";
  write("repeated.msh", join(gmsh));
  EXPECT_CONTAINS(read_error("repeated.msh", 20), "tet 7 uses vertex 20 twice");
}

TEST_F(MeshIoTest, ZeroVolumeTetIsAnError) {
  std::vector<std::string> medit = medit_lines();
  medit[10] = "1 1 0 1";  // vertex 5 in the plane z = 0 of vertices 1 2 3
  medit[26] = "1 2 3 5 0";
  write("flat.mesh", join(medit));
  EXPECT_CONTAINS(read_error("flat.mesh", 27), "tet 2 has zero volume");

  medit[10] = "1 1 1e-17 1";  // flat up to rounding
  write("nearly_flat.mesh", join(medit));
  EXPECT_CONTAINS(read_error("nearly_flat.mesh", 27), "tet 2 has zero volume");
}

TEST_F(MeshIoTest, DuplicateNodeTagIsAnError) {
  std::vector<std::string> gmsh = gmsh22_lines();
  gmsh[13] = "20 1 1 1";
  write("twice.msh", join(gmsh));
  EXPECT_CONTAINS(read_error("twice.msh", 14),
                  "node tag 20 appears twice in $Nodes (first on line 11)");
}

TEST_F(MeshIoTest, BinaryGmshIsRejected) {
  const char binary[] = "$MeshFormat\n4.1 1 8\n\x01\0\0\0\n$EndMeshFormat\n";
  write("binary.msh", std::string(binary, sizeof binary - 1));
  EXPECT_CONTAINS(read_error("binary.msh", 2), "binary .msh files are not supported");
}

TEST_F(MeshIoTest, HugeDeclaredCountsDoNotAllocate) {
  std::vector<std::string> gmsh = gmsh22_lines();
  gmsh[8] = "1000000000000000";
  write("huge.msh", join(gmsh));
  EXPECT_CONTAINS(read_error("huge.msh", 9), "outside the supported range");

  gmsh[8] = "2000000000";  // fits 32-bit indices, far beyond the file
  write("big.msh", join(gmsh));
  EXPECT_CONTAINS(read_error("big.msh", 15), "expected a node tag (an integer), found '$EndNodes'");

  write("big.node", kTetgenNodes);
  write("big.ele", join({"2000000000 4 0", "1 1 2 3 4"}));
  EXPECT_CONTAINS(read_error("big.ele", 2), "after 1 of the 2000000000 tets");

  std::vector<std::string> medit = medit_lines();
  medit[24] = "2147483000";
  write("big.mesh", join(medit));
  EXPECT_CONTAINS(read_error("big.mesh", 28), "found 'End'");
}

TEST_F(MeshIoTest, MeshWithoutTetsIsAnError) {
  std::vector<std::string> medit = medit_lines();
  medit.erase(medit.begin() + 23, medit.begin() + 27);
  write("no_tets.mesh", join(medit));
  EXPECT_CONTAINS(read_error("no_tets.mesh", 24), "no Tetrahedra section");

  std::vector<std::string> gmsh = gmsh22_lines();
  gmsh[16] = "3";
  gmsh[19] = "7 11 2 0 1 10 20 30 40 10 10 10 10 10 10";
  gmsh.erase(gmsh.begin() + 20);
  write("no_tets.msh", join(gmsh));
  EXPECT_CONTAINS(read_error("no_tets.msh", 16),
                  "no 4-node tets (type 4); skipped volume elements of Gmsh type 11 (1)");
}

TEST_F(MeshIoTest, MissingMeditEndIsAnError) {
  std::vector<std::string> medit = medit_lines();
  medit.pop_back();
  write("open.mesh", join(medit));
  EXPECT_CONTAINS(read_error("open.mesh", 27), "without End");
}

TEST_F(MeshIoTest, UnknownExtensionListsTheSupportedOnes) {
  write("raptor.stl", "solid raptor\n");
  try {
    read_mesh(path("raptor.stl"));
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& error) {
    EXPECT_CONTAINS(error.what(), "raptor.stl");
    EXPECT_CONTAINS(error.what(), ".vtk");
    EXPECT_CONTAINS(error.what(), ".msh");
    EXPECT_CONTAINS(error.what(), ".mesh");
    EXPECT_CONTAINS(error.what(), ".vtu");
    EXPECT_CONTAINS(error.what(), ".node/.ele");
  }
}

TEST_F(MeshIoTest, MissingFileIsAnErrorNamingIt) {
  for (const char* name : {"nothere.msh", "nothere.mesh", "nothere.ele", "nothere"}) {
    try {
      read_mesh(path(name));
      ADD_FAILURE() << "no InputError for " << name;
    } catch (const InputError& error) {
      EXPECT_CONTAINS(error.what(), "nothere");
      EXPECT_CONTAINS(error.what(), "cannot open");
    }
  }
}

// ---------------------------------------------------------------- writing

TEST_F(MeshIoTest, EveryWriterRoundTripsExactly) {
  // Far from the origin and tiny: digits that a shorter format would lose.
  for (const auto& [offset, scale] : {std::pair{12345.678901234567, 1.0}, std::pair{0.0, 1e-80}}) {
    Mesh mesh = two_tet_mesh();
    for (std::size_t i = 0; i < mesh.positions.size(); ++i)
      mesh.positions[i] = offset + scale * (mesh.positions[i] + std::sin(i + 1.0) * 1e-3 / 3);
    for (const char* name : {"out.mesh", "out.msh", "out.node"}) {
      write_mesh(mesh, path(name));
      const Mesh back = read_mesh(path(name));
      EXPECT_EQ(back.positions, mesh.positions) << name << " scale " << scale;
      EXPECT_EQ(back.tets, mesh.tets) << name << " scale " << scale;
    }
  }
  EXPECT_TRUE(fs::exists(path("out.ele")));
}

TEST_F(MeshIoTest, WriteFailureNamesThePath) {
  const std::string target = path("no/such/dir/out.mesh");
  try {
    write_mesh(two_tet_mesh(), target);
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& error) {
    EXPECT_CONTAINS(error.what(), target);
  }
  EXPECT_THROW(write_mesh(two_tet_mesh(), path("out.vtu")), InputError);
}

// ---------------------------------------------------------------- real meshes

struct RealMesh {
  const char* file;
  index_t vertices;
  index_t tets;
  double volume;  // from the README, to its printed digits
};

void check_real_mesh(const RealMesh& expected) {
  const std::string file = std::string(DESCENT_SHARED_MESHES) + "/" + expected.file;
  const std::string probe = fs::path(file).extension().empty() ? file + ".node" : file;
  if (!fs::exists(probe)) GTEST_SKIP() << probe << " is absent (real meshes are not shipped)";
  MeshReadReport report;
  const auto start = std::chrono::steady_clock::now();
  const Mesh mesh = read_mesh(file, &report);
  const std::chrono::duration<double, std::milli> took = std::chrono::steady_clock::now() - start;
  std::cout << "[ timing   ] read " << expected.file << " in " << took.count() << " ms\n";
  EXPECT_EQ(mesh.num_vertices(), expected.vertices);
  EXPECT_EQ(mesh.num_tets(), expected.tets);
  EXPECT_EQ(report.reoriented_tets, 0);
  EXPECT_EQ(report.unreferenced_vertices, 0);
  EXPECT_NEAR(total_volume(mesh), expected.volume, 1e-4 * expected.volume);
}

TEST(RealMeshes, ArmadilloTetgen) { check_real_mesh({"armadillo_10k", 14779, 54855, 237594}); }
TEST(RealMeshes, DragonMedit) { check_real_mesh({"dragon_16k.mesh", 16443, 59990, 0.10853}); }
TEST(RealMeshes, ArmadilloGmsh41) {
  check_real_mesh({"armadillo_13k_ipc.msh", 13230, 54985, 237516});
}
TEST(RealMeshes, BunnyGmsh41) { check_real_mesh({"bunny_ipc.msh", 4670, 19379, 6.0104}); }
TEST(RealMeshes, BunnyGmsh22) { check_real_mesh({"bunny_ipc_msh22.msh", 4670, 19379, 6.0104}); }

// The README's raptor: 2 vertices no tet uses, kept and counted.
TEST(RealMeshes, RaptorVtu) {
  const std::string file = std::string(DESCENT_SHARED_MESHES) + "/raptorTetra_19409.vtu";
  if (!fs::exists(file)) GTEST_SKIP() << file << " is absent (real meshes are not shipped)";
  MeshReadReport report;
  const Mesh mesh = read_mesh(file, &report);
  EXPECT_EQ(mesh.num_vertices(), 5992);
  EXPECT_EQ(mesh.num_tets(), 19409);
  EXPECT_EQ(report.reoriented_tets, 0);
  EXPECT_EQ(report.unreferenced_vertices, 2);
  EXPECT_NEAR(total_volume(mesh), 27.489, 1e-4 * 27.489);
}

TEST(RealMeshes, BunnyIsTheSameInGmsh22And41) {
  const std::string dir = DESCENT_SHARED_MESHES;
  if (!fs::exists(dir + "/bunny_ipc.msh") || !fs::exists(dir + "/bunny_ipc_msh22.msh"))
    GTEST_SKIP() << "the bunny meshes are absent from " << dir;
  const Mesh v41 = read_mesh(dir + "/bunny_ipc.msh");
  const Mesh v22 = read_mesh(dir + "/bunny_ipc_msh22.msh");
  EXPECT_EQ(v41.positions, v22.positions);
  EXPECT_EQ(v41.tets, v22.tets);
}

}  // namespace
}  // namespace descent
