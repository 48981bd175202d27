#include "flow/checkpoint.h"

#include "io/atomic_file.h"
#include "io/bytes.h"
#include "mesh/error.h"

#include <fmt/format.h>

#include <algorithm>
#include <cstring>
#include <filesystem>

namespace vesselmesh::flow {
namespace {

constexpr char kMagic[] = "vesselmesh checkpoint\n";
// 2: the rcr ends' capacitor pressures; 3: the indices' mesh points; 4: pieces; 5: the steps' lengths;
// 6: the time statistics (5 still read: a run its program's update stopped goes on, keeping none)
constexpr uint32_t kVersion = 6;
constexpr uint32_t kOldestRead = 5;

constexpr char kPieceMagic[] = "vesselmesh checkpoint piece\n";

// A checkpoint file (`magic`: the checkpoint's or a piece's) of a format this program reads, past its
// header, and that format; its reads cut short, another file or another format are InputErrors naming it.
template <size_t N>
std::pair<io::ByteReader, uint32_t> open_checkpoint_file(const std::string& path, const char (&magic)[N]) {
  io::ByteReader r(io::read_file(path), [path](size_t at, size_t size) {
    throw InputError(fmt::format("{}: the checkpoint is cut short (at byte {} of {}): it was not written whole; "
                                 "run the case again without --restart",
                                 path, at, size));
  });
  char read[N - 1];
  r.bytes(read, sizeof read);
  if (std::memcmp(read, magic, sizeof read) != 0)
    throw InputError(fmt::format("{}: not a vesselmesh checkpoint", path));
  const auto version = r.value<uint32_t>();
  if (version < kOldestRead || version > kVersion)
    throw InputError(fmt::format("{}: a checkpoint of format {} (this program reads {} to {}): run the case again",
                                 path, version, kOldestRead, kVersion));
  return {std::move(r), version};
}

// FNV-1a over bytes.
struct Hash {
  uint64_t value = 1469598103934665603ull;
  void add(const void* data, size_t bytes) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (size_t i = 0; i < bytes; ++i) value = (value ^ p[i]) * 1099511628211ull;
  }
  template <typename T>
  void add_vector(const std::vector<T>& v) {
    const uint64_t n = v.size();
    add(&n, sizeof n);
    if (n) add(v.data(), n * sizeof(T));
  }
};

}  // namespace

uint64_t run_fingerprint(const TetMesh& mesh, double dt) {
  Hash h;
  h.add_vector(mesh.points);
  h.add_vector(mesh.tets);
  h.add_vector(mesh.prisms);
  h.add_vector(mesh.boundary);
  h.add_vector(mesh.boundary_tags);
  h.add(&dt, sizeof dt);
  return h.value;
}

void write_checkpoint(const std::string& path, const Checkpoint& c) {
  io::ByteWriter w;
  w.bytes(kMagic, sizeof kMagic - 1);
  w.value(kVersion);
  w.value(c.fingerprint);
  w.value(c.flow.time);
  w.value(c.flow.steps);
  w.vector(c.flow.velocity);
  w.vector(c.flow.previous);
  w.vector(c.flow.kinematic_pressure);
  w.vector(c.flow.capacitor_pressure);
  w.value(c.saved);
  w.value(c.linear_iterations);
  w.string(c.log);
  for (const auto* files : {&c.fluid_files, &c.wall_files}) {
    w.value<uint64_t>(files->size());
    for (const auto& [time, name] : *files) {
      w.value(time);
      w.string(name);
    }
  }
  const post::WssIndexAccumulator::State& s = c.indices;
  w.value(s.samples);
  w.value(s.start);
  w.value(s.last_time);
  w.vector(s.last);
  w.vector(s.integral);
  w.vector(s.magnitude_integral);
  w.vector(s.change);
  w.vector(c.index_points);
  w.value(c.pieces);
  w.value(c.flow.time_step);
  w.value(c.flow.last_time_step);
  w.value(c.statistics.start);
  w.value(c.statistics.end);
  w.value(c.statistics.weight);
  w.value(c.statistics.steps);
  io::write_text(path, w.text());
}

Checkpoint read_checkpoint(const std::string& path) {
  auto [r, version] = open_checkpoint_file(path, kMagic);
  Checkpoint c;
  c.fingerprint = r.value<uint64_t>();
  c.flow.time = r.value<double>();
  c.flow.steps = r.value<int>();
  c.flow.velocity = r.vector<Vec3>();
  c.flow.previous = r.vector<Vec3>();
  c.flow.kinematic_pressure = r.vector<double>();
  c.flow.capacitor_pressure = r.vector<double>();
  c.saved = r.value<int>();
  c.linear_iterations = r.value<int>();
  c.log = r.string();
  for (auto* files : {&c.fluid_files, &c.wall_files}) {
    const auto n = r.value<uint64_t>();
    for (uint64_t k = 0; k < n; ++k) {
      const double time = r.value<double>();
      files->emplace_back(time, r.string());
    }
  }
  post::WssIndexAccumulator::State& s = c.indices;
  s.samples = r.value<int>();
  s.start = r.value<double>();
  s.last_time = r.value<double>();
  s.last = r.vector<Vec3>();
  s.integral = r.vector<Vec3>();
  s.magnitude_integral = r.vector<double>();
  s.change = r.vector<double>();
  c.index_points = r.vector<int>();
  c.pieces = r.value<int>();
  c.flow.time_step = r.value<double>();
  c.flow.last_time_step = r.value<double>();
  if (version >= 6) {
    c.statistics.start = r.value<double>();
    c.statistics.end = r.value<double>();
    c.statistics.weight = r.value<double>();
    c.statistics.steps = r.value<int>();
  }
  if (c.index_points.size() != s.last.size())
    throw InputError(fmt::format("{}: the checkpoint's indices do not fit their points: not one of ours", path));
  if (!r.done()) throw InputError(fmt::format("{}: the checkpoint has bytes past its end: not one of ours", path));
  return c;
}

