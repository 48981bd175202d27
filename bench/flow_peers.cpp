// The flow solver's peers on one pipe (bench/flow_peers.sh drives it): writes the pipe's
// Poiseuille flow into the peers' initial conditions (their meshes come from `vesselmesh export`)
// and reads their results back, so that the script compares like with like.
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
//   bench_flow_peers svfsi-initial MESH.vtu OUT.vtu RADIUS_M FLOW_M3S
//       The Poiseuille flow at the points of svMultiPhysics's mesh (mesh-complete.mesh.vtu, in
//       metres, as `vesselmesh export --format svfsi --units m` wrote it): OUT.vtu, the same mesh
//       with the point array Velocity, for <Initial_velocities_file_path>; prints `nodes`.
//   bench_flow_peers svfsi-steps LOG
//       Seconds per step from svMultiPhysics's "NS <step>-<iteration> <seconds>" lines (the first
//       step left out), Newton and linear iterations per step.
//   bench_flow_peers svfsi-wss RESULT.vtu WALL.vtp Z0_M Z1_M
//       The WSS point array of an svMultiPhysics result at the points of its wall face (WALL.vtp,
//       as the export wrote it: GlobalNodeID) with Z0 <= z <= Z1.
// Each prints `key value` lines for the script; a bad argument or file: a message, exit 2.
#include "post/wall_series.h"

#include <algorithm>
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

#include <vtkDataArray.h>
#include <vtkDoubleArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLPolyDataReader.h>
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

// The Poiseuille flow of FLOW (m3/s) in a pipe of radius RADIUS (m) along +z, at `x` (m):
// u = 2Q/A (1 - r^2/R^2), zero outside R.
Vec3 poiseuille(const Vec3& x, double radius, double flow) {
  const double peak = 2.0 * flow / (std::numbers::pi * radius * radius);
  const double r2 = x.x() * x.x() + x.y() * x.y();
  return Vec3(0, 0, std::max(0.0, peak * (1.0 - r2 / (radius * radius))));
}

int openfoam_fields(const fs::path& dir, double radius, double flow) {
  const std::string c = read_text(dir / "0" / "C");
  auto poiseuille_at = [&](const std::vector<Vec3>& centres) {
    std::vector<Vec3> u(centres.size());
    for (std::size_t i = 0; i < u.size(); ++i) u[i] = poiseuille(centres[i], radius, flow);
    return u;
  };
  std::ofstream u(dir / "0" / "U");
  u << header("volVectorField", "U") << "dimensions [0 1 -1 0 0 0 0];\ninternalField ";
  write_vectors(u, poiseuille_at(internal_vectors(c, "0/C")));
  u << ";\nboundaryField\n{\n    inlet\n    {\n        type fixedValue;\n        value ";
  write_vectors(u, poiseuille_at(patch_vectors(c, "inlet", "0/C")));
  u << ";\n    }\n    outlet_1\n    {\n        type pressureInletOutletVelocity;\n        value uniform (0 0 0);\n"
       "    }\n    wall\n    {\n        type noSlip;\n    }\n}\n";
  std::ofstream p(dir / "0" / "p");
  p << header("volScalarField", "p")
    << "dimensions [0 2 -2 0 0 0 0];\ninternalField uniform 0;\nboundaryField\n{\n"
       "    inlet\n    {\n        type zeroGradient;\n    }\n"
       "    outlet_1\n    {\n        type fixedValue;\n        value uniform 0;\n    }\n"
       "    wall\n    {\n        type zeroGradient;\n    }\n}\n";
  if (!u || !p) throw std::runtime_error("cannot write the fields in " + (dir / "0").string());
  std::printf("peak_velocity_m_s %.6g\n", poiseuille(Vec3::Zero(), radius, flow).z());
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

// ---- svMultiPhysics ----

int svfsi_initial(const std::string& mesh, const std::string& out, double radius, double flow) {
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  reader->SetFileName(mesh.c_str());
  reader->Update();
  vtkUnstructuredGrid* grid = reader->GetOutput();
  if (grid == nullptr || grid->GetNumberOfPoints() == 0)
    throw std::runtime_error("cannot read a mesh from " + mesh);
  vtkNew<vtkDoubleArray> velocity;
  velocity->SetName("Velocity");
  velocity->SetNumberOfComponents(3);
  velocity->SetNumberOfTuples(grid->GetNumberOfPoints());
  for (vtkIdType i = 0; i < grid->GetNumberOfPoints(); ++i) {
    double x[3];
    grid->GetPoint(i, x);
    const Vec3 u = poiseuille(Vec3(x[0], x[1], x[2]), radius, flow);
    velocity->SetTuple3(i, u.x(), u.y(), u.z());
  }
  grid->GetPointData()->AddArray(velocity);
  vtkNew<vtkXMLUnstructuredGridWriter> writer;
  writer->SetFileName(out.c_str());
  writer->SetInputData(grid);
  writer->SetDataModeToBinary();
  if (writer->Write() != 1) throw std::runtime_error("cannot write " + out);
  std::printf("nodes %lld\n", static_cast<long long>(grid->GetNumberOfPoints()));
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
    if (a.size() == 5 && a[0] == "svfsi-initial")
      return svfsi_initial(a[1], a[2], std::stod(a[3]), std::stod(a[4]));
    if (a.size() == 2 && a[0] == "svfsi-steps") return svfsi_steps(a[1]);
    if (a.size() == 5 && a[0] == "svfsi-wss") return svfsi_wss(a[1], a[2], std::stod(a[3]), std::stod(a[4]));
    std::fprintf(stderr, "usage: see the comment at the top of bench/flow_peers.cpp\n");
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_flow_peers: %s\n", e.what());
    return 2;
  }
}
