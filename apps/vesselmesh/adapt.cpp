// vesselmesh adapt: flow-adapted meshes by cycles (study/adaptation.h, issue 52).
#include "commands.h"

#include "flow/case.h"
#include "mesh/error.h"
#include "study/adaptation.h"
#include "volume/volume_mesh.h"

#include <fmt/format.h>

#include <cmath>

namespace vesselmesh::cli {

Command add_adapt_command(CLI::App& parent) {
  CLI::App* app = parent.add_subcommand(
      "adapt",
      "Flow-adapted meshes by cycles: a first mesh of --start's kind (surface at --target-triangles, boundary "
      "layer, interior) and CASE's flow on it (its mesh replaced), then --cycles times: the surface remeshed to "
      "the last flow's WSS error (as 'remesh --size flow'), the interior sized by its velocity's error (as "
      "'volume --flow') at the first mesh's point count (or --target-points), and the flow again. Each cycle "
      "says its counts and how far its wall's WSS moved from the cycle before's (the L2 norm and the 95th "
      "percentile of the difference over the wall, over its mean |WSS|). Writes DIR/cycle_K/{surface.vtp, "
      "volume.msh, flow/} and DIR/summary.json. One process (a cluster runs the stages one by one: size/remesh "
      "--size flow, volume --flow, mpirun ... simulate)");
  struct Options {
    SurfaceInput surface;
    std::string flow_case, output, start = "curvature", algorithm = "delaunay";
    std::vector<std::string> ends;
    study::AdaptOptions adapt;
    CommonOptions common;
  };
  auto o = std::make_shared<Options>();
  add_surface_input(*app, o->surface);
  app->add_option("CASE", o->flow_case, "Flow case (.toml, as for 'vesselmesh simulate'; its mesh is replaced)")
      ->required()
      ->check(CLI::ExistingFile);
  app->add_option("-o,--output", o->output, "Output folder (created if absent)")->required();
  app->add_option("--target-triangles", o->adapt.target_triangles, "Every cycle's surface triangles")->required();
  app->add_option("--cycles", o->adapt.cycles, "Flow-adapted cycles after the first mesh")->capture_default_str();
  app->add_option("--start", o->start, "The first mesh's kind: uniform, distance, curvature or anisotropic")
      ->check(CLI::IsMember({"uniform", "distance", "curvature", "anisotropic"}))
      ->capture_default_str();
  app->add_option("--target-points", o->adapt.target_points,
                  "Every cycle's volume points (default: the first mesh's, as its volume comes out)");
  app->add_option("--layers", o->adapt.volume.layer.layers, "Boundary-layer layers (0: none)")->capture_default_str();
  app->add_option("--thickness-ratio", o->adapt.volume.layer.thickness_ratio, "Layer thickness over the local radius")
      ->capture_default_str();
  app->add_option("--algorithm", o->algorithm, "Interior tetrahedra: delaunay, hxt, tetgen or frontal (as 'volume')")
      ->check(CLI::IsMember({"delaunay", "frontal", "hxt", "tetgen"}))
      ->capture_default_str();
  app->add_option("--end", o->ends, "NAME:x,y,z names the end nearest the point (as 'volume'; repeat for each end)");
  app->add_option("--error-norm", o->adapt.error.p,
                  "p of the L^p norm of the WSS's and the velocity's interpolation error the sizes make least")
      ->check(CLI::Range(1.0, 1e6))
      ->capture_default_str();
  app->add_option("--layer-y-plus", o->adapt.y_plus,
                  "The later cycles' first layer no higher than this y+ in the last flow's largest wall shear (as "
                  "'volume --flow'); 0: the layer as --thickness-ratio makes it")
      ->capture_default_str();
  add_common_options(*app, o->common);
  return {app, [o] {
            TerminalReporter reporter(o->common.quiet);
            study::AdaptOptions options = o->adapt;
            options.start = sizing::parse_size_kind(o->start);
            options.volume.algorithm = volume::parse_fill_algorithm(o->algorithm);
            for (const std::string& text : o->ends) {
              auto [name, point] = parse_named_point(text, "--end");
              options.volume.end_at.push_back({name, point});
            }
            study::check_adapt_options(options);
            const flow::FlowCase flow_case = flow::read_case(o->flow_case);
            const CheckedSurface surface = read_surface_input(o->surface, reporter);
            if (surface.ends.empty())
              throw InputError(fmt::format("{}: the surface has no open or flat-capped end: a flow domain needs an "
                                           "inlet and an outlet; cut the vessel's ends open",
                                           o->surface.path));
            const std::vector<study::AdaptCycle> cycles =
                study::adapt_to_flow(surface.file.mesh, flow_case, o->output, options, reporter);
            if (o->common.json) {
              Json out = Json::array();
              for (const study::AdaptCycle& c : cycles)
                out.push_back({{"cycle", c.cycle},
                               {"triangles", c.triangles},
                               {"volume_points", c.volume_points},
                               {"wss_change_l2", std::isfinite(c.change_l2) ? Json(round_to(c.change_l2, 6)) : Json()},
                               {"wss_change_p95", std::isfinite(c.change_p95) ? Json(round_to(c.change_p95, 6)) : Json()},
                               {"folder", c.folder}});
              print_json(Json{{"output", o->output}, {"summary", o->output + "/summary.json"}, {"cycles", out}});
            } else {
              reporter.info(fmt::format("adapt done: {} cycles in {} (summary.json)", cycles.size() - 1, o->output));
            }
            return 0;
          }};
}

}  // namespace vesselmesh::cli
