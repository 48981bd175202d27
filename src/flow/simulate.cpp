#include "flow/simulate.h"

#include "flow/checkpoint.h"
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

#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <filesystem>
#include <map>
#include <optional>

namespace vesselmesh::flow {
namespace {

using Clock = std::chrono::steady_clock;

// SIGTERM / SIGINT during the time steps: the number of the signal, acted on after the step under
// way (a checkpoint, then the run ends).
volatile std::sig_atomic_t stop_signal = 0;
extern "C" void note_stop_signal(int signal) { stop_signal = signal; }

// The handlers while it lives, the program's before and after.
class StopSignals {
 public:
  StopSignals() {
    stop_signal = 0;
    term_ = std::signal(SIGTERM, note_stop_signal);
    interrupt_ = std::signal(SIGINT, note_stop_signal);
  }
  ~StopSignals() {
    std::signal(SIGTERM, term_);
    std::signal(SIGINT, interrupt_);
  }
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;

 private:
  void (*term_)(int) = SIG_DFL;
  void (*interrupt_)(int) = SIG_DFL;
};

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

std::map<std::string, std::string> end_logs(const std::string& log, const std::vector<std::string>& tags) {
  constexpr double kPaPerMmHg = 133.322387415;
  std::vector<std::string> lines;
  for (size_t at = 0; at < log.size();) {
    const size_t end = log.find('\n', at);
    lines.push_back(log.substr(at, end == std::string::npos ? std::string::npos : end - at));
    at = end == std::string::npos ? log.size() : end + 1;
  }
  const auto split = [](const std::string& line) {
    std::vector<std::string> cells;
    for (size_t at = 0;;) {
      const size_t comma = line.find(',', at);
      cells.push_back(line.substr(at, comma == std::string::npos ? std::string::npos : comma - at));
      if (comma == std::string::npos) return cells;
      at = comma + 1;
    }
  };
  std::map<std::string, std::string> out;
  if (lines.empty()) return out;
  const std::vector<std::string> header = split(lines[0]);
  const auto column = [&](const std::string& name) {
    const auto it = std::find(header.begin(), header.end(), name);
    return it == header.end() ? -1 : static_cast<int>(it - header.begin());
  };
  for (const std::string& tag : tags) {
    const int flux = column(tag + "_flux_m3_s"), pressure = column(tag + "_mean_pressure_Pa"),
              capacitor = column(tag + "_capacitor_pressure_Pa");
    if (flux < 0 || pressure < 0)
      throw InternalError(fmt::format("log.csv has no flux or pressure column for the end {}", tag));
    std::string text = "step,time_s,flux_m3_s,flux_mL_s,mean_pressure_Pa,mean_pressure_mmHg";
    if (capacitor >= 0) text += ",capacitor_pressure_Pa,capacitor_pressure_mmHg";
    text += "\n";
    for (size_t k = 1; k < lines.size(); ++k) {
      if (lines[k].empty()) continue;
      const std::vector<std::string> cells = split(lines[k]);
      const auto value = [&](int c) { return std::stod(cells.at(static_cast<size_t>(c))); };
      text += fmt::format("{},{},{},{:.9g},{},{:.9g}", cells.at(0), cells.at(1), cells.at(flux), value(flux) * 1e6,
                          cells.at(pressure), value(pressure) / kPaPerMmHg);
      if (capacitor >= 0) text += fmt::format(",{},{:.9g}", cells.at(capacitor), value(capacitor) / kPaPerMmHg);
      text += "\n";
    }
    out[tag] = std::move(text);
  }
  return out;
}

SimulationSummary simulate(const FlowCase& input_case, const std::string& output_dir,
                           const std::string& extra_petsc_options, const Reporter& all_reporter, bool restart) {
  const auto start = Clock::now();
  // Under mpirun every process reads the mesh, keeps its part of it and assembles its own rows; the
  // flow is whole on every process after a step, the first computes the wall shear stress and writes.
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
  // The wall and its shear stress where the whole flow is gathered and written: on the first process.
  const post::WallSurface wall = writer ? post::extract_wall(mesh, all, wall_tags) : post::WallSurface{};
  std::optional<post::WallShearOperator> wall_shear;
  if (writer) {
    std::vector<Vec3> si(mesh.points.size());
    for (size_t i = 0; i < si.size(); ++i) si[i] = mesh.points[i] * fc.length_scale;
    wall_shear.emplace(wall, all, si, post::parse_wss_method(fc.wss_method));
    reporter.info(fmt::format("wall shear stress: {} method on {} wall points{}", fc.wss_method,
                              wall.mesh.num_points(),
                              wall_shear->face_fallbacks() > 0
                                  ? fmt::format(" ({} by their faces: too few neighbours for a quadratic)",
                                                wall_shear->face_fallbacks())
                                  : ""));
  }

  if (writer) std::filesystem::create_directories(output_dir);
  const PartitionReport partition = ns.partition();
  if (ranks > 1) {
    const auto [least, most] = std::minmax_element(partition.owned_points.begin(), partition.owned_points.end());
    const auto [least_ghosts, most_ghosts] =
        std::minmax_element(partition.ghost_points.begin(), partition.ghost_points.end());
    const double mean = static_cast<double>(mesh.num_points()) / ranks;
    reporter.info(fmt::format("{} MPI processes (points split by PT-Scotch): {} to {} unknowns each (largest / mean "
                              "{:.3f}), {} to {} ghost points, up to {} neighbours",
                              ranks, 4 * *least, 4 * *most, *most / mean, *least_ghosts, *most_ghosts,
                              *std::max_element(partition.neighbours.begin(), partition.neighbours.end())));
  }
  const std::string units = fmt::format("points in {} (x {:g} m), velocity m/s, pressure Pa, wss Pa, time s",
                                        fc.length_unit, fc.length_scale);
  SimulationSummary summary;
  summary.points = mesh.num_points();
  summary.tetrahedra = static_cast<int>(all.size());
  summary.dofs = ns.dofs();
  summary.ranks = ranks;
  summary.partition = partition;
  // Every process's peak resident memory (MB), gathered (every process calls it).
  const auto gather_memory = [&]() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    summary.peak_memory_mb = gather_all(static_cast<double>(usage.ru_maxrss) / 1024.0);
  };
  summary.length_scale = fc.length_scale;
  summary.setup_seconds = std::chrono::duration<double>(Clock::now() - start).count();
  std::vector<std::pair<double, std::string>> fluid_files, wall_files;

