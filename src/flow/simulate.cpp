#include "flow/simulate.h"

#include "flow/checkpoint.h"
#include "flow/navier_stokes.h"
#include "io/atomic_file.h"
#include "io/msh.h"
#include "io/volume_file.h"
#include "io/vtk_formats.h"
#include "mesh/error.h"
#include "parallel/processes.h"
#include "post/indices.h"
#include "post/wss.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <sys/resource.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
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
  if (ext == ".msh" || ext == ".vtu") return io::read_volume(c.mesh);
  throw InputError(fmt::format("{}: mesh \"{}\": a volume mesh is read from .msh (Gmsh) or .vtu (with cell data "
                               "`tag`), as `vesselmesh volume` writes them",
                               c.path, c.mesh));
}

// This process's peak resident memory so far (MB).
double peak_memory_mb() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_maxrss) / 1024.0;
}

// This process's resident pages of mapped files (MB; /proc/self/status RssFile, 0 where there is
// none): the shared libraries' code and constants, mapped once at the start and shared by every
// process of a node (about 57 MB here: PETSc and its solvers, MPI, VTK, Gmsh). The peak less it is
// the memory the process holds of its own.
double file_memory_mb() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line))
    if (line.rfind("RssFile:", 0) == 0) return std::strtod(line.c_str() + 8, nullptr) / 1024.0;
  return 0.0;
}

// The wall whose shear stress this process computes and writes, and how its points lead back to
// the mesh.
struct WallPiece {
  post::WallSurface surface;  // the wall the operator works on
  std::optional<post::WallShearOperator> shear;
  TriMesh mesh;                    // the triangles this process writes, in the mesh's unit (labels: tags)
  std::vector<int> surface_point;  // per point of `mesh`, its point of `surface`
  std::vector<int> mesh_point;     // per point of `mesh`, its number in the mesh read
  // The wall points this process owns (each counted on one process) and those of them that took
  // the face value.
  int owned_points = 0, owned_fallbacks = 0;

  // Per point of `mesh`, Pa; `velocity` per point of the volume the operator was made on.
  std::vector<Vec3> stress(const std::vector<Vec3>& velocity, double viscosity) const {
    const std::vector<Vec3> all = shear->apply(velocity, viscosity);
    std::vector<Vec3> out(surface_point.size());
    for (size_t i = 0; i < out.size(); ++i) out[i] = all[surface_point[i]];
    return out;
  }
};

// One process: the whole wall of the mesh read.
WallPiece whole_wall(const TetMesh& mesh, const std::vector<int>& wall_tags, const FlowCase& fc) {
  WallPiece w;
  const std::vector<Tet> all = mesh::all_tetrahedra(mesh);
  w.surface = post::extract_wall(mesh, all, wall_tags);
  std::vector<Vec3> si(mesh.points.size());
  for (size_t i = 0; i < si.size(); ++i) si[i] = mesh.points[i] * fc.length_scale;
  w.shear.emplace(w.surface, all, si, post::parse_wss_method(fc.wss_method));
  w.mesh = w.surface.mesh;
  w.surface_point.resize(w.mesh.num_points());
  for (int v = 0; v < w.mesh.num_points(); ++v) w.surface_point[v] = v;
  w.mesh_point = w.surface.volume_point;
  w.owned_points = w.mesh.num_points();
  w.owned_fallbacks = w.shear->face_fallbacks();
  return w;
}

// Under MPI: the process's part of the wall (MeshPart::wall), the operator on its cells within
// the stencils' reach (its local points), and the triangles it writes.
WallPiece distributed_wall(const MeshPart& part, const std::vector<int>& wall_tags, const FlowCase& fc) {
  WallPiece w;
  TetMesh band;
  band.points = part.points;
  band.boundary = part.wall.triangles;
  band.boundary_tags = part.wall.tags;
  w.surface = post::extract_wall(band, part.wall.cells, wall_tags);
  std::vector<Vec3> si(part.points.size());
  for (size_t i = 0; i < si.size(); ++i) si[i] = part.points[i] * fc.length_scale;
  w.shear.emplace(w.surface, part.wall.cells, si, post::parse_wss_method(fc.wss_method));
  // extract_wall keeps the triangles' order: the written ones, their points numbered anew.
  std::vector<int> at(w.surface.mesh.num_points(), -1);
  for (size_t f = 0; f < part.wall.triangles.size(); ++f) {
    if (!part.wall.written[f]) continue;
    Triangle tri = w.surface.mesh.triangles[f];
    for (int& v : tri) {
      if (at[v] < 0) {
        at[v] = w.mesh.num_points();
        w.mesh.points.push_back(w.surface.mesh.points[v]);
        w.surface_point.push_back(v);
        w.mesh_point.push_back(part.mesh_point[w.surface.volume_point[v]]);
      }
      v = at[v];
    }
    w.mesh.triangles.push_back(tri);
    w.mesh.labels.push_back(part.wall.tags[f]);
  }
  for (int v = 0; v < w.surface.mesh.num_points(); ++v)
    if (w.surface.volume_point[v] < part.owned) {
      ++w.owned_points;
      if (w.shear->by_face(v)) ++w.owned_fallbacks;
    }
  return w;
}

