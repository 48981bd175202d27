// The FDA nozzle (issue 8's and 47's validation): `vesselmesh simulate`'s result on the nozzle of
// `vesselmesh synth nozzle` against the FDA's measurements (conformance files of the laboratories,
// sudden-expansion orientation, any Reynolds number: the flow rate is the files'): the centerline
// axial velocity, the wall pressure, the radial profiles of axial velocity at the stations and the
// wall shear stress, each against every laboratory.
//   bench_fda_nozzle RESULT_DIR EXPERIMENT_DIR OUT_DIR
//   bench_fda_nozzle --series FINE_OUT MEDIUM_OUT COARSE_OUT SERIES_OUT
// RESULT_DIR: simulate's output folder (the last frame of fluid.pvd is compared; the one before,
// when there is one, says how steady it was; a run with time statistics: their means, and the wall
// shear stress's time mean over the same span, indices.vtp's mean_wss). EXPERIMENT_DIR: the
// unzipped `experiment/` folder (*_<lab>.txt; z in m, flow along +z). Prints the tables and the summary; writes
// OUT_DIR/comparison.json (the figures), centerline_velocity.csv, wall_pressure.csv,
// velocity_profiles.csv, wall_shear_stress.csv and their charts (SVG and PNG; profile_z<Z> a
// station's profiles). The mesh is in mm (as synth writes it). Pressures are compared as
// differences from the most downstream tap every laboratory has (the measurements are gauge
// pressures with each laboratory's own zero); profiles as the mean of ours along four directions at
// each measured radius (the nozzle is axisymmetric); the wall shear stress as its magnitude, the
// mean over the side wall within 0.5 mm of each station (on the step, z = 0, the throat's wall).
// --series: three levels' OUT_DIRs (their CSVs and comparison.json, and RESULT_DIR = OUT_DIR/flow
// for the point counts), finest first: per station the three values, the observed order, the
// extrapolated value and the finest level's GCI (study/gci.h, Celik et al. 2008), whether each
// level lies within the laboratories' range, and each level's RMS difference and other figures;
// SERIES_OUT/series_velocity.csv and .svg/.png.
#include "io/atomic_file.h"
#include "io/conformance.h"
#include "io/vtk_formats.h"
#include "mesh/error.h"
#include "post/fluid_sample.h"
#include "post/wall_series.h"
#include "study/chart.h"
#include "study/gci.h"
#include "study/raster.h"
#include "synth/shapes.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <functional>
#include <iostream>
#include <map>
#include <optional>
#include <set>
#include <sstream>

