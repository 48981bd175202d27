#include "io/vtk_formats.h"

#include "mesh/error.h"
#include "synth/shapes.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "io/atomic_file.h"

#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>

namespace vesselmesh::io {
namespace {

TEST(VtkFormats, VtpRoundTripKeepsPointsTrianglesLabelsAndFields) {
  test::TemporaryFolder tmp;
  TriMesh m = synth::cylinder({.radius = 1.0, .length = 2.0, .resolution = 0.5, .capped = true});
  std::vector<double> height;
  for (const Vec3& p : m.points) height.push_back(p.z());
  std::vector<Vec3> normal(m.points.size(), Vec3(0, 0, 1));
  std::vector<double> area(m.triangles.size(), 0.25);
  write_vtp(tmp.path("c.vtp"), m, {Field::scalar("height", height), Field::vector("normal", normal)},
            {Field::scalar("area", area)});
  EXPECT_EQ(tmp.files(), std::vector<std::string>{"c.vtp"});

  const SurfaceData back = read_vtk_surface(tmp.path("c.vtp"), VtkFormat::vtp);
  EXPECT_EQ(back.mesh.points, m.points);  // Float64, bit for bit
  EXPECT_EQ(back.mesh.triangles, m.triangles);
  EXPECT_EQ(back.mesh.labels, m.labels);
  EXPECT_EQ(back.label_array, "tag");
  ASSERT_EQ(back.point_data.size(), 2u);
  EXPECT_EQ(back.point_data[0].name, "height");
  EXPECT_EQ(back.point_data[0].values, height);
  EXPECT_EQ(back.point_data[1].components, 3);
  ASSERT_EQ(back.cell_data.size(), 1u);
  EXPECT_EQ(back.cell_data[0].values, area);
}

TEST(VtkFormats, VtuTrianglesAreASurface) {
  const std::string vtu =
      R"(<?xml version="1.0"?><VTKFile type="UnstructuredGrid" version="0.1"><UnstructuredGrid><Piece NumberOfPoints="3" NumberOfCells="1">)"
      R"(<Points><DataArray type="Float64" NumberOfComponents="3" format="ascii">0 0 0 1 0 0 0 1 0</DataArray></Points>)"
      R"(<Cells><DataArray type="Int64" Name="connectivity" format="ascii">0 1 2</DataArray>)"
      R"(<DataArray type="Int64" Name="offsets" format="ascii">3</DataArray>)"
      R"(<DataArray type="UInt8" Name="types" format="ascii">5</DataArray></Cells>)"
      R"(<CellData><DataArray type="Int32" Name="CellEntityIds" format="ascii">7</DataArray></CellData>)"
      R"(</Piece></UnstructuredGrid></VTKFile>)";
  const SurfaceData s = parse_vtk_xml_surface(vtu, VtkFormat::vtu, "t.vtu");
  EXPECT_EQ(s.mesh.num_triangles(), 1);
  EXPECT_EQ(s.mesh.labels, std::vector<int>{7});
  EXPECT_EQ(s.label_array, "CellEntityIds");
}

TEST(VtkFormats, BadXmlGivesAnErrorNamingTheFile) {
  for (const std::string& bytes : {std::string(""), std::string("not xml at all"),
                                  std::string("<VTKFile type=\"PolyData\"><PolyData><Piece NumberOfPoints=\"3\""),
                                  std::string("<?xml version=\"1.0\"?><VTKFile type=\"PolyData\" version=\"0.1\">"
                                              "<PolyData><Piece NumberOfPoints=\"0\" NumberOfPolys=\"0\"></Piece>"
                                              "</PolyData></VTKFile>")}) {
    try {
      parse_vtk_xml_surface(bytes, VtkFormat::vtp, "bad.vtp");
      FAIL() << "accepted: " << bytes;
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()).rfind("bad.vtp: ", 0), 0u) << e.what();
      EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << "one line: " << e.what();
    }
  }
}

TEST(VtkFormats, InlineBase64AndAppendedBase64AreRead) {
  VESSELMESH_REQUIRE_SHARED(centerlines, "vessels/vmtk_aorta_iliac_bifurcation_centerlines_mm.vtp");
  // Lines only: read, then refused for having no surface.
  try {
    read_vtk_surface(centerlines, VtkFormat::vtp);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no triangles"), std::string::npos) << e.what();
  }
}

TEST(VtkFormats, DamagedCompressionHeaderIsRefusedBeforeDecoding) {
  test::TemporaryFolder tmp;
  write_vtp(tmp.path("t.vtp"), test::tetrahedron());
  std::string bytes = read_file(tmp.path("t.vtp"));
  // The first array's block count (raw appended, UInt32) claims four billion blocks.
  const size_t data = bytes.find('_', bytes.find("<AppendedData")) + 1;
  std::memset(bytes.data() + data, 0xff, 4);
  try {
    parse_vtk_xml_surface(bytes, VtkFormat::vtp, "damaged.vtp");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("compression header"), std::string::npos) << e.what();
  }
}

