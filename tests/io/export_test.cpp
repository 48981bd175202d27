#include "io/export.h"

#include "analysis/open_ends.h"
#include "io/atomic_file.h"
#include "io/vtk_formats.h"
#include "mesh/error.h"
#include "synth/shapes.h"
#include "test_support.h"
#include "volume/volume_mesh.h"

#include <gtest/gtest.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLPolyDataReader.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <algorithm>
#include <filesystem>
#include <sstream>

namespace vesselmesh::io {
namespace {

// A pipe (mm) as `vesselmesh volume` builds it, tagged wall / inlet / outlet_1.
TetMesh pipe(bool keep_prisms = false) {
  const TriMesh surface = synth::cylinder({.radius = 2.0, .length = 6.0, .resolution = 0.8});
  volume::VolumeOptions options;
  options.keep_prisms = keep_prisms;
  return volume::build_volume(surface, analysis::open_ends(surface), std::vector<double>(surface.points.size(), 2.0),
                              options)
      .mesh;
}

int value(vtkDataArray* array, vtkIdType k) { return static_cast<int>(array->GetTuple1(k)); }

// svMultiPhysics's mesh-complete, read back by VTK's own readers: the volume's points in metres
// with GlobalNodeID 1..n, its tetrahedra with GlobalElementID 1..m; each face's triangles with the
// volume's node IDs at the same coordinates and the ID of a tetrahedron holding all three; the
// faces together the boundary, the walls combined the wall; solver.xml names every face.
TEST(Export, SvfsiMeshCompleteReadBackByVtk) {
  test::TemporaryFolder tmp;
  const TetMesh mesh = pipe();
  ASSERT_EQ(mesh.num_prisms(), 0);
  const ExportReport report = export_volume(mesh, tmp.path("sv"), ExportFormat::svfsi, 1e-3);
  EXPECT_EQ(report.tetrahedra, mesh.num_tets());
  const std::filesystem::path complete = tmp.folder() / "sv" / "mesh-complete";

  vtkNew<vtkXMLUnstructuredGridReader> volume;
  volume->SetFileName((complete / "mesh-complete.mesh.vtu").c_str());
  volume->Update();
  vtkUnstructuredGrid* grid = volume->GetOutput();
  ASSERT_EQ(grid->GetNumberOfPoints(), mesh.num_points());
  ASSERT_EQ(grid->GetNumberOfCells(), mesh.num_tets());
  vtkDataArray* node_ids = grid->GetPointData()->GetArray("GlobalNodeID");
  vtkDataArray* element_ids = grid->GetCellData()->GetArray("GlobalElementID");
  ASSERT_NE(node_ids, nullptr);
  ASSERT_NE(element_ids, nullptr);
  for (vtkIdType k = 0; k < grid->GetNumberOfPoints(); ++k) {
    ASSERT_EQ(value(node_ids, k), k + 1);
    double x[3];
    grid->GetPoint(k, x);
    ASSERT_LT((Vec3(x[0], x[1], x[2]) - mesh.points[k] * 1e-3).norm(), 1e-15);
  }
  for (vtkIdType k = 0; k < grid->GetNumberOfCells(); ++k) {
    ASSERT_EQ(grid->GetCellType(k), 10);  // VTK_TETRA
    ASSERT_EQ(value(element_ids, k), k + 1);
  }

  const auto read_face = [&](const std::filesystem::path& path) {
    vtkNew<vtkXMLPolyDataReader> reader;
    reader->SetFileName(path.c_str());
    reader->Update();
    vtkPolyData* face = reader->GetOutput();
    vtkDataArray* nodes = face->GetPointData()->GetArray("GlobalNodeID");
    vtkDataArray* elements = face->GetCellData()->GetArray("GlobalElementID");
    EXPECT_NE(nodes, nullptr);
    EXPECT_NE(elements, nullptr);
    EXPECT_NE(face->GetCellData()->GetArray("ModelFaceID"), nullptr);
    for (vtkIdType c = 0; nodes && elements && c < face->GetNumberOfCells(); ++c) {
      const Tet& tet = mesh.tets[value(elements, c) - 1];
      vtkIdType count = 0;
      const vtkIdType* ids = nullptr;
      face->GetCellPoints(c, count, ids);
      EXPECT_EQ(count, 3);
      for (vtkIdType k = 0; k < count; ++k) {
        const int node = value(nodes, ids[k]) - 1;
        EXPECT_NE(std::find(tet.begin(), tet.end(), node), tet.end()) << path << " triangle " << c;
        double x[3];
        face->GetPoint(ids[k], x);
        EXPECT_LT((Vec3(x[0], x[1], x[2]) - mesh.points[node] * 1e-3).norm(), 1e-15);
      }
    }
    return static_cast<int>(face->GetNumberOfCells());
  };
  int faces = 0, walls = 0;
  for (const auto& [tag, name] : mesh.tag_names) {
    const int n = read_face(complete / "mesh-surfaces" / (name + ".vtp"));
    EXPECT_EQ(n, std::count(mesh.boundary_tags.begin(), mesh.boundary_tags.end(), tag)) << name;
    faces += n;
    if (name == "wall") walls = n;
  }
  EXPECT_EQ(faces, static_cast<int>(mesh.boundary.size()));
  EXPECT_EQ(read_face(complete / "walls_combined.vtp"), walls);
  EXPECT_EQ(read_face(complete / "mesh-complete.exterior.vtp"), faces);

  const std::string xml = read_file(tmp.path("sv/solver.xml"));
  for (const auto& [tag, name] : mesh.tag_names)
    EXPECT_NE(xml.find("<Add_face name=\"" + name + "\">"), std::string::npos) << name;
  size_t parabolic = 0;
  for (size_t at = xml.find("Parabolic"); at != std::string::npos; at = xml.find("Parabolic", at + 1)) ++parabolic;
  EXPECT_EQ(parabolic, 1u);
}

// svMultiPhysics takes one element type: a volume with prisms is refused, saying how to build one.
TEST(Export, SvfsiRefusesPrisms) {
  test::TemporaryFolder tmp;
  try {
    export_volume(pipe(true), tmp.path("sv"), ExportFormat::svfsi, 1e-3);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--keep-prisms"), std::string::npos) << e.what();
  }
  EXPECT_THROW(parse_export_format("openfoam2"), InputError);
}

// Medit's .mesh: every section's count, 1-based corners, references the tags; a prism in Gmsh's
// order (positive: its first triangle facing its second). The VTU is `volume`'s, scaled.
TEST(Export, MeditAndVtu) {
  test::TemporaryFolder tmp;
  const TetMesh mesh = pipe(true);
  ASSERT_GT(mesh.num_prisms(), 0);
  export_volume(mesh, tmp.path("p.mesh"), ExportFormat::medit, 1.0);
  std::istringstream in(read_file(tmp.path("p.mesh")));
  std::string word;
  std::map<std::string, int> counts;
  std::vector<int> first_prism(7);
  while (in >> word) {
    if (word != "Vertices" && word != "Triangles" && word != "Tetrahedra" && word != "Prisms") continue;
    int n = 0;
    in >> n;
    counts[word] = n;
    const int columns = word == "Vertices" ? 4 : word == "Triangles" ? 4 : word == "Tetrahedra" ? 5 : 7;
    for (int k = 0; k < n; ++k)
      for (int c = 0; c < columns; ++c) {
        double v = 0.0;
        in >> v;
        if (word == "Prisms" && k == 0) first_prism[c] = static_cast<int>(v);
      }
  }
  EXPECT_EQ(counts["Vertices"], mesh.num_points());
  EXPECT_EQ(counts["Triangles"], static_cast<int>(mesh.boundary.size()));
  EXPECT_EQ(counts["Tetrahedra"], mesh.num_tets());
  EXPECT_EQ(counts["Prisms"], mesh.num_prisms());
  const auto at = [&](int k) { return mesh.points[first_prism[k] - 1]; };
  EXPECT_GT((at(1) - at(0)).cross(at(2) - at(0)).dot(at(3) - at(0)), 0.0);
  EXPECT_EQ(first_prism[6], mesh.volume_tag);

  export_volume(mesh, tmp.path("p.vtu"), ExportFormat::vtu, 1e-3);
  const TetMesh back = read_vtu_volume(tmp.path("p.vtu"));
  EXPECT_EQ(back.num_tets(), mesh.num_tets());
  EXPECT_EQ(back.num_prisms(), mesh.num_prisms());
  EXPECT_LT((back.points[5] - mesh.points[5] * 1e-3).norm(), 1e-15);
  EXPECT_EQ(back.tag_names, mesh.tag_names);
}

}  // namespace
}  // namespace vesselmesh::io
