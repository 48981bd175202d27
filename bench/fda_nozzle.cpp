// The FDA nozzle (issue 8's validation): `vesselmesh simulate`'s result on the nozzle of
// `vesselmesh synth nozzle` against the FDA's measurements (conformance files of the five
// laboratories, Re_throat = 500): the centerline axial velocity and the wall pressure along z.
//   bench_fda_nozzle RESULT_DIR EXPERIMENT_DIR OUT_DIR
//   bench_fda_nozzle --series FINE_OUT MEDIUM_OUT COARSE_OUT SERIES_OUT
// RESULT_DIR: simulate's output folder (the last frame of fluid.pvd is compared; the one before,
// when there is one, says how steady it was). EXPERIMENT_DIR: the unzipped `experiment/` folder
// (PIV_*_500_<lab>.txt; z in m, flow along +z). Prints the tables and the summary; writes
// OUT_DIR/centerline_velocity.csv, wall_pressure.csv and their charts (SVG and PNG). The mesh is in mm
// (as synth writes it). Pressures are compared as differences from the most downstream tap every
// laboratory has (the measurements are gauge pressures with each laboratory's own zero).
// --series: three levels' OUT_DIRs (their CSVs, and RESULT_DIR = OUT_DIR/flow for the point counts),
// finest first: per station the three values, the observed order, the extrapolated value and the
// finest level's GCI (study/gci.h, Celik et al. 2008), whether each level lies within the
// laboratories' range, and each level's RMS difference; SERIES_OUT/series_velocity.csv and .svg/.png.
#include "io/atomic_file.h"
#include "mesh/error.h"
#include "post/fluid_sample.h"
#include "study/chart.h"
#include "study/gci.h"
#include "study/raster.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <set>
#include <sstream>

namespace {

using namespace vesselmesh;
using Curve = std::vector<std::pair<double, double>>;  // (z in mm, value), increasing z

// The throat's mean velocity at the data files' flow, m/s: Q / (pi r_t^2), the RMS differences' scale.
const double throat_mean = 5.20624e-6 / (M_PI * 4e-6);

// The rows of section `keyword` of a conformance file (none when the laboratory has none).
Curve read_section(const std::filesystem::path& file, const std::string& keyword, double z_scale) {
  std::ifstream in(file);
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream words(line);
    std::string first;
    words >> first;
    if (first != keyword) continue;
    int count = 0;
    if (!std::getline(in, line) || !(std::istringstream(line) >> count) || count < 0)
      throw InputError(fmt::format("{}: section {} has no row count", file.string(), keyword));
    Curve curve;
    for (int i = 0; i < count && std::getline(in, line); ++i) {
      double z = 0.0, value = 0.0;
      if (!(std::istringstream(line) >> z >> value))
        throw InputError(fmt::format("{}: row {} of {} is not two numbers: {}", file.string(), i + 1, keyword, line));
      curve.emplace_back(z * z_scale, value);
    }
    std::sort(curve.begin(), curve.end());
    return curve;
  }
  return {};
}

struct Lab {
  std::string code;
  Curve velocity, pressure;
};

std::vector<Lab> read_labs(const std::string& folder) {
  std::vector<std::filesystem::path> files;
  for (const auto& entry : std::filesystem::directory_iterator(folder))
    if (entry.path().extension() == ".txt") files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  std::vector<Lab> labs;
  for (const auto& file : files) {
    Lab lab;
    const std::string stem = file.stem().string();
    lab.code = stem.substr(stem.rfind('_') + 1);
    lab.velocity = read_section(file, "plot-z-distribution-axial-velocity", 1e3);
    lab.pressure = read_section(file, "plot-wall-distribution-pressure", 1e3);
    labs.push_back(lab);
  }
  if (labs.empty()) throw InputError(fmt::format("{}: no laboratory files (*.txt)", folder));
  return labs;
}

// The wall pressure at z: the mean over the wall's points within `window` mm of z.
double wall_pressure(const post::FluidField& f, const std::vector<int>& wall_points, double z, double window) {
  double sum = 0.0;
  int n = 0;
  for (int v : wall_points)
    if (std::abs(f.mesh.points[v].z() - z) <= window) sum += f.pressure[v], ++n;
  return n ? sum / n : std::nan("");
}

struct Stats {
  double mean = 0.0, low = 0.0, high = 0.0;
  int labs = 0;
};

