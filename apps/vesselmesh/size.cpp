// vesselmesh size: the size field (an SPD metric per point) the remesher adapts to.
#include "commands.h"

#include "analysis/curvature.h"
#include "centerline/distance_map.h"
#include "io/medit.h"
#include "io/surface.h"
#include "mesh/error.h"
#include "post/wall_metric.h"
#include "sizing/metric.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>

namespace vesselmesh::cli {

void add_sizing_options(CLI::App& app, SizingArgs& args, bool size_required) {
  app.add_option("--size", args.kind,
                 "Size field: uniform, distance, curvature, anisotropic, or flow (adapted to a flow's wall shear "
                 "stress: give --flow and --target-triangles)")
      ->required(size_required)
      ->check(CLI::IsMember({"uniform", "distance", "curvature", "anisotropic", "flow"}));
  app.add_option("--flow", args.flow,
                 "--size flow: a 'vesselmesh simulate' output folder. The size field is finest where the linear "
                 "interpolation of its WSS errs most (the recovered Hessian of each WSS component on its wall, "
                 "intersected over the saved times, normalized for the error's L^p norm), anisotropic along the "
                 "Hessian's directions");
  app.add_option("--flow-time", args.flow_times,
                 "--size flow: the times (s) whose WSS to bound (repeat; default: every saved frame of the last "
                 "period, or the last frame of a steady flow)");
  app.add_option("--error-norm", args.error_norm,
                 "--size flow: p of the L^p norm of the WSS's interpolation error that the field makes least for its "
                 "count (larger: closer to bounding the largest error)")
      ->check(CLI::Range(1.0, 1e6))
      ->capture_default_str();
  app.add_option("--h", args.options.h, "Uniform size (mm)");
  app.add_option("--points-per-circle", args.options.points_per_circle,
                 "N: points around the vessel (distance) or on the osculating circle (curvature)")
      ->capture_default_str();
  app.add_option("--hmin", args.options.hmin, "Smallest size (mm; default a tenth of the small vessels' radius)");
  app.add_option("--hmax", args.options.hmax, "Largest size (mm; default the large vessels' radius)");
  app.add_option("--gradation", args.options.gradation, "Largest growth of the size per unit of metric length (<= 1: none)")
      ->capture_default_str();
  app.add_option("--max-chord-error", args.options.max_chord_error,
                 "Also bound the size by this chord error (mm): h <= sqrt(8 eps / |k|), the largest |k| (anisotropic: along "
                 "each principal direction)");
  app.add_option("--target-triangles", args.options.target_triangles, "Scale the field to about this many triangles");
}

SizedSurface size_surface(const CheckedSurface& surface, const SizingArgs& args, const Reporter& reporter) {
  SizedSurface out;
  sizing::SizingOptions options = args.options;
  options.kind = sizing::parse_size_kind(args.kind);
  const TriMesh& mesh = surface.file.mesh;
  const bool flow = options.kind == sizing::SizeKind::flow;
  if (flow != !args.flow.empty()) throw OptionError("--size flow and --flow FOLDER go together");
  if (!flow && (!args.flow_times.empty() || args.error_norm != 2.0))
    throw OptionError("--flow-time and --error-norm go with --size flow");
  if (flow && !(options.target_triangles > 0.0))
    throw OptionError("--size flow needs --target-triangles: the flow says where to refine, the count how much");
  if (options.kind != sizing::SizeKind::uniform || options.max_chord_error > 0.0)
    out.curvature = analysis::curvature(mesh, {}, reporter);
  if (flow) {
    const post::WallMetric wall = post::wall_error_metric(args.flow, args.flow_times, {.p = args.error_norm}, reporter);
    out.flow_metric = remesh::carry_metric(wall.wall, wall.metric, mesh, fmt::format("{}: the flow's wall", args.flow));
    out.flow_times = wall.times;
  }
  if (options.kind != sizing::SizeKind::uniform) {
    // Centerlines give the distance field and the radius range; without ends, the curvature
    // kinds fall back on the curvature for the range.
    try {
      out.centerlines = centerline::extract(mesh, {}, reporter);
      out.distance = centerline::distance_map(mesh, *out.centerlines);
    } catch (const InputError& e) {
      if (options.kind == sizing::SizeKind::distance) throw InputError(fmt::format("{}: {}", surface.file.path, e.what()));
      reporter.warning(fmt::format("no centerlines ({}); the radius range comes from the curvature", e.what()));
    }
  }
  sizing::SizeInputs inputs{.curvature = out.curvature ? &*out.curvature : nullptr,
                            .distance = out.distance ? &*out.distance : nullptr,
                            .flow = out.flow_metric ? &*out.flow_metric : nullptr};
  out.field = sizing::make_size_field(mesh, options, inputs, reporter);
  return out;
}

std::vector<Field> size_fields(const SizedSurface& sized) {
  const sizing::SizeField& field = sized.field;
  std::vector<Field> out = {Field::scalar("size", field.size), metric_field(field.metric)};
  if (sized.distance) out.push_back(Field::scalar("radius", sized.distance->radius));
  return out;
}

Json size_json(const sizing::SizeField& field) {
  std::vector<double> sizes = field.size;
  std::sort(sizes.begin(), sizes.end());
  auto at = [&](double q) { return round_to(sizes[static_cast<size_t>(q * (sizes.size() - 1))]); };
  return {{"kind", sizing::size_kind_name(field.kind)},
          {"hmin", round_to(field.hmin)},
          {"hmax", std::isfinite(field.hmax) ? Json(round_to(field.hmax)) : Json(nullptr)},
          {"scale", round_to(field.scale)},
          {"predicted_triangles", std::lround(field.predicted_triangles)},
          {"gradation_passes", field.gradation_passes},
          {"size", {{"min", at(0.0)}, {"median", at(0.5)}, {"max", at(1.0)}}}};
}

Command add_size_command(CLI::App& parent) {
  CLI::App* app = parent.add_subcommand(
      "size", "The size field the remesher adapts to: per point an SPD metric (isotropic: I/h^2) from a uniform size, "
              "the distance to the centerline, the mean curvature, the principal curvatures (anisotropic), or where a "
              "flow's WSS is least well interpolated (flow); clamped, "
              "graded, optionally scaled to a triangle count. Writes point data size (mm), metric (xx,xy,xz,yy,yz,zz) "
              "and, when the surface has ends, radius (mm, the distance map's, for the remesher's distance bound)");
  struct Options {
    SurfaceInput surface;
    std::string output, medit;
    SizingArgs sizing;
    CommonOptions common;
  };
  auto o = std::make_shared<Options>();
  add_surface_input(*app, o->surface);
  app->add_option("-o,--output", o->output, "Output .vtp with point data size and metric")->required();
  add_sizing_options(*app, o->sizing);
  app->add_option("--medit", o->medit,
                  "Also write BASE.mesh (the checked surface) and BASE.sol (the metric), Medit files for MMG's mmgs");
  add_common_options(*app, o->common);
  return {app, [o] {
            if (io::surface_format(o->output) != io::SurfaceFormat::vtp)
              throw OptionError(fmt::format("{}: the size field is written as VTP point data: use a .vtp name", o->output));
            TerminalReporter reporter(o->common.quiet);
            const CheckedSurface surface = read_surface_input(o->surface, reporter);
            const auto start = std::chrono::steady_clock::now();
            const SizedSurface sized = size_surface(surface, o->sizing, reporter);
            const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
            io::write_vtp(o->output, surface.file.mesh, size_fields(sized));
            if (!o->medit.empty()) {
              io::write_medit(o->medit + ".mesh", surface.file.mesh);
              io::write_medit_metric(o->medit + ".sol", sized.field.metric);
            }
            if (o->common.json) {
              Json json = size_json(sized.field);
              json["input"] = o->surface.path;
              json["output"] = o->output;
              json["units"] = "mm";
              json["points"] = surface.file.mesh.num_points();
              if (sized.flow_metric) json["flow_times_s"] = sized.flow_times;
              json["seconds"] = round_to(seconds, 4);
              print_json(json);
            } else {
              reporter.info(fmt::format("{} size field: sizes {:.3g} to {:.3g} mm, about {:.0f} triangles; wrote {}",
                                        o->sizing.kind, *std::min_element(sized.field.size.begin(), sized.field.size.end()),
                                        *std::max_element(sized.field.size.begin(), sized.field.size.end()),
                                        sized.field.predicted_triangles, o->output));
            }
            return 0;
          }};
}

}  // namespace vesselmesh::cli
