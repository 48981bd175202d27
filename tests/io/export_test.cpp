#include "io/export.h"

#include "analysis/open_ends.h"
#include "io/atomic_file.h"
#include "io/vtk_formats.h"
#include "mesh/error.h"
#include "synth/shapes.h"
#include "test_support.h"
#include "volume/volume_mesh.h"

#include <fmt/format.h>
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
#include <cstdio>
#include <cstdlib>
#include <map>
#include <set>
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

// svMultiPhysics takes one element type: a volume with prisms is refused, saying how to build one;
// an output that cannot be a folder is an input error.
TEST(Export, SvfsiRefusesPrisms) {
  test::TemporaryFolder tmp;
  try {
    export_volume(pipe(true), tmp.path("sv"), ExportFormat::svfsi, 1e-3);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--keep-prisms"), std::string::npos) << e.what();
  }
  EXPECT_THROW(parse_export_format("openfoam2"), InputError);
  for (ExportFormat f : {ExportFormat::svfsi, ExportFormat::openfoam, ExportFormat::xdmf, ExportFormat::fluent,
                         ExportFormat::vtu, ExportFormat::medit})
    EXPECT_EQ(parse_export_format(to_string(f)), f) << to_string(f);
  // A file where the output folder would be: an InputError naming it, nothing written.
  write_text(tmp.path("taken"), "x");
  EXPECT_THROW(export_volume(pipe(), tmp.path("taken"), ExportFormat::openfoam, 1e-3), InputError);
  EXPECT_THROW(export_volume(pipe(), tmp.path("taken"), ExportFormat::svfsi, 1e-3), InputError);
  EXPECT_EQ(read_file(tmp.path("taken")), "x");
}

// A polyMesh list: the entries between the parentheses that follow the count after the header.
std::vector<std::string> foam_list(const std::string& path) {
  std::istringstream in(read_file(path));
  std::string line;
  while (std::getline(in, line) && line != "}") {
  }
  int count = -1;
  while (count < 0 && std::getline(in, line))
    if (!line.empty() && std::isdigit(static_cast<unsigned char>(line[0]))) count = std::stoi(line);
  std::getline(in, line);
  EXPECT_EQ(line, "(") << path;
  std::vector<std::string> entries(static_cast<size_t>(std::max(count, 0)));
  for (std::string& e : entries) std::getline(in, e);
  std::getline(in, line);
  EXPECT_EQ(line, ")") << path;
  return entries;
}

