#include "flow/checkpoint.h"

#include "io/atomic_file.h"
#include "io/bytes.h"
#include "mesh/error.h"

#include <fmt/format.h>

#include <cstring>
#include <fstream>

namespace vesselmesh::flow {
namespace {

constexpr char kMagic[] = "vesselmesh checkpoint\n";
constexpr uint32_t kVersion = 3;  // 2: the rcr ends' capacitor pressures; 3: the indices' mesh points

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
  io::write_atomically(path, [&](const std::string& temporary) {
    std::ofstream out(temporary, std::ios::binary);
    out.write(w.text().data(), static_cast<std::streamsize>(w.text().size()));
    if (!out) throw InputError(fmt::format("{}: cannot write the checkpoint", path));
  });
}

Checkpoint read_checkpoint(const std::string& path) {
  io::ByteReader r(io::read_file(path), [&](size_t at, size_t size) {
    throw InputError(fmt::format("{}: the checkpoint is cut short (at byte {} of {}): it was not written whole; "
                                 "run the case again without --restart",
                                 path, at, size));
  });
  char magic[sizeof kMagic - 1];
  r.bytes(magic, sizeof magic);
  if (std::memcmp(magic, kMagic, sizeof magic) != 0)
    throw InputError(fmt::format("{}: not a vesselmesh checkpoint", path));
  const auto version = r.value<uint32_t>();
  if (version != kVersion)
    throw InputError(fmt::format("{}: a checkpoint of format {} (this program reads {}): run the case again", path,
                                 version, kVersion));
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
  if (c.index_points.size() != s.last.size())
    throw InputError(fmt::format("{}: the checkpoint's indices do not fit their points: not one of ours", path));
  if (!r.done()) throw InputError(fmt::format("{}: the checkpoint has bytes past its end: not one of ours", path));
  return c;
}

}  // namespace vesselmesh::flow