  std::string log = "step,time_s";
  for (const BoundaryCondition& b : fc.boundaries) {
    log += fmt::format(",{0}_flux_m3_s,{0}_mean_pressure_Pa", b.tag);
    if (b.type == BoundaryType::rcr) log += fmt::format(",{}_capacitor_pressure_Pa", b.tag);
  }
  log += ",linear_iterations,max_cfl,assembly_seconds,solve_seconds,seconds\n";
  const std::string log_header = log;
  std::vector<std::string> end_tags;
  for (const BoundaryCondition& b : fc.boundaries)
    if (b.type != BoundaryType::wall) end_tags.push_back(b.tag);
  // ends/TAG.csv's texts, grown a row a step from log.csv's (end_logs of its header and the new
  // line: one formatting for both), made whole from the log at a restart.
  std::map<std::string, std::string> end_texts = end_logs(log_header, end_tags);
  const auto log_line = [&](const std::string& line) {
    log += line;
    for (const auto& [tag, text] : end_logs(log_header + line, end_tags)) end_texts[tag] += text.substr(text.find('\n') + 1);
  };
  // log.csv and ends/TAG.csv (the writing process only).
  const auto write_logs = [&]() {
    if (!writer) return;
    io::write_text(output_dir + "/log.csv", log);
    std::filesystem::create_directories(output_dir + "/ends");
    for (const auto& [tag, text] : end_texts) io::write_text(output_dir + "/ends/" + tag + ".csv", text);
  };

