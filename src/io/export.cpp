#include "io/export.h"

#include "io/atomic_file.h"
#include "io/hdf5_file.h"
#include "io/vtk_formats.h"
#include "mesh/error.h"

#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <iterator>
#include <map>

namespace vesselmesh::io {
namespace {

namespace fs = std::filesystem;

// Makes `folder` (and its parents); InputError naming it when it cannot be made (a file in the way,
// no permission).
void make_folder(const fs::path& folder) {
  std::error_code error;
  fs::create_directories(folder, error);
  if (error || !fs::is_directory(folder))
    throw InputError(fmt::format("{}: cannot make the folder: {}; choose another output (-o)", folder.string(),
                                 error ? error.message() : "a file is in the way"));
}

std::vector<Vec3> scaled(const std::vector<Vec3>& points, double scale) {
  std::vector<Vec3> out;
  out.reserve(points.size());
  for (const Vec3& p : points) out.push_back(p * scale);
  return out;
}

std::string tag_name(const TetMesh& mesh, int tag) {
  const auto named = mesh.tag_names.find(tag);
  return named != mesh.tag_names.end() ? named->second : mesh::unnamed_tag(tag);
}

// A face file of svMultiPhysics: boundary triangles (mesh::boundary_part) with their own points, each
// point's GlobalNodeID and each triangle's GlobalElementID (the tetrahedron it bounds; from 1) and
// ModelFaceID (its tag).
void write_face(const std::string& path, mesh::BoundaryPart face, double scale) {
  for (Vec3& p : face.mesh.points) p *= scale;
  std::vector<int> node_ids, element_ids;
  for (int v : face.volume_point) node_ids.push_back(v + 1);
  for (int t : face.tet) element_ids.push_back(t + 1);
  const std::vector<int> face_ids = std::move(face.mesh.labels);
  face.mesh.labels.clear();
  write_vtp(path, face.mesh, {Field::labels("GlobalNodeID", node_ids)},
            {Field::labels("GlobalElementID", element_ids), Field::labels("ModelFaceID", face_ids)});
}

// A solver.xml to start from: every face named, blood, a parabolic 1 mL/s inflow at the largest
// face that is not a wall, zero traction at the others, no slip on the walls.
std::string solver_xml(const std::vector<std::string>& faces, const std::string& inlet, double scale) {
  std::string out = fmt::format(R"(<?xml version="1.0" encoding="UTF-8" ?>
<!-- Written by 'vesselmesh export --format svfsi': a skeleton to edit (time, conditions, solver).
     Lengths in the mesh are the volume's scaled by {:g} (metres with the default --units m for a
     volume in mm); density and viscosity below are SI (kg/m3, Pa s), right for a mesh in metres.
     The inflow (m3/s, negative: into the domain) is a placeholder. -->
<svMultiPhysicsFile version="0.1">
<GeneralSimulationParameters>
  <Continue_previous_simulation> false </Continue_previous_simulation>
  <Number_of_spatial_dimensions> 3 </Number_of_spatial_dimensions>
  <Number_of_time_steps> 100 </Number_of_time_steps>
  <Time_step_size> 0.001 </Time_step_size>
  <Spectral_radius_of_infinite_time_step> 0.5 </Spectral_radius_of_infinite_time_step>
  <Save_results_to_VTK_format> true </Save_results_to_VTK_format>
  <Name_prefix_of_saved_VTK_files> result </Name_prefix_of_saved_VTK_files>
  <Increment_in_saving_VTK_files> 10 </Increment_in_saving_VTK_files>
  <Start_saving_after_time_step> 1 </Start_saving_after_time_step>
  <Verbose> true </Verbose>
  <Warning> true </Warning>
  <Debug> false </Debug>
</GeneralSimulationParameters>
<Add_mesh name="fluid">
  <Mesh_file_path> mesh-complete/mesh-complete.mesh.vtu </Mesh_file_path>
)",
                                scale);
  for (const std::string& f : faces)
    out += fmt::format("  <Add_face name=\"{0}\"> <Face_file_path> mesh-complete/mesh-surfaces/{0}.vtp "
                       "</Face_file_path> </Add_face>\n",
                       f);
  out += R"(</Add_mesh>
<Add_equation type="fluid">
  <Coupled> true </Coupled>
  <Min_iterations> 3 </Min_iterations>
  <Max_iterations> 5 </Max_iterations>
  <Tolerance> 1e-4 </Tolerance>
  <Backflow_stabilization_coefficient> 0.2 </Backflow_stabilization_coefficient>
  <Density> 1060.0 </Density>
  <Viscosity model="Constant"> <Value> 0.0035 </Value> </Viscosity>
  <Output type="Spatial"> <Velocity> true </Velocity> <Pressure> true </Pressure> <WSS> true </WSS> </Output>
  <LS type="NS">
    <Linear_algebra type="fsils"> <Preconditioner> fsils </Preconditioner> </Linear_algebra>
    <Max_iterations> 15 </Max_iterations>
    <Tolerance> 1e-3 </Tolerance>
  </LS>
)";
  for (const std::string& f : faces) {
    if (f.rfind("wall", 0) == 0)
      out += fmt::format("  <Add_BC name=\"{}\"> <Type> Dir </Type> <Time_dependence> Steady </Time_dependence> "
                         "<Value> 0.0 </Value> </Add_BC>\n",
                         f);
    else if (f == inlet)
      out += fmt::format("  <Add_BC name=\"{}\"> <Type> Dir </Type> <Time_dependence> Steady </Time_dependence> "
                         "<Value> -1e-6 </Value> <Profile> Parabolic </Profile> <Impose_flux> true </Impose_flux> "
                         "</Add_BC>\n",
                         f);
    else
      out += fmt::format("  <Add_BC name=\"{}\"> <Type> Neu </Type> <Time_dependence> Steady </Time_dependence> "
                         "<Value> 0.0 </Value> </Add_BC>\n",
                         f);
  }
  out += "</Add_equation>\n</svMultiPhysicsFile>\n";
  return out;
}

