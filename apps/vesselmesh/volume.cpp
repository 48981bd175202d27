// vesselmesh volume: boundary layer, caps and interior tetrahedra (volume/volume_mesh.h);
// vesselmesh quality: the figures of a volume mesh (volume/quality.h).
#include "commands.h"

#include "io/msh.h"
#include "io/volume_file.h"
#include "io/vtk_formats.h"
#include "mesh/error.h"
#include "mesh/geometry.h"
#include "post/fluid_metric.h"
#include "post/wall_metric.h"
#include "volume/quality.h"
#include "volume/volume_mesh.h"

#include <fmt/format.h>

#include <filesystem>

namespace vesselmesh::cli {
namespace {

// --refine x,y,z:x,y,z:RADIUS:SIZE, or OptionError quoting it.
volume::RefineRegion parse_region(const std::string& text) {
  const std::vector<std::string> parts = split(text, ':');
  const auto fail = [&] {
    return OptionError(fmt::format("--refine '{}': give x,y,z:x,y,z:RADIUS:SIZE (two points, a radius and a size "
                                   "> 0, in the mesh's unit)",
                                   text));
  };
  if (parts.size() != 4) throw fail();
  volume::RefineRegion r;
  r.from = parse_point(parts[0], "--refine");
  r.to = parse_point(parts[1], "--refine");
  try {
    size_t used_radius = 0, used_size = 0;
    r.radius = std::stod(parts[2], &used_radius);
    r.size = std::stod(parts[3], &used_size);
    if (used_radius != parts[2].size() || used_size != parts[3].size()) throw fail();
  } catch (const std::exception&) {
    throw fail();
  }
  if (!(r.radius > 0.0 && r.size > 0.0 && std::isfinite(r.radius) && std::isfinite(r.size))) throw fail();
  return r;
}

Json quality_json(const volume::VolumeQuality& q) {
  Json tags = Json::object();
  for (const auto& [name, count] : q.triangles_per_tag) tags[name] = count;
  Json json = {{"points", q.points},
               {"tetrahedra", q.tets},
               {"prisms", q.prisms},
               {"boundary_triangles", tags},
               {"inverted", q.inverted},
               {"closed_boundary", q.closed},
               {"open_faces", q.open_faces},
               {"stray_triangles", q.stray_triangles},
               {"dihedral_deg",
                {{"min", round_to(q.min_dihedral, 4)},
                 {"median", round_to(q.median_dihedral, 4)},
                 {"max", round_to(q.max_dihedral, 4)},
                 {"min_layer", q.min_dihedral_layer >= 0 ? Json(round_to(q.min_dihedral_layer, 4)) : Json(nullptr)},
                 {"min_layer_frame",
                  q.min_dihedral_layer_frame >= 0 ? Json(round_to(q.min_dihedral_layer_frame, 4)) : Json(nullptr)},
                 {"min_interior", q.min_dihedral_interior >= 0 ? Json(round_to(q.min_dihedral_interior, 4)) : Json(nullptr)}}},
               {"worst_scaled_jacobian", round_to(q.worst_scaled_jacobian, 4)},
               {"worst_aspect_ratio", round_to(q.worst_aspect_ratio, 4)}};
  if (q.has_layers) {
    json["boundary_layer"] = {
        {"wall_triangles", q.wall_triangles},
        {"layers_min", q.min_layers},
        {"layers_max", q.max_layers},
        {"thickness_over_radius_min", q.min_thickness_ratio >= 0 ? Json(round_to(q.min_thickness_ratio, 4)) : Json(nullptr)},
        {"thickness_over_radius_max", q.max_thickness_ratio >= 0 ? Json(round_to(q.max_thickness_ratio, 4)) : Json(nullptr)}};
  } else {
    json["boundary_layer"] = nullptr;
  }
  return json;
}

std::string quality_text(const volume::VolumeQuality& q) {
  std::string tags;
  for (const auto& [name, count] : q.triangles_per_tag) tags += fmt::format("{}{} {}", tags.empty() ? "" : ", ", name, count);
  std::string text = fmt::format(
      "{} points, {} tetrahedra, {} prisms; boundary triangles: {}; inverted {}; boundary {}; dihedral angles min {:.2f} "
      "median {:.1f} max {:.1f} deg",
      q.points, q.tets, q.prisms, tags, q.inverted,
      q.closed ? "closed" : fmt::format("OPEN ({} faces untagged, {} stray triangles)", q.open_faces, q.stray_triangles),
      q.min_dihedral, q.median_dihedral, q.max_dihedral);
  if (q.min_dihedral_layer >= 0) {
    text += fmt::format(" (layer {:.2f}", q.min_dihedral_layer);
    if (q.min_dihedral_layer_frame >= 0) text += fmt::format(", {:.2f} in the layer's frame", q.min_dihedral_layer_frame);
    text += fmt::format(", interior {:.2f})", q.min_dihedral_interior);
  }
  text += fmt::format("; worst scaled Jacobian {:.3f}, worst aspect ratio {:.2f}", q.worst_scaled_jacobian, q.worst_aspect_ratio);
  if (q.has_layers) {
    text += fmt::format("; layers per wall triangle {}..{}", q.min_layers, q.max_layers);
    if (q.min_thickness_ratio >= 0)
      text += fmt::format(", thickness {:.3f}..{:.3f} of the local radius", q.min_thickness_ratio, q.max_thickness_ratio);
  }
  return text;
}

// The command's options as given.
struct VolumeCommandOptions {
  SurfaceInput surface;
  std::string output, algorithm = "delaunay", end_names;
  std::vector<std::string> ends;
  std::vector<std::string> refine;
  std::string flow;
  std::vector<double> flow_times;
  double layer_y_plus = 1.0;
  double error_norm = 2.0;
  volume::VolumeOptions volume;
  int target_points = 0;
  CommonOptions common;
};

// What `vesselmesh volume` does with them: the volume made, checked, written and reported.
int run_volume(const VolumeCommandOptions& o) {
    io::check_volume_output(o.output);
    volume::VolumeOptions options = o.volume;
    options.algorithm = volume::parse_fill_algorithm(o.algorithm);
    if (!o.end_names.empty()) options.end_names = split(o.end_names, ',');
    for (const std::string& text : o.refine) options.interior.regions.push_back(parse_region(text));
    for (const std::string& text : o.ends) {
      auto [name, point] = parse_named_point(text, "--end");
      options.end_at.push_back({name, point});
    }
    TerminalReporter reporter(o.common.quiet);
    const auto start = std::chrono::steady_clock::now();
    const CheckedSurface surface = read_surface_input(o.surface, reporter);
    const TriMesh& wall = surface.file.mesh;
    if (surface.ends.empty())
      throw InputError(fmt::format("{}: the surface has no open or flat-capped end: a flow domain needs an inlet and "
                                   "an outlet; cut the vessel's ends open",
                                   o.surface.path));
    volume::check_interior_size_options(options.interior);
    if (o.flow.empty() && (!o.flow_times.empty() || o.error_norm != 2.0 || o.layer_y_plus != 1.0))
      throw OptionError("--flow-time, --error-norm and --layer-y-plus go with --flow");
    int target_points = o.target_points;
    Json flow_json = nullptr;
    if (!o.flow.empty()) {  // the interior's sizes from the flow's velocity (issue 52), at the flow mesh's count
      post::FluidSizes sizes = post::fluid_error_sizes(o.flow, o.flow_times, options.interior.gradation,
                                                       {.p = o.error_norm}, reporter);
      if (target_points == 0) target_points = sizes.mesh.num_points();
      const auto [low, high] = std::minmax_element(sizes.sizes.begin(), sizes.sizes.end());
      flow_json = {{"folder", o.flow}, {"times_s", sizes.times}, {"error_norm", o.error_norm},
                   {"flow_mesh_points", sizes.mesh.num_points()},
                   {"size_mm", {{"min", round_to(*low, 5)}, {"max", round_to(*high, 5)}}}};
      options.interior.flow = post::size_function(std::move(sizes));
      if (o.layer_y_plus > 0.0 && options.layer.layers > 0) {  // the first layer's height from the wall shear
        post::WallHeights heights = post::first_layer_heights(o.flow, o.flow_times, o.layer_y_plus, {}, reporter);
        const auto least = std::min_element(heights.heights.begin(), heights.heights.end());
        flow_json["layer_y_plus"] = o.layer_y_plus;
        flow_json["least_first_height_mm"] = round_to(*least, 6);
        options.layer.first_height = post::height_function(std::move(heights));
      }
    }
    // The layer's thickness and the interior's core bound follow the local radius: the
    // distance map (without a layer, a surface whose centerlines cannot be traced is
    // filled without the core bound, said).
    std::vector<double> radius;
    try {
      radius = centerline::distance_map(wall, centerline::extract(wall, {}, reporter)).radius;
    } catch (const InputError& e) {
      if (options.layer.layers > 0) throw;
      reporter.warning(fmt::format("no centerlines ({}): the interior's core is not bounded by the radius",
                                   e.what()));
    }
    const volume::VolumeResult result =
        target_points > 0 ? volume::build_volume_with_points(wall, surface.ends, radius, options,
                                                              target_points, 0.02, reporter)
                             : volume::build_volume(wall, surface.ends, radius, options, reporter);
    io::write_volume(o.output, result.mesh, {Field::scalar("radius", result.radius)});
    const volume::VolumeQuality q = volume::measure_volume(result.mesh, result.radius);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const volume::VolumeReport& r = result.report;
    if (o.common.json) {
      Json ends = Json::array();
      for (const volume::VolumeEnd& end : r.ends)
        ends.push_back({{"name", end.name},
                        {"tag", end.tag},
                        {"center", to_json(end.center)},
                        {"normal", to_json(end.normal)},
                        {"radius", round_to(end.radius, 6)},
                        {"capped_in_input", end.capped},
                        {"cap_triangles", end.cap_triangles}});
      Json json = quality_json(q);
      json["input"] = o.surface.path;
      json["output"] = o.output;
      json["units"] = "mm";
      json["algorithm"] = volume::fill_algorithm_name(options.algorithm);
      json["layers"] = r.layers;
      json["layer_cells"] = r.layer_tets + r.layer_prisms;
      json["interior_tetrahedra"] = r.interior_tets;
      json["interior_points"] = r.interior_points;
      json["interior_size"] = {{"factor", r.interior_factor},
                               {"gradation", options.interior.gradation},
                               {"core_fraction", options.interior.core_fraction},
                               {"refine", o.refine},
                               {"flow", flow_json},
                               {"at_wall_mm", {{"min", round_to(r.interior_size_min, 5)},
                                               {"median", round_to(r.interior_size_median, 5)},
                                               {"max", round_to(r.interior_size_max, 5)}}}};
      json["wall_tag"] = r.wall_tag;
      json["ends"] = ends;
      json["slivers"] = {{"angle_deg", options.sliver_angle_deg},
                         {"below_before", r.slivers.below_before},
                         {"below_after", r.slivers.below_after},
                         {"least_before_deg", round_to(r.slivers.least_before, 4)},
                         {"least_after_deg", round_to(r.slivers.least_after, 4)},
                         {"flips", r.slivers.flips},
                         {"moves", r.slivers.moves},
                         {"insertions", r.slivers.insertions},
                         {"collapses", r.slivers.collapses}};
      json["first_height_capped"] = r.first_height_capped;
      json["shrink"] = {{"wall_points", r.shrunk_vertices},
                        {"least_fraction", round_to(r.least_fraction, 4)},
                        {"least_at", to_json(r.least_at)}};
      json["thicken"] = {{"angle_deg", options.layer.min_angle_deg},
                         {"wall_points", r.thickened_vertices},
                         {"most_fraction", round_to(r.most_fraction, 4)},
                         {"most_at", to_json(r.most_at)},
                         {"under_angle_prisms", r.under_angle_prisms},
                         {"least_layer_angle_deg", round_to(r.least_layer_angle, 4)}};
      json["split"] = {{"angle_deg", options.layer.split_angle_deg}, {"wall_edges", r.split_edges}};
      json["seconds"] = round_to(seconds, 4);
      print_json(json);
    } else {
      std::string names;
      for (const volume::VolumeEnd& end : r.ends)
        names += fmt::format("{}{} (tag {}) at {}", names.empty() ? "" : ", ", end.name, end.tag,
                             mesh::format_point(end.center));
      reporter.info(fmt::format("ends: {}", names));
      reporter.info(quality_text(q));
      reporter.info(fmt::format("{:.1f} s; wrote {} (mm)", seconds, o.output));
    }
    return 0;
}

}  // namespace

Command add_volume_command(CLI::App& parent) {
  CLI::App* app = parent.add_subcommand(
      "volume",
      "Builds the volume mesh of the lumen: --layers prism layers extruded inward from the wall (total thickness "
      "--thickness-ratio x the local radius from the distance map, shrunk smoothly where columns would cross, grown "
      "where the wall's triangles are too wide for --layer-angle, and reported), each prism cut into three tetrahedra; a planar quality cap on each end; tetrahedra inside "
      "sized by design whatever the --algorithm: the wall's area-equivalent size (the side of an equilateral triangle of "
      "its triangles' mean area: sqrt(h1 h2) on an anisotropic wall, so that equal surface counts give comparable "
      "volumes) carried inward, growing by --interior-gradation from the layer, the core at most a tenth of the local "
      "radius (never finer than the wall), times --interior-size. "
      "Boundary tags: wall, inlet (the largest end unless --inlet), outlet_1, ... in the order of 'vesselmesh info'. "
      "Give a remeshed surface (vesselmesh remesh): the layer stands on its triangles");
  auto o = std::make_shared<VolumeCommandOptions>();
  add_surface_input(*app, o->surface);
  app->add_option("-o,--output", o->output,
                  "Output volume mesh: .vtu (cell data tag, layer, column; point data radius) or .msh (Gmsh 4.1, physical "
                  "groups)")
      ->required();
  app->add_option("--layers", o->volume.layer.layers, "Boundary-layer layers (0: none)")
      ->check(CLI::Range(0, 100))
      ->capture_default_str();
  app->add_option("--thickness-ratio", o->volume.layer.thickness_ratio, "Layer thickness over the local radius")
      ->check(CLI::Range(1e-6, 0.5))
      ->capture_default_str();
  app->add_option("--growth", o->volume.layer.growth, "Height ratio of successive layers, from the wall (1: uniform)")
      ->check(CLI::Range(0.2, 5.0))
      ->capture_default_str();
  app->add_option("--layer-angle", o->volume.layer.min_angle_deg,
                  "The layer grows thicker than asked (up to half the radius, reported) where the wall's triangles are "
                  "so large against its thinnest layer that its tetrahedra would have a dihedral angle under this "
                  "(degrees); 0: the thickness asked, whatever the angles")
      ->check(CLI::Range(0.0, 30.0))
      ->capture_default_str();
  app->add_option("--layer-split-angle", o->volume.layer.split_angle_deg,
                  "Wall triangles whose layer tetrahedra stay under this dihedral angle (degrees) once the layer is "
                  "built (a thin layer over stretched triangles, as on an anisotropic wall) have their longest edge "
                  "halved, and the layer is built again: the wall gains points (reported), keeps its shape and the "
                  "layer its thickness; 0: the wall's triangles as given")
      ->check(CLI::Range(0.0, 30.0))
      ->capture_default_str();
  app->add_option("--algorithm", o->algorithm,
                  "Interior tetrahedra: delaunay (Gmsh's; the same mesh run after run), hxt (Gmsh's HXT: threaded, "
                  "fewer slivers, but not the same mesh twice), tetgen (TetGen 1.5: quality-bounded, the same mesh "
                  "run after run), or frontal (needs a Gmsh built with Netgen)")
      ->check(CLI::IsMember({"delaunay", "frontal", "hxt", "tetgen"}))
      ->capture_default_str();
  app->add_option("--interior-size", o->volume.interior.factor,
                  "Scales the interior's size field (1: the wall's area-equivalent size; 2: edges twice as long, about "
                  "an eighth of the interior points)")
      ->capture_default_str();
  app->add_option("--interior-gradation", o->volume.interior.gradation,
                  "Growth of the interior's sizes with the depth below the boundary layer: the size grows by ln(g) per "
                  "unit length, as the surface's gradation (1: the wall's size throughout, up to the core bound)")
      ->capture_default_str();
  app->add_option("--target-points", o->target_points,
                  "A volume of about this many points (within 2 %): --interior-size is the start, then scaled (the "
                  "layer and the wall kept, only the interior's count moves; at most four builds); the factor used is "
                  "printed and in --json (interior_size.factor). For comparing meshes of equal volume counts")
      ->check(CLI::PositiveNumber);
  app->add_option("--flow", o->flow,
                  "A 'vesselmesh simulate' output folder (with fluid frames: its case's output.fluid_every) on a first "
                  "mesh of this vessel: the interior is sized where the velocity's linear interpolation error asks "
                  "(its Hessians recovered over the flow's mesh, bounded together over --flow-time, graded by "
                  "--interior-gradation) in place of the core bound, the wall's growth inward kept; the volume gets "
                  "the flow mesh's point count unless --target-points says otherwise (the flow-adapted kind, the "
                  "surface from 'vesselmesh remesh --size flow')");
  app->add_option("--flow-time", o->flow_times,
                  "--flow: the times (s) whose velocity to bound (repeat; default: every saved fluid frame of the last "
                  "period, or the last frame of a steady flow)");
  app->add_option("--error-norm", o->error_norm,
                  "--flow: p of the L^p norm of the velocity's interpolation error that the sizes make least for the "
                  "count (larger: closer to bounding the largest error)")
      ->check(CLI::Range(1.0, 1e6))
      ->capture_default_str();
  app->add_option("--layer-y-plus", o->layer_y_plus,
                  "--flow: the first layer no higher than this y+ in the flow's largest wall shear over --flow-time "
                  "(y = y+ mu / sqrt(rho |WSS|), the near-wall viscous length; the fluid from the flow's summary): "
                  "where that is below the first layer's height, the layers there grow from it over the same "
                  "thickness (growth up to 2, beyond which the layer is thinner), graded along the wall; 0: the "
                  "layers as --thickness-ratio and --growth give them")
      ->check(CLI::Range(0.0, 1e6))
      ->capture_default_str();
  app->add_option("--sliver-angle", o->volume.sliver_angle_deg,
                  "Interior tetrahedra with a dihedral angle under this (degrees) are improved after the fill by flips, "
                  "moves of inside points and insertions (the boundary is kept); 0: the fill as it comes")
      ->check(CLI::Range(0.0, 30.0))
      ->capture_default_str();
  app->add_flag("--keep-prisms", o->volume.keep_prisms, "Write the layer's prisms instead of cutting them into tetrahedra");
  app->add_option("--inlet", o->volume.inlet, "The end that is the inlet, numbered from 0 as 'vesselmesh info' lists them "
                                              "(default: the largest)");
  app->add_option("--end-names", o->end_names,
                  "Names of all ends, comma-separated, in the order of 'vesselmesh info' (instead of inlet, outlet_1, ...)");
  app->add_option("--end", o->ends,
                  "NAME:x,y,z names the end whose centre is nearest the point (repeat it for every end; instead of "
                  "--inlet and --end-names, and the same whatever order the ends come in)");
  app->add_option("--refine", o->refine,
                  "x,y,z:x,y,z:RADIUS:SIZE — the interior no coarser than SIZE within RADIUS of the segment between "
                  "the two points (mesh units), graded outward by --interior-gradation: where the flow, not the wall, "
                  "asks for a finer mesh (a jet and its shear layer). Repeat it for several regions");
  app->add_option("--threads", o->volume.threads, "Threads for HXT (0: all)")->check(CLI::NonNegativeNumber);
  add_common_options(*app, o->common);
  return {app, [o] { return run_volume(*o); }};
}

Command add_quality_command(CLI::App& parent) {
  CLI::App* app = parent.add_subcommand(
      "quality",
      "Figures of a volume mesh (.msh or .vtu, as 'vesselmesh volume' or Gmsh writes it): points, tetrahedra, triangles per "
      "tag, inverted cells, dihedral angles, worst scaled Jacobian and aspect ratio, whether the tagged boundary closes "
      "the volume. Exit code 3 when a cell is inverted or the boundary is open");
  struct Options {
    std::string mesh;
    CommonOptions common;
  };
  auto o = std::make_shared<Options>();
  app->add_option("MESH", o->mesh, "Volume mesh (.msh or .vtu)")->required();
  add_common_options(*app, o->common);
  return {app, [o] {
            TerminalReporter reporter(o->common.quiet);
            io::check_volume_output(o->mesh);  // .msh or .vtu, else an option error
            const TetMesh mesh = io::read_volume(o->mesh);
            const volume::VolumeQuality q = volume::measure_volume(mesh);
            if (o->common.json) {
              Json json = quality_json(q);
              json["mesh"] = o->mesh;
              print_json(json);
            } else {
              reporter.info(quality_text(q));
            }
            return q.inverted == 0 && q.closed ? 0 : 3;
          }};
}

}  // namespace vesselmesh::cli
