#include "study/study.h"

#include "analysis/curvature.h"
#include "analysis/open_ends.h"
#include "centerline/distance_map.h"
#include "centerline/extract.h"
#include "flow/case.h"
#include "flow/simulate.h"
#include "io/atomic_file.h"
#include "io/msh.h"
#include "io/process.h"
#include "io/surface.h"
#include "io/toml_reader.h"
#include "io/units.h"
#include "io/volume_file.h"
#include "io/vtk_formats.h"
#include "mesh/clean.h"
#include "mesh/error.h"
#include "mesh/locator.h"
#include "post/fluid_metric.h"
#include "post/wall_metric.h"
#include "post/wall_series.h"
#include "remesh/adapt.h"
#include "remesh/extend.h"
#include "sizing/metric.h"
#include "study/adaptation.h"
#include "study/envelope.h"
#include "study/study_report.h"
#include "study/wall_difference.h"
#include "volume/fill.h"
#include "volume/quality.h"
#include "volume/volume_mesh.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <limits>

#ifndef VESSELMESH_VERSION
#define VESSELMESH_VERSION "0.0.0"
#endif

namespace vesselmesh::study {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using Json = nlohmann::ordered_json;

double since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

// The flow of one mesh on config.ranks processes: `mpirun -np N PROGRAM simulate CASE --mesh MESH -o DIR
// -q [--restart]` (its messages on ours), what it did read back from DIR/summary.json. OpenMPI runs
// as root when told so (its environment); a failed run is an error naming the command.
flow::SimulationSummary simulate_under_mpirun(const StudyConfig& config, const std::string& mesh,
                                              const std::string& dir, bool restart, int time_step_divisor = 1,
                                              double end = 0.0) {
  if (config.program.empty()) throw InternalError("study: ranks > 1 without the program to run under mpirun");
  std::vector<std::string> command = {"mpirun", "-np",   std::to_string(config.ranks), config.program, "simulate",
                                      config.flow_case, "--mesh", mesh, "-o", dir, "-q"};
  if (restart) command.push_back("--restart");
  if (time_step_divisor > 1) {
    command.push_back("--time-step-divisor");
    command.push_back(std::to_string(time_step_divisor));
  }
  if (end > 0.0) {
    command.push_back("--end");
    command.push_back(fmt::format("{:.17g}", end));
  }
  // Without the variables of this process's own MPI (a singleton once PETSc started here), which
  // would make mpirun take its processes for this one's.
  const int code = io::run_process(command, {"OMPI_ALLOW_RUN_AS_ROOT=1", "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1"},
                                   {"OMPI_", "PMIX_", "OPAL_", "PRTE_", "ORTE_"});
  std::string line;
  for (const std::string& word : command) line += (line.empty() ? "" : " ") + word;
  flow::SimulationSummary s;
  if (code == 0 || code > 128) {
    const std::string summary = dir + "/summary.json";
    if (fs::exists(summary)) {
      const Json j = Json::parse(io::read_file(summary));
      s.status = j.value("status", "");
      s.signal = j.value("signal", 0);
      s.dofs = j.value("dofs", 0);
      s.ranks = j.value("ranks", 0);
      s.steps = j.value("steps", 0);
      if (s.status == "completed" || s.status == "stopped") return s;
    }
  }
  const std::string what = fmt::format("study: the flow under mpirun ({}) ended with exit code {}", line, code);
  if (code == 2) throw InputError(what + ": its message is above");
  throw ComputationError(what + ": see its messages above");
}

// FNV-1a, 64 bits: the stamps' fingerprints (not a security measure).
std::string fingerprint(const std::string& text) {
  uint64_t h = 1469598103934665603ull;
  for (unsigned char c : text) {
    h ^= c;
    h *= 1099511628211ull;
  }
  return fmt::format("{:016x}", h);
}

// What a stamp says was made, or nothing when the stamp is missing or was made otherwise.
std::optional<Json> matching_stamp(const std::string& path, const std::string& key) {
  if (!fs::exists(path)) return std::nullopt;
  try {
    Json j = Json::parse(io::read_file(path));
    if (j.value("key", "") == key) return j;
  } catch (const std::exception&) {
  }
  return std::nullopt;
}

// The places the study measures, on the input: each ring (36 positions round it at most), then each
// point (its closest point on the wall); per position the inward normal and the local radius of
// the input's nearest corner.
std::vector<Place> measured_places(const TriMesh& surface, const std::vector<double>& radius,
                                   const std::vector<post::RingSpec>& rings, const std::vector<post::PointSpec>& points) {
  std::vector<Vec3> normal(surface.points.size(), Vec3::Zero());
  for (const Triangle& f : surface.triangles) {
    const Vec3 a = (surface.points[f[1]] - surface.points[f[0]]).cross(surface.points[f[2]] - surface.points[f[0]]);
    for (int v : f) normal[v] += a;
  }
  const mesh::SurfaceLocator locator(surface);
  const auto add = [&](Place& place, const Vec3& x) {
    const mesh::SurfaceLocator::Hit hit = locator.closest(x);
    int nearest = surface.triangles[hit.triangle][0];
    for (int v : surface.triangles[hit.triangle])
      if ((surface.points[v] - hit.point).norm() < (surface.points[nearest] - hit.point).norm()) nearest = v;
    place.positions.push_back(hit.point);
    place.inward.push_back(-normal[nearest].normalized());
    place.radius.push_back(radius[nearest]);
  };
  std::vector<Place> places;
  const std::vector<Vec3> zero(surface.points.size(), Vec3::Zero());
  for (const post::RingSpec& spec : rings) {
    const post::Ring ring = post::cut_ring(surface, zero, spec);
    Place place{"ring " + spec.name, {}, {}, {}};
    const size_t step = std::max<size_t>(1, ring.samples.size() / 36);
    for (size_t k = 0; k < ring.samples.size(); k += step) add(place, ring.samples[k].point);
    places.push_back(place);
  }
  for (const post::PointSpec& p : points) {
    Place place{"point " + p.name, {}, {}, {}};
    add(place, p.point);
    places.push_back(place);
  }
  return places;
}

// The hemodynamic indices a flow wrote (over its last period; flow/simulate.h), if any.
struct WallIndices {
  TriMesh mesh;
  std::vector<double> tawss, osi;
};
std::optional<WallIndices> read_wall_indices(const std::string& flow_dir) {
  const std::string summary = flow_dir + "/summary.json";
  if (!fs::exists(summary)) return std::nullopt;
  const Json j = Json::parse(io::read_file(summary));
  if (!j.contains("indices") || !j["indices"].contains("file")) return std::nullopt;
  const std::string file = flow_dir + "/" + j["indices"]["file"].get<std::string>();
  if (!fs::exists(file)) return std::nullopt;
  io::SurfaceData data = io::read_vtk_surface(file, io::VtkFormat::vtp);
  WallIndices w;
  w.mesh = std::move(data.mesh);
  for (const Field& f : data.point_data) {
    if (f.name == "tawss") w.tawss = f.values;
    if (f.name == "osi") w.osi = f.values;
  }
  if (w.tawss.size() != w.mesh.points.size() || w.osi.size() != w.mesh.points.size()) return std::nullopt;
  return w;
}

// Each mesh's WSS (and its TAWSS and OSI, where its flow wrote them) on the reference's wall, their
// whole-wall differences from the reference's (study/wall_difference.h); the half-step run's fields too.
void measure_whole_wall(StudyResult& result, const post::WallSeries& reference_series) {
  const post::WallField reference_wall = post::wall_at_time(reference_series, result.time);
  result.reference_area = lumped_areas(reference_wall.mesh);
  const std::optional<WallIndices> reference_indices = read_wall_indices(result.meshes.back().folder + "/flow");
  for (MeshRun& run : result.meshes) {
    const post::WallField wall = post::wall_at_time(post::read_wall_series(run.folder + "/flow"), result.time);
    const WallMap map = map_onto(wall.mesh, reference_wall.mesh);
    run.wss_on_reference = interpolate(map, wall.wss);
    run.wall["wss"] = wall_difference(result.reference_area, run.wss_on_reference, reference_wall.wss);
    const std::optional<WallIndices> indices = read_wall_indices(run.folder + "/flow");
    if (!reference_indices || !indices) continue;
    const WallMap index_map = map_onto(indices->mesh, reference_indices->mesh);
    run.tawss_on_reference = interpolate(index_map, indices->tawss);
    run.osi_on_reference = interpolate(index_map, indices->osi);
    if (result.reference_index_area.empty()) result.reference_index_area = lumped_areas(reference_indices->mesh);
    run.wall["tawss"] = wall_difference(result.reference_index_area, run.tawss_on_reference, reference_indices->tawss);
    run.wall["osi"] = wall_difference(result.reference_index_area, run.osi_on_reference, reference_indices->osi);
  }
  // The checks' fields on the reference's wall, for the time step's and the start-up's share of each measure.
  for (std::optional<MeshRun>* check : {&result.half_step, &result.next_period}) {
    if (!*check) continue;
    MeshRun& run = **check;
    const post::WallField wall =
        post::wall_at_time(post::read_wall_series(run.folder + "/flow"), result.time + run.read_after);
    run.wss_on_reference = interpolate(map_onto(wall.mesh, reference_wall.mesh), wall.wss);
    const std::optional<WallIndices> indices = read_wall_indices(run.folder + "/flow");
    if (reference_indices && indices) {
      const WallMap index_map = map_onto(indices->mesh, reference_indices->mesh);
      run.tawss_on_reference = interpolate(index_map, indices->tawss);
      run.osi_on_reference = interpolate(index_map, indices->osi);
    }
  }
}

// The series' first level's flow run again as a check of the reference's temporal error (its stamp
// the level's with the check's name: reused when it matches): at half the time step, saving at the
// same times (`next_period` false); or one period more (`next_period` true: a copy of the level's
// flow goes on from its last checkpoint to the case's end + period, read a period after the
// study's time, its indices over the new last period).
MeshRun run_check(const StudyConfig& config, const flow::FlowCase& base_case, const MeshRun& level,
                  const std::string& folder, bool next_period, const Reporter& reporter) {
  MeshRun check;
  check.name = level.name + (next_period ? "_next_period" : "_half_dt");
  check.folder = (fs::path(folder) / check.name).string();
  check.read_after = next_period ? base_case.period : 0.0;
  const std::string flow_dir = check.folder + "/flow", stamp_file = check.folder + "/stamp.json";
  const std::string key =
      fingerprint(io::read_file(level.folder + "/stamp.json") + (next_period ? "one period more" : "time step / 2"));
  const std::optional<Json> stamp = matching_stamp(stamp_file, key);
  if (stamp && fs::exists(flow_dir + "/wall.pvd")) {
    for (const auto& [k, v] : (*stamp)["seconds"].items()) check.seconds[k] = v.get<double>();
    check.reused = true;
    reporter.info(fmt::format("study: {}: reused from {}", check.name, stamp_file));
  } else {
    reporter.info(next_period ? fmt::format("study: {}: {}'s flow one period ({:g} s) more", check.name, level.name,
                                            base_case.period)
                              : fmt::format("study: {}: {}'s flow again at half the time step ({:g} s)", check.name,
                                            level.name, base_case.dt / 2));
    const auto started = Clock::now();
    flow::FlowCase fc = base_case;
    fc.mesh = level.folder + "/volume.msh";
    if (next_period) flow::set_end(fc, base_case.end + base_case.period);
    else flow::divide_time_step(fc, 2);
    const std::string flow_key_file = flow_dir + "/study_flow_key";
    const bool resume =
        fs::exists(flow_dir + "/checkpoint.bin") && fs::exists(flow_key_file) && io::read_file(flow_key_file) == key;
    if (next_period && !resume) {  // the level's flow as it ended, to go on from
      fs::remove_all(flow_dir);
      fs::create_directories(check.folder);
      fs::copy(level.folder + "/flow", flow_dir, fs::copy_options::recursive);
    }
    fs::create_directories(flow_dir);
    io::write_text(flow_key_file, key);
    const bool restart = resume || next_period;
    const flow::SimulationSummary s =
        config.ranks > 1 ? simulate_under_mpirun(config, fc.mesh, flow_dir, restart, next_period ? 1 : 2,
                                                 next_period ? fc.end : 0.0)
                         : flow::simulate(fc, flow_dir, "", reporter, restart);
    if (s.status == "stopped")
      throw StoppedError(fmt::format("stopped by signal {} in {}'s flow (its checkpoint is kept): run the same "
                                     "study again to go on",
                                     s.signal, check.name),
                         s.signal);
    check.seconds["flow"] = since(started);
    io::write_text(stamp_file, Json{{"key", key}, {"mesh", check.name}, {"seconds", check.seconds}}.dump(2) + "\n");
  }
  check.dofs = level.dofs;
  check.volume_points = level.volume_points;
  return check;
}

// The checks of the reference's temporal error, each the series' coarsest level's flow run again
// (run_check): at half the time step (issue 46: the time step's share), saved at the same times; and
// where the case says its period, one period more (the start-up's share).
void run_checks(const StudyConfig& config, const flow::FlowCase& base_case, const std::string& folder,
                StudyResult& result, const Reporter& reporter) {
  result.period = base_case.steady ? 0.0 : base_case.period;
  if (config.levels < 1) return;
  const MeshRun& level = result.meshes[config.kinds.size()];
  if (!base_case.steady && config.time_step_check)
    result.half_step = run_check(config, base_case, level, folder, false, reporter);
  if (!(result.period > 0.0 && config.period_check)) return;
  if (fs::exists(level.folder + "/flow/checkpoint.bin")) {
    result.next_period = run_check(config, base_case, level, folder, true, reporter);
    return;
  }
  result.warnings.push_back(fmt::format("the start-up's share is not measured: {}'s flow has no checkpoint to go on "
                                        "from (a flow from before they were written: run the study into a new folder)",
                                        level.folder));
  reporter.warning(result.warnings.back());
}

// A mesh's figures from its stamp (study.json's keys; those a stamp from before lacks as they were).
void read_stamp(const Json& j, const StudyConfig& config, MeshRun& run) {
  run.surface_triangles = j["surface_triangles"];
  run.least_count = j.value("least_count", 0);
  run.surface_points = j["surface_points"];
  run.volume_points = j["volume_points"];
  run.tetrahedra = j["tetrahedra"];
  run.dofs = j["dofs"];
  run.min_dihedral = j["min_dihedral"];
  run.min_dihedral_layer = j.value("min_dihedral_layer", -1.0);
  run.min_dihedral_interior = j.value("min_dihedral_interior", -1.0);
  run.min_dihedral_layer_frame = j.value("min_dihedral_layer_frame", -1.0);
  run.interior_size = j.value("interior_size", config.interior.factor);
  run.target_triangles = j.value("target_triangles", run.target_triangles);
  run.layers = j.value("layers", config.layers);
  run.layer_growth = j.value("layer_growth", 1.0);
  for (const auto& [k, v] : j["seconds"].items()) run.seconds[k] = v.get<double>();
}

// The stamp of a mesh made: what made it (`key`) and its figures.
Json stamp_of(const MeshRun& run, const std::string& key) {
  return {{"key", key},
          {"mesh", run.name},
          {"surface_triangles", run.surface_triangles},
          {"least_count", run.least_count},
          {"surface_points", run.surface_points},
          {"volume_points", run.volume_points},
          {"tetrahedra", run.tetrahedra},
          {"dofs", run.dofs},
          {"min_dihedral", run.min_dihedral},
          {"min_dihedral_layer", run.min_dihedral_layer},
          {"min_dihedral_interior", run.min_dihedral_interior},
          {"min_dihedral_layer_frame", run.min_dihedral_layer_frame},
          {"interior_size", run.interior_size},
          {"target_triangles", run.target_triangles},
          {"layers", run.layers},
          {"layer_growth", run.layer_growth},
          {"seconds", run.seconds}};
}

// A mesh's WSS at the study's time on each ring and at each point.
void sample_wall(MeshRun& run, const StudyResult& result, const std::vector<post::PointSpec>& points) {
  const post::WallField wall =
      post::wall_at_time(post::read_wall_series(run.folder + "/flow"), result.time + run.read_after);
  for (const post::RingSpec& spec : result.rings) run.rings.push_back(post::cut_ring(wall.mesh, wall.wss, spec));
  run.points = post::probe_points(wall.mesh, wall.wss, points);
}

// The envelope series' wall sizes on the input, its interior's factor, and what they depend on (the
// compared surfaces, their interiors) for the levels' key.
struct Envelope {
  std::vector<double> sizes;
  double interior_factor = 1.0;
  std::function<double(const Vec3&)> flow;  // the flow kinds' interiors (envelope.h: least_flow_interior)
  std::vector<post::WallHeights> first_heights;  // the flow kinds' layers (envelope.h: level_first_height)
  std::string key;
};
Envelope make_envelope(const TriMesh& surface, const std::vector<MeshRun>& made, const StudyConfig& config,
                       const flow::FlowCase& base_case, const Reporter& reporter) {
  Envelope out;
  std::vector<TriMesh> walls;
  std::vector<double> compared_factors, flow_factors;
  std::vector<post::FluidSizes> flows;
  for (const MeshRun& done : made) {
    if (done.series) continue;
    const std::string wall_file = done.folder + "/surface.vtp";
    walls.push_back(io::read_surface(wall_file).mesh);
    out.key += fmt::format("compared {} {} interior {}\n", done.name, fingerprint(io::read_file(wall_file)),
                           done.interior_size);
    compared_factors.push_back(done.interior_size);
    if (done.adapted_from.empty()) continue;  // a flow kind: its interior as its volume had it
    const std::string source = (fs::path(done.folder).parent_path() / done.adapted_from).string();
    flows.push_back(post::fluid_error_sizes(source + "/flow", {}, config.interior.gradation, {}, reporter));
    flow_factors.push_back(done.interior_size);
    if (config.flow_y_plus > 0.0)
      out.first_heights.push_back(post::first_layer_heights(source + "/flow", {}, config.flow_y_plus,
                                                            {base_case.density, base_case.viscosity}, reporter));
    out.key += fmt::format("its interior and layer (y+ {}) from {} {}\n", config.flow_y_plus, done.adapted_from,
                           fingerprint(io::read_file(source + "/stamp.json")));
  }
  if (!flows.empty()) out.flow = least_flow_interior(std::move(flows), flow_factors);
  std::vector<const TriMesh*> meshes;
  for (const TriMesh& w : walls) meshes.push_back(&w);
  reporter.info(fmt::format("study: the reference's sizes: the least of the {} compared meshes'", meshes.size()));
  out.sizes = envelope_sizes(surface, meshes);
  out.interior_factor = envelope_interior_factor(surface, meshes, compared_factors, out.sizes);
  return out;
}

// A mesh's volume: its wall's boundary layer (`layer_design`) and interior, sized to `volume_points`
// nodes when that is positive (the first compared mesh's).
volume::VolumeResult make_volume(const TriMesh& wall, const StudyConfig& config, const flow::FlowCase& base_case,
                                 const LevelLayers& layer_design, const volume::InteriorSizeOptions& interior,
                                 const std::vector<volume::EndAt>& end_at, int volume_points, const std::string& name,
                                 const std::string& flow_dir, std::function<double(const Vec3&)> first_height,
                                 const Reporter& reporter) {
  const centerline::DistanceMap wall_distance = centerline::distance_map(wall, centerline::extract(wall, {}, reporter));
  volume::VolumeOptions vo;
  vo.layer = {.layers = layer_design.layers, .thickness_ratio = config.thickness_ratio, .growth = layer_design.growth,
              .min_angle_deg = config.layer_angle, .split_angle_deg = config.layer_split_angle,
              .first_height = std::move(first_height)};
  vo.algorithm = volume::parse_fill_algorithm(config.algorithm);
  vo.interior = interior;
  if (!flow_dir.empty()) size_volume_to_flow(vo, flow_dir, {}, config.flow_y_plus, base_case, reporter);
  vo.inlet = config.inlet;
  vo.end_names = config.end_names;
  vo.end_at = end_at;
  if (volume_points > 0)
    reporter.info(fmt::format("study: {}: its volume sized to {} nodes, the first compared's", name, volume_points));
  return volume_points > 0 ? volume::build_volume_with_points(wall, analysis::open_ends(wall), wall_distance.radius,
                                                           vo, volume_points, 0.02, reporter)
                           : volume::build_volume(wall, analysis::open_ends(wall), wall_distance.radius, vo, reporter);
}

// A mesh's flow, going on from its checkpoint where a flow of this mesh and case (`key`) stopped;
// StoppedError when a signal stops it.
flow::SimulationSummary run_flow(const StudyConfig& config, const flow::FlowCase& base_case, const std::string& name,
                                 const std::string& volume_file, const std::string& flow_dir, const std::string& key,
                                 const Reporter& reporter) {
  flow::FlowCase fc = base_case;
  fc.mesh = volume_file;
  // A flow of this mesh and case stopped before its end (the study killed) goes on from its
  // checkpoint: the meshes are made again the same, the key names the case.
  const std::string flow_key_file = flow_dir + "/study_flow_key";
  const bool resume = !fc.steady && fs::exists(flow_dir + "/checkpoint.bin") && fs::exists(flow_key_file) &&
                      io::read_file(flow_key_file) == key;
  if (resume) reporter.info(fmt::format("study: {}: the flow goes on from its checkpoint", name));
  fs::create_directories(flow_dir);
  io::write_text(flow_key_file, key);
  const flow::SimulationSummary s = config.ranks > 1
                                        ? simulate_under_mpirun(config, volume_file, flow_dir, resume)
                                        : flow::simulate(fc, flow_dir, "", reporter, resume);
  if (s.status == "stopped")
    throw StoppedError(fmt::format("stopped by signal {} in {}'s flow (its checkpoint is kept): run the same "
                                   "study again to go on",
                                   s.signal, name),
                       s.signal);
  return s;
}

// The warning for a compared mesh more than 3 % from its asked count, or nothing.
std::string unequal_size_warning(const MeshRun& run) {
  if (run.series || !(std::abs(run.surface_triangles - run.target_triangles) > 0.03 * run.target_triangles)) return {};
  return fmt::format(
      "the {} mesh has {} triangles, {:+.1f} % from the {:.0f} asked: the meshes are not of equal size (the "
      "distance bound of the remesher keeps a coarse mesh from the surface's curves; raise `triangles`{})",
      run.name, run.surface_triangles, 100.0 * (run.surface_triangles / run.target_triangles - 1.0),
      run.target_triangles,
      run.least_count > 0 ? fmt::format(" to at least {}, the least count the bound allows this kind", run.least_count)
                          : std::string());
}

// The study's measures of every mesh: its WSS at the chosen time on the rings and points; its wall
// fields on the reference's wall (study/wall_difference.h); what it resolves at each ring and point
// (study/resolution.h). Their times in result.seconds.
void measure_meshes(StudyResult& result, const StudyConfig& config, const TriMesh& surface,
                    const centerline::DistanceMap& distance, const Reporter& reporter) {
  auto step = Clock::now();
  const post::WallSeries reference_series = post::read_wall_series(result.meshes.back().folder + "/flow");
  result.time = config.time.value_or(reference_series.frames.back().time);
  result.length_unit = reference_series.length_unit;
  for (MeshRun& run : result.meshes) sample_wall(run, result, config.points);
  for (std::optional<MeshRun>* check : {&result.half_step, &result.next_period})
    if (*check) sample_wall(**check, result, config.points);
  result.seconds["wss on rings and points"] = since(step);

  // Whole-wall measures (study/wall_difference.h): each mesh's WSS, TAWSS and OSI on the reference's wall.
  step = Clock::now();
  reporter.info("study: every mesh's wall fields on the reference's wall");
  measure_whole_wall(result, reference_series);
  result.seconds["whole-wall differences"] = since(step);

  // What every mesh resolves at each ring and point (study/resolution.h).
  step = Clock::now();
  reporter.info("study: the meshes' resolution at the rings and points");
  result.places = measured_places(surface, distance.radius, result.rings, config.points);
  for (MeshRun& run : result.meshes)
    run.resolution = measure_resolution(io::read_surface(run.folder + "/surface.vtp").mesh,
                                        io::read_volume(run.folder + "/volume.msh"), result.places);
  result.seconds["resolution at the rings and points"] = since(step);
}

// What every mesh depends on: the input's bytes, the options, the version.
std::string common_key(const StudyConfig& config, const std::vector<volume::EndAt>& end_at) {
  std::string common = fmt::format(
      "vesselmesh {}\n{}\nunits={}\nlayers={} ratio={} layer_angle={} split_angle={} algorithm={} inlet={}\n"
      "interior sized by design: factor={} gradation={} core={} equal volume nodes={} (Gmsh Delaunay optimized to 0.8)\n",
      VESSELMESH_VERSION, fingerprint(io::read_file(config.surface)), config.units, config.layers,
      config.thickness_ratio, config.layer_angle, config.layer_split_angle, config.algorithm, config.inlet,
      config.interior.factor, config.interior.gradation, config.interior.core_fraction, config.equal_volume_nodes);
  for (const std::string& n : config.end_names) common += n + ",";
  if (config.extension_length > 0.0)
    common += fmt::format("\nextensions {} {}", config.extension_length, config.extension_mode);
  for (const volume::EndAt& e : end_at)
    common += fmt::format("\nend {} {} {} {}", e.name, e.point.x(), e.point.y(), e.point.z());
  return common;
}

// The meshes to make, in order: the compared kinds at `triangles`, then the series' levels (a
// uniform level at triangles x factor^k; an envelope level's count is what its sizes predict, known
// once the compared meshes are made: 0 here).
struct Planned {
  std::string name;
  sizing::SizeKind kind;
  double target_triangles;
};
std::vector<Planned> study_plan(const StudyConfig& config) {
  std::vector<Planned> plan;
  for (sizing::SizeKind kind : config.kinds) {
    const bool cycles = kind == sizing::SizeKind::flow && config.flow_cycles > 1;  // flow_1 .. flow_N
    for (int j = 1; j <= (cycles ? config.flow_cycles : 1); ++j)
      plan.push_back({cycles ? fmt::format("flow_{}", j) : sizing::size_kind_name(kind), kind, config.triangles});
  }
  for (int k = 1; k <= config.levels; ++k)
    plan.push_back({fmt::format("level_{}", k), sizing::SizeKind::uniform,
                    config.reference == ReferenceKind::envelope ? 0.0 : config.triangles * std::pow(config.factor, k)});
  return plan;
}

// The compared mesh whose flow the flow kind's mesh `name` adapts to: cycle j > 1 (flow_j) the cycle
// before's, else the curvature mesh where it is compared, else the first.
const MeshRun& flow_source(const std::vector<MeshRun>& made, const std::string& name) {
  const int cycle = name.rfind("flow_", 0) == 0 ? std::stoi(name.substr(5)) : 1;
  for (const MeshRun& m : made)
    if (cycle > 1 && m.name == fmt::format("flow_{}", cycle - 1)) return m;
  for (const MeshRun& m : made)
    if (m.name == "curvature") return m;
  return made.front();
}

// The flow kind's error metric on the input (sizing/size_field.h), from the WSS of `source`'s flow
// over its last period's saved frames (or its last frame).
std::vector<Sym3> flow_metric(const TriMesh& surface, const MeshRun& source, const Reporter& reporter) {
  reporter.info(fmt::format("study: flow: adapted to the WSS of the flow on the {} mesh", source.name));
  const post::WallMetric wall = post::wall_error_metric(source.folder + "/flow", {}, {}, reporter);
  return remesh::carry_metric(wall.wall, wall.metric, surface, fmt::format("{}'s flow's wall", source.name));
}

// The study's input surface: read, repaired, with flow extensions on its open ends when asked (the
// [[end]] points in `end_at` follow their ends).
TriMesh study_input(const StudyConfig& config, std::vector<volume::EndAt>& end_at, const Reporter& reporter) {
  io::ReadOptions read;
  if (!config.units.empty()) read.units = io::parse_unit(config.units);
  io::SurfaceFile file = io::read_surface(config.surface, read, reporter);
  mesh::clean(file.mesh, {}, reporter);
  if (!end_at.empty()) volume::names_of_ends(analysis::open_ends(file.mesh), end_at);  // and the ends' names
  if (config.extension_length > 0.0) {
    // Flow extensions on every open end; the [[end]] points follow their ends.
    const std::vector<analysis::OpenEnd> ends = analysis::open_ends(file.mesh);
    remesh::ExtensionResult extended =
        remesh::extend_ends(file.mesh, ends,
                            {.length = config.extension_length, .mode = remesh::parse_extension_mode(config.extension_mode)});
    for (volume::EndAt& e : end_at) {
      const remesh::ExtendedEnd* nearest = nullptr;
      for (const remesh::ExtendedEnd& x : extended.extended)
        if (!nearest || (x.old_center - e.point).norm() < (nearest->old_center - e.point).norm()) nearest = &x;
      if (nearest) e.point = nearest->center;
    }
    for (const remesh::ExtendedEnd& x : extended.extended)
      reporter.info(fmt::format("study: end {} extended by {:.4g} (radius {:.4g}): its centre now ({:.4g}, {:.4g}, {:.4g})",
                                x.end, x.length, x.radius, x.center.x(), x.center.y(), x.center.z()));
    file.mesh = std::move(extended.mesh);
  }
  return std::move(file.mesh);
}

}  // namespace

