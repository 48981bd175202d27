// vesselmesh export: a volume mesh in the formats of the solvers users run (io/export.h).
#include "commands.h"

#include "io/export.h"
#include "io/units.h"
#include "io/volume_file.h"
#include "mesh/error.h"

#include <fmt/format.h>


namespace vesselmesh::cli {

Command add_export_command(CLI::App& parent) {
  CLI::App* app = parent.add_subcommand(
      "export",
      "A volume mesh (.msh or .vtu, as 'vesselmesh volume' writes it) for another solver: svfsi (svMultiPhysics / "
      "SimVascular: OUT/mesh-complete/ with the volume, a .vtp per boundary tag, walls_combined.vtp and the exterior, "
      "GlobalNodeID and GlobalElementID; OUT/solver.xml, a skeleton naming the faces), openfoam "
      "(OUT/constant/polyMesh, ASCII: a cell per tetrahedron and prism, a patch per boundary tag, wall for wall*), fluent "
      "(Ansys Fluent's ASCII .msh: a face zone per boundary tag, wall for wall*, velocity-inlet for inlet, "
      "pressure-outlet otherwise), xdmf (XDMF + HDF5 as dolfinx reads them: OUT/mesh.h5, OUT/mesh.xdmf with the "
      "cell tags, OUT/facets.xdmf with the facet tags; tetrahedra only), vtu "
      "(VTK, as 'volume' writes it) or medit (INRIA .mesh: vertices, triangles by tag, tetrahedra, prisms). Lengths scaled from the mesh's "
      "unit (--mesh-units, default mm) to --units (default: m for svfsi, openfoam, xdmf and fluent, the mesh's unit "
      "otherwise)");
  struct Options {
    std::string mesh, output, format, units, mesh_units = "mm";
    CommonOptions common;
  };
  auto o = std::make_shared<Options>();
  app->add_option("VOLUME", o->mesh, "Volume mesh (.msh or .vtu)")->required();
  app->add_option("-o,--output", o->output, "Output: a folder for svfsi, openfoam and xdmf, a file (.msh for fluent, .vtu, .mesh) otherwise")
      ->required();
  app->add_option("--format", o->format, "svfsi, openfoam, xdmf, fluent, vtu or medit")->required();
  app->add_option("--units", o->units, "Length unit of the output: um, mm, cm or m");
  app->add_option("--mesh-units", o->mesh_units, "Length unit of the volume mesh (default mm)");
  add_common_options(*app, o->common);
  return {app, [o] {
            TerminalReporter reporter(o->common.quiet);
            io::ExportFormat format;
            try {
              format = io::parse_export_format(o->format);
            } catch (const InputError& e) {
              throw OptionError(fmt::format("--format: {}", e.what()));
            }
            const io::Unit from = io::parse_unit(o->mesh_units);
            const io::Unit to =
                o->units.empty() ? (format == io::ExportFormat::svfsi || format == io::ExportFormat::openfoam ||
                                                           format == io::ExportFormat::fluent || format == io::ExportFormat::xdmf
                                                       ? io::Unit::m
                                                       : from) : io::parse_unit(o->units);
            const double scale = io::millimetres_per(from) / io::millimetres_per(to);
            const std::string reading = "reading " + o->mesh;
            reporter.progress(reading, 0.0);
            const TetMesh mesh = io::read_volume(o->mesh);
            reporter.progress(reading, 1.0);
            const std::string writing = fmt::format("writing {} ({})", o->output, io::to_string(format));
            reporter.progress(writing, 0.0);
            const io::ExportReport report = io::export_volume(mesh, o->output, format, scale);
            reporter.progress(writing, 1.0);
            if (o->common.json) {
              Json json;
              json["format"] = io::to_string(format);
              json["units"] = io::unit_name(to);
              json["scale"] = scale;
              json["points"] = report.points;
              json["tetrahedra"] = report.tetrahedra;
              json["prisms"] = report.prisms;
              json["boundary_triangles"] = report.boundary_triangles;
              json["files"] = report.files;
              print_json(json);
            } else {
              reporter.info(fmt::format("{} points, {} tetrahedra, {} prisms, {} boundary triangles in {} (lengths in "
                                        "{}, x {:g} from {}); {} file{}",
                                        report.points, report.tetrahedra, report.prisms, report.boundary_triangles,
                                        io::to_string(format), io::unit_name(to), scale, io::unit_name(from),
                                        report.files.size(), report.files.size() == 1 ? "" : "s"));
            }
            return 0;
          }};
}

}  // namespace vesselmesh::cli