std::string checkpoint_piece_path(const std::string& path, int steps, int piece) {
  return fmt::format("{}.{:06d}.{}", path, steps, piece);
}


void write_checkpoint_piece(const std::string& path, const FlowState& own, const FlowStatistics::State& statistics) {
  io::ByteWriter w;
  w.bytes(kPieceMagic, sizeof kPieceMagic - 1);
  w.value(kVersion);
  w.value(own.steps);
  w.value(own.time);
  w.vector(own.points);
  w.vector(own.velocity);
  w.vector(own.previous);
  w.vector(own.kinematic_pressure);
  w.vector(statistics.mean_velocity);
  w.vector(statistics.squares);
  w.vector(statistics.mean_pressure);
  io::write_text(path, w.text());
}

FlowState read_checkpoint_pieces(const std::string& path, const Checkpoint& c, const std::vector<int>& wanted,
                                 int mesh_points, FlowStatistics::State* statistics) {
  if (statistics) {
    *statistics = c.statistics;
    statistics->points.clear();
  }
  FlowState flow;
  flow.time = c.flow.time;
  flow.steps = c.flow.steps;
  flow.time_step = c.flow.time_step;
  flow.last_time_step = c.flow.last_time_step;
  flow.capacitor_pressure = c.flow.capacitor_pressure;
  std::vector<char> found(wanted.size(), 0);
  for (int k = 0; k < c.pieces; ++k) {
    const std::string piece = checkpoint_piece_path(path, c.flow.steps, k);
    if (!std::filesystem::exists(piece))
      throw InputError(fmt::format("{}: the checkpoint's piece {} is missing: run the case without --restart", path,
                                   piece));
    auto [r, version] = open_checkpoint_file(piece, kPieceMagic);
    const int steps = r.value<int>();
    r.value<double>();
    if (steps != c.flow.steps)
      throw InputError(fmt::format("{}: a piece of step {}, the checkpoint is of step {}", piece, steps, c.flow.steps));
    const std::vector<int> at = r.vector<int>();
    const std::vector<Vec3> velocity = r.vector<Vec3>(), previous = r.vector<Vec3>();
    const std::vector<double> pressure = r.vector<double>();
    std::vector<Vec3> mean, squares;
    std::vector<double> mean_pressure;
    if (version >= 6) {
      mean = r.vector<Vec3>();
      squares = r.vector<Vec3>();
      mean_pressure = r.vector<double>();
    }
    const bool kept = c.statistics.steps > 0;  // the run kept statistics: every piece holds them
    const size_t kept_size = kept ? at.size() : 0;
    if (velocity.size() != at.size() || previous.size() != at.size() || pressure.size() != at.size() ||
        mean.size() != kept_size || squares.size() != kept_size || mean_pressure.size() != kept_size || !r.done())
      throw InputError(fmt::format("{}: the piece's fields do not fit its points: not one of ours", piece));
    for (size_t i = 0; i < at.size(); ++i) {
      if (at[i] < 0 || at[i] >= mesh_points)
        throw InputError(fmt::format("{}: point {} is not in the mesh of {} points: a checkpoint of another mesh",
                                     piece, at[i], mesh_points));
      const auto it = std::lower_bound(wanted.begin(), wanted.end(), at[i]);
      if (it == wanted.end() || *it != at[i] || found[it - wanted.begin()]) continue;
      found[it - wanted.begin()] = 1;
      flow.points.push_back(at[i]);
      flow.velocity.push_back(velocity[i]);
      flow.previous.push_back(previous[i]);
      flow.kinematic_pressure.push_back(pressure[i]);
      if (statistics && kept) {
        statistics->points.push_back(at[i]);
        statistics->mean_velocity.push_back(mean[i]);
        statistics->squares.push_back(squares[i]);
        statistics->mean_pressure.push_back(mean_pressure[i]);
      }
    }
  }
  const auto missing = std::find(found.begin(), found.end(), 0);
  if (missing != found.end())
    throw InputError(fmt::format("{}: its pieces have no state for mesh point {}: run the case without --restart", path,
                                 wanted[missing - found.begin()]));
  return flow;
}

}  // namespace vesselmesh::flow