  const auto write_summary = [&]() {
    if (!writer) return;
    nlohmann::ordered_json j;
    j["status"] = summary.status;
    if (summary.signal != 0) j["signal"] = summary.signal;
    j["case"] = fc.path;
    j["mesh"] = fc.mesh;
    j["units"] = {{"points", fc.length_unit}, {"length_scale_m", fc.length_scale}, {"velocity", "m/s"},
                  {"pressure", "Pa"}, {"wss", "Pa"}, {"time", "s"}, {"flux", "m3/s"}};
    j["points"] = summary.points;
    j["tetrahedra"] = summary.tetrahedra;
    j["dofs"] = summary.dofs;
    j["ranks"] = ranks;
    nlohmann::ordered_json parts;
    parts["owned_unknowns"] = nlohmann::ordered_json::array();
    for (int points : summary.partition.owned_points) parts["owned_unknowns"].push_back(4 * points);
    parts["ghost_points"] = summary.partition.ghost_points;
    parts["neighbours"] = summary.partition.neighbours;
    j["partition"] = parts;
    if (!summary.peak_memory_mb.empty()) j["peak_memory_mb"] = summary.peak_memory_mb;
    if (!summary.ends.empty()) {
      nlohmann::ordered_json ends = nlohmann::ordered_json::array();
      for (size_t k = 0; k < summary.ends.size(); ++k) {
        const BoundaryFlow& f = summary.ends[k];
        nlohmann::ordered_json e = {{"tag", f.tag}, {"type", to_string(fc.boundaries[k].type)},
                                    {"flux_m3_s", f.flux}, {"mean_pressure_Pa", f.mean_pressure}};
        if (fc.boundaries[k].type == BoundaryType::rcr) e["capacitor_pressure_Pa"] = f.capacitor_pressure;
        ends.push_back(e);
      }
      j["ends"] = ends;  // at the last step
    }
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
    const std::vector<double>& pressure = ns.pressure();
    io::write_vtu(output_dir + "/fluid_" + name + ".vtu", mesh,
                  {Field::vector("velocity", ns.velocity()), Field::scalar("pressure", pressure)});
    const std::vector<Vec3> tau =
        computed ? *computed : wall_shear->apply(ns.velocity(), fc.viscosity);
    std::vector<double> magnitude(tau.size());
    for (size_t i = 0; i < tau.size(); ++i) magnitude[i] = tau[i].norm();
    io::write_vtp(output_dir + "/wall_" + name + ".vtp", wall.mesh,
                  {Field::vector("wss", tau), Field::scalar("wss_magnitude", magnitude)});
    fluid_files.emplace_back(time, "fluid_" + name + ".vtu");
    wall_files.emplace_back(time, "wall_" + name + ".vtp");
    summary.saved += 1;
    io::write_text(output_dir + "/fluid.pvd", pvd(fluid_files, units));
    io::write_text(output_dir + "/wall.pvd", pvd(wall_files, units));
    write_logs();
  };

  const auto log_step = [&](const StepReport& r) {
    std::string line = fmt::format("{},{:.9g}", r.step, r.time);
    const std::vector<BoundaryFlow> flows = ns.boundary_flows();
    for (size_t k = 0; k < flows.size(); ++k) {
      line += fmt::format(",{:.9g},{:.9g}", flows[k].flux, flows[k].mean_pressure);
      if (fc.boundaries[k].type == BoundaryType::rcr) line += fmt::format(",{:.9g}", flows[k].capacitor_pressure);
    }
    line += fmt::format(",{},{:.4g},{:.4g},{:.4g},{:.4g}\n", r.linear_iterations, r.max_cfl, r.assembly_seconds,
                        r.solve_seconds, r.seconds);
    log_line(line);
  };

