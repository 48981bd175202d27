#include "analysis/mixed_areas.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace vesselmesh::analysis {

std::array<double, 3> triangle_corner_areas(const Vec3 e[3]) {
  const double l2[3] = {e[0].squaredNorm(), e[1].squaredNorm(), e[2].squaredNorm()};
  return triangle_corner_areas(l2, 0.5 * e[0].cross(e[1]).norm());
}

std::array<double, 3> triangle_corner_areas(const double l2[3], double area) {
  std::array<double, 3> out{};
  if (!(area > 0.0)) return out;
  // Corner i is obtuse when its opposite edge is longer than the other two together.
  int obtuse = -1;
  for (int i = 0; i < 3; ++i)
    if (l2[i] > l2[(i + 1) % 3] + l2[(i + 2) % 3]) obtuse = i;
  if (obtuse >= 0) {
    for (int i = 0; i < 3; ++i) out[i] = (i == obtuse ? 0.5 : 0.25) * area;
    return out;
  }
  // Voronoi: corner i gets (|e_j|^2 cot(angle j) + |e_k|^2 cot(angle k)) / 8 for the edges e_j,
  // e_k that meet at it, with cot(angle j) = (l2_i + l2_k - l2_j) / (4 area).
  const double scale = 1.0 / (32.0 * area);
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3, k = (i + 2) % 3;
    out[i] = (l2[j] * (l2[i] + l2[k] - l2[j]) + l2[k] * (l2[i] + l2[j] - l2[k])) * scale;
  }
  return out;
}

std::vector<std::array<double, 3>> corner_areas(const TriMesh& mesh) {
  std::vector<std::array<double, 3>> areas(mesh.triangles.size());
  tbb::parallel_for(tbb::blocked_range<int>(0, mesh.num_triangles(), 4096), [&](const tbb::blocked_range<int>& range) {
    for (int t = range.begin(); t < range.end(); ++t) {
      const Triangle& f = mesh.triangles[t];
      const Vec3 e[3] = {mesh.points[f[2]] - mesh.points[f[1]], mesh.points[f[0]] - mesh.points[f[2]],
                         mesh.points[f[1]] - mesh.points[f[0]]};
      areas[t] = triangle_corner_areas(e);
    }
  });
  return areas;
}

std::vector<double> point_areas(const TriMesh& mesh, const std::vector<std::array<double, 3>>& corners) {
  std::vector<double> areas(mesh.points.size(), 0.0);
  for (int t = 0; t < mesh.num_triangles(); ++t)
    for (int i = 0; i < 3; ++i) areas[mesh.triangles[t][i]] += corners[t][i];
  return areas;
}

}  // namespace vesselmesh::analysis