TEST(VtkFormats, DuplicateArrayNamesAreAnError) {
  const std::string vtp =
      R"(<VTKFile type="PolyData" version="0.1"><PolyData><Piece NumberOfPoints="3" NumberOfPolys="1">)"
      R"(<Points><DataArray type="Float32" NumberOfComponents="3" format="ascii">0 0 0 1 0 0 0 1 0</DataArray></Points>)"
      R"(<Polys><DataArray type="Int32" Name="connectivity" format="ascii">0 1 2</DataArray>)"
      R"(<DataArray type="Int32" Name="offsets" format="ascii">3</DataArray></Polys>)"
      R"(<CellData><DataArray type="Int32" Name="a" format="ascii">1</DataArray>)"
      R"(<DataArray type="Int32" Name="a" format="ascii">1</DataArray></CellData></Piece></PolyData></VTKFile>)";
  EXPECT_THROW(parse_vtk_xml_surface(vtp, VtkFormat::vtp, "dup.vtp"), InputError);
  std::string short_array = vtp;
  short_array.replace(short_array.find("0 0 0 1 0 0 0 1 0"), 17, "0 0 0 1 0 0 0 1");
  EXPECT_THROW(parse_vtk_xml_surface(short_array, VtkFormat::vtp, "short.vtp"), InputError);
  std::string bad_index = vtp;
  bad_index.replace(bad_index.find(">0 1 2<"), 7, ">0 1 7<");
  EXPECT_THROW(parse_vtk_xml_surface(bad_index, VtkFormat::vtp, "index.vtp"), InputError);
}

TEST(VtkFormats, NamedLabelArrayMustExist) {
  test::TemporaryFolder tmp;
  write_vtp(tmp.path("t.vtp"), test::tetrahedron());
  EXPECT_THROW(read_vtk_surface(tmp.path("t.vtp"), VtkFormat::vtp, "ModelFaceID"), InputError);
}

TEST(VtkFormats, SimVascularModelFaceIdsAreLabels) {
  VESSELMESH_REQUIRE_SHARED(path, "vessels/simvascular_demo_aorta_iliacs_capped_cm.vtp");
  const SurfaceData s = read_vtk_surface(path, VtkFormat::vtp);
  EXPECT_EQ(s.label_array, "ModelFaceID");
  std::map<int, int> count;
  for (int label : s.mesh.labels) ++count[label];
  // The counts its README gives for faces 1..5.
  EXPECT_EQ(count, (std::map<int, int>{{1, 9267}, {2, 5222}, {3, 78}, {4, 35}, {5, 32}}));
  EXPECT_EQ(s.mesh.num_points(), 7319);
}

}  // namespace
}  // namespace vesselmesh::io

namespace vesselmesh::io {
namespace {

TEST(VtuVolume, BoundaryTrianglesReadBackWithTheirTags) {
  test::TemporaryFolder tmp;
  TetMesh m;
  m.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  m.tets = {{0, 1, 2, 3}};
  m.boundary = mesh::tet_boundary(m.tets);
  m.boundary_tags = {3, 4, 4, 4};
  m.tag_names = {{3, "inlet"}, {4, "wall"}};
  write_vtu(tmp.path("v.vtu"), m, {Field::scalar("radius", {1, 2, 3, 4})});
  // The surface reader takes the triangles of a VTU and its `tag` array as labels.
  const SurfaceData back = read_vtk_surface(tmp.path("v.vtu"), VtkFormat::vtu);
  EXPECT_EQ(back.mesh.num_triangles(), 4);
  ASSERT_EQ(back.mesh.labels.size(), 4u);
  EXPECT_EQ(std::count(back.mesh.labels.begin(), back.mesh.labels.end(), 4), 3);
  EXPECT_EQ(tmp.files(), std::vector<std::string>{"v.vtu"});
}

// write_vtu then read_vtu_volume: the same cells, tags, names and layer data.
TEST(VtuVolume, ReadsBackWhatWriteVtuWrote) {
  test::TemporaryFolder tmp;
  TetMesh m;
  m.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0, 0, 2}, {1, 0, 2}, {0, 1, 2}};
  m.tets = {{0, 1, 2, 3}};
  // A wedge on the tetrahedron's top... not a closed mesh, just cells to read back.
  m.prisms = {{3, 1, 2, 4, 5, 6}};
  m.boundary = mesh::tet_boundary(m.tets);
  m.boundary_tags = {3, 2, 2, 7};
  m.tag_names = {{3, "inlet"}, {2, "wall"}};  // 7 has no name; the wall shares the volume's number
  m.volume_tag = 2;
  m.volume_name = "lumen";
  m.tet_layer = {0};
  m.tet_column = {-1};
  m.prism_layer = {1};
  m.prism_column = {2};
  write_vtu(tmp.path("v.vtu"), m, {Field::scalar("radius", {1, 2, 3, 4, 5, 6, 7})});
  const TetMesh back = read_vtu_volume(tmp.path("v.vtu"));
  EXPECT_EQ(back.points, m.points);
  EXPECT_EQ(back.tets, m.tets);
  EXPECT_EQ(back.prisms, m.prisms);
  EXPECT_EQ(back.boundary, m.boundary);
  EXPECT_EQ(back.boundary_tags, m.boundary_tags);
  EXPECT_EQ(back.tag_names, (std::map<int, std::string>{{2, "wall"}, {3, "inlet"}, {7, "tag_7"}}));
  EXPECT_EQ(back.volume_tag, 2);
  EXPECT_EQ(back.volume_name, "lumen");
  EXPECT_EQ(back.tet_layer, m.tet_layer);
  EXPECT_EQ(back.prism_column, m.prism_column);

