#include "flow/simulate.h"

#include "flow/checkpoint.h"
#include "flow/navier_stokes.h"
#include "flow/result_pieces.h"
#include "flow/statistics.h"
#include "io/atomic_file.h"
#include "io/msh.h"
#include "io/process.h"
#include "io/volume_file.h"
#include "io/vtk_formats.h"
#include "mesh/error.h"
#include "parallel/processes.h"
#include "post/indices.h"
#include "post/wss.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <csignal>
#include <cstdlib>
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
  if (ext == ".msh" || ext == ".vtu") return io::read_volume(c.mesh);
  throw InputError(fmt::format("{}: mesh \"{}\": a volume mesh is read from .msh (Gmsh) or .vtu (with cell data "
                               "`tag`), as `vesselmesh volume` writes them",
                               c.path, c.mesh));
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

namespace {

// One run of simulate(), in the steps it takes (simulate() calls them in order): the mesh read and
// distributed, the partition described, the logs opened, a checkpoint restored, then the steady
// solve or the time steps, each saved, checkpointed and summarized. Under mpirun the first process
// reads the mesh and sends every process its part (the others never read it); each assembles its
// own rows, computes the wall shear stress of its part of the wall and writes its pieces of the
// results (pieces/, joined by .pvtu / .pvtp files the first writes). On one process the results
// are whole files, the mesh as read. Every member is called by every process alike.
class Run {
 public:
  Run(const FlowCase& input_case, const std::string& output_dir,
      const std::string& extra_petsc_options, const Reporter& all_reporter, bool restart)
      : start_(Clock::now()),
        output_dir_(output_dir),
        restart_(restart),
        ranks_(parallel::process_count()),
        rank_(parallel::process_rank()),
        writer_(rank_ == 0),
        pieces_(ranks_ > 1),
        reporter_(writer_ ? all_reporter : silent_reporter()),
        fc_(input_case),
        checkpoint_path_(output_dir + "/checkpoint.bin") {
    if (!extra_petsc_options.empty()) fc_.petsc_options += " " + extra_petsc_options;
    // The indices' window: the last period; without one, the time statistics' span (a transitional
    // flow's mean wall shear stress beside its mean flow), else the whole run.
    window_start_ = fc_.period > 0.0 && fc_.period < fc_.end ? fc_.end - fc_.period
                    : fc_.statistics_from >= 0.0          ? fc_.statistics_from
                                                          : 0.0;
  }

  void read_and_distribute();
  void describe_partition();
  void open_logs();
  void restore_checkpoint();
  // The steady solve or the time steps to the end (or to a stop signal), the summary written.
  SimulationSummary go();

 private:
  std::vector<Vec3> wall_stress() const;
  void gather_memory();
  void log_line(const std::string& line);
  void log_step(const StepReport& r);
  void write_logs() const;
  void write_series() const;
  void write_summary() const;
  std::string write_result(const std::string& name, io::VtkFormat format,
                           const std::vector<Field>& fields,
                           const std::function<void(const std::string&)>& write_piece) const;
  void write_indices();
  std::string write_fluid(const std::string& name, const std::vector<Field>& local) const;
  void write_statistics();
  void save(double time, const std::vector<Vec3>* computed, bool with_fluid);
  void write_checkpoint_now();
  void finish(const char* status);
  void run_steady();
  bool run_time_steps();  // false: stopped by a signal (the summary written)

