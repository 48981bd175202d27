// vesselmesh sample: the flow (velocity, pressure) read back from a simulation's results and
// sampled inside the volume, along a line and at points (post/fluid_sample).
#include "commands.h"

#include "io/atomic_file.h"
#include "mesh/error.h"
#include "post/fluid_sample.h"

#include <fmt/format.h>

#include <optional>
#include <utility>

namespace vesselmesh::cli {

Command add_sample_command(CLI::App& parent) {
  CLI::App* app = parent.add_subcommand(
      "sample",
      "Velocity and pressure from the results of 'vesselmesh simulate' (its DIR/fluid.pvd) inside the volume: along a "
      "line (e.g. the centerline velocity against measurements) and at named points, at a chosen time (linear between "
      "saved frames), interpolated linearly in the tetrahedron that holds each point. Writes one CSV: distance along "
      "the line and position in the mesh's unit, velocity in m/s, pressure in Pa; points outside the mesh are marked "
      "and left empty. --statistics samples the run's time statistics instead (its mean velocity and pressure, and "
      "the RMS of the velocity's fluctuation)");
  struct Options {
    std::string results, output, line;
    int samples = 101;
    std::optional<double> time;
    bool statistics = false;
    std::vector<std::string> points;
    CommonOptions common;
  };
  auto o = std::make_shared<Options>();
  app->add_option("RESULTS", o->results, "Output folder of 'vesselmesh simulate'")->required()->check(CLI::ExistingDirectory);
  app->add_option("-o,--output", o->output, "Output CSV")->required();
  app->add_option("--line", o->line, "x,y,z:x,y,z — sample the segment between the two points");
  app->add_option("--samples", o->samples, "Points on the line, both ends included")
      ->capture_default_str()
      ->check(CLI::Range(2, 1000000));
  app->add_option("--point", o->points, "NAME:x,y,z — a point to sample. Repeatable");
  CLI::Option* time_option = app->add_option("-t,--time", o->time, "Time in s (default: the last saved)");
  app->add_flag("--statistics", o->statistics,
                "Sample the time statistics (RESULTS/statistics.vtu, of a case with [output] statistics_from) "
                "instead of a saved frame: the mean velocity and pressure, and three more columns, the RMS of the "
                "velocity's fluctuation per component (m/s)")
      ->excludes(time_option);
  add_common_options(*app, o->common);
  return {app, [o] {
            TerminalReporter reporter(o->common.quiet);
            if (o->line.empty() && o->points.empty()) throw OptionError("give --line and/or --point: nothing to sample");
            std::optional<std::pair<Vec3, Vec3>> line;
            if (!o->line.empty()) {
              const std::vector<std::string> ends = split(o->line, ':');
              if (ends.size() != 2) throw OptionError(fmt::format("--line '{}': give x,y,z:x,y,z", o->line));
              line = {parse_point(ends[0], "--line"), parse_point(ends[1], "--line")};
              if (line->first == line->second) throw OptionError(fmt::format("--line '{}': the ends coincide", o->line));
            }
            std::vector<std::string> names;
            std::vector<Vec3> points;
            for (const std::string& p : o->points) {
              auto [name, point] = parse_named_point(p, "--point");
              names.push_back(name);
              points.push_back(point);
            }
            const post::WallSeries series = post::read_wall_series(o->results, "fluid");
            std::optional<post::FluidStatistics> statistics;
            if (o->statistics) statistics = post::read_fluid_statistics(o->results);
            const double time = o->time.value_or(series.frames.back().time);
            post::FluidField field = statistics ? std::move(statistics->mean) : post::fluid_at_time(series, time);
            const post::TetLocator locator(field.mesh);
            const std::string& unit = series.length_unit;
            const std::string what = statistics ? fmt::format("the time statistics over t = {:g} to {:g} s",
                                                              statistics->start, statistics->end)
                                                : fmt::format("t = {:g} s", time);
            reporter.info(fmt::format("fluid at {}: {} points, {} tetrahedra (lengths in {})", what,
                                      field.mesh.num_points(), locator.tets().size(), unit));
            const auto sample = [&](const post::FluidField& f) {
              std::vector<post::FluidSample> out;
              if (line) out = post::sample_line(f, locator, line->first, line->second, o->samples);
              for (const post::FluidSample& s : post::sample_points(f, locator, points)) out.push_back(s);
              return out;
            };
            const std::vector<post::FluidSample> samples = sample(field);
            const size_t on_line = line ? static_cast<size_t>(o->samples) : 0;
            std::vector<post::FluidSample> spread;  // the RMS of the fluctuation, sampled as a velocity
            if (statistics) {
              field.velocity.swap(statistics->rms);  // on the same mesh: no copy of it
              spread = sample(field);
            }
            std::string csv = fmt::format(
                "# vesselmesh sample of {} at {}: lengths in {}, velocity in m/s, pressure in Pa{}; inside = 0: "
                "the point is outside the mesh\n",
                o->results, what, unit,
                statistics ? " (time means; rms: the RMS of the velocity's fluctuation about its mean)" : "");
            csv += fmt::format("name,distance_{0},x_{0},y_{0},z_{0},inside,velocity_x_m_s,velocity_y_m_s,"
                               "velocity_z_m_s,speed_m_s,pressure_Pa{1}\n",
                               unit, statistics ? ",rms_x_m_s,rms_y_m_s,rms_z_m_s" : "");
            int outside = 0;
            Json json_points = Json::array();
            for (size_t i = 0; i < samples.size(); ++i) {
              const post::FluidSample& s = samples[i];
              const std::string name = i < on_line ? "line" : names[i - on_line];
              const double distance = i < on_line ? s.distance : 0.0;
              csv += fmt::format("{},{:.9g},{:.9g},{:.9g},{:.9g},{:d}", name, distance, s.point.x(), s.point.y(),
                                 s.point.z(), s.inside);
              if (s.inside) {
                csv += fmt::format(",{:.9g},{:.9g},{:.9g},{:.9g},{:.9g}", s.velocity.x(), s.velocity.y(),
                                   s.velocity.z(), s.velocity.norm(), s.pressure);
                if (statistics)
                  csv += fmt::format(",{:.9g},{:.9g},{:.9g}", spread[i].velocity.x(), spread[i].velocity.y(),
                                     spread[i].velocity.z());
              } else {
                csv += statistics ? ",,,,,,,," : ",,,,,";
                ++outside;
              }
              csv += "\n";
              if (i >= on_line) {
                json_points.push_back({{"name", name}, {"point", to_json(s.point)}, {"inside", s.inside},
                                       {"velocity", to_json(s.velocity)}, {"pressure", round_to(s.pressure)}});
                if (statistics) json_points.back()["rms"] = to_json(spread[i].velocity);
              }
            }
            io::write_text(o->output, csv);
            if (outside > 0)
              reporter.warning(fmt::format("{} of {} sample(s) lie outside the mesh (left empty in the CSV)", outside,
                                        samples.size()));
            if (o->common.json)
              print_json({{"results", o->results},
                          {"time", statistics ? statistics->end : time},
                          {"units", {{"length", unit}, {"velocity", "m/s"}, {"pressure", "Pa"}}},
                          {"line_samples", on_line}, {"outside", outside}, {"points", json_points},
                          {"output", o->output}});
            else
              reporter.info(fmt::format("wrote {} sample(s) to {}", samples.size(), o->output));
            return 0;
          }};
}

}  // namespace vesselmesh::cli