// The laboratories' values at z (those that measured there).
Stats at(const std::vector<Lab>& labs, Curve Lab::*which, double z, const std::map<std::string, double>& offset = {}) {
  Stats s{0.0, 1e300, -1e300, 0};
  for (const Lab& lab : labs)
    for (const auto& [zz, v] : lab.*which)
      if (std::abs(zz - z) < 1e-6) {
        const double value = v - (offset.count(lab.code) ? offset.at(lab.code) : 0.0);
        s.mean += value, s.low = std::min(s.low, value), s.high = std::max(s.high, value), ++s.labs;
      }
  if (s.labs) s.mean /= s.labs;
  return s;
}

std::vector<double> stations(const std::vector<Lab>& labs, Curve Lab::*which) {
  std::vector<double> z;
  for (const Lab& lab : labs)
    for (const auto& row : lab.*which) z.push_back(row.first);
  std::sort(z.begin(), z.end());
  z.erase(std::unique(z.begin(), z.end(), [](double a, double b) { return std::abs(a - b) < 1e-6; }), z.end());
  return z;
}

int run(int argc, char** argv) {
  if (argc != 4) {
    std::cerr << "usage: bench_fda_nozzle RESULT_DIR EXPERIMENT_DIR OUT_DIR\n";
    return 2;
  }
  const std::string results = argv[1], experiment = argv[2], out = argv[3];
  std::filesystem::create_directories(out);
  const std::vector<Lab> labs = read_labs(experiment);
  const post::WallSeries series = post::read_wall_series(results, "fluid");
  if (series.length_unit != "mm") throw InputError(fmt::format("{}: the mesh is in {}, not mm", results, series.length_unit));
  const post::FluidField field = post::read_fluid_frame(series.frames.back());
  const post::TetLocator locator(field.mesh);
  // The wall's points: those of the volume the wall's own frame (DIR/wall.pvd) holds, matched by
  // their coordinates (the volume's frames hold its tetrahedra only).
  std::vector<int> wall_points;
  {
    std::set<std::array<double, 3>> on_wall;
    for (const Vec3& q : post::read_wall_frame(post::read_wall_series(results).frames.back()).mesh.points)
      on_wall.insert({q.x(), q.y(), q.z()});
    for (size_t v = 0; v < field.mesh.points.size(); ++v) {
      const Vec3& q = field.mesh.points[v];
      if (on_wall.count({q.x(), q.y(), q.z()})) wall_points.push_back(static_cast<int>(v));
    }
    if (wall_points.empty())
      throw InputError(fmt::format("{}: no point of the wall's frame is a point of the volume's", results));
  }
  fmt::print("result: {} (t = {:g} s, {} points, {} tetrahedra); {} laboratories\n", results, field.time,
             field.mesh.points.size(), locator.tets().size(), labs.size());

  // Centerline velocity.
  const auto axial = [&](const post::FluidField& f, double z) {
    const post::FluidSample s = post::sample_points(f, locator, {Vec3(0.0, 0.0, z)})[0];
    return s.inside ? s.velocity.z() : std::nan("");
  };
  fmt::print("\ncenterline axial velocity (m/s)\n{:>9} {:>9} {:>17} {:>9} {:>9}\n", "z mm", "labs", "range", "ours",
             "diff");
  std::string csv = "z_mm,labs_mean_m_s,labs_min_m_s,labs_max_m_s,labs,ours_m_s\n";
  double sum2 = 0.0, worst = 0.0;
  int n = 0;
  for (double z : stations(labs, &Lab::velocity)) {
    const Stats s = at(labs, &Lab::velocity, z);
    const double ours = axial(field, z);
    fmt::print("{:9.2f} {:9.4f} {:8.4f}..{:<8.4f} {:9.4f} {:+9.4f}\n", z, s.mean, s.low, s.high, ours, ours - s.mean);
    csv += fmt::format("{},{},{},{},{},{}\n", z, s.mean, s.low, s.high, s.labs, ours);
    if (std::isfinite(ours)) sum2 += (ours - s.mean) * (ours - s.mean), worst = std::max(worst, std::abs(ours - s.mean)), ++n;
  }
  fmt::print("centerline velocity: RMS difference from the labs' mean {:.4f} m/s ({:.1f} % of the throat's mean "
             "velocity {:.4f} m/s), worst {:.4f} m/s, over {} stations\n",
             std::sqrt(sum2 / std::max(n, 1)), 100 * std::sqrt(sum2 / std::max(n, 1)) / throat_mean, throat_mean, worst, n);
  io::write_text(out + "/centerline_velocity.csv", csv);

  // Steadiness: the last frame against the one before.
  if (series.frames.size() >= 2) {
    const post::FluidField before = post::read_fluid_frame(series.frames[series.frames.size() - 2]);
    double change = 0.0;
    for (double z : stations(labs, &Lab::velocity)) {
      const double a = axial(field, z), b = axial(before, z);
      if (std::isfinite(a) && std::isfinite(b)) change = std::max(change, std::abs(a - b));
    }
    fmt::print("steadiness: the centerline velocity changed by at most {:.4f} m/s from t = {:g} s to {:g} s\n", change,
               before.time, field.time);
  }

  // Wall pressure, as differences from the most downstream tap every laboratory has.
  double reference = 1e300;
  for (const Lab& lab : labs)
    if (!lab.pressure.empty()) reference = std::min(reference, lab.pressure.back().first);
  std::map<std::string, double> offset;
  for (const Lab& lab : labs)
    for (const auto& [z, p] : lab.pressure)
      if (std::abs(z - reference) < 1e-6) offset[lab.code] = p;
  const double window = 0.5;  // mm
  const double ours_reference = wall_pressure(field, wall_points, reference, window);
  fmt::print("\nwall pressure (Pa), relative to z = {:g} mm\n{:>9} {:>9} {:>17} {:>9} {:>9}\n", reference, "z mm",
             "labs", "range", "ours", "diff");
  csv = "z_mm,labs_mean_Pa,labs_min_Pa,labs_max_Pa,labs,ours_Pa\n";
  double drop_labs = 0.0, drop_ours = 0.0;
  const std::vector<double> taps = stations(labs, &Lab::pressure);
  for (double z : taps) {
    const Stats s = at(labs, &Lab::pressure, z, offset);
    const double ours = wall_pressure(field, wall_points, z, window) - ours_reference;
    fmt::print("{:9.2f} {:9.2f} {:8.2f}..{:<8.2f} {:9.2f} {:+9.2f}\n", z, s.mean, s.low, s.high, ours, ours - s.mean);
    csv += fmt::format("{},{},{},{},{},{}\n", z, s.mean, s.low, s.high, s.labs, ours);
    if (z == taps.front()) drop_labs = s.mean, drop_ours = ours;
  }
  fmt::print("pressure drop from z = {:g} mm to z = {:g} mm: labs' mean {:.1f} Pa, ours {:.1f} Pa ({:+.1f} %)\n",
             taps.front(), reference, drop_labs, drop_ours, 100 * (drop_ours - drop_labs) / drop_labs);
  io::write_text(out + "/wall_pressure.csv", csv);

  // Charts: the laboratories as dashed lines, ours sampled finely.
  for (int which = 0; which < 2; ++which) {
    study::LineChart chart;
    chart.x_label = "z (mm), flow along +z";
    chart.title = which == 0 ? "FDA nozzle, Re_throat = 500: centerline axial velocity"
                             : fmt::format("FDA nozzle, Re_throat = 500: wall pressure relative to z = {:g} mm", reference);
    chart.y_label = which == 0 ? "velocity (m/s)" : "pressure (Pa)";
    for (const Lab& lab : labs) {
      study::Series s{.name = "lab " + lab.code, .x = {}, .y = {}, .dashed = true};
      for (const auto& [z, v] : which == 0 ? lab.velocity : lab.pressure) {
        s.x.push_back(z);
        s.y.push_back(which == 0 ? v : v - offset[lab.code]);
      }
      if (!s.x.empty()) chart.series.push_back(s);
    }
    study::Series ours{.name = "vesselmesh", .x = {}, .y = {}, .dashed = false};
    const double z0 = which == 0 ? -100.0 : taps.front(), z1 = which == 0 ? 100.0 : reference;
    for (int i = 0; i <= 400; ++i) {
      const double z = z0 + (z1 - z0) * i / 400.0;
      ours.x.push_back(z);
      ours.y.push_back(which == 0 ? axial(field, z) : wall_pressure(field, wall_points, z, window) - ours_reference);
    }
    chart.series.push_back(ours);
    study::write_svg_and_png(out + (which == 0 ? "/centerline_velocity" : "/wall_pressure"), study::svg(chart));
  }
  fmt::print("\nwrote {}/centerline_velocity.csv|svg|png, wall_pressure.csv|svg|png\n", out);
  return 0;
}