// The indices' running sums of every process (per point of its wall piece, `mesh_point` their
// numbers in the mesh), on the first process: by mesh point, once each (a point two processes
// write has the same sums on both), with those numbers. Every process calls it.
std::pair<post::WssIndexAccumulator::State, std::vector<int>> gather_indices(
    const post::WssIndexAccumulator::State& mine, const std::vector<int>& mesh_point) {
  constexpr int kWidth = 9;  // mesh point, last (3), integral (3), |tau| integral, change
  std::vector<double> packed;
  if (!mine.last.empty())
    for (size_t k = 0; k < mesh_point.size(); ++k) {
      packed.push_back(mesh_point[k]);
      for (int i = 0; i < 3; ++i) packed.push_back(mine.last[k][i]);
      for (int i = 0; i < 3; ++i) packed.push_back(mine.integral[k][i]);
      packed.push_back(mine.magnitude_integral[k]);
      packed.push_back(mine.change[k]);
    }
  const std::vector<double> all = parallel::gather_to_first(packed);
  post::WssIndexAccumulator::State whole{mine.samples, mine.start, mine.last_time, {}, {}, {}, {}};
  std::vector<int> points;
  std::vector<size_t> order(all.size() / kWidth);
  for (size_t k = 0; k < order.size(); ++k) order[k] = k;
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return all[kWidth * a] < all[kWidth * b]; });
  for (size_t k : order) {
    const double* at = &all[kWidth * k];
    if (!points.empty() && points.back() == static_cast<int>(at[0])) continue;
    points.push_back(static_cast<int>(at[0]));
    whole.last.emplace_back(at[1], at[2], at[3]);
    whole.integral.emplace_back(at[4], at[5], at[6]);
    whole.magnitude_integral.push_back(at[7]);
    whole.change.push_back(at[8]);
  }
  return {std::move(whole), std::move(points)};
}

// A checkpoint's indices (by mesh point, `points` sorted) at the points of this process's wall
// piece. InputError when one is missing (a checkpoint of another wall).
post::WssIndexAccumulator::State indices_at(const post::WssIndexAccumulator::State& whole,
                                            const std::vector<int>& points, const std::vector<int>& mesh_point,
                                            const std::string& path) {
  post::WssIndexAccumulator::State mine{whole.samples, whole.start, whole.last_time, {}, {}, {}, {}};
  if (whole.last.empty()) return mine;
  for (int m : mesh_point) {
    const auto it = std::lower_bound(points.begin(), points.end(), m);
    if (it == points.end() || *it != m)
      throw InputError(fmt::format("{}: the checkpoint has no indices at wall point {} of the mesh: run the case "
                                   "without --restart",
                                   path, m));
    const size_t k = static_cast<size_t>(it - points.begin());
    mine.last.push_back(whole.last[k]);
    mine.integral.push_back(whole.integral[k]);
    mine.magnitude_integral.push_back(whole.magnitude_integral[k]);
    mine.change.push_back(whole.change[k]);
  }
  return mine;
}

std::string pvd(const std::vector<std::pair<double, std::string>>& files, const std::string& units) {
  std::string text = "<?xml version=\"1.0\"?>\n<!-- vesselmesh simulate: " + units + " -->\n"
                     "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n  <Collection>\n";
  for (const auto& [time, file] : files)
    text += fmt::format("    <DataSet timestep=\"{:.9g}\" group=\"\" part=\"0\" file=\"{}\"/>\n", time, file);
  return text + "  </Collection>\n</VTKFile>\n";
}

