// The flow solver's peers on one pipe (bench/flow_peers.sh drives it): converts the pipe's fields
// and meshes to the peers' formats and reads their results back, so that the script compares
// like with like.
//
//   bench_flow_peers openfoam-fields CASE RADIUS_M FLOW_M3S
//       Writes CASE/0/U and CASE/0/p from the cell and face centres in CASE/0/C (postProcess
//       -func writeCellCentres): the Poiseuille flow u = 2Q/A (1 - r^2/R^2) along +z inside and
//       on the patch `inlet` (fixed value), no slip on `wall`, zero pressure and
//       pressureInletOutletVelocity on `outlet_1`.
//   bench_flow_peers openfoam-wss CASE TIME DENSITY Z0_M Z1_M
//       The wall patch's wall shear stress (CASE/TIME/wallShearStress, kinematic, times DENSITY)
//       on the faces whose centre has Z0 <= z <= Z1: prints `faces`, `mean_pa`, `rms_error_pa`
//       against the analytic value given as the environment variable WSS_EXACT (Pa).
//   bench_flow_peers openfoam-steps LOG
//       Seconds per step from pimpleFoam's "ExecutionTime" lines (the first step left out: it
//       holds the setup), and the mean pressure iterations per step.
//   bench_flow_peers vesselmesh-wss RESULT_DIR Z0_MM Z1_MM
//       The last saved wall frame's nodal WSS magnitude at the wall points with Z0 <= z <= Z1.
//   bench_flow_peers svfsi-mesh VOLUME.vtu DIR SCALE RADIUS_M FLOW_M3S
//       svFSIplus's mesh, in metres (the points times SCALE): DIR/mesh-complete.mesh.vtu
//       (tetrahedra, GlobalNodeID, GlobalElementID, and the Poiseuille flow as the point array
//       Velocity, for <Initial_velocities_file_path>) and DIR/mesh-surfaces/NAME.vtp per boundary
//       tag (GlobalNodeID, GlobalElementID of the tetrahedron under each triangle), from a
//       tetrahedral VTU written by `vesselmesh volume`.
//   bench_flow_peers svfsi-steps LOG
//       Seconds per step from svFSIplus's "NS <step>-<iteration> <seconds>" lines (the first step
//       left out), Newton and linear iterations per step.
//   bench_flow_peers svfsi-wss RESULT.vtu WALL.vtp Z0_M Z1_M
//       The WSS point array of an svFSIplus result at the points of its wall face (WALL.vtp, as
//       svfsi-mesh wrote it) with Z0 <= z <= Z1.
// Each prints `key value` lines for the script; a bad argument or file: a message, exit 2.
#include "io/vtk_formats.h"
#include "mesh/tetmesh.h"
#include "post/wall_series.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkDoubleArray.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLPolyDataReader.h>
#include <vtkXMLPolyDataWriter.h>
#include <vtkXMLUnstructuredGridReader.h>
#include <vtkXMLUnstructuredGridWriter.h>

