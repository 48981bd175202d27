// vesselmesh wss: wall shear stress read back from a simulation's results, on rings and at
// points, at a chosen time; hemodynamic indices over a chosen window (post/).
#include "commands.h"

#include "io/atomic_file.h"
#include "io/vtk_formats.h"
#include "mesh/error.h"
#include "post/indices.h"
#include "post/ring.h"
#include "post/wall_series.h"
#include "study/chart.h"
#include "study/raster.h"

#include <fmt/format.h>

#include <filesystem>
#include <optional>

namespace vesselmesh::cli {
namespace {

// NAME:x,y,z:nx,ny,nz[:rx,ry,rz], or NAME:x,y,z for the plane normal to the centerline there.
post::RingRequest parse_ring(const std::string& text) {
  const std::vector<std::string> parts = split(text, ':');
  if (parts.size() < 2 || parts.size() > 4)
    throw OptionError(fmt::format("--ring '{}': give NAME:x,y,z:nx,ny,nz (a point and the plane's normal), "
                                  "NAME:x,y,z:nx,ny,nz:rx,ry,rz (and where angle 0 points), or NAME:x,y,z (the "
                                  "plane normal to the centerline nearest the point)",
                                  text));
  post::RingRequest r;
  r.spec.name = checked_name(parts[0], text, "--ring");
  r.spec.point = parse_point(parts[1], "--ring");
  r.on_centerline = parts.size() == 2;
  if (parts.size() >= 3) {
    r.spec.normal = parse_point(parts[2], "--ring (normal)");
    if (!(r.spec.normal.norm() > 0.0)) throw OptionError(fmt::format("--ring '{}': the normal is zero", text));
  }
  if (parts.size() == 4) r.spec.reference = parse_point(parts[3], "--ring (reference)");
  return r;
}

post::PointSpec parse_probe(const std::string& text) {
  auto [name, point] = parse_named_point(text, "--point");
  return {name, point};
}

std::pair<double, double> parse_window(const std::string& text) {
  const std::vector<std::string> parts = split(text, ':');
  try {
    if (parts.size() == 2) {
      size_t used_a = 0, used_b = 0;
      const double a = std::stod(parts[0], &used_a), b = std::stod(parts[1], &used_b);
      if (used_a == parts[0].size() && used_b == parts[1].size() && b > a) return {a, b};
    }
  } catch (const std::exception&) {
  }
  throw OptionError(fmt::format("--indices '{}': give START:END in s, START < END", text));
}

void write_ring(const std::string& dir, const post::Ring& ring, double time, const std::string& unit) {
  std::string csv = fmt::format("# ring {}: wall shear stress at t = {:g} s; lengths in {}, stresses in Pa; "
                                "angle counter-clockwise about the normal ({:.6g}, {:.6g}, {:.6g})\n",
                                ring.name, time, unit, ring.normal.x(), ring.normal.y(), ring.normal.z());
  csv += fmt::format("arc_length_{0},angle_deg,x_{0},y_{0},z_{0},wss_x_Pa,wss_y_Pa,wss_z_Pa,wss_axial_Pa,"
                     "wss_circumferential_Pa,wss_magnitude_Pa\n",
                     unit);
  study::Series magnitude{"|wss|", {}, {}}, axial{"axial", {}, {}, true}, circumferential{"circumferential", {}, {}, true};
  study::Series magnitude_by_angle = magnitude;
  for (const post::RingSample& s : ring.samples) {
    csv += fmt::format("{:.9g},{:.6g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g}\n", s.arc_length,
                       s.angle, s.point.x(), s.point.y(), s.point.z(), s.value.x(), s.value.y(), s.value.z(), s.axial,
                       s.circumferential, s.magnitude);
    for (auto* series : {&magnitude, &axial, &circumferential}) series->x.push_back(s.arc_length);
    magnitude.y.push_back(s.magnitude);
    axial.y.push_back(s.axial);
    circumferential.y.push_back(s.circumferential);
    magnitude_by_angle.x.push_back(s.angle);
    magnitude_by_angle.y.push_back(s.magnitude);
  }
  io::write_text(dir + "/ring_" + ring.name + ".csv", csv);
  const post::RingSample& least = ring.samples[ring.minimum];
  const std::string label = fmt::format("min {:.4g} Pa", least.magnitude);
  study::LineChart chart;
  chart.title = fmt::format("Wall shear stress on ring {} at t = {:g} s", ring.name, time);
  chart.x_label = fmt::format("arc length ({}) from angle 0", unit);
  chart.y_label = "wall shear stress (Pa)";
  chart.series = {magnitude, axial, circumferential};
  chart.markers = {{label, least.arc_length, least.magnitude}};
  study::write_svg_and_png(dir + "/ring_" + ring.name, study::svg(chart));
  chart.x_label = "angle (degrees, counter-clockwise about the ring's normal)";
  chart.series = {magnitude_by_angle};
  chart.markers = {{label, least.angle, least.magnitude}};
  chart.y_from_zero = true;
  study::write_svg_and_png(dir + "/ring_" + ring.name + "_angle", study::svg(chart));
}

Json ring_json(const post::Ring& ring) {
  const post::RingSample& least = ring.samples[ring.minimum];
  double mean = 0.0, largest = 0.0;
  for (size_t k = 1; k < ring.samples.size(); ++k) {
    const double ds = ring.samples[k].arc_length - ring.samples[k - 1].arc_length;
    mean += 0.5 * ds * (ring.samples[k].magnitude + ring.samples[k - 1].magnitude);
  }
  for (const post::RingSample& s : ring.samples) largest = std::max(largest, s.magnitude);
  mean = ring.length > 0.0 ? mean / ring.length : ring.samples[0].magnitude;
  return {{"name", ring.name},
          {"closed", ring.closed},
          {"other_loops", ring.other_loops},
          {"centroid", to_json(ring.centroid)},
          {"normal", to_json(ring.normal)},
          {"length", round_to(ring.length)},
          {"samples", ring.samples.size()},
          {"minimum", {{"wss_magnitude", round_to(least.magnitude)},
                       {"arc_length", round_to(least.arc_length)},
                       {"angle_deg", round_to(least.angle, 5)},
                       {"point", to_json(least.point)}}},
          {"maximum_wss_magnitude", round_to(largest)},
          {"mean_wss_magnitude", round_to(mean)}};
}

}  // namespace

Command add_wss_command(CLI::App& parent) {
  CLI::App* app = parent.add_subcommand(
      "wss",
      "Wall shear stress from the results of 'vesselmesh simulate' (its DIR/wall.pvd): on rings (the wall cut by a "
      "plane) as CSV and SVG plots against arc length and angle with the minimum and where it is, at points (the "
      "nearest wall location), at a chosen time (linear between saved frames); hemodynamic indices (TAWSS, OSI, "
      "RRT, TWSSG) over a chosen window of the saved frames. Lengths in the mesh's unit, stresses in Pa. Writes "
      "OUT/wall_at_time.vtp, OUT/rings.vtp, OUT/ring_NAME.csv, plots ring_NAME.svg/.png and ring_NAME_angle.svg/.png, OUT/points.csv, OUT/wss.json");
  struct Options {
    std::string results, output, indices;
    std::optional<double> time;
    std::vector<std::string> rings, points;
    CommonOptions common;
  };
  auto o = std::make_shared<Options>();
  app->add_option("RESULTS", o->results, "Output folder of 'vesselmesh simulate'")->required()->check(CLI::ExistingDirectory);
  app->add_option("-o,--output", o->output, "Output folder (default RESULTS/wss)");
  app->add_option("-t,--time", o->time, "Time in s (default: the last saved)");
  app->add_option("--ring", o->rings,
                  "NAME:x,y,z:nx,ny,nz — the wall cut by the plane through the point with that normal (the loop "
                  "nearest the point); add :rx,ry,rz for where angle 0 points. NAME:x,y,z — the plane normal to the "
                  "centerline nearest the point. Repeatable");
  app->add_option("--point", o->points, "NAME:x,y,z — wall shear stress at the nearest wall location. Repeatable");
  app->add_option("--indices", o->indices,
                  "START:END (s): TAWSS, OSI, RRT, TWSSG from the saved frames in that window, to OUT/indices.vtp "
                  "('simulate' already wrote RESULTS/indices.vtp, indices.pvtp under mpirun, from every step of the last "
                  "period)");
  add_common_options(*app, o->common);
  return {app, [o] {
            TerminalReporter reporter(o->common.quiet);
            std::vector<post::RingRequest> requests;
            for (const std::string& r : o->rings) requests.push_back(parse_ring(r));
            std::vector<post::PointSpec> points;
            for (const std::string& p : o->points) points.push_back(parse_probe(p));
            std::optional<std::pair<double, double>> window;
            if (!o->indices.empty()) window = parse_window(o->indices);
            const post::WallSeries series = post::read_wall_series(o->results);
            const std::string out = o->output.empty() ? o->results + "/wss" : o->output;
            const double time = o->time.value_or(series.frames.back().time);
            const std::string& unit = series.length_unit;

            // Everything is computed first: a ring that misses the wall or a window without frames
            // stops before the output folder is made.
            const post::WallField field = post::wall_at_time(series, time);
            reporter.info(fmt::format("wall at t = {:g} s: {} points, {} triangles (lengths in {}, wss in Pa)", time,
                                      field.mesh.num_points(), field.mesh.num_triangles(), unit));
            std::vector<post::Ring> rings;
            for (const post::RingSpec& spec : post::place_rings(field.mesh, requests, reporter))
              rings.push_back(post::cut_ring(field.mesh, field.wss, spec));
            const std::vector<post::PointProbe> probes = post::probe_points(field.mesh, field.wss, points);
            std::optional<post::WssIndices> indices;
            TriMesh indices_wall;  // the first frame's wall carries the indices
            if (window) {
              post::WssIndexAccumulator accumulator;
              const double tolerance = 1e-9 * std::max(1.0, std::abs(window->second));
              std::vector<const post::WallFrame*> chosen;
              for (const post::WallFrame& f : series.frames)
                if (f.time >= window->first - tolerance && f.time <= window->second + tolerance) chosen.push_back(&f);
              if (chosen.size() < 2)
                throw InputError(fmt::format("--indices {}: {} saved frame(s) in that window; the results hold "
                                             "{:g} to {:g} s in {} frames",
                                             o->indices, chosen.size(), series.frames.front().time,
                                             series.frames.back().time, series.frames.size()));
              for (size_t k = 0; k < chosen.size(); ++k) {
                post::WallField frame = post::read_wall_frame(*chosen[k]);
                accumulator.add(chosen[k]->time, frame.wss);
                if (k == 0) indices_wall = std::move(frame.mesh);
                reporter.progress("reading frames", double(k + 1) / chosen.size());
              }
              indices = accumulator.result();
            }

            std::filesystem::create_directories(out);
            std::vector<double> magnitude(field.wss.size());
            for (size_t i = 0; i < magnitude.size(); ++i) magnitude[i] = field.wss[i].norm();
            io::write_vtp(out + "/wall_at_time.vtp", field.mesh,
                          {Field::vector("wss", field.wss), Field::scalar("wss_magnitude", magnitude)});

            Json ring_list = Json::array();
            std::vector<std::vector<Vec3>> lines;
            std::vector<double> line_magnitude;
            std::vector<Vec3> line_wss;
            for (const post::Ring& ring : rings) {
              write_ring(out, ring, time, unit);
              const post::RingSample& least = ring.samples[ring.minimum];
              reporter.info(fmt::format("ring {}: length {:.4g} {}{}, minimum {:.4g} Pa at s = {:.4g} {} (angle "
                                        "{:.1f} deg, ({:.4g}, {:.4g}, {:.4g})){}",
                                        ring.name, ring.length, unit, ring.closed ? "" : " (open)", least.magnitude,
                                        least.arc_length, unit, least.angle, least.point.x(), least.point.y(),
                                        least.point.z(),
                                        ring.other_loops > 0
                                            ? fmt::format("; {} other loop(s) of that plane left aside", ring.other_loops)
                                            : ""));
              ring_list.push_back(ring_json(ring));
              std::vector<Vec3> line;
              for (const post::RingSample& sample : ring.samples) {
                line.push_back(sample.point);
                line_wss.push_back(sample.value);
                line_magnitude.push_back(sample.magnitude);
              }
              lines.push_back(line);
            }
            if (!lines.empty())
              io::write_vtp_polylines(out + "/rings.vtp", lines,
                                      {Field::vector("wss", line_wss), Field::scalar("wss_magnitude", line_magnitude)});

            Json point_list = Json::array();
            if (!probes.empty()) {
              std::string csv = fmt::format("# wall shear stress at t = {:g} s at the wall location nearest each "
                                            "point; lengths in {}, stresses in Pa\n",
                                            time, unit);
              csv += fmt::format("name,x_{0},y_{0},z_{0},distance_{0},wss_x_Pa,wss_y_Pa,wss_z_Pa,wss_magnitude_Pa\n",
                                 unit);
              for (const post::PointProbe& p : probes) {
                csv += fmt::format("{},{:.9g},{:.9g},{:.9g},{:.6g},{:.9g},{:.9g},{:.9g},{:.9g}\n", p.name, p.point.x(),
                                   p.point.y(), p.point.z(), p.distance, p.value.x(), p.value.y(), p.value.z(),
                                   p.value.norm());
                reporter.info(fmt::format("point {}: {:.4g} Pa at ({:.4g}, {:.4g}, {:.4g}), {:.3g} {} from the point "
                                          "given",
                                          p.name, p.value.norm(), p.point.x(), p.point.y(), p.point.z(), p.distance,
                                          unit));
                point_list.push_back({{"name", p.name},
                                      {"requested", to_json(p.requested)},
                                      {"point", to_json(p.point)},
                                      {"distance", round_to(p.distance)},
                                      {"wss", to_json(p.value)},
                                      {"wss_magnitude", round_to(p.value.norm())}});
              }
              io::write_text(out + "/points.csv", csv);
            }

            Json j = {{"results", o->results},
                      {"time_s", time},
                      {"units", {{"length", unit}, {"wss", "Pa"}, {"time", "s"}}},
                      {"rings", ring_list},
                      {"points", point_list}};
            if (indices) {
              post::write_indices(out + "/indices.vtp", indices_wall, *indices);
              j["indices"] = {{"file", "indices.vtp"}, {"start_s", indices->start}, {"end_s", indices->end},
                              {"frames", indices->samples},
                              {"units", {{"tawss", "Pa"}, {"osi", "1"}, {"rrt", "1/Pa"}, {"twssg", "Pa/s"}}}};
              reporter.info(fmt::format("indices.vtp: tawss, osi, rrt, twssg from {} frames, t = {:g} to {:g} s",
                                        indices->samples, indices->start, indices->end));
            }
            io::write_text(out + "/wss.json", j.dump(2) + "\n");
            reporter.info(fmt::format("results in {}", out));
            if (o->common.json) print_json(j);
            return 0;
          }};
}

}  // namespace vesselmesh::cli