namespace {

using namespace vesselmesh;
using Curve = std::vector<std::pair<double, double>>;  // (z in mm, value), increasing z

struct Lab {
  std::string code;  // the laboratory's, and " LDV" for its LDV file
  Curve velocity, pressure,
      wss;  // along z: centerline axial velocity, wall pressure, wall shear stress
  Curve axial_sd, radial_sd;  // along z: the standard deviation of the axial and radial velocity on
                              // the centerline (m/s; the LDV file's profiles on the axis)
  std::map<double, Curve> profiles;  // z mm -> (signed radius mm, axial velocity m/s)
  double flow = 0.0;                 // m^3/s
};

// A profile's value on the axis (its point within 0.25 mm of it, the nearest), if it has one.
std::optional<double> on_axis(const Curve& profile) {
  const auto nearest = std::min_element(
      profile.begin(), profile.end(),
      [](const auto& a, const auto& b) { return std::abs(a.first) < std::abs(b.first); });
  if (nearest == profile.end() || std::abs(nearest->first) > 0.25) return std::nullopt;
  return nearest->second;
}

// The laboratories' files of a folder (*.txt, each lab's code the last word of its name); all must
// give the same flow rate. A laboratory without a centerline section (the LDV file) has its
// profiles' values on the axis for it.
std::vector<Lab> read_labs(const std::string& folder) {
  if (!std::filesystem::is_directory(folder))
    throw InputError(fmt::format("{}: no such folder (the measurements' experiment/ folder, unzipped)", folder));
  std::vector<std::filesystem::path> files;
  for (const auto& entry : std::filesystem::directory_iterator(folder))
    if (entry.path().extension() == ".txt") files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  std::vector<Lab> labs;
  for (const auto& file : files) {
    Lab lab;
    const std::string stem = file.stem().string();
    lab.code = stem.substr(stem.rfind('_') + 1) + (stem.rfind("LDV", 0) == 0 ? " LDV" : "");
    const io::ConformanceFile data = io::read_conformance(file.string());
    if (data.sections.empty()) {  // another format
      fmt::print("{}: no plot- section (not a conformance file), left out\n",
                 file.filename().string());
      continue;
    }
    lab.flow = data.flow;
    for (const io::ConformanceSection& s : data.sections) {
      Curve rows;  // positions in mm, increasing
      for (const auto& [position, value] : s.rows) rows.emplace_back(position * 1e3, value);
      std::sort(rows.begin(), rows.end());
      if (s.keyword == "plot-z-distribution-axial-velocity") lab.velocity = rows;
      if (s.keyword == "plot-wall-distribution-pressure") lab.pressure = rows;
      if (s.keyword == "plot-wall-distribution-wall-shear-stress") lab.wss = rows;
      if (s.parameters.empty()) continue;
      const double z = std::round(s.parameters[0] * 1e4) / 10;  // the station in mm, to 0.1 mm
      if (s.keyword == "plot-profile-axial-velocity-at-z") lab.profiles[z] = rows;
      for (auto [keyword, sd] :
           {std::pair{"plot-profile-axial-velocity-stdev-at-z", &Lab::axial_sd},
            {"plot-profile-radial-velocity-stdev-at-z", &Lab::radial_sd}})
        if (const std::optional<double> v = on_axis(rows); s.keyword == keyword && v)
          (lab.*sd).emplace_back(z, *v);
    }
    if (lab.velocity.empty())
      for (const auto& [z, rows] : lab.profiles)
        if (const std::optional<double> v = on_axis(rows)) lab.velocity.emplace_back(z, *v);
    std::sort(lab.axial_sd.begin(), lab.axial_sd.end());
    std::sort(lab.radial_sd.begin(), lab.radial_sd.end());
    if (lab.flow <= 0.0)
      throw InputError(fmt::format("{}: no fluid-volumetric-flow-rate", file.string()));
    labs.push_back(std::move(lab));
  }
  if (labs.empty()) throw InputError(fmt::format("{}: no laboratory files (*.txt)", folder));
  // By code: a laboratory's PIV file (the flow rate to five digits) before its LDV file (to three).
  std::stable_sort(labs.begin(), labs.end(),
                   [](const Lab& a, const Lab& b) { return a.code < b.code; });
  for (const Lab& lab : labs)
    if (std::abs(lab.flow - labs[0].flow) > 5e-3 * labs[0].flow)
      throw InputError(fmt::format("{}: lab {}'s flow rate is {:g} m^3/s, lab {}'s {:g}", folder,
                                   lab.code, lab.flow, labs[0].code, labs[0].flow));
  return labs;
}

// The nozzle's wall radius at a station, mm; on the step (z = 0) the throat's, as the
// laboratories' wall values there are the throat's.
double station_radius(double z) {
  return synth::nozzle_radius(synth::NozzleOptions{}, z - 1e-6);
}

struct Stats {
  double mean = 0.0, low = 0.0, high = 0.0;
  int labs = 0;  // rows: a laboratory that measured two walls counts twice
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

// A curve's value at station z, NaN where it has none.
double value_at(const Curve& curve, double z) {
  for (const auto& [zz, v] : curve)
    if (std::abs(zz - z) < 1e-6) return v;
  return std::nan("");
}

std::vector<double> stations(const std::vector<Lab>& labs, Curve Lab::*which) {
  std::vector<double> z;
  for (const Lab& lab : labs)
    for (const auto& row : lab.*which) z.push_back(row.first);
  std::sort(z.begin(), z.end());
  z.erase(std::unique(z.begin(), z.end(), [](double a, double b) { return std::abs(a - b) < 1e-6; }), z.end());
  return z;
}

double rms(double sum2, int n) {
  return n ? std::sqrt(sum2 / n) : std::nan("");
}

// The run's time statistics, when it kept them (its summary.json names them).
std::optional<post::FluidStatistics> statistics_of(const std::string& results) {
  const std::string summary = results + "/summary.json";
  if (!std::filesystem::exists(summary) ||
      !nlohmann::json::parse(io::read_file(summary)).contains("statistics"))
    return std::nullopt;
  return post::read_fluid_statistics(results);
}

// The wall's time-mean shear stress over the statistics' span (the indices' `mean_wss`, which a run with
// statistics and no period takes over that span), else the wall's last frame (with a note why).
struct OurWall {
  post::WallField field;
  bool time_mean = false;
};
OurWall wall_of(const std::string& results, bool with_statistics) {
  const auto last = [&] { return OurWall{post::read_wall_frame(post::read_wall_series(results).frames.back())}; };
  if (!with_statistics) return last();
  const nlohmann::json j = nlohmann::json::parse(io::read_file(results + "/summary.json"));
  const nlohmann::json& stats = j["statistics"];
  const double span = stats.value("end_s", 0.0) - stats.value("start_s", 0.0);
  const double start = j.contains("indices") ? j["indices"].value("start_s", -1.0) : -1.0;
  if (std::abs(start - stats.value("start_s", 0.0)) <= 0.05 * span) {
    io::SurfaceData data = io::read_vtk_surface(results + "/" + j["indices"].value("file", std::string()),
                                                io::VtkFormat::vtp);
    if (const Field* mean = find_field(data.point_data, "mean_wss", 3, data.mesh.points.size())) {
      post::WallField w;
      w.wss = mean->vectors();
      w.mesh = std::move(data.mesh);
      return {std::move(w), true};
    }
  }
  fmt::print("{}: no time-mean wall shear stress over the statistics' span (a run before it was written): the "
             "wall's last frame is compared\n", results);
  return last();
}

// What the comparisons share: the laboratories, our flow (the time means when the run kept its
// statistics, else the last frame, and the one before when saved), the wall (its time mean over the
// statistics' span, else its last frame), and the figures and tables gathered for comparison.json and
// comparison.md.
struct Comparison {
  std::vector<Lab> labs;
  post::WallSeries series;
  std::optional<post::FluidStatistics> statistics;  // its mean moved into `field`
  post::FluidField field;
  post::TetLocator locator;
  OurWall wall;
  double throat_mean = 0.0;      // m/s: the flow rate over the throat's area, the RMS differences' scale
  std::string out;
  nlohmann::json summary;
  std::string markdown;  // the tables, for docs/validation/fda_nozzle.md

  Comparison(const std::string& results, const std::string& experiment, std::string out_dir)
      : labs(read_labs(experiment)),
        series(post::read_wall_series(results, "fluid")),
        statistics(statistics_of(results)),
        field(statistics ? std::move(statistics->mean)
                         : post::read_fluid_frame(series.frames.back())),
        locator(field.mesh),
        wall(wall_of(results, statistics.has_value())),
        throat_mean(labs[0].flow / (M_PI * 4e-6)),
        out(std::move(out_dir)) {
    if (series.length_unit != "mm")
      throw InputError(fmt::format("{}: the mesh is in {}, not mm", results, series.length_unit));
    if (wall.field.wss.size() != wall.field.mesh.points.size() || wall.field.mesh.points.empty())
      throw InputError(fmt::format("{}: the wall has no wall shear stress on its points", results));
  }

