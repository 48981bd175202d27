#include "flow/checkpoint.h"

#include "analysis/open_ends.h"
#include "flow/simulate.h"
#include "io/atomic_file.h"
#include "io/msh.h"
#include "io/vtk_formats.h"
#include "mesh/error.h"
#include "parallel/processes.h"
#include "synth/shapes.h"
#include "test_support.h"
#include "volume/volume_mesh.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <numeric>
#include <sstream>
#include <string>
#include <vector>

namespace vesselmesh::flow {
namespace {

Checkpoint sample_checkpoint() {
  Checkpoint c;
  c.fingerprint = 0x1234abcdull;
  c.flow.time = 0.125;
  c.flow.steps = 25;
  c.flow.time_step = 0.0055;
  c.flow.last_time_step = 0.005;
  c.flow.velocity = {Vec3(1, 2, 3), Vec3(-1, 0.5, 1e-9)};
  c.flow.previous = {Vec3(0.9, 2, 3), Vec3(-1, 0.25, 0)};
  c.flow.kinematic_pressure = {3.5, -2.0};
  c.flow.capacitor_pressure = {0.0, 1.2e4};
  c.saved = 3;
  c.linear_iterations = 321;
  c.log = "step,time_s\n1,0.005\n";
  c.fluid_files = {{0.05, "fluid_000000.vtu"}, {0.1, "fluid_000001.vtu"}};
  c.wall_files = {{0.05, "wall_000000.vtp"}};
  c.indices.samples = 4;
  c.indices.start = 0.01;
  c.indices.last_time = 0.125;
  c.indices.last = {Vec3(0.1, 0.2, 0.3)};
  c.indices.integral = {Vec3(1, 1, 1)};
  c.indices.magnitude_integral = {0.7};
  c.indices.change = {0.01};
  c.index_points = {42};
  return c;
}

TEST(Checkpoint, ReadsBackWhatItWroteAndRefusesDamagedFiles) {
  const test::TemporaryFolder folder;
  const std::string path = folder.path("checkpoint.bin");
  const Checkpoint c = sample_checkpoint();
  write_checkpoint(path, c);
  const Checkpoint r = read_checkpoint(path);
  EXPECT_EQ(r.fingerprint, c.fingerprint);
  EXPECT_EQ(r.flow.time, c.flow.time);
  EXPECT_EQ(r.flow.steps, c.flow.steps);
  EXPECT_EQ(r.flow.time_step, c.flow.time_step);
  EXPECT_EQ(r.flow.last_time_step, c.flow.last_time_step);
  EXPECT_EQ(r.flow.velocity, c.flow.velocity);
  EXPECT_EQ(r.flow.previous, c.flow.previous);
  EXPECT_EQ(r.flow.kinematic_pressure, c.flow.kinematic_pressure);
  EXPECT_EQ(r.flow.capacitor_pressure, c.flow.capacitor_pressure);
  EXPECT_EQ(r.saved, c.saved);
  EXPECT_EQ(r.linear_iterations, c.linear_iterations);
  EXPECT_EQ(r.log, c.log);
  EXPECT_EQ(r.fluid_files, c.fluid_files);
  EXPECT_EQ(r.wall_files, c.wall_files);
  EXPECT_EQ(r.indices.samples, 4);
  EXPECT_EQ(r.indices.last, c.indices.last);
  EXPECT_EQ(r.indices.change, c.indices.change);
  EXPECT_EQ(r.index_points, c.index_points);

  // Cut short at any byte: a clear error, never a half-read state.
  const std::string bytes = io::read_file(path);
  for (size_t keep : {size_t{0}, size_t{10}, bytes.size() / 2, bytes.size() - 1}) {
    test::write_bytes(folder.path("cut.bin"), bytes.substr(0, keep));
    try {
      read_checkpoint(folder.path("cut.bin"));
      ADD_FAILURE() << "a checkpoint of " << keep << " bytes was read";
    } catch (const InputError& e) {
      EXPECT_TRUE(std::string(e.what()).find("cut short") != std::string::npos ||
                  std::string(e.what()).find("not a vesselmesh checkpoint") != std::string::npos)
          << e.what();
    }
  }
  test::write_bytes(folder.path("other.bin"), "mesh = \"pipe.msh\"\n" + std::string(200, 'x'));
  EXPECT_THROW(read_checkpoint(folder.path("other.bin")), InputError);
  test::write_bytes(folder.path("long.bin"), bytes + "x");
  EXPECT_THROW(read_checkpoint(folder.path("long.bin")), InputError);

  // A write that cannot be made leaves the old checkpoint whole (and nothing half-written).
  std::filesystem::permissions(folder.folder(), std::filesystem::perms::owner_read | std::filesystem::perms::owner_exec);
  const bool writable = [&] {  // root writes anyway: then this part says nothing
    std::FILE* f = std::fopen(folder.path("probe").c_str(), "w");
    if (f) std::fclose(f), std::filesystem::remove(folder.path("probe"));
    return f != nullptr;
  }();
  if (!writable) {
    Checkpoint later = c;
    later.flow.steps = 99;
    EXPECT_THROW(write_checkpoint(path, later), Error);
    EXPECT_EQ(read_checkpoint(path).flow.steps, 25);
  }
  std::filesystem::permissions(folder.folder(), std::filesystem::perms::owner_all);
  EXPECT_THROW(write_checkpoint(folder.path("no/such/folder/checkpoint.bin"), c), InputError);
  for (const std::string& name : folder.files()) EXPECT_EQ(name.find(".tmp"), std::string::npos) << name;
}

// The flow's fields in pieces (one per process, its own points by mesh number): placed back
// whole; a missing piece, one of another step or a point outside the mesh is an InputError.
TEST(Checkpoint, PiecesMakeTheFlowWhole) {
  const test::TemporaryFolder folder;
  const std::string path = folder.path("checkpoint.bin");
  Checkpoint c = sample_checkpoint();
  const FlowState whole = c.flow;
  c.pieces = 2;  // the fields in the pieces only
  c.flow.velocity.clear();
  c.flow.previous.clear();
  c.flow.kinematic_pressure.clear();
  write_checkpoint(path, c);
  const auto piece = [&](std::vector<int> points) {
    FlowState p;
    p.steps = whole.steps;
    p.time = whole.time;
    for (int m : points) {
      p.velocity.push_back(whole.velocity[m]);
      p.previous.push_back(whole.previous[m]);
      p.kinematic_pressure.push_back(whole.kinematic_pressure[m]);
    }
    p.points = std::move(points);
    return p;
  };
  write_checkpoint_piece(checkpoint_piece_path(path, whole.steps, 0), piece({1}));
  write_checkpoint_piece(checkpoint_piece_path(path, whole.steps, 1), piece({0}));
  const Checkpoint r = read_checkpoint(path);
  EXPECT_EQ(r.pieces, 2);
  EXPECT_TRUE(r.flow.velocity.empty());
  const FlowState both = read_checkpoint_pieces(path, r, {0, 1}, 2);
  EXPECT_EQ(both.points, (std::vector<int>{1, 0}));  // as the pieces hold them
  EXPECT_EQ(both.velocity, (std::vector<Vec3>{whole.velocity[1], whole.velocity[0]}));
  EXPECT_EQ(both.previous, (std::vector<Vec3>{whole.previous[1], whole.previous[0]}));
  EXPECT_EQ(both.kinematic_pressure, (std::vector<double>{whole.kinematic_pressure[1], whole.kinematic_pressure[0]}));
  EXPECT_EQ(both.steps, whole.steps);
  EXPECT_EQ(both.capacitor_pressure, whole.capacitor_pressure);
  const FlowState one = read_checkpoint_pieces(path, r, {0}, 2);  // a process keeps its own
  EXPECT_EQ(one.points, (std::vector<int>{0}));
  EXPECT_EQ(one.velocity, (std::vector<Vec3>{whole.velocity[0]}));
  const auto refused = [&](std::vector<int> wanted, int points) {
    try {
      read_checkpoint_pieces(path, read_checkpoint(path), wanted, points);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(refused({0}, 1).find("not in the mesh of 1 points"), std::string::npos) << refused({0}, 1);
  EXPECT_NE(refused({0, 2}, 3).find("no state for mesh point 2"), std::string::npos) << refused({0, 2}, 3);
  FlowState other = piece({0});
  other.steps = whole.steps + 1;
  write_checkpoint_piece(checkpoint_piece_path(path, whole.steps, 1), other);
  EXPECT_NE(refused({0}, 2).find("a piece of step"), std::string::npos) << refused({0}, 2);
  std::filesystem::remove(checkpoint_piece_path(path, whole.steps, 1));
  EXPECT_NE(refused({0}, 2).find("is missing"), std::string::npos) << refused({0}, 2);
}

// The time statistics' span in the checkpoint, their fields by point in the pieces (issue 47); a
// checkpoint of format 5, made before them, still reads (without them).
TEST(Checkpoint, PiecesKeepTheTimeStatistics) {
  const test::TemporaryFolder folder;
  const std::string path = folder.path("checkpoint.bin");
  Checkpoint c = sample_checkpoint();
  const FlowState whole = c.flow;
  c.pieces = 1;
  c.flow.velocity.clear();
  c.flow.previous.clear();
  c.flow.kinematic_pressure.clear();
  FlowStatistics kept;
  kept.add(0.2, 0.1, {Vec3(1, 2, 3), Vec3(4, 5, 6)}, {7.0, 8.0});
  kept.add(0.3, 0.1, {Vec3(3, 2, 1), Vec3(6, 5, 4)}, {9.0, 10.0});
  FlowStatistics::State own = kept.state();
  c.statistics.start = own.start;
  c.statistics.end = own.end;
  c.statistics.weight = own.weight;
  c.statistics.steps = own.steps;
  write_checkpoint(path, c);
  FlowState piece = whole;
  piece.points = {0, 1};
  write_checkpoint_piece(checkpoint_piece_path(path, whole.steps, 0), piece, own);
  const Checkpoint r = read_checkpoint(path);
  EXPECT_EQ(r.statistics.steps, 2);
  EXPECT_DOUBLE_EQ(r.statistics.start, 0.1);
  EXPECT_DOUBLE_EQ(r.statistics.weight, 0.2);
  FlowStatistics::State read;
  read_checkpoint_pieces(path, r, {0, 1}, 2, &read);
  EXPECT_EQ(read.points, (std::vector<int>{0, 1}));
  // At a process's local points (mesh numbers, in its order): the same statistics as never stopped.
  FlowStatistics resumed(statistics_at(read, {1, 0}, path));
  EXPECT_EQ(resumed.mean_velocity()[0], kept.mean_velocity()[1]);
  EXPECT_EQ(resumed.rms_velocity()[1], kept.rms_velocity()[0]);
  EXPECT_EQ(resumed.mean_pressure()[0], 9.0);
  EXPECT_THROW(statistics_at(read, {2}, path), InputError);

  // Format 5: the same bytes without the statistics (the checkpoint's last 28 bytes, the piece's three
  // empty fields' counts), its version 5.
  const auto as_format_5 = [](const std::string& file, size_t cut) {
    std::string bytes = io::read_file(file);
    bytes.resize(bytes.size() - cut);
    const uint32_t five = 5;
    std::memcpy(bytes.data() + bytes.find('\n') + 1, &five, sizeof five);  // the version after the magic line
    io::write_text(file, bytes);
  };
  Checkpoint none = c;
  none.statistics = {};
  write_checkpoint(path, none);
  write_checkpoint_piece(checkpoint_piece_path(path, whole.steps, 0), piece);
  as_format_5(path, 3 * sizeof(double) + sizeof(int));
  as_format_5(checkpoint_piece_path(path, whole.steps, 0), 3 * sizeof(uint64_t));
  const Checkpoint old = read_checkpoint(path);
  EXPECT_EQ(old.statistics.steps, 0);
  EXPECT_EQ(read_checkpoint_pieces(path, old, {0, 1}, 2, &read).velocity, whole.velocity);
  EXPECT_TRUE(read.mean_velocity.empty());
}

// A pipe's volume mesh in `folder`/pipe.msh and a pulsatile case on it ending at `steps` steps; its
// outlet an rcr end whose capacitor (R_d C = 4 ms, 2 steps) carries state across a restart.
std::string pipe_case(const test::TemporaryFolder& folder, int steps, const std::string& extra = "") {
  if (!std::filesystem::exists(folder.path("pipe.msh"))) {
    const TriMesh pipe = synth::cylinder({.radius = 1.5, .length = 6.0, .resolution = 0.45});
    const auto ends = analysis::open_ends(pipe);
    volume::VolumeOptions options;
    options.layer.layers = 2;
    options.inlet = ends[0].center.z() < ends[1].center.z() ? 0 : 1;
    io::write_msh(folder.path("pipe.msh"),
                  volume::build_volume(pipe, ends, std::vector<double>(pipe.points.size(), 1.5), options).mesh);
    test::write_bytes(folder.path("flow.csv"), "time,flow\n0,0.2\n0.02,0.6\n0.04,0.2\n");
  }
  const std::string path = folder.path(fmt::format("case_{}.toml", steps));
  test::write_bytes(path, fmt::format(R"(mesh = "pipe.msh"
length_unit = "mm"
[time]
dt = 0.002
end = {}
save_every = 4
initial = "stokes"
[[boundary]]
tag = "inlet"
type = "velocity"
waveform = "flow.csv"
[[boundary]]
tag = "outlet_1"
type = "rcr"
proximal_resistance = 2e7
distal_resistance = 8e7
capacitance = 5e-11
distal_pressure = 500.0
[[boundary]]
tag = "wall"
type = "wall"
[output]
checkpoint_every = 3
{})",
                                      0.002 * steps, extra));
  return path;
}

// A column of a run's log.csv by its header's name, a value a step (the test fails where it is missing).
std::vector<double> log_column(const std::string& path, const std::string& name) {
  std::istringstream log(io::read_file(path));
  std::string line;
  std::getline(log, line);
  std::vector<std::string> header;
  for (std::istringstream cells(line); std::getline(cells, line, ',');) header.push_back(line);
  const auto at = std::find(header.begin(), header.end(), name) - header.begin();
  std::vector<double> values;
  if (at == static_cast<long>(header.size())) {
    ADD_FAILURE() << path << " has no column " << name;
    return values;
  }
  while (std::getline(log, line)) {
    std::istringstream cells(line);
    std::string cell;
    for (long k = 0; k <= at && std::getline(cells, cell, ','); ++k) {}
    values.push_back(std::stod(cell));
  }
  return values;
}

// The last saved frame's velocity and pressure, and the indices.
struct Results {
  std::vector<double> velocity, pressure, tawss, osi;
};
Results results_in(const std::string& dir, int frame) {
  Results r;
  std::vector<Field> fields;
  io::read_vtu_volume(fmt::format("{}/fluid_{:06d}.vtu", dir, frame), &fields);
  for (const Field& f : fields) {
    if (f.name == "velocity") r.velocity = f.values;
    if (f.name == "pressure") r.pressure = f.values;
  }
  const io::SurfaceData indices = io::read_vtk_surface(dir + "/indices.vtp", io::VtkFormat::vtp);
  for (const Field& f : indices.point_data) {
    if (f.name == "tawss") r.tawss = f.values;
    if (f.name == "osi") r.osi = f.values;
  }
  return r;
}

double largest_difference(const std::vector<double>& a, const std::vector<double>& b) {
  EXPECT_EQ(a.size(), b.size());
  EXPECT_FALSE(a.empty());
  double worst = 0.0, scale = 0.0;
  for (size_t i = 0; i < std::min(a.size(), b.size()); ++i) {
    worst = std::max(worst, std::abs(a[i] - b[i]));
    scale = std::max(scale, std::abs(a[i]));
  }
  return scale > 0.0 ? worst / scale : worst;
}

// [output] fluid_every: the wall at every save, the fluid volume every fluid_every steps and at the
// last step (0: the last only); the .pvd files list what was written.
TEST(Simulate, SavesTheFluidVolumeEveryFluidEverySteps) {
  const test::TemporaryFolder folder;
  const auto listed = [](const std::string& pvd) {
    const std::string text = io::read_file(pvd);
    size_t n = 0;
    for (size_t at = text.find("<DataSet"); at != std::string::npos; at = text.find("<DataSet", at + 1)) ++n;
    return n;
  };
  // Saves at steps 4, 8 and 10 (the last); the fluid at 8 and 10.
  const SimulationSummary a = simulate(read_case(pipe_case(folder, 10, "fluid_every = 8")), folder.path("a"));
  EXPECT_EQ(a.saved, 3);
  EXPECT_EQ(listed(folder.path("a/wall.pvd")), 3u);
  EXPECT_EQ(listed(folder.path("a/fluid.pvd")), 2u);
  EXPECT_FALSE(std::filesystem::exists(folder.path("a/fluid_000000.vtu")));
  EXPECT_TRUE(std::filesystem::exists(folder.path("a/fluid_000001.vtu")));
  EXPECT_TRUE(std::filesystem::exists(folder.path("a/fluid_000002.vtu")));
  EXPECT_TRUE(std::filesystem::exists(folder.path("a/wall_000000.vtp")));
  EXPECT_NE(io::read_file(folder.path("a/fluid.pvd")).find("fluid_000002.vtu"), std::string::npos);
  // 0: the last step's only, the same field as with every save.
  const SimulationSummary b = simulate(read_case(pipe_case(folder, 10, "fluid_every = 0")), folder.path("b"));
  EXPECT_EQ(b.saved, 3);
  EXPECT_EQ(listed(folder.path("b/fluid.pvd")), 1u);
  EXPECT_FALSE(std::filesystem::exists(folder.path("b/fluid_000001.vtu")));
  const Results ra = results_in(folder.path("a"), 2), rb = results_in(folder.path("b"), 2);
  EXPECT_EQ(ra.velocity, rb.velocity);
  EXPECT_EQ(ra.pressure, rb.pressure);
}

// Issue 48: log.csv says per step how many of its solves built their preconditioner (the
// benchmarks' set-up count): a reused one builds at the first time step and then only where a
// solve took more than it should, one built every step says 1 every step; the iterations are the
// step's all.
TEST(Simulate, TheLogCountsThePreconditionersBuilt) {
  if (parallel::process_count() > 1) GTEST_SKIP() << "one process: each makes its own folder, the first writes the log";
  const test::TemporaryFolder folder;
  const auto column = [&](const std::string& run, const std::string& name) {
    return log_column(folder.path(run + "/log.csv"), name);
  };
  const SimulationSummary reused = simulate(read_case(pipe_case(folder, 8, "")), folder.path("reused"));
  const std::vector<double> built = column("reused", "preconditioners_built");
  ASSERT_EQ(built.size(), 8u);
  EXPECT_GE(built[0], 1);
  EXPECT_LT(std::accumulate(built.begin(), built.end(), 0.0), 8.0);  // reused at some steps
  const std::vector<double> iterations = column("reused", "linear_iterations");
  EXPECT_EQ(std::accumulate(iterations.begin(), iterations.end(), 0.0), reused.linear_iterations);
  simulate(read_case(pipe_case(folder, 8, "[solver]\nreuse_preconditioner = false")), folder.path("every"));
  for (double b : column("every", "preconditioners_built")) EXPECT_EQ(b, 1.0);
}

// Issue 49: the run's closing figures name their parts: the first step apart, the settled steps' mean
// as bench/flow_scaling.sh takes it (log.csv's steps 2..N), in the summary and summary.json.
TEST(Simulate, TheRunsFiguresNameTheirParts) {
  const test::TemporaryFolder folder;
  const SimulationSummary s = simulate(read_case(pipe_case(folder, 6, "")), folder.path("a"));
  EXPECT_EQ(s.settled_steps, 5);
  EXPECT_GT(s.first_step_seconds, 0.0);
  EXPECT_GT(s.settled_step_seconds, 0.0);
  const std::vector<double> seconds = log_column(folder.path("a/log.csv"), "seconds");
  ASSERT_EQ(seconds.size(), 6u);
  const double sum = std::accumulate(seconds.begin() + 1, seconds.end(), 0.0);
  const int rows = 5;
  EXPECT_NEAR(s.settled_step_seconds, sum / rows, 1e-3 * s.settled_step_seconds + 1e-4);  // the log's 4 digits
  const nlohmann::json j = nlohmann::json::parse(io::read_file(folder.path("a/summary.json")));
  EXPECT_EQ(j["settled_steps"], 5);
  EXPECT_DOUBLE_EQ(j["settled_step_seconds"].get<double>(), s.settled_step_seconds);
  EXPECT_DOUBLE_EQ(j["first_step_seconds"].get<double>(), s.first_step_seconds);
  EXPECT_TRUE(j.contains("initial_state_seconds"));
  EXPECT_NEAR(j["settled_seconds_per_step_per_million_dofs"].get<double>(), s.settled_step_seconds / (s.dofs * 1e-6),
              1e-9);
}

// Issue 48: a case aiming at a CFL number (cfl_target) chooses its steps' lengths: from its dt
// they grow by at most 1.25x a step until the largest CFL number is about the target, the last
// lands on the end; fewer steps than the fixed dt's; summary.json says what it did; a checkpoint
// keeps the next step's length and the last one's, and a restart goes on with them.
TEST(Simulate, StepsChosenForACflTargetGrowToItAndLandOnTheEnd) {
  const test::TemporaryFolder folder;
  FlowCase fc = read_case(pipe_case(folder, 12));
  const SimulationSummary fixed = simulate(fc, folder.path("fixed"));
  // The fixed steps' largest CFL number, from their log.
  const auto rows = [](const std::string& log_path) {
    std::vector<std::array<double, 3>> out;  // time, max_cfl, linear iterations
    const std::vector<double> time = log_column(log_path, "time_s"), cfl = log_column(log_path, "max_cfl"),
                              iterations = log_column(log_path, "linear_iterations");
    for (size_t k = 0; k < time.size() && k < cfl.size() && k < iterations.size(); ++k)
      out.push_back({time[k], cfl[k], iterations[k]});
    return out;
  };
  const double fixed_cfl = rows(folder.path("fixed/log.csv")).back()[1];
  ASSERT_GT(fixed_cfl, 0.0);
  fc.cfl_target = 3.0 * fixed_cfl;
  const SimulationSummary chosen = simulate(fc, folder.path("chosen"));
  EXPECT_EQ(chosen.status, "completed");
  EXPECT_LT(chosen.steps, fixed.steps);
  const auto steps = rows(folder.path("chosen/log.csv"));
  ASSERT_EQ(static_cast<int>(steps.size()), chosen.steps);
  EXPECT_NEAR(steps.back()[0], fc.end, 1e-9);
  double before = fc.dt, time = 0.0;
  for (size_t k = 0; k < steps.size(); ++k) {
    const double dt = steps[k][0] - time;
    time = steps[k][0];
    std::printf("step %zu: dt %.4g ms, cfl %.3g, its %g\n", k + 1, 1e3 * dt, steps[k][1], steps[k][2]);
    if (k + 1 < steps.size()) {
      EXPECT_LE(dt, 1.25 * before * (1 + 1e-9)) << "step " << k + 1;
    }
    EXPECT_LE(steps[k][1], 1.3 * fc.cfl_target) << "step " << k + 1;
    before = dt;
  }
  EXPECT_NEAR(chosen.least_time_step, fc.dt, 1e-12);
  EXPECT_GT(chosen.largest_time_step, 2.0 * fc.dt);
  const auto j = nlohmann::json::parse(io::read_file(folder.path("chosen/summary.json")));
  EXPECT_DOUBLE_EQ(j["time_steps"]["cfl_target"].get<double>(), fc.cfl_target);
  EXPECT_DOUBLE_EQ(j["time_steps"]["largest_s"].get<double>(), chosen.largest_time_step);
  EXPECT_NEAR(j["time_steps"]["simulated_s"].get<double>(), fc.end, 1e-12);
  EXPECT_FALSE(nlohmann::json::parse(io::read_file(folder.path("fixed/summary.json"))).contains("time_steps"));
  // The checkpoint at the end: the last step's length and the next one's.
  const Checkpoint c = read_checkpoint(folder.path("chosen/checkpoint.bin"));
  EXPECT_NEAR(c.flow.last_time_step, steps.back()[0] - steps[steps.size() - 2][0], 1e-9);
  EXPECT_GT(c.flow.time_step, 0.0);
  // Extended by a restart: it goes on from there to the new end, with the steps' lengths kept.
  FlowCase longer = fc;
  longer.end = 2.0 * fc.end;
  const SimulationSummary more = simulate(longer, folder.path("chosen"), "", silent_reporter(), /*restart=*/true);
  EXPECT_EQ(more.status, "completed");
  const auto all = rows(folder.path("chosen/log.csv"));
  ASSERT_GT(all.size(), steps.size());
  EXPECT_NEAR(all.back()[0], longer.end, 1e-9);
  EXPECT_NEAR(all[steps.size()][0] - steps.back()[0], c.flow.time_step, 1e-9);  // the log's 9 digits
}

// Issue 29: a run stopped at step 8 of 12 (a case ending there, at a save) and restarted from its
// checkpoint with the whole case gives the run that was not stopped: the same saved frames,
// fields, indices and log, to the linear solver's tolerance.
TEST(Simulate, ARestartGoesOnAsIfTheRunHadNotStopped) {
  const test::TemporaryFolder folder;
  const FlowCase whole = read_case(pipe_case(folder, 12));
  const SimulationSummary a = simulate(whole, folder.path("whole"));
  EXPECT_EQ(a.status, "completed");
  EXPECT_EQ(a.steps, 12);

  const SimulationSummary first = simulate(read_case(pipe_case(folder, 8)), folder.path("parts"));
  EXPECT_EQ(first.steps, 8);
  const Checkpoint at_eight = read_checkpoint(folder.path("parts/checkpoint.bin"));
  EXPECT_EQ(at_eight.flow.steps, 8);  // written at the run's last step
  const SimulationSummary b = simulate(whole, folder.path("parts"), "", silent_reporter(), /*restart=*/true);
  EXPECT_EQ(b.status, "completed");
  EXPECT_EQ(b.steps, 12);
  EXPECT_EQ(b.saved, a.saved);
  EXPECT_EQ(read_checkpoint(folder.path("parts/checkpoint.bin")).flow.steps, 12);

  const Results ra = results_in(folder.path("whole"), a.saved - 1), rb = results_in(folder.path("parts"), b.saved - 1);
  EXPECT_LT(largest_difference(ra.velocity, rb.velocity), 1e-5);
  EXPECT_LT(largest_difference(ra.pressure, rb.pressure), 1e-5);
  EXPECT_LT(largest_difference(ra.tawss, rb.tawss), 1e-5);
  // OSI (in [0, 0.5]) absolutely: it is nearly 0 in this pipe, so that relative to its largest value
  // the solver's tolerance shows.
  ASSERT_EQ(ra.osi.size(), rb.osi.size());
  double osi_difference = 0.0;
  for (size_t i = 0; i < ra.osi.size(); ++i) osi_difference = std::max(osi_difference, std::abs(ra.osi[i] - rb.osi[i]));
  EXPECT_LT(osi_difference, 1e-5) << "largest OSI " << *std::max_element(ra.osi.begin(), ra.osi.end());
  ASSERT_EQ(a.ends.size(), 3u);
  ASSERT_EQ(b.ends.size(), 3u);
  EXPECT_GT(a.ends[1].capacitor_pressure, 500.0);
  EXPECT_NEAR(b.ends[1].capacitor_pressure, a.ends[1].capacitor_pressure, 1e-6 * a.ends[1].capacitor_pressure);
  const auto summary = nlohmann::json::parse(io::read_file(folder.path("parts/summary.json")));
  EXPECT_EQ(summary["ends"][1]["type"], "rcr");
  EXPECT_NEAR(summary["ends"][1]["capacitor_pressure_Pa"].get<double>(), b.ends[1].capacitor_pressure, 1e-9);
  // The log: the same steps, times and (to 9 digits, within the tolerance) flows.
  const std::string la = io::read_file(folder.path("whole/log.csv")), lb = io::read_file(folder.path("parts/log.csv"));
  EXPECT_EQ(std::count(la.begin(), la.end(), '\n'), std::count(lb.begin(), lb.end(), '\n'));
  EXPECT_EQ(io::read_file(folder.path("whole/fluid.pvd")), io::read_file(folder.path("parts/fluid.pvd")));
  // A CSV per end (not the wall), the restart's too: every step, flux in m3/s and mL/s, pressures
  // in Pa and mmHg, the rcr end's capacitor; its last row the run's end.
  EXPECT_FALSE(std::filesystem::exists(folder.path("parts/ends/wall.csv")));
  EXPECT_TRUE(std::filesystem::exists(folder.path("parts/ends/inlet.csv")));
  const std::string outlet = io::read_file(folder.path("parts/ends/outlet_1.csv"));
  EXPECT_EQ(outlet.substr(0, outlet.find('\n')),
            "step,time_s,flux_m3_s,flux_mL_s,mean_pressure_Pa,mean_pressure_mmHg,capacitor_pressure_Pa,"
            "capacitor_pressure_mmHg");
  EXPECT_EQ(std::count(outlet.begin(), outlet.end(), '\n'), 13);  // the header and 12 steps
  const std::string last = outlet.substr(outlet.rfind('\n', outlet.size() - 2) + 1);
  double step = 0, time = 0, flux = 0, flux_ml = 0, p = 0, p_mmhg = 0, pc = 0, pc_mmhg = 0;
  ASSERT_EQ(std::sscanf(last.c_str(), "%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf", &step, &time, &flux, &flux_ml, &p, &p_mmhg,
                        &pc, &pc_mmhg),
            8)
      << last;
  EXPECT_EQ(step, 12);
  EXPECT_NEAR(time, 0.024, 1e-12);
  EXPECT_NEAR(flux, b.ends[1].flux, 1e-8 * std::abs(b.ends[1].flux));
  EXPECT_NEAR(flux_ml, 1e6 * flux, 1e-8 * std::abs(flux_ml));
  EXPECT_NEAR(p_mmhg, p / 133.322387415, 1e-8 * std::abs(p_mmhg));
  EXPECT_NEAR(pc, b.ends[1].capacitor_pressure, 1e-8 * pc);
  EXPECT_NEAR(pc_mmhg, pc / 133.322387415, 1e-8 * pc_mmhg);
  EXPECT_THROW(end_logs("step,time_s\n1,0.1\n", {"outlet"}), InternalError);

  // Another mesh or time step: refused, naming the checkpoint.
  FlowCase other_dt = read_case(pipe_case(folder, 14));
  other_dt.dt = 0.001;
  try {
    simulate(other_dt, folder.path("parts"), "", silent_reporter(), true);
    ADD_FAILURE() << "a checkpoint of another time step was taken";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("another mesh or time step"), std::string::npos) << e.what();
  }
  EXPECT_THROW(simulate(whole, folder.path("nowhere"), "", silent_reporter(), true), InputError);
}

// A restart that extends a run moves the hemodynamic indices to the new last period: where that
// starts after the checkpoint or at it, the indices of the run that was not stopped, over the same
// window; where it started before (its first samples inside sums begun earlier), the sums go on,
// the summary says over which span and a warning why.
TEST(Simulate, ARestartThatExtendsTheRunTakesTheIndicesOverTheNewLastPeriod) {
  const test::TemporaryFolder folder;
  const auto with_period = [&](int steps) {
    FlowCase c = read_case(pipe_case(folder, steps));
    c.period = 0.008;  // 4 steps: the indices over the last 4
    return c;
  };
  const FlowCase whole = with_period(16);
  const SimulationSummary a = simulate(whole, folder.path("whole"));
  EXPECT_NEAR(a.indices_start, 0.024, 1e-9);
  EXPECT_NEAR(a.indices_end, 0.032, 1e-9);
  const Results ra = results_in(folder.path("whole"), a.saved - 1);
  for (const int first_steps : {8, 12}) {  // the checkpoint at t = 0.016 s (before the window), 0.024 s (at it)
    SCOPED_TRACE(first_steps);
    const std::string dir = folder.path(fmt::format("from_{}", first_steps));
    const SimulationSummary first = simulate(with_period(first_steps), dir);
    EXPECT_NEAR(first.indices_start, 0.002 * first_steps - 0.008, 1e-9);
    const SimulationSummary b = simulate(whole, dir, "", silent_reporter(), /*restart=*/true);
    EXPECT_NEAR(b.indices_start, 0.024, 1e-9);
    EXPECT_NEAR(b.indices_end, 0.032, 1e-9);
    // To the linear solver's tolerance (the restart builds its preconditioner again and starts without the
    // solutions it kept); a window short of its first sample would be a quarter off.
    const Results rb = results_in(dir, b.saved - 1);
    EXPECT_LT(largest_difference(ra.tawss, rb.tawss), 1e-4);
    const auto summary = nlohmann::json::parse(io::read_file(dir + "/summary.json"));
    EXPECT_NEAR(summary["indices"]["start_s"].get<double>(), 0.024, 1e-9);
  }
  // From t = 0.028 s: the window's first samples are in the sums begun at 0.020 s.
  const std::string dir = folder.path("from_14");
  EXPECT_NEAR(simulate(with_period(14), dir).indices_start, 0.020, 1e-9);
  const test::Warnings warnings;
  const SimulationSummary c = simulate(whole, dir, "", warnings, /*restart=*/true);
  EXPECT_NEAR(c.indices_start, 0.020, 1e-9);
  EXPECT_NEAR(c.indices_end, 0.032, 1e-9);
  EXPECT_NE(warnings.text.find("the hemodynamic indices will cover t = 0.02 to 0.032 s, not their window (0.024 "
                               "to 0.032 s: the last period"),
            std::string::npos)
      << warnings.text;
}

// Issue 47: a disturbed inflow is a function of the place and the time, so a run stopped and
// restarted goes on with it as the run that was not stopped (to the linear solver's tolerance); the
// disturbance changes the flow (against the same run without it).
TEST(Simulate, ARestartGoesOnWithTheSameDisturbedInflow) {
  const test::TemporaryFolder folder;
  const auto disturbed = [&](int steps) {
    FlowCase c = read_case(pipe_case(folder, steps));
    EXPECT_EQ(c.boundaries[0].tag, "inlet");
    c.boundaries[0].perturbation = 0.05;
    return c;
  };
  const FlowCase whole = disturbed(12);
  const SimulationSummary a = simulate(whole, folder.path("whole"));
  simulate(disturbed(8), folder.path("parts"));
  const SimulationSummary b = simulate(whole, folder.path("parts"), "", silent_reporter(), /*restart=*/true);
  EXPECT_EQ(b.steps, 12);
  const Results ra = results_in(folder.path("whole"), a.saved - 1), rb = results_in(folder.path("parts"), b.saved - 1);
  EXPECT_LT(largest_difference(ra.velocity, rb.velocity), 1e-5);
  const SimulationSummary q = simulate(read_case(pipe_case(folder, 12)), folder.path("quiet"));
  EXPECT_GT(largest_difference(ra.velocity, results_in(folder.path("quiet"), q.saved - 1).velocity), 1e-3);
}

}  // namespace
}  // namespace vesselmesh::flow