ExportReport write_svfsi(const TetMesh& mesh, const fs::path& out, double scale) {
  if (!mesh.prisms.empty())
    throw InputError(fmt::format("{}: svMultiPhysics takes one element type and this volume has {} prisms: build it "
                                 "with 'vesselmesh volume' without --keep-prisms (its prisms cut into tetrahedra)",
                                 out.string(), mesh.num_prisms()));
  std::map<int, std::vector<int>> by_tag;
  for (size_t f = 0; f < mesh.boundary.size(); ++f) by_tag[mesh.boundary_tags[f]].push_back(static_cast<int>(f));
  for (const auto& [tag, list] : by_tag)
    if (!is_file_name_safe(tag_name(mesh, tag)))
      throw InputError(fmt::format("boundary tag {} is named \"{}\", which cannot be a file name: rename it (letters, "
                                   "digits, '_', '-', '.')",
                                   tag, tag_name(mesh, tag)));
  // Every boundary triangle with the tetrahedron it bounds, before anything is written (an error
  // here leaves no file).
  std::vector<int> all;
  for (const auto& [tag, list] : by_tag) all.push_back(tag);
  mesh::BoundaryPart exterior = mesh::boundary_part(mesh, mesh.tets, all);
  const fs::path complete = out / "mesh-complete", surfaces = complete / "mesh-surfaces";
  make_folder(surfaces);
  ExportReport report;
  const std::vector<Vec3> points = scaled(mesh.points, scale);
  std::vector<int> node_ids(points.size()), element_ids(mesh.tets.size());
  for (size_t k = 0; k < node_ids.size(); ++k) node_ids[k] = static_cast<int>(k) + 1;
  for (size_t k = 0; k < element_ids.size(); ++k) element_ids[k] = static_cast<int>(k) + 1;
  report.files.push_back((complete / "mesh-complete.mesh.vtu").string());
  write_vtu_tetrahedra(report.files.back(), points, mesh.tets, {Field::labels("GlobalNodeID", node_ids)},
                       {Field::labels("GlobalElementID", element_ids)});
  report.files.push_back((complete / "mesh-complete.exterior.vtp").string());
  write_face(report.files.back(), std::move(exterior), scale);
  std::vector<int> walls;
  std::vector<std::string> faces;
  std::string inlet;
  double largest = -1.0;
  for (const auto& [tag, list] : by_tag) {
    const std::string name = tag_name(mesh, tag);
    faces.push_back(name);
    report.files.push_back((surfaces / (name + ".vtp")).string());
    write_face(report.files.back(), mesh::boundary_part(mesh, mesh.tets, {tag}), scale);
    if (name.rfind("wall", 0) == 0) {
      walls.push_back(tag);
      continue;
    }
    double area = 0.0;
    for (int f : list) {
      const Triangle& t = mesh.boundary[f];
      area += 0.5 * (mesh.points[t[1]] - mesh.points[t[0]]).cross(mesh.points[t[2]] - mesh.points[t[0]]).norm();
    }
    if (area > largest) largest = area, inlet = name;
  }
  if (!walls.empty()) {
    report.files.push_back((complete / "walls_combined.vtp").string());
    write_face(report.files.back(), mesh::boundary_part(mesh, mesh.tets, walls), scale);
  }
  report.files.push_back((out / "solver.xml").string());
  write_text(report.files.back(), solver_xml(faces, inlet, scale));
  return report;
}

