// vesselmesh info: read a surface, run the mesh doctor, and describe what is there.
#include "commands.h"

#include "io/units.h"
#include "mesh/error.h"

#include <fmt/format.h>

#include <iostream>

namespace vesselmesh::cli {

CheckedSurface check_surface(const std::string& path, const SurfaceCheckOptions& options,
                             const Reporter& reporter) {
  io::ReadOptions read{.units = std::nullopt, .label_array = options.label_array};
  if (options.units) read.units = io::parse_unit(*options.units);
  CheckedSurface out;
  reporter.progress("reading " + path, 0.0);
  out.file = io::read_surface(path, read, reporter);
  reporter.progress("reading " + path, 1.0);
  try {
    out.repairs = mesh::clean(out.file.mesh, options.clean, reporter);
  } catch (const InputError& e) {
    throw InputError(fmt::format("{}: {}", path, e.what()));
  }
  out.statistics = mesh::statistics(out.file.mesh);
  out.ends = analysis::open_ends(out.file.mesh, options.ends);
  return out;
}

namespace {

Json range_json(const mesh::Range& r) {
  return {{"min", round_to(r.min)}, {"mean", round_to(r.mean)}, {"median", round_to(r.median)}, {"max", round_to(r.max)}};
}

Json ends_json(const std::vector<analysis::OpenEnd>& ends) {
  Json list = Json::array();
  for (size_t i = 0; i < ends.size(); ++i) {
    const analysis::OpenEnd& e = ends[i];
    Json end = {{"id", i},
                {"center", to_json(e.center)},
                {"normal", to_json(e.normal)},
                {"area", round_to(e.area)},
                {"radius", round_to(e.radius)},
                {"perimeter", round_to(e.perimeter)},
                {"capped", e.capped},
                {"loop_points", e.loop.size()}};
    if (e.capped) end["cap_triangles"] = e.cap_triangles.size();
    if (e.label >= 0) end["label"] = e.label;
    list.push_back(end);
  }
  return list;
}

}  // namespace

void add_surface_input(CLI::App& app, SurfaceInput& input) {
  app.add_option("SURFACE", input.path, "Surface file: .stl, .vtp, .vtu, .ply, .obj, .msh, .mesh")->required();
  app.add_option("--units", input.units, "Length unit of the file: um, mm, cm or m (default mm); results are in mm");
  app.add_option("--label-array", input.label_array,
                 "Integer cell array holding face labels (default: ModelFaceID, tag, CellEntityIds, gmsh:physical)");
}

CheckedSurface read_surface_input(const SurfaceInput& input, const Reporter& reporter) {
  SurfaceCheckOptions check;
  if (!input.units.empty()) check.units = input.units;
  check.label_array = input.label_array;
  check.clean.find_self_intersections = false;  // `info` reports them; no stage needs the search
  return check_surface(input.path, check, reporter);
}

Field metric_field(const std::vector<Sym3>& metric) {
  Field field{.name = "metric", .components = 6, .values = {}};
  field.values.reserve(6 * metric.size());
  for (const Sym3& m : metric) field.values.insert(field.values.end(), m.v.begin(), m.v.end());
  return field;
}

Json describe(const CheckedSurface& s) {
  const mesh::Statistics& st = s.statistics;
  Json json;
  json["file"] = s.file.path;
  json["format"] = s.file.format;
  json["units"] = "mm";
  json["input_units"] = io::unit_name(s.file.unit);
  json["input_units_assumed"] = !s.file.unit_given;
  json["scale_to_mm"] = s.file.scale_to_mm;
  json["input_points"] = s.repairs.input_points;
  json["input_triangles"] = s.repairs.input_triangles;
  json["points"] = st.points;
  json["triangles"] = st.triangles;
  json["components"] = std::max(s.repairs.input_components, st.components);
  json["closed"] = st.closed;
  json["area"] = round_to(st.area);
  json["volume"] = round_to(st.volume);
  json["euler_characteristic"] = st.euler_characteristic;
  json["genus"] = st.genus;
  json["bounding_box"] = {{"min", to_json(st.box_min)}, {"max", to_json(st.box_max)},
                          {"size", to_json(st.box_max - st.box_min)}};
  json["edge_length"] = range_json(st.edge_length);
  json["min_angle_deg"] = range_json(st.min_angle);
  json["max_angle_deg"] = round_to(st.max_angle);
  json["triangles_below_5deg"] = st.sliver_triangles;
  json["open_ends"] = ends_json(s.ends);
  json["defects"] = s.repairs.defects;
  json["repairs"] = s.repairs.repairs;
  json["notes"] = s.repairs.notes;
  if (s.file.mesh.has_labels()) json["label_array"] = s.file.label_array;
  return json;
}

std::string describe_as_text(const CheckedSurface& s) {
  const mesh::Statistics& st = s.statistics;
  std::string out;
  auto line = [&](std::string_view key, const std::string& value) { out += fmt::format("{:<13}{}\n", key, value); };
  line("file", fmt::format("{} ({}, {} {}; lengths below in mm)", s.file.path, s.file.format,
                           io::unit_name(s.file.unit), s.file.unit_given ? "stated" : "assumed"));
  line("size", fmt::format("{} points, {} triangles, {} component(s)", st.points, st.triangles,
                           std::max(s.repairs.input_components, st.components)));
  int capped = 0;
  for (const auto& e : s.ends) capped += e.capped;
  line("topology", fmt::format("{}, {} open end(s), {} capped end(s), genus {}",
                               st.closed ? "closed" : "open", static_cast<int>(s.ends.size()) - capped, capped, st.genus));
  line("area", fmt::format("{:.6g} mm2, enclosed volume {:.6g} mm3{}", st.area, st.volume,
                           st.closed ? "" : " (open ends closed by fans)"));
  const Vec3 size = st.box_max - st.box_min;
  line("box", fmt::format("{:.4g} x {:.4g} x {:.4g} mm, from ({:.6g}, {:.6g}, {:.6g})", size.x(), size.y(), size.z(),
                          st.box_min.x(), st.box_min.y(), st.box_min.z()));
  line("edges", fmt::format("min {:.4g}, mean {:.4g}, median {:.4g}, max {:.4g} mm", st.edge_length.min,
                            st.edge_length.mean, st.edge_length.median, st.edge_length.max));
  line("angles", fmt::format("smallest {:.3g} deg, median smallest {:.3g} deg, largest {:.4g} deg; {} triangle(s) "
                             "with an angle below 5 deg",
                             st.min_angle.min, st.min_angle.median, st.max_angle, st.sliver_triangles));
  for (size_t i = 0; i < s.ends.size(); ++i) {
    const auto& e = s.ends[i];
    line(i == 0 ? "ends" : "",
         fmt::format("{} {:6} radius {:.4g} mm, area {:.5g} mm2, centre ({:.5g}, {:.5g}, {:.5g}), normal ({:.3f}, "
                     "{:.3f}, {:.3f}){}",
                     i, e.capped ? "capped" : "open", e.radius, e.area, e.center.x(), e.center.y(), e.center.z(),
                     e.normal.x(), e.normal.y(), e.normal.z(), e.label >= 0 ? fmt::format(", label {}", e.label) : ""));
  }
  std::string found, changed;
  for (const auto& [kind, count] : s.repairs.defects)
    if (count) found += fmt::format("{}{} {}", found.empty() ? "" : ", ", kind, count);
  for (const auto& [kind, count] : s.repairs.repairs)
    if (count) changed += fmt::format("{}{} {}", changed.empty() ? "" : ", ", kind, count);
  line("defects", found.empty() ? "none" : found);
  line("repairs", changed.empty() ? "none" : changed);
  return out;
}

void write_repaired(const std::string& path, const CheckedSurface& s) {
  auto carry = [](const std::vector<Field>& fields, const std::vector<int>& origin) {
    std::vector<Field> out;
    for (const Field& f : fields) {
      Field g{.name = f.name, .components = f.components, .values = {}, .integer = f.integer};
      g.values.reserve(origin.size() * f.components);
      for (int i : origin)
        for (int c = 0; c < f.components; ++c) g.values.push_back(f.values[static_cast<size_t>(i) * f.components + c]);
      out.push_back(std::move(g));
    }
    return out;
  };
  io::write_surface(path, s.file.mesh, carry(s.file.point_data, s.repairs.point_origin),
                    carry(s.file.cell_data, s.repairs.triangle_origin));
}

Command add_info_command(CLI::App& parent) {
  CLI::App* app = parent.add_subcommand(
      "info", "Read a surface, check and repair it (the mesh doctor), and describe it: size, topology, open "
              "and capped ends, edge and angle statistics, defects and repairs");
  struct Options {
    std::string input, output;
    SurfaceCheckOptions check;
    std::string units;
    bool keep_all_components = false;
    bool skip_self_intersections = false;
    CommonOptions common;
  };
  auto o = std::make_shared<Options>();
  app->add_option("SURFACE", o->input, "Surface file: .stl (binary or ASCII), .vtp, .vtu, .ply, .obj, .msh")->required();
  app->add_option("--units", o->units, "Length unit of the file: um, mm, cm or m (default mm); results are in mm");
  app->add_option("--label-array", o->check.label_array,
                  "Integer cell array holding face labels (default: ModelFaceID, tag, CellEntityIds, gmsh:physical)");
  app->add_option("-o,--output", o->output, "Write the repaired surface (.stl, .vtp or .msh), in mm");
  app->add_option("--merge-tolerance", o->check.clean.merge_tolerance,
                  "Merge points closer than this fraction of their mean edge length")
      ->capture_default_str();
  app->add_option("--crease-angle", o->check.ends.cap_crease_angle_deg,
                  "Dihedral angle (deg) above which an edge is a crease bounding a flat cap")
      ->capture_default_str();
  app->add_flag("--keep-all-components", o->keep_all_components, "Keep every connected component (default: keep the largest)");
  app->add_flag("--no-self-intersections", o->skip_self_intersections, "Skip the self-intersection test (faster on very large surfaces)");
  add_common_options(*app, o->common);
  return {app, [o] {
            o->check.clean.keep_largest_component = !o->keep_all_components;
            o->check.clean.find_self_intersections = !o->skip_self_intersections;
            if (!o->units.empty()) o->check.units = o->units;
            if (!o->output.empty()) io::check_surface_output(o->output);  // a bad extension fails before any work
            TerminalReporter reporter(o->common.quiet);
            const CheckedSurface surface = check_surface(o->input, o->check, reporter);
            if (!o->output.empty()) {
              write_repaired(o->output, surface);
              reporter.info(fmt::format("wrote the repaired surface to {}", o->output));
            }
            if (o->common.json) {
              Json json = describe(surface);
              if (!o->output.empty()) json["output"] = o->output;
              print_json(json);
            } else {
              std::cout << describe_as_text(surface);
            }
            return 0;
          }};
}

}  // namespace vesselmesh::cli