namespace {

using vesselmesh::Vec3;
namespace fs = std::filesystem;

std::string read_text(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read " + path.string());
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// A `nonuniform List<vector> N ( (x y z) ... )` or `List<scalar>` starting at `pos` in `text`.
std::vector<double> read_list(const std::string& text, std::size_t pos, int components,
                              const std::string& what) {
  const std::size_t open = text.find('(', pos);
  if (open == std::string::npos) throw std::runtime_error(what + ": no list");
  const long count = std::strtol(text.c_str() + pos, nullptr, 10);  // the count before "("
  if (count <= 0) throw std::runtime_error(what + ": no list length");
  std::vector<double> values;
  values.reserve(static_cast<std::size_t>(count) * components);
  const char* p = text.c_str() + open + 1;
  for (long i = 0; i < count * components; ++i) {
    while (*p == '(' || *p == ')' || std::isspace(static_cast<unsigned char>(*p))) ++p;
    char* end = nullptr;
    values.push_back(std::strtod(p, &end));
    if (end == p) throw std::runtime_error(what + ": bad number in the list");
    p = end;
  }
  return values;
}

std::vector<Vec3> as_vectors(const std::vector<double>& v) {
  std::vector<Vec3> out(v.size() / 3);
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = Vec3(v[3 * i], v[3 * i + 1], v[3 * i + 2]);
  return out;
}

// The internal field of an OpenFOAM volVectorField file.
std::vector<Vec3> internal_vectors(const std::string& text, const std::string& what) {
  const std::size_t at = text.find("internalField");
  const std::size_t list = text.find("List<vector>", at);
  if (at == std::string::npos || list == std::string::npos) throw std::runtime_error(what + ": no internalField list");
  return as_vectors(read_list(text, list + 12, 3, what));
}

// The `value` list of patch `patch` in a volVectorField file.
std::vector<Vec3> patch_vectors(const std::string& text, const std::string& patch, const std::string& what) {
  const std::size_t field = text.find("boundaryField");
  const std::size_t at = text.find("\n    " + patch + "\n", field);
  if (field == std::string::npos || at == std::string::npos) throw std::runtime_error(what + ": no patch " + patch);
  const std::size_t value = text.find("value", at);
  const std::size_t close = text.find('}', at);
  if (value == std::string::npos || value > close) throw std::runtime_error(what + ": patch " + patch + " has no value");
  const std::size_t list = text.find("List<vector>", value);
  if (list == std::string::npos || list > close) return {};  // uniform: no per-face values
  return as_vectors(read_list(text, list + 12, 3, what));
}

std::string header(const std::string& cls, const std::string& object) {
  return "FoamFile\n{\n    version 2.0;\n    format ascii;\n    class " + cls + ";\n    object " + object +
         ";\n}\n";
}

void write_vectors(std::ostream& out, const std::vector<Vec3>& v) {
  out << "nonuniform List<vector>\n" << v.size() << "\n(\n";
  char line[96];
  for (const Vec3& x : v) {
    std::snprintf(line, sizeof line, "(%.10g %.10g %.10g)\n", x.x(), x.y(), x.z());
    out << line;
  }
  out << ")";
}

int openfoam_fields(const fs::path& dir, double radius, double flow) {
  const std::string c = read_text(dir / "0" / "C");
  const double peak = 2.0 * flow / (std::numbers::pi * radius * radius);
  auto poiseuille = [&](const std::vector<Vec3>& centres) {
    std::vector<Vec3> u(centres.size());
    for (std::size_t i = 0; i < u.size(); ++i) {
      const double r2 = centres[i].x() * centres[i].x() + centres[i].y() * centres[i].y();
      u[i] = Vec3(0, 0, std::max(0.0, peak * (1.0 - r2 / (radius * radius))));
    }
    return u;
  };
  std::ofstream u(dir / "0" / "U");
  u << header("volVectorField", "U") << "dimensions [0 1 -1 0 0 0 0];\ninternalField ";
  write_vectors(u, poiseuille(internal_vectors(c, "0/C")));
  u << ";\nboundaryField\n{\n    inlet\n    {\n        type fixedValue;\n        value ";
  write_vectors(u, poiseuille(patch_vectors(c, "inlet", "0/C")));
  u << ";\n    }\n    outlet_1\n    {\n        type pressureInletOutletVelocity;\n        value uniform (0 0 0);\n"
       "    }\n    wall\n    {\n        type noSlip;\n    }\n}\n";
  std::ofstream p(dir / "0" / "p");
  p << header("volScalarField", "p")
    << "dimensions [0 2 -2 0 0 0 0];\ninternalField uniform 0;\nboundaryField\n{\n"
       "    inlet\n    {\n        type zeroGradient;\n    }\n"
       "    outlet_1\n    {\n        type fixedValue;\n        value uniform 0;\n    }\n"
       "    wall\n    {\n        type zeroGradient;\n    }\n}\n";
  if (!u || !p) throw std::runtime_error("cannot write the fields in " + (dir / "0").string());
  std::printf("peak_velocity_m_s %.6g\n", peak);
  return 0;
}

// Mean and RMS error against WSS_EXACT of the magnitudes `values` at `z` within [z0, z1].
void print_wss(const std::vector<double>& magnitudes, const std::vector<double>& z, double z0, double z1,
               const char* what) {
  const char* exact_text = std::getenv("WSS_EXACT");
  const double exact = exact_text ? std::atof(exact_text) : 0.0;
  double sum = 0, sum_error2 = 0;
  int count = 0;
  for (std::size_t i = 0; i < magnitudes.size(); ++i) {
    if (z[i] < z0 || z[i] > z1) continue;
    sum += magnitudes[i];
    sum_error2 += (magnitudes[i] - exact) * (magnitudes[i] - exact);
    ++count;
  }
  if (count == 0) throw std::runtime_error(std::string("no wall ") + what + " between the given z");
  std::printf("%s %d\nmean_pa %.6g\nrms_error_pa %.6g\n", what, count, sum / count, std::sqrt(sum_error2 / count));
}

int openfoam_wss(const fs::path& dir, const std::string& time, double density, double z0, double z1) {
  const std::vector<Vec3> centres = patch_vectors(read_text(dir / "0" / "C"), "wall", "0/C");
  const std::vector<Vec3> tau = patch_vectors(read_text(dir / time / "wallShearStress"), "wall", "wallShearStress");
  if (tau.size() != centres.size()) throw std::runtime_error("wallShearStress and C differ on the wall");
  std::vector<double> magnitude(tau.size()), z(tau.size());
  for (std::size_t i = 0; i < tau.size(); ++i) {
    magnitude[i] = density * tau[i].norm();
    z[i] = centres[i].z();
  }
  print_wss(magnitude, z, z0, z1, "faces");
  return 0;
}

int openfoam_steps(const fs::path& log) {
  std::ifstream in(log);
  if (!in) throw std::runtime_error("cannot read " + log.string());
  std::vector<double> times;
  int pressure_solves = 0, pressure_iterations = 0;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("ExecutionTime = ", 0) == 0) times.push_back(std::atof(line.c_str() + 16));
    const std::size_t at = line.find("Solving for p, ");
    if (at != std::string::npos) {
      const std::size_t it = line.find("No Iterations ", at);
      if (it != std::string::npos) {
        pressure_iterations += std::atoi(line.c_str() + it + 14);
        ++pressure_solves;
      }
    }
  }
  if (times.size() < 3) throw std::runtime_error(log.string() + ": fewer than three time steps");
  std::printf("steps %zu\nseconds_per_step %.6g\npressure_iterations_per_step %.4g\n", times.size(),
              (times.back() - times.front()) / static_cast<double>(times.size() - 1),
              static_cast<double>(pressure_iterations) / static_cast<double>(times.size()));
  return 0;
}