ReferenceKind parse_reference_kind(const std::string& name) {
  if (name == "envelope") return ReferenceKind::envelope;
  if (name == "uniform") return ReferenceKind::uniform;
  throw OptionError(fmt::format("unknown reference kind '{}': give \"envelope\" (finer than every compared mesh "
                                "everywhere) or \"uniform\" (the seed paper's uniform series)",
                                name));
}

std::string reference_kind_name(ReferenceKind kind) {
  return kind == ReferenceKind::envelope ? "envelope" : "uniform";
}

StudyConfig parse_study(const std::string& text, const std::string& path) {
  const toml::table parsed = io::parse_toml(text, path);
  const toml::table& root = parsed;
  const io::TomlReader r{path};
  StudyConfig c;
  c.path = path;
  r.known_keys(root, "", {"surface", "units", "case", "triangles", "meshes", "reference", "volume", "post", "ring", "end",
                          "point", "ranks", "extensions", "flow_cycles"});
  const std::string surface = r.text(root["surface"], "surface", "");
  if (surface.empty()) r.fail("surface", "missing: the vessel surface (STL, VTP, ...) to study");
  c.surface = io::resolve_path(path, surface);
  c.units = r.text(root["units"], "units", "");
  if (!c.units.empty()) {
    try {
      io::parse_unit(c.units);
    } catch (const OptionError& e) {
      r.fail("units", e.what());
    }
  }
  const std::string flow_case = r.text(root["case"], "case", "");
  if (flow_case.empty()) r.fail("case", "missing: the flow case (TOML, as for `vesselmesh simulate`) run on each mesh");
  c.flow_case = io::resolve_path(path, flow_case);
  c.ranks = r.integer(root["ranks"], "ranks", c.ranks, 1);
  c.flow_cycles = r.integer(root["flow_cycles"], "flow_cycles", c.flow_cycles, 1);
  c.triangles = r.number(root["triangles"], "triangles", c.triangles);
  if (c.triangles < 100) r.fail("triangles", "at least 100");
  if (root["meshes"]) {
    c.kinds.clear();
    for (const std::string& name : r.strings(root["meshes"], "meshes")) {
      try {
        c.kinds.push_back(sizing::parse_size_kind(name));
      } catch (const Error& e) {
        r.fail("meshes", e.what());
      }
    }
    if (!c.kinds.empty() && c.kinds.front() == sizing::SizeKind::flow)
      r.fail("meshes", "\"flow\" adapts to the flow on another compared mesh: list a geometric kind before it");
  }
  if (c.flow_cycles > 1 && std::find(c.kinds.begin(), c.kinds.end(), sizing::SizeKind::flow) == c.kinds.end())
    r.fail("flow_cycles", "the flow kind's cycles: list \"flow\" in meshes");
  if (c.flow_cycles > 10) r.fail("flow_cycles", "at most 10 (each cycle a flow more)");
  if (const toml::table* t = root["reference"].as_table()) {
    r.known_keys(*t, "reference", {"kind", "levels", "factor", "time_step_check", "period_check"});
    const io::TomlView v = root["reference"];
    try {
      c.reference = parse_reference_kind(r.text(v["kind"], "reference.kind", reference_kind_name(c.reference)));
    } catch (const Error& e) {
      r.fail("reference.kind", e.what());
    }
    c.levels = r.integer(v["levels"], "reference.levels", c.levels, 1);
    c.time_step_check = r.flag(v["time_step_check"], "reference.time_step_check", c.time_step_check);
    c.period_check = r.flag(v["period_check"], "reference.period_check", c.period_check);
    c.factor = r.number(v["factor"], "reference.factor", c.reference == ReferenceKind::envelope ? 1.33 : 2.0);
    if (!(c.factor > 1.0))
      r.fail("reference.factor", c.reference == ReferenceKind::envelope
                                     ? "must be more than 1 (each level that many times finer in h; 1.3 or more for "
                                       "a grid convergence that means something)"
                                     : "must be more than 1 (each level has that many times the triangles)");
  }
  if (const toml::table* t = root["volume"].as_table()) {
    r.known_keys(*t, "volume", {"layers", "thickness_ratio", "layer_angle", "layer_split_angle", "algorithm",
                                "inlet", "end_names", "interior_size", "interior_gradation",
                                "equal_volume_nodes", "flow_y_plus"});
    const io::TomlView v = root["volume"];
    c.layers = r.integer(v["layers"], "volume.layers", c.layers, 0);
    c.thickness_ratio = r.number(v["thickness_ratio"], "volume.thickness_ratio", c.thickness_ratio);
    c.layer_angle = r.number(v["layer_angle"], "volume.layer_angle", c.layer_angle);
    if (!(c.layer_angle >= 0.0 && c.layer_angle <= 30.0)) r.fail("volume.layer_angle", "give 0 to 30 degrees");
    c.layer_split_angle = r.number(v["layer_split_angle"], "volume.layer_split_angle", c.layer_split_angle);
    c.flow_y_plus = r.number(v["flow_y_plus"], "volume.flow_y_plus", c.flow_y_plus);
    if (!(c.flow_y_plus >= 0.0 && std::isfinite(c.flow_y_plus))) r.fail("volume.flow_y_plus", "give a y+ >= 0");
    if (!(c.layer_split_angle >= 0.0 && c.layer_split_angle <= 30.0))
      r.fail("volume.layer_split_angle", "give 0 to 30 degrees (0: the wall's triangles as meshed)");
    c.algorithm = r.text(v["algorithm"], "volume.algorithm", c.algorithm);
    try {
      volume::parse_fill_algorithm(c.algorithm);
    } catch (const Error& e) {
      r.fail("volume.algorithm", e.what());
    }
    c.interior.factor = r.number(v["interior_size"], "volume.interior_size", c.interior.factor);
    if (!(c.interior.factor > 0.0)) r.fail("volume.interior_size", "give a factor > 0 (1: the wall's size)");
    c.interior.gradation = r.number(v["interior_gradation"], "volume.interior_gradation", c.interior.gradation);
    if (!(c.interior.gradation >= 1.0)) r.fail("volume.interior_gradation", "give a growth >= 1 (1: none)");
    c.equal_volume_nodes = r.flag(v["equal_volume_nodes"], "volume.equal_volume_nodes", c.equal_volume_nodes);
    c.inlet = r.integer(v["inlet"], "volume.inlet", -1, 0);
    c.end_names = r.strings(v["end_names"], "volume.end_names");
  }
  if (const toml::table* t = root["extensions"].as_table()) {
    r.known_keys(*t, "extensions", {"length", "mode"});
    const io::TomlView v = root["extensions"];
    c.extension_length = r.number(v["length"], "extensions.length", 0.0);
    if (!(c.extension_length >= 0.0)) r.fail("extensions.length", "give the tubes' length in radii of each end (0: none)");
    c.extension_mode = r.text(v["mode"], "extensions.mode", c.extension_mode);
    try {
      remesh::parse_extension_mode(c.extension_mode);
    } catch (const InputError& e) {
      r.fail("extensions.mode", e.what());
    }
  }
  if (const toml::table* t = root["post"].as_table()) {
    r.known_keys(*t, "post", {"time"});
    if (root["post"]["time"]) c.time = r.number(root["post"]["time"], "post.time", 0.0, false);
  }
  const auto named = [&](const toml::table& t, const std::string& where) {
    const std::string name = r.text(io::TomlView(&t)["name"], where + ".name", "");
    if (!io::is_file_name_safe(name))
      r.fail(where + ".name", "missing or not made of letters, digits, '_', '-', '.' (it names files)");
    return name;
  };
  for (const auto& [where, t] : r.tables(root, "ring")) {
    r.known_keys(*t, where, {"name", "point", "normal", "reference"});
    const io::TomlView v(t);
    post::RingRequest request;
    request.spec.name = named(*t, where);
    request.spec.point = r.point(v["point"], where + ".point");
    request.on_centerline = !v["normal"];
    if (v["normal"]) {
      request.spec.normal = r.point(v["normal"], where + ".normal");
      if (!(request.spec.normal.norm() > 0.0)) r.fail(where + ".normal", "is zero");
    }
    if (v["reference"]) request.spec.reference = r.point(v["reference"], where + ".reference");
    c.rings.push_back(request);
  }
  for (const auto& [where, t] : r.tables(root, "point")) {
    r.known_keys(*t, where, {"name", "point"});
    c.points.push_back({named(*t, where), r.point(io::TomlView(t)["point"], where + ".point")});
  }
  for (const auto& [where, t] : r.tables(root, "end")) {
    r.known_keys(*t, where, {"name", "point"});
    const io::TomlView v(t);
    const std::string name = r.text(v["name"], where + ".name", "");
    if (name.empty() || name == "wall") r.fail(where + ".name", "missing, or 'wall' (the wall's own tag)");
    c.end_at.push_back({name, r.point(v["point"], where + ".point")});
  }
  if (!c.end_at.empty() && (!c.end_names.empty() || c.inlet >= 0))
    r.fail("end", "name the ends by [[end]] or by [volume] inlet / end_names, not both");
  if (c.reference == ReferenceKind::envelope && c.kinds.empty())
    r.fail("meshes", "empty: the envelope reference is made finer than the compared meshes (give some, or "
                     "[reference] kind = \"uniform\")");
  if (c.rings.empty() && c.points.empty())
    r.fail("ring", "give at least one [[ring]] or [[point]]: the study compares WSS there");
  return c;
}

