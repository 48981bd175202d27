#include "mesh/statistics.h"

#include "mesh/clean.h"
#include "mesh/connectivity.h"
#include "mesh/geometry.h"

#include <algorithm>
#include <numbers>
#include <numeric>

namespace vesselmesh::mesh {
namespace {

Range range_of(std::vector<double> values) {
  Range r;
  if (values.empty()) return r;
  const auto middle = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), middle, values.end());
  r.median = *middle;
  const auto [lo, hi] = std::minmax_element(values.begin(), values.end());
  r.min = *lo;
  r.max = *hi;
  r.mean = std::accumulate(values.begin(), values.end(), 0.0) / static_cast<double>(values.size());
  return r;
}

}  // namespace

Statistics statistics(const TriMesh& mesh) {
  Statistics s;
  const EdgeMap edges = build_edge_map(mesh);
  s.points = mesh.num_points();
  s.triangles = mesh.num_triangles();
  s.edges = edges.num_edges();
  for (int e = 0; e < edges.num_edges(); ++e) s.boundary_edges += edges.is_boundary(e);
  s.closed = s.boundary_edges == 0;
  s.boundary_loops = static_cast<int>(boundary_loops(mesh, edges).size());
  triangle_components(mesh, edges, &s.components);
  s.euler_characteristic = s.points - s.edges + s.triangles;
  s.genus = (2 * s.components - s.euler_characteristic - s.boundary_loops) / 2;
  s.area = surface_area(mesh);
  s.volume = signed_volume(mesh);
  const auto box = bounding_box(mesh.points);
  s.box_min = box[0];
  s.box_max = box[1];

  std::vector<double> lengths(edges.num_edges());
  for (int e = 0; e < edges.num_edges(); ++e)
    lengths[e] = (mesh.points[edges.edges[e][0]] - mesh.points[edges.edges[e][1]]).norm();
  s.edge_length = range_of(std::move(lengths));

  constexpr double kDegrees = 180.0 / std::numbers::pi;
  std::vector<double> smallest(mesh.triangles.size());
  for (int t = 0; t < mesh.num_triangles(); ++t) {
    const auto angles = triangle_angles(mesh, t);
    smallest[t] = *std::min_element(angles.begin(), angles.end()) * kDegrees;
    s.max_angle = std::max(s.max_angle, *std::max_element(angles.begin(), angles.end()) * kDegrees);
    s.sliver_triangles += smallest[t] < 5.0;
  }
  s.min_angle = range_of(std::move(smallest));
  return s;
}

}  // namespace vesselmesh::mesh
