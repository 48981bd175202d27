#include "post/fluid_sample.h"

#include "io/atomic_file.h"
#include "io/vtk_formats.h"
#include "mesh/error.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>

namespace vesselmesh::post {
namespace {

constexpr double kTolerance = 1e-9;  // of a barycentric weight: points on faces belong to both sides

}  // namespace

TetLocator::TetLocator(const TetMesh& mesh) : points_(mesh.points), tets_(mesh::all_tetrahedra(mesh)) {
  if (tets_.empty()) throw InputError("the mesh has no tetrahedra to look points up in");
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::max()), hi = -lo;
  double volume = 0.0;
  for (const Tet& t : tets_) {
    for (int v : t) lo = lo.cwiseMin(points_[v]), hi = hi.cwiseMax(points_[v]);
    volume += std::abs(mesh::tet_volume6(points_[t[0]], points_[t[1]], points_[t[2]], points_[t[3]])) / 6.0;
  }
  // Buckets about twice a mean tetrahedron's size, no more of them than tetrahedra times four.
  const Vec3 extent = (hi - lo).cwiseMax(1e-12);
  cell_ = std::max(2.0 * std::cbrt(volume / tets_.size()), std::cbrt(extent.prod() / (4.0 * tets_.size())));
  origin_ = lo;
  for (int k = 0; k < 3; ++k) dims_[k] = std::max(1, static_cast<int>(std::ceil(extent[k] / cell_)));
  const auto bucket_range = [&](const Tet& t, std::array<int, 3>& from, std::array<int, 3>& to) {
    Vec3 a = points_[t[0]], b = a;
    for (int v : t) a = a.cwiseMin(points_[v]), b = b.cwiseMax(points_[v]);
    for (int k = 0; k < 3; ++k) {
      from[k] = std::clamp(static_cast<int>(std::floor((a[k] - origin_[k]) / cell_)), 0, dims_[k] - 1);
      to[k] = std::clamp(static_cast<int>(std::floor((b[k] - origin_[k]) / cell_)), 0, dims_[k] - 1);
    }
  };
  const size_t buckets = size_t(dims_[0]) * dims_[1] * dims_[2];
  bucket_start_.assign(buckets + 1, 0);
  for (int pass = 0; pass < 2; ++pass) {
    std::vector<int> fill(bucket_start_.begin(), bucket_start_.end() - 1);
    if (pass == 1) bucket_tets_.resize(bucket_start_.back());
    for (size_t i = 0; i < tets_.size(); ++i) {
      std::array<int, 3> from{}, to{};
      bucket_range(tets_[i], from, to);
      for (int z = from[2]; z <= to[2]; ++z)
        for (int y = from[1]; y <= to[1]; ++y)
          for (int x = from[0]; x <= to[0]; ++x) {
            const size_t b = (size_t(z) * dims_[1] + y) * dims_[0] + x;
            if (pass == 0) ++bucket_start_[b + 1];
            else bucket_tets_[fill[b]++] = static_cast<int>(i);
          }
    }
    if (pass == 0)
      for (size_t b = 0; b < buckets; ++b) bucket_start_[b + 1] += bucket_start_[b];
  }
}

std::optional<TetLocator::Hit> TetLocator::locate(const Vec3& p) const {
  std::array<int, 3> at{};
  for (int k = 0; k < 3; ++k) {
    const double u = (p[k] - origin_[k]) / cell_;
    if (!(u >= -1e-9 * dims_[k] && u <= dims_[k] * (1.0 + 1e-9))) return std::nullopt;
    at[k] = std::clamp(static_cast<int>(std::floor(u)), 0, dims_[k] - 1);
  }
  const size_t b = (size_t(at[2]) * dims_[1] + at[1]) * dims_[0] + at[0];
  for (int i = bucket_start_[b]; i < bucket_start_[b + 1]; ++i) {
    const Tet& t = tets_[bucket_tets_[i]];
    const Vec3 &a = points_[t[0]], &c1 = points_[t[1]], &c2 = points_[t[2]], &c3 = points_[t[3]];
    const double whole = mesh::tet_volume6(a, c1, c2, c3);
    if (whole == 0.0) continue;
    Hit hit;
    hit.tet = bucket_tets_[i];
    hit.weights = {mesh::tet_volume6(p, c1, c2, c3) / whole, mesh::tet_volume6(a, p, c2, c3) / whole,
                   mesh::tet_volume6(a, c1, p, c3) / whole, mesh::tet_volume6(a, c1, c2, p) / whole};
    if (*std::min_element(hit.weights.begin(), hit.weights.end()) >= -kTolerance) return hit;
  }
  return std::nullopt;
}