// OpenFOAM's polyMesh. A cell's faces, each listed out of the cell (its normal by the right-hand
// rule pointing away from it): a positive tetrahedron's four triangles; a prism's bottom (TetMesh
// order: facing away from its top), its top reversed and the three sides.
struct CellFace {
  std::array<int, 4> v;
  int n;  // 3 or 4 corners
};
std::vector<CellFace> cell_faces(const TetMesh& mesh, size_t cell) {
  const size_t tets = mesh.tets.size();
  if (cell < tets) {
    const Tet& t = mesh.tets[cell];
    return {{{t[0], t[2], t[1], -1}, 3}, {{t[0], t[1], t[3], -1}, 3}, {{t[1], t[2], t[3], -1}, 3},
            {{t[0], t[3], t[2], -1}, 3}};
  }
  const Prism& p = mesh.prisms[cell - tets];
  std::vector<CellFace> faces = {{{p[0], p[1], p[2], -1}, 3}, {{p[3], p[5], p[4], -1}, 3}};
  for (int e = 0; e < 3; ++e) {
    const int a = e, b = (e + 1) % 3;
    faces.push_back({{p[a], p[a + 3], p[b + 3], p[b]}, 4});
  }
  return faces;
}

std::array<int, 4> face_key(const CellFace& f) {
  std::array<int, 4> key = f.v;
  if (f.n == 3) {
    key[3] = -1;
    std::sort(key.begin(), key.begin() + 3);
  } else {
    std::sort(key.begin(), key.end());
  }
  return key;
}

std::string foam_header(const std::string& cls, const std::string& object, const std::string& note = "") {
  return fmt::format(
      "FoamFile\n{{\n    version     2.0;\n    format      ascii;\n    class       {};\n{}    location    "
      "\"constant/polyMesh\";\n    object      {};\n}}\n// Written by vesselmesh export\n\n",
      cls, note.empty() ? "" : fmt::format("    note        \"{}\";\n", note), object);
}