// OpenFOAM's polyMesh, read back and checked for what checkMesh checks first: every face once,
// owner < neighbour in upper-triangular order, each face's normal out of its owner (into its
// neighbour), every cell closed (its outward area vectors summing to zero), the boundary faces in
// contiguous patches after the internal ones, one per tag, the walls of type wall. On tetrahedra
// and on a volume with prisms (their quadrilaterals at the ends taking the covering triangles' tags).
TEST(Export, OpenFoamPolyMeshInvariants) {
  for (bool prisms : {false, true}) {
    test::TemporaryFolder tmp;
    const TetMesh mesh = pipe(prisms);
    export_volume(mesh, tmp.path("foam"), ExportFormat::openfoam, 1e-3);
    const std::string dir = tmp.path("foam/constant/polyMesh/");
    const std::vector<std::string> points_text = foam_list(dir + "points"), faces_text = foam_list(dir + "faces"),
                                   owner_text = foam_list(dir + "owner"), neighbour_text = foam_list(dir + "neighbour");
    ASSERT_EQ(static_cast<int>(points_text.size()), mesh.num_points());
    std::vector<Vec3> x;
    for (const std::string& p : points_text) {
      Vec3 v;
      std::sscanf(p.c_str(), "(%lf %lf %lf)", &v[0], &v[1], &v[2]);
      x.push_back(v);
    }
    std::vector<std::vector<int>> faces;
    for (const std::string& f : faces_text) {
      std::istringstream in(f.substr(2, f.size() - 3));
      std::vector<int> v(static_cast<size_t>(f[0] - '0'));
      for (int& k : v) in >> k;
      faces.push_back(v);
    }
    const int cells = mesh.num_tets() + mesh.num_prisms(), internal = static_cast<int>(neighbour_text.size());
    ASSERT_EQ(owner_text.size(), faces.size());
    std::vector<int> owner, neighbour;
    for (const std::string& o : owner_text) owner.push_back(std::stoi(o));
    for (const std::string& n : neighbour_text) neighbour.push_back(std::stoi(n));
    // Cell centres: the mean of their points.
    std::vector<Vec3> centre(cells, Vec3::Zero());
    std::vector<std::set<int>> corners(cells);
    for (size_t f = 0; f < faces.size(); ++f)
      for (int side = 0; side < (static_cast<int>(f) < internal ? 2 : 1); ++side)
        for (int k : faces[f]) corners[side ? neighbour[f] : owner[f]].insert(k);
    for (int c = 0; c < cells; ++c) {
      ASSERT_EQ(corners[c].size(), c < mesh.num_tets() ? 4u : 6u) << "cell " << c;
      for (int k : corners[c]) centre[c] += x[k] / static_cast<double>(corners[c].size());
    }
    std::set<std::vector<int>> seen;
    std::vector<Vec3> closure(cells, Vec3::Zero());
    std::vector<int> face_count(cells, 0);
    for (size_t f = 0; f < faces.size(); ++f) {
      std::vector<int> key = faces[f];
      std::sort(key.begin(), key.end());
      ASSERT_TRUE(seen.insert(key).second) << "face " << f << " twice";
      Vec3 area = Vec3::Zero(), middle = Vec3::Zero();  // Newell's area vector
      for (size_t k = 0; k < faces[f].size(); ++k) {
        area += 0.5 * x[faces[f][k]].cross(x[faces[f][(k + 1) % faces[f].size()]]);
        middle += x[faces[f][k]] / static_cast<double>(faces[f].size());
      }
      ASSERT_GT(area.dot(middle - centre[owner[f]]), 0.0) << "face " << f << " not out of its owner";
      closure[owner[f]] += area;
      ++face_count[owner[f]];
      if (static_cast<int>(f) < internal) {
        ASSERT_LT(owner[f], neighbour[f]) << "face " << f;
        if (f > 0) {
          ASSERT_LE(std::pair(owner[f - 1], neighbour[f - 1]), std::pair(owner[f], neighbour[f])) << f;
        }
        ASSERT_GT(area.dot(centre[neighbour[f]] - middle), 0.0) << "face " << f << " not into its neighbour";
        closure[neighbour[f]] -= area;
        ++face_count[neighbour[f]];
      }
    }
    for (int c = 0; c < cells; ++c) {
      ASSERT_EQ(face_count[c], c < mesh.num_tets() ? 4 : 5) << "cell " << c;
      ASSERT_LT(closure[c].norm(), 1e-18) << "cell " << c << " not closed";
    }
    // The patches: after the internal faces, contiguous, one per tag.
    const std::string boundary = read_file(dir + "boundary");
    int start = internal, total = 0;
    for (const auto& [tag, name] : mesh.tag_names) {
      const size_t at = boundary.find("    " + name + "\n");
      ASSERT_NE(at, std::string::npos) << name;
      const size_t type = boundary.find("type", at), n = boundary.find("nFaces", at), s0 = boundary.find("startFace", at);
      EXPECT_EQ(boundary.substr(type, boundary.find(';', type) - type).find(name == "wall" ? "wall" : "patch") !=
                    std::string::npos,
                true)
          << name;
      const int count = std::stoi(boundary.substr(n + 6)), first = std::stoi(boundary.substr(s0 + 9));
      EXPECT_EQ(first, start) << name;
      for (int f = first; f < first + count; ++f) EXPECT_GE(f, internal);
      start += count;
      total += count;
    }
    EXPECT_EQ(total, static_cast<int>(faces.size()) - internal);
    if (!prisms) {
      EXPECT_EQ(total, static_cast<int>(mesh.boundary.size()));
    }
  }
}