// A steady solve's iterations for summary.json (also of a solve that did not settle): what each
// was, the share of the inflow, the residual of the flow it started from (null for the first), the
// change it made, its linear iterations.
nlohmann::ordered_json history_json(const std::vector<SteadyIteration>& history) {
  nlohmann::ordered_json rows = nlohmann::ordered_json::array();
  for (const SteadyIteration& k : history)
    rows.push_back({{"iteration", k.iteration},
                    {"method", k.method},
                    {"inflow", k.inflow},
                    {"residual", k.residual >= 0.0 ? nlohmann::ordered_json(k.residual) : nlohmann::ordered_json()},
                    {"change", k.change},
                    {"linear_iterations", k.linear_iterations}});
  return rows;
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
  // Under mpirun the first process reads the mesh and sends every process its part (the others
  // never read it); each assembles its own rows, computes the wall shear stress of its part of the
  // wall and writes its pieces of the results (pieces/, joined by .pvtu / .pvtp files the first
  // writes). On one process the results are whole files, the mesh as read.
  const int ranks = parallel::process_count(), rank = parallel::process_rank();
  const bool writer = rank == 0, pieces = ranks > 1;
  const Reporter& reporter = writer ? all_reporter : silent_reporter();
  FlowCase fc = input_case;
  if (!extra_petsc_options.empty()) fc.petsc_options += " " + extra_petsc_options;
  std::vector<std::string> wall_names;
  for (const BoundaryCondition& b : fc.boundaries)
    if (b.type == BoundaryType::wall) wall_names.push_back(b.tag);
  TetMesh mesh;
  uint64_t fingerprint = 0;  // of the mesh and the time step, the first process's (checkpoints)
  std::exception_ptr unread;
  if (writer) {
    try {
      mesh = read_mesh(fc);
      reporter.info(fmt::format("mesh {}: {} points, {} tetrahedra, {} prisms, {} boundary triangles", fc.mesh,
                                mesh.num_points(), mesh.num_tets(), mesh.num_prisms(), mesh.boundary.size()));
      fingerprint = run_fingerprint(mesh, fc.dt);
    } catch (...) {
      unread = std::current_exception();
    }
  }
  MeshPart part =
      distribute_mesh(writer ? &mesh : nullptr, fc.mesh, unread, pieces ? wall_names : std::vector<std::string>{});
  if (pieces) mesh = TetMesh{};  // the parts hold it now
  const double distribution_memory = peak_memory_mb();  // the first process's: the whole mesh read and split
  if (pieces)
    reporter.info(fmt::format("mesh read and split by the first process (peak memory {:.0f} MB), a part sent to "
                              "each of the {} others",
                              distribution_memory, ranks - 1));
  reporter.info(fmt::format("units: mesh in {}, scaled by {:g} to metres; velocity m/s, pressure Pa, wss Pa",
                            fc.length_unit, fc.length_scale));
  const int mesh_tetrahedra = part.mesh_tetrahedra, mesh_points = part.total_points;
  std::vector<int> wall_tags;
  for (const auto& [tag, name] : part.tag_names)
    if (std::find(wall_names.begin(), wall_names.end(), name) != wall_names.end()) wall_tags.push_back(tag);
  // The results this process writes: the whole mesh on one process; under MPI its piece of the
  // fluid (its cells whose least point it owns) and of the wall (its wall triangles).
  WallPiece wall;
  TetMesh fluid_piece;
  std::vector<int> fluid_local;  // per point of the fluid piece, its local point
  if (pieces) {
    wall = distributed_wall(part, wall_tags, fc);
    fluid_piece.tag_names = part.tag_names;
    std::vector<int> at(part.points.size(), -1);
    for (const Tet& t4 : part.tets) {
      int least = t4[0];
      for (int a : t4)
        if (part.local_global[a] < part.local_global[least]) least = a;
      if (least >= part.owned) continue;  // another process's
      Tet cell = t4;
      for (int& a : cell) {
        if (at[a] < 0) {
          at[a] = static_cast<int>(fluid_local.size());
          fluid_local.push_back(a);
          fluid_piece.points.push_back(part.points[a]);
        }
        a = at[a];
      }
      fluid_piece.tets.push_back(cell);
    }
  } else {
    wall = whole_wall(mesh, wall_tags, fc);
  }
  NavierStokes ns(std::move(part), fc, reporter);
  const int wall_points = pieces ? static_cast<int>(parallel::sum_all({static_cast<double>(wall.owned_points)})[0])
                                 : wall.mesh.num_points();
  const int fallbacks = pieces ? static_cast<int>(parallel::sum_all({static_cast<double>(wall.owned_fallbacks)})[0])
                               : wall.shear->face_fallbacks();
  reporter.info(fmt::format("wall shear stress: {} method on {} wall points{}", fc.wss_method, wall_points,
                            fallbacks > 0 ? fmt::format(" ({} by their faces: too few neighbours for a quadratic)",
                                                        fallbacks)
                                          : ""));
  // The wall shear stress at the wall points this process writes (Pa).
  const auto wall_stress = [&]() {
    return wall.stress(pieces ? ns.local_velocity() : ns.velocity(), fc.viscosity);
  };

  if (writer) std::filesystem::create_directories(output_dir);
  const PartitionReport partition = ns.partition();
  reporter.info(fmt::format("assembly: {} thread{} a process", partition.threads, partition.threads > 1 ? "s" : ""));
  if (ranks > 1) {
    const auto [least, most] = std::minmax_element(partition.owned_points.begin(), partition.owned_points.end());
    const auto [least_ghosts, most_ghosts] =
        std::minmax_element(partition.ghost_points.begin(), partition.ghost_points.end());
    const double mean = static_cast<double>(mesh_points) / ranks;
    reporter.info(fmt::format("{} MPI processes (points split by PT-Scotch): {} to {} unknowns each (largest / mean "
                              "{:.3f}), {} to {} ghost points, up to {} neighbours",
                              ranks, 4 * *least, 4 * *most, *most / mean, *least_ghosts, *most_ghosts,
                              *std::max_element(partition.neighbours.begin(), partition.neighbours.end())));
  }
  const std::string units = fmt::format("points in {} (x {:g} m), velocity m/s, pressure Pa, wss Pa, time s",
                                        fc.length_unit, fc.length_scale);
  SimulationSummary summary;
  summary.points = mesh_points;
  summary.tetrahedra = mesh_tetrahedra;
  summary.distribution_memory_mb = distribution_memory;
  summary.dofs = ns.dofs();
  summary.ranks = ranks;
  summary.partition = partition;
  // Every process's peak resident memory (MB), gathered (every process calls it).
  const auto gather_memory = [&]() {
    summary.peak_memory_mb = parallel::gather_all(peak_memory_mb());
    summary.library_memory_mb = parallel::gather_all(file_memory_mb());
    summary.own_memory_mb.resize(summary.peak_memory_mb.size());
    for (size_t r = 0; r < summary.own_memory_mb.size(); ++r)
      summary.own_memory_mb[r] = summary.peak_memory_mb[r] - summary.library_memory_mb[r];
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
    j["assembly_threads"] = summary.partition.threads;
    if (!summary.peak_memory_mb.empty()) {
      j["peak_memory_mb"] = summary.peak_memory_mb;
      j["library_memory_mb"] = summary.library_memory_mb;
      j["peak_own_memory_mb"] = summary.own_memory_mb;
    }
    j["distribution_peak_memory_mb"] = summary.distribution_memory_mb;
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
    if (fc.steady && summary.steady_residual >= 0.0) j["steady_residual"] = summary.steady_residual;
    if (fc.steady) {
      j["steady_method"] = fc.steady_method;
      j["steady_history"] = history_json(ns.steady_history());
    }
    j["wss_method"] = fc.wss_method;
    if (!fc.steady) j["initial"] = fc.stokes_start ? "stokes" : "rest";
    if (fc.period > 0.0) j["period"] = fc.period;
    if (summary.indices_end > summary.indices_start)
      j["indices"] = {{"file", summary.indices_file}, {"start_s", summary.indices_start}, {"end_s", summary.indices_end},
                      {"units", {{"tawss", "Pa"}, {"osi", "1"}, {"rrt", "1/Pa"}, {"twssg", "Pa/s"}}}};
    j["steps"] = summary.steps;
    j["saved"] = summary.saved;
    j["linear_iterations"] = summary.linear_iterations;
    j["setup_seconds"] = summary.setup_seconds;
    j["seconds"] = summary.seconds;
    j["seconds_per_step"] = summary.seconds_per_step;
    j["seconds_per_step_per_million_dofs"] = summary.per_million_dofs(summary.seconds_per_step);
    if (!fc.steady) {
      j["initial_state_seconds"] = summary.initial_seconds;
      j["first_step_seconds"] = summary.first_step_seconds;
      j["settled_steps"] = summary.settled_steps;
      j["settled_step_seconds"] = summary.settled_step_seconds;
      j["settled_seconds_per_step_per_million_dofs"] = summary.per_million_dofs(summary.settled_step_seconds);
    }
    j["solver"] = summary.solver;
    j["petsc_options"] = fc.petsc_options;
    io::write_text(output_dir + "/summary.json", j.dump(2) + "\n");
  };

  // A result file: whole on one process (NAME.vtu / NAME.vtp); under MPI each process writes its
  // piece (pieces/NAME_RANK.vtu) and, once all have, the first the .pvtu / .pvtp that joins them.
  // `write_piece(path)` writes this process's; `fields` describe its point data. Returns the name.
  if (pieces && writer) std::filesystem::create_directories(output_dir + "/pieces");
  const auto write_result = [&](const std::string& name, io::VtkFormat format, const std::vector<Field>& fields,
                                const std::function<void(const std::string&)>& write_piece) {
    const std::string ext = format == io::VtkFormat::vtu ? "vtu" : "vtp";
    if (!pieces) {
      write_piece(output_dir + "/" + name + "." + ext);
      return name + "." + ext;
    }
    write_piece(fmt::format("{}/pieces/{}_{}.{}", output_dir, name, rank, ext));
    parallel::any_process(false);  // every piece written
    if (writer) {
      std::vector<std::string> sources;
      for (int r = 0; r < ranks; ++r) sources.push_back(fmt::format("pieces/{}_{}.{}", name, r, ext));
      io::write_parallel_file(output_dir + "/" + name + ".p" + ext, format, sources, fields);
    }
    return name + ".p" + ext;
  };

  // Hemodynamic indices over the last period (the whole run without one), from every step, at
  // the wall points this process writes.
  post::WssIndexAccumulator indices;
  const double window_start = fc.period > 0.0 && fc.period < fc.end ? fc.end - fc.period : 0.0;
  const auto write_indices = [&]() {
    if (indices.samples() < 2) return;
    const post::WssIndices r = indices.result();
    const std::string file = write_result(
        "indices", io::VtkFormat::vtp,
        {Field::scalar("tawss", {}), Field::scalar("osi", {}), Field::scalar("rrt", {}), Field::scalar("twssg", {})},
        [&](const std::string& path) { post::write_indices(path, wall.mesh, r); });
    summary.indices_start = r.start;
    summary.indices_end = r.end;
    summary.indices_file = file;
    reporter.info(fmt::format("{}: tawss (Pa), osi, rrt (1/Pa), twssg (Pa/s) over t = {:g} to {:g} s, {} samples", file,
                              r.start, r.end, r.samples));
  };

  // `computed`: this step's wall shear stress when the indices already needed it; `with_fluid`:
  // the fluid volume too ([output] fluid_every), not only the wall.
  const auto save = [&](double time, const std::vector<Vec3>* computed, bool with_fluid) {
    const std::string name = fmt::format("{:06d}", summary.saved);
    if (with_fluid) {
      const std::vector<Field> fluid_fields{Field::vector("velocity", {}), Field::scalar("pressure", {})};
      const std::string fluid_file = write_result("fluid_" + name, io::VtkFormat::vtu, fluid_fields,
                                                  [&](const std::string& path) {
        if (!pieces) {
          // The volume's cells in the mesh's numbering, without the boundary faces (as the pieces
          // under MPI): handed to VTK without copies.
          io::write_vtu(path, mesh, {Field::vector("velocity", ns.velocity()), Field::scalar("pressure", ns.pressure())},
                        /*boundary=*/false);
          return;
        }
        const std::vector<Vec3>& u = ns.local_velocity();
        const std::vector<double> p = ns.local_pressure();
        std::vector<Vec3> velocity(fluid_local.size());
        std::vector<double> pressure(fluid_local.size());
        for (size_t k = 0; k < fluid_local.size(); ++k) {
          velocity[k] = u[fluid_local[k]];
          pressure[k] = p[fluid_local[k]];
        }
        io::write_vtu(path, fluid_piece, {Field::vector("velocity", velocity), Field::scalar("pressure", pressure)});
      });
      fluid_files.emplace_back(time, fluid_file);
    }
    const std::vector<Vec3> tau = computed ? *computed : wall_stress();
    std::vector<double> magnitude(tau.size());
    for (size_t i = 0; i < tau.size(); ++i) magnitude[i] = tau[i].norm();
    const std::string wall_file =
        write_result("wall_" + name, io::VtkFormat::vtp, {Field::vector("wss", {}), Field::scalar("wss_magnitude", {})},
                     [&](const std::string& path) {
                       io::write_vtp(path, wall.mesh, {Field::vector("wss", tau), Field::scalar("wss_magnitude", magnitude)});
                     });
    wall_files.emplace_back(time, wall_file);
    summary.saved += 1;
    if (!writer) return;
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
  const auto write_checkpoint_now = [&]() {
    // Each process's own points in a piece of its own, then (all written) the first writes the
    // checkpoint and removes the pieces of the one before.
    FlowState own = ns.own_state();
    write_checkpoint_piece(checkpoint_piece_path(checkpoint_path, own.steps, rank), own);
    auto gathered = gather_indices(indices.state(), wall.mesh_point);  // on the first once every piece is written
    if (!writer) return;
    Checkpoint c;
    c.fingerprint = fingerprint;
    c.flow.time = own.time;
    c.flow.steps = own.steps;
    c.flow.capacitor_pressure = own.capacitor_pressure;
    c.pieces = ranks;
    c.saved = summary.saved;
    c.linear_iterations = summary.linear_iterations;
    c.log = log;
    c.fluid_files = fluid_files;
    c.wall_files = wall_files;
    c.indices = std::move(gathered.first);
    c.index_points = std::move(gathered.second);
    write_checkpoint(checkpoint_path, c);
    // The pieces of the checkpoints before (CHECKPOINT.SSSSSS.K of another step SSSSSS).
    const std::string name = std::filesystem::path(checkpoint_path).filename().string() + ".";
    const std::string current = fmt::format("{}{:06d}.", name, c.flow.steps);
    for (const auto& entry : std::filesystem::directory_iterator(output_dir)) {
      const std::string file = entry.path().filename().string();
      const bool piece = file.starts_with(name) && file.size() > name.size() + 7 && file[name.size() + 6] == '.' &&
                         std::all_of(file.begin() + static_cast<std::ptrdiff_t>(name.size()), file.end(),
                                     [](char ch) { return std::isdigit(static_cast<unsigned char>(ch)) || ch == '.'; });
      if (piece && !file.starts_with(current)) std::filesystem::remove(entry.path());
    }
  };
  int first_step = 0;
  if (restart) {
    if (fc.steady) throw InputError(fmt::format("{}: --restart: a steady case has no time steps to go on from", fc.path));
    if (!std::filesystem::exists(checkpoint_path))
      throw InputError(fmt::format("{}: no checkpoint to restart from; run the case without --restart", checkpoint_path));
    Checkpoint c = read_checkpoint(checkpoint_path);
    if (c.pieces > 0) {  // each process keeps its own points' state as it reads the pieces
      std::vector<int> wanted = ns.local_points();
      std::sort(wanted.begin(), wanted.end());
      c.flow = read_checkpoint_pieces(checkpoint_path, c, wanted, mesh_points);
    }
    if (parallel::any_process(writer && c.fingerprint != fingerprint))
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
    indices.restore(indices_at(c.indices, c.index_points, wall.mesh_point, checkpoint_path));
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
      summary.steady_residual = r.residual;
      summary.steps = r.step;
      summary.linear_iterations = r.linear_iterations;
      log_step(r);
      summary.solver = ns.solver_description();
      save(0.0, nullptr, true);
    } else {
      const int steps = static_cast<int>(std::ceil(fc.end / fc.dt - 1e-9));
      reporter.info(fmt::format("{} steps of {:g} s to t = {:g} s, {} dofs", steps, fc.dt, fc.end, ns.dofs()));
      if (fc.stokes_start && !restart) {
        const StepReport r = ns.start_from_stokes();
        reporter.info(fmt::format("initial state: the Stokes flow at t = {:g} s ({} linear iterations, {:.3g} s)",
                                  r.time, r.linear_iterations, r.seconds));
        summary.initial_seconds = r.seconds;
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
        if (k == first_step) {
          summary.first_step_seconds = r.seconds;
        } else {
          summary.settled_step_seconds += (r.seconds - summary.settled_step_seconds) / (summary.settled_steps + 1);
          ++summary.settled_steps;
        }
        std::vector<Vec3> tau;
        const bool in_window = r.time >= window_start - 0.5 * fc.dt;
        if (in_window) {
          tau = wall_stress();
          indices.add(r.time, tau);
        }
        if (r.step % fc.save_every == 0 || k + 1 == steps)
          save(r.time, in_window ? &tau : nullptr,
               k + 1 == steps || (fc.fluid_every > 0 && r.step % fc.fluid_every == 0));
        // Every process stops at the same step (a signal may reach them apart).
        const bool stop = parallel::any_process(stop_signal != 0);
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
