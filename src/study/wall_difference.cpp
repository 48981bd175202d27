#include "study/wall_difference.h"

#include "mesh/error.h"
#include "mesh/geometry.h"
#include "mesh/locator.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <numeric>

namespace vesselmesh::study {
namespace {

// From |d_i| and |reference_i| per point.
WallDifference measure(const std::vector<double>& area, const std::vector<double>& difference,
                       const std::vector<double>& magnitude) {
  VM_CHECK(area.size() == difference.size() && area.size() == magnitude.size(), "wall_difference: one value a point");
  WallDifference w;
  double total = 0.0, squares = 0.0, mean = 0.0;
  for (size_t i = 0; i < area.size(); ++i) {
    total += area[i];
    squares += area[i] * difference[i] * difference[i];
    mean += area[i] * magnitude[i];
  }
  if (!(total > 0.0)) return {NAN, NAN, NAN};
  w.mean = mean / total;
  std::vector<size_t> order(area.size());
  std::iota(order.begin(), order.end(), size_t{0});
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return difference[a] < difference[b]; });
  double below = 0.0, p95 = 0.0;
  for (size_t i : order) {
    below += area[i];
    p95 = difference[i];
    if (below >= 0.95 * total) break;
  }
  w.l2 = w.mean > 0.0 ? std::sqrt(squares / total) / w.mean : NAN;
  w.p95 = w.mean > 0.0 ? p95 / w.mean : NAN;
  return w;
}

template <typename T>
std::vector<T> interpolated(const WallMap& map, const std::vector<T>& field) {
  std::vector<T> out(map.corners.size());
  for (size_t i = 0; i < out.size(); ++i) {
    const auto& c = map.corners[i];
    const auto& w = map.weights[i];
    out[i] = w[0] * field[c[0]] + w[1] * field[c[1]] + w[2] * field[c[2]];
  }
  return out;
}

}  // namespace

WallMap map_onto(const TriMesh& source, const TriMesh& target) {
  const mesh::SurfaceLocator locator(source);
  WallMap map;
  map.corners.resize(target.points.size());
  map.weights.resize(target.points.size());
  tbb::parallel_for(size_t{0}, target.points.size(), [&](size_t i) {
    const mesh::SurfaceLocator::Hit hit = locator.closest(target.points[i]);
    const Triangle& f = source.triangles[hit.triangle];
    map.corners[i] = f;
    map.weights[i] = mesh::barycentric(hit.point, source.points[f[0]], source.points[f[1]], source.points[f[2]]);
  });
  return map;
}

std::vector<Vec3> interpolate(const WallMap& map, const std::vector<Vec3>& field) { return interpolated(map, field); }
std::vector<double> interpolate(const WallMap& map, const std::vector<double>& field) {
  return interpolated(map, field);
}

std::vector<double> lumped_areas(const TriMesh& mesh) {
  std::vector<double> area(mesh.points.size(), 0.0);
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    const double a = mesh::triangle_area(mesh, static_cast<int>(t)) / 3.0;
    for (int v : mesh.triangles[t]) area[v] += a;
  }
  return area;
}

WallDifference wall_difference(const std::vector<double>& area, const std::vector<Vec3>& field,
                               const std::vector<Vec3>& reference) {
  VM_CHECK(field.size() == reference.size(), "wall_difference: the fields on the same points");
  std::vector<double> difference(field.size()), magnitude(field.size());
  for (size_t i = 0; i < field.size(); ++i) {
    difference[i] = (field[i] - reference[i]).norm();
    magnitude[i] = reference[i].norm();
  }
  return measure(area, difference, magnitude);
}

WallDifference wall_difference(const std::vector<double>& area, const std::vector<double>& field,
                               const std::vector<double>& reference) {
  VM_CHECK(field.size() == reference.size(), "wall_difference: the fields on the same points");
  std::vector<double> difference(field.size()), magnitude(field.size());
  for (size_t i = 0; i < field.size(); ++i) {
    difference[i] = std::abs(field[i] - reference[i]);
    magnitude[i] = std::abs(reference[i]);
  }
  return measure(area, difference, magnitude);
}

}  // namespace vesselmesh::study