// Fluent's .msh read back by hand (hexadecimal indices): the nodes in metres, the cells (tetrahedra,
// and wedges among them where kept), every face once in a zone — the internal ones with the
// right-hand normal from c1 to c0, the boundary ones pointing into c0 with c1 = 0 — every cell
// closed by its faces, a zone per tag named in the (45 ...) sections with Fluent's types.
// (bench/export_check.sh reads the same file with OpenFOAM's fluent3DMeshToFoam: checkMesh "Mesh OK".)
TEST(Export, FluentMeshInvariants) {
  for (bool prisms : {false, true}) {
    SCOPED_TRACE(prisms ? "prisms" : "tetrahedra");
    test::TemporaryFolder tmp;
    const TetMesh mesh = pipe(prisms);
    export_volume(mesh, tmp.path("pipe.msh"), ExportFormat::fluent, 1e-3);
    std::istringstream in(read_file(tmp.path("pipe.msh")));
    std::string line;
    std::vector<Vec3> x;
    struct FaceRow {
      std::vector<int> v;
      int c0, c1, zone;
    };
    std::vector<FaceRow> faces;
    std::map<int, std::pair<std::string, std::string>> zones;  // id: type, name
    std::map<int, int> zone_bc;
    int cells = 0, declared_faces = 0, zone = -1;
    enum { none, nodes, face_rows } reading = none;
    while (std::getline(in, line)) {
      if (line == "))") {
        reading = none;
        continue;
      }
      if (reading == nodes) {
        Vec3 v;
        std::istringstream(line) >> v[0] >> v[1] >> v[2];
        x.push_back(v);
        continue;
      }
      if (reading == face_rows) {
        std::istringstream row(line);
        row >> std::hex;
        int n = 0;
        row >> n;
        FaceRow f;
        f.v.resize(static_cast<size_t>(n));
        for (int& k : f.v) row >> k, --k;
        row >> f.c0 >> f.c1;
        f.zone = zone;
        faces.push_back(f);
        continue;
      }
      unsigned a = 0, b = 0, c = 0, d = 0, e = 0;
      char name[64] = "", type[64] = "";
      if (std::sscanf(line.c_str(), "(10 (1 %x %x %x %x)(", &a, &b, &c, &d) == 4) reading = nodes;
      else if (std::sscanf(line.c_str(), "(12 (0 1 %x 0))", &a) == 1) cells = static_cast<int>(a);
      else if (std::sscanf(line.c_str(), "(13 (0 1 %x 0))", &a) == 1) declared_faces = static_cast<int>(a);
      else if (std::sscanf(line.c_str(), "(13 (%x %x %x %x %x)(", &a, &b, &c, &d, &e) == 5) {
        reading = face_rows;
        zone = static_cast<int>(a);
        zone_bc[zone] = static_cast<int>(d);
        EXPECT_EQ(static_cast<int>(b), static_cast<int>(faces.size()) + 1) << "zone " << zone << " starts after the last";
      } else if (std::sscanf(line.c_str(), "(45 (%u %63s %63[^)])())", &a, type, name) == 3) {
        zones[static_cast<int>(a)] = {type, name};
      }
    }
    ASSERT_EQ(static_cast<int>(x.size()), mesh.num_points());
    EXPECT_NEAR(x[0].x(), mesh.points[0].x() * 1e-3, 1e-15);
    ASSERT_EQ(cells, mesh.num_tets() + mesh.num_prisms());
    ASSERT_EQ(static_cast<int>(faces.size()), declared_faces);
    // Cell centres from the faces' corners.
    std::vector<std::set<int>> corners(static_cast<size_t>(cells) + 1);
    for (const FaceRow& f : faces)
      for (int c : {f.c0, f.c1})
        if (c > 0) corners[static_cast<size_t>(c)].insert(f.v.begin(), f.v.end());
    std::vector<Vec3> centre(static_cast<size_t>(cells) + 1, Vec3::Zero());
    for (int c = 1; c <= cells; ++c) {
      ASSERT_EQ(corners[c].size(), c <= mesh.num_tets() ? 4u : 6u) << "cell " << c;
      for (int k : corners[c]) centre[c] += x[k] / static_cast<double>(corners[c].size());
    }
    std::vector<Vec3> closure(static_cast<size_t>(cells) + 1, Vec3::Zero());
    std::set<std::vector<int>> seen;
    std::map<int, int> boundary_faces;  // zone: count
    for (const FaceRow& f : faces) {
      std::vector<int> key = f.v;
      std::sort(key.begin(), key.end());
      ASSERT_TRUE(seen.insert(key).second) << "a face twice";
      Vec3 area = Vec3::Zero(), middle = Vec3::Zero();
      for (size_t k = 0; k < f.v.size(); ++k) {
        area += 0.5 * x[f.v[k]].cross(x[f.v[(k + 1) % f.v.size()]]);
        middle += x[f.v[k]] / static_cast<double>(f.v.size());
      }
      ASSERT_GT(f.c0, 0);
      ASSERT_GT(area.dot(centre[f.c0] - middle), 0.0) << "a face's normal not towards c0";
      closure[f.c0] -= area;
      if (f.c1 > 0) {
        ASSERT_EQ(f.zone, 3) << "an internal face outside the interior zone";
        ASSERT_GT(area.dot(middle - centre[f.c1]), 0.0) << "a face's normal not out of c1";
        closure[f.c1] += area;
      } else {
        ASSERT_NE(f.zone, 3) << "a boundary face in the interior zone";
        ++boundary_faces[f.zone];
      }
    }
    for (int c = 1; c <= cells; ++c) ASSERT_LT(closure[c].norm(), 1e-18) << "cell " << c << " not closed";
    // The zones: the cells, the interior, a zone per tag with Fluent's type and bc code.
    EXPECT_EQ(zones[2].first, "fluid");
    EXPECT_EQ(zones[3].first, "interior");
    EXPECT_EQ(zone_bc[3], 2);
    std::map<std::string, std::string> type_of;
    for (const auto& [id, zone_text] : zones) type_of[zone_text.second] = zone_text.first;
    EXPECT_EQ(type_of["wall"], "wall");
    EXPECT_EQ(type_of["inlet"], "velocity-inlet");
    EXPECT_EQ(type_of["outlet_1"], "pressure-outlet");
    EXPECT_EQ(boundary_faces.size(), mesh.tag_names.size());
    for (const auto& [id, zone_text] : zones) {
      if (id > 3) {
        EXPECT_EQ(zone_bc[id], zone_text.first == "wall" ? 3 : zone_text.first == "velocity-inlet" ? 10 : 5);
      }
    }
  }
}

