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
#include "io/vtk_formats.h"
#include "mesh/clean.h"
#include "mesh/error.h"
#include "post/wall_series.h"
#include "remesh/adapt.h"
#include "remesh/extend.h"
#include "study/study_report.h"
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
                                              const std::string& dir, bool restart) {
  if (config.program.empty()) throw InternalError("study: ranks > 1 without the program to run under mpirun");
  std::vector<std::string> command = {"mpirun", "-np",   std::to_string(config.ranks), config.program, "simulate",
                                      config.flow_case, "--mesh", mesh, "-o", dir, "-q"};
  if (restart) command.push_back("--restart");
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

}  // namespace

StudyConfig parse_study(const std::string& text, const std::string& path) {
  const toml::table parsed = io::parse_toml(text, path);
  const toml::table& root = parsed;
  const io::TomlReader r{path};
  StudyConfig c;
  c.path = path;
  r.known_keys(root, "", {"surface", "units", "case", "triangles", "meshes", "reference", "volume", "post", "ring", "end",
                          "point", "ranks", "extensions"});
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
  }
  if (const toml::table* t = root["reference"].as_table()) {
    r.known_keys(*t, "reference", {"levels", "factor"});
    c.levels = r.integer(root["reference"]["levels"], "reference.levels", c.levels, 1);
    c.factor = r.number(root["reference"]["factor"], "reference.factor", c.factor);
    if (c.factor <= 1.0) r.fail("reference.factor", "must be more than 1 (each level has that many times the triangles)");
  }
  if (const toml::table* t = root["volume"].as_table()) {
    r.known_keys(*t, "volume", {"layers", "thickness_ratio", "layer_angle", "layer_split_angle", "algorithm",
                                "inlet", "end_names", "interior_size", "interior_gradation",
                                "equal_volume_nodes"});
    const io::TomlView v = root["volume"];
    c.layers = r.integer(v["layers"], "volume.layers", c.layers, 0);
    c.thickness_ratio = r.number(v["thickness_ratio"], "volume.thickness_ratio", c.thickness_ratio);
    c.layer_angle = r.number(v["layer_angle"], "volume.layer_angle", c.layer_angle);
    if (!(c.layer_angle >= 0.0 && c.layer_angle <= 30.0)) r.fail("volume.layer_angle", "give 0 to 30 degrees");
    c.layer_split_angle = r.number(v["layer_split_angle"], "volume.layer_split_angle", c.layer_split_angle);
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
  io::ReadOptions read;
  if (!config.units.empty()) read.units = io::parse_unit(config.units);
  io::SurfaceFile file = io::read_surface(config.surface, read, reporter);
  mesh::clean(file.mesh, {}, reporter);
  const flow::FlowCase base_case = flow::read_case(config.flow_case);  // checked before any long step
  std::vector<volume::EndAt> end_at = config.end_at;
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
  const TriMesh& surface = file.mesh;
  reporter.info("study: curvature, centerlines and distance map of the input");
  const analysis::CurvatureField curvature = analysis::curvature(surface, {}, reporter);
  const centerline::Centerlines lines = centerline::extract(surface, {}, reporter);
  const centerline::DistanceMap distance = centerline::distance_map(surface, lines);
  result.rings = post::place_rings(surface, config.rings, reporter);
  // A ring plane that misses the vessel is found now, not after every flow has run.
  for (const post::RingSpec& spec : result.rings)
    post::cut_ring(surface, std::vector<Vec3>(surface.points.size(), Vec3::Zero()), spec);
  result.seconds["input analysis"] = since(step);

  // What every mesh depends on: the input's bytes, the options, the version.
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
  std::string case_text = io::read_file(config.flow_case);
  for (const flow::BoundaryCondition& b : base_case.boundaries)
    if (!b.waveform_file.empty()) case_text += io::read_file(b.waveform_file);

  std::vector<std::pair<std::string, sizing::SizeKind>> plan;
  std::vector<double> targets;
  for (sizing::SizeKind kind : config.kinds) {
    plan.emplace_back(sizing::size_kind_name(kind), kind);
    targets.push_back(config.triangles);
  }
  for (int k = 1; k <= config.levels; ++k) {
    plan.emplace_back(fmt::format("level_{}", k), sizing::SizeKind::uniform);
    targets.push_back(config.triangles * std::pow(config.factor, k));
  }

  int volume_target = 0;  // the first compared mesh's volume nodes, when the others are to have them
  for (size_t m = 0; m < plan.size(); ++m) {
    const auto& [name, kind] = plan[m];
    MeshRun run;
    run.name = name;
    run.series = name.rfind("level_", 0) == 0;
    run.target_triangles = targets[m];
    run.folder = (fs::path(folder) / name).string();
    fs::create_directories(run.folder);
    const int volume_points = run.series ? 0 : volume_target;
    const std::string mesh_key = fingerprint(common + fmt::format("kind={} triangles={} volume points={}\n",
                                                                  sizing::size_kind_name(kind), run.target_triangles,
                                                                  volume_points));
    const std::string flow_key = fingerprint(mesh_key + case_text);
    const std::string surface_file = run.folder + "/surface.vtp", volume_file = run.folder + "/volume.msh";
    const std::string flow_dir = run.folder + "/flow", stamp_file = run.folder + "/stamp.json";
    const std::optional<Json> stamp = matching_stamp(stamp_file, flow_key);
    if (stamp && fs::exists(volume_file) && fs::exists(flow_dir + "/wall.pvd")) {
      const Json& j = *stamp;
      run.surface_triangles = j["surface_triangles"];
      run.surface_points = j["surface_points"];
      run.volume_points = j["volume_points"];
      run.tetrahedra = j["tetrahedra"];
      run.dofs = j["dofs"];
      run.min_dihedral = j["min_dihedral"];
      run.interior_size = j.value("interior_size", config.interior.factor);
      for (const auto& [k, v] : j["seconds"].items()) run.seconds[k] = v.get<double>();
      run.reused = true;
      reporter.info(fmt::format("study: {} ({} of {}): reused from {}", name, m + 1, plan.size(), stamp_file));
    } else {
      reporter.info(fmt::format("study: {} ({} of {}): surface mesh of about {:.0f} triangles", name, m + 1,
                                plan.size(), run.target_triangles));
      step = Clock::now();
      const sizing::SizeField field = sizing::make_size_field(
          surface, {.kind = kind, .target_triangles = run.target_triangles},
          {.curvature = &curvature, .distance = &distance}, reporter);
      remesh::RemeshOptions options;
      options.input_radius = &distance.radius;
      const remesh::RemeshResult remeshed =
          remesh::adapt_to_count(surface, field.metric, run.target_triangles, options, reporter);
      io::write_vtp(surface_file, remeshed.mesh);
      run.seconds["remesh"] = since(step);

      reporter.info(fmt::format("study: {}: volume mesh", name));
      step = Clock::now();
      const TriMesh& wall = remeshed.mesh;
      const centerline::DistanceMap wall_distance =
          centerline::distance_map(wall, centerline::extract(wall, {}, reporter));
      volume::VolumeOptions vo;
      vo.layer.layers = config.layers;
      vo.layer.thickness_ratio = config.thickness_ratio;
      vo.layer.min_angle_deg = config.layer_angle;
      vo.layer.split_angle_deg = config.layer_split_angle;
      vo.algorithm = volume::parse_fill_algorithm(config.algorithm);
      vo.interior = config.interior;
      vo.inlet = config.inlet;
      vo.end_names = config.end_names;
      vo.end_at = end_at;
      if (volume_points > 0)
        reporter.info(fmt::format("study: {}: its volume sized to {} nodes, as the first compared mesh's", name,
                                  volume_points));
      const volume::VolumeResult volume_mesh =
          volume_points > 0 ? volume::build_volume_with_points(wall, analysis::open_ends(wall), wall_distance.radius,
                                                               vo, volume_points, 0.02, reporter)
                            : volume::build_volume(wall, analysis::open_ends(wall), wall_distance.radius, vo, reporter);
      io::write_msh(volume_file, volume_mesh.mesh);
      const volume::VolumeQuality quality = volume::measure_volume(volume_mesh.mesh, volume_mesh.radius);
      run.seconds["volume"] = since(step);

      reporter.info(fmt::format("study: {}: flow", name));
      step = Clock::now();
      flow::FlowCase fc = base_case;
      fc.mesh = volume_file;
      // A flow of this mesh and case stopped before its end (the study killed) goes on from its
      // checkpoint: the meshes are made again the same, the key names the case.
      const std::string flow_key_file = flow_dir + "/study_flow_key";
      const bool resume = !fc.steady && fs::exists(flow_dir + "/checkpoint.bin") && fs::exists(flow_key_file) &&
                          io::read_file(flow_key_file) == flow_key;
      if (resume) reporter.info(fmt::format("study: {}: the flow goes on from its checkpoint", name));
      fs::create_directories(flow_dir);
      io::write_text(flow_key_file, flow_key);
      const flow::SimulationSummary s = config.ranks > 1
                                            ? simulate_under_mpirun(config, volume_file, flow_dir, resume)
                                            : flow::simulate(fc, flow_dir, "", reporter, resume);
      if (s.status == "stopped")
        throw StoppedError(fmt::format("stopped by signal {} in {}'s flow (its checkpoint is kept): run the same "
                                       "study again to go on",
                                       s.signal, name),
                           s.signal);
      run.seconds["flow"] = since(step);
      run.surface_triangles = remeshed.stats.triangles;
      run.surface_points = remeshed.stats.points;
      run.volume_points = quality.points;
      run.tetrahedra = quality.tets + 3 * quality.prisms;
      run.dofs = s.dofs;
      run.min_dihedral = quality.min_dihedral;
      run.interior_size = volume_mesh.report.interior_factor;
      Json j = {{"key", flow_key},
                {"mesh", name},
                {"surface_triangles", run.surface_triangles},
                {"surface_points", run.surface_points},
                {"volume_points", run.volume_points},
                {"tetrahedra", run.tetrahedra},
                {"dofs", run.dofs},
                {"min_dihedral", run.min_dihedral},
                {"interior_size", run.interior_size},
                {"seconds", run.seconds}};
      io::write_text(stamp_file, j.dump(2) + "\n");
    }
    if (!run.series && std::abs(run.surface_triangles - run.target_triangles) > 0.03 * run.target_triangles) {
      const std::string warning = fmt::format(
          "the {} mesh has {} triangles, {:+.1f} % from the {:.0f} asked: the meshes are not of equal size (the "
          "distance bound of the remesher keeps a coarse mesh from the surface's curves; raise `triangles`)",
          name, run.surface_triangles, 100.0 * (run.surface_triangles / run.target_triangles - 1.0),
          run.target_triangles);
      reporter.warning(warning);
      result.warnings.push_back(warning);
    }
    if (!run.series && config.equal_volume_nodes && volume_target == 0) volume_target = run.volume_points;
    result.meshes.push_back(run);
  }
  result.reference = static_cast<int>(result.meshes.size()) - 1;
  if (const std::string w = volume_count_warning(result.meshes); !w.empty()) {
    reporter.warning(w);
    result.warnings.push_back(w);
  }

  // 6. WSS at the chosen time on the rings and points of every mesh.
  step = Clock::now();
  const post::WallSeries reference_series = post::read_wall_series(result.meshes.back().folder + "/flow");
  result.time = config.time.value_or(reference_series.frames.back().time);
  result.length_unit = reference_series.length_unit;
  for (MeshRun& run : result.meshes) {
    const post::WallField wall = post::wall_at_time(post::read_wall_series(run.folder + "/flow"), result.time);
    for (const post::RingSpec& spec : result.rings) run.rings.push_back(post::cut_ring(wall.mesh, wall.wss, spec));
    run.points = post::probe_points(wall.mesh, wall.wss, config.points);
  }
  result.seconds["wss on rings and points"] = since(step);

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