namespace {

// A point array of a fluid file: vectors or scalars (empty where the file has none of that name and size).
std::vector<Vec3> point_vectors(const std::vector<Field>& fields, const std::string& name, size_t points) {
  const Field* f = find_field(fields, name, 3, points);
  return f ? f->vectors() : std::vector<Vec3>{};
}
std::vector<double> point_scalars(const std::vector<Field>& fields, const std::string& name, size_t points) {
  const Field* f = find_field(fields, name, 1, points);
  return f ? f->values : std::vector<double>{};
}

}  // namespace

FluidField read_fluid_frame(const WallFrame& frame) {
  std::vector<Field> fields;
  FluidField field;
  field.mesh = io::read_vtu_volume(frame.file, &fields);
  field.time = frame.time;
  field.velocity = point_vectors(fields, "velocity", field.mesh.points.size());
  field.pressure = point_scalars(fields, "pressure", field.mesh.points.size());
  if (field.velocity.empty() || field.pressure.empty())
    throw InputError(fmt::format("{}: has no point data `velocity` (3 components) and `pressure`; is it a fluid "
                                 "file of 'vesselmesh simulate'?",
                                 frame.file));
  return field;
}

FluidStatistics read_fluid_statistics(const std::string& directory) {
  const std::string summary = directory + "/summary.json";
  nlohmann::json kept;
  try {
    if (std::filesystem::exists(summary))
      kept = nlohmann::json::parse(io::read_file(summary)).value("statistics", kept);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(fmt::format("{}: {}", summary, e.what()));
  }
  if (!kept.is_object() || !kept.contains("file"))
    throw InputError(fmt::format("{}: the run kept no time statistics (its summary.json names none): give its case "
                                 "[output] statistics_from = T and run it again",
                                 directory));
  FluidStatistics out;
  const std::string file = directory + "/" + kept.at("file").get<std::string>();
  std::vector<Field> fields;
  out.mean.mesh = io::read_vtu_volume(file, &fields);
  const size_t points = out.mean.mesh.points.size();
  out.mean.velocity = point_vectors(fields, "mean_velocity", points);
  out.mean.pressure = point_scalars(fields, "mean_pressure", points);
  out.rms = point_vectors(fields, "rms_velocity", points);
  if (out.mean.velocity.empty() || out.mean.pressure.empty() || out.rms.empty())
    throw InputError(fmt::format("{}: has no point data `mean_velocity`, `rms_velocity` (3 components) and "
                                 "`mean_pressure`; is it the statistics file of 'vesselmesh simulate'?",
                                 file));
  out.start = kept.value("start_s", 0.0);
  out.end = kept.value("end_s", 0.0);
  out.mean.time = out.end;
  return out;
}

FluidField fluid_at_time(const WallSeries& series, double time) {
  const FramePair pair = frames_around(series, time);
  FluidField a = read_fluid_frame(series.frames[pair.first]);
  if (pair.second == pair.first) return a;
  const FluidField b = read_fluid_frame(series.frames[pair.second]);
  if (b.mesh.points.size() != a.mesh.points.size() || b.mesh.tets.size() != a.mesh.tets.size())
    throw InputError(fmt::format("{} and {}: different meshes", series.frames[pair.first].file,
                                 series.frames[pair.second].file));
  for (size_t i = 0; i < a.velocity.size(); ++i) {
    a.velocity[i] += pair.weight * (b.velocity[i] - a.velocity[i]);
    a.pressure[i] += pair.weight * (b.pressure[i] - a.pressure[i]);
  }
  a.time = time;
  return a;
}

std::vector<FluidSample> sample_points(const FluidField& field, const TetLocator& locator,
                                      const std::vector<Vec3>& points) {
  std::vector<FluidSample> samples(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    FluidSample& s = samples[i];
    s.point = points[i];
    s.distance = i == 0 ? 0.0 : samples[i - 1].distance + (points[i] - points[i - 1]).norm();
    const std::optional<TetLocator::Hit> hit = locator.locate(points[i]);
    if (!hit) continue;
    s.inside = true;
    s.velocity = locator.interpolate(*hit, field.velocity);
    s.pressure = locator.interpolate(*hit, field.pressure);
  }
  return samples;
}

std::vector<FluidSample> sample_line(const FluidField& field, const TetLocator& locator, const Vec3& a, const Vec3& b,
                                    int samples) {
  if (samples < 2) throw OptionError(fmt::format("a line needs at least 2 samples, got {}", samples));
  std::vector<Vec3> points(samples);
  for (int i = 0; i < samples; ++i) points[i] = a + (b - a) * (double(i) / (samples - 1));
  return sample_points(field, locator, points);
}

}  // namespace vesselmesh::post
