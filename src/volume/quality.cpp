#include "volume/quality.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
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

double layer_frame_angle(const TetMesh& m, int column, const Tet& t) {
  const Triangle& f = m.boundary[column];
  const Vec3 &a = m.points[f[0]], e1 = m.points[f[1]] - a, e2 = m.points[f[2]] - a;
  const Vec3 normal = e1.cross(e2).normalized();
  // In-plane coordinates (s, t) along the wall triangle's edges, w along its normal.
  const double g11 = e1.dot(e1), g12 = e1.dot(e2), g22 = e2.dot(e2), det = g11 * g22 - g12 * g12;
  if (!(det > 0) || !std::isfinite(det)) return 0.0;
  std::array<Vec3, 4> local;
  for (int k = 0; k < 4; ++k) {
    const Vec3 d = m.points[t[k]] - a;
    const double d1 = d.dot(e1), d2 = d.dot(e2);
    local[k] = Vec3((g22 * d1 - g12 * d2) / det, (g11 * d2 - g12 * d1) / det, d.dot(normal));
  }
  const auto [low, high] = std::minmax_element(local.begin(), local.end(),
                                               [](const Vec3& p, const Vec3& q) { return p.z() < q.z(); });
  const double height = high->z() - low->z();
  if (!(height > 0)) return 0.0;
  // The wall triangle onto the equilateral one of side 1, the cell's height onto 1.
  const Vec3 side1(1.0, 0.0, 0.0), side2(0.5, std::sqrt(3.0) / 2.0, 0.0), up(0.0, 0.0, 1.0);
  std::array<Vec3, 4> p;
  for (int k = 0; k < 4; ++k) p[k] = local[k].x() * side1 + local[k].y() * side2 + (local[k].z() / height) * up;
  double least = 180.0;
  for (double angle : mesh::dihedral_angles(p[0], p[1], p[2], p[3])) least = std::min(least, angle * 180.0 / std::numbers::pi);
  return least;
}

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

  // Every cell as tetrahedra (prisms by their split), with its layer (-1: unknown).
  const std::vector<Tet> all = mesh::all_tetrahedra(m);
  std::vector<int> layer(all.size(), -1), column_of(all.size(), -1);
  for (int t = 0; t < m.num_tets() && !m.tet_layer.empty(); ++t) layer[t] = m.tet_layer[t];
  for (int t = 0; t < m.num_tets() && !m.tet_column.empty(); ++t) column_of[t] = m.tet_column[t];
  for (int p = 0; p < m.num_prisms(); ++p) {
    bool inverted = false;
    for (int k = 0; k < 3; ++k) {
      const size_t i = m.tets.size() + 3 * p + k;
      layer[i] = m.prism_layer.empty() ? 1 : m.prism_layer[p];
      if (!m.prism_column.empty()) column_of[i] = m.prism_column[p];
      if (!(mesh::tet_volume6(m, all[i]) > 0)) inverted = true;
    }
    if (inverted) ++q.inverted;
  }
  std::vector<double> angles;
  angles.reserve(6 * all.size());
  q.worst_scaled_jacobian = 1.0;
  q.worst_aspect_ratio = 1.0;
  double min_layer = 1e300, min_interior = 1e300, min_layer_frame = 1e300;
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
    if (layer[i] > 0 && column_of[i] >= 0 && column_of[i] < static_cast<int>(m.boundary.size()))
      min_layer_frame = std::min(min_layer_frame, layer_frame_angle(m, column_of[i], t));
    if (layer[i] == 0) min_interior = std::min(min_interior, least);
    q.worst_scaled_jacobian = std::min(q.worst_scaled_jacobian, mesh::scaled_jacobian(a, b, c, d));
    q.worst_aspect_ratio = std::max(q.worst_aspect_ratio, aspect_ratio(a, b, c, d));
  }
  if (!angles.empty()) {
    const auto [least, most] = std::minmax_element(angles.begin(), angles.end());
    q.min_dihedral = *least;
    q.max_dihedral = *most;
    std::nth_element(angles.begin(), angles.begin() + angles.size() / 2, angles.end());
    q.median_dihedral = angles[angles.size() / 2];
  }
  if (min_layer < 1e300) q.min_dihedral_layer = min_layer;
  if (min_layer_frame < 1e300) q.min_dihedral_layer_frame = min_layer_frame;
  if (min_interior < 1e300) q.min_dihedral_interior = min_interior;

  const mesh::BoundaryClosure closure = mesh::boundary_closure(m, all);
  q.open_faces = closure.open_faces;
  q.stray_triangles = closure.stray_triangles;
  q.closed = closure.closed();

  // Layers per wall triangle: the distinct layer numbers of the cells on its column, over every
  // boundary triangle with the tag of a column's (so a wall triangle with no layer counts 0).
  // Thickness: the farthest column point from the wall triangle's plane, over the mean radius
  // of its corners.
  if (m.tet_column.empty() && m.prism_column.empty()) return q;
  std::vector<std::pair<int, int>> column_layers;  // (column, layer)
  std::vector<double> thickness(m.boundary.size(), 0.0);
  auto add = [&](int column, int level, std::span<const int> corners) {
    if (column < 0 || column >= static_cast<int>(m.boundary.size())) return;
    column_layers.emplace_back(column, level);
    const Triangle& f = m.boundary[column];
    const Vec3 normal = (m.points[f[1]] - m.points[f[0]]).cross(m.points[f[2]] - m.points[f[0]]).normalized();
    for (int v : corners) thickness[column] = std::max(thickness[column], std::abs((m.points[v] - m.points[f[0]]).dot(normal)));
  };
  for (int t = 0; t < m.num_tets() && !m.tet_column.empty(); ++t) add(m.tet_column[t], m.tet_layer[t], m.tets[t]);
  for (int p = 0; p < m.num_prisms() && !m.prism_column.empty(); ++p) add(m.prism_column[p], m.prism_layer[p], m.prisms[p]);
  std::sort(column_layers.begin(), column_layers.end());
  column_layers.erase(std::unique(column_layers.begin(), column_layers.end()), column_layers.end());
  std::vector<int> layers_on(m.boundary.size(), 0);
  std::set<int> wall_tags;
  for (const auto& [column, level] : column_layers) {
    ++layers_on[column];
    wall_tags.insert(m.boundary_tags.empty() ? 0 : m.boundary_tags[column]);
  }
  q.has_layers = !column_layers.empty();
  if (!q.has_layers) return q;
  q.min_layers = std::numeric_limits<int>::max();
  for (size_t c = 0; c < m.boundary.size(); ++c) {
    if (!wall_tags.count(m.boundary_tags.empty() ? 0 : m.boundary_tags[c])) continue;
    ++q.wall_triangles;
    q.min_layers = std::min(q.min_layers, layers_on[c]);
    q.max_layers = std::max(q.max_layers, layers_on[c]);
    if (radius.size() != m.points.size() || layers_on[c] == 0) continue;
    const Triangle& f = m.boundary[c];
    const double r = (radius[f[0]] + radius[f[1]] + radius[f[2]]) / 3.0;
    if (!(r > 0)) continue;
    const double ratio = thickness[c] / r;
    q.min_thickness_ratio = q.min_thickness_ratio < 0 ? ratio : std::min(q.min_thickness_ratio, ratio);
    q.max_thickness_ratio = std::max(q.max_thickness_ratio, ratio);
  }
  return q;
}

}  // namespace vesselmesh::volume