// Every face of the volume once, as OpenFOAM and Fluent list them: the first cell to list a face
// owns it (the lower number; its normal points out of it), the second is its neighbour; internal
// faces by (owner, neighbour), then the boundary's by (tag, owner), each boundary face with its
// tag (a quadrilateral's from a triangle on three of its corners).
struct Face {
  CellFace f;
  int owner, neighbour = -1;
};
struct VolumeFaces {
  std::vector<Face> faces;
  std::vector<int> internal, boundary;  // into faces, in order
  std::vector<int> tag;                 // per face (boundary faces)
};
VolumeFaces volume_faces(const TetMesh& mesh) {
  const size_t cells = mesh.tets.size() + mesh.prisms.size();
  VolumeFaces v;
  std::vector<Face>& faces = v.faces;
  std::map<std::array<int, 4>, int> index;
  for (size_t c = 0; c < cells; ++c)
    for (const CellFace& f : cell_faces(mesh, c)) {
      const auto [it, fresh] = index.emplace(face_key(f), static_cast<int>(faces.size()));
      if (fresh) {
        faces.push_back({f, static_cast<int>(c)});
      } else {
        if (faces[it->second].neighbour >= 0)
          throw InputError(fmt::format("a face of cell {} is shared by three cells: the volume is not a valid mesh", c));
        faces[it->second].neighbour = static_cast<int>(c);
      }
    }
  index.clear();
  std::map<std::array<int, 4>, int> tag_of;
  for (size_t f = 0; f < mesh.boundary.size(); ++f) {
    std::array<int, 4> key = {mesh.boundary[f][0], mesh.boundary[f][1], mesh.boundary[f][2], -1};
    std::sort(key.begin(), key.begin() + 3);
    tag_of.emplace(key, mesh.boundary_tags[f]);
  }
  const auto boundary_tag = [&](const CellFace& f) {
    for (int skip = f.n == 4 ? 0 : -1; skip < (f.n == 4 ? 4 : 0); ++skip) {
      std::array<int, 4> key = {-1, -1, -1, -1};
      for (int k = 0, n = 0; k < f.n; ++k)
        if (k != skip) key[n++] = f.v[k];
      std::sort(key.begin(), key.begin() + 3);
      const auto found = tag_of.find(key);
      if (found != tag_of.end()) return found->second;
    }
    throw InputError(fmt::format("a boundary face ({}, {}, {}{}) has no tagged boundary triangle: the volume's boundary "
                                 "does not match its cells (check it with 'vesselmesh quality')",
                                 f.v[0], f.v[1], f.v[2], f.n == 4 ? fmt::format(", {}", f.v[3]) : ""));
  };
  v.tag.assign(faces.size(), 0);
  for (size_t f = 0; f < faces.size(); ++f) {
    if (faces[f].neighbour >= 0) v.internal.push_back(static_cast<int>(f));
    else v.tag[f] = boundary_tag(faces[f].f), v.boundary.push_back(static_cast<int>(f));
  }
  std::sort(v.internal.begin(), v.internal.end(), [&](int a, int b) {
    return std::pair(faces[a].owner, faces[a].neighbour) < std::pair(faces[b].owner, faces[b].neighbour);
  });
  std::stable_sort(v.boundary.begin(), v.boundary.end(), [&](int a, int b) {
    return std::pair(v.tag[a], faces[a].owner) < std::pair(v.tag[b], faces[b].owner);
  });
  return v;
}

// The boundary tags in the order of the faces (a run of faces a tag), with their face counts.
std::vector<std::pair<int, int>> face_runs(const VolumeFaces& v) {
  std::vector<std::pair<int, int>> runs;
  for (int f : v.boundary) {
    if (runs.empty() || runs.back().first != v.tag[f]) runs.push_back({v.tag[f], 0});
    ++runs.back().second;
  }
  return runs;
}

void check_patch_names(const TetMesh& mesh) {
  for (const auto& [tag, name] : mesh.tag_names)
    if (!is_file_name_safe(name))
      throw InputError(fmt::format("boundary tag {} is named \"{}\", which cannot be a patch name: rename it", tag, name));
}

