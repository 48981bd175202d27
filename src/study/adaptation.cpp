#include "study/adaptation.h"

#include "analysis/curvature.h"
#include "analysis/open_ends.h"
#include "centerline/distance_map.h"
#include "centerline/extract.h"
#include "flow/simulate.h"
#include "io/atomic_file.h"
#include "io/msh.h"
#include "io/vtk_formats.h"
#include "mesh/error.h"
#include "post/fluid_metric.h"
#include "post/wall_metric.h"
#include "post/wall_series.h"
#include "remesh/adapt.h"
#include "study/wall_difference.h"
#include "volume/quality.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <filesystem>

namespace vesselmesh::study {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

double since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

// A flow folder's last saved wall.
post::WallField last_wall(const std::string& flow_dir) {
  const post::WallSeries series = post::read_wall_series(flow_dir);
  if (series.frames.empty()) throw InputError(fmt::format("{}: the flow saved no wall frame", flow_dir));
  return post::read_wall_frame(series.frames.back());
}

}  // namespace

void size_volume_to_flow(volume::VolumeOptions& vo, const std::string& flow_dir,
                         const sizing::ErrorMetricOptions& error,
                         double y_plus, const flow::FlowCase& flow_case, const Reporter& reporter) {
  vo.interior.flow =
      post::size_function(post::fluid_error_sizes(flow_dir, {}, vo.interior.gradation, error, reporter));
  if (y_plus > 0.0 && vo.layer.layers > 0)
    vo.layer.first_height = post::height_function(
        post::first_layer_heights(flow_dir, {}, y_plus, {flow_case.density, flow_case.viscosity}, reporter));
}

void check_adapt_options(const AdaptOptions& o) {
  if (!(o.target_triangles > 0.0 && std::isfinite(o.target_triangles)))
    throw OptionError(fmt::format("--target-triangles {}: give the count every cycle's surface is made at (> 0)",
                                  o.target_triangles));
  if (o.cycles < 1) throw OptionError(fmt::format("--cycles {}: at least 1 flow-adapted cycle", o.cycles));
  if (o.target_points < 0) throw OptionError(fmt::format("--target-points {}: give a count > 0", o.target_points));
  if (!(o.y_plus >= 0.0 && std::isfinite(o.y_plus)))
    throw OptionError(fmt::format("--layer-y-plus {}: give a y+ >= 0 (0: the layer as --thickness-ratio makes it)",
                                  o.y_plus));
  if (o.start == sizing::SizeKind::flow)
    throw OptionError("--start flow: the first mesh is of a geometric kind (the flow kind needs a flow to adapt to)");
  volume::check_interior_size_options(o.volume.interior);
}