// XDMF + HDF5 and Fluent read back by meshio (Debian's python3-meshio and python3-h5py, under
// Debian's /usr/bin/python3; skipped with a message without them): the XDMF's points, tetrahedra
// (positive, in metres), cell tags, facet triangles per tag and the tags' names, the HDF5 layout;
// Fluent's points and its face zones (the interior, a zone a tag) — read_back_with_meshio.py.
// A volume with prisms is refused for XDMF (dolfinx holds one cell type).
TEST(Export, XdmfAndFluentReadByMeshio) {
  test::TemporaryFolder tmp;
  const TetMesh mesh = pipe();
  export_volume(mesh, tmp.path("xdmf"), ExportFormat::xdmf, 1e-3);
  export_volume(mesh, tmp.path("pipe.msh"), ExportFormat::fluent, 1e-3);
  EXPECT_TRUE(std::filesystem::exists(tmp.path("xdmf/mesh.h5")));
  EXPECT_NE(read_file(tmp.path("xdmf/mesh.xdmf")).find("mesh.h5:/mesh/topology"), std::string::npos);
  try {
    export_volume(pipe(true), tmp.path("prisms"), ExportFormat::xdmf, 1e-3);
    ADD_FAILURE() << "prisms in XDMF";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("one cell type"), std::string::npos) << e.what();
  }
  if (std::system("/usr/bin/python3 -c 'import meshio, h5py' >/dev/null 2>&1") != 0)
    GTEST_SKIP() << "Debian's python3-meshio and python3-h5py are needed (scripts/install-deps installs them)";
  std::map<std::string, int> per_tag;
  for (size_t f = 0; f < mesh.boundary.size(); ++f) ++per_tag[mesh.tag_names.at(mesh.boundary_tags[f])];
  const int internal = (4 * mesh.num_tets() - static_cast<int>(mesh.boundary.size())) / 2;
  std::string command = fmt::format("/usr/bin/python3 {}/read_back_with_meshio.py {} {} {} {} {}",
                                    std::filesystem::path(__FILE__).parent_path().string(), tmp.path("xdmf"),
                                    tmp.path("pipe.msh"), mesh.num_points(), mesh.num_tets(), internal);
  for (const auto& [name, count] : per_tag) command += fmt::format(" {}={}", name, count);
  command += " >" + tmp.path("meshio.log") + " 2>&1";
  const int code = std::system(command.c_str());
  const std::string log = read_file(tmp.path("meshio.log"));
  std::printf("%s", log.c_str());
  EXPECT_EQ(code, 0) << log;
  EXPECT_NE(log.find("meshio"), std::string::npos) << log;
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