ExportReport write_openfoam(const TetMesh& mesh, const fs::path& out, double scale) {
  check_patch_names(mesh);
  const size_t cells = mesh.tets.size() + mesh.prisms.size();
  const VolumeFaces volume = volume_faces(mesh);
  const std::vector<Face>& faces = volume.faces;
  const std::vector<int>&internal = volume.internal, &boundary = volume.boundary;

  const fs::path folder = out / "constant" / "polyMesh";
  make_folder(folder);
  ExportReport report;
  const auto write = [&](const std::string& name, const std::string& text) {
    report.files.push_back((folder / name).string());
    write_text(report.files.back(), text);
  };
  fmt::memory_buffer text;
  const auto into = std::back_inserter(text);
  text.append(foam_header("vectorField", "points"));
  fmt::format_to(into, "{}\n(\n", mesh.points.size());
  for (const Vec3& p : mesh.points) fmt::format_to(into, "({:.17g} {:.17g} {:.17g})\n", p.x() * scale, p.y() * scale, p.z() * scale);
  text.append(std::string_view(")\n"));
  write("points", fmt::to_string(text));

  text.clear();
  text.append(foam_header("faceList", "faces"));
  fmt::format_to(into, "{}\n(\n", faces.size());
  for (const std::vector<int>* list : {&internal, &boundary})
    for (int f : *list) {
      const CellFace& c = faces[f].f;
      if (c.n == 3) fmt::format_to(into, "3({} {} {})\n", c.v[0], c.v[1], c.v[2]);
      else fmt::format_to(into, "4({} {} {} {})\n", c.v[0], c.v[1], c.v[2], c.v[3]);
    }
  text.append(std::string_view(")\n"));
  write("faces", fmt::to_string(text));

  const std::string note = fmt::format("nPoints:{} nCells:{} nFaces:{} nInternalFaces:{}", mesh.points.size(), cells,
                                       faces.size(), internal.size());
  text.clear();
  text.append(foam_header("labelList", "owner", note));
  fmt::format_to(into, "{}\n(\n", faces.size());
  for (const std::vector<int>* list : {&internal, &boundary})
    for (int f : *list) fmt::format_to(into, "{}\n", faces[f].owner);
  text.append(std::string_view(")\n"));
  write("owner", fmt::to_string(text));

  text.clear();
  text.append(foam_header("labelList", "neighbour", note));
  fmt::format_to(into, "{}\n(\n", internal.size());
  for (int f : internal) fmt::format_to(into, "{}\n", faces[f].neighbour);
  text.append(std::string_view(")\n"));
  write("neighbour", fmt::to_string(text));

  text.clear();
  text.append(foam_header("polyBoundaryMesh", "boundary"));
  const std::vector<std::pair<int, int>> patches = face_runs(volume);  // tag, faces
  fmt::format_to(into, "{}\n(\n", patches.size());
  size_t start = internal.size();
  for (const auto& [t, count] : patches) {
    const std::string name = tag_name(mesh, t);
    fmt::format_to(into, "    {}\n    {{\n        type            {};\n{}        nFaces          {};\n        startFace       {};\n    }}\n",
                   name, name.rfind("wall", 0) == 0 ? "wall" : "patch",
                   name.rfind("wall", 0) == 0 ? "        inGroups        List<word> 1(wall);\n" : "", count, start);
    start += static_cast<size_t>(count);
  }
  text.append(std::string_view(")\n"));
  write("boundary", fmt::to_string(text));
  return report;
}