  const Clock::time_point start_;
  Clock::time_point solve_start_;
  const std::string output_dir_;
  const bool restart_;
  const int ranks_, rank_;
  const bool writer_, pieces_;
  const Reporter& reporter_;
  FlowCase fc_;
  TetMesh mesh_;
  uint64_t fingerprint_ = 0;  // of the mesh and the time step, the first process's (checkpoints)
  int mesh_points_ = 0;
  // The results this process writes: the whole mesh on one process; under MPI its piece of the
  // fluid (its cells whose least point it owns) and of the wall (its wall triangles).
  WallPiece wall_;
  FluidPiece fluid_;
  std::unique_ptr<NavierStokes> ns_;
  std::string units_;
  SimulationSummary summary_;
  std::vector<std::pair<double, std::string>> fluid_files_, wall_files_;
  std::string log_, log_header_;
  std::vector<std::string> end_tags_;
  // ends/TAG.csv's texts, grown a row a step from log.csv's (end_logs of its header and the new
  // line: one formatting for both), made whole from the log at a restart.
  std::map<std::string, std::string> end_texts_;
  // Hemodynamic indices over the last period (without one the statistics' span, else the whole run), from
  // every step, at the wall points this process writes.
  post::WssIndexAccumulator indices_;
  double window_start_ = 0.0;
  FlowStatistics statistics_;  // [output] statistics_from: at this process's local points
  const std::string checkpoint_path_;  // the state to go on from, in the mesh's numbering
  int first_step_ = 0;
};

void Run::read_and_distribute() {
  std::vector<std::string> wall_names;
  for (const BoundaryCondition& b : fc_.boundaries)
    if (b.type == BoundaryType::wall) wall_names.push_back(b.tag);
  std::exception_ptr unread;
  if (writer_) {
    try {
      mesh_ = read_mesh(fc_);
      reporter_.info(fmt::format(
          "mesh {}: {} points, {} tetrahedra, {} prisms, {} boundary triangles", fc_.mesh,
          mesh_.num_points(), mesh_.num_tets(), mesh_.num_prisms(), mesh_.boundary.size()));
      fingerprint_ = run_fingerprint(mesh_, fc_.dt);
    } catch (...) {
      unread = std::current_exception();
    }
  }
  MeshPart part = distribute_mesh(writer_ ? &mesh_ : nullptr, fc_.mesh, unread,
                                  pieces_ ? wall_names : std::vector<std::string>{});
  if (pieces_) mesh_ = TetMesh{};  // the parts hold it now
  // The first process's peak: the whole mesh read and split.
  summary_.distribution_memory_mb = io::peak_memory_mb();
  if (pieces_)
    reporter_.info(fmt::format(
        "mesh read and split by the first process (peak memory {:.0f} MB), a part sent to "
        "each of the {} others",
        summary_.distribution_memory_mb, ranks_ - 1));
  reporter_.info(
      fmt::format("units: mesh in {}, scaled by {:g} to metres; velocity m/s, pressure Pa, wss Pa",
                  fc_.length_unit, fc_.length_scale));
  summary_.tetrahedra = part.mesh_tetrahedra;
  summary_.points = mesh_points_ = part.total_points;
  std::vector<int> wall_tags;
  for (const auto& [tag, name] : part.tag_names)
    if (std::find(wall_names.begin(), wall_names.end(), name) != wall_names.end())
      wall_tags.push_back(tag);
  if (pieces_) {
    wall_ = distributed_wall(part, wall_tags, fc_);
    fluid_ = own_fluid_piece(part);
  } else {
    wall_ = whole_wall(mesh_, wall_tags, fc_);
  }
  ns_ = std::make_unique<NavierStokes>(std::move(part), fc_, reporter_);
  const int wall_points =
      pieces_ ? static_cast<int>(parallel::sum_all({static_cast<double>(wall_.owned_points)})[0])
              : wall_.mesh.num_points();
  const int fallbacks =
      pieces_ ? static_cast<int>(parallel::sum_all({static_cast<double>(wall_.owned_fallbacks)})[0])
              : wall_.shear->face_fallbacks();
  reporter_.info(fmt::format(
      "wall shear stress: {} method on {} wall points{}", fc_.wss_method, wall_points,
      fallbacks > 0
          ? fmt::format(" ({} by their faces: too few neighbours for a quadratic)", fallbacks)
          : ""));
}

// The wall shear stress at the wall points this process writes (Pa).
std::vector<Vec3> Run::wall_stress() const {
  return wall_.stress(pieces_ ? ns_->local_velocity() : ns_->gathered_velocity(), fc_.viscosity);
}

void Run::describe_partition() {
  if (writer_) std::filesystem::create_directories(output_dir_ + (pieces_ ? "/pieces" : ""));
  const PartitionReport partition = ns_->partition();
  reporter_.info(fmt::format("assembly: {} thread{} a process", partition.threads,
                             partition.threads > 1 ? "s" : ""));
  if (ranks_ > 1) {
    const auto [least, most] =
        std::minmax_element(partition.owned_points.begin(), partition.owned_points.end());
    const auto [least_ghosts, most_ghosts] =
        std::minmax_element(partition.ghost_points.begin(), partition.ghost_points.end());
    const double mean = static_cast<double>(mesh_points_) / ranks_;
    reporter_.info(fmt::format(
        "{} MPI processes (points split by PT-Scotch): {} to {} unknowns each (largest / mean "
        "{:.3f}), {} to {} ghost points, up to {} neighbours",
        ranks_, 4 * *least, 4 * *most, *most / mean, *least_ghosts, *most_ghosts,
        *std::max_element(partition.neighbours.begin(), partition.neighbours.end())));
  }
  units_ = fmt::format("points in {} (x {:g} m), velocity m/s, pressure Pa, wss Pa, time s",
                       fc_.length_unit, fc_.length_scale);
  summary_.dofs = ns_->dofs();
  summary_.ranks = ranks_;
  summary_.partition = partition;
  summary_.length_scale = fc_.length_scale;
  summary_.setup_seconds = std::chrono::duration<double>(Clock::now() - start_).count();
}

// Every process's peak resident memory (MB), gathered (every process calls it).
void Run::gather_memory() {
  summary_.peak_memory_mb = parallel::gather_all(io::peak_memory_mb());
  summary_.library_memory_mb = parallel::gather_all(io::file_memory_mb());
  summary_.own_memory_mb.resize(summary_.peak_memory_mb.size());
  for (size_t r = 0; r < summary_.own_memory_mb.size(); ++r)
    summary_.own_memory_mb[r] = summary_.peak_memory_mb[r] - summary_.library_memory_mb[r];
}

void Run::open_logs() {
  log_ = "step,time_s";
  for (const BoundaryCondition& b : fc_.boundaries) {
    log_ += fmt::format(",{0}_flux_m3_s,{0}_mean_pressure_Pa", b.tag);
    if (b.type == BoundaryType::rcr) log_ += fmt::format(",{}_capacitor_pressure_Pa", b.tag);
  }
  log_ += ",preconditioners_built,linear_iterations,max_cfl,assembly_seconds,solve_seconds,seconds\n";
  log_header_ = log_;
  for (const BoundaryCondition& b : fc_.boundaries)
    if (b.type != BoundaryType::wall) end_tags_.push_back(b.tag);
  end_texts_ = end_logs(log_header_, end_tags_);
}

void Run::log_line(const std::string& line) {
  log_ += line;
  for (const auto& [tag, text] : end_logs(log_header_ + line, end_tags_))
    end_texts_[tag] += text.substr(text.find('\n') + 1);
}

// log.csv and ends/TAG.csv (the writing process only).
void Run::write_logs() const {
  if (!writer_) return;
  io::write_text(output_dir_ + "/log.csv", log_);
  std::filesystem::create_directories(output_dir_ + "/ends");
  for (const auto& [tag, text] : end_texts_)
    io::write_text(output_dir_ + "/ends/" + tag + ".csv", text);
}

void Run::write_summary() const {
  if (!writer_) return;
  nlohmann::ordered_json j;
  j["status"] = summary_.status;
  if (summary_.signal != 0) j["signal"] = summary_.signal;
  j["case"] = fc_.path;
  j["mesh"] = fc_.mesh;
  j["units"] = {{"points", fc_.length_unit},
                {"length_scale_m", fc_.length_scale},
                {"velocity", "m/s"},
                {"pressure", "Pa"},
                {"wss", "Pa"},
                {"time", "s"},
                {"flux", "m3/s"}};
  j["points"] = summary_.points;
  j["tetrahedra"] = summary_.tetrahedra;
  j["dofs"] = summary_.dofs;
  j["ranks"] = ranks_;
  nlohmann::ordered_json parts;
  parts["owned_unknowns"] = nlohmann::ordered_json::array();
  for (int points : summary_.partition.owned_points) parts["owned_unknowns"].push_back(4 * points);
  parts["ghost_points"] = summary_.partition.ghost_points;
  parts["neighbours"] = summary_.partition.neighbours;
  j["partition"] = parts;
  j["assembly_threads"] = summary_.partition.threads;
  if (!summary_.peak_memory_mb.empty()) {
    j["peak_memory_mb"] = summary_.peak_memory_mb;
    j["library_memory_mb"] = summary_.library_memory_mb;
    j["peak_own_memory_mb"] = summary_.own_memory_mb;
  }
  j["distribution_peak_memory_mb"] = summary_.distribution_memory_mb;
  if (!summary_.ends.empty()) {
    nlohmann::ordered_json ends = nlohmann::ordered_json::array();
    for (size_t k = 0; k < summary_.ends.size(); ++k) {
      const BoundaryFlow& f = summary_.ends[k];
      nlohmann::ordered_json e = {{"tag", f.tag},
                                  {"type", to_string(fc_.boundaries[k].type)},
                                  {"flux_m3_s", f.flux},
                                  {"mean_pressure_Pa", f.mean_pressure}};
      if (fc_.boundaries[k].type == BoundaryType::rcr)
        e["capacitor_pressure_Pa"] = f.capacitor_pressure;
      ends.push_back(e);
    }
    j["ends"] = ends;  // at the last step
  }
  j["steady"] = fc_.steady;
  if (fc_.steady && summary_.steady_residual >= 0.0)
    j["steady_residual"] = summary_.steady_residual;
  if (fc_.steady) {
    j["steady_method"] = fc_.steady_method;
    j["steady_history"] = history_json(ns_->steady_history());
  }
  j["fluid"] = {{"density_kg_m3", fc_.density}, {"viscosity_Pa_s", fc_.viscosity}};
  j["wss_method"] = fc_.wss_method;
  if (!fc_.steady) j["initial"] = fc_.stokes_start ? "stokes" : "rest";
  if (fc_.period > 0.0) j["period"] = fc_.period;
  if (summary_.indices_end > summary_.indices_start)
    j["indices"] = {{"file", summary_.indices_file},
                    {"start_s", summary_.indices_start},
                    {"end_s", summary_.indices_end},
                    {"units", {{"tawss", "Pa"}, {"osi", "1"}, {"rrt", "1/Pa"}, {"twssg", "Pa/s"}, {"mean_wss", "Pa"}}}};
  if (summary_.statistics_steps > 0)
    j["statistics"] = {{"file", summary_.statistics_file},
                       {"start_s", summary_.statistics_start},
                       {"end_s", summary_.statistics_end},
                       {"steps", summary_.statistics_steps},
                       {"units", {{"mean_velocity", "m/s"}, {"rms_velocity", "m/s"}, {"mean_pressure", "Pa"}}}};
  j["steps"] = summary_.steps;
  j["saved"] = summary_.saved;
  j["linear_iterations"] = summary_.linear_iterations;
  j["setup_seconds"] = summary_.setup_seconds;
  j["seconds"] = summary_.seconds;
  j["seconds_per_step"] = summary_.seconds_per_step;
  j["seconds_per_step_per_million_dofs"] = summary_.per_million_dofs(summary_.seconds_per_step);
  if (!fc_.steady) {
    j["initial_state_seconds"] = summary_.initial_seconds;
    j["first_step_seconds"] = summary_.first_step_seconds;
    j["settled_steps"] = summary_.settled_steps;
    j["settled_step_seconds"] = summary_.settled_step_seconds;
    j["settled_seconds_per_step_per_million_dofs"] =
        summary_.per_million_dofs(summary_.settled_step_seconds);
    if (fc_.cfl_target > 0.0)
      j["time_steps"] = {{"cfl_target", fc_.cfl_target},
                         {"least_s", summary_.least_time_step},
                         {"largest_s", summary_.largest_time_step},
                         {"simulated_s", summary_.simulated_seconds}};
  }
  j["solver"] = summary_.solver;
  j["petsc_options"] = fc_.petsc_options;
  io::write_text(output_dir_ + "/summary.json", j.dump(2) + "\n");
}

// A result file: whole on one process (NAME.vtu / NAME.vtp); under MPI each process writes its
// piece (pieces/NAME_RANK.vtu) and, once all have, the first the .pvtu / .pvtp that joins them.
// `write_piece(path)` writes this process's; `fields` describe its point data. Returns the name.
std::string Run::write_result(const std::string& name, io::VtkFormat format,
                              const std::vector<Field>& fields,
                              const std::function<void(const std::string&)>& write_piece) const {
  const std::string ext = format == io::VtkFormat::vtu ? "vtu" : "vtp";
  if (!pieces_) {
    write_piece(output_dir_ + "/" + name + "." + ext);
    return name + "." + ext;
  }
  write_piece(fmt::format("{}/pieces/{}_{}.{}", output_dir_, name, rank_, ext));
  parallel::any_process(false);  // every piece written
  if (writer_) {
    std::vector<std::string> sources;
    for (int r = 0; r < ranks_; ++r)
      sources.push_back(fmt::format("pieces/{}_{}.{}", name, r, ext));
    io::write_parallel_file(output_dir_ + "/" + name + ".p" + ext, format, sources, fields);
  }
  return name + ".p" + ext;
}

void Run::write_indices() {
  if (indices_.samples() < 2) return;
  const post::WssIndices r = indices_.result();
  const std::string file =
      write_result("indices", io::VtkFormat::vtp,
                   {Field::scalar("tawss", {}), Field::scalar("osi", {}), Field::scalar("rrt", {}),
                    Field::scalar("twssg", {}), Field::vector("mean_wss", {})},
                   [&](const std::string& path) { post::write_indices(path, wall_.mesh, r); });
  summary_.indices_start = r.start;
  summary_.indices_end = r.end;
  summary_.indices_file = file;
  reporter_.info(fmt::format(
      "{}: tawss (Pa), osi, rrt (1/Pa), twssg (Pa/s), mean_wss (Pa) over t = {:g} to {:g} s, {} samples", file,
      r.start, r.end, r.samples));
}

// A fluid file of fields given per local point (this process's part's numbering): on one process
// NAME.vtu of every mesh point, under MPI this process's piece and NAME.pvtu.
std::string Run::write_fluid(const std::string& name, const std::vector<Field>& local) const {
  std::vector<Field> described;
  for (const Field& f : local) described.push_back(Field{f.name, f.components, {}});
  return write_result(name, io::VtkFormat::vtu, described, [&](const std::string& path) {
    std::vector<int> pick = fluid_.local;  // per point written, its local point
    if (!pieces_) {  // every mesh point, by its number
      pick.assign(static_cast<size_t>(mesh_.num_points()), -1);
      const std::vector<int>& at = ns_->local_points();
      for (size_t k = 0; k < at.size(); ++k) pick[static_cast<size_t>(at[k])] = static_cast<int>(k);
    }
    std::vector<Field> picked;
    for (const Field& f : local) {
      const auto c = static_cast<size_t>(f.components);
      Field& g = picked.emplace_back(Field{f.name, f.components, std::vector<double>(pick.size() * c, 0.0)});
      for (size_t k = 0; k < pick.size(); ++k)
        if (pick[k] >= 0) std::copy_n(f.values.begin() + static_cast<std::ptrdiff_t>(pick[k] * c), c, &g.values[k * c]);
    }
    io::write_vtu(path, pieces_ ? fluid_.mesh : mesh_, picked, /*boundary=*/false);
  });
}

// statistics.vtu (.pvtu) at the run's end, when the case asks for it.
void Run::write_statistics() {
  if (fc_.statistics_from < 0.0) return;
  if (statistics_.steps() == 0) {
    reporter_.warning(fmt::format("no time step after output.statistics_from = {:g} s (the run ends at {:g} s): no "
                                  "statistics written", fc_.statistics_from, ns_->time()));
    return;
  }
  const FlowStatistics::State& s = statistics_.state();
  summary_.statistics_file = write_fluid("statistics", statistics_.fields());
  summary_.statistics_start = s.start;
  summary_.statistics_end = s.end;
  summary_.statistics_steps = s.steps;
  reporter_.info(fmt::format("{}: mean_velocity, rms_velocity (m/s), mean_pressure (Pa) over t = {:g} to {:g} s, "
                             "{} steps", summary_.statistics_file, s.start, s.end, s.steps));
}

// `computed`: this step's wall shear stress when the indices already needed it; `with_fluid`:
// the fluid volume too ([output] fluid_every), not only the wall.
void Run::save(double time, const std::vector<Vec3>* computed, bool with_fluid) {
  const std::string name = fmt::format("{:06d}", summary_.saved);
  if (with_fluid)
    fluid_files_.emplace_back(time, write_fluid("fluid_" + name, {Field::vector("velocity", ns_->local_velocity()),
                                                                  Field::scalar("pressure", ns_->local_pressure())}));
  const std::vector<Vec3> tau = computed ? *computed : wall_stress();
  std::vector<double> magnitude(tau.size());
  for (size_t i = 0; i < tau.size(); ++i) magnitude[i] = tau[i].norm();
  const std::string wall_file = write_result(
      "wall_" + name, io::VtkFormat::vtp,
      {Field::vector("wss", {}), Field::scalar("wss_magnitude", {})}, [&](const std::string& path) {
        io::write_vtp(path, wall_.mesh,
                      {Field::vector("wss", tau), Field::scalar("wss_magnitude", magnitude)});
      });
  wall_files_.emplace_back(time, wall_file);
  summary_.saved += 1;
  write_series();
}

// fluid.pvd, wall.pvd and the logs as they stand (the writing process only).
void Run::write_series() const {
  if (!writer_) return;
  io::write_text(output_dir_ + "/fluid.pvd", pvd(fluid_files_, units_));
  io::write_text(output_dir_ + "/wall.pvd", pvd(wall_files_, units_));
  write_logs();
}

void Run::log_step(const StepReport& r) {
  std::string line = fmt::format("{},{:.9g}", r.step, r.time);
  const std::vector<BoundaryFlow> flows = ns_->boundary_flows();
  for (size_t k = 0; k < flows.size(); ++k) {
    line += fmt::format(",{:.9g},{:.9g}", flows[k].flux, flows[k].mean_pressure);
    if (fc_.boundaries[k].type == BoundaryType::rcr)
      line += fmt::format(",{:.9g}", flows[k].capacitor_pressure);
  }
  line += fmt::format(",{},{},{:.4g},{:.4g},{:.4g},{:.4g}\n", r.preconditioners_built, r.linear_iterations, r.max_cfl,
                      r.assembly_seconds, r.solve_seconds, r.seconds);
  log_line(line);
}

// Each process's own points in a piece of its own, then (all written) the first writes the
// checkpoint and removes the pieces of the one before.
void Run::write_checkpoint_now() {
  FlowState own = ns_->own_state();
  FlowStatistics::State kept = statistics_.state();  // its own points' (the first local ones)
  for (auto* field : {&kept.mean_velocity, &kept.squares}) field->resize(std::min(field->size(), own.points.size()));
  kept.mean_pressure.resize(std::min(kept.mean_pressure.size(), own.points.size()));
  write_checkpoint_piece(checkpoint_piece_path(checkpoint_path_, own.steps, rank_), own, kept);
  // The indices, on the first once every piece is written.
  auto gathered = gather_indices(indices_.state(), wall_.mesh_point);
  if (!writer_) return;
  Checkpoint c;
  c.fingerprint = fingerprint_;
  c.flow.time = own.time;
  c.flow.steps = own.steps;
  c.flow.time_step = own.time_step;
  c.flow.last_time_step = own.last_time_step;
  c.flow.capacitor_pressure = own.capacitor_pressure;
  c.pieces = ranks_;
  c.saved = summary_.saved;
  c.linear_iterations = summary_.linear_iterations;
  c.log = log_;
  c.fluid_files = fluid_files_;
  c.wall_files = wall_files_;
  c.indices = std::move(gathered.first);
  c.index_points = std::move(gathered.second);
  c.statistics.start = kept.start;
  c.statistics.end = kept.end;
  c.statistics.weight = kept.weight;
  c.statistics.steps = kept.steps;
  write_checkpoint(checkpoint_path_, c);
  // The pieces of the checkpoints before (CHECKPOINT.SSSSSS.K of another step SSSSSS).
  const std::string name = std::filesystem::path(checkpoint_path_).filename().string() + ".";
  const std::string current = fmt::format("{}{:06d}.", name, c.flow.steps);
  for (const auto& entry : std::filesystem::directory_iterator(output_dir_)) {
    const std::string file = entry.path().filename().string();
    const bool piece =
        file.starts_with(name) && file.size() > name.size() + 7 && file[name.size() + 6] == '.' &&
        std::all_of(
            file.begin() + static_cast<std::ptrdiff_t>(name.size()), file.end(),
            [](char ch) { return std::isdigit(static_cast<unsigned char>(ch)) || ch == '.'; });
    if (piece && !file.starts_with(current)) std::filesystem::remove(entry.path());
  }
}

void Run::restore_checkpoint() {
  if (fc_.steady)
    throw InputError(
        fmt::format("{}: --restart: a steady case has no time steps to go on from", fc_.path));
  if (!std::filesystem::exists(checkpoint_path_))
    throw InputError(fmt::format(
        "{}: no checkpoint to restart from; run the case without --restart", checkpoint_path_));
  Checkpoint c = read_checkpoint(checkpoint_path_);
  FlowStatistics::State statistics;
  if (c.pieces > 0) {  // each process keeps its own points' state as it reads the pieces
    std::vector<int> wanted = ns_->local_points();
    std::sort(wanted.begin(), wanted.end());
    c.flow = read_checkpoint_pieces(checkpoint_path_, c, wanted, mesh_points_, &statistics);
  }
  if (fc_.statistics_from >= 0.0 && statistics.steps > 0) {
    statistics_ = FlowStatistics(statistics_at(statistics, ns_->local_points(), checkpoint_path_));
  } else if (fc_.statistics_from >= 0.0 && fc_.statistics_from < c.flow.time) {
    reporter_.warning(fmt::format("{}: the run that wrote it kept no time statistics: they will cover t = {:g} s to "
                                  "the end, not from output.statistics_from = {:g} s (for that, run the case again "
                                  "without --restart)", checkpoint_path_, c.flow.time, fc_.statistics_from));
  }
  if (parallel::any_process(writer_ && c.fingerprint != fingerprint_))
    throw InputError(fmt::format("{}: the checkpoint is of another mesh or time step than {}'s; run the case without "
                                 "--restart (or into another folder)", checkpoint_path_, fc_.path));
  ns_->restore(c.flow);
  first_step_ = c.flow.steps;
  summary_.steps = c.flow.steps;
  summary_.saved = c.saved;
  summary_.linear_iterations = c.linear_iterations;
  log_ = c.log;
  end_texts_ = end_logs(log_, end_tags_);
  fluid_files_ = c.fluid_files;
  wall_files_ = c.wall_files;
  // A run extended (its case's end later): its indices over the new last period where they can be.
  const post::WssIndexAccumulator::State sums =
      indices_at(c.indices, c.index_points, wall_.mesh_point, checkpoint_path_);
  const auto moved =
      post::window_sums(sums, window_start_, c.flow.time, c.flow.time_step > 0.0 ? c.flow.time_step : fc_.dt);
  if (!moved)
    reporter_.warning(fmt::format(
        "{}: the hemodynamic indices will cover t = {:g} to {:g} s, not their window ({:g} to {:g} s: the last period "
        "or the statistics' span): the run that wrote the checkpoint began them at {:g} s, and its samples from {:g} "
        "to {:g} s are not kept apart; for that window, run the case again without --restart",
        checkpoint_path_, sums.start, fc_.end, window_start_, fc_.end, sums.start, window_start_, c.flow.time));
  indices_.restore(moved ? *moved : sums);
  write_series();  // the folder as it was at the checkpoint (later saves are written again)
  reporter_.info(fmt::format("restart from {}: step {}, t = {:g} s", checkpoint_path_, c.flow.steps, c.flow.time));
}

// The run's end (completed or stopped): its times, every process's memory, the summary.
void Run::finish(const char* status) {
  summary_.status = status;
  summary_.seconds = std::chrono::duration<double>(Clock::now() - start_).count();
  const double solving = std::chrono::duration<double>(Clock::now() - solve_start_).count();
  summary_.seconds_per_step =
      summary_.steps > first_step_ ? solving / (summary_.steps - first_step_) : 0.0;
  gather_memory();
  summary_.ends = ns_->boundary_flows();  // every process takes part
  write_summary();
}

void Run::run_steady() {
  const StepReport r = ns_->solve_steady();
  summary_.steady_residual = r.residual;
  summary_.steps = r.step;
  summary_.linear_iterations = r.linear_iterations;
  log_step(r);
  summary_.solver = ns_->solver_description();
  save(0.0, nullptr, true);
}

bool Run::run_time_steps() {
  // Steps of the case's dt, or (cfl_target) of lengths chosen as the flow goes, the last landing
  // on the end.
  const bool chosen = fc_.cfl_target > 0.0;
  const int steps = static_cast<int>(std::ceil(fc_.end / fc_.dt - 1e-9));
  const double end_tolerance = 1e-9 * fc_.dt;
  if (chosen)
    reporter_.info(fmt::format("steps for a largest CFL number of about {:g} (the first {:g} s) to t = {:g} s, {} dofs",
                               fc_.cfl_target, ns_->time_step(), fc_.end, ns_->dofs()));
  else
    reporter_.info(fmt::format("{} steps of {:g} s to t = {:g} s, {} dofs", steps, fc_.dt, fc_.end, ns_->dofs()));
  if (fc_.stokes_start && !restart_) {
    const StepReport r = ns_->start_from_stokes();
    reporter_.info(
        fmt::format("initial state: the Stokes flow at t = {:g} s ({} linear iterations, {:.3g} s)",
                    r.time, r.linear_iterations, r.seconds));
    summary_.initial_seconds = r.seconds;
  }
  const double start_time = ns_->time();
  if (chosen ? start_time >= fc_.end - end_tolerance : first_step_ >= steps)
    reporter_.warning(fmt::format(
        "the checkpoint is at step {} (t = {:g} s), the case ends at t = {:g} s: nothing to do (a later "
        "[time] end extends the run)",
        first_step_, start_time, fc_.end));
  const StopSignals signals;
  for (int k = first_step_; chosen ? ns_->time() < fc_.end - end_tolerance : k < steps; ++k) {
    if (chosen) ns_->set_time_step(landing_time_step(ns_->time_step(), ns_->time(), fc_.end));
    const StepReport r = ns_->step();
    const bool last = chosen ? r.time >= fc_.end - end_tolerance : k + 1 == steps;
    if (chosen) ns_->set_time_step(next_time_step(r.time_step, r.max_cfl, fc_.cfl_target));
    summary_.steps = r.step;
    summary_.linear_iterations += r.linear_iterations;
    summary_.least_time_step =
        k == first_step_ ? r.time_step : std::min(summary_.least_time_step, r.time_step);
    summary_.largest_time_step = std::max(summary_.largest_time_step, r.time_step);
    summary_.simulated_seconds = r.time - start_time;
    log_step(r);
    if (k == 0) summary_.solver = ns_->solver_description();
    if (k == first_step_) {
      summary_.first_step_seconds = r.seconds;
    } else {
      summary_.settled_step_seconds +=
          (r.seconds - summary_.settled_step_seconds) / (summary_.settled_steps + 1);
      ++summary_.settled_steps;
    }
    std::vector<Vec3> tau;
    const bool in_window = r.time >= window_start_ - 0.5 * r.time_step;
    if (in_window) {
      tau = wall_stress();
      indices_.add(r.time, tau);
    }
    if (fc_.statistics_from >= 0.0 && r.time - 0.5 * r.time_step >= fc_.statistics_from)
      statistics_.add(r.time, r.time_step, ns_->local_velocity(), ns_->local_pressure());
    if (r.step % fc_.save_every == 0 || last)
      save(r.time, in_window ? &tau : nullptr,
           last || (fc_.fluid_every > 0 && r.step % fc_.fluid_every == 0));
    // Every process stops at the same step (a signal may reach them apart).
    const bool stop = parallel::any_process(stop_signal != 0);
    if (stop || last || (fc_.checkpoint_every > 0 && r.step % fc_.checkpoint_every == 0))
      write_checkpoint_now();
    if (stop) {
      summary_.signal = stop_signal != 0 ? static_cast<int>(stop_signal) : SIGTERM;
      write_logs();
      finish("stopped");
      reporter_.warning(fmt::format(
          "stopped by signal {} after step {} (t = {:g} s); the checkpoint {} holds it: "
          "'vesselmesh simulate {} -o {} --restart' goes on",
          summary_.signal, r.step, r.time, checkpoint_path_, fc_.path, output_dir_));
      return false;
    }
    reporter_.progress("time steps", chosen ? (r.time - start_time) / (fc_.end - start_time) : double(k + 1) / steps);
  }
  return true;
}

SimulationSummary Run::go() {
  solve_start_ = Clock::now();
  try {
    if (fc_.steady)
      run_steady();
    else if (!run_time_steps())
      return summary_;
  } catch (const ComputationError&) {
    summary_.status = "diverged";
    summary_.seconds = std::chrono::duration<double>(Clock::now() - start_).count();
    write_logs();
    write_summary();
    throw;
  }
  write_indices();
  write_statistics();
  finish("completed");
  return summary_;
}

}  // namespace

SimulationSummary simulate(const FlowCase& input_case, const std::string& output_dir,
                           const std::string& extra_petsc_options, const Reporter& all_reporter,
                           bool restart) {
  Run run(input_case, output_dir, extra_petsc_options, all_reporter, restart);
  run.read_and_distribute();  // the first process reads; every process gets its part
  run.describe_partition();
  run.open_logs();
  if (restart) run.restore_checkpoint();
  return run.go();
}

}  // namespace vesselmesh::flow
