// vesselmesh centerline: centerlines (VMTK's Voronoi method), branches, and the distance map.
#include "commands.h"

#include "centerline/distance_map.h"
#include "centerline/extract.h"
#include "io/surface.h"
#include "mesh/error.h"

#include <fmt/format.h>

#include <chrono>
#include <iostream>

namespace vesselmesh::cli {
namespace {

Json branch_json(const centerline::Branch& b) {
  double mean = 0.0;
  for (double r : b.radius) mean += r;
  mean /= static_cast<double>(std::max<size_t>(1, b.radius.size()));
  return {{"id", b.id},        {"parent", b.parent},         {"children", b.children},
          {"end", b.end},      {"length", round_to(b.length())}, {"mean_radius", round_to(mean)},
          {"start", to_json(b.points.front())}, {"stop", to_json(b.points.back())}};
}

}  // namespace

void write_centerlines(const std::string& path, const centerline::Centerlines& c) {
  std::vector<std::vector<Vec3>> lines;
  std::vector<double> radius, branch_ids;
  for (const centerline::Branch& b : c.branches) {
    lines.push_back(b.points);
    radius.insert(radius.end(), b.radius.begin(), b.radius.end());
    branch_ids.push_back(b.id);
  }
  io::write_vtp_polylines(path, lines, {Field::scalar("radius", radius)},
                          {Field{.name = "branch", .components = 1, .values = branch_ids, .integer = true}});
}

void write_distance_map(const std::string& path, const TriMesh& surface, const centerline::Centerlines& c) {
  const centerline::DistanceMap map = centerline::distance_map(surface, c);
  io::write_vtp(path, surface, {Field::scalar("distance", map.distance), Field::scalar("radius", map.radius)});
}

Command add_centerline_command(CLI::App& parent) {
  CLI::App* app = parent.add_subcommand(
      "centerline",
      "Centerlines from the inlet to every outlet through the lumen's internal Voronoi diagram (Antiga & Steinman, as "
      "VMTK), split into branches at the bifurcations; each point carries the maximal inscribed sphere radius. "
      "Optionally the distance map: each surface point's distance to the centerline and the radius there");
  struct Options {
    SurfaceInput surface;
    std::string output, distance_map;
    std::optional<int> inlet;
    std::string source;
    std::vector<std::string> targets;
    double step = 0.0;
    CommonOptions common;
  };
  auto o = std::make_shared<Options>();
  add_surface_input(*app, o->surface);
  app->add_option("-o,--output", o->output, "Centerlines .vtp: one polyline per branch, point data radius, cell data branch")
      ->required();
  app->add_option("--distance-map", o->distance_map, "Also write the surface (.vtp) with point data distance and radius");
  app->add_option("--inlet", o->inlet, "The end the centerlines start from, by its number in 'vesselmesh info' (default 0, the largest)");
  app->add_option("--source-point", o->source, "Start here instead (x,y,z in mm, after --units)");
  app->add_option("--target-point", o->targets, "End here instead of at the outlets (x,y,z in mm; repeat for several)");
  app->add_option("--resampling-step", o->step, "Distance between centerline points (mm; default a tenth of the smallest end radius)");
  add_common_options(*app, o->common);
  return {app, [o] {
            for (const std::string& path : {o->output, o->distance_map})
              if (!path.empty() && io::surface_format(path) != io::SurfaceFormat::vtp)
                throw OptionError(fmt::format("{}: centerlines and distance maps are written as VTP: use a .vtp name", path));
            centerline::CenterlineOptions options{.inlet = o->inlet, .resampling_step = o->step};
            if (!o->source.empty()) options.source = parse_point(o->source, "--source-point");
            for (const std::string& t : o->targets) options.targets.push_back(parse_point(t, "--target-point"));
            TerminalReporter reporter(o->common.quiet);
            const CheckedSurface surface = read_surface_input(o->surface, reporter);
            const auto start = std::chrono::steady_clock::now();
            centerline::Centerlines c;
            try {
              c = centerline::extract(surface.file.mesh, options, reporter);
            } catch (const InputError& e) {
              throw InputError(fmt::format("{}: {}", o->surface.path, e.what()));
            }
            write_centerlines(o->output, c);
            if (!o->distance_map.empty()) write_distance_map(o->distance_map, surface.file.mesh, c);
            const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
            if (o->common.json) {
              Json branches = Json::array(), bifurcations = Json::array();
              for (const auto& b : c.branches) branches.push_back(branch_json(b));
              for (const Vec3& p : c.bifurcations) bifurcations.push_back(to_json(p));
              Json json = {{"input", o->surface.path}, {"output", o->output}, {"units", "mm"}, {"inlet", c.inlet},
                           {"outlets", c.outlets}, {"branches", branches}, {"bifurcations", bifurcations},
                           {"seconds", round_to(seconds, 4)}};
              if (!o->distance_map.empty()) json["distance_map"] = o->distance_map;
              print_json(json);
            } else {
              reporter.info(fmt::format("{} branch(es), {} bifurcation(s) from end {} to {} outlet(s); wrote {}{} "
                                        "({:.2f} s)",
                                        c.branches.size(), c.bifurcations.size(), c.inlet, c.outlets.size(), o->output,
                                        o->distance_map.empty() ? "" : " and " + o->distance_map, seconds));
            }
            return 0;
          }};
}

}  // namespace vesselmesh::cli