  // Our axial velocity at (x, y, z), NaN outside the mesh.
  double axial(const post::FluidField& f, double x, double y, double z) const {
    const post::FluidSample s = post::sample_points(f, locator, {Vec3(x, y, z)})[0];
    return s.inside ? s.velocity.z() : std::nan("");
  }
  // The RMS of our velocity's fluctuation at (x, y, z), per component (m/s); NaN outside the mesh
  // or without statistics.
  Vec3 fluctuation(double x, double y, double z) const {
    const std::optional<post::TetLocator::Hit> hit = locator.locate(Vec3(x, y, z));
    if (!hit || !statistics) return Vec3::Constant(std::nan(""));
    return locator.interpolate(*hit, statistics->rms);
  }
  // At signed radius r of station z: the mean over four directions (x, y, -x, -y), those inside.
  double axial_at_radius(double r, double z) const {
    double sum = 0.0;
    int n = 0;
    for (const auto& [cx, cy] : {std::pair{1.0, 0.0}, {0.0, 1.0}, {-1.0, 0.0}, {0.0, -1.0}})
      if (const double u = axial(field, cx * r, cy * r, z); std::isfinite(u)) sum += u, ++n;
    return n ? sum / n : std::nan("");
  }
  // The wall pressure at z: the mean of the pressure at 0.98 of the station's radius along eight
  // directions, those inside (a tap reads the pressure where it is; a mean over the wall's points
  // within a window blurs the drops at the throat's corners; 2 % inside the wall keeps the points
  // within the faceted wall of 16 or more edges around).
  double wall_pressure(double z) const {
    const double r = 0.98 * station_radius(z);
    double sum = 0.0;
    int n = 0;
    for (int k = 0; k < 8; ++k) {
      const Vec3 p(r * std::cos(k * M_PI / 4), r * std::sin(k * M_PI / 4), z);
      if (const post::FluidSample s = post::sample_points(field, locator, {p})[0]; s.inside) sum += s.pressure, ++n;
    }
    return n ? sum / n : std::nan("");
  }
  // The wall shear stress's magnitude at z: the mean over the wall's points within `window` mm of
  // z on the station's side wall (within 0.3 mm of its radius: the step's face left out).
  double wall_shear(double z, double window = 0.5) const {
    const double radius = station_radius(z);
    double sum = 0.0;
    int n = 0;
    for (size_t v = 0; v < wall.field.mesh.points.size(); ++v) {
      const Vec3& q = wall.field.mesh.points[v];
      if (std::abs(q.z() - z) <= window && std::abs(std::hypot(q.x(), q.y()) - radius) < 0.3)
        sum += wall.field.wss[v].norm(), ++n;
    }
    return n ? sum / n : std::nan("");
  }
};

// A chart of the laboratories' curves (dashed) and ours.
void write_chart(const std::string& stem, const std::string& title, const std::string& x_label,
                 const std::string& y_label, std::vector<study::Series> labs, study::Series ours) {
  study::LineChart chart;
  chart.title = title, chart.x_label = x_label, chart.y_label = y_label;
  chart.series = std::move(labs);
  chart.series.push_back(std::move(ours));
  study::write_svg_and_png(stem, study::svg(chart));
}

// A chart along z: each laboratory's curve `which` (less its offset, where given) and ours from z0
// to z1.
void write_chart_along_z(const Comparison& c, const std::string& name, const std::string& title,
                         const std::string& y_label, Curve Lab::*which, const std::map<std::string, double>& offset,
                         double z0, double z1, const std::function<double(double)>& ours_at) {
  std::vector<study::Series> labs;
  for (const Lab& lab : c.labs) {
    study::Series s{.name = "lab " + lab.code, .x = {}, .y = {}, .dashed = true};
    const double shift = offset.count(lab.code) ? offset.at(lab.code) : 0.0;
    for (const auto& [z, v] : lab.*which) s.x.push_back(z), s.y.push_back(v - shift);
    if (!s.x.empty()) labs.push_back(s);
  }
  study::Series ours{.name = "vesselmesh", .x = {}, .y = {}, .dashed = false};
  for (int i = 0; i <= 400; ++i) {
    const double z = z0 + (z1 - z0) * i / 400.0;
    ours.x.push_back(z), ours.y.push_back(ours_at(z));
  }
  write_chart(c.out + "/" + name, title, "z (mm), flow along +z", y_label, labs, ours);
}

void compare_centerline(Comparison& c) {
  const std::string re = fmt::format("Re_throat = {:.0f}", 1056.0 * c.throat_mean * 4e-3 / 0.0035);
  const std::string mean = c.statistics
                               ? fmt::format(", ours the time mean over t = {:g} to {:g} s",
                                             c.statistics->start, c.statistics->end)
                               : "";
  fmt::print("\ncenterline axial velocity (m/s{})\n{:>9} {:>9} {:>17} {:>9} {:>9}\n", mean, "z mm",
             "labs", "range", "ours", "diff");
  std::string csv = "z_mm,labs_mean_m_s,labs_min_m_s,labs_max_m_s,labs,ours_m_s\n";
  c.markdown +=
      "| centreline velocity, z (mm) | labs' mean [range] (m/s) | ours | difference "
      "|\n|---|---|---|---|\n";
  double sum2 = 0.0, worst = 0.0, downstream2 = 0.0;
  int n = 0, within = 0, downstream = 0;
  const std::vector<double> z_stations = stations(c.labs, &Lab::velocity);
  for (double z : z_stations) {
    const Stats s = at(c.labs, &Lab::velocity, z);
    const double ours = c.axial(c.field, 0.0, 0.0, z);
    fmt::print("{:9.2f} {:9.4f} {:8.4f}..{:<8.4f} {:9.4f} {:+9.4f}\n", z, s.mean, s.low, s.high, ours, ours - s.mean);
    csv += fmt::format("{},{},{},{},{},{}\n", z, s.mean, s.low, s.high, s.labs, ours);
    c.markdown += fmt::format("| {:g} | {:.3f} [{:.3f}, {:.3f}] | {:.3f}{} | {:+.3f} |\n", z, s.mean, s.low, s.high,
                              ours, s.low <= ours && ours <= s.high ? "" : " (out)", ours - s.mean);
    if (!std::isfinite(ours)) continue;
    sum2 += (ours - s.mean) * (ours - s.mean), worst = std::max(worst, std::abs(ours - s.mean)), ++n;
    within += s.low <= ours && ours <= s.high;
    if (z >= 0.0) downstream2 += (ours - s.mean) * (ours - s.mean), ++downstream;
  }
  const double downstream_percent = 100 * rms(downstream2, downstream) / c.throat_mean;
  fmt::print(
      "centerline velocity: RMS difference from the labs' mean {:.4f} m/s ({:.1f} % of the throat's mean velocity "
      "{:.4f} m/s), worst {:.4f} m/s, over {} stations; {} within the labs' range; downstream of the expansion "
      "(z >= 0) {:.1f} % over {} stations\n",
      rms(sum2, n), 100 * rms(sum2, n) / c.throat_mean, c.throat_mean, worst, n, within, downstream_percent,
      downstream);
  c.summary["centerline"] = {{"rms_percent", 100 * rms(sum2, n) / c.throat_mean},
                             {"stations", n},
                             {"within", within},
                             {"downstream_rms_percent", downstream_percent},
                             {"time_mean", c.statistics.has_value()}};
  io::write_text(c.out + "/centerline_velocity.csv", csv);

  // Each laboratory on its own: ours against it, and it against the others' mean (their spread).
  fmt::print("per laboratory (RMS over its stations, % of the throat's mean velocity):\n{:>6} {:>9} {:>12} {:>18}\n",
             "lab", "stations", "ours - lab", "lab - others' mean");
  c.markdown += fmt::format(
      "\nRMS difference {:.1f} % of the throat's mean velocity ({:.1f} % downstream of the expansion); {} of {} "
      "stations within the labs' range.\n\n| laboratory | stations | ours − lab (RMS, % of the throat's mean) | lab − "
      "the others' mean |\n|---|---|---|---|\n",
      100 * rms(sum2, n) / c.throat_mean, downstream_percent, within, n);
  for (const Lab& lab : c.labs) {
    double ours2 = 0.0, spread2 = 0.0;
    int m = 0, k = 0;
    for (const auto& [z, v] : lab.velocity) {
      if (const double ours = c.axial(c.field, 0.0, 0.0, z); std::isfinite(ours)) ours2 += (ours - v) * (ours - v), ++m;
      double others = 0.0;
      int count = 0;
      for (const Lab& other : c.labs)
        for (const auto& [zz, w] : other.velocity)
          if (&other != &lab && std::abs(zz - z) < 1e-6) others += w, ++count;
      if (count) spread2 += (v - others / count) * (v - others / count), ++k;
    }
    if (lab.velocity.empty()) continue;
    fmt::print("{:>6} {:>9} {:>11.1f}% {:>17.1f}%\n", lab.code, lab.velocity.size(),
               100 * rms(ours2, m) / c.throat_mean, 100 * rms(spread2, k) / c.throat_mean);
    c.markdown += fmt::format("| {} | {} | {:.1f} % | {:.1f} % |\n", lab.code, lab.velocity.size(),
                              100 * rms(ours2, m) / c.throat_mean, 100 * rms(spread2, k) / c.throat_mean);
    c.summary["centerline"]["labs"][lab.code] = {{"ours_rms_percent", 100 * rms(ours2, m) / c.throat_mean},
                                                 {"spread_rms_percent", 100 * rms(spread2, k) / c.throat_mean}};
  }

  // Steadiness: the last frame against the one before (not of time means).
  if (c.series.frames.size() >= 2 && !c.statistics) {
    const post::FluidField before =
        post::read_fluid_frame(c.series.frames[c.series.frames.size() - 2]);
    double change = 0.0;
    for (double z : z_stations) {
      const double a = c.axial(c.field, 0.0, 0.0, z), b = c.axial(before, 0.0, 0.0, z);
      if (std::isfinite(a) && std::isfinite(b)) change = std::max(change, std::abs(a - b));
    }
    fmt::print("steadiness: the centerline velocity changed by at most {:.4f} m/s from t = {:g} s to {:g} s\n", change,
               before.time, c.field.time);
  }

  write_chart_along_z(
      c, "centerline_velocity",
      "FDA nozzle, " + re + ": centerline axial velocity" + (c.statistics ? " (time mean)" : ""),
      "velocity (m/s)", &Lab::velocity, {}, -100.0, 100.0,
      [&](double z) { return c.axial(c.field, 0.0, 0.0, z); });
}

// Where a centerline velocity u(z) first falls below `level` past the expansion (z >= 0), linear
// between its samples; NaN when it does not within them.
double first_fall(const Curve& u, double level) {
  for (size_t i = 1; i < u.size(); ++i) {
    const auto [z0, u0] = u[i - 1];
    const auto [z1, u1] = u[i];
    if (z0 >= 0.0 && u0 >= level && u1 < level) return z0 + (z1 - z0) * (u0 - level) / (u0 - u1);
  }
  return std::nan("");
}

// The jet's breakdown: where the (time-mean) centerline velocity has fallen to half the throat's
// mean velocity, ours (sampled every 0.25 mm) and each laboratory's (linear between its stations).
void compare_breakdown(Comparison& c) {
  const double level = 0.5 * c.throat_mean;
  Curve ours_curve;
  for (int i = 0; i <= 400; ++i)
    if (const double u = c.axial(c.field, 0.0, 0.0, 0.25 * i); std::isfinite(u))
      ours_curve.emplace_back(0.25 * i, u);
  const double ours = first_fall(ours_curve, level);
  fmt::print("\njet breakdown: where the centerline velocity falls to half the throat's mean velocity ({:.3f} m/s)\n",
             level);
  c.markdown += fmt::format(
      "\n| jet breakdown: the centreline velocity at half the throat's mean ({:.3f} m/s) | z (mm) |\n|---|---|\n",
      level);
  double low = 1e300, high = -1e300;
  for (const Lab& lab : c.labs) {
    if (lab.velocity.empty()) continue;
    const double z = first_fall(lab.velocity, level);
    const std::string where =
        std::isfinite(z) ? fmt::format("{:.1f}", z)
                         : fmt::format("beyond {:g} (its last station, {:.2f} m/s)",
                                       lab.velocity.back().first, lab.velocity.back().second);
    fmt::print("{:>9}: {}\n", "lab " + lab.code, where);
    c.markdown += fmt::format("| lab {} | {} |\n", lab.code, where);
    if (std::isfinite(z)) low = std::min(low, z), high = std::max(high, z);
    c.summary["breakdown"]["labs"][lab.code] =
        std::isfinite(z) ? nlohmann::json(z) : nlohmann::json(nullptr);
  }
  const bool within = low <= ours && ours <= high;
  const std::string where =
      std::isfinite(ours) ? fmt::format("{:.1f}", ours) : "not before z = 100 mm";
  fmt::print("{:>9}: {}{}\n", "ours", where, within ? " (within the labs' range)" : "");
  c.markdown += fmt::format("| **vesselmesh** | **{}**{} |\n", where,
                            within ? " (within the labs' range)" : "");
  c.summary["breakdown"]["ours_mm"] =
      std::isfinite(ours) ? nlohmann::json(ours) : nlohmann::json(nullptr);
  c.summary["breakdown"]["within"] = within;
}

// The velocity's fluctuation on the centerline (runs that kept their time statistics): our RMS of
// the axial and radial velocity's fluctuation against the laboratories' standard deviations (the
// LDV file's), beside the mean velocities, and the chart of the axial one.
void compare_fluctuations(Comparison& c) {
  if (!c.statistics)
    return fmt::print(
        "\nfluctuations: the run kept no time statistics ([output] statistics_from)\n");
  if (stations(c.labs, &Lab::axial_sd).empty())
    return fmt::print("\nfluctuations: no laboratory measured them\n");
  fmt::print(
      "\ncenterline fluctuation (m/s): standard deviation (labs) and RMS (ours) of the velocity\n");
  fmt::print("{:>9} {:>9} {:>9} {:>9} {:>9} {:>9} {:>9} {:>9}\n", "lab", "z mm", "lab mean", "ours",
             "lab axial", "ours", "lab radial", "ours");
  c.markdown +=
      "\n| centreline, z (mm) | lab | mean axial velocity: lab / ours (m/s) | axial fluctuation: lab's SD / our RMS "
      "(m/s) | radial: lab / ours |\n|---|---|---|---|---|\n";
  std::string csv =
      "lab,z_mm,lab_mean_m_s,ours_mean_m_s,lab_axial_sd_m_s,ours_axial_rms_m_s,lab_radial_sd_m_s,"
      "ours_radial_rms_m_s\n";
  for (const Lab& lab : c.labs) {
    double sum2 = 0.0;
    int n = 0;
    for (const auto& [z, sd] : lab.axial_sd) {
      const Vec3 f = c.fluctuation(0.0, 0.0, z);
      const double radial = std::sqrt(0.5 * (f.x() * f.x() + f.y() * f.y()));
      const double mean = value_at(lab.velocity, z), radial_sd = value_at(lab.radial_sd, z);
      const double ours_mean = c.axial(c.field, 0.0, 0.0, z);
      fmt::print("{:>9} {:9.1f} {:9.3f} {:9.3f} {:9.3f} {:9.3f} {:9.3f} {:9.3f}\n", lab.code, z,
                 mean, ours_mean, sd, f.z(), radial_sd, radial);
      csv += fmt::format("{},{},{},{},{},{},{},{}\n", lab.code, z, mean, ours_mean, sd, f.z(),
                         radial_sd, radial);
      c.markdown +=
          fmt::format("| {:g} | {} | {:.3f} / {:.3f} | {:.3f} / {:.3f} | {:.3f} / {:.3f} |\n", z,
                      lab.code, mean, ours_mean, sd, f.z(), radial_sd, radial);
      if (z >= 0.0 && std::isfinite(f.z())) sum2 += (f.z() - sd) * (f.z() - sd), ++n;
    }
    if (lab.axial_sd.empty()) continue;
    fmt::print(
        "lab {}: the axial fluctuation's RMS difference downstream of the expansion {:.1f} % of the throat's mean "
        "velocity over {} stations\n",
        lab.code, 100 * rms(sum2, n) / c.throat_mean, n);
    c.markdown += fmt::format(
        "\nLab {}: the axial fluctuation's RMS difference downstream of the expansion {:.1f} % of "
        "the throat's mean velocity ({} stations).\n",
        lab.code, 100 * rms(sum2, n) / c.throat_mean, n);
    c.summary["fluctuations"][lab.code] = {
        {"axial_rms_percent", 100 * rms(sum2, n) / c.throat_mean}, {"stations", n}};
  }
  io::write_text(c.out + "/centerline_fluctuation.csv", csv);
  write_chart_along_z(
      c, "centerline_fluctuation",
      "FDA nozzle: the axial velocity's fluctuation on the centerline (labs: SD; ours: RMS)",
      "fluctuation (m/s)", &Lab::axial_sd, {}, -100.0, 100.0,
      [&](double z) { return c.fluctuation(0.0, 0.0, z).z(); });
}

// Wall pressure, as differences from the most downstream tap every laboratory has.
void compare_pressure(Comparison& c) {
  double reference = 1e300;
  for (const Lab& lab : c.labs)
    if (!lab.pressure.empty()) reference = std::min(reference, lab.pressure.back().first);
  if (reference == 1e300) return fmt::print("\nwall pressure: no laboratory measured it\n");
  std::map<std::string, double> offset;
  for (const Lab& lab : c.labs)
    for (const auto& [z, p] : lab.pressure)
      if (std::abs(z - reference) < 1e-6) offset[lab.code] = p;
  const double ours_reference = c.wall_pressure(reference);
  fmt::print("\nwall pressure (Pa), relative to z = {:g} mm\n{:>9} {:>9} {:>17} {:>9} {:>9}\n", reference, "z mm",
             "labs", "range", "ours", "diff");
  std::string csv = "z_mm,labs_mean_Pa,labs_min_Pa,labs_max_Pa,labs,ours_Pa\n";
  c.markdown += fmt::format(
      "\n| wall pressure, z (mm) | labs' mean [range] (Pa, relative to z = {:g} mm) | ours | difference "
      "|\n|---|---|---|---|\n",
      reference);
  double drop_labs = 0.0, drop_ours = 0.0;
  int within = 0;
  const std::vector<double> taps = stations(c.labs, &Lab::pressure);
  for (double z : taps) {
    const Stats s = at(c.labs, &Lab::pressure, z, offset);
    const double ours = c.wall_pressure(z) - ours_reference;
    fmt::print("{:9.2f} {:9.2f} {:8.2f}..{:<8.2f} {:9.2f} {:+9.2f}\n", z, s.mean, s.low, s.high, ours, ours - s.mean);
    csv += fmt::format("{},{},{},{},{},{}\n", z, s.mean, s.low, s.high, s.labs, ours);
    c.markdown += fmt::format("| {:g} | {:.0f} [{:.0f}, {:.0f}] | {:.0f}{} | {:+.0f} |\n", z, s.mean, s.low, s.high,
                              ours, s.low <= ours && ours <= s.high ? "" : " (out)", ours - s.mean);
    within += s.low <= ours && ours <= s.high;
    if (z == taps.front()) drop_labs = s.mean, drop_ours = ours;
  }
  fmt::print(
      "pressure drop from z = {:g} mm to z = {:g} mm: labs' mean {:.1f} Pa, ours {:.1f} Pa ({:+.1f} %); {} of {} taps "
      "within the labs' range\n",
      taps.front(), reference, drop_labs, drop_ours, 100 * (drop_ours - drop_labs) / drop_labs, within, taps.size());
  c.markdown += fmt::format(
      "\nPressure drop from z = {:g} to {:g} mm: labs' mean {:.0f} Pa, ours {:.0f} Pa ({:+.1f} %); {} of {} taps "
      "within the labs' range.\n",
      taps.front(), reference, drop_labs, drop_ours, 100 * (drop_ours - drop_labs) / drop_labs, within, taps.size());
  c.summary["pressure"] = {
      {"drop_labs_Pa", drop_labs}, {"drop_ours_Pa", drop_ours}, {"taps", taps.size()}, {"within", within}};
  io::write_text(c.out + "/wall_pressure.csv", csv);
  write_chart_along_z(c, "wall_pressure", fmt::format("FDA nozzle: wall pressure relative to z = {:g} mm", reference),
                      "pressure (Pa)", &Lab::pressure, offset, taps.front(), reference,
                      [&](double z) { return c.wall_pressure(z) - ours_reference; });
}

// Carried[z][lab]: the flow rate a laboratory's profile at station z carries and ours on the same
// points, each over the stated flow rate.
using Carried = std::map<double, std::map<std::string, std::pair<double, double>>>;

// The flow rate each laboratory's profile carries, over the stated one: the integral of pi |r| u
// across the diameter (trapezoids between its points; a profile across the whole lumen gives the
// flow through it). Ours on the same points, beside it, says what the quadrature itself misses.
void report_profile_flows(Comparison& c, const Carried& carried) {
  fmt::print("\nflow rate carried by each profile, over the stated {:g} mL/s: lab / ours on the lab's points\n{:>9}",
             c.labs[0].flow * 1e6, "z mm");
  c.markdown += "\n| flow rate a profile carries / the stated one, z (mm) |";
  for (const Lab& lab : c.labs) fmt::print(" {:>11}", lab.code), c.markdown += " lab " + lab.code + " (ours) |";
  c.markdown += "\n|---|";
  for (size_t i = 0; i < c.labs.size(); ++i) c.markdown += "---|";
  c.markdown += "\n";
  for (const auto& [z, by_lab] : carried) {
    fmt::print("\n{:9.1f}", z);
    c.markdown += fmt::format("| {:g} |", z);
    for (const Lab& lab : c.labs) {
      const auto found = by_lab.find(lab.code);
      if (found == by_lab.end()) {
        fmt::print(" {:>11}", "-");
        c.markdown += " – |";
        continue;
      }
      const auto [theirs, ours] = found->second;
      fmt::print(" {:>5.2f}/{:<5.2f}", theirs, ours);
      c.markdown += fmt::format(" {:.2f} ({:.2f}) |", theirs, ours);
      c.summary["profiles"]["carried"][lab.code].push_back({{"z_mm", z}, {"lab", theirs}, {"ours", ours}});
    }
    c.markdown += "\n";
  }
  fmt::print("\n");
}

// Radial profiles of the axial velocity at the laboratories' stations: per station and laboratory
// the RMS difference over its points inside our mesh, and the flow rate the profile carries
// (report_profile_flows); each station's chart.
void compare_profiles(Comparison& c) {
  std::set<double> z_stations;
  for (const Lab& lab : c.labs)
    for (const auto& [z, rows] : lab.profiles) z_stations.insert(z);
  if (z_stations.empty()) return fmt::print("\nvelocity profiles: no laboratory measured them\n");
  fmt::print(
      "\naxial velocity profiles: RMS difference over each laboratory's points, % of the throat's mean velocity\n{:>9}",
      "z mm");
  c.markdown += "\n| axial velocity profiles, z (mm) |";
  for (const Lab& lab : c.labs) fmt::print(" {:>7}", lab.code), c.markdown += " lab " + lab.code + " |";
  fmt::print(" {:>7}\n", "all");
  c.markdown += " all |\n|---|";
  for (size_t i = 0; i <= c.labs.size(); ++i) c.markdown += "---|";
  c.markdown += "\n";
  std::string csv = "z_mm,lab,r_mm,lab_m_s,ours_m_s\n";
  double all2 = 0.0;
  int all_n = 0;
  Carried carried;
  for (double z : z_stations) {
    fmt::print("{:9.1f}", z);
    c.markdown += fmt::format("| {:g} |", z);
    double station2 = 0.0;
    int station_n = 0;
    std::vector<study::Series> labs;
    for (const Lab& lab : c.labs) {
      const auto found = lab.profiles.find(z);
      if (found == lab.profiles.end()) {
        fmt::print(" {:>7}", "-");
        c.markdown += " – |";
        continue;
      }
      study::Series s{.name = "lab " + lab.code, .x = {}, .y = {}, .dashed = true};
      double sum2 = 0.0, lab_flow = 0.0, our_flow = 0.0, previous = 0.0;
      int n = 0;
      const Curve& rows = found->second;
      for (size_t i = 0; i < rows.size(); ++i) {
        const auto [r, u] = rows[i];
        if (std::abs(r) <= station_radius(z) + 0.5) s.x.push_back(r), s.y.push_back(u);  // not the rows past the wall
        const double ours = c.axial_at_radius(r, z), inside = std::isfinite(ours) ? ours : 0.0;
        csv += fmt::format("{},{},{},{},{}\n", z, lab.code, r, u, ours);
        if (std::isfinite(ours)) sum2 += (ours - u) * (ours - u), ++n;
        if (i > 0) {  // pi |r| dr at the middle of the interval, r in mm -> m^2
          const double weight = M_PI * 1e-6 * std::abs(r + rows[i - 1].first) / 2 * (r - rows[i - 1].first);
          lab_flow += weight * (u + rows[i - 1].second) / 2, our_flow += weight * (inside + previous) / 2;
        }
        previous = inside;
      }
      carried[z][lab.code] = {lab_flow / c.labs[0].flow, our_flow / c.labs[0].flow};
      labs.push_back(s);
      fmt::print(" {:>6.1f}%", 100 * rms(sum2, n) / c.throat_mean);
      c.markdown += fmt::format(" {:.1f} % |", 100 * rms(sum2, n) / c.throat_mean);
      station2 += sum2, station_n += n;
    }
    fmt::print(" {:>6.1f}%\n", 100 * rms(station2, station_n) / c.throat_mean);
    c.markdown += fmt::format(" {:.1f} % |\n", 100 * rms(station2, station_n) / c.throat_mean);
    c.summary["profiles"]["stations"].push_back(
        {{"z_mm", z}, {"rms_percent", 100 * rms(station2, station_n) / c.throat_mean}});
    all2 += station2, all_n += station_n;
    const double radius = station_radius(z);
    study::Series ours{.name = "vesselmesh", .x = {}, .y = {}, .dashed = false};
    for (int i = 0; i <= 160; ++i) {
      const double r = radius * (-1.0 + 2.0 * i / 160.0);
      ours.x.push_back(r), ours.y.push_back(c.axial_at_radius(r, z));
    }
    write_chart(fmt::format("{}/profile_z{:+.0f}", c.out, z),
                fmt::format("FDA nozzle: axial velocity across the lumen at z = {:g} mm", z), "radius (mm)",
                "axial velocity (m/s)", labs, ours);
  }
  fmt::print("velocity profiles: RMS difference {:.1f} % of the throat's mean velocity over {} points of {} stations\n",
             100 * rms(all2, all_n) / c.throat_mean, all_n, z_stations.size());
  c.summary["profiles"]["rms_percent"] = 100 * rms(all2, all_n) / c.throat_mean;
  c.markdown += fmt::format(
      "\nProfiles: RMS difference {:.1f} % of the throat's mean velocity over {} measured points (RMS over each "
      "laboratory's points at each station, % of the throat's mean velocity).\n",
      100 * rms(all2, all_n) / c.throat_mean, all_n);
  io::write_text(c.out + "/velocity_profiles.csv", csv);
  report_profile_flows(c, carried);
}

// The wall shear stress's magnitude along z, where a laboratory measured it (each wall's row its
// own).
void compare_wall_shear(Comparison& c) {
  const std::vector<double> z_stations = stations(c.labs, &Lab::wss);
  if (z_stations.empty()) return fmt::print("\nwall shear stress: no laboratory measured it\n");
  const std::string ours_is = c.wall.time_mean ? "ours the time mean's" : "ours the last frame's";
  fmt::print("\nwall shear stress (Pa, magnitude; the labs' rows are walls: mean and range; {})\n{:>9} {:>9} {:>17} "
             "{:>9} {:>9}\n", ours_is, "z mm", "labs", "range", "ours", "diff");
  std::string csv = "z_mm,labs_mean_Pa,labs_min_Pa,labs_max_Pa,rows,ours_Pa\n";
  c.markdown +=
      "\n| wall shear stress, z (mm) | labs' mean [range] (Pa; each lab's walls) | ours | difference "
      "|\n|---|---|---|---|\n";
  int within = 0;
  for (double z : z_stations) {
    const Stats s = at(c.labs, &Lab::wss, z);
    const double ours = c.wall_shear(z);
    fmt::print("{:9.2f} {:9.4f} {:8.4f}..{:<8.4f} {:9.4f} {:+9.4f}\n", z, s.mean, s.low, s.high, ours, ours - s.mean);
    csv += fmt::format("{},{},{},{},{},{}\n", z, s.mean, s.low, s.high, s.labs, ours);
    c.markdown += fmt::format("| {:g} | {:.3f} [{:.3f}, {:.3f}] | {:.3f}{} | {:+.3f} |\n", z, s.mean, s.low, s.high,
                              ours, s.low <= ours && ours <= s.high ? "" : " (out)", ours - s.mean);
    within += s.low <= ours && ours <= s.high;
  }
  fmt::print("wall shear stress: {} of {} stations within the rows' range\n", within, z_stations.size());
  c.summary["wall_shear_stress"] = {
      {"stations", z_stations.size()}, {"within", within}, {"time_mean", c.wall.time_mean}};
  io::write_text(c.out + "/wall_shear_stress.csv", csv);
  write_chart_along_z(c, "wall_shear_stress",
                      c.wall.time_mean ? "FDA nozzle: time-mean wall shear stress (magnitude)"
                                       : "FDA nozzle: wall shear stress (magnitude)",
                      "wall shear stress (Pa)",
                      &Lab::wss, {}, -100.0, 100.0, [&](double z) { return c.wall_shear(z); });
}

int run(int argc, char** argv) {
  if (argc != 4) {
    std::cerr << "usage: bench_fda_nozzle RESULT_DIR EXPERIMENT_DIR OUT_DIR\n";
    return 2;
  }
  Comparison c(argv[1], argv[2], argv[3]);  // the inputs read before anything is written
  std::filesystem::create_directories(c.out);
  fmt::print(
      "result: {} ({}, {} points, {} tetrahedra); {} laboratories; flow {:g} mL/s, throat's mean velocity "
      "{:.4f} m/s\n",
      argv[1],
      c.statistics ? fmt::format("the time means over t = {:g} to {:g} s", c.statistics->start,
                                 c.statistics->end)
                   : fmt::format("t = {:g} s", c.field.time),
      c.field.mesh.points.size(), c.locator.tets().size(), c.labs.size(), c.labs[0].flow * 1e6,
      c.throat_mean);
  compare_centerline(c);
  compare_breakdown(c);
  compare_fluctuations(c);
  compare_pressure(c);
  compare_profiles(c);
  compare_wall_shear(c);
  c.summary["points"] = c.field.mesh.points.size();
  c.summary["time_s"] = c.field.time;
  if (c.statistics) c.summary["statistics_s"] = {c.statistics->start, c.statistics->end};
  c.summary["throat_mean_velocity_m_s"] = c.throat_mean;
  io::write_text(c.out + "/comparison.json", c.summary.dump(2) + "\n");
  io::write_text(c.out + "/comparison.md", c.markdown);
  fmt::print(
      "\nwrote {}/comparison.json|md, centerline_velocity, wall_pressure, wall_shear_stress, velocity_profiles (.csv), "
      "their charts (.svg, .png)\n",
      c.out);
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
  std::array<nlohmann::json, 3> compared;
  for (int k = 0; k < 3; ++k) {
    points[k] = nlohmann::json::parse(io::read_file(level[k] + "/flow/summary.json"))["points"].get<double>();
    compared[k] = nlohmann::json::parse(io::read_file(level[k] + "/comparison.json"));
    velocity[k] = read_csv(level[k] + "/centerline_velocity.csv");  // z, mean, min, max, labs, ours
    if (velocity[k].size() != velocity[0].size()) throw InputError(level[k] + ": other stations than the finest's");
  }
  fmt::print("levels (finest first): {:.0f}, {:.0f}, {:.0f} points; r21 = {:.3f}, r32 = {:.3f} (in h = N^-1/3)\n",
             points[0], points[1], points[2], std::cbrt(points[0] / points[1]), std::cbrt(points[1] / points[2]));
  fmt::print("{:>7} {:>8} {:>17} {:>8} {:>8} {:>8} {:>6} {:>9} {:>8}  {}\n", "z mm", "labs", "range", "fine", "medium",
             "coarse", "p", "extrap.", "GCI", "status");
  std::string csv =
      "z_mm,labs_mean_m_s,labs_min_m_s,labs_max_m_s,fine_m_s,medium_m_s,coarse_m_s,order,extrapolated_m_s,gci_fine_"
      "percent\n";
  std::string markdown = fmt::format(
      "| centreline velocity (m/s), z (mm) | labs' mean [range] | {:.0f} points | {:.0f} | {:.0f} | order | "
      "extrapolated | GCI (finest) |\n|---|---|---|---|---|---|---|---|\n",
      points[2], points[1], points[0]);
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
    const auto cell = [&](double value) {
      return fmt::format("{:.3f}{}", value, low <= value && value <= high ? "" : "*");
    };
    markdown +=
        fmt::format("| {:g} | {:.3f} [{:.3f}, {:.3f}] | {} | {} | {} | {} | {} | {} |\n", row[0], mean, low, high,
                    cell(v[2]), cell(v[1]), cell(v[0]), std::isfinite(g.order) ? fmt::format("{:.2f}", g.order) : "–",
                    std::isfinite(g.extrapolated) ? fmt::format("{:.3f}", g.extrapolated) : "–",
                    g.found ? fmt::format("{:.1f} %", 100 * g.gci_fine) : g.status);
  }
  markdown += fmt::format(
      "\n(* outside the laboratories' range; refinement ratios in h {:.2f} and {:.2f})\n\n| level | points | "
      "centreline RMS | stations in range | profiles' RMS | pressure taps in range | pressure drop (labs') | WSS "
      "stations in range |\n|---|---|---|---|---|---|---|---|\n",
      std::cbrt(points[1] / points[2]), std::cbrt(points[0] / points[1]));
  for (int k = 2; k >= 0; --k) {
    const nlohmann::json& j = compared[k];
    markdown +=
        fmt::format("| {} | {:.0f} | {:.1f} % | {} of {} | {:.1f} % | {} of {} | {:.0f} Pa ({:.0f}) | {} of {} |\n",
                    std::array{"fine", "medium", "coarse"}[k], points[k],
                    100 * std::sqrt(sum2[k] / n) / j["throat_mean_velocity_m_s"].get<double>(), within[k], n,
                    j["profiles"].value("rms_percent", std::nan("")), j["pressure"].value("within", 0),
                    j["pressure"].value("taps", 0), j["pressure"].value("drop_ours_Pa", std::nan("")),
                    j["pressure"].value("drop_labs_Pa", std::nan("")), j["wall_shear_stress"].value("within", 0),
                    j["wall_shear_stress"].value("stations", 0));
  }
  for (int k = 0; k < 3; ++k) {
    const nlohmann::json& j = compared[k];
    fmt::print(
        "{}: centreline RMS difference from the labs' mean {:.1f} % of the throat's mean velocity, {} of {} stations "
        "within the labs' range; profiles' RMS {:.1f} %; wall pressure {} of {} taps within range, drop {:.1f} Pa "
        "(labs {:.1f}); wall shear stress {} of {} within the rows' range\n",
        level[k], 100 * std::sqrt(sum2[k] / n) / j["throat_mean_velocity_m_s"].get<double>(), within[k], n,
        j["profiles"].value("rms_percent", std::nan("")), j["pressure"].value("within", 0),
        j["pressure"].value("taps", 0), j["pressure"].value("drop_ours_Pa", std::nan("")),
        j["pressure"].value("drop_labs_Pa", std::nan("")), j["wall_shear_stress"].value("within", 0),
        j["wall_shear_stress"].value("stations", 0));
  }
  std::filesystem::create_directories(out);
  io::write_text(out + "/series_velocity.csv", csv);
  io::write_text(out + "/series.md", markdown);
  study::LineChart chart;
  chart.title = "FDA nozzle: centerline axial velocity on three meshes";
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
  fmt::print("wrote {}/series.md, series_velocity.csv|svg|png\n", out);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    if (argc > 1 && std::string(argv[1]) == "--series") return series(argc, argv);
    return run(argc, argv);
  } catch (const InputError& e) {  // bad input: what is wrong and where, exit 2 as the CLI's
    std::cerr << "bench_fda_nozzle: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "bench_fda_nozzle: " << e.what() << "\n";
    return 1;
  }
}