// The rows of a CSV this program wrote (a header line, then numbers).
std::vector<std::vector<double>> read_csv(const std::string& path) {
  std::istringstream in(io::read_file(path));
  std::string line;
  std::getline(in, line);
  std::vector<std::vector<double>> rows;
  while (std::getline(in, line)) {
    std::vector<double> row;
    std::istringstream cells(line);
    for (std::string cell; std::getline(cells, cell, ',');) row.push_back(std::stod(cell));
    rows.push_back(row);
  }
  return rows;
}

int series(int argc, char** argv) {
  if (argc != 6) {
    std::cerr << "usage: bench_fda_nozzle --series FINE_OUT MEDIUM_OUT COARSE_OUT SERIES_OUT\n";
    return 2;
  }
  const std::array<std::string, 3> level = {argv[2], argv[3], argv[4]};
  const std::string out = argv[5];
  std::array<double, 3> points{};
  std::array<std::vector<std::vector<double>>, 3> velocity;
  for (int k = 0; k < 3; ++k) {
    points[k] = nlohmann::json::parse(io::read_file(level[k] + "/flow/summary.json"))["points"].get<double>();
    velocity[k] = read_csv(level[k] + "/centerline_velocity.csv");  // z, mean, min, max, labs, ours
    if (velocity[k].size() != velocity[0].size()) throw InputError(level[k] + ": other stations than the finest's");
  }
  fmt::print("levels (finest first): {:.0f}, {:.0f}, {:.0f} points; r21 = {:.3f}, r32 = {:.3f} (in h = N^-1/3)\n",
             points[0], points[1], points[2], std::cbrt(points[0] / points[1]), std::cbrt(points[1] / points[2]));
  fmt::print("{:>7} {:>8} {:>17} {:>8} {:>8} {:>8} {:>6} {:>9} {:>8}  {}\n", "z mm", "labs", "range", "fine", "medium",
             "coarse", "p", "extrap.", "GCI", "status");
  std::string csv = "z_mm,labs_mean_m_s,labs_min_m_s,labs_max_m_s,fine_m_s,medium_m_s,coarse_m_s,order,extrapolated_m_s,"
                    "gci_fine_percent\n";
  std::array<double, 3> sum2{};
  std::array<int, 3> within{};
  const size_t n = velocity[0].size();
  for (size_t i = 0; i < n; ++i) {
    const std::vector<double>& row = velocity[0][i];
    const double mean = row[1], low = row[2], high = row[3];
    std::array<double, 3> v{};
    for (int k = 0; k < 3; ++k) {
      v[k] = velocity[k][i][5];
      sum2[k] += (v[k] - mean) * (v[k] - mean);
      within[k] += low <= v[k] && v[k] <= high;
    }
    const study::GridConvergence g = study::grid_convergence(points[0], points[1], points[2], v[0], v[1], v[2]);
    fmt::print("{:7.1f} {:8.4f} {:8.4f}..{:<8.4f} {:8.4f} {:8.4f} {:8.4f} {:6.2f} {:9.4f} {:7.2f}%  {}\n", row[0], mean,
               low, high, v[0], v[1], v[2], g.order, g.extrapolated, 100 * g.gci_fine, g.status);
    csv += fmt::format("{},{},{},{},{},{},{},{},{},{}\n", row[0], mean, low, high, v[0], v[1], v[2], g.order,
                       g.extrapolated, 100 * g.gci_fine);
  }
  for (int k = 0; k < 3; ++k)
    fmt::print("{}: RMS difference from the labs' mean {:.1f} % of the throat's mean velocity, {} of {} stations within "
               "the labs' range\n",
               level[k], 100 * std::sqrt(sum2[k] / n) / throat_mean, within[k], n);
  std::filesystem::create_directories(out);
  io::write_text(out + "/series_velocity.csv", csv);
  study::LineChart chart;
  chart.title = "FDA nozzle, Re_throat = 500: centerline axial velocity on three meshes";
  chart.x_label = "z (mm), flow along +z";
  chart.y_label = "velocity (m/s)";
  study::Series low{.name = "labs' lowest", .x = {}, .y = {}, .dashed = true},
      high{.name = "labs' highest", .x = {}, .y = {}, .dashed = true};
  for (const std::vector<double>& row : velocity[0]) {
    low.x.push_back(row[0]), low.y.push_back(row[2]);
    high.x.push_back(row[0]), high.y.push_back(row[3]);
  }
  chart.series = {low, high};
  for (int k = 0; k < 3; ++k) {
    study::Series s{.name = fmt::format("{:.0f} points", points[k]), .x = {}, .y = {}, .dashed = false};
    for (const std::vector<double>& row : velocity[k]) s.x.push_back(row[0]), s.y.push_back(row[5]);
    chart.series.push_back(s);
  }
  study::write_svg_and_png(out + "/series_velocity", study::svg(chart));
  fmt::print("wrote {}/series_velocity.csv|svg|png\n", out);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    if (argc > 1 && std::string(argv[1]) == "--series") return series(argc, argv);
    return run(argc, argv);
  } catch (const std::exception& e) {
    std::cerr << "bench_fda_nozzle: " << e.what() << "\n";
    return 1;
  }
}