StudyConfig read_study(const std::string& path) {
  if (!fs::exists(path)) throw InputError(fmt::format("{}: no such study file", path));
  return parse_study(io::read_file(path), path);
}

double relative_difference(double value, double reference) {
  if (reference == 0.0) return std::numeric_limits<double>::quiet_NaN();
  return 100.0 * (value - reference) / std::abs(reference);
}

StudyResult run_study(const StudyConfig& config, const std::string& folder, const Reporter& reporter) {
  const auto start = Clock::now();
  StudyResult result;
  fs::create_directories(folder);

  // 1. The input: read, repaired, its curvature, centerlines and distance map.
  auto step = Clock::now();
  reporter.info(fmt::format("study: reading {}", config.surface));
  const flow::FlowCase base_case = flow::read_case(config.flow_case);  // checked before any long step
  std::vector<volume::EndAt> end_at = config.end_at;
  const TriMesh surface = study_input(config, end_at, reporter);
  reporter.info("study: curvature, centerlines and distance map of the input");
  const analysis::CurvatureField curvature = analysis::curvature(surface, {}, reporter);
  const centerline::Centerlines lines = centerline::extract(surface, {}, reporter);
  const centerline::DistanceMap distance = centerline::distance_map(surface, lines);
  result.rings = post::place_rings(surface, config.rings, reporter);
  // A ring plane that misses the vessel is found now, not after every flow has run.
  for (const post::RingSpec& spec : result.rings)
    post::cut_ring(surface, std::vector<Vec3>(surface.points.size(), Vec3::Zero()), spec);
  result.seconds["input analysis"] = since(step);

  const std::string common = common_key(config, end_at);
  std::string case_text = io::read_file(config.flow_case);
  for (const flow::BoundaryCondition& b : base_case.boundaries)
    if (!b.waveform_file.empty()) case_text += io::read_file(b.waveform_file);

  const std::vector<Planned> plan = study_plan(config);
  const bool envelope_series = config.reference == ReferenceKind::envelope;
  // The envelope series' wall sizes on the input (study/envelope.h), made from the compared meshes'
  // surfaces once they exist.
  Envelope envelope;
  int volume_target = 0;  // the first compared mesh's volume nodes, when the others are to have them
  for (size_t m = 0; m < plan.size(); ++m) {
    const auto& [name, kind, target] = plan[m];
    MeshRun run;
    run.name = name;
    run.series = name.rfind("level_", 0) == 0;
    run.target_triangles = target;
    run.folder = (fs::path(folder) / name).string();
    fs::create_directories(run.folder);
    const int volume_points = run.series ? 0 : volume_target;
    // An envelope level k: its sizes, layer and interior factor^(k-1) finer than the envelope's (margin beside).
    const bool envelope_level = run.series && envelope_series;
    const double scale =
        envelope_level_scale(config.factor, static_cast<int>(m + 1 - config.kinds.size()), config.levels);
    if (envelope_level && envelope.sizes.empty())
      envelope = make_envelope(surface, result.meshes, config, base_case, reporter);
    const LevelLayers layer_design = envelope_level ? level_layers(config.layers, scale) : LevelLayers{config.layers};
    const volume::InteriorSizeOptions interior =
        envelope_level ? level_interior(config.interior, envelope.interior_factor, scale, envelope.flow)
                       : config.interior;
    std::string what = fmt::format("kind={} triangles={} volume points={}\n", sizing::size_kind_name(kind),
                                   run.target_triangles, volume_points);
    if (envelope_level)
      what = fmt::format("envelope level {} scale={} layers={} growth={} interior={} {} {}\n{}", name, scale,
                         layer_design.layers, layer_design.growth, interior.factor, interior.gradation,
                         interior.core_fraction, envelope.key);
    // The flow kind depends on its source's meshes and flow (their stamp).
    const MeshRun* source = kind == sizing::SizeKind::flow ? &flow_source(result.meshes, name) : nullptr;
    if (source) run.adapted_from = source->name;
    if (source)
      what += fmt::format("flow from {} {} (wall, interior, layer at y+ {})\n", source->name,
                          fingerprint(io::read_file(source->folder + "/stamp.json")), config.flow_y_plus);
    const std::string mesh_key = fingerprint(common + what);
    const std::string flow_key = fingerprint(mesh_key + case_text);
    const std::string surface_file = run.folder + "/surface.vtp", volume_file = run.folder + "/volume.msh";
    const std::string flow_dir = run.folder + "/flow", stamp_file = run.folder + "/stamp.json";
    const std::optional<Json> stamp = matching_stamp(stamp_file, flow_key);
    if (stamp && fs::exists(volume_file) && fs::exists(flow_dir + "/wall.pvd")) {
      read_stamp(*stamp, config, run);
      run.reused = true;
      reporter.info(fmt::format("study: {} ({} of {}): reused from {}", name, m + 1, plan.size(), stamp_file));
    } else {
      step = Clock::now();
      remesh::RemeshOptions options;
      options.input_radius = &distance.radius;
      remesh::RemeshResult remeshed;
      if (envelope_level) {
        reporter.info(fmt::format("study: {} ({} of {}): surface mesh {:.3g} times finer than every compared mesh",
                                  name, m + 1, plan.size(), scale));
        std::vector<double> sizes(surface.points.size());
        for (size_t v = 0; v < sizes.size(); ++v) sizes[v] = envelope.sizes[v] / scale;
        remeshed = remesh_level(surface, sizes, options, run.target_triangles, reporter);
      } else {
        reporter.info(fmt::format("study: {} ({} of {}): surface mesh of about {:.0f} triangles", name, m + 1,
                                  plan.size(), run.target_triangles));
        const std::vector<Sym3> adapted_to = source ? flow_metric(surface, *source, reporter) : std::vector<Sym3>{};
        const sizing::SizeField field = sizing::make_size_field(
            surface, {.kind = kind, .target_triangles = run.target_triangles},
            {.curvature = &curvature, .distance = &distance, .flow = &adapted_to}, reporter);
        remeshed = remesh::adapt_to_count(surface, field.metric, run.target_triangles, options, reporter);
      }
      io::write_vtp(surface_file, remeshed.mesh);
      run.seconds["remesh"] = since(step);

      reporter.info(fmt::format("study: {}: volume mesh", name));
      step = Clock::now();
      const volume::VolumeResult volume_mesh =
          make_volume(remeshed.mesh, config, base_case, layer_design, interior, end_at, volume_points, name,
                      source ? source->folder + "/flow" : std::string(),
                      envelope_level ? level_first_height(envelope.first_heights, scale) : nullptr, reporter);
      io::write_msh(volume_file, volume_mesh.mesh);
      const volume::VolumeQuality quality = volume::measure_volume(volume_mesh.mesh, volume_mesh.radius);
      run.seconds["volume"] = since(step);

      reporter.info(fmt::format("study: {}: flow", name));
      step = Clock::now();
      const flow::SimulationSummary s = run_flow(config, base_case, name, volume_file, flow_dir, flow_key, reporter);
      run.seconds["flow"] = since(step);
      run.surface_triangles = remeshed.stats.triangles;
      run.least_count = remeshed.least_count;
      run.surface_points = remeshed.stats.points;
      run.volume_points = quality.points;
      run.tetrahedra = quality.tets + 3 * quality.prisms;
      run.dofs = s.dofs;
      run.min_dihedral = quality.min_dihedral;
      run.min_dihedral_layer = quality.min_dihedral_layer;
      run.min_dihedral_interior = quality.min_dihedral_interior;
      run.min_dihedral_layer_frame = quality.min_dihedral_layer_frame;
      run.interior_size = volume_mesh.report.interior_factor;
      run.layers = layer_design.layers;
      run.layer_growth = layer_design.growth;
      io::write_text(stamp_file, stamp_of(run, flow_key).dump(2) + "\n");
    }
    if (const std::string warning = unequal_size_warning(run); !warning.empty()) {
      reporter.warning(warning);
      result.warnings.push_back(warning);
    }
    if (!run.series && config.equal_volume_nodes && volume_target == 0) volume_target = run.volume_points;
    result.meshes.push_back(run);
  }
  result.reference = static_cast<int>(result.meshes.size()) - 1;
  result.time_step = base_case.steady ? 0.0 : base_case.dt;

  run_checks(config, base_case, folder, result, reporter);
  if (const std::string w = volume_count_warning(result.meshes); !w.empty()) {
    reporter.warning(w);
    result.warnings.push_back(w);
  }

  // 6. WSS at the chosen time on the rings and points of every mesh; over the whole wall; what each
  // mesh resolves at each ring and point.
  measure_meshes(result, config, surface, distance, reporter);

  // 7. The report (the total it states stops before it).
  result.seconds["total before the report"] = since(start);
  write_report(config, result, folder, reporter);
  return result;
}

std::string volume_count_warning(const std::vector<MeshRun>& meshes) {
  const MeshRun* least = nullptr;
  const MeshRun* most = nullptr;
  for (const MeshRun& m : meshes) {
    if (m.series) continue;
    if (!least || m.volume_points < least->volume_points) least = &m;
    if (!most || m.volume_points > most->volume_points) most = &m;
  }
  if (!least || most->volume_points <= 1.05 * least->volume_points) return "";
  return fmt::format("the compared meshes' volume nodes differ by {:.1f} % ({} for {}, {} for {}): at equal surface "
                     "counts their interiors are not alike, and the comparison weighs the volume as well as the wall "
                     "(set [volume] equal_volume_nodes = true, or check the layer)",
                     100.0 * (static_cast<double>(most->volume_points) / least->volume_points - 1.0),
                     least->volume_points, least->name, most->volume_points, most->name);
}

}  // namespace vesselmesh::study
