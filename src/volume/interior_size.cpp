#include "volume/interior_size.h"

#include "mesh/error.h"
#include "mesh/geometry.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace vesselmesh::volume {
void check_interior_size_options(const InteriorSizeOptions& o) {
  if (!(o.factor > 0.0 && std::isfinite(o.factor)))
    throw OptionError(fmt::format("--interior-size {}: give a factor > 0 (1: the wall's area-equivalent size)", o.factor));
  if (!(o.gradation >= 1.0 && std::isfinite(o.gradation)))
    throw OptionError(fmt::format("--interior-gradation {}: give a growth >= 1 (1: no growth inward)", o.gradation));
  if (!(o.core_fraction > 0.0 && std::isfinite(o.core_fraction)))
    throw OptionError(fmt::format("the interior's core fraction {} must be > 0", o.core_fraction));
  for (const RefineRegion& r : o.regions)
    if (!(r.radius > 0.0 && std::isfinite(r.radius) && r.size > 0.0 && std::isfinite(r.size) &&
          r.from.allFinite() && r.to.allFinite()))
      throw OptionError(fmt::format("--refine: a region needs a radius > 0 and a size > 0 (given radius {}, size {})",
                                    r.radius, r.size));
}

std::vector<double> area_equivalent_sizes(const TriMesh& mesh) {
  std::vector<double> area(mesh.points.size(), 0.0);
  std::vector<int> count(mesh.points.size(), 0);
  for (int t = 0; t < mesh.num_triangles(); ++t) {
    const double a = mesh::triangle_area(mesh, t);
    for (int v : mesh.triangles[t]) {
      area[v] += a;
      count[v] += 1;
    }
  }
  const double scale = 4.0 / std::sqrt(3.0);
  std::vector<double> size(mesh.points.size(), 0.0);
  for (size_t v = 0; v < size.size(); ++v)
    if (count[v] > 0) size[v] = std::sqrt(scale * area[v] / count[v]);
  return size;
}

InteriorSize::InteriorSize(const TriMesh& wall, const std::vector<double>& radius, const InteriorSizeOptions& options,
                           const std::vector<double>& layer)
    : wall_(wall),
      size_(area_equivalent_sizes(wall)),
      radius_(radius),
      layer_(layer),
      options_(options),
      slope_(std::log(options.gradation)),
      locator_(wall) {
  check_interior_size_options(options);
  VM_CHECK(radius.empty() || radius.size() == wall.points.size(), "InteriorSize: one radius per wall point");
  VM_CHECK(layer.empty() || layer.size() == wall.points.size(), "InteriorSize: one layer thickness per wall point");
  if (wall.triangles.empty()) throw InputError("the interior's size field needs the wall's triangles");
}

double InteriorSize::at(const Vec3& x) const {
  const mesh::SurfaceLocator::Hit hit = locator_.closest(x);
  const Triangle& f = wall_.triangles[hit.triangle];
  const auto w = mesh::barycentric(hit.point, wall_.points[f[0]], wall_.points[f[1]], wall_.points[f[2]]);
  double h = 0.0, r = 0.0, t = 0.0;  // (mesh::barycentric's weights are clamped to the triangle: sum 1)
  for (int k = 0; k < 3; ++k) {
    h += w[k] * size_[f[k]];
    if (!radius_.empty()) r += w[k] * radius_[f[k]];
    if (!layer_.empty()) t += w[k] * layer_[f[k]];
  }
  double size = h + slope_ * std::max(0.0, hit.distance - t);
  const double flow = options_.flow ? options_.flow(x) : 0.0;
  if ((!(flow > 0.0) || options_.flow_keeps_core) && !radius_.empty())
    size = std::min(size, std::max(h, options_.core_fraction * r));
  if (flow > 0.0) size = std::min(size, flow);
  for (const RefineRegion& region : options_.regions) {
    const Vec3 axis = region.to - region.from;
    const double length2 = axis.squaredNorm();
    const double along = length2 > 0.0 ? std::clamp((x - region.from).dot(axis) / length2, 0.0, 1.0) : 0.0;
    const double outside = std::max(0.0, (x - (region.from + along * axis)).norm() - region.radius);
    size = std::min(size, region.size + slope_ * outside);
  }
  return options_.factor * size;
}

}  // namespace vesselmesh::volume