int vesselmesh_wss(const std::string& results, double z0, double z1) {
  const vesselmesh::post::WallSeries series = vesselmesh::post::read_wall_series(results);
  const vesselmesh::post::WallField wall = vesselmesh::post::read_wall_frame(series.frames.back());
  std::vector<double> magnitude(wall.wss.size()), z(wall.wss.size());
  for (std::size_t i = 0; i < wall.wss.size(); ++i) {
    magnitude[i] = wall.wss[i].norm();
    z[i] = wall.mesh.points[i].z();
  }
  print_wss(magnitude, z, z0, z1, "points");
  return 0;
}

// ---- svFSIplus's mesh-complete format ----

vtkNew<vtkIntArray> int_array(const char* name, const std::vector<int>& values) {
  vtkNew<vtkIntArray> array;
  array->SetName(name);
  array->SetNumberOfValues(static_cast<vtkIdType>(values.size()));
  for (std::size_t i = 0; i < values.size(); ++i) array->SetValue(static_cast<vtkIdType>(i), values[i]);
  return array;
}

template <class Writer, class Data>
void write_xml(const std::string& path, Data* data) {
  vtkNew<Writer> writer;
  writer->SetFileName(path.c_str());
  writer->SetInputData(data);
  writer->SetDataModeToBinary();
  if (writer->Write() != 1) throw std::runtime_error("cannot write " + path);
}

