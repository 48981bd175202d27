// vesselmesh synth: analytic and synthetic vessel shapes, the fixtures of the tests.
#include "commands.h"

#include "mesh/error.h"
#include "mesh/statistics.h"
#include "synth/anastomosis.h"
#include "synth/bifurcation.h"
#include "synth/shapes.h"

#include <fmt/format.h>

#include <iostream>
#include <map>
#include <memory>

namespace vesselmesh::cli {
namespace {

struct ShapeCommon {
  std::string output;
  double resolution = 0.0;
  double jitter = 0.0;
  uint64_t seed = 1;
  CommonOptions common;
};

// Options every shape has; `resolution` starts at the shape's default.
void add_shape_options(CLI::App& app, ShapeCommon& c, double default_resolution) {
  c.resolution = default_resolution;
  app.add_option("-o,--output", c.output, "Output surface (.stl, .vtp or .msh), lengths in mm")->required();
  app.add_option("--resolution", c.resolution, "Target edge length (mm)")->capture_default_str();
  app.add_option("--jitter", c.jitter,
                 "Move every point along the surface by a random fraction (up to this) of its edge length, "
                 "for an irregular triangulation (0 to 0.45)")
      ->capture_default_str();
  app.add_option("--seed", c.seed, "Seed of the random diagonals and jitter")->capture_default_str();
  add_common_options(app, c.common);
}

// Writes the shape and says what it wrote; `extra` (JSON keys) and `notes` (lines) add what a
// shape has to say of itself.
int write_shape(const ShapeCommon& c, const std::string& shape, const TriMesh& mesh, const Json& extra = Json::object(),
                const std::vector<std::string>& notes = {}) {
  io::surface_format(c.output);
  io::write_surface(c.output, mesh);
  TerminalReporter reporter(c.common.quiet);
  const mesh::Statistics st = mesh::statistics(mesh);
  if (c.common.json) {
    Json json = {{"shape", shape}, {"output", c.output}, {"units", "mm"}, {"points", st.points},
                 {"triangles", st.triangles}, {"closed", st.closed}, {"boundary_loops", st.boundary_loops},
                 {"area", round_to(st.area)}, {"edge_length", {{"min", round_to(st.edge_length.min)},
                                                               {"mean", round_to(st.edge_length.mean)},
                                                               {"max", round_to(st.edge_length.max)}}},
                 {"min_angle_deg", round_to(st.min_angle.min)}};
    for (const auto& [key, value] : extra.items()) json[key] = value;
    print_json(json);
  } else {
    reporter.info(fmt::format("wrote {} ({} points, {} triangles, mean edge {:.3g} mm) to {}", shape, st.points,
                              st.triangles, st.edge_length.mean, c.output));
    for (const std::string& line : notes) reporter.info(line);
  }
  return 0;
}

// The shape's generator, called with the options every shape shares filled in.
template <typename Options>
std::function<TriMesh(Options, const ShapeCommon&)> with_common_options(TriMesh (*make)(const Options&)) {
  return [make](Options o, const ShapeCommon& c) {
    o.resolution = c.resolution;
    o.jitter = c.jitter;
    o.seed = c.seed;
    return make(o);
  };
}

template <typename Options, typename Make>
Command shape_command(CLI::App& parent, const std::string& name, const std::string& help, double resolution,
                      std::function<void(CLI::App&, Options&)> add_options, Make make) {
  CLI::App* app = parent.add_subcommand(name, help);
  struct State {
    Options shape;
    ShapeCommon common;
  };
  auto state = std::make_shared<State>();
  add_options(*app, state->shape);
  add_shape_options(*app, state->common, resolution);
  return {app, [state, name, make] {
            const ShapeCommon& c = state->common;
            return write_shape(c, name, make(state->shape, c));
          }};
}

Json point_json(const Vec3& p) { return {round_to(p.x()), round_to(p.y()), round_to(p.z())}; }

// The anastomosis also says where its ends, heel, toe, floor and rings are: the case and the
// study name them.
Command add_anastomosis(CLI::App& parent) {
  CLI::App* app = parent.add_subcommand(
      "anastomosis",
      "Distal end-to-side anastomosis (femoro-popliteal bypass): the graft joins the host artery's side at --angle; "
      "the host upstream is a blind stump. Host along +x (distal), graft above it in the xz plane. Ends: inlet (graft), "
      "outlet (distal host), stump (proximal host); prints them with the heel, toe, floor and the two rings' planes");
  struct State {
    synth::AnastomosisOptions shape;
    ShapeCommon common;
  };
  auto state = std::make_shared<State>();
  synth::AnastomosisOptions& o = state->shape;
  app->add_option("--host-radius", o.host_radius, "Host artery radius (mm)")->capture_default_str();
  app->add_option("--graft-radius", o.graft_radius, "Graft radius (mm)")->capture_default_str();
  app->add_option("--angle", o.angle_deg, "Angle between the graft's axis at the junction and the distal host (deg)")
      ->capture_default_str();
  app->add_option("--graft-bend", o.graft_bend_deg,
                  "Turn of the graft above the junction, towards the host's direction (deg; 0: straight graft)")
      ->capture_default_str();
  app->add_option("--graft-bend-radius", o.graft_bend_radius, "Radius of that turn's centerline (mm; 0: 4 graft radii)")
      ->capture_default_str();
  app->add_option("--graft-length", o.graft_length, "Straight graft from the turn to the inlet (mm)")->capture_default_str();
  app->add_option("--fillet", o.fillet, "Width of the smooth blend at heel, toe and sides (mm; 0: a crease)")
      ->capture_default_str();
  app->add_option("--stump-length", o.stump_length, "Host from the heel back to the stump's end (mm)")->capture_default_str();
  app->add_option("--outlet-length", o.outlet_length, "Host from the toe to the outlet (mm)")->capture_default_str();
  app->add_option("--tortuosity", o.tortuosity,
                  "Amplitude of an S-bend of the distal host out of the graft's plane (mm; 0: straight)")
      ->capture_default_str();
  add_shape_options(*app, state->common, o.resolution);
  return {app, [state] {
            synth::AnastomosisOptions options = state->shape;
            const ShapeCommon& c = state->common;
            options.resolution = c.resolution, options.jitter = c.jitter, options.seed = c.seed;
            io::surface_format(c.output);  // a bad name fails before the work
            const synth::AnastomosisLandmarks l = synth::anastomosis_landmarks(options);
            TerminalReporter reporter(c.common.quiet);
            reporter.info("building the anastomosis: implicit surface, flying edges, relaxation, three cuts");
            const TriMesh mesh = synth::anastomosis(options);
            Json ends = Json::array();
            std::vector<std::string> notes;
            auto xyz = [](const Vec3& p) { return fmt::format("{:.4g},{:.4g},{:.4g}", p.x(), p.y(), p.z()); };
            for (const synth::NamedEnd& e : l.ends) {
              ends.push_back({{"name", e.name}, {"center", point_json(e.end.center)},
                              {"normal", point_json(e.end.normal)}, {"radius", round_to(e.end.radius)}});
              notes.push_back(fmt::format("  end {:7} centre {}  normal {}  radius {:.4g} mm", e.name,
                                          xyz(e.end.center), xyz(e.end.normal), e.end.radius));
            }
            notes.push_back(fmt::format("  heel {}  toe {}  floor {} (mm)", xyz(l.heel), xyz(l.toe), xyz(l.floor)));
            notes.push_back(fmt::format("  ring 1 (heel-toe) point {} normal {}", xyz(l.ring1_point), xyz(l.ring1_normal)));
            notes.push_back(
                fmt::format("  ring 2 (distal host) point {} normal {}", xyz(l.ring2_point), xyz(l.ring2_normal)));
            const Json extra = {{"ends", ends},
                                {"heel", point_json(l.heel)},
                                {"toe", point_json(l.toe)},
                                {"floor", point_json(l.floor)},
                                {"ring1", {{"point", point_json(l.ring1_point)}, {"normal", point_json(l.ring1_normal)}}},
                                {"ring2", {{"point", point_json(l.ring2_point)}, {"normal", point_json(l.ring2_normal)}}}};
            return write_shape(c, "anastomosis", mesh, extra, notes);
          }};
}

}  // namespace

Command add_synth_command(CLI::App& parent) {
  CLI::App* app = parent.add_subcommand("synth", "Write an analytic or synthetic vessel shape (mm)");
  app->require_subcommand(1);
  std::vector<Command> shapes;

  shapes.push_back(shape_command<synth::SphereOptions>(
      *app, "sphere", "Geodesic sphere", synth::SphereOptions{}.resolution,
      [](CLI::App& a, synth::SphereOptions& o) { a.add_option("--radius", o.radius, "Radius (mm)")->capture_default_str(); },
      with_common_options(&synth::sphere)));
  shapes.push_back(shape_command<synth::CylinderOptions>(
      *app, "cylinder", "Straight pipe along +z, open ends (or flat caps with --capped)",
      synth::CylinderOptions{}.resolution,
      [](CLI::App& a, synth::CylinderOptions& o) {
        a.add_option("--radius", o.radius, "Radius (mm)")->capture_default_str();
        a.add_option("--length", o.length, "Length (mm)")->capture_default_str();
        a.add_flag("--capped", o.capped, "Close the ends with flat caps (labels: 1 wall, 2 and 3 caps)");
        a.add_flag("!--regular-diagonals", o.random_diagonals, "Alternate the grid's diagonals instead of random ones");
      },
      with_common_options(&synth::cylinder)));
  shapes.push_back(shape_command<synth::TorusOptions>(
      *app, "torus", "Torus about the z axis", synth::TorusOptions{}.resolution,
      [](CLI::App& a, synth::TorusOptions& o) {
        a.add_option("--major-radius", o.major_radius, "Distance from the axis to the tube's centre (mm)")->capture_default_str();
        a.add_option("--minor-radius", o.minor_radius, "Tube radius (mm)")->capture_default_str();
        a.add_flag("!--regular-diagonals", o.random_diagonals, "Alternate the grid's diagonals instead of random ones");
      },
      with_common_options(&synth::torus)));
  shapes.push_back(shape_command<synth::EllipsoidOptions>(
      *app, "ellipsoid", "Ellipsoid x2/a2 + y2/b2 + z2/c2 = 1", synth::EllipsoidOptions{}.resolution,
      [](CLI::App& a, synth::EllipsoidOptions& o) {
        a.add_option_function<std::vector<double>>(
             "--semi-axes", [&o](const std::vector<double>& v) { o.semi_axes = Vec3(v[0], v[1], v[2]); },
             "Semi-axes a,b,c (mm), default 6,4,3")
            ->expected(3)
            ->delimiter(',');
      },
      with_common_options(&synth::ellipsoid)));
  shapes.push_back(shape_command<synth::BendOptions>(
      *app, "bend", "Bent pipe in the xy plane: straight inlet along +y, an arc, a straight outlet",
      synth::BendOptions{}.resolution,
      [](CLI::App& a, synth::BendOptions& o) {
        a.add_option("--radius", o.radius, "Pipe radius (mm)")->capture_default_str();
        a.add_option("--bend-radius", o.bend_radius, "Radius of the arc of the centerline (mm)")->capture_default_str();
        a.add_option("--angle", o.angle_deg, "Turning angle (deg)")->capture_default_str();
        a.add_option("--inlet-length", o.inlet_length, "Straight length before the bend (mm)")->capture_default_str();
        a.add_option("--outlet-length", o.outlet_length, "Straight length after the bend (mm)")->capture_default_str();
        a.add_flag("!--regular-diagonals", o.random_diagonals, "Alternate the grid's diagonals instead of random ones");
      },
      with_common_options(&synth::bend)));
  shapes.push_back(shape_command<synth::BifurcationOptions>(
      *app, "bifurcation", "Y bifurcation: a parent pipe along +z splitting into two daughters in the xz plane",
      synth::BifurcationOptions{}.resolution,
      [](CLI::App& a, synth::BifurcationOptions& o) {
        a.add_option("--radius", o.radius, "Parent radius (mm)")->capture_default_str();
        a.add_option_function<std::vector<double>>(
             "--daughter-radii", [&o](const std::vector<double>& v) { o.daughter_radius = {v[0], v[1]}; },
             "Daughter radii r1,r2 (mm), default 2.4,2.4")
            ->expected(2)
            ->delimiter(',');
        a.add_option_function<std::vector<double>>(
             "--angles", [&o](const std::vector<double>& v) { o.angle_deg = {v[0], v[1]}; },
             "Angles of the daughters from the parent's axis a1,a2 (deg), default 35,35")
            ->expected(2)
            ->delimiter(',');
        a.add_option("--parent-length", o.parent_length, "Parent length (mm)")->capture_default_str();
        a.add_option("--daughter-length", o.daughter_length, "Daughter length (mm)")->capture_default_str();
        a.add_option("--blend", o.blend, "Radius of the smooth blend at the junction (mm)")->capture_default_str();
        a.add_option("--aneurysm-radius", o.aneurysm_radius,
                     "A saccular aneurysm at the apex: a sphere of this radius (mm) on the daughters' bisector, its "
                     "centre 0.7 radii beyond where the daughters' walls part, blended in (0: none)")
            ->capture_default_str();
      },
      with_common_options(&synth::bifurcation)));
  shapes.push_back(add_anastomosis(*app));
  shapes.push_back(shape_command<synth::NozzleOptions>(
      *app, "nozzle",
      "The FDA benchmark nozzle (Hariharan et al. 2011) about the z axis, in the coordinates of the FDA's data (the "
      "step at z = 0, flow along +z): pipe, 20-degree cone, throat, sudden expansion, pipe (or mirrored, "
      "--orientation conical-diffuser). Open ends: the inlet at the lowest z",
      synth::NozzleOptions{}.resolution,
      [](CLI::App& a, synth::NozzleOptions& o) {
        a.add_option("--radius", o.radius, "Radius of the inlet and outlet pipes (mm)")->capture_default_str();
        a.add_option("--throat-radius", o.throat_radius, "Radius of the throat (mm)")->capture_default_str();
        a.add_option("--throat-length", o.throat_length, "Length of the throat (mm)")->capture_default_str();
        a.add_option("--cone-half-angle", o.cone_half_angle_deg, "Half the cone's opening angle (deg)")
            ->capture_default_str();
        a.add_option("--inlet-length", o.inlet_length, "Straight pipe before the nozzle (mm)")->capture_default_str();
        a.add_option("--outlet-length", o.outlet_length, "Straight pipe after the nozzle (mm)")->capture_default_str();
        a.add_option("--orientation", o.orientation,
                     "sudden-expansion (cone, throat, step) or conical-diffuser (step, throat, cone) along the flow")
            ->transform(CLI::CheckedTransformer(
                std::map<std::string, synth::NozzleOrientation>{
                    {"sudden-expansion", synth::NozzleOrientation::sudden_expansion},
                    {"conical-diffuser", synth::NozzleOrientation::conical_diffuser}},
                CLI::ignore_case))
            ->default_str("sudden-expansion");
      },
      with_common_options(&synth::nozzle)));
  return {app, [shapes] {
            for (const Command& shape : shapes)
              if (shape.app->parsed()) return shape.action();
            throw OptionError("name a shape: sphere, cylinder, torus, ellipsoid, bend, bifurcation, anastomosis or nozzle");
          }};
}

}  // namespace vesselmesh::cli