  // Checkpoints: the state to go on from, in the mesh's numbering.
  const std::string checkpoint_path = output_dir + "/checkpoint.bin";
  const uint64_t fingerprint = run_fingerprint(mesh, fc.dt);
  const auto write_checkpoint_now = [&]() {
    FlowState flow = ns.state();  // every process takes part; the first has it whole
    if (!writer) return;
    Checkpoint c;
    c.fingerprint = fingerprint;
    c.flow = std::move(flow);
    c.saved = summary.saved;
    c.linear_iterations = summary.linear_iterations;
    c.log = log;
    c.fluid_files = fluid_files;
    c.wall_files = wall_files;
    c.indices = indices.state();
    write_checkpoint(checkpoint_path, c);
  };
  int first_step = 0;
  if (restart) {
    if (fc.steady) throw InputError(fmt::format("{}: --restart: a steady case has no time steps to go on from", fc.path));
    if (!std::filesystem::exists(checkpoint_path))
      throw InputError(fmt::format("{}: no checkpoint to restart from; run the case without --restart", checkpoint_path));
    const Checkpoint c = read_checkpoint(checkpoint_path);
    if (c.fingerprint != fingerprint)
      throw InputError(fmt::format("{}: the checkpoint is of another mesh or time step than {}'s; run the case without "
                                   "--restart (or into another folder)",
                                   checkpoint_path, fc.path));
    ns.restore(c.flow);
    first_step = c.flow.steps;
    summary.steps = c.flow.steps;
    summary.saved = c.saved;
    summary.linear_iterations = c.linear_iterations;
    log = c.log;
    end_texts = end_logs(log, end_tags);
    fluid_files = c.fluid_files;
    wall_files = c.wall_files;
    indices.restore(c.indices);
    if (writer) {  // the folder as it was at the checkpoint (later saves are written again)
      io::write_text(output_dir + "/fluid.pvd", pvd(fluid_files, units));
      io::write_text(output_dir + "/wall.pvd", pvd(wall_files, units));
      write_logs();
    }
    reporter.info(fmt::format("restart from {}: step {}, t = {:g} s", checkpoint_path, c.flow.steps, c.flow.time));
  }

  const auto solve_start = Clock::now();
  // The run's end (completed or stopped): its times, every process's memory, the summary.
  const auto finish = [&](const char* status) {
    summary.status = status;
    summary.seconds = std::chrono::duration<double>(Clock::now() - start).count();
    const double solving = std::chrono::duration<double>(Clock::now() - solve_start).count();
    summary.seconds_per_step = summary.steps > first_step ? solving / (summary.steps - first_step) : 0.0;
    gather_memory();
    summary.ends = ns.boundary_flows();  // every process takes part
    write_summary();
  };

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
      if (fc.stokes_start && !restart) {
        const StepReport r = ns.start_from_stokes();
        reporter.info(fmt::format("initial state: the Stokes flow at t = {:g} s ({} linear iterations, {:.3g} s)",
                                  r.time, r.linear_iterations, r.seconds));
      }
      if (first_step >= steps)
        reporter.warning(fmt::format("the checkpoint is at step {}, the case ends at step {}: nothing to do (a later "
                                     "[time] end extends the run)",
                                     first_step, steps));
      const StopSignals signals;
      for (int k = first_step; k < steps; ++k) {
        const StepReport r = ns.step();
        summary.steps = r.step;
        summary.linear_iterations += r.linear_iterations;
        log_step(r);
        if (k == 0) summary.solver = ns.solver_description();
        std::vector<Vec3> tau;
        const bool in_window = writer && r.time >= window_start - 0.5 * fc.dt;
        if (in_window) {
          tau = wall_shear->apply(ns.velocity(), fc.viscosity);
          indices.add(r.time, tau);
        }
        if (r.step % fc.save_every == 0 || k + 1 == steps) save(r.time, in_window ? &tau : nullptr);
        // Every process stops at the same step (a signal may reach them apart).
        const bool stop = any_process(stop_signal != 0);
        if (stop || k + 1 == steps || (fc.checkpoint_every > 0 && r.step % fc.checkpoint_every == 0))
          write_checkpoint_now();
        if (stop) {
          summary.signal = stop_signal != 0 ? static_cast<int>(stop_signal) : SIGTERM;
          write_logs();
          finish("stopped");
          reporter.warning(fmt::format("stopped by signal {} after step {} (t = {:g} s); the checkpoint {} holds it: "
                                       "'vesselmesh simulate {} -o {} --restart' goes on",
                                       summary.signal, r.step, r.time, checkpoint_path, fc.path, output_dir));
          return summary;
        }
        reporter.progress("time steps", double(k + 1) / steps);
      }
    }
  } catch (const ComputationError&) {
    summary.status = "diverged";
    summary.seconds = std::chrono::duration<double>(Clock::now() - start).count();
    write_logs();
    write_summary();
    throw;
  }
  write_indices();
  finish("completed");
  return summary;
}

}  // namespace vesselmesh::flow
