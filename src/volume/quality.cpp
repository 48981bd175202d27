#include "volume/quality.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <iterator>
#include <limits>
#include <set>
#include <span>

namespace vesselmesh::volume {
namespace {

double aspect_ratio(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  const double volume = std::abs(mesh::tet_volume6(a, b, c, d)) / 6.0;
  const double area = 0.5 * ((b - a).cross(c - a).norm() + (b - a).cross(d - a).norm() + (c - a).cross(d - a).norm() +
                             (c - b).cross(d - b).norm());
  const double longest = std::max({(b - a).norm(), (c - a).norm(), (d - a).norm(), (c - b).norm(), (d - b).norm(),
                                   (d - c).norm()});
  if (volume <= 0 || area <= 0) return std::numeric_limits<double>::infinity();
  const double inradius = 3.0 * volume / area;
  return longest / (2.0 * std::sqrt(6.0) * inradius);
}

}  // namespace

VolumeQuality measure_volume(const TetMesh& m, const std::vector<double>& radius) {
  VolumeQuality q;
  q.points = m.num_points();
  q.tets = m.num_tets();
  q.prisms = m.num_prisms();
  for (size_t i = 0; i < m.boundary.size(); ++i) {
    const int tag = m.boundary_tags.empty() ? 0 : m.boundary_tags[i];
    const auto name = m.tag_names.find(tag);
    ++q.triangles_per_tag[name != m.tag_names.end() ? name->second : fmt::format("tag_{}", tag)];
  }

  // Every cell as tetrahedra, with its layer.
  std::vector<Tet> all;
  std::vector<int> layer;
  for (int t = 0; t < m.num_tets(); ++t) {
    all.push_back(m.tets[t]);
    layer.push_back(m.tet_layer.empty() ? -1 : m.tet_layer[t]);
  }
  for (int p = 0; p < m.num_prisms(); ++p) {
    bool inverted = false;
    for (const Tet& t : mesh::split_prism(m.prisms[p])) {
      all.push_back(t);
      layer.push_back(m.prism_layer.empty() ? 1 : m.prism_layer[p]);
      if (!(mesh::tet_volume6(m, t) > 0)) inverted = true;
    }
    if (inverted) ++q.inverted;
  }
  std::vector<double> angles;
  angles.reserve(6 * all.size());
  q.worst_scaled_jacobian = 1.0;
  q.worst_aspect_ratio = 1.0;
  double min_layer = 1e300, min_interior = 1e300;
  for (size_t i = 0; i < all.size(); ++i) {
    const Tet& t = all[i];
    const Vec3 &a = m.points[t[0]], &b = m.points[t[1]], &c = m.points[t[2]], &d = m.points[t[3]];
    if (i < m.tets.size() && !(mesh::tet_volume6(a, b, c, d) > 0)) ++q.inverted;
    double least = 1e300;
    for (double angle : mesh::dihedral_angles(a, b, c, d)) {
      angles.push_back(angle * 180.0 / std::numbers::pi);
      least = std::min(least, angles.back());
    }
    if (layer[i] > 0) min_layer = std::min(min_layer, least);
    if (layer[i] == 0) min_interior = std::min(min_interior, least);
    q.worst_scaled_jacobian = std::min(q.worst_scaled_jacobian, mesh::scaled_jacobian(a, b, c, d));
    q.worst_aspect_ratio = std::max(q.worst_aspect_ratio, aspect_ratio(a, b, c, d));
  }
  if (!angles.empty()) {
    std::sort(angles.begin(), angles.end());
    q.min_dihedral = angles.front();
    q.max_dihedral = angles.back();
    q.median_dihedral = angles[angles.size() / 2];
  }
  if (min_layer < 1e300) q.min_dihedral_layer = min_layer;
  if (min_interior < 1e300) q.min_dihedral_interior = min_interior;

  // Closure: the faces used by one cell against the tagged triangles.
  int nonmanifold = 0;
  const std::vector<Triangle> faces = mesh::tet_boundary(all, &nonmanifold);
  std::vector<Triangle> boundary;
  for (const Triangle& f : m.boundary) boundary.push_back(mesh::canonical_rotation(f));
  std::sort(boundary.begin(), boundary.end());
  std::vector<Triangle> missing, stray;
  std::set_difference(faces.begin(), faces.end(), boundary.begin(), boundary.end(), std::back_inserter(missing));
  std::set_difference(boundary.begin(), boundary.end(), faces.begin(), faces.end(), std::back_inserter(stray));
  q.open_faces = static_cast<int>(missing.size());
  q.stray_triangles = static_cast<int>(stray.size());
  q.closed = missing.empty() && stray.empty() && nonmanifold == 0;

  // Layers per wall triangle: the distinct layer numbers of the cells on each column.
  const bool columns = (!m.tet_column.empty() || !m.prism_column.empty());
  if (columns) {
    std::vector<std::set<int>> seen;
    std::vector<std::set<int>> column_points;
    auto add = [&](int column, int level, std::span<const int> corners) {
      if (column < 0) return;
      if (static_cast<int>(seen.size()) <= column) seen.resize(column + 1), column_points.resize(column + 1);
      seen[column].insert(level);
      column_points[column].insert(corners.begin(), corners.end());
    };
    for (int t = 0; t < m.num_tets() && !m.tet_column.empty(); ++t) add(m.tet_column[t], m.tet_layer[t], m.tets[t]);
    for (int p = 0; p < m.num_prisms() && !m.prism_column.empty(); ++p)
      add(m.prism_column[p], m.prism_layer[p], m.prisms[p]);
    q.has_layers = !seen.empty();
    q.min_layers = std::numeric_limits<int>::max();
    for (size_t c = 0; c < seen.size(); ++c) {
      q.min_layers = std::min(q.min_layers, static_cast<int>(seen[c].size()));
      q.max_layers = std::max(q.max_layers, static_cast<int>(seen[c].size()));
      if (seen[c].empty() || c >= m.boundary.size()) continue;
      ++q.wall_triangles;
      // Thickness: the farthest column point from the wall triangle's plane, over the mean
      // radius of its corners.
      if (radius.size() != m.points.size()) continue;
      const Triangle& f = m.boundary[c];
      const Vec3 normal = (m.points[f[1]] - m.points[f[0]]).cross(m.points[f[2]] - m.points[f[0]]).normalized();
      double thickness = 0;
      for (int v : column_points[c]) thickness = std::max(thickness, std::abs((m.points[v] - m.points[f[0]]).dot(normal)));
      const double r = (radius[f[0]] + radius[f[1]] + radius[f[2]]) / 3.0;
      if (!(r > 0)) continue;
      const double ratio = thickness / r;
      q.min_thickness_ratio = q.min_thickness_ratio < 0 ? ratio : std::min(q.min_thickness_ratio, ratio);
      q.max_thickness_ratio = std::max(q.max_thickness_ratio, ratio);
    }
    if (!q.has_layers) q.min_layers = 0;
  }
  return q;
}

}  // namespace vesselmesh::volume
