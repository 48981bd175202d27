#include "flow/checkpoint.h"

#include "io/atomic_file.h"
#include "mesh/error.h"

#include <fmt/format.h>

#include <cstring>
#include <fstream>

namespace vesselmesh::flow {
namespace {

constexpr char kMagic[] = "vesselmesh checkpoint\n";
constexpr uint32_t kVersion = 2;  // 2: the rcr ends' capacitor pressures

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

class Writer {
 public:
  void bytes(const void* data, size_t n) { text_.append(static_cast<const char*>(data), n); }
  template <typename T>
  void value(const T& v) {
    bytes(&v, sizeof v);
  }
  template <typename T>
  void vector(const std::vector<T>& v) {
    value<uint64_t>(v.size());
    if (!v.empty()) bytes(v.data(), v.size() * sizeof(T));
  }
  void string(const std::string& s) {
    value<uint64_t>(s.size());
    bytes(s.data(), s.size());
  }
  const std::string& text() const { return text_; }

 private:
  std::string text_;
};

class Reader {
 public:
  Reader(std::string text, std::string path) : text_(std::move(text)), path_(std::move(path)) {}
  void bytes(void* data, size_t n) {
    if (n == 0) return;
    if (n > text_.size() - at_)
      throw InputError(fmt::format("{}: the checkpoint is cut short (at byte {} of {}): it was not written whole; "
                                   "run the case again without --restart",
                                   path_, at_, text_.size()));
    std::memcpy(data, text_.data() + at_, n);
    at_ += n;
  }
  template <typename T>
  T value() {
    T v;
    bytes(&v, sizeof v);
    return v;
  }
  template <typename T>
  std::vector<T> vector() {
    const uint64_t n = value<uint64_t>();
    if (n > (text_.size() - at_) / sizeof(T)) bytes(nullptr, text_.size() - at_ + 1);  // too long: cut short
    std::vector<T> v(n);
    if (n) bytes(v.data(), n * sizeof(T));
    return v;
  }
  std::string string() {
    const uint64_t n = value<uint64_t>();
    if (n > text_.size() - at_) bytes(nullptr, text_.size() - at_ + 1);
    std::string s(n, '\0');
    if (n) bytes(s.data(), n);
    return s;
  }
  bool done() const { return at_ == text_.size(); }

 private:
  std::string text_, path_;
  size_t at_ = 0;
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
  Writer w;
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
  io::write_atomically(path, [&](const std::string& temporary) {
    std::ofstream out(temporary, std::ios::binary);
    out.write(w.text().data(), static_cast<std::streamsize>(w.text().size()));
    if (!out) throw InputError(fmt::format("{}: cannot write the checkpoint", path));
  });
}

Checkpoint read_checkpoint(const std::string& path) {
  Reader r(io::read_file(path), path);
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
  if (!r.done()) throw InputError(fmt::format("{}: the checkpoint has bytes past its end: not one of ours", path));
  return c;
}

}  // namespace vesselmesh::flow
