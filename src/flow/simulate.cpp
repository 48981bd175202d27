#include "flow/simulate.h"

#include "flow/linear_solver.h"
#include "flow/navier_stokes.h"
#include "io/atomic_file.h"
#include "io/msh.h"
#include "io/vtk_formats.h"
#include "mesh/error.h"
#include "post/indices.h"
#include "post/wss.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <filesystem>

namespace vesselmesh::flow {
namespace {

using Clock = std::chrono::steady_clock;

TetMesh read_mesh(const FlowCase& c) {
  const std::string ext = std::filesystem::path(c.mesh).extension().string();
  if (!std::filesystem::exists(c.mesh))
    throw InputError(fmt::format("{}: mesh \"{}\" does not exist (paths are relative to the case file)", c.path, c.mesh));
  if (ext == ".msh") return io::read_msh_volume(c.mesh);
  if (ext == ".vtu") return io::read_vtu_volume(c.mesh);
  throw InputError(fmt::format("{}: mesh \"{}\": a volume mesh is read from .msh (Gmsh) or .vtu (with cell data "
                               "`tag`), as `vesselmesh volume` writes them",
                               c.path, c.mesh));
}

std::string pvd(const std::vector<std::pair<double, std::string>>& files, const std::string& units) {
  std::string text = "<?xml version=\"1.0\"?>\n<!-- vesselmesh simulate: " + units + " -->\n"
                     "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n  <Collection>\n";
  for (const auto& [time, file] : files)
    text += fmt::format("    <DataSet timestep=\"{:.9g}\" group=\"\" part=\"0\" file=\"{}\"/>\n", time, file);
  return text + "  </Collection>\n</VTKFile>\n";
}

}  // namespace

SimulationSummary simulate(const FlowCase& input_case, const std::string& output_dir,
                           const std::string& extra_petsc_options, const Reporter& all_reporter) {
  const auto start = Clock::now();
  // Under mpirun every process reads the mesh and assembles its own rows; the first writes.
  const int ranks = process_count();
  const bool writer = process_rank() == 0;
  const Reporter& reporter = writer ? all_reporter : silent_reporter();
  FlowCase fc = input_case;
  if (!extra_petsc_options.empty()) fc.petsc_options += " " + extra_petsc_options;
  const TetMesh mesh = read_mesh(fc);
  reporter.info(fmt::format("mesh {}: {} points, {} tetrahedra, {} prisms, {} boundary triangles", fc.mesh,
                            mesh.num_points(), mesh.num_tets(), mesh.num_prisms(), mesh.boundary.size()));
  reporter.info(fmt::format("units: mesh in {}, scaled by {:g} to metres; velocity m/s, pressure Pa, wss Pa",
                            fc.length_unit, fc.length_scale));
  NavierStokes ns(mesh, fc, reporter);

  std::vector<int> wall_tags;
  for (const auto& [tag, name] : mesh::boundary_tag_names(mesh))
    for (const BoundaryCondition& b : fc.boundaries)
      if (b.tag == name && b.type == BoundaryType::wall) wall_tags.push_back(tag);
  const std::vector<Tet> all = mesh::all_tetrahedra(mesh);
  const post::WallSurface wall = post::extract_wall(mesh, all, wall_tags);
  std::vector<Vec3> si(mesh.points.size());
  for (size_t i = 0; i < si.size(); ++i) si[i] = mesh.points[i] * fc.length_scale;
  const post::WallShearOperator wall_shear(wall, all, si, post::parse_wss_method(fc.wss_method));
  reporter.info(fmt::format("wall shear stress: {} method on {} wall points{}", fc.wss_method, wall.mesh.num_points(),
                            wall_shear.face_fallbacks() > 0
                                ? fmt::format(" ({} by their faces: too few neighbours for a quadratic)",
                                              wall_shear.face_fallbacks())
                                : ""));

  if (writer) std::filesystem::create_directories(output_dir);
  if (ranks > 1) reporter.info(fmt::format("{} MPI processes, about {} points each", ranks, mesh.num_points() / ranks));
  const std::string units = fmt::format("points in {} (x {:g} m), velocity m/s, pressure Pa, wss Pa, time s",
                                        fc.length_unit, fc.length_scale);
  SimulationSummary summary;
  summary.points = mesh.num_points();
  summary.tetrahedra = static_cast<int>(all.size());
  summary.dofs = ns.dofs();
  summary.ranks = ranks;
  summary.length_scale = fc.length_scale;
  summary.setup_seconds = std::chrono::duration<double>(Clock::now() - start).count();
  std::vector<std::pair<double, std::string>> fluid_files, wall_files;

  std::string log = "step,time_s";
  for (const BoundaryCondition& b : fc.boundaries)
    log += fmt::format(",{0}_flux_m3_s,{0}_mean_pressure_Pa", b.tag);
  log += ",linear_iterations,max_cfl,assembly_seconds,solve_seconds,seconds\n";

  const auto write_summary = [&]() {
    if (!writer) return;
    nlohmann::ordered_json j;
    j["status"] = summary.status;
    j["case"] = fc.path;
    j["mesh"] = fc.mesh;
    j["units"] = {{"points", fc.length_unit}, {"length_scale_m", fc.length_scale}, {"velocity", "m/s"},
                  {"pressure", "Pa"}, {"wss", "Pa"}, {"time", "s"}, {"flux", "m3/s"}};
    j["points"] = summary.points;
    j["tetrahedra"] = summary.tetrahedra;
    j["dofs"] = summary.dofs;
    j["ranks"] = ranks;
    j["steady"] = fc.steady;
    j["wss_method"] = fc.wss_method;
    if (!fc.steady) j["initial"] = fc.stokes_start ? "stokes" : "rest";
    if (fc.period > 0.0) j["period"] = fc.period;
    if (summary.indices_end > summary.indices_start)
      j["indices"] = {{"file", "indices.vtp"}, {"start_s", summary.indices_start}, {"end_s", summary.indices_end},
                      {"units", {{"tawss", "Pa"}, {"osi", "1"}, {"rrt", "1/Pa"}, {"twssg", "Pa/s"}}}};
    j["steps"] = summary.steps;
    j["saved"] = summary.saved;
    j["linear_iterations"] = summary.linear_iterations;
    j["setup_seconds"] = summary.setup_seconds;
    j["seconds"] = summary.seconds;
    j["seconds_per_step"] = summary.seconds_per_step;
    j["seconds_per_step_per_million_dofs"] =
        summary.dofs > 0 ? summary.seconds_per_step / (summary.dofs * 1e-6) : 0.0;
    j["solver"] = summary.solver;
    j["petsc_options"] = fc.petsc_options;
    io::write_text(output_dir + "/summary.json", j.dump(2) + "\n");
  };

  // Hemodynamic indices over the last period (the whole run without one), from every step.
  post::WssIndexAccumulator indices;
  const double window_start = fc.period > 0.0 && fc.period < fc.end ? fc.end - fc.period : 0.0;
  const auto write_indices = [&]() {
    if (!writer || indices.samples() < 2) return;
    const post::WssIndices r = indices.result();
    post::write_indices(output_dir + "/indices.vtp", wall.mesh, r);
    summary.indices_start = r.start;
    summary.indices_end = r.end;
    reporter.info(fmt::format("indices.vtp: tawss (Pa), osi, rrt (1/Pa), twssg (Pa/s) over t = {:g} to {:g} s, {} "
                              "samples",
                              r.start, r.end, r.samples));
  };

  // `computed`: this step's wall shear stress when the indices already needed it.
  const auto save = [&](double time, const std::vector<Vec3>* computed) {
    const std::string name = fmt::format("{:06d}", summary.saved);
    if (!writer) {
      summary.saved += 1;
      return;
    }
    std::vector<double> pressure = ns.pressure();
    io::write_vtu(output_dir + "/fluid_" + name + ".vtu", mesh,
                  {Field::vector("velocity", ns.velocity()), Field::scalar("pressure", pressure)});
    const std::vector<Vec3> tau =
        computed ? *computed : wall_shear.apply(ns.velocity(), fc.viscosity);
    std::vector<double> magnitude(tau.size());
    for (size_t i = 0; i < tau.size(); ++i) magnitude[i] = tau[i].norm();
    io::write_vtp(output_dir + "/wall_" + name + ".vtp", wall.mesh,
                  {Field::vector("wss", tau), Field::scalar("wss_magnitude", magnitude)});
    fluid_files.emplace_back(time, "fluid_" + name + ".vtu");
    wall_files.emplace_back(time, "wall_" + name + ".vtp");
    summary.saved += 1;
    io::write_text(output_dir + "/fluid.pvd", pvd(fluid_files, units));
    io::write_text(output_dir + "/wall.pvd", pvd(wall_files, units));
    io::write_text(output_dir + "/log.csv", log);
  };

  const auto log_step = [&](const StepReport& r) {
    log += fmt::format("{},{:.9g}", r.step, r.time);
    for (const BoundaryFlow& f : ns.boundary_flows()) log += fmt::format(",{:.9g},{:.9g}", f.flux, f.mean_pressure);
    log += fmt::format(",{},{:.4g},{:.4g},{:.4g},{:.4g}\n", r.linear_iterations, r.max_cfl, r.assembly_seconds,
                       r.solve_seconds, r.seconds);
  };

  const auto solve_start = Clock::now();
  try {
    if (fc.steady) {
      const StepReport r = ns.solve_steady();
      summary.steps = r.step;
      summary.linear_iterations = r.linear_iterations;
      log_step(r);
      summary.solver = ns.solver_description();
      save(0.0, nullptr);
    } else {
      const int steps = static_cast<int>(std::ceil(fc.end / fc.dt - 1e-9));
      reporter.info(fmt::format("{} steps of {:g} s to t = {:g} s, {} dofs", steps, fc.dt, fc.end, ns.dofs()));
      if (fc.stokes_start) {
        const StepReport r = ns.start_from_stokes();
        reporter.info(fmt::format("initial state: the Stokes flow at t = {:g} s ({} linear iterations, {:.3g} s)",
                                  r.time, r.linear_iterations, r.seconds));
      }
      for (int k = 0; k < steps; ++k) {
        const StepReport r = ns.step();
        summary.steps = r.step;
        summary.linear_iterations += r.linear_iterations;
        log_step(r);
        if (k == 0) summary.solver = ns.solver_description();
        std::vector<Vec3> tau;
        const bool in_window = writer && r.time >= window_start - 0.5 * fc.dt;
        if (in_window) {
          tau = wall_shear.apply(ns.velocity(), fc.viscosity);
          indices.add(r.time, tau);
        }
        if (r.step % fc.save_every == 0 || k + 1 == steps) save(r.time, in_window ? &tau : nullptr);
        reporter.progress("time steps", double(k + 1) / steps);
      }
    }
  } catch (const ComputationError&) {
    summary.status = "diverged";
    summary.seconds = std::chrono::duration<double>(Clock::now() - start).count();
    if (writer) io::write_text(output_dir + "/log.csv", log);
    write_summary();
    throw;
  }
  write_indices();
  summary.status = "completed";
  summary.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  const double solving = std::chrono::duration<double>(Clock::now() - solve_start).count();
  summary.seconds_per_step = summary.steps > 0 ? solving / summary.steps : 0.0;
  write_summary();
  return summary;
}

}  // namespace vesselmesh::flow