std::vector<AdaptCycle> adapt_to_flow(const TriMesh& input, const flow::FlowCase& flow_case,
                                      const std::string& folder, const AdaptOptions& options,
                                      const Reporter& reporter) {
  check_adapt_options(options);
  fs::create_directories(folder);
  reporter.info("adapt: curvature, centerlines and distance map of the input");
  const analysis::CurvatureField curvature = analysis::curvature(input, {}, reporter);
  const centerline::DistanceMap distance = centerline::distance_map(input, centerline::extract(input, {}, reporter));
  remesh::RemeshOptions remesh_options;
  remesh_options.input_radius = &distance.radius;
  std::vector<AdaptCycle> out;
  int points = options.target_points;
  std::vector<volume::EndAt> end_at = options.volume.end_at;
  for (int k = 0; k <= options.cycles; ++k) {
    AdaptCycle c;
    c.cycle = k;
    c.folder = (fs::path(folder) / fmt::format("cycle_{}", k)).string();
    fs::create_directories(c.folder);
    const std::string before = k > 0 ? out.back().folder + "/flow" : std::string();
    const sizing::SizeKind kind = k > 0 ? sizing::SizeKind::flow : options.start;
    reporter.info(fmt::format("adapt: cycle {} of {}: {} surface of about {:.0f} triangles", k, options.cycles,
                              k > 0 ? "the last flow's" : sizing::size_kind_name(kind), options.target_triangles));
    auto step = Clock::now();
    std::vector<Sym3> flow_metric;
    if (k > 0) {
      const post::WallMetric wall = post::wall_error_metric(before, {}, options.error, reporter);
      flow_metric = remesh::carry_metric(wall.wall, wall.metric, input, before + "'s wall");
    }
    const sizing::SizeField field = sizing::make_size_field(
        input, {.kind = kind, .target_triangles = options.target_triangles},
        {.curvature = &curvature, .distance = &distance, .flow = k > 0 ? &flow_metric : nullptr}, reporter);
    const remesh::RemeshResult remeshed =
        remesh::adapt_to_count(input, field.metric, options.target_triangles, remesh_options, reporter);
    io::write_vtp(c.folder + "/surface.vtp", remeshed.mesh);
    c.remesh_seconds = since(step);

    step = Clock::now();
    volume::VolumeOptions vo = options.volume;
    vo.end_at = end_at;
    if (k > 0) size_volume_to_flow(vo, before, options.error, options.y_plus, flow_case, reporter);
    const centerline::DistanceMap wall_distance =
        centerline::distance_map(remeshed.mesh, centerline::extract(remeshed.mesh, {}, reporter));
    const std::vector<analysis::OpenEnd> ends = analysis::open_ends(remeshed.mesh);
    const volume::VolumeResult volume =
        points > 0 ? volume::build_volume_with_points(remeshed.mesh, ends, wall_distance.radius, vo, points, 0.02,
                                                      reporter)
                   : volume::build_volume(remeshed.mesh, ends, wall_distance.radius, vo, reporter);
    io::write_msh(c.folder + "/volume.msh", volume.mesh);
    const volume::VolumeQuality quality = volume::measure_volume(volume.mesh, volume.radius);
    if (points == 0) points = volume.mesh.num_points();  // the later cycles at the first mesh's count
    // The later cycles' ends named as the first mesh's were (by their centres): ends of about equal size
    // would otherwise swap the inlet with another end where a remeshed end came out a little larger.
    if (end_at.empty())
      for (const volume::VolumeEnd& e : volume.report.ends) end_at.push_back({e.name, e.center});
    c.volume_seconds = since(step);

    step = Clock::now();
    flow::FlowCase fc = flow_case;
    fc.mesh = c.folder + "/volume.msh";
    const flow::SimulationSummary s = flow::simulate(fc, c.folder + "/flow", "", reporter);
    if (s.status != "completed")
      throw InputError(fmt::format("adapt: cycle {}'s flow {} ({}/flow/summary.json)", k, s.status, c.folder));
    c.flow_seconds = since(step);

    const post::WallField wall = last_wall(c.folder + "/flow");
    const std::vector<double> area = lumped_areas(wall.mesh);
    c.wall_mean_wss = wall_difference(area, wall.wss, wall.wss).mean;
    c.change_l2 = c.change_p95 = NAN;
    if (k > 0) {
      const post::WallField last = last_wall(before);
      const WallDifference d = wall_difference(area, interpolate(map_onto(last.mesh, wall.mesh), last.wss), wall.wss);
      c.change_l2 = d.l2;
      c.change_p95 = d.p95;
    }
    c.triangles = remeshed.stats.triangles;
    c.surface_points = remeshed.stats.points;
    c.volume_points = quality.points;
    c.dofs = s.dofs;
    c.min_dihedral_interior = quality.min_dihedral_interior;
    reporter.info(fmt::format("adapt: cycle {}: {} triangles, {} volume points; the wall's WSS moved {} from the "
                              "cycle before (L2 over its mean {:.4g} Pa)",
                              k, c.triangles, c.volume_points,
                              k > 0 ? fmt::format("{:.2f} %", 100.0 * c.change_l2) : std::string("(first mesh)"),
                              c.wall_mean_wss));
    out.push_back(c);
  }
  nlohmann::json cycles = nlohmann::json::array();
  for (const AdaptCycle& c : out)
    cycles.push_back({{"cycle", c.cycle}, {"folder", c.folder}, {"triangles", c.triangles},
                      {"surface_points", c.surface_points}, {"volume_points", c.volume_points}, {"dofs", c.dofs},
                      {"min_dihedral_interior_deg", c.min_dihedral_interior},
                      {"seconds", {{"remesh", c.remesh_seconds}, {"volume", c.volume_seconds}, {"flow", c.flow_seconds}}},
                      {"wall_mean_wss_Pa", c.wall_mean_wss},
                      {"wss_change_l2", std::isfinite(c.change_l2) ? nlohmann::json(c.change_l2) : nlohmann::json()},
                      {"wss_change_p95", std::isfinite(c.change_p95) ? nlohmann::json(c.change_p95) : nlohmann::json()}});
  const nlohmann::json summary = {{"units", {{"lengths", "mm"}, {"wss", "Pa"}}},
                                  {"start", sizing::size_kind_name(options.start)},
                                  {"target_triangles", options.target_triangles},
                                  {"target_points", points},
                                  {"error_norm", options.error.p},
                                  {"cycles", cycles}};
  io::write_text(folder + "/summary.json", summary.dump(2) + "\n");
  return out;
}

}  // namespace vesselmesh::study