// Fluent's ASCII mesh (.msh; Ansys Fluent User's Guide, appendix "Mesh File Format"): every index
// in hexadecimal, from 1; the zone ids of the (45 ...) sections in decimal. A face lists its nodes
// then c0 and c1, its normal by the right-hand rule pointing to c0: an internal face as OpenFOAM's
// (its normal out of its owner) with c0 its neighbour and c1 its owner; a boundary face reversed
// (its normal into the domain) with c0 its cell and c1 = 0. Zones: 2 the cells ("fluid"), 3 the
// internal faces, then one a boundary tag — wall (3) for the tags named wall*, velocity-inlet (10)
// for "inlet", pressure-outlet (5) otherwise.
std::string fluent_text(const TetMesh& mesh, double scale) {
  check_patch_names(mesh);
  const VolumeFaces volume = volume_faces(mesh);
  const size_t cells = mesh.tets.size() + mesh.prisms.size();
  fmt::memory_buffer out;
  const auto into = std::back_inserter(out);
  fmt::format_to(into, "(0 \"vesselmesh export: lengths scaled by {:g} from the mesh's unit\")\n(2 3)\n", scale);
  fmt::format_to(into, "(10 (0 1 {:x} 0 3))\n(10 (1 1 {:x} 1 3)(\n", mesh.points.size(), mesh.points.size());
  for (const Vec3& p : mesh.points) fmt::format_to(into, "{:.17g} {:.17g} {:.17g}\n", p.x() * scale, p.y() * scale, p.z() * scale);
  out.append(std::string_view("))\n"));
  fmt::format_to(into, "(12 (0 1 {:x} 0))\n", cells);
  if (mesh.prisms.empty()) {
    fmt::format_to(into, "(12 (2 1 {:x} 1 2))\n", cells);  // every cell a tetrahedron
  } else {
    fmt::format_to(into, "(12 (2 1 {:x} 1 0)(\n", cells);  // mixed: 2 a tetrahedron, 6 a wedge
    for (size_t c = 0; c < cells; ++c) out.append(std::string_view(c < mesh.tets.size() ? "2\n" : "6\n"));
    out.append(std::string_view("))\n"));
  }
  fmt::format_to(into, "(13 (0 1 {:x} 0))\n", volume.faces.size());
  const auto face_line = [&](const CellFace& f, bool reversed, int c0, int c1) {
    fmt::format_to(into, "{:x}", f.n);
    for (int k = 0; k < f.n; ++k) fmt::format_to(into, " {:x}", f.v[reversed ? f.n - 1 - k : k] + 1);
    fmt::format_to(into, " {:x} {:x}\n", c0, c1);
  };
  size_t first = 1;
  if (!volume.internal.empty()) {
    fmt::format_to(into, "(13 (3 {:x} {:x} 2 0)(\n", first, first + volume.internal.size() - 1);
    for (int f : volume.internal) {
      const Face& face = volume.faces[f];
      face_line(face.f, false, face.neighbour + 1, face.owner + 1);
    }
    out.append(std::string_view("))\n"));
    first += volume.internal.size();
  }
  struct Zone {
    int id;
    std::string type, name;
  };
  std::vector<Zone> zones = {{2, "fluid", "fluid"}, {3, "interior", "interior-fluid"}};
  size_t at = 0;
  for (const auto& [tag, count] : face_runs(volume)) {
    const std::string name = tag_name(mesh, tag);
    const bool wall = name.rfind("wall", 0) == 0;
    const Zone zone{4 + static_cast<int>(zones.size()) - 2, wall ? "wall" : name == "inlet" ? "velocity-inlet" : "pressure-outlet",
                    name};
    const int bc = wall ? 3 : name == "inlet" ? 10 : 5;
    fmt::format_to(into, "(13 ({:x} {:x} {:x} {:x} 0)(\n", zone.id, first, first + count - 1, bc);
    for (int k = 0; k < count; ++k, ++at) {
      const Face& face = volume.faces[volume.boundary[at]];
      face_line(face.f, true, face.owner + 1, 0);
    }
    out.append(std::string_view("))\n"));
    first += static_cast<size_t>(count);
    zones.push_back(zone);
  }
  for (const Zone& z : zones) fmt::format_to(into, "(45 ({} {} {})())\n", z.id, z.type, z.name);
  return fmt::to_string(out);
}

