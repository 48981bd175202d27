// vesselmesh remesh: the surface adapted to a size field (remesh/adapt.h).
#include "commands.h"

#include "io/surface.h"
#include "mesh/error.h"
#include "remesh/adapt.h"
#include "remesh/reparametrize.h"
#include "sizing/metric.h"

#include <Eigen/Eigenvalues>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace vesselmesh::cli {
namespace {

// The metric stored in FIELD.vtp (`vesselmesh size` writes one): point data `metric` (6
// components) or `size` (mm, isotropic). A field on the same points is taken as it is; one on
// another surface is carried over by projecting each point onto it (log-Euclidean
// interpolation inside its triangles). The field's `radius` (the distance map's), when it has
// one on the same points, goes to `radius`.
std::vector<Sym3> read_metric(const std::string& path, const TriMesh& surface, std::vector<double>& radius) {
  const io::SurfaceFile file = io::read_surface(path);
  std::vector<Sym3> metric(file.mesh.points.size());
  const Field* tensor = nullptr;
  const Field* size = nullptr;
  for (const Field& f : file.point_data) {
    if (f.name == "metric" && f.components == 6) tensor = &f;
    if (f.name == "size" && f.components == 1) size = &f;
  }
  if (!tensor && !size)
    throw InputError(fmt::format("{}: no point data 'metric' (6 components: xx, xy, xz, yy, yz, zz) nor 'size' (mm); "
                                 "write the field with 'vesselmesh size'",
                                 path));
  for (size_t v = 0; v < metric.size(); ++v) {
    if (tensor) {
      std::copy_n(tensor->values.begin() + 6 * v, 6, metric[v].v.begin());
    } else {
      const double h = size->values[v];
      metric[v] = Sym3{{1.0 / (h * h), 0.0, 0.0, 1.0 / (h * h), 0.0, 1.0 / (h * h)}};
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(metric[v].matrix());
    if (!metric[v].matrix().allFinite() || eigen.eigenvalues().minCoeff() <= 0.0)
      throw InputError(fmt::format("{}: point {}: the metric is not symmetric positive definite (eigenvalues {:.4g}, "
                                   "{:.4g}, {:.4g})",
                                   path, v, eigen.eigenvalues()[0], eigen.eigenvalues()[1], eigen.eigenvalues()[2]));
  }
  if (file.mesh.points == surface.points) {
    for (const Field& f : file.point_data)
      if (f.name == "radius" && f.components == 1) radius = f.values;
    return metric;
  }
  return remesh::carry_metric(file.mesh, metric, surface, fmt::format("{}: the field's surface", path));
}

}  // namespace

Json remesh_json(const remesh::RemeshStats& s) {
  return {{"points", s.points},
          {"triangles", s.triangles},
          {"edges_in_unit_range", round_to(s.edges_in_unit_range, 4)},
          {"min_angle_deg", round_to(s.min_angle_deg, 4)},
          {"mean_quality", round_to(s.mean_quality, 4)},
          {"min_quality", round_to(s.min_quality, 4)},
          {"hausdorff", round_to(s.hausdorff, 4)},
          {"hausdorff_relative", s.hausdorff_relative >= 0.0 ? Json(round_to(s.hausdorff_relative, 4)) : Json(nullptr)},
          {"hausdorff_facets", round_to(s.hausdorff_facets, 4)},
          {"hausdorff_facets_relative",
           s.hausdorff_facets_relative >= 0.0 ? Json(round_to(s.hausdorff_facets_relative, 4)) : Json(nullptr)},
          {"seconds", round_to(s.seconds, 4)},
          {"operations",
           {{"splits", s.splits},
            {"collapses", s.collapses},
            {"flips", s.flips},
            {"moves", s.moves},
            {"distance_refinements", s.refinements}}}};
}

void write_remeshed(const std::string& path, const remesh::RemeshResult& result) {
  std::vector<double> quality(result.mesh.num_triangles());
  for (int t = 0; t < result.mesh.num_triangles(); ++t) {
    const Triangle& f = result.mesh.triangles[t];
    quality[t] = sizing::triangle_quality(result.mesh.points[f[0]], result.mesh.points[f[1]], result.mesh.points[f[2]],
                                          result.metric[f[0]], result.metric[f[1]], result.metric[f[2]]);
  }
  io::write_surface(path, result.mesh, {metric_field(result.metric)}, {Field::scalar("quality", quality)});
}

Command add_remesh_command(CLI::App& parent) {
  CLI::App* app = parent.add_subcommand(
      "remesh",
      "Adapts the surface to a size field by local operations in the metric (split, collapse, flip, move; as MMG's "
      "mmgs): edges of unit metric length, well-shaped triangles, every point on the input. Open ends, creases and label "
      "borders are kept as feature lines; labels follow their triangles. The distance from the input stays below "
      "--hausdorff (mm) and --hausdorff-relative times the local vessel radius, measured against the smooth surface the input's "
      "triangles stand for (Phong tessellation through the input's points and normals: on a coarse, faceted "
      "segmentation the output follows the vessel, not its facets; --keep-facets: against the triangles themselves, as "
      "mmgs); --json gives both distances (hausdorff, hausdorff_facets). --engine gmsh takes the seed paper's "
      "route instead: Gmsh cuts the surface into patches it can flatten, meshes each in its plane to the same field and "
      "maps it back");
  struct Options {
    SurfaceInput surface;
    std::string output, metric;
    SizingArgs sizing;
    remesh::RemeshOptions remesh;
    std::string engine = "native", gmsh_algorithm = "delaunay";
    remesh::GmshRemeshOptions gmsh;
    CommonOptions common;
  };
  auto o = std::make_shared<Options>();
  add_surface_input(*app, o->surface);
  app->add_option("-o,--output", o->output, "Output surface: .stl, .vtp (with point data metric, cell data tag and "
                                            "quality), .msh or .mesh (Medit)")
      ->required();
  add_sizing_options(*app, o->sizing, false);
  app->add_option("--metric", o->metric,
                  "Size field to adapt to instead of --size: a .vtp with point data metric or size, as 'vesselmesh size' "
                  "writes it");
  app->add_option("--hausdorff", o->remesh.hausdorff, "Largest distance of an output triangle from the input (mm; 0: none)")
      ->check(CLI::NonNegativeNumber);
  app->add_option("--hausdorff-relative", o->remesh.hausdorff_relative,
                  "Largest distance from the input over the local radius (the distance map's, else 1/max|k|; 0: none)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app->add_flag_function(
      "--keep-facets", [o](std::int64_t) { o->remesh.reconstruction = remesh::Reconstruction::facets; },
      "Put the points on the input's triangles and bound the distance to them (as mmgs), instead of the smooth surface "
      "they stand for: a coarse input's facets are then reproduced to within the bound, at a cost in triangles");
  app->add_option("--feature-angle", o->remesh.features.feature_angle_deg,
                  "Dihedral angle (degrees) above which an edge is a crease kept as a feature line")
      ->check(CLI::Range(0.0, 180.0))
      ->capture_default_str();
  app->add_option("--max-iterations", o->remesh.max_iterations, "Passes of split, collapse, flip and move")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  app->add_option("--engine", o->engine,
                  "native (local operations in the metric) or gmsh (Gmsh's reparametrization: patches meshed in their "
                  "plane; see --gmsh-algorithm; it does not enforce the distance bound)")
      ->check(CLI::IsMember({"native", "gmsh"}))
      ->capture_default_str();
  app->add_option("--gmsh-algorithm", o->gmsh_algorithm,
                  "Gmsh's 2D algorithm for --engine gmsh (bamg: anisotropic, the whole metric; the others meet its "
                  "smallest size)")
      ->check(CLI::IsMember({"delaunay", "frontal", "meshadapt", "bamg"}))
      ->capture_default_str();
  app->add_option("--classify-angle", o->gmsh.classify_angle_deg,
                  "--engine gmsh: patches are split where the normals turn more than this (degrees)")
      ->check(CLI::Range(1.0, 179.0))
      ->capture_default_str();
  add_common_options(*app, o->common);
  return {app, [o, app] {
            io::check_surface_output(o->output);
            const bool gmsh = o->engine == "gmsh";
            if (!gmsh && app->count("--gmsh-algorithm") + app->count("--classify-angle") > 0)
              throw OptionError("--gmsh-algorithm and --classify-angle go with --engine gmsh");
            if (o->metric.empty() == o->sizing.kind.empty())
              throw OptionError("give the size field either by --size KIND (with sizing options) or by --metric FIELD.vtp");
            TerminalReporter reporter(o->common.quiet);
            const CheckedSurface surface = read_surface_input(o->surface, reporter);
            const TriMesh& input = surface.file.mesh;
            const auto start = std::chrono::steady_clock::now();

            std::vector<Sym3> metric;
            std::vector<double> field_radius;
            std::optional<SizedSurface> sized;
            if (o->metric.empty()) {
              sized = size_surface(surface, o->sizing, reporter);
              metric = sized->field.metric;
            } else {
              metric = read_metric(o->metric, input, field_radius);
            }
            // The local radius for the relative distance bound: the distance map's, when the
            // surface has ends to trace centerlines between (the uniform field does not trace
            // them for itself; the other kinds have tried already); else its inner poles'.
            std::optional<centerline::DistanceMap> distance;
            if (sized && sized->distance) {
              distance = sized->distance;
            } else if (!field_radius.empty()) {
              distance = centerline::DistanceMap{.distance = {}, .radius = std::move(field_radius)};
            } else if (o->remesh.hausdorff_relative > 0.0) {
              std::string why = "as said above";
              if (!sized || sized->field.kind == sizing::SizeKind::uniform) {
                try {
                  distance = centerline::distance_map(input, centerline::extract(input, {}, reporter));
                } catch (const InputError& e) {
                  why = e.what();
                }
              }
              if (!distance) {
                try {
                  distance = centerline::DistanceMap{.distance = {}, .radius = centerline::pole_radius(input, reporter)};
                  reporter.warning(fmt::format("no centerlines ({}); the local radius of the distance bound comes from "
                                               "the inscribed balls at the surface (Voronoi poles)", why));
                } catch (const InputError& e) {
                  reporter.warning(fmt::format("no centerlines ({}) nor inscribed balls ({}); the local radius comes "
                                               "from the curvature", why, e.what()));
                }
              }
            }
            remesh::RemeshOptions options = o->remesh;
            if (distance) options.input_radius = &distance->radius;
            const double target = o->sizing.options.target_triangles;
            int patches = 0;
            remesh::GmshRemeshOptions gmsh_options = o->gmsh;
            gmsh_options.algorithm = remesh::parse_gmsh_algorithm(o->gmsh_algorithm);
            gmsh_options.remesh = options;
            // Gmsh's engine runs its count loop itself (one classification for all the runs).
            gmsh_options.target_triangles = std::max(0.0, target);
            const remesh::RemeshResult result = [&] {
              if (!gmsh) return target > 0.0 ? remesh::adapt_to_count(input, metric, target, options, reporter)
                                             : remesh::adapt(input, metric, options, reporter);
              remesh::GmshRemeshResult r = remesh::reparametrize(input, metric, gmsh_options, reporter);
              patches = r.patches;
              return std::move(r.result);
            }();
            const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
            const remesh::RemeshStats& s = result.stats;
            // Gmsh meets the field but not the distance bound (nothing checks its triangles
            // against the input): say so when its mesh strays beyond.
            const bool beyond_relative = options.hausdorff_relative > 0.0 && s.hausdorff_relative > options.hausdorff_relative;
            const bool beyond_absolute = options.hausdorff > 0.0 && s.hausdorff > options.hausdorff;
            if (gmsh && (beyond_relative || beyond_absolute))
              reporter.warning(fmt::format(
                  "Gmsh's mesh strays up to {:.4g} mm from the input{}, beyond the distance bound ({}): its engine does "
                  "not enforce it; the native engine does",
                  s.hausdorff,
                  s.hausdorff_relative >= 0.0 ? fmt::format(" ({:.3g} % of the local radius)", 100.0 * s.hausdorff_relative)
                                              : std::string(),
                  beyond_relative ? fmt::format("{:.3g} % of the radius", 100.0 * options.hausdorff_relative)
                                  : fmt::format("{:.4g} mm", options.hausdorff)));

            write_remeshed(o->output, result);

            if (o->common.json) {
              Json json = remesh_json(s);
              json["input"] = o->surface.path;
              json["output"] = o->output;
              json["units"] = "mm";
              json["size"] = sized ? Json(sizing::size_kind_name(sized->field.kind)) : Json("metric file");
              if (sized && sized->flow_metric) json["flow_times_s"] = sized->flow_times;
              if (target > 0.0) {
                json["target_triangles"] = std::lround(target);
                json["count_note"] = result.count_note.empty() ? Json(nullptr) : Json(result.count_note);
                json["least_count"] = result.least_count > 0 ? Json(result.least_count) : Json(nullptr);
              }
              json["engine"] = o->engine;
              json["distance_to"] = gmsh || options.reconstruction == remesh::Reconstruction::facets ? "input triangles"
                                                                                                    : "smooth surface";
              if (gmsh) {
                json["gmsh_algorithm"] = o->gmsh_algorithm;
                json["patches"] = patches;
              }
              json["seconds"] = round_to(seconds, 4);
              print_json(json);
            } else {
              reporter.info(fmt::format(
                  "{} points, {} triangles; edges of unit metric length {:.1f} %, smallest angle {:.1f} deg, quality mean "
                  "{:.3f} worst {:.3f}; Hausdorff distance {:.4g} mm{}; {:.1f} s; wrote {}",
                  s.points, s.triangles, 100.0 * s.edges_in_unit_range, s.min_angle_deg, s.mean_quality, s.min_quality,
                  s.hausdorff,
                  s.hausdorff_relative >= 0.0 ? fmt::format(" ({:.2f} % of the local radius)", 100.0 * s.hausdorff_relative)
                                              : std::string(),
                  seconds, o->output));
            }
            return 0;
          }};
}

}  // namespace vesselmesh::cli