int svfsi_mesh(const std::string& volume, const std::string& directory, double scale, double radius, double flow) {
  const vesselmesh::TetMesh mesh = vesselmesh::io::read_vtu_volume(volume);
  if (mesh.num_prisms() != 0) throw std::runtime_error(volume + " has prisms: svFSIplus takes one element type");
  fs::create_directories(fs::path(directory) / "mesh-surfaces");
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  // Faces are matched to the volume by their points' coordinates: both written from the same
  // products.
  auto metres = [&](const Vec3& p) -> Vec3 { return p * scale; };
  const double peak = 2.0 * flow / (std::numbers::pi * radius * radius);
  vtkNew<vtkDoubleArray> velocity;
  velocity->SetName("Velocity");
  velocity->SetNumberOfComponents(3);
  for (const Vec3& p : mesh.points) {
    const Vec3 x = metres(p);
    points->InsertNextPoint(x.x(), x.y(), x.z());
    const double r2 = x.x() * x.x() + x.y() * x.y();
    velocity->InsertNextTuple3(0, 0, std::max(0.0, peak * (1.0 - r2 / (radius * radius))));
  }
  std::vector<int> node_ids(mesh.points.size());
  for (std::size_t i = 0; i < node_ids.size(); ++i) node_ids[i] = static_cast<int>(i) + 1;

  vtkNew<vtkUnstructuredGrid> grid;
  grid->SetPoints(points);
  std::map<std::array<int, 3>, int> tet_of_face;  // sorted face -> 1-based tetrahedron
  std::vector<int> element_ids(mesh.tets.size());
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
    const vesselmesh::Tet& tet = mesh.tets[t];
    const vtkIdType ids[4] = {tet[0], tet[1], tet[2], tet[3]};
    grid->InsertNextCell(10 /* VTK_TETRA */, 4, ids);
    element_ids[t] = static_cast<int>(t) + 1;
    for (int skip = 0; skip < 4; ++skip) {
      std::array<int, 3> face{};
      for (int k = 0, n = 0; k < 4; ++k)
        if (k != skip) face[n++] = tet[k];
      std::sort(face.begin(), face.end());
      tet_of_face[face] = static_cast<int>(t) + 1;
    }
  }
  grid->GetPointData()->AddArray(int_array("GlobalNodeID", node_ids));
  grid->GetCellData()->AddArray(int_array("GlobalElementID", element_ids));
  grid->GetPointData()->AddArray(velocity);
  write_xml<vtkXMLUnstructuredGridWriter>((fs::path(directory) / "mesh-complete.mesh.vtu").string(), grid.Get());

  std::map<int, std::vector<int>> triangles_of_tag;
  for (std::size_t f = 0; f < mesh.boundary.size(); ++f) triangles_of_tag[mesh.boundary_tags[f]].push_back(static_cast<int>(f));
  for (const auto& [tag, triangles] : triangles_of_tag) {
    const auto named = mesh.tag_names.find(tag);
    const std::string name = named != mesh.tag_names.end() ? named->second : "tag_" + std::to_string(tag);
    std::map<int, int> local;  // global point -> face point
    vtkNew<vtkPoints> face_points;
    face_points->SetDataTypeToDouble();
    std::vector<int> face_node_ids, face_element_ids;
    vtkNew<vtkCellArray> cells;
    for (int f : triangles) {
      vtkIdType ids[3];
      for (int k = 0; k < 3; ++k) {
        const int g = mesh.boundary[f][k];
        auto [it, inserted] = local.emplace(g, static_cast<int>(local.size()));
        if (inserted) {
          const Vec3 x = metres(mesh.points[g]);
          face_points->InsertNextPoint(x.x(), x.y(), x.z());
          face_node_ids.push_back(g + 1);
        }
        ids[k] = it->second;
      }
      cells->InsertNextCell(3, ids);
      std::array<int, 3> key = mesh.boundary[f];
      std::sort(key.begin(), key.end());
      const auto owner = tet_of_face.find(key);
      if (owner == tet_of_face.end()) throw std::runtime_error("boundary triangle " + std::to_string(f) + " has no tetrahedron");
      face_element_ids.push_back(owner->second);
    }
    vtkNew<vtkPolyData> face;
    face->SetPoints(face_points);
    face->SetPolys(cells);
    face->GetPointData()->AddArray(int_array("GlobalNodeID", face_node_ids));
    face->GetCellData()->AddArray(int_array("GlobalElementID", face_element_ids));
    write_xml<vtkXMLPolyDataWriter>((fs::path(directory) / "mesh-surfaces" / (name + ".vtp")).string(), face.Get());
    std::printf("face %s %zu\n", name.c_str(), triangles.size());
  }
  std::printf("nodes %zu\ntetrahedra %zu\n", mesh.points.size(), mesh.tets.size());
  return 0;
}