// XDMF + HDF5 as dolfinx reads them (XDMFFile.read_mesh, read_meshtags) and meshio, ParaView and
// VisIt open them: OUT/mesh.h5 with /mesh/geometry (points x 3), /mesh/topology (tetrahedra x 4,
// from 0), /mesh/cell_tags, /facets/topology (boundary triangles x 3), /facets/facet_tags; and two
// light files naming them, OUT/mesh.xdmf (the grid "mesh" with the attribute "cell_tags") and
// OUT/facets.xdmf (the grid "facet_tags" over the same points, with the attribute "facet_tags" and
// the tags' names in an Information as meshio writes them), the two files of the meshio-to-dolfinx route. dolfinx meshes
// are of one cell type: prisms are refused.
ExportReport write_xdmf(const TetMesh& mesh, const fs::path& out, double scale) {
  check_patch_names(mesh);  // names in XML
  if (!mesh.prisms.empty())
    throw InputError(fmt::format("the volume has {} prisms: XDMF for dolfinx holds one cell type; build the volume "
                                 "without --keep-prisms (its prisms cut into tetrahedra)",
                                 mesh.prisms.size()));
  make_folder(out);
  std::vector<Hdf5Dataset> data(5);
  data[0] = {"/mesh/geometry", {static_cast<uint64_t>(mesh.points.size()), 3}, {}, {}, false};
  for (const Vec3& p : mesh.points)
    for (int i = 0; i < 3; ++i) data[0].real.push_back(p[i] * scale);
  data[1] = {"/mesh/topology", {static_cast<uint64_t>(mesh.tets.size()), 4}, {}, {}, true};
  for (const Tet& t : mesh.tets) data[1].integer.insert(data[1].integer.end(), t.begin(), t.end());
  data[2] = {"/mesh/cell_tags", {static_cast<uint64_t>(mesh.tets.size())}, {}, {}, true};
  data[2].integer.assign(mesh.tets.size(), mesh.volume_tag);
  data[3] = {"/facets/topology", {static_cast<uint64_t>(mesh.boundary.size()), 3}, {}, {}, true};
  for (const Triangle& f : mesh.boundary) data[3].integer.insert(data[3].integer.end(), f.begin(), f.end());
  data[4] = {"/facets/facet_tags", {static_cast<uint64_t>(mesh.boundary.size())}, {}, {}, true};
  data[4].integer.assign(mesh.boundary_tags.begin(), mesh.boundary_tags.end());
  ExportReport report;
  report.files.push_back((out / "mesh.h5").string());
  write_hdf5(report.files.back(), data);

  const size_t n = mesh.points.size(), cells = mesh.tets.size(), facets = mesh.boundary.size();
  const std::string geometry = fmt::format(
      "      <Geometry GeometryType=\"XYZ\">\n        <DataItem Dimensions=\"{} 3\" NumberType=\"Float\" "
      "Precision=\"8\" Format=\"HDF\">mesh.h5:/mesh/geometry</DataItem>\n      </Geometry>\n",
      n);
  const auto grid = [&](const std::string& name, const char* type, size_t count, int corners, const std::string& group,
                        const std::string& attribute, const std::string& values, const std::string& information) {
    return fmt::format(
        "    <Grid Name=\"{0}\" GridType=\"Uniform\">\n{8}      <Topology TopologyType=\"{1}\" NumberOfElements=\"{2}\" "
        "NodesPerElement=\"{3}\">\n        <DataItem Dimensions=\"{2} {3}\" NumberType=\"Int\" Precision=\"8\" "
        "Format=\"HDF\">mesh.h5:/{4}/topology</DataItem>\n      </Topology>\n{5}      <Attribute Name=\"{6}\" "
        "AttributeType=\"Scalar\" Center=\"Cell\">\n        <DataItem Dimensions=\"{2}\" NumberType=\"Int\" "
        "Precision=\"8\" Format=\"HDF\">mesh.h5:/{4}/{7}</DataItem>\n      </Attribute>\n    </Grid>\n",
        name, type, count, corners, group, geometry, attribute, values, information);
  };
  const std::string head = "<?xml version=\"1.0\"?>\n<Xdmf Version=\"3.0\">\n  <Domain>\n";
  const std::string tail = "  </Domain>\n</Xdmf>\n";
  // The tags' names as meshio keeps them (its field_data: a name's tag and dimension).
  std::string names;
  for (const auto& [tag, name] : mesh.tag_names) names += fmt::format("<map key=\"{}\" dim=\"2\">{}</map>", name, tag);
  report.files.push_back((out / "mesh.xdmf").string());
  write_text(report.files.back(),
             head + grid("mesh", "Tetrahedron", cells, 4, "mesh", "cell_tags", "cell_tags", "") + tail);
  report.files.push_back((out / "facets.xdmf").string());
  write_text(report.files.back(),
             head +
                 grid("facet_tags", "Triangle", facets, 3, "facets", "facet_tags", "facet_tags",
                      fmt::format("      <Information Name=\"Information\" Value=\"{}\"><![CDATA[<main>{}</main>]]>"
                                  "</Information>\n",
                                  mesh.tag_names.size(), names)) +
                 tail);
  return report;
}