  // A surface VTU is no volume; a VTU without tags cannot be used.
  TriMesh tri = test::tetrahedron();
  write_vtp(tmp.path("s.vtp"), tri);
  EXPECT_THROW(read_vtu_volume(tmp.path("s.vtp")), InputError);
  test::write_bytes(tmp.path("bad.vtu"), "<VTKFile type=\"UnstructuredGrid\"><UnstructuredGrid></UnstructuredGrid></VTKFile>");
  EXPECT_THROW(read_vtu_volume(tmp.path("bad.vtu")), InputError);
}


// Pieces joined by a .pvtp / .pvtu (as `simulate` writes them under MPI) read whole: the surface's
// shared points merged (their data the same on both sides), the volume's too (its pieces one after
// the other, a process's ghost points one with their owner's); a parallel file naming no piece, or
// a missing piece, is an InputError naming it.
TEST(VtkParallel, PiecesReadWhole) {
  test::TemporaryFolder tmp;
  std::filesystem::create_directories(tmp.path("pieces"));
  // Two triangles of a square, one a piece, sharing the diagonal's points.
  TriMesh a, b;
  a.points = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}};
  a.triangles = {{0, 1, 2}};
  a.labels = {4};
  b.points = {{0, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  b.triangles = {{0, 1, 2}};
  b.labels = {4};
  const auto height = [](const TriMesh& m) {
    std::vector<double> h;
    for (const Vec3& p : m.points) h.push_back(p.x() + 10 * p.y());
    return h;
  };
  write_vtp(tmp.path("pieces/w_0.vtp"), a, {Field::scalar("h", height(a))});
  write_vtp(tmp.path("pieces/w_1.vtp"), b, {Field::scalar("h", height(b))});
  write_parallel_file(tmp.path("w.pvtp"), VtkFormat::vtp, {"pieces/w_0.vtp", "pieces/w_1.vtp"},
                      {Field::scalar("h", {})});
  EXPECT_NE(io::read_file(tmp.path("w.pvtp")).find("<PPolyData"), std::string::npos);
  const SurfaceData whole = read_vtk_surface(tmp.path("w.pvtp"), VtkFormat::vtp);
  ASSERT_EQ(whole.mesh.num_points(), 4);
  ASSERT_EQ(whole.mesh.num_triangles(), 2);
  EXPECT_EQ(whole.mesh.labels, (std::vector<int>{4, 4}));
  ASSERT_EQ(whole.point_data.size(), 1u);
  for (int v = 0; v < 4; ++v)
    EXPECT_EQ(whole.point_data[0].values[v], whole.mesh.points[v].x() + 10 * whole.mesh.points[v].y());

  TetMesh t0, t1;
  t0.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  t0.tets = {{0, 1, 2, 3}};
  t1.points = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}};
  t1.tets = {{0, 2, 1, 3}};
  write_vtu(tmp.path("pieces/f_0.vtu"), t0, {Field::scalar("p", {1, 2, 3, 4})});
  write_vtu(tmp.path("pieces/f_1.vtu"), t1, {Field::scalar("p", {2, 3, 4, 5})});
  write_parallel_file(tmp.path("f.pvtu"), VtkFormat::vtu, {"pieces/f_0.vtu", "pieces/f_1.vtu"},
                      {Field::scalar("p", {})});
  std::vector<Field> fields;
  const TetMesh volume = read_vtu_volume(tmp.path("f.pvtu"), &fields);
  EXPECT_EQ(volume.num_points(), 5);
  EXPECT_EQ(volume.tets, (std::vector<Tet>{{0, 1, 2, 3}, {1, 3, 2, 4}}));
  ASSERT_EQ(fields.size(), 1u);
  EXPECT_EQ(fields[0].values, (std::vector<double>{1, 2, 3, 4, 5}));

  test::write_bytes(tmp.path("none.pvtu"), "<VTKFile type=\"PUnstructuredGrid\"><PUnstructuredGrid></PUnstructuredGrid></VTKFile>");
  EXPECT_THROW(read_vtu_volume(tmp.path("none.pvtu")), InputError);
  std::filesystem::remove(tmp.path("pieces/f_1.vtu"));
  try {
    read_vtu_volume(tmp.path("f.pvtu"));
    ADD_FAILURE() << "a missing piece was read";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("f_1.vtu"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace vesselmesh::io
