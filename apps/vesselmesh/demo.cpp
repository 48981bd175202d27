// vesselmesh demo: the whole pipeline, as far as it exists, on the bundled example vessel.
// Stages that land are added here in pipeline order; each writes its outputs into the folder.
#include "commands.h"

#include "flow/case.h"
#include "flow/simulate.h"
#include "io/atomic_file.h"
#include "io/msh.h"
#include "io/vtk_formats.h"
#include "mesh/error.h"
#include "remesh/extend.h"
#include "study/study.h"
#include "volume/quality.h"
#include "volume/volume_mesh.h"

#include <fmt/format.h>

#include <filesystem>
#include <iostream>
#include <optional>

#include <unistd.h>

#ifndef VESSELMESH_SOURCE_DATA_DIR
#define VESSELMESH_SOURCE_DATA_DIR ""
#endif

namespace vesselmesh::cli {
namespace {

namespace fs = std::filesystem;

constexpr const char* kDemoVessel = "y_bifurcation.stl";
constexpr double kDemoTriangles = 8000.0;  // the paper compares meshes of equal size
constexpr double kDemoFlow = 2.0;          // mL/s into the parent vessel (r = 3 mm): Re about 130
constexpr double kStudyTriangles = 4000.0; // the reduced study: small meshes, one refinement level

// The bundled data folder: beside the build or install tree, else the source tree.
fs::path data_folder() {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  std::vector<fs::path> candidates;
  if (!ec) {
    candidates.push_back(exe.parent_path().parent_path() / "data");
    candidates.push_back(exe.parent_path().parent_path() / "share" / "vesselmesh" / "data");
  }
  candidates.emplace_back(VESSELMESH_SOURCE_DATA_DIR);
  for (const fs::path& folder : candidates)
    if (!folder.empty() && fs::exists(folder / kDemoVessel, ec)) return folder;
  throw InputError(fmt::format("cannot find the bundled example '{}' (looked beside the program and in {}); "
                               "give a surface with --input",
                               kDemoVessel, VESSELMESH_SOURCE_DATA_DIR));
}

}  // namespace

Command add_demo_command(CLI::App& parent) {
  CLI::App* app = parent.add_subcommand(
      "demo", "Run the pipeline on the bundled example vessel (or --input) and write every stage's output "
              "into a folder");
  struct Options {
    std::string output, input, units;
    double extensions = 0.0;
    CommonOptions common;
  };
  auto o = std::make_shared<Options>();
  app->add_option("-o,--output", o->output, "Folder for the results (created if needed)")->required();
  app->add_option("--input", o->input, "Run on this surface instead of the bundled example");
  app->add_option("--units", o->units, "Length unit of --input: um, mm, cm or m (default mm)");
  app->add_option("--extensions", o->extensions,
                  "Flow extensions of this many radii on every open end (as 'vesselmesh extend'; 0: none), for every "
                  "stage after the first and the study ([extensions] length)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  add_common_options(*app, o->common);
  return {app, [o] {
            TerminalReporter reporter(o->common.quiet);
            const fs::path input = o->input.empty() ? data_folder() / kDemoVessel : fs::path(o->input);
            const fs::path folder(o->output);
            std::error_code ec;
            fs::create_directories(folder, ec);
            if (ec || !fs::is_directory(folder))
              throw InputError(fmt::format("{}: cannot create the output folder: {}", o->output, ec.message()));

            // Stage 1: read, check and repair the surface; describe its ends.
            SurfaceCheckOptions check;
            if (!o->units.empty()) check.units = o->units;
            reporter.info(fmt::format("stage 1: checking {}", input.string()));
            const CheckedSurface surface = check_surface(input.string(), check, reporter);
            const Json info = describe(surface);
            io::write_text((folder / "surface_info.json").string(), info.dump(2) + "\n");
            io::write_text((folder / "surface_info.txt").string(), describe_as_text(surface));
            write_repaired((folder / "surface.vtp").string(), surface);
            std::optional<remesh::ExtensionResult> extended;
            if (o->extensions > 0.0) {
              reporter.info(fmt::format("stage 1: flow extensions of {:g} radii on every open end", o->extensions));
              extended = remesh::extend_ends(surface.file.mesh, surface.ends, {.length = o->extensions});
              io::write_vtp((folder / "surface_extended.vtp").string(), extended->mesh);
            }
            const TriMesh& vessel = extended ? extended->mesh : surface.file.mesh;  // what the stages below mesh

            // Stage 2: curvature (drives the curvature-adapted meshes).
            reporter.info("stage 2: curvature");
            const analysis::CurvatureField curvature = analysis::curvature(vessel, {}, reporter);
            io::write_vtp((folder / "curvature.vtp").string(), vessel, curvature_fields(curvature));

            // Stage 3: centerlines and the distance map (drive the distance-adapted meshes and the
            // boundary layer's thickness).
            reporter.info("stage 3: centerlines and distance map");
            const centerline::Centerlines lines = centerline::extract(vessel, {}, reporter);
            write_centerlines((folder / "centerlines.vtp").string(), lines);
            write_distance_map((folder / "distance_map.vtp").string(), vessel, lines);

            // Stage 4: the paper's four surface meshes, one size field each, with the same
            // number of triangles.
            const centerline::DistanceMap distance = centerline::distance_map(vessel, lines);
            Json meshes = Json::object();
            std::vector<std::pair<std::string, std::string>> remeshed;
            TriMesh curvature_adapted;  // the wall of stage 5
            for (sizing::SizeKind kind : {sizing::SizeKind::uniform, sizing::SizeKind::distance,
                                          sizing::SizeKind::curvature, sizing::SizeKind::anisotropic}) {
              const std::string name = sizing::size_kind_name(kind);
              reporter.info(fmt::format("stage 4: {} surface mesh of about {} triangles", name, kDemoTriangles));
              const sizing::SizeField field =
                  sizing::make_size_field(vessel, {.kind = kind, .target_triangles = kDemoTriangles},
                                          {.curvature = &curvature, .distance = &distance}, reporter);
              remesh::RemeshOptions options;
              options.input_radius = &distance.radius;
              const remesh::RemeshResult result =
                  remesh::adapt_to_count(vessel, field.metric, kDemoTriangles, options, reporter);
              write_remeshed((folder / ("surface_" + name + ".vtp")).string(), result);
              if (kind == sizing::SizeKind::curvature) curvature_adapted = result.mesh;
              meshes[name] = remesh_json(result.stats);
              remeshed.emplace_back("surface_" + name + ".vtp",
                                    fmt::format("the {} surface mesh: {} triangles, metric and quality", name,
                                                result.stats.triangles));
            }

            // Stage 5: the volume mesh (4 layers, 10 % of the radius) on the curvature-adapted
            // surface.
            reporter.info("stage 5: volume mesh on the curvature-adapted surface");
            const TriMesh& wall = curvature_adapted;
            const auto wall_ends = analysis::open_ends(wall);
            const centerline::DistanceMap wall_distance =
                centerline::distance_map(wall, centerline::extract(wall, {}, reporter));
            const volume::VolumeResult volume_mesh =
                volume::build_volume(wall, wall_ends, wall_distance.radius, {}, reporter);
            io::write_vtu((folder / "volume.vtu").string(), volume_mesh.mesh, {Field::scalar("radius", volume_mesh.radius)});
            const volume::VolumeQuality volume_quality = volume::measure_volume(volume_mesh.mesh, volume_mesh.radius);
            remeshed.emplace_back("volume.vtu", fmt::format("the volume mesh: {} tetrahedra, 4 layers, tags wall/inlet/"
                                                            "outlet_1/outlet_2, least dihedral angle {:.1f} deg",
                                                            volume_quality.tets, volume_quality.min_dihedral));

            // Stage 6: steady flow on that volume mesh, from a case file written beside it.
            reporter.info("stage 6: steady flow on the volume mesh");
            io::write_msh((folder / "volume.msh").string(), volume_mesh.mesh);
            std::string case_text = fmt::format(
                "# Written by vesselmesh demo: steady flow in the demo vessel (run it again with\n"
                "#   vesselmesh simulate {0}/flow.toml -o {0}/flow)\n"
                "mesh = \"volume.msh\"\nlength_unit = \"mm\"\n"
                "[fluid]\ndensity = 1060.0\nviscosity = 0.0035\n[time]\nsteady = true\n"
                "[[boundary]]\ntag = \"inlet\"\ntype = \"velocity\"\nprofile = \"parabolic\"\nflow = {1}\n",
                o->output, kDemoFlow);
            for (const auto& end : volume_mesh.report.ends)
              if (end.name != "inlet")
                case_text += fmt::format("[[boundary]]\ntag = \"{}\"\ntype = \"traction\"\n", end.name);
            case_text += "[[boundary]]\ntag = \"wall\"\ntype = \"wall\"\n";
            io::write_text((folder / "flow.toml").string(), case_text);
            const flow::SimulationSummary flow_summary =
                flow::simulate(flow::read_case((folder / "flow.toml").string()), (folder / "flow").string(), "", reporter);
            remeshed.emplace_back("volume.msh", "the same volume mesh as Gmsh MSH 4.1, for the solver");
            remeshed.emplace_back("flow.toml", fmt::format("the flow case: {} mL/s in, zero traction at the outlets", kDemoFlow));
            remeshed.emplace_back("flow/fluid.pvd", "steady velocity (m/s) and pressure (Pa)");
            remeshed.emplace_back("flow/wall.pvd", "wall shear stress wss, wss_magnitude (Pa)");

            // Stage 7: the reduced mesh-impact study: the four meshes at 4000 triangles against one
            // level of the envelope reference (1.46 times finer than the finest of them everywhere),
            // the same steady flow, a ring at the middle of every branch.
            reporter.info("stage 7: the reduced mesh-impact study");
            std::string study_text = fmt::format(
                "# Written by vesselmesh demo: the reduced mesh-impact study (run it again with\n"
                "#   vesselmesh study {0}/study.toml -o {0}/study)\n"
                "surface = \"surface.vtp\"\ncase = \"flow.toml\"\ntriangles = {1}\n"
                "[reference]\nlevels = 1\n",
                o->output, kStudyTriangles);
            if (o->extensions > 0.0) study_text += fmt::format("[extensions]\nlength = {:g}\n", o->extensions);
            for (const centerline::Branch& b : lines.branches) {
              const Vec3& p = b.points[b.points.size() / 2];
              study_text += fmt::format("[[ring]]\nname = \"branch_{}\"\npoint = [{:.6g}, {:.6g}, {:.6g}]\n", b.id,
                                        p.x(), p.y(), p.z());
            }
            io::write_text((folder / "study.toml").string(), study_text);
            const study::StudyResult study_result =
                study::run_study(study::read_study((folder / "study.toml").string()), (folder / "study").string(),
                                 reporter);
            remeshed.emplace_back("study.toml", "the reduced study: 4 meshes of 4000 triangles, 1 envelope reference level");
            if (extended)
              remeshed.insert(remeshed.begin(), {"surface_extended.vtp",
                                                 fmt::format("the surface with flow extensions of {:g} radii (mm)",
                                                             o->extensions)});
            remeshed.emplace_back("study/report.html", "the study's report (also report.md, figures/, study.json)");

            std::vector<std::pair<std::string, std::string>> outputs = {
                {"surface_info.txt", "what the mesh doctor found, the open ends, statistics"},
                {"surface_info.json", "the same, machine-readable (vesselmesh info --json)"},
                {"surface.vtp", "the repaired surface in mm (open in ParaView)"},
                {"curvature.vtp", "k1, k2, mean and Gaussian curvature (1/mm), principal directions, normals"},
                {"centerlines.vtp", "centerline branches with the inscribed sphere radius (mm)"},
                {"distance_map.vtp", "each wall point's distance to the centerline and the radius there (mm)"},
            };
            outputs.insert(outputs.end(), remeshed.begin(), remeshed.end());
            if (o->common.json) {
              Json summary = {{"input", input.string()},
                              {"output", o->output},
                              {"surface", info},
                              {"surface_meshes", meshes},
                              {"volume",
                               {{"tetrahedra", volume_quality.tets},
                                {"inverted", volume_quality.inverted},
                                {"closed_boundary", volume_quality.closed},
                                {"min_dihedral_deg", round_to(volume_quality.min_dihedral, 4)}}},
                              {"flow",
                               {{"dofs", flow_summary.dofs},
                                {"steady_method", "newton"},  // the default, as the demo's case leaves it
                                {"steady_iterations", flow_summary.steps},
                                {"linear_iterations", flow_summary.linear_iterations},
                                {"seconds", round_to(flow_summary.seconds, 4)}}},
                              {"study", {{"report", study_result.report_html}, {"meshes", study_result.meshes.size()}}}};
              Json files = Json::array();
              for (const auto& [name, what] : outputs) files.push_back((folder / name).string());
              summary["files"] = files;
              print_json(summary);
            } else {
              std::cout << describe_as_text(surface) << "\nwritten to " << o->output << ":\n";
              for (const auto& [name, what] : outputs) std::cout << fmt::format("  {:<26} {}\n", name, what);
              std::cout << fmt::format("\nthe study's report: {}\n", study_result.report_html);
            }
            return 0;
          }};
}

}  // namespace vesselmesh::cli
