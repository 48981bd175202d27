// vesselmesh extend: flow extensions on the chosen open ends of a surface (remesh/extend.h).
#include "commands.h"

#include "io/surface.h"
#include "mesh/error.h"
#include "remesh/extend.h"

#include <fmt/format.h>

#include <algorithm>

namespace vesselmesh::cli {

Command add_extend_command(CLI::App& parent) {
  CLI::App* app = parent.add_subcommand(
      "extend",
      "Flow extensions: adds to each chosen open end a tube of --length times the end's equivalent radius along the "
      "end's outward normal (as VMTK's vmtkflowextensions), its rings about the wall's triangle size there apart, "
      "each of as many points as the end's loop evenly spaced (every other shifted by half: near-equilateral "
      "triangles), the "
      "end's shape turning into a circle of the end's equivalent radius over min(length / 2, 2) radii, and, in smooth "
      "mode, the tube leaving the wall in the wall's own direction (no crease); the new end is planar and normal to "
      "the axis. Labels follow the wall triangles the tube grows from. Prints each moved end's new centre (name ends "
      "by it: 'volume --end NAME:x,y,z'). Remesh the result before 'volume', as the study does (the tube keeps the "
      "loop's own spacing next to it)");
  struct Options {
    SurfaceInput surface;
    std::string output, ends = "all", mode = "smooth";
    double length = 5.0;
    int inlet = 0;
    CommonOptions common;
  };
  auto o = std::make_shared<Options>();
  add_surface_input(*app, o->surface);
  app->add_option("-o,--output", o->output, "The extended surface (.vtp, .stl, .msh, .mesh)")->required();
  app->add_option("--length", o->length, "Each tube's length in radii of its end (VaMPy's default: 5)")
      ->capture_default_str();
  app->add_option("--ends", o->ends,
                  "The ends to extend: all, or a comma-separated list of indices (as 'vesselmesh info' lists them) "
                  "or names (inlet, outlet_1, ... as 'vesselmesh volume' names them)")
      ->capture_default_str();
  app->add_option("--mode", o->mode, "smooth (the tube leaves the wall along it) or straight (along the end's normal)")
      ->capture_default_str();
  app->add_option("--inlet", o->inlet, "Index of the end named inlet (for --ends names; default 0, the largest)")
      ->capture_default_str();
  add_common_options(*app, o->common);
  return {app, [o] {
            remesh::ExtensionOptions options;
            options.length = o->length;
            if (!(o->length > 0.0)) throw OptionError(fmt::format("--length {}: give a positive number of radii", o->length));
            try {
              options.mode = remesh::parse_extension_mode(o->mode);
            } catch (const InputError& e) {
              throw OptionError(fmt::format("--mode: {}", e.what()));
            }
            io::check_surface_output(o->output);  // an extension that cannot be written: refused before the work
            TerminalReporter reporter(o->common.quiet);
            const CheckedSurface surface = read_surface_input(o->surface, reporter);
            const int count = static_cast<int>(surface.ends.size());
            if (count == 0) throw InputError(fmt::format("{}: the surface has no ends to extend", o->surface.path));
            if (o->inlet < 0 || o->inlet >= count)
              throw OptionError(fmt::format("--inlet {}: the surface has {} ends (0 to {})", o->inlet, count, count - 1));
            const std::vector<std::string> names = analysis::default_end_names(count, o->inlet);
            if (o->ends != "all") {
              for (const std::string& item : split(o->ends, ',')) {
                const auto named = std::find(names.begin(), names.end(), item);
                int e = -1;
                if (named != names.end()) {
                  e = static_cast<int>(named - names.begin());
                } else {
                  try {
                    size_t used = 0;
                    e = std::stoi(item, &used);
                    if (used != item.size()) e = -1;
                  } catch (const std::exception&) {
                    e = -1;
                  }
                }
                if (e < 0 || e >= count)
                  throw OptionError(fmt::format("--ends: \"{}\" is neither an end's index (0 to {}) nor its name ({})",
                                                item, count - 1, fmt::join(names, ", ")));
                options.ends.push_back(e);
              }
            }
            const std::string task = "adding flow extensions";
            reporter.progress(task, 0.0);
            const remesh::ExtensionResult result = remesh::extend_ends(surface.file.mesh, surface.ends, options);
            reporter.progress(task, 1.0);
            io::write_surface(o->output, result.mesh);
            Json moved = Json::array();
            for (const remesh::ExtendedEnd& x : result.extended) {
              reporter.info(fmt::format("end {} ({}): radius {:.4g} mm, extended {:.4g} mm ({} rings); its centre "
                                        "({:.4g}, {:.4g}, {:.4g}) -> ({:.4g}, {:.4g}, {:.4g})",
                                        x.end, names[x.end], x.radius, x.length, x.rings, x.old_center.x(),
                                        x.old_center.y(), x.old_center.z(), x.center.x(), x.center.y(), x.center.z()));
              moved.push_back({{"end", x.end},
                               {"name", names[x.end]},
                               {"radius_mm", round_to(x.radius)},
                               {"length_mm", round_to(x.length)},
                               {"rings", x.rings},
                               {"old_center", to_json(x.old_center)},
                               {"center", to_json(x.center)},
                               {"normal", to_json(x.normal)}});
            }
            reporter.info(fmt::format("{}: {} points, {} triangles (mm)", o->output, result.mesh.num_points(),
                                      result.mesh.num_triangles()));
            if (o->common.json)
              print_json({{"output", o->output},
                          {"units", "mm"},
                          {"points", result.mesh.num_points()},
                          {"triangles", result.mesh.num_triangles()},
                          {"extended", moved}});
            return 0;
          }};
}

}  // namespace vesselmesh::cli