// Medit's .mesh, 1-based: a prism in Gmsh's order (its first triangle facing its second).
std::string medit_text(const TetMesh& mesh, double scale) {
  fmt::memory_buffer out;
  fmt::format_to(std::back_inserter(out), "MeshVersionFormatted 2\nDimension 3\nVertices\n{}\n", mesh.num_points());
  for (const Vec3& p : mesh.points)
    fmt::format_to(std::back_inserter(out), "{:.17g} {:.17g} {:.17g} 0\n", p.x() * scale, p.y() * scale, p.z() * scale);
  fmt::format_to(std::back_inserter(out), "Triangles\n{}\n", mesh.boundary.size());
  for (size_t f = 0; f < mesh.boundary.size(); ++f) {
    const Triangle& t = mesh.boundary[f];
    fmt::format_to(std::back_inserter(out), "{} {} {} {}\n", t[0] + 1, t[1] + 1, t[2] + 1, mesh.boundary_tags[f]);
  }
  fmt::format_to(std::back_inserter(out), "Tetrahedra\n{}\n", mesh.num_tets());
  for (const Tet& t : mesh.tets)
    fmt::format_to(std::back_inserter(out), "{} {} {} {} {}\n", t[0] + 1, t[1] + 1, t[2] + 1, t[3] + 1, mesh.volume_tag);
  if (!mesh.prisms.empty()) {
    fmt::format_to(std::back_inserter(out), "Prisms\n{}\n", mesh.num_prisms());
    for (const Prism& prism : mesh.prisms) {
      const Prism p = mesh::flipped_prism(prism);
      fmt::format_to(std::back_inserter(out), "{} {} {} {} {} {} {}\n", p[0] + 1, p[1] + 1, p[2] + 1, p[3] + 1,
                     p[4] + 1, p[5] + 1, mesh.volume_tag);
    }
  }
  fmt::format_to(std::back_inserter(out), "End\n");
  return fmt::to_string(out);
}

}  // namespace

namespace {
// Each format and its name, in the order the help and the messages list them.
constexpr std::pair<ExportFormat, const char*> kFormats[] = {
    {ExportFormat::svfsi, "svfsi"}, {ExportFormat::openfoam, "openfoam"}, {ExportFormat::xdmf, "xdmf"},
    {ExportFormat::fluent, "fluent"}, {ExportFormat::vtu, "vtu"},         {ExportFormat::medit, "medit"}};
}  // namespace

ExportFormat parse_export_format(const std::string& name) {
  std::string names;
  for (const auto& [format, known] : kFormats) {
    if (name == known) return format;
    names += names.empty() ? known : std::string(", ") + known;
  }
  throw InputError(fmt::format("export format \"{}\": expected one of {}", name, names));
}

std::string to_string(ExportFormat format) {
  for (const auto& [known, name] : kFormats)
    if (known == format) return name;
  return "?";
}

ExportReport export_volume(const TetMesh& mesh, const std::string& out, ExportFormat format, double scale) {
  ExportReport report;
  if (format == ExportFormat::svfsi) {
    report = write_svfsi(mesh, fs::path(out), scale);
  } else if (format == ExportFormat::openfoam) {
    report = write_openfoam(mesh, fs::path(out), scale);
  } else if (format == ExportFormat::vtu) {
    TetMesh copy = mesh;
    copy.points = scaled(mesh.points, scale);
    write_vtu(out, copy);
    report.files = {out};
  } else if (format == ExportFormat::xdmf) {
    report = write_xdmf(mesh, fs::path(out), scale);
  } else if (format == ExportFormat::fluent) {
    write_text(out, fluent_text(mesh, scale));
    report.files = {out};
  } else {
    write_text(out, medit_text(mesh, scale));
    report.files = {out};
  }
  report.points = mesh.num_points();
  report.tetrahedra = mesh.num_tets();
  report.prisms = mesh.num_prisms();
  report.boundary_triangles = static_cast<int>(mesh.boundary.size());
  return report;
}

}  // namespace vesselmesh::io