int svfsi_steps(const std::string& log) {
  std::ifstream in(log);
  if (!in) throw std::runtime_error("cannot read " + log);
  // "NS 20-3s 4.091e+01 [..] [linear_iterations ..]": seconds since the setup at the end of
  // each Newton iteration; the last iteration of a step ends it.
  std::map<int, double> end_of_step;
  std::map<int, int> newton, linear;
  for (std::string line; std::getline(in, line);) {
    const std::size_t at = line.find("NS ");
    if (at == std::string::npos) continue;
    // Fields: "NS", "<step>-<iteration>" (an "s" after it when the step was saved), seconds.
    std::istringstream fields(line.substr(at + 3));
    std::string counter;
    double seconds = 0;
    int step = 0, iteration = 0;
    if (!(fields >> counter >> seconds) || std::sscanf(counter.c_str(), "%d-%d", &step, &iteration) != 2) continue;
    end_of_step[step] = seconds;
    newton[step] = std::max(newton[step], iteration);
    const std::size_t first = line.find('[', at);
    const std::size_t second = first == std::string::npos ? first : line.find('[', first + 1);
    if (second != std::string::npos) linear[step] += std::atoi(line.c_str() + second + 1);
  }
  if (end_of_step.size() < 3) throw std::runtime_error(log + ": fewer than three time steps");
  const double span = end_of_step.rbegin()->second - end_of_step.begin()->second;
  const int steps = static_cast<int>(end_of_step.size());
  int newton_total = 0, linear_total = 0;
  for (const auto& [step, n] : newton) newton_total += n;
  for (const auto& [step, n] : linear) linear_total += n;
  std::printf("steps %d\nseconds_per_step %.6g\nnewton_iterations_per_step %.4g\nlinear_iterations_per_step %.4g\n", steps,
              span / (steps - 1), static_cast<double>(newton_total) / steps, static_cast<double>(linear_total) / steps);
  return 0;
}

int svfsi_wss(const std::string& result, const std::string& wall, double z0, double z1) {
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  reader->SetFileName(result.c_str());
  reader->Update();
  vtkUnstructuredGrid* grid = reader->GetOutput();
  vtkDataArray* wss = grid ? grid->GetPointData()->GetArray("WSS") : nullptr;
  if (wss == nullptr || wss->GetNumberOfComponents() != 3)
    throw std::runtime_error(result + " has no 3-component point array WSS");
  // The wall's points: the face file's GlobalNodeID (1-based) into the result, which keeps the
  // mesh's point order.
  vtkNew<vtkXMLPolyDataReader> face_reader;
  face_reader->SetFileName(wall.c_str());
  face_reader->Update();
  vtkDataArray* ids = face_reader->GetOutput()->GetPointData()->GetArray("GlobalNodeID");
  if (ids == nullptr) throw std::runtime_error(wall + " has no point array GlobalNodeID");
  std::vector<double> magnitude, z;
  for (vtkIdType k = 0; k < ids->GetNumberOfTuples(); ++k) {
    const auto i = static_cast<vtkIdType>(ids->GetTuple1(k)) - 1;
    if (i < 0 || i >= grid->GetNumberOfPoints()) throw std::runtime_error(wall + ": a GlobalNodeID outside the result");
    double t[3], x[3];
    wss->GetTuple(i, t);
    grid->GetPoint(i, x);
    magnitude.push_back(std::sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]));
    z.push_back(x[2]);
  }
  print_wss(magnitude, z, z0, z1, "points");
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const std::vector<std::string> a(argv + 1, argv + argc);
    if (a.size() == 4 && a[0] == "openfoam-fields") return openfoam_fields(a[1], std::stod(a[2]), std::stod(a[3]));
    if (a.size() == 6 && a[0] == "openfoam-wss")
      return openfoam_wss(a[1], a[2], std::stod(a[3]), std::stod(a[4]), std::stod(a[5]));
    if (a.size() == 2 && a[0] == "openfoam-steps") return openfoam_steps(a[1]);
    if (a.size() == 4 && a[0] == "vesselmesh-wss") return vesselmesh_wss(a[1], std::stod(a[2]), std::stod(a[3]));
    if (a.size() == 6 && a[0] == "svfsi-mesh")
      return svfsi_mesh(a[1], a[2], std::stod(a[3]), std::stod(a[4]), std::stod(a[5]));
    if (a.size() == 2 && a[0] == "svfsi-steps") return svfsi_steps(a[1]);
    if (a.size() == 5 && a[0] == "svfsi-wss") return svfsi_wss(a[1], a[2], std::stod(a[3]), std::stod(a[4]));
    std::fprintf(stderr, "usage: see the comment at the top of bench/flow_peers.cpp\n");
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_flow_peers: %s\n", e.what());
    return 2;
  }
}
